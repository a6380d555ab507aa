//! Every quantity a run records, as a series a time chart can show: each DOF's coordinate and
//! velocity, each contact's gap, gap rate, slip rate, normal and tangential force, each
//! hysteretic element's deformation and force (columns, bearings, keys), the energy ledger's
//! terms and each seat's margin. A series is named by a key (`q:deck.theta`, `gap:left_top`,
//! `force:col1`, `energy:kinetic`) that survives reruns and model edits.

use crate::tui::results::run::TERMS;
use crate::tui::runs::data::RunData;
use std::borrow::Cow;

/// What a series is of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    /// A coordinate (x, y, θ) of a body.
    Q,
    /// Its velocity.
    V,
    Gap,
    GapRate,
    SlipRate,
    /// λ_N, λ_T of a contact (0 when open).
    Normal,
    Tangential,
    /// A hysteretic element's deformation and force.
    Def,
    Force,
    /// A term of the energy ledger ([`TERMS`]).
    Energy,
    /// A seat's margin: its width − (g_N − g_N(0)); below 0 the corner is unseated.
    Seat,
}

const KINDS: [(Kind, &str, &str); 11] = [
    (Kind::Q, "q", ""),
    (Kind::V, "v", "velocity"),
    (Kind::Gap, "gap", "gap"),
    (Kind::GapRate, "gap_rate", "gap rate"),
    (Kind::SlipRate, "slip_rate", "slip rate"),
    (Kind::Normal, "normal", "normal force"),
    (Kind::Tangential, "tangential", "tangential force"),
    (Kind::Def, "def", "deformation"),
    (Kind::Force, "force", "force"),
    (Kind::Energy, "energy", "energy"),
    (Kind::Seat, "seat", "seat margin"),
];

impl Kind {
    fn entry(self) -> &'static (Kind, &'static str, &'static str) {
        KINDS.iter().find(|k| k.0 == self).unwrap_or(&KINDS[0])
    }
    /// The key's prefix (`q`, `gap_rate`).
    pub fn prefix(self) -> &'static str {
        self.entry().1
    }
    /// The words after a series' subject (`gap rate`; none for a coordinate).
    pub fn words(self) -> &'static str {
        self.entry().2
    }
}

/// What a series is measured in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dim {
    Length,
    Angle,
    Velocity,
    AngularVelocity,
    Force,
    Energy,
}

/// One series: its kind and the name of its DOF, contact, element, energy term or seat's
/// contact.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct SeriesId {
    pub kind: Kind,
    pub of: String,
}

impl SeriesId {
    pub fn new(kind: Kind, of: &str) -> Self {
        Self {
            kind,
            of: of.to_string(),
        }
    }

    /// `q:deck.theta`, `gap:left_top`.
    pub fn key(&self) -> String {
        format!("{}:{}", self.kind.prefix(), self.of)
    }

    /// The series of a key (None for one that names no kind).
    pub fn parse(key: &str) -> Option<Self> {
        let (p, of) = key.split_once(':')?;
        let kind = KINDS.iter().find(|k| k.1 == p)?.0;
        (!of.is_empty()).then(|| Self::new(kind, of))
    }

    /// In words: `deck.theta`, `deck.x velocity`, `left_top gap rate`, `energy kinetic`.
    pub fn label(&self) -> String {
        match self.kind {
            Kind::Q => self.of.clone(),
            Kind::Energy => format!("energy {}", self.of),
            k => format!("{} {}", self.of, k.words()),
        }
    }

    /// A rotation or its rate (a DOF named `*.theta`).
    pub fn angular(&self) -> bool {
        matches!(self.kind, Kind::Q | Kind::V) && self.of.ends_with(".theta")
    }

    pub fn dim(&self) -> Dim {
        match self.kind {
            Kind::Q if self.angular() => Dim::Angle,
            Kind::V if self.angular() => Dim::AngularVelocity,
            Kind::Q | Kind::Gap | Kind::Def | Kind::Seat => Dim::Length,
            Kind::V | Kind::GapRate | Kind::SlipRate => Dim::Velocity,
            Kind::Normal | Kind::Tangential | Kind::Force => Dim::Force,
            Kind::Energy => Dim::Energy,
        }
    }
}

/// Every series `run` records, in order: coordinates, velocities, then per contact its gap,
/// gap rate, slip rate, normal and tangential force, per element its deformation and force,
/// the energy terms, the seats' margins.
pub fn catalogue(run: &RunData) -> Vec<SeriesId> {
    let mut out = Vec::new();
    for kind in [Kind::Q, Kind::V] {
        out.extend(run.dof_names.iter().map(|n| SeriesId::new(kind, n)));
    }
    for n in &run.contact_names {
        out.extend(
            [
                Kind::Gap,
                Kind::GapRate,
                Kind::SlipRate,
                Kind::Normal,
                Kind::Tangential,
            ]
            .map(|k| SeriesId::new(k, n)),
        );
    }
    for n in &run.element_names {
        out.extend([Kind::Def, Kind::Force].map(|k| SeriesId::new(k, n)));
    }
    out.extend(TERMS.iter().map(|t| SeriesId::new(Kind::Energy, t)));
    for &(c, _) in &run.seats {
        if let Some(n) = run.contact_names.get(c) {
            out.push(SeriesId::new(Kind::Seat, n));
        }
    }
    out.retain(|id| column(run, id).is_some());
    out
}

