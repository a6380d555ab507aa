//! Peak values, durations and end drift of a processed motion.

use serde::{Deserialize, Serialize};

use super::motion::{GroundMotion, max_abs};
use super::readers::G;

/// Summary of a processed motion (SI units unless `_g`).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
pub struct MotionStats {
    /// Peak ground acceleration, g.
    pub pga_g: f64,
    /// m/s².
    pub pga: f64,
    /// Exact max |v| of the piecewise-quadratic velocity, m/s.
    pub pgv: f64,
    /// Exact max |d| of the piecewise-cubic displacement, m.
    pub pgd: f64,
    /// Sampled length (without lag), s.
    pub duration: f64,
    /// 5–95 % Arias significant duration (Trifunac & Brady 1975), s.
    pub significant_duration: f64,
    /// Arias intensity `π/(2g)∫a²dt`, m/s.
    pub arias_intensity: f64,
    /// Displacement at the record's end, m.
    pub final_displacement: f64,
    /// Velocity at the record's end, m/s.
    pub final_velocity: f64,
    /// Relative PGA change from baseline correction + taper (before amplitude scaling).
    pub correction_pga_change: f64,
}

impl GroundMotion {
    /// Peak values (exact for the piecewise polynomials), durations and end drift.
    pub fn stats(&self) -> MotionStats {
        let duration = self.duration();
        let pga = max_abs(&self.acc);
        let mut st = MotionStats {
            pga_g: pga / G,
            pga,
            pgv: 0.0,
            pgd: 0.0,
            duration,
            significant_duration: 0.0,
            arias_intensity: 0.0,
            final_displacement: self.disp.last().copied().unwrap_or(0.0),
            final_velocity: self.vel.last().copied().unwrap_or(0.0),
            correction_pga_change: self.correction_pga_change,
        };
        if !self.valid() {
            return st;
        }
        (st.pgv, st.pgd) = self.peak_velocity_displacement();
        (st.arias_intensity, st.significant_duration) = self.arias();
        st
    }

    /// Exact max |v| and max |d| of the piecewise-quadratic velocity and cubic displacement.
    fn peak_velocity_displacement(&self) -> (f64, f64) {
        let dt = self.dt;
        let mut pgv = max_abs(&self.vel);
        let mut pgd = max_abs(&self.disp);
        for i in 0..self.acc.len() - 1 {
            let (a0, a1, v0) = (self.acc[i], self.acc[i + 1], self.vel[i]);
            // velocity extremum where a = 0
            if a0 * a1 < 0.0 {
                let s = a0 * dt / (a0 - a1);
                pgv = pgv.max(self.local(i, s).1.abs());
            }
            // displacement extrema where v = v0 + a0 s + k s² = 0
            let k = 0.5 * (a1 - a0) / dt;
            let mut roots = [f64::NAN; 2];
            if k == 0.0 {
                if a0 != 0.0 {
                    roots[0] = -v0 / a0;
                }
            } else {
                let disc = a0 * a0 - 4.0 * k * v0;
                if disc >= 0.0 {
                    let sgn = if a0 >= 0.0 { 1.0 } else { -1.0 };
                    let q = -0.5 * (a0 + sgn * disc.sqrt());
                    roots[0] = q / k;
                    if q != 0.0 {
                        roots[1] = v0 / q;
                    }
                }
            }
            for s in roots {
                if s > 0.0 && s < dt {
                    pgd = pgd.max(self.local(i, s).0.abs());
                }
            }
        }
        (pgv, pgd)
    }

    /// Arias intensity `π/(2g)∫a²dt` and the 5–95 % significant duration.
    fn arias(&self) -> (f64, f64) {
        let cum = self.arias_cumulative();
        let e = cum.last().copied().unwrap_or(0.0);
        let intensity = std::f64::consts::PI / (2.0 * G) * e;
        let mut significant = 0.0;
        if e > 0.0 {
            significant = self.arias_crossing(&cum, 0.95) - self.arias_crossing(&cum, 0.05);
        }
        (intensity, significant)
    }

    /// The strong-motion window (Trifunac & Brady 1975): the times at which the Arias
    /// intensity `I(t) ∝ ∫₀ᵗ a²` reaches 5 % and 95 % of its total, in the run's time axis
    /// (`t0` included, as `excitation.window`). None for a motion without intensity.
    pub fn strong_motion_window(&self) -> Option<(f64, f64)> {
        if !self.valid() {
            return None;
        }
        let cum = self.arias_cumulative();
        let e = cum.last().copied().unwrap_or(0.0);
        (e > 0.0).then(|| {
            let t = |frac| self.t0 + self.arias_crossing(&cum, frac);
            (t(0.05), t(0.95))
        })
    }

    /// ∫a² over interval i up to local time s, exact for linear a.
    fn arias_segment(&self, i: usize, s: f64) -> f64 {
        let a0 = self.acc[i];
        let j = (self.acc[i + 1] - a0) / self.dt;
        s * (a0 * a0 + s * (a0 * j + s * j * j / 3.0))
    }

    /// ∫₀^{t_i} a² at every node (a valid motion).
    fn arias_cumulative(&self) -> Vec<f64> {
        let mut cum = Vec::with_capacity(self.acc.len());
        let mut e = 0.0;
        cum.push(0.0);
        for i in 0..self.acc.len() - 1 {
            e += self.arias_segment(i, self.dt);
            cum.push(e);
        }
        cum
    }

    /// Local time (from the first sample) at which ∫a² reaches `frac` of its total `cum`'s
    /// last: the interval by bisection of the nodes, the time in it by 60 bisections.
    fn arias_crossing(&self, cum: &[f64], frac: f64) -> f64 {
        let dt = self.dt;
        let target = frac * cum[cum.len() - 1];
        let i = cum.partition_point(|c| *c < target).clamp(1, cum.len() - 1) - 1;
        let (mut lo, mut hi) = (0.0, dt);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if cum[i] + self.arias_segment(i, mid) < target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        i as f64 * dt + 0.5 * (lo + hi)
    }
}
