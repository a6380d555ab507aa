//! The integration methods, in one registry: names, parsing, the knob a work–precision diagram
//! sweeps for each, and chart letters (the dispatch of a scene to its method is [`crate::simulate`]).

use std::fmt;

/// How a scene is integrated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// The paper's event-driven scheme (DP5 between events, LCPs at events).
    Event,
    /// Moreau–Jean time-stepping: one velocity LCP per step, θ-method for smooth forces.
    Moreau,
    /// Penalty (gap elements) with Newmark average acceleration.
    Penalty,
    /// Penalty with the explicit central-difference scheme.
    PenaltyExplicit,
}

/// What a work–precision diagram varies for a method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Knob {
    /// rtol of the DP5 error control (atol = 10⁻³ rtol).
    Tolerance,
    /// The fixed step h.
    Step,
    /// The fixed step h × the contact stiffness k of the gap elements.
    StepStiffness,
}

impl Method {
    /// Every method, in the order of tables and charts.
    pub const ALL: [Method; 4] = [
        Method::Event,
        Method::Moreau,
        Method::Penalty,
        Method::PenaltyExplicit,
    ];

    /// The method of a model's `solver.method` / `--method` name.
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == s)
    }

    /// The name in model files and on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Method::Event => "event",
            Method::Moreau => "moreau",
            Method::Penalty => "penalty",
            Method::PenaltyExplicit => "penalty-explicit",
        }
    }

    /// The names of all methods joined by `sep`.
    pub fn names(sep: &str) -> String {
        Self::ALL.map(|m| m.name()).join(sep)
    }

    /// Contacts by gap elements (penalty): a compliant contact law whose compression is the
    /// law itself, not a penetration to judge; the others hold g_N ≥ 0 (eq. 5–10).
    pub(crate) fn compliant_contact(&self) -> bool {
        match self {
            Method::Event | Method::Moreau => false,
            Method::Penalty | Method::PenaltyExplicit => true,
        }
    }

    /// The name in chart legends.
    pub fn title(&self) -> &'static str {
        match self {
            Method::Event => "event-driven",
            Method::Moreau => "Moreau–Jean",
            Method::Penalty => "penalty (Newmark)",
            Method::PenaltyExplicit => "penalty (central difference)",
        }
    }

    /// The letter of its points in text charts.
    pub fn letter(&self) -> char {
        match self {
            Method::Event => 'E',
            Method::Moreau => 'M',
            Method::Penalty => 'P',
            Method::PenaltyExplicit => 'X',
        }
    }

    /// What sets its accuracy (and cost).
    pub fn knob(&self) -> Knob {
        match self {
            Method::Event => Knob::Tolerance,
            Method::Moreau => Knob::Step,
            Method::Penalty | Method::PenaltyExplicit => Knob::StepStiffness,
        }
    }
}

/// The name, padded as a `str` is.
impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::Method;

    #[test]
    fn every_name_parses_back_to_its_method() {
        for m in Method::ALL {
            assert_eq!(Method::parse(m.name()), Some(m));
        }
        assert_eq!(Method::parse("Event"), None);
        assert_eq!(Method::names(","), "event,moreau,penalty,penalty-explicit");
    }
}
