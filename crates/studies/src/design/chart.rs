//! The chart of fragility curves: per limit state the observed fraction at each level
//! (markers), the fitted curve, the bootstrap band and a dashed line at θ (unlabelled: the
//! curve's legend entry gives θ).

use super::fragility::{Fragility, group_text};
use crate::plot::{Axis, Band, Chart, Marker, RefLine, Series};

/// Text-chart glyphs of the fitted curves and of the observed fractions, per limit state.
const CURVE_GLYPHS: [char; 6] = ['*', '#', '+', '%', '=', '~'];
const POINT_GLYPHS: [char; 6] = ['o', '@', 'x', '&', '$', 'v'];

/// The curves of `fits` (one group) against the intensity `measure` (g).
pub fn chart(fits: &[Fragility], measure: &str) -> Chart {
    let group = fits
        .first()
        .map(|f| group_text(&f.group))
        .unwrap_or_default();
    let title = if group.is_empty() {
        "Fragility curves".to_string()
    } else {
        format!("Fragility curves at {group}")
    };
    let x_hi = (fits.iter())
        .flat_map(|f| f.curve.last().map(|p| p.x))
        .fold(0.0, f64::max);
    let x_axis = Axis::linear(&format!("intensity, {measure}"), "g");
    let x_axis = if x_hi > 0.0 {
        x_axis.with_range(0.0, x_hi)
    } else {
        x_axis
    };
    let mut c = Chart::new(
        &title,
        x_axis,
        Axis::linear("P(exceed)", "").with_range(0.0, 1.0),
    );
    for (k, f) in fits.iter().enumerate() {
        let name = &f.limit.name;
        if f.band.is_some() {
            let pts: Vec<(f64, f64, f64)> = (f.curve.iter())
                .filter_map(|p| Some((p.x, p.lo?, p.hi?)))
                .collect();
            c.bands.push(Band {
                label: format!("{name}: 5–95 % band"),
                points: pts,
                color: k,
            });
        }
        // unlabelled: the curve's legend entry gives θ
        c.lines.push(RefLine::vertical(f.fit.theta, "", k));
        let observed: Vec<(f64, f64)> = (f.levels.iter())
            .filter(|l| l.runs > 0)
            .map(|l| (l.level, l.exceed as f64 / l.runs as f64))
            .collect();
        c.series.push(
            Series::points(&format!("{name}: observed"), observed)
                .marker(Marker::Circle)
                .color(k)
                .glyph(POINT_GLYPHS[k % POINT_GLYPHS.len()]),
        );
        let fitted: Vec<(f64, f64)> = f.curve.iter().map(|p| (p.x, p.p)).collect();
        c.series.push(
            Series::line(
                &format!("{name}: θ = {:.3} g, β = {:.3}", f.fit.theta, f.fit.beta),
                fitted,
            )
            .color(k)
            .glyph(CURVE_GLYPHS[k % CURVE_GLYPHS.len()]),
        );
    }
    c
}
