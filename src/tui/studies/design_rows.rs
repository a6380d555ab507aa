//! The rows of the two design studies as the studies view shows them and its cursor steps
//! through: the model ladder's (the full model, then each variant in the study's order) and
//! the swings' (the inputs, widest swing of the shown quantity first, as the tornado draws
//! them).

use crate::design::adequacy::Adequacy;
use crate::design::swings::{InputSwings, Sensitivity, Swing};
use crate::study_table::StudyTable;

/// The number of rows of the ladder's or the swings' table (None: another study's table).
pub fn rows(table: &StudyTable) -> Option<usize> {
    match table {
        StudyTable::Adequacy(a) => Some(1 + a.variants.len()),
        StudyTable::Sensitivity(s) => Some(s.inputs.len()),
        _ => None,
    }
}

/// The ladder's row `row`: `None` the full model, else the index of its variant.
pub fn variant_of_row(a: &Adequacy, row: usize) -> Option<usize> {
    row.checked_sub(1).filter(|v| *v < a.variants.len())
}

/// The quantity shown of the swings: `q` held within their quantities.
pub fn quantity(s: &Sensitivity, q: usize) -> usize {
    q.min(s.quantities.len().saturating_sub(1))
}

/// The inputs' indices in the order of the rows for quantity `q`: widest |swing| first, those
/// without a swing last, ties in the study's order (`swings::sort_by_swing`, the tornado's).
pub fn order(s: &Sensitivity, q: usize) -> Vec<usize> {
    let key = |i: &InputSwings| i.swings.get(q).and_then(Swing::swing).map(f64::abs);
    let mut idx: Vec<usize> = (0..s.inputs.len()).collect();
    idx.sort_by(|&a, &b| match (key(&s.inputs[a]), key(&s.inputs[b])) {
        (Some(x), Some(y)) => y.total_cmp(&x),
        (Some(_), None) => std::cmp::Ordering::Less,
        (None, Some(_)) => std::cmp::Ordering::Greater,
        (None, None) => std::cmp::Ordering::Equal,
    });
    idx
}
