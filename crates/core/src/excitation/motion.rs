//! A processed support motion and its exact evaluation at any time.

/// A processed, uniformly sampled support motion (SI units).
#[derive(Clone, Debug, PartialEq)]
pub struct GroundMotion {
    /// Sampling interval, s.
    pub dt: f64,
    /// Start time (the lag), s.
    pub t0: f64,
    /// Node accelerations, m/s².
    pub acc: Vec<f64>,
    /// Node velocities, m/s (exact integral, `vel[0] = 0`).
    pub vel: Vec<f64>,
    /// Node displacements, m (exact integral, `disp[0] = 0`).
    pub disp: Vec<f64>,
    /// Relative PGA change from baseline correction + taper.
    pub correction_pga_change: f64,
}

pub(super) fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m: f64, x| m.max(x.abs()))
}

impl GroundMotion {
    pub(super) fn valid(&self) -> bool {
        let n = self.acc.len();
        n >= 2 && self.vel.len() == n && self.disp.len() == n
    }

    /// (d, v, a) at local time `s ∈ [0, dt]` of interval `i`.
    #[inline]
    pub(super) fn local(&self, i: usize, s: f64) -> (f64, f64, f64) {
        let (a0, a1) = (self.acc[i], self.acc[i + 1]);
        let j = (a1 - a0) / self.dt;
        let a = a0 + j * s;
        let v = self.vel[i] + s * (a0 + 0.5 * j * s);
        let d = self.disp[i] + s * (self.vel[i] + s * (0.5 * a0 + j * s / 6.0));
        (d, v, a)
    }

    /// (displacement, velocity, acceleration) at `t`: zero before `t0`; at and after the end,
    /// (final displacement, 0, 0). O(1), no allocation; NaN `t` gives NaNs.
    pub fn at(&self, t: f64) -> (f64, f64, f64) {
        let tau = t - self.t0;
        if tau.is_nan() {
            return (f64::NAN, f64::NAN, f64::NAN);
        }
        if tau < 0.0 || !self.valid() {
            return (0.0, 0.0, 0.0);
        }
        let last = self.acc.len() - 1;
        if tau >= last as f64 * self.dt {
            return (self.disp[last], 0.0, 0.0);
        }
        let i = ((tau / self.dt) as usize).min(last - 1);
        self.local(i, tau - i as f64 * self.dt)
    }

    /// Sampled length `(n − 1)·dt`, s (the lag not included).
    pub fn duration(&self) -> f64 {
        self.acc.len().saturating_sub(1) as f64 * self.dt
    }

    /// `t0 + duration()`: from here on the support is at rest.
    pub fn end_time(&self) -> f64 {
        self.t0 + self.duration()
    }

    /// The breakpoints `t0 + i·dt` (kinks of the acceleration).
    pub fn sample_times(&self) -> impl Iterator<Item = f64> + use<> {
        let (t0, dt) = (self.t0, self.dt);
        (0..self.acc.len()).map(move |i| t0 + i as f64 * dt)
    }
}
