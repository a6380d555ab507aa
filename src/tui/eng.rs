//! Numbers as the workbench prints its readouts and axes: engineering notation (the exponent a
//! multiple of 3) with a fixed number of significant digits, an SI prefix on the units that
//! take one (`17.83 mm`, `266.5 µrad`, `-1.100 nm`, `162.7 N`; `u` for µ in ASCII mode) and
//! the exponent written out on the others (`1.234e3 kN/m`).

/// Significant digits of the readouts and axis labels.
pub const SIG: usize = 4;

/// Prefixes by power of ten (µ spelled `u` in ASCII mode).
const PREFIXES: [(i32, &str); 7] = [
    (-12, "p"),
    (-9, "n"),
    (-6, "µ"),
    (-3, "m"),
    (0, ""),
    (3, "k"),
    (6, "M"),
];

/// A unit that takes an SI prefix as (its base, the power of ten of its own prefix): `m`,
/// `rad`, `s`, and forces, impulses and moments (`kN` is N × 10³, printed `162.7 N` or
/// `1.234 MN`); None for the others, which keep their exponent.
fn prefixable(unit: &str) -> Option<(&str, i32)> {
    let base = |u: &str| matches!(u, "m" | "rad" | "s" | "N" | "N·s" | "N*s" | "N·m" | "N*m");
    match unit.strip_prefix('k') {
        Some(b) if b.starts_with('N') && base(b) => Some((b, 3)),
        _ => base(unit).then_some((unit, 0)),
    }
}

/// The prefix of power `e` (a multiple of 3), if the table has it.
fn prefix(e: i32, ascii: bool) -> Option<&'static str> {
    PREFIXES
        .iter()
        .find(|p| p.0 == e)
        .map(|p| if ascii && p.1 == "µ" { "u" } else { p.1 })
}

/// The engineering exponent of `v` rounded to `sig` digits (0 for 0 and non-finite values).
pub fn exponent(v: f64, sig: usize) -> i32 {
    if v == 0.0 || !v.is_finite() {
        return 0;
    }
    let e = v.abs().log10().floor() as i32;
    // rounding to `sig` digits may carry into the next decade (999.96 → 1000)
    let step = 10f64.powi(e + 1 - sig.max(1) as i32);
    let r = (v.abs() / step).round() * step;
    let e = r.log10().floor() as i32;
    e.div_euclid(3) * 3
}

/// Decimals that give `m` (a mantissa, or the largest value of a scale) `sig` digits.
fn decimals(m: f64, sig: usize) -> usize {
    let int_digits = if m.abs() >= 1.0 {
        m.abs().log10().floor() as i32 + 1
    } else {
        1
    };
    (sig as i32 - int_digits).max(0) as usize
}

/// `v` with `d` decimals, without a sign on a value that prints as zero.
fn fixed(v: f64, d: usize) -> String {
    let s = format!("{v:.d$}");
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
}

/// `v` with `sig` significant digits and its unit: `266.5 µrad`, `-1.100 nm`, `45.67 kN`,
/// `1.234e3 kN`, `0 m`; `""` as unit gives the bare number.
pub fn eng_sig(v: f64, unit: &str, sig: usize, ascii: bool) -> String {
    let join = |num: String, u: &str| {
        if u.is_empty() {
            num
        } else {
            format!("{num} {u}")
        }
    };
    if !v.is_finite() {
        return join(format!("{v}"), unit);
    }
    if v == 0.0 {
        return join("0".into(), unit);
    }
    let e = exponent(v, sig);
    let m = v / 10f64.powi(e);
    let num = fixed(m, decimals(m, sig));
    let prefixed = prefixable(unit).and_then(|(b, k)| prefix(e + k, ascii).map(|p| (b, p)));
    match prefixed {
        Some((b, p)) => join(num, &format!("{p}{b}")),
        None if e == 0 => join(num, unit),
        None => join(format!("{num}e{e}"), unit),
    }
}

/// `v` with [`SIG`] significant digits and its unit.
pub fn eng(v: f64, unit: &str, ascii: bool) -> String {
    eng_sig(v, unit, SIG, ascii)
}