/// The column of series `id` in `run`, one value per sample (None when the run does not
/// record it: another model's name, or a kept run, which keeps fewer columns).
pub fn column<'a>(run: &'a RunData, id: &SeriesId) -> Option<Cow<'a, [f64]>> {
    let dof = || run.dof_names.iter().position(|n| *n == id.of);
    let contact = || run.contact_names.iter().position(|n| *n == id.of);
    let element = || run.element_names.iter().position(|n| *n == id.of);
    let f = &run.results.forces;
    let col: &[f64] = match id.kind {
        Kind::Q => run.q.get(dof()?)?,
        Kind::V => run.v.get(dof()?)?,
        Kind::Gap => run.gap.get(contact()?)?,
        Kind::GapRate => run.gap_rate.get(contact()?)?,
        Kind::SlipRate => run.slip_rate.get(contact()?)?,
        Kind::Normal => f.normal.get(contact()?)?,
        Kind::Tangential => f.tangential.get(contact()?)?,
        Kind::Def => &run.el.get(element()?)?.0,
        Kind::Force => &run.el.get(element()?)?.1,
        Kind::Energy => {
            let k = TERMS.iter().position(|t| *t == id.of)?;
            &run.results.ledger.terms[k]
        }
        Kind::Seat => {
            let c = contact()?;
            let &(_, edge) = run.seats.iter().find(|s| s.0 == c)?;
            let g = run.gap.get(c)?;
            if g.len() != run.t.len() {
                return None;
            }
            return Some(Cow::Owned(g.iter().map(|g| edge - g).collect()));
        }
    };
    // a column kept for every sample, or none at all
    (col.len() == run.t.len()).then_some(Cow::Borrowed(col))
}

/// The series a chart shows until one is picked: 0 the charted rotation, 1 every contact's
/// gap, 2 x and y of the rotating body ([`RunData::rot`], [`RunData::xy`]).
pub fn defaults(run: &RunData, chart: usize) -> Vec<SeriesId> {
    match chart {
        0 => run
            .rot
            .map(|r| SeriesId::new(Kind::Q, &run.dof_names[r]))
            .into_iter()
            .collect(),
        1 => (run.contact_names.iter())
            .map(|n| SeriesId::new(Kind::Gap, n))
            .collect(),
        2 => (run.xy.iter())
            .map(|&k| SeriesId::new(Kind::Q, &run.dof_names[k]))
            .collect(),
        _ => Vec::new(),
    }
}

/// The title of a chart of `ids`: one or two series by name (`deck.x / deck.y`), every gap
/// `gaps g_N`, more of one kind `col1 … force ×3`, else their number.
pub fn title(ids: &[SeriesId]) -> String {
    match ids {
        [] => "no series".into(),
        [a] => a.label(),
        [a, b] => format!("{} / {}", a.label(), b.label()),
        [a, rest @ ..] if rest.iter().all(|b| b.kind == a.kind) => match a.kind {
            Kind::Gap => "gaps g_N".into(),
            Kind::Q => format!("{} … ×{}", a.of, ids.len()),
            Kind::Energy => format!("energy ×{}", ids.len()),
            k => format!("{} ×{}", k.words(), ids.len()),
        },
        _ => format!("{} series", ids.len()),
    }
}

/// The name of a series in a chart of `ids`: its subject when they are all of one kind
/// (`left_top`), else its label.
pub fn name_in(id: &SeriesId, ids: &[SeriesId]) -> String {
    if ids.iter().all(|b| b.kind == id.kind) {
        id.of.clone()
    } else {
        id.label()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_read_back() {
        for (k, p, _) in KINDS {
            let id = SeriesId::new(k, "left_top");
            assert_eq!(id.key(), format!("{p}:left_top"));
            assert_eq!(SeriesId::parse(&id.key()), Some(id));
        }
        assert_eq!(SeriesId::parse("x:left_top"), None);
        assert_eq!(SeriesId::parse("gap:"), None);
        assert_eq!(SeriesId::parse("gap"), None);
        let id = SeriesId::parse("q:deck.theta").unwrap();
        assert_eq!((id.dim(), id.label()), (Dim::Angle, "deck.theta".into()));
        let id = SeriesId::parse("v:deck.x").unwrap();
        assert_eq!(
            (id.dim(), id.label()),
            (Dim::Velocity, "deck.x velocity".into())
        );
    }
}
