//! The deck of a run's output: the bodies free in x, y and θ (the specimen's deck, a bridge's
//! frames), the rotation a chart or a precision measure follows, and the peaks over all the
//! bodies free in x and y (θ or not) that sweeps and suites report.

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

/// The bodies free in x and y, as their (x, y) DOFs and θ DOF, None for a body without one
/// (a translating deck, `deck.rotation = false`): the deck's bodies for its peaks.
pub(crate) fn plane_bodies(names: &[String]) -> Vec<(usize, usize, Option<usize>)> {
    let dof = |n: String| names.iter().position(|m| *m == n);
    (names.iter())
        .filter_map(|n| n.strip_suffix(".x"))
        .filter_map(|b| {
            let x = dof(format!("{b}.x"))?;
            Some((x, dof(format!("{b}.y"))?, dof(format!("{b}.theta"))))
        })
        .collect()
}

/// The deck's peaks over all its bodies ([`plane_bodies`]: a body without θ turns by exactly
/// 0; without one, [`rotation_dof`] and no translations): max |θ|, the residual θ(t_end)
/// largest in magnitude (signed), max |x|, max |y|.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeckPeaks {
    /// Peak deck rotation, rad.
    pub rotation: f64,
    /// The residual rotation θ(t_end) largest in magnitude, signed, rad.
    pub residual: f64,
    /// Peak longitudinal displacement, m.
    pub x: f64,
    /// Peak transverse displacement, m.
    pub y: f64,
}

impl DeckPeaks {
    /// The deck's peaks of the run `r`.
    pub fn of(r: &RunOutput) -> Self {
        let peaks = &r.summary.peaks;
        let bodies = plane_bodies(&r.dof_names);
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
        // a body without θ turns by exactly 0
        let peak = |k: Option<usize>| k.map_or(0.0, |k| peaks[k].max_abs);
        let max = |axis: usize| {
            (bodies.iter())
                .map(|b| peak([Some(b.0), Some(b.1), b.2][axis]))
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let residual = (bodies.iter())
            .map(|b| b.2.map_or(0.0, |k| peaks[k].residual))
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
