//! A sensitivity study's tornado chart as `plot` data: a row per input, the widest swing on
//! top, a bar from the base value to the value at the input's low value and one to the value at
//! its high value, around a dashed line at the base value.

use super::swings::{Sensitivity, range_text, sort_by_swing};
use crate::plot::{Axis, Bars, Chart, RefLine};

/// Mark of the bars to the value at an input's low value in the text chart.
pub(crate) const LOW_GLYPH: char = '=';
/// Mark of the bars to the value at an input's high value.
pub(crate) const HIGH_GLYPH: char = '#';

/// The unit of a quantity of `suite::row::METRICS` (lengths are in the model's units).
pub fn unit(quantity: &str) -> &'static str {
    match quantity {
        "peak_rotation" | "residual_rotation" => "rad",
        _ => "",
    }
}

/// The tornado of quantity `q` (an index into [`Sensitivity::quantities`]); `None` when
/// there is no such quantity.
pub fn tornado(s: &Sensitivity, q: usize) -> Option<Chart> {
    let name = s.quantities.get(q)?;
    let cases = s.cases();
    let mut c = Chart::new(
        &format!("Tornado: {name} (median over {cases} cases)"),
        Axis::linear(name, unit(name)),
        Axis::linear("", ""),
    );
    let mut inputs = s.inputs.clone();
    sort_by_swing(&mut inputs, q);
    let mut low = Bars {
        label: "at the low value".into(),
        bars: Vec::new(),
        color: 0,
        glyph: LOW_GLYPH,
    };
    let mut high = Bars {
        label: "at the high value".into(),
        glyph: HIGH_GLYPH,
        color: 3,
        ..low.clone()
    };
    for (row, i) in inputs.iter().enumerate() {
        c.rows
            .push(format!("{} ({})", i.input.name, range_text(&i.input)));
        let Some(w) = i.swings.get(q) else { continue };
        if let (Some(b), Some(l), Some(h)) = (w.base, w.low, w.high) {
            low.bars.push((row, b, l));
            high.bars.push((row, b, h));
        }
    }
    c.bars = vec![low, high];
    if let Some(b) = s.base.get(q).copied().flatten() {
        c.lines
            .push(RefLine::vertical(b, &format!("base {b:.4e}"), 7));
    }
    Some(c)
}
