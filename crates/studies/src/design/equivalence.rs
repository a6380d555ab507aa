//! Gap-element equivalence: which contact stiffness k and step h make the penalty method (gap
//! elements, as OpenSees users build them) give the event-driven peak rotation within 1, 5, 10 %.

use crate::methods::Method;
use crate::precision::{Bench, Point, Reference};
use crate::progress::Progress;
use rayon::prelude::*;
use serde::Serialize;

/// One (k, h) of the grid and its work–precision point.
#[derive(Clone, Debug, Serialize)]
pub struct Cell {
    /// Contact stiffness k (`solver.contact_stiffness`), model units (kN/m).
    pub k: f64,
    /// Step h (`solver.step`), s.
    pub h: f64,
    pub point: Point,
}

impl Cell {
    /// Finished with a peak error of at most `tol` (relative).
    pub fn within(&self, tol: f64) -> bool {
        self.point.is_ok() && self.point.peak_error <= tol
    }
}

/// The penalty `method` over every k × h, in parallel, its runs reported to `progress`. Cells
/// in the order k-major, as given.
pub fn grid(
    bench: &Bench,
    reference: &Reference,
    method: Method,
    ks: &[f64],
    hs: &[f64],
    progress: &dyn Progress,
) -> Vec<Cell> {
    let pairs: Vec<(f64, f64)> = ks
        .iter()
        .flat_map(|&k| hs.iter().map(move |&h| (k, h)))
        .collect();
    progress.plan(pairs.len());
    pairs
        .par_iter()
        .map(|&(k, h)| {
            let set = [
                format!("solver.contact_stiffness={k:e}"),
                format!("solver.step={h:e}"),
            ];
            let point = bench.measure(reference, method, &format!("k={k:e} h={h:e}"), &set);
            progress.done(1);
            Cell { k, h, point }
        })
        .collect()
}

/// The answer for one tolerance.
#[derive(Clone, Debug, Serialize)]
pub struct Answer {
    pub tol: f64,
    /// The cell within `tol` with the fewest steps (the largest h; then the smaller k).
    pub cheapest: Option<(f64, f64)>,
    /// For each k: the largest h within `tol` (None: none of the steps tried).
    pub largest_step: Vec<(f64, Option<f64>)>,
}

/// [`Answer`]s for each tolerance of `tols`.
pub fn answers(cells: &[Cell], tols: &[f64]) -> Vec<Answer> {
    let mut ks: Vec<f64> = cells.iter().map(|c| c.k).collect();
    ks.sort_by(f64::total_cmp);
    ks.dedup();
    tols.iter()
        .map(|&tol| {
            let ok: Vec<&Cell> = cells.iter().filter(|c| c.within(tol)).collect();
            let cheapest = ok
                .iter()
                .min_by(|a, b| b.h.total_cmp(&a.h).then(a.k.total_cmp(&b.k)))
                .map(|c| (c.k, c.h));
            let largest_step = ks
                .iter()
                .map(|&k| {
                    let h = (ok.iter().filter(|c| c.k == k).map(|c| c.h))
                        .fold(None, |m, h| Some(m.map_or(h, |m: f64| m.max(h))));
                    (k, h)
                })
                .collect();
            Answer {
                tol,
                cheapest,
                largest_step,
            }
        })
        .collect()
}

/// The default grid: k = 1e4 … 1e8 (model units) and h = 4e-3 … 1e-4 s; `quick` fewer.
pub fn default_grid(quick: bool) -> (Vec<f64>, Vec<f64>) {
    if quick {
        (vec![1e5, 1e6, 1e7], vec![2e-3, 5e-4])
    } else {
        (
            vec![1e4, 1e5, 1e6, 1e7, 1e8],
            vec![4e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4],
        )
    }
}