/// One scale for several values (a chart's readouts): the unit with the prefix of the largest
/// magnitude, and as many decimals as give that magnitude [`SIG`] digits, so that every value
/// of the chart is printed with the same precision.
#[derive(Clone, Debug, PartialEq)]
pub struct Scale {
    /// Power of ten the values are divided by.
    pub e: i32,
    /// Decimals of every value.
    pub decimals: usize,
    /// The unit as printed: `mm`, `µrad`, `1e3 kN`.
    pub unit: String,
}

impl Scale {
    /// The scale of values whose largest magnitude is `max_abs`.
    pub fn new(max_abs: f64, unit: &str, ascii: bool) -> Scale {
        let e = if max_abs.is_finite() && max_abs > 0.0 {
            exponent(max_abs, SIG)
        } else {
            0
        };
        let prefixed = prefixable(unit).and_then(|(b, k)| prefix(e + k, ascii).map(|p| (b, p)));
        let unit = match prefixed {
            Some((b, p)) => format!("{p}{b}"),
            None if e == 0 => unit.to_string(),
            None => format!("1e{e} {unit}").trim_end().to_string(),
        };
        let decimals = if max_abs.is_finite() && max_abs > 0.0 {
            decimals(max_abs / 10f64.powi(e), SIG)
        } else {
            SIG - 1
        };
        Scale { e, decimals, unit }
    }

    /// The scale of values in a unit that keeps no prefix and no exponent (θ in `mrad` or
    /// `°`): [`SIG`] significant digits of `max_abs`, at most 6 decimals.
    pub fn fixed(max_abs: f64, unit: &str) -> Scale {
        let decimals = if max_abs.is_finite() && max_abs > 0.0 {
            let int_digits = max_abs.log10().floor() as i32 + 1;
            (SIG as i32 - int_digits).clamp(0, 6) as usize
        } else {
            SIG - 1
        };
        Scale {
            e: 0,
            decimals,
            unit: unit.to_string(),
        }
    }

    /// `v` in this scale, without its unit.
    pub fn fmt(&self, v: f64) -> String {
        if !v.is_finite() {
            return format!("{v}");
        }
        fixed(v / 10f64.powi(self.e), self.decimals)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn engineering_notation_with_prefixes() {
        assert_eq!(eng(266.5e-6, "rad", false), "266.5 µrad");
        assert_eq!(eng(266.5e-6, "rad", true), "266.5 urad");
        assert_eq!(eng(-1.1e-9, "m", false), "-1.100 nm");
        assert_eq!(eng(0.017834, "m", false), "17.83 mm");
        assert_eq!(eng(0.02778912, "m", false), "27.79 mm");
        assert_eq!(eng(-189.04e-6, "rad", false), "-189.0 µrad");
        assert_eq!(eng(105.757, "kN", false), "105.8 kN");
        assert_eq!(eng(1234.5, "kN", false), "1.234 MN");
        assert_eq!(eng(0.16271, "kN", false), "162.7 N");
        assert_eq!(eng(2.5e-3, "kN·s", false), "2.500 N·s");
        assert_eq!(eng(1234.5, "kN/m", false), "1.234e3 kN/m");
        assert_eq!(eng(0.9999999, "m", false), "1.000 m");
        assert_eq!(eng(999.96e-6, "m", false), "1.000 mm");
        assert_eq!(eng(0.0, "m", false), "0 m");
        assert_eq!(eng(2.5e-3, "", false), "2.500e-3");
        assert_eq!(eng(3.0e-20, "m", false), "30.00e-21 m");
    }

    #[test]
    fn one_scale_for_a_chart() {
        let s = Scale::new(0.01783, "m", false);
        assert_eq!(s.unit, "mm");
        assert_eq!(s.fmt(0.01783), "17.83");
        assert_eq!(s.fmt(0.004), "4.00");
        assert_eq!(s.fmt(-1.1e-9), "0.00");
        let s = Scale::new(266.5e-6, "rad", true);
        assert_eq!(
            (s.unit.as_str(), s.fmt(151.3e-6).as_str()),
            ("urad", "151.3")
        );
        assert_eq!(Scale::new(2000.0, "kN", false).unit, "MN");
        assert_eq!(Scale::new(2000.0, "kN/m", false).unit, "1e3 kN/m");
        let s = Scale::fixed(0.01406, "°");
        assert_eq!((s.unit.as_str(), s.fmt(-0.01406)), ("°", "-0.01406".into()));
        assert_eq!(Scale::fixed(2.8134, "mrad").fmt(2.8134), "2.813");
    }
}
