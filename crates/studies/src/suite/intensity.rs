//! Intensity measures of a record pair for incremental dynamic analysis: PGA, and the pseudo
//! spectral acceleration Sa(T, ζ) = ω² max|u| of the linear oscillator
//! ü + 2ζωu̇ + ω²u = −a_g(t), a_g linear between samples, solved by the exact recurrence for a
//! piecewise-linear excitation (Nigam & Jennings 1969, BSSA 59(2) 909–922), its peak taken
//! exactly: at the samples, at the zeros of u̇ inside a step, and in the free vibration after
//! the record. A pair's intensity is the geometric mean of its two components' (FEMA P695).

use crate::excitation::G;
use crate::studies::parse_axis;

/// The period of Sa: given, or the model's first mode (`sa:T1`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Period {
    Seconds(f64),
    FirstMode,
}

/// An intensity measure as the command line names it (`--measure`, `--damping`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MeasureSpec {
    Pga,
    Sa { period: Period, damping: f64 },
}

/// An intensity measure with its period known.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Measure {
    /// Peak ground acceleration, g.
    Pga,
    /// Pseudo spectral acceleration ω² max|u|, g, at `period` s and damping ratio `damping`.
    Sa { period: f64, damping: f64 },
}

/// Damping ratio of Sa when `--damping` is not given (the usual 5 %).
pub(crate) const DEFAULT_DAMPING: f64 = 0.05;

/// A `--measure`, `--damping` or `--levels` argument that cannot be used.
#[derive(Debug, thiserror::Error)]
#[error("{option} '{argument}': {reason}")]
pub struct MeasureError {
    /// `--measure`, `--damping` or `--levels`.
    pub option: &'static str,
    pub argument: String,
    pub reason: String,
}

fn measure_error(option: &'static str, argument: &str, reason: &str) -> MeasureError {
    MeasureError {
        option,
        argument: argument.to_string(),
        reason: reason.to_string(),
    }
}

/// `pga`, `sa:T` (T in s) or `sa:T1`; `damping` (ζ in [0, 1)) for Sa only, else
/// [`DEFAULT_DAMPING`].
pub fn parse_measure(arg: &str, damping: Option<f64>) -> Result<MeasureSpec, MeasureError> {
    let a = arg.trim();
    if a.eq_ignore_ascii_case("pga") {
        if let Some(z) = damping {
            let reason = "applies to --measure sa:T only";
            return Err(measure_error("--damping", &z.to_string(), reason));
        }
        return Ok(MeasureSpec::Pga);
    }
    let t = (a.strip_prefix("sa:").or_else(|| a.strip_prefix("Sa:")))
        .ok_or_else(|| measure_error("--measure", arg, "expected pga, sa:T (s) or sa:T1"))?;
    let period = if t.eq_ignore_ascii_case("t1") {
        Period::FirstMode
    } else {
        match t.parse::<f64>() {
            Ok(x) if x.is_finite() && x > 0.0 => Period::Seconds(x),
            _ => {
                let reason = format!("the period '{t}' is not a number of seconds > 0 (or T1)");
                return Err(measure_error("--measure", arg, &reason));
            }
        }
    };
    let damping = damping.unwrap_or(DEFAULT_DAMPING);
    if !(0.0..1.0).contains(&damping) {
        let reason = "the damping ratio must lie in [0, 1)";
        return Err(measure_error("--damping", &damping.to_string(), reason));
    }
    Ok(MeasureSpec::Sa { period, damping })
}

/// `a:b:step` (inclusive) or `v1,v2,…`: intensity levels, g, each finite and > 0.
pub fn parse_levels(arg: &str) -> Result<Vec<f64>, MeasureError> {
    let axis = parse_axis(&format!("levels={arg}")).map_err(|e| {
        let reason = e.replace(&format!("'levels={arg}': "), "");
        measure_error("--levels", arg, &reason)
    })?;
    (axis.values.iter())
        .map(|v| match v.parse::<f64>() {
            Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
            _ => Err(measure_error(
                "--levels",
                arg,
                &format!("'{v}' is not a level > 0 (g)"),
            )),
        })
        .collect()
}

impl Measure {
    /// `pga`, or `sa(Ts,ζ%)` with T and 100 ζ as their shortest round-trip numbers.
    pub fn label(&self) -> String {
        match self {
            Measure::Pga => "pga".into(),
            Measure::Sa { period, damping } => {
                let percent = (damping * 100.0 * 1e9).round() / 1e9;
                format!("sa({}s,{}%)", plain(*period), plain(percent))
            }
        }
    }

