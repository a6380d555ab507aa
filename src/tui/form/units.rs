//! Units typed with a number in the form: the field's own, or another unit of the field's
//! quantity in any of the unit systems (`20 mm` or `0.5 in` into a length in m, `12.7 mm` into
//! a length in in, `10 kN/mm`, `3 kip`, `50 ms` …), converted to the field's unit.

use crate::tui::form::spec::{Dim, Kind};
use crate::units::{Quantity, UnitSystem, ascii_unit};
use toml_edit::Value;

/// N per kip (1 lbf = 4.4482216152605 N exactly).
const N_PER_KIP: f64 = 4_448.221_615_260_5;
const N_PER_LBF: f64 = 4.448_221_615_260_5;
/// m per inch and per foot (exact).
const M_PER_IN: f64 = 0.0254;
const M_PER_FT: f64 = 0.3048;

/// The units a number of quantity `q` may carry: (name, value of one in SI base units: kg, m,
/// s, N, rad for angles in radians, degrees for angles in degrees). Each system's own unit
/// ([`UnitSystem::unit`]) is among them.
fn units_of(q: Quantity) -> Vec<(&'static str, f64)> {
    use Quantity as Q;
    let kip_s2_in = N_PER_KIP / M_PER_IN;
    let deg = std::f64::consts::PI / 180.0;
    match q {
        Q::Length => vec![
            ("m", 1.0),
            ("mm", 1e-3),
            ("cm", 1e-2),
            ("km", 1e3),
            ("in", M_PER_IN),
            ("ft", M_PER_FT),
        ],
        Q::Mass => vec![("t", 1e3), ("kg", 1.0), ("kip·s²/in", kip_s2_in)],
        Q::Inertia => vec![
            ("t·m²", 1e3),
            ("kg·m²", 1.0),
            ("kip·s²·in", kip_s2_in * M_PER_IN * M_PER_IN),
        ],
        Q::Time => vec![
            ("s", 1.0),
            ("ms", 1e-3),
            ("us", 1e-6),
            ("µs", 1e-6),
            ("min", 60.0),
        ],
        Q::Force => vec![
            ("kN", 1e3),
            ("N", 1.0),
            ("MN", 1e6),
            ("kip", N_PER_KIP),
            ("lbf", N_PER_LBF),
        ],
        Q::Stiffness => vec![
            ("kN/m", 1e3),
            ("N/m", 1.0),
            ("MN/m", 1e6),
            ("kN/mm", 1e6),
            ("N/mm", 1e3),
            ("kip/in", N_PER_KIP / M_PER_IN),
            ("kip/ft", N_PER_KIP / M_PER_FT),
            ("lbf/in", N_PER_LBF / M_PER_IN),
        ],
        Q::Damping => vec![
            ("kN·s/m", 1e3),
            ("N·s/m", 1.0),
            ("kip·s/in", N_PER_KIP / M_PER_IN),
        ],
        Q::Moment | Q::Energy => vec![
            ("kN·m", 1e3),
            ("N·m", 1.0),
            ("kJ", 1e3),
            ("J", 1.0),
            ("kip·in", N_PER_KIP * M_PER_IN),
            ("kip·ft", N_PER_KIP * M_PER_FT),
        ],
        Q::RotationalStiffness => vec![
            ("kN·m/rad", 1e3),
            ("N·m/rad", 1.0),
            ("kip·in/rad", N_PER_KIP * M_PER_IN),
            ("kip·ft/rad", N_PER_KIP * M_PER_FT),
        ],
        Q::RotationalDamping => vec![
            ("kN·m·s/rad", 1e3),
            ("N·m·s/rad", 1.0),
            ("kip·in·s/rad", N_PER_KIP * M_PER_IN),
        ],
        Q::Velocity => vec![("m/s", 1.0), ("mm/s", 1e-3), ("in/s", M_PER_IN)],
        Q::Acceleration => vec![("m/s²", 1.0), ("in/s²", M_PER_IN)],
        Q::Angle => vec![("rad", 1.0), ("deg", deg), ("°", deg)],
        Q::Degrees => vec![("°", 1.0), ("deg", 1.0), ("rad", 1.0 / deg)],
        Q::AngularVelocity => vec![("rad/s", 1.0), ("deg/s", deg)],
    }
}

