//! What a run carries besides its charted history, for the results pages: the energy ledger
//! over time and the contact forces per corner, one column per term or contact, filled from
//! the same samples as [`crate::tui::runs::data::RunData`].

use crate::output::{EnergySample, Sample};
use crate::units::{Quantity, UnitSystem};

/// The units of the results pages in the model's unit system (its `units` key): energy
/// (force × length: kJ in SI-kN, J in SI, kip·in in kip-in), force (kN, N, kip) and impulse
/// (kN·s, N·s, kip·s).
pub fn units(sys: UnitSystem) -> ResultUnits {
    let force = sys.unit(Quantity::Force);
    ResultUnits {
        energy: sys.unit(Quantity::Energy),
        force,
        impulse: format!("{force}·s"),
    }
}

/// [`units`]: the energy, force and impulse units of a model.
#[derive(Clone, Debug, PartialEq)]
pub struct ResultUnits {
    pub energy: &'static str,
    pub force: &'static str,
    pub impulse: String,
}

/// The ledger's terms, in the order of [`Ledger::terms`].
pub const TERMS: [&str; 8] = [
    "input",
    "kinetic",
    "elastic",
    "damping",
    "hysteresis",
    "friction",
    "impacts",
    "closure",
];

/// The ledger's terms at one instant: the input (initial energy + work of the loads and of
/// the supports), kinetic, elastic (linear springs), damping, hysteresis, friction, impacts
/// (normal and tangential), and the closure (the balance error, left minus right side).
pub fn terms(e: &EnergySample) -> [f64; 8] {
    [
        e.initial + e.loads + e.supports,
        e.kinetic,
        e.elastic,
        e.damping,
        e.hysteretic,
        e.friction,
        e.impact_normal + e.impact_tangential,
        e.closure,
    ]
}

/// The energy ledger over time: a column per term of [`TERMS`].
#[derive(Clone, Debug, Default)]
pub struct Ledger {
    pub terms: [Vec<f64>; 8],
}

/// λ_N and λ_T of each contact over time (0 when open).
#[derive(Clone, Debug, Default)]
pub struct Forces {
    pub normal: Vec<Vec<f64>>,
    pub tangential: Vec<Vec<f64>>,
}

/// The ledger and the contact forces of a run.
#[derive(Clone, Debug, Default)]
pub struct RunResults {
    pub ledger: Ledger,
    pub forces: Forces,
}

impl RunResults {
    pub fn new(contacts: usize) -> Self {
        Self {
            ledger: Ledger::default(),
            forces: Forces {
                normal: vec![Vec::new(); contacts],
                tangential: vec![Vec::new(); contacts],
            },
        }
    }

    /// Appends one sample.
    pub fn push(&mut self, s: &Sample) {
        for (col, v) in self.ledger.terms.iter_mut().zip(terms(&s.energy)) {
            col.push(v);
        }
        let f = &mut self.forces;
        for (i, c) in s.contacts.iter().enumerate().take(f.normal.len()) {
            f.normal[i].push(c.normal_force);
            f.tangential[i].push(c.tangential_force);
        }
    }

    /// The largest |closure| of the samples (the summary's `energy_closure_abs` once the run
    /// finished).
    pub fn max_closure(&self) -> f64 {
        self.ledger.terms[7]
            .iter()
            .fold(0.0f64, |m, x| m.max(x.abs()))
    }
}