    /// The intensity of one processed component (acceleration m/s², samples `dt` apart), g.
    pub fn of_component(&self, acc: &[f64], dt: f64) -> f64 {
        match *self {
            Measure::Pga => acc.iter().fold(0.0f64, |m, a| m.max(a.abs())) / G,
            Measure::Sa { period, damping } => pseudo_acceleration(acc, dt, period, damping) / G,
        }
    }
}

/// The shortest round-trip text of `x`, a whole number without `.0`.
fn plain(x: f64) -> String {
    let mut n = crate::output::number::Numbers::new();
    let s = n.format(x);
    s.strip_suffix(".0").unwrap_or(s).to_string()
}

/// The pseudo spectral acceleration ω² max|u|, m/s², of the oscillator of `period` s and
/// damping ratio `zeta` (in [0, 1)) under `acc` (m/s², linear between samples `dt` apart),
/// from rest.
pub fn pseudo_acceleration(acc: &[f64], dt: f64, period: f64, zeta: f64) -> f64 {
    let omega = 2.0 * std::f64::consts::PI / period;
    omega * omega * peak_displacement(acc, dt, omega, zeta)
}

/// The exact step of the oscillator (ω, ζ) over Δt under f = −a_g linear from f0 to f1:
/// u = e^{−ζωτ}(c₁ cos ω_Dτ + c₂ sin ω_Dτ) + (f0 + sτ)/ω² − 2ζs/ω³, s = (f1 − f0)/Δt.
struct Oscillator {
    omega: f64,
    zeta: f64,
    omega_d: f64,
    dt: f64,
    /// e^{−ζωΔt}, cos ω_DΔt, sin ω_DΔt.
    decay: f64,
    cos: f64,
    sin: f64,
}

/// One step's homogeneous weights and forcing: (c₁, c₂, f0, s).
type Step = (f64, f64, f64, f64);

impl Oscillator {
    fn new(omega: f64, zeta: f64, dt: f64) -> Self {
        let omega_d = omega * (1.0 - zeta * zeta).sqrt();
        Self {
            omega,
            zeta,
            omega_d,
            dt,
            decay: (-zeta * omega * dt).exp(),
            cos: (omega_d * dt).cos(),
            sin: (omega_d * dt).sin(),
        }
    }

    /// The weights of the step from (u0, v0) under f0 → f1.
    fn step(&self, u0: f64, v0: f64, f0: f64, f1: f64) -> Step {
        let (w, z) = (self.omega, self.zeta);
        let s = (f1 - f0) / self.dt;
        let c1 = u0 - f0 / (w * w) + 2.0 * z * s / (w * w * w);
        let c2 = (v0 - s / (w * w) + z * w * c1) / self.omega_d;
        (c1, c2, f0, s)
    }

    /// (u, u̇) at τ into the step; `trig` = (e^{−ζωτ}, cos ω_Dτ, sin ω_Dτ).
    fn state(&self, (c1, c2, f0, s): Step, tau: f64, (e, c, sn): (f64, f64, f64)) -> (f64, f64) {
        let (w, z, wd) = (self.omega, self.zeta, self.omega_d);
        let u = e * (c1 * c + c2 * sn) + (f0 + s * tau) / (w * w) - 2.0 * z * s / (w * w * w);
        let v = e * ((wd * c2 - z * w * c1) * c - (wd * c1 + z * w * c2) * sn) + s / (w * w);
        (u, v)
    }

    fn at(&self, st: Step, tau: f64) -> (f64, f64) {
        let e = (-self.zeta * self.omega * tau).exp();
        let a = self.omega_d * tau;
        self.state(st, tau, (e, a.cos(), a.sin()))
    }

    /// |u| at the zero of u̇ inside a step whose ends have rates of opposite signs (bisection
    /// to the last bit).
    fn inner_peak(&self, st: Step, v0: f64) -> f64 {
        let (mut a, mut b) = (0.0, self.dt);
        for _ in 0..80 {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            if (self.at(st, m).1 > 0.0) == (v0 > 0.0) {
                a = m;
            } else {
                b = m;
            }
        }
        self.at(st, 0.5 * (a + b)).0.abs()
    }

