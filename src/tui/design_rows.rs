//! The rows of the design studies as the studies view shows them and its cursor steps
//! through: the model ladder's (the full model, then each variant in the study's order).

use crate::design::adequacy::Adequacy;
use crate::study_table::StudyTable;

/// The number of rows of the ladder's table (None: another study's table).
pub fn rows(table: &StudyTable) -> Option<usize> {
    match table {
        StudyTable::Adequacy(a) => Some(1 + a.variants.len()),
        _ => None,
    }
}

/// The ladder's row `row`: `None` the full model, else the index of its variant.
pub fn variant_of_row(a: &Adequacy, row: usize) -> Option<usize> {
    row.checked_sub(1).filter(|v| *v < a.variants.len())
}