/// The units a field of this dimension takes (its own first): (name, factor to the field's
/// unit).
fn taken(dim: Dim, sys: UnitSystem) -> Vec<(String, f64)> {
    match dim {
        Dim::Q(q) => {
            let all = units_of(q);
            let own = sys.unit(q);
            let base = (all.iter().find(|(n, _)| *n == own)).map_or(1.0, |(_, f)| *f);
            let mut out = vec![(own.to_string(), 1.0)];
            out.extend(
                all.iter()
                    .filter(|(n, _)| *n != own)
                    .map(|(n, f)| (n.to_string(), f / base)),
            );
            out
        }
        Dim::G => vec![
            ("g".into(), 1.0),
            ("m/s²".into(), 1.0 / crate::units::G_SI),
            ("in/s²".into(), M_PER_IN / crate::units::G_SI),
        ],
        Dim::Percent => vec![("%".into(), 1.0)],
        Dim::Count | Dim::Ratio | Dim::Plain | Dim::State | Dim::Choice(_) | Dim::Methods => {
            Vec::new()
        }
    }
}

/// The units a field of this dimension takes besides its own (shown with the field).
pub fn others_taken(dim: Dim, sys: UnitSystem) -> Vec<String> {
    taken(dim, sys)
        .into_iter()
        .skip(1)
        .map(|(u, _)| u)
        .collect()
}

/// A unit's spelling for comparison: ASCII (`*` for `·`, `^2` for `²`, `deg` for `°`).
fn canon(u: &str) -> String {
    ascii_unit(u).replace(' ', "")
}

/// "20 mm" → ("20", "mm"); "0.02" → ("0.02", ""): the unit is what follows the last character
/// a number can end with, after blanks.
pub(super) fn split_unit(t: &str) -> (&str, &str) {
    let end = t
        .char_indices()
        .filter(|(_, c)| c.is_ascii_digit() || *c == '.')
        .map(|(i, c)| i + c.len_utf8())
        .next_back()
        .unwrap_or(0);
    let (n, u) = t.split_at(end);
    let u = u.trim();
    // an exponent or a sign glued to the number belongs to it ("1e4", "inf", "nan")
    if u.chars().next().is_some_and(|c| c == 'e' || c == 'E') && n.chars().all(|c| c != ' ') {
        return (t, "");
    }
    // a unit with a digit in it ("s²/in"): the digits belong to the unit
    if let Some(k) = t.find(|c: char| c.is_alphabetic() && c != 'e' && c != 'E') {
        let (n2, u2) = t.split_at(k);
        if !n2.trim().is_empty() && u2.chars().any(|c| c.is_ascii_digit()) {
            return (n2.trim_end(), u2.trim());
        }
    }
    if !u.is_empty() && !n.is_empty() {
        (n.trim_end(), u)
    } else {
        (t, "")
    }
}

/// Whether what is being typed carries a unit of its own ("20 mm", not "20" nor "1e-4").
pub fn carries_unit(typed: &str) -> bool {
    !split_unit(typed.trim()).1.is_empty()
}

/// The factor from the `typed` unit to the field's unit (1 without a unit).
pub(super) fn unit_factor(typed: &str, dim: Dim, sys: UnitSystem) -> Result<f64, String> {
    let own = dim.unit(sys);
    if typed.is_empty() || typed == own {
        return Ok(1.0);
    }
    let units = taken(dim, sys);
    let t = canon(typed);
    if let Some((_, f)) = units.iter().find(|(u, _)| canon(u) == t) {
        return Ok(*f);
    }
    Err(if units.is_empty() {
        format!("'{typed}': this field takes a plain number")
    } else {
        let names: Vec<&str> = units.iter().map(|(u, _)| u.as_str()).collect();
        format!(
            "'{typed}' is not a unit of this field (it takes {})",
            names.join(", ")
        )
    })
}