    /// The largest |u| of the free vibration from (u, v): the first extreme (u̇ = 0 at
    /// tan ω_Dτ = v ω_D / (ζωv + ω²u)) or the start; later extremes decay.
    fn free_peak(&self, u: f64, v: f64) -> f64 {
        let (w, z, wd) = (self.omega, self.zeta, self.omega_d);
        let p = (z * w * v + w * w * u) / wd;
        let mut theta = v.atan2(p);
        if theta < 0.0 {
            theta += std::f64::consts::PI;
        }
        let tau = theta / wd;
        let (c1, c2) = (u, (v + z * w * u) / wd);
        let e = (-z * w * tau).exp();
        let first = e * (c1 * theta.cos() + c2 * theta.sin());
        first.abs().max(u.abs())
    }
}

/// max |u(t)| of the oscillator (ω, ζ) under `acc` from rest, over the record and the free
/// vibration after it.
pub(crate) fn peak_displacement(acc: &[f64], dt: f64, omega: f64, zeta: f64) -> f64 {
    let osc = Oscillator::new(omega, zeta, dt);
    let trig = (osc.decay, osc.cos, osc.sin);
    let (mut u, mut v, mut peak) = (0.0f64, 0.0f64, 0.0f64);
    for w in acc.windows(2) {
        let st = osc.step(u, v, -w[0], -w[1]);
        let (u1, v1) = osc.state(st, dt, trig);
        if (v > 0.0 && v1 < 0.0) || (v < 0.0 && v1 > 0.0) {
            peak = peak.max(osc.inner_peak(st, v));
        }
        (u, v) = (u1, v1);
        peak = peak.max(u.abs());
    }
    peak.max(osc.free_peak(u, v))
}

