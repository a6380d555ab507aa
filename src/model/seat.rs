//! Seats under the deck ends: the seat width of a bridge file, and the minimum support length
//! of AASHTO LRFD 4.7.4.4 it is compared with.

use super::check::{Check, ModelError};
use crate::scene::Seat;

/// Feet per metre.
const FT_PER_M: f64 = 1.0 / 0.3048;
/// Metres per inch.
const M_PER_IN: f64 = 0.0254;

/// AASHTO LRFD 4.7.4.4: N = (8 + 0.02 L + 0.08 H)(1 + 0.000125 S²) in., with L the deck length
/// to the next joint or its end (ft), H the average height of the columns supporting it (ft)
/// and S the skew (degrees); in metres.
pub fn aashto_support_length(length: f64, height: f64, skew_deg: f64) -> f64 {
    let n_in = (8.0 + 0.02 * length * FT_PER_M + 0.08 * height * FT_PER_M)
        * (1.0 + 0.000125 * skew_deg * skew_deg);
    n_in * M_PER_IN
}

/// What a bridge file says of its seats and the deck they carry.
pub(super) struct SeatSpec {
    /// `abutment.seat_width`, `abutment.seat_percent`.
    pub width: Option<f64>,
    pub percent: Option<f64>,
    /// The corners' initial gaps, m.
    pub gaps: [f64; 4],
    /// Deck length, the bents' average height (m), skew (degrees).
    pub length: f64,
    pub height: f64,
    pub skew: f64,
}

/// One seat per corner contact when `abutment.seat_width` is given (the deck's length, the
/// bents' average height and the skew give AASHTO's N, times `abutment.seat_percent`).
pub(super) fn seats(f: &SeatSpec, ck: &Check) -> Result<Vec<Seat>, ModelError> {
    let Some(width) = f.width else {
        if f.percent.is_some() {
            return Err(ck.err(
                "abutment.seat_percent",
                "needs abutment.seat_width (the seat it is compared with)",
            ));
        }
        return Ok(Vec::new());
    };
    let width = ck.positive("abutment.seat_width", width)?;
    let percent = match f.percent {
        Some(p) => ck.positive("abutment.seat_percent", p)?,
        None => 100.0,
    };
    let n = aashto_support_length(f.length, f.height, f.skew);
    Ok((0..f.gaps.len())
        .map(|contact| Seat {
            contact,
            width,
            edge: width + f.gaps[contact],
            required: Some((n * percent / 100.0, percent)),
        })
        .collect())
}