fn unit_hint(unit: &str) -> String {
    if unit.is_empty() || unit == "–" || unit == "#" {
        String::new()
    } else {
        format!(" (in {unit})")
    }
}

/// A converted number rounded to 15 significant digits (`12.7 mm` in in is 0.5, not
/// 0.5000000000000001); unconverted numbers are kept as typed.
fn tidy(v: f64) -> f64 {
    if !v.is_finite() || v == 0.0 {
        return v;
    }
    format!("{v:.14e}").parse().unwrap_or(v)
}

/// Parses what the user typed for a field of this kind. A number may carry a unit: the
/// field's own ("0.02 m") or one of its quantity in any system ("20 mm", "0.5 in", "1e4
/// kN/mm", "650 kg"); any other unit is refused, naming the ones taken.
pub fn parse_input(kind: Kind, raw: &str, dim: Dim, sys: UnitSystem) -> Result<Value, String> {
    let t = raw.trim();
    if t.is_empty() {
        return Err(format!("empty: expected a {}", kind.name()));
    }
    let unit = dim.unit(sys);
    match kind {
        Kind::Float => {
            let (number, typed) = split_unit(t);
            let factor = unit_factor(typed, dim, sys)?;
            let v = match number.parse::<Value>() {
                Ok(Value::Float(f)) => *f.value(),
                Ok(Value::Integer(i)) => *i.value() as f64,
                _ => number
                    .parse::<f64>()
                    .map_err(|_| format!("'{number}' is not a number{}", unit_hint(&unit)))?,
            };
            Ok(Value::from(if factor == 1.0 {
                v
            } else {
                tidy(v * factor)
            }))
        }
        Kind::Int => match t
            .strip_suffix(unit.as_str())
            .filter(|_| !unit.is_empty())
            .unwrap_or(t)
            .trim_end()
            .parse::<Value>()
        {
            Ok(Value::Integer(i)) => Ok(Value::Integer(i)),
            _ => Err(format!("'{t}' is not an integer")),
        },
        Kind::Bool => match t.to_ascii_lowercase().as_str() {
            "true" | "yes" | "on" | "1" => Ok(Value::from(true)),
            "false" | "no" | "off" | "0" => Ok(Value::from(false)),
            _ => Err(format!("'{t}' is not true or false")),
        },
        Kind::Str => match t.parse::<Value>() {
            Ok(Value::String(s)) => Ok(Value::String(s)),
            _ => Ok(Value::from(t)),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::{Dim, Kind, parse_input, split_unit};
    use crate::units::{Quantity as Q, UnitSystem as U};

    fn f(raw: &str, dim: Dim, sys: U) -> Result<Option<f64>, String> {
        parse_input(Kind::Float, raw, dim, sys).map(|v| v.as_float())
    }

    #[test]
    fn numbers_take_their_units_and_convert() {
        let m = Dim::Q(Q::Length);
        let si = U::SiKn;
        assert_eq!(f("0.02", m, si), Ok(Some(0.02)));
        assert_eq!(f("0.02 m", m, si), Ok(Some(0.02)));
        assert_eq!(f("20 mm", m, si), Ok(Some(0.02)));
        assert_eq!(f("20mm", m, si), Ok(Some(0.02)));
        assert_eq!(f("1.5 cm", m, si), Ok(Some(0.015)));
        assert_eq!(f("650 kg", Dim::Q(Q::Mass), si), Ok(Some(0.65)));
        assert_eq!(f("10 kN/mm", Dim::Q(Q::Stiffness), si), Ok(Some(1e4)));
        assert_eq!(f("1e4", Dim::Q(Q::Stiffness), si), Ok(Some(1e4)));
        assert_eq!(f("-3.5e-2 m", m, si), Ok(Some(-3.5e-2)));
        assert_eq!(f("50 ms", Dim::Q(Q::Time), si), Ok(Some(0.05)));
        // microseconds, as `us` or `µs`: solver steps and tolerances are typed in them
        assert_eq!(f("20 us", Dim::Q(Q::Time), si), Ok(Some(2e-5)));
        assert_eq!(f("20 µs", Dim::Q(Q::Time), si), Ok(Some(2e-5)));
        assert_eq!(f("2 MN", Dim::Q(Q::Force), si), Ok(Some(2000.0)));
        let e = f("20 kg", m, si).unwrap_err();
        assert!(
            e.contains("'kg' is not a unit of this field (it takes m, mm, cm, km, in, ft)"),
            "{e}"
        );
        let e = f("abc", m, si).unwrap_err();
        assert!(e.contains("'abc' is not a number (in m)"), "{e}");
        let e = f("0.5 m", Dim::Ratio, si).unwrap_err();
        assert!(e.contains("plain number"), "{e}");
    }

    #[test]
    fn us_units_convert_both_ways_exactly() {
        let len = Dim::Q(Q::Length);
        // into a field in m, and into a field in in
        assert_eq!(f("0.5 in", len, U::SiKn), Ok(Some(0.0127)));
        assert_eq!(f("12.7 mm", len, U::KipIn), Ok(Some(0.5)));
        assert_eq!(f("2 ft", len, U::KipIn), Ok(Some(24.0)));
        assert_eq!(f("1 ft", len, U::Si), Ok(Some(0.3048)));
        assert_eq!(f("1 m", len, U::KipIn), Ok(Some(39.3700787401575)));
        let force = Dim::Q(Q::Force);
        assert_eq!(f("1 kip", force, U::SiKn), Ok(Some(4.4482216152605)));
        assert_eq!(f("1000 lbf", force, U::KipIn), Ok(Some(1.0)));
        assert_eq!(f("4.4482216152605 kN", force, U::KipIn), Ok(Some(1.0)));
        assert_eq!(f("1 kip", force, U::Si), Ok(Some(4448.2216152605)));
        let k = Dim::Q(Q::Stiffness);
        assert_eq!(f("1 kip/in", k, U::SiKn), Ok(Some(175.126835246476)));
        assert_eq!(f("12 kip/ft", k, U::KipIn), Ok(Some(1.0)));
        // the system's own units, in ASCII too
        let mass = Dim::Q(Q::Mass);
        assert_eq!(f("2 kip·s²/in", mass, U::KipIn), Ok(Some(2.0)));
        assert_eq!(f("2 kip*s^2/in", mass, U::KipIn), Ok(Some(2.0)));
        assert_eq!(f("1 kip*s^2/in", mass, U::SiKn), Ok(Some(175.126835246476)));
        assert_eq!(f("0.5 g", Dim::G, U::KipIn), Ok(Some(0.5)));
        assert_eq!(f("9.80665 m/s²", Dim::G, U::SiKn), Ok(Some(1.0)));
        assert_eq!(f("30 deg", Dim::Q(Q::Degrees), U::SiKn), Ok(Some(30.0)));
        // a kip-in field names the US units first
        let e = f("3 kg", force, U::KipIn).unwrap_err();
        assert!(e.contains("(it takes kip, kN, N, MN, lbf)"), "{e}");
    }

    #[test]
    fn units_with_digits_split_from_the_number() {
        assert_eq!(split_unit("2 kip*s^2/in"), ("2", "kip*s^2/in"));
        assert_eq!(split_unit("1.5e-3 m"), ("1.5e-3", "m"));
        assert_eq!(split_unit("1e4"), ("1e4", ""));
        assert_eq!(split_unit("-2"), ("-2", ""));
    }
}
