//! What summary.json holds: the run's counts, every DOF's peak, each contact's extremes and
//! each seat's margin.

use super::{EnergySample, EventKind, KeyFailure};
use serde::Serialize;

/// The counts of a run.
#[derive(Clone, Debug, Default, Serialize)]
pub struct RunStats {
    /// Accepted steps.
    pub steps_accepted: usize,
    /// Rejected steps.
    pub steps_rejected: usize,
    /// Right-hand side evaluations.
    pub rhs_evals: usize,
    /// Event method: per state component (q, then q̇), the accepted DP5 steps whose error
    /// estimate it dominated — which motion sets the step size (labelled in
    /// [`Summary::step_control`]).
    #[serde(skip)]
    pub step_control: Vec<usize>,
    /// LCPs solved.
    pub lcp_solves: usize,
    /// Lemke's pivots over every LCP.
    pub lemke_pivots: usize,
    /// LCPs solved only after regularisation (degenerate contact sets).
    pub lcp_regularized: usize,
    /// Contacts left approaching by an impact (the impact law forbids it: always 0 unless the
    /// LCP was solved inaccurately; a debug build stops there).
    pub approaching_after_impact: usize,
    /// Contacts that impacts elsewhere lifted slower than `zeno_velocity`, held closed (the
    /// alternating impacts of two corners; left out of summary.json while 0).
    #[serde(skip_serializing_if = "is_zero")]
    pub held_after_impact: usize,
    /// Events located.
    pub events_located: usize,
    /// Branch changes of the hysteretic elements.
    pub branch_events: usize,
    /// Impacts.
    pub impacts: usize,
    /// Transitions to stick.
    pub sticks: usize,
    /// Transitions to slip.
    pub slips: usize,
    /// Detachments.
    pub releases: usize,
    /// Impact accumulations closed by the accumulation rule.
    pub accumulations: usize,
    /// Failed shear keys (left out of summary.json while 0).
    #[serde(skip_serializing_if = "is_zero")]
    pub key_failures: usize,
    /// Wall time, s.
    pub wall_time: f64,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl RunStats {
    /// One more event of kind `k`.
    pub fn count(&mut self, k: EventKind) {
        match k {
            EventKind::Impact => self.impacts += 1,
            EventKind::Stick => self.sticks += 1,
            EventKind::Slip => self.slips += 1,
            EventKind::Release => self.releases += 1,
            EventKind::Accumulation => self.accumulations += 1,
            EventKind::KeyFailure => self.key_failures += 1,
        }
    }
}

/// The peak of one DOF.
#[derive(Clone, Debug, Serialize)]
pub struct DofPeak {
    /// Its name.
    pub name: String,
    /// max |q|.
    pub max_abs: f64,
    /// When, s.
    pub at: f64,
    /// The value at the end of the run.
    pub residual: f64,
    /// max |q̇|.
    pub max_abs_velocity: f64,
}

/// A deck corner's seat over the run: its margin width − (g_N − g_N(0)) at the largest gap.
#[derive(Clone, Debug, Serialize)]
pub struct SeatSummary {
    /// The contact's name.
    pub contact: String,
    /// Support length, m.
    pub width: f64,
    /// width − (max g_N − g_N(0)): below 0 the corner is unseated.
    pub min_margin: f64,
    /// When, s.
    pub at: f64,
    /// AASHTO LRFD 4.7.4.4's N for this deck, times `percent` / 100, m (bridge files).
    pub required: Option<f64>,
    /// The percentage of AASHTO's N applied.
    pub percent: Option<f64>,
}

/// The extremes of one contact.
#[derive(Clone, Debug, Serialize)]
pub struct ContactSummary {
    /// Its name.
    pub name: String,
    /// Smallest g_N, m.
    pub min_gap: f64,
    /// The largest gap over the samples, and when.
    pub max_gap: f64,
    /// When g_N was largest, s.
    pub max_gap_at: f64,
    /// Largest λ_N.
    pub max_normal_force: f64,
    /// The smallest normal force over the samples (0 if never below): below 0 a pull, which a
    /// unilateral contact never exerts.
    pub min_normal_force: f64,
    /// Largest Λ_N.
    pub max_normal_impulse: f64,
    /// Impacts.
    pub impacts: usize,
    /// Time stuck, s.
    pub stick_time: f64,
    /// Time sliding, s.
    pub slide_time: f64,
}

/// What summary.json holds.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Summary {
    /// The model's title.
    pub title: String,
    /// End time, s.
    pub t_end: f64,
    /// Per DOF.
    pub peaks: Vec<DofPeak>,
    /// Per contact.
    pub contacts: Vec<ContactSummary>,
    /// Empty without seats.
    pub seats: Vec<SeatSummary>,
    /// Deepest penetration, m.
    pub max_penetration: f64,
    /// The largest pull of any contact at any sample, max(0, −min λ_N), in force units.
    pub max_pull: f64,
    /// The ledger at the end.
    pub energy_final: EnergySample,
    /// The largest |closure|, energy.
    pub energy_closure_abs: f64,
    /// The largest |closure| relative to the energy scale.
    pub energy_closure_rel: f64,
    /// Each accumulation's contact and time.
    pub accumulation_times: Vec<(String, f64)>,
    /// The run's counts.
    pub stats: RunStats,
    /// Event method: the state components (`x`, `d/dt x`) whose local error estimate set the
    /// accepted DP5 steps, with their step counts, most first (zero counts left out).
    pub step_control: Vec<(String, usize)>,
    /// The shear keys that failed, in order; absent from summary.json without `key` elements.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub key_failures: Option<Vec<KeyFailure>>,
}