/// The geometric mean √(I_L I_T) of two components' intensities.
pub(crate) fn pair_intensity(longitudinal: f64, transverse: f64) -> f64 {
    (longitudinal * transverse).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn measures_and_levels_parse_or_name_their_option() {
        assert_eq!(parse_measure("pga", None).unwrap(), MeasureSpec::Pga);
        let sa = parse_measure("sa:0.25", None).unwrap();
        let period = Period::Seconds(0.25);
        assert_eq!(
            sa,
            MeasureSpec::Sa {
                period,
                damping: 0.05
            }
        );
        let t1 = parse_measure("sa:T1", Some(0.02)).unwrap();
        let period = Period::FirstMode;
        assert_eq!(
            t1,
            MeasureSpec::Sa {
                period,
                damping: 0.02
            }
        );
        for (m, d, start) in [
            ("pgv", None, "--measure 'pgv'"),
            ("sa:0", None, "--measure 'sa:0'"),
            ("sa:x", None, "--measure 'sa:x'"),
            ("pga", Some(0.05), "--damping '0.05'"),
            ("sa:1", Some(1.0), "--damping '1'"),
        ] {
            let e = parse_measure(m, d).unwrap_err().to_string();
            assert!(e.starts_with(start), "{e}");
        }
        let l = parse_levels("0.1:1.5:0.1").unwrap();
        assert_eq!(l.len(), 15);
        assert_eq!((l[0], l[2], l[14]), (0.1, 0.3, 1.5));
        assert_eq!(parse_levels("0.2, 0.4").unwrap(), vec![0.2, 0.4]);
        for bad in ["0,0.5", "x", "0.5:0.1:0.1", "-1"] {
            let e = parse_levels(bad).unwrap_err().to_string();
            assert!(e.starts_with(&format!("--levels '{bad}': ")), "{e}");
        }
    }

    #[test]
    fn measure_labels_name_period_and_damping() {
        assert_eq!(Measure::Pga.label(), "pga");
        let sa = |period, damping| Measure::Sa { period, damping }.label();
        assert_eq!(sa(0.25, 0.05), "sa(0.25s,5%)");
        assert_eq!(sa(1.0, 0.07), "sa(1s,7%)");
        assert_eq!(sa(0.38924, 0.025), "sa(0.38924s,2.5%)");
    }

    /// A constant ground acceleration −a0 from rest: u = a0/ω² (1 − e^{−ζωt}(cos ω_Dt +
    /// ζ/√(1−ζ²) sin ω_Dt)), first peak at t = π/ω_D: u = a0/ω² (1 + e^{−ζπ/√(1−ζ²)}).
    #[test]
    fn a_constant_acceleration_peaks_at_its_closed_form() {
        let (a0, period) = (1.7, 0.4);
        for zeta in [0.0, 0.02, 0.05, 0.3] {
            let w = 2.0 * std::f64::consts::PI / period;
            let wd = w * (1.0f64 - zeta * zeta).sqrt();
            let r = zeta / (1.0f64 - zeta * zeta).sqrt();
            // a node at every 1/100 of the first peak's time, the record to 1.3 of it
            let dt = std::f64::consts::PI / wd / 100.0;
            let acc = vec![-a0; 131];
            let exact = |t: f64| {
                a0 / (w * w) * (1.0 - (-zeta * w * t).exp() * ((wd * t).cos() + r * (wd * t).sin()))
            };
            // the recurrence at each node against the closed form
            let osc = Oscillator::new(w, zeta, dt);
            let (mut u, mut v) = (0.0, 0.0);
            for i in 1..acc.len() {
                let st = osc.step(u, v, a0, a0);
                (u, v) = osc.state(st, dt, (osc.decay, osc.cos, osc.sin));
                let e = exact(i as f64 * dt);
                assert!((u - e).abs() <= 1e-12 * a0 / (w * w), "ζ {zeta} node {i}");
            }
            // the record is short of the second peak: the peak is the first one
            let sa = pseudo_acceleration(&acc, dt, period, zeta);
            let want = a0 * (1.0 + (-r * std::f64::consts::PI).exp());
            assert!(
                (sa - want).abs() <= 1e-10 * want,
                "ζ {zeta}: {sa} vs {want}"
            );
        }
    }

    /// The response to the ramp f = t·H(t) from rest:
    /// R(t) = t/ω² − 2ζ/ω³ + e^{−ζωt}(2ζ/ω³ cos ω_Dt + (2ζ² − 1)/(ω²ω_D) sin ω_Dt).
    fn ramp(t: f64, w: f64, z: f64) -> f64 {
        if t <= 0.0 {
            return 0.0;
        }
        let wd = w * (1.0 - z * z).sqrt();
        let e = (-z * w * t).exp();
        t / (w * w) - 2.0 * z / w.powi(3)
            + e * (2.0 * z / w.powi(3) * (wd * t).cos()
                + (2.0 * z * z - 1.0) / (w * w * wd) * (wd * t).sin())
    }

    /// A triangular pulse a_g (0 → −p at t1 → 0 at t2, then 0) is a sum of three ramps;
    /// its peak |u|, taken on a grid of 2·10⁶ points of the closed form (inside the pulse and
    /// over two periods after it), against the recurrence's.
    #[test]
    fn a_triangular_pulse_peaks_as_its_sum_of_ramps() {
        let (p, t1, t2) = (2.5, 0.06, 0.2);
        for (period, zeta) in [(0.05, 0.05), (0.15, 0.02), (1.0, 0.05), (0.4, 0.0)] {
            let w = 2.0 * std::f64::consts::PI / period;
            let exact = |t: f64| {
                p / t1 * ramp(t, w, zeta) - p * t2 / (t1 * (t2 - t1)) * ramp(t - t1, w, zeta)
                    + p / (t2 - t1) * ramp(t - t2, w, zeta)
            };
            // samples 0.02 s apart: t1 and t2 are nodes
            let dt = 0.02;
            let acc: Vec<f64> = (0..11)
                .map(|i| {
                    let t = i as f64 * dt;
                    if t <= t1 {
                        -p * t / t1
                    } else {
                        -p * (t2 - t).max(0.0) / (t2 - t1)
                    }
                })
                .collect();
            let end = t2 + 2.0 * period;
            let n = 2_000_000;
            let grid = (0..=n).map(|k| exact(end * k as f64 / n as f64).abs());
            let want = grid.fold(0.0, f64::max);
            let got = peak_displacement(&acc, dt, w, zeta);
            // the grid's maximum is below the true one by O((ω h)²)
            let h = end / n as f64;
            let tol = 1e-10 + (w * h).powi(2);
            assert!(
                got >= want * (1.0 - 1e-12),
                "T {period}: {got} below {want}"
            );
            assert!((got - want) / want <= tol, "T {period}: {got} vs {want}");
        }
    }

    #[test]
    fn a_stiff_oscillator_follows_the_ground() {
        // Sa(T → 0) → PGA: within (ωdt)-small terms for T = 1 ms under a smooth record
        let dt = 0.01;
        let acc: Vec<f64> = (0..400)
            .map(|i| (i as f64 * dt * 7.0).sin() * (i as f64 * dt * 1.3).cos() * 3.0)
            .collect();
        let pga = Measure::Pga.of_component(&acc, dt);
        let sa = Measure::Sa {
            period: 1e-3,
            damping: 0.05,
        }
        .of_component(&acc, dt);
        assert!((sa - pga).abs() <= 1e-3 * pga, "{sa} vs {pga}");
        assert_eq!(pair_intensity(0.5, 2.0), 1.0);
    }
}
