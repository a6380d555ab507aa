//! The deck of a run's output: the bodies free in x, y and θ (the specimen's deck, a bridge's
//! frames), the rotation a chart or a precision measure follows, and the peaks over all of
//! them that sweeps and suites report.

use super::RunOutput;

/// Index of the deck rotation DOF: `deck.theta`, else that of the first body free in x, y and
/// θ (a bridge's first frame), else the first `*.theta`, else DOF 0.
pub fn rotation_dof(r: &RunOutput) -> usize {
    r.dof("deck.theta")
        .or_else(|| free_body_rotation(&r.dof_names))
        .or_else(|| r.dof_names.iter().position(|n| n.ends_with(".theta")))
        .unwrap_or(0)
}

/// The rotation DOF of the deck's body that turns most ([`deck_bodies`]: the frame whose peak
/// |θ| is largest), else [`rotation_dof`]: what a measure of one rotation follows.
pub fn largest_rotation_dof(r: &RunOutput) -> usize {
    let peaks = &r.summary.peaks;
    (deck_bodies(&r.dof_names).iter())
        .map(|b| b[2])
        .max_by(|&i, &j| peaks[i].max_abs.total_cmp(&peaks[j].max_abs))
        .unwrap_or_else(|| rotation_dof(r))
}

/// The first `B.theta` whose body B also has `B.x` and `B.y`.
pub fn free_body_rotation(names: &[String]) -> Option<usize> {
    deck_bodies(names).first().map(|b| b[2])
}

/// The bodies free in x, y and θ (the specimen's deck, a bridge's frames), as their (x, y, θ)
/// DOFs.
pub fn deck_bodies(names: &[String]) -> Vec<[usize; 3]> {
    let dof = |n: String| names.iter().position(|m| *m == n);
    (names.iter())
        .filter_map(|n| n.strip_suffix(".theta"))
        .filter_map(|b| {
            Some([
                dof(format!("{b}.x"))?,
                dof(format!("{b}.y"))?,
                dof(format!("{b}.theta"))?,
            ])
        })
        .collect()
}

/// The deck's peaks over all its bodies ([`deck_bodies`]; without one, [`rotation_dof`] and
/// no translations): max |θ|, the residual θ(t_end) largest in magnitude (signed), max |x|,
/// max |y|.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeckPeaks {
    pub rotation: f64,
    pub residual: f64,
    pub x: f64,
    pub y: f64,
}

impl DeckPeaks {
    pub fn of(r: &RunOutput) -> Self {
        let peaks = &r.summary.peaks;
        let bodies = deck_bodies(&r.dof_names);
        if bodies.is_empty() {
            let k = rotation_dof(r);
            let p = peaks.get(k);
            return Self {
                rotation: p.map_or(f64::NAN, |p| p.max_abs),
                residual: p.map_or(f64::NAN, |p| p.residual),
                x: f64::NAN,
                y: f64::NAN,
            };
        }
        let max = |axis: usize| {
            (bodies.iter())
                .map(|b| peaks[b[axis]].max_abs)
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let residual = (bodies.iter())
            .map(|b| peaks[b[2]].residual)
            .fold(f64::NAN, |a: f64, r| {
                if a.is_nan() || r.abs() > a.abs() {
                    r
                } else {
                    a
                }
            });
        Self {
            rotation: max(2),
            residual,
            x: max(0),
            y: max(1),
        }
    }
}
