//! Seats under the deck ends: the seat width of a bridge file, and the minimum support length
//! of AASHTO LRFD 4.7.4.4 it is compared with.

use crate::model::check::{Check, ModelError};
use crate::scene::Seat;

/// Feet per metre.
const FT_PER_M: f64 = 1.0 / 0.3048;
/// Metres per inch.
const M_PER_IN: f64 = 0.0254;

/// AASHTO LRFD 4.7.4.4: N = (8 + 0.02 L + 0.08 H)(1 + 0.000125 S²) in., with L the deck length
/// to the next joint or its end (ft), H the average height of the columns supporting it (ft)
/// and S the skew (degrees); in metres.
pub(crate) fn aashto_support_length(length: f64, height: f64, skew_deg: f64) -> f64 {
    let n_in = (8.0 + 0.02 * length * FT_PER_M + 0.08 * height * FT_PER_M)
        * (1.0 + 0.000125 * skew_deg * skew_deg);
    n_in * M_PER_IN
}

/// The seats of one support line: the corner contacts on it and the deck they carry.
pub(super) struct SeatSpec {
    /// Field prefix of `seat_width`, `seat_percent` (`abutment`, `joint.{j}`).
    pub table: String,
    pub width: Option<f64>,
    pub percent: Option<f64>,
    /// (contact index, initial gap) of the corners on this seat.
    pub corners: Vec<(usize, f64)>,
    /// AASHTO's L (deck length to the next joint or end; both sides at a hinge), H (average
    /// height of the columns supporting it), m, and S (skew, degrees).
    pub length: f64,
    pub height: f64,
    pub skew: f64,
}

/// One seat per corner contact of each line with a `seat_width` (AASHTO's N from its L, H, S,
/// times its `seat_percent`).
pub(super) fn seats(lines: &[SeatSpec], ck: &Check) -> Result<Vec<Seat>, ModelError> {
    let mut out = Vec::new();
    for f in lines {
        let field = |k: &str| format!("{}.{k}", f.table);
        let Some(width) = f.width else {
            if f.percent.is_some() {
                return Err(ck.err(
                    &field("seat_percent"),
                    format!(
                        "needs {} (the seat it is compared with)",
                        field("seat_width")
                    ),
                ));
            }
            continue;
        };
        let width = ck.positive(&field("seat_width"), width)?;
        let percent = match f.percent {
            Some(p) => ck.positive(&field("seat_percent"), p)?,
            None => 100.0,
        };
        let m = ck.units.per_metre();
        let n = m * aashto_support_length(f.length / m, f.height / m, f.skew);
        out.extend(f.corners.iter().map(|&(contact, gap)| Seat {
            contact,
            width,
            edge: width + gap,
            required: Some((n * percent / 100.0, percent)),
        }));
    }
    Ok(out)
}
