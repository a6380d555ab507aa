//! Units typed with a number in the form: the field's own, or one that converts to it.

/// (field unit, typed unit, factor to the field's unit) of the units a number may carry.
pub const CONVERSIONS: [(&str, &str, f64); 10] = [
    ("m", "mm", 1e-3),
    ("m", "cm", 1e-2),
    ("s", "ms", 1e-3),
    ("t", "kg", 1e-3),
    ("kN", "N", 1e-3),
    ("kN", "MN", 1e3),
    ("kN/m", "kN/mm", 1e3),
    ("kN/m", "MN/m", 1e3),
    ("kN/m", "N/m", 1e-3),
    ("°", "deg", 1.0),
];

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
    if !u.is_empty() && !n.is_empty() {
        (n.trim_end(), u)
    } else {
        (t, "")
    }
}

/// The factor from the `typed` unit to the field's `unit` (1 without a unit).
pub(super) fn unit_factor(typed: &str, unit: &str) -> Result<f64, String> {
    if typed.is_empty() || typed == unit {
        return Ok(1.0);
    }
    if let Some((_, _, f)) = CONVERSIONS
        .iter()
        .find(|(u, t, _)| *u == unit && *t == typed)
    {
        return Ok(*f);
    }
    let mut taken: Vec<&str> = vec![unit];
    taken.extend(
        CONVERSIONS
            .iter()
            .filter(|(u, ..)| *u == unit)
            .map(|(_, t, _)| *t),
    );
    Err(if unit.is_empty() || unit == "–" {
        format!("'{typed}': this field takes a plain number")
    } else {
        format!(
            "'{typed}' is not a unit of this field (it takes {})",
            taken.join(", ")
        )
    })
}

pub(super) fn unit_hint(unit: &str) -> String {
    if unit.is_empty() || unit == "–" {
        String::new()
    } else {
        format!(" (in {unit})")
    }
}

#[cfg(test)]
mod tests {
    use crate::tui::form::{Kind, parse_input};

    #[test]
    fn numbers_take_their_units_and_convert() {
        let f = |raw: &str, unit: &str| parse_input(Kind::Float, raw, unit).map(|v| v.as_float());
        assert_eq!(f("0.02", "m"), Ok(Some(0.02)));
        assert_eq!(f("0.02 m", "m"), Ok(Some(0.02)));
        assert_eq!(f("20 mm", "m"), Ok(Some(20.0 * 1e-3)));
        assert_eq!(f("20mm", "m"), Ok(Some(20.0 * 1e-3)));
        assert_eq!(f("1.5 cm", "m"), Ok(Some(1.5e-2)));
        assert_eq!(f("650 kg", "t"), Ok(Some(650.0 * 1e-3)));
        assert_eq!(f("10 kN/mm", "kN/m"), Ok(Some(1e4)));
        assert_eq!(f("1e4", "kN/m"), Ok(Some(1e4)));
        assert_eq!(f("-3.5e-2 m", "m"), Ok(Some(-3.5e-2)));
        let e = f("20 kg", "m").unwrap_err();
        assert!(
            e.contains("'kg' is not a unit of this field (it takes m, mm, cm)"),
            "{e}"
        );
        let e = f("abc", "m").unwrap_err();
        assert!(e.contains("'abc' is not a number (in m)"), "{e}");
        let e = f("0.5 m", "–").unwrap_err();
        assert!(e.contains("plain number"), "{e}");
    }
}
