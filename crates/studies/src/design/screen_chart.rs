//! The screening maps as `plot` grids: rows of skew (60° at the top), columns of L/B, the
//! model's end marked `@`.

use super::screen::{Corners, Flush, MapCell};
use crate::plot::{Category, Cell, Grid, GridRow};

fn category(name: &str, glyph: char, color: usize) -> Category {
    Category {
        name: name.into(),
        glyph,
        color,
    }
}

/// The two maps of [`super::screen::screening_map`] over `lb` × `skew` (degrees) for μ and ε:
/// what a flush impact does, and which corner sticks when struck alone; `point` (L/B, skew°)
/// marks the model's cell. The bottom row's cells carry their L/B.
pub fn map_grids(
    cells: &[MapCell],
    lb: &[f64],
    skew: &[f64],
    point: Option<(usize, usize)>,
    mu: f64,
    eps: f64,
) -> [Grid; 2] {
    let flush = |m: &MapCell| Flush::ALL.iter().position(|f| *f == m.flush).unwrap_or(0);
    let corner = |m: &MapCell| {
        let c = m.corners();
        Corners::ALL.iter().position(|k| *k == c).unwrap_or(0)
    };
    let rows = |f: &dyn Fn(&MapCell) -> usize| -> Vec<GridRow> {
        (0..skew.len())
            .rev()
            .map(|r| GridRow {
                label: format!("{:.0}°", skew[r]),
                cells: (0..lb.len())
                    .map(|c| Cell {
                        label: if point == Some((c, r)) {
                            "@".into()
                        } else if r == 0 {
                            format!("{:.3}", lb[c]).chars().take(4).collect()
                        } else {
                            String::new()
                        },
                        category: f(&cells[r * lb.len() + c]),
                    })
                    .collect(),
            })
            .collect()
    };
    let columns = format!(
        "L/B {:.0} … {:.0} (log), skew φ 0 … {:.0}°; @ this model",
        lb[0],
        lb[lb.len() - 1],
        skew[skew.len() - 1]
    );
    [
        Grid {
            title: format!("After a flush impact of the end (μ {mu}, ε {eps})"),
            columns: columns.clone(),
            rows: rows(&flush),
            categories: (Flush::ALL.iter().zip([2, 1, 3]))
                .map(|(f, color)| category(f.name(), f.glyph(), color))
                .collect(),
        },
        Grid {
            title: format!("A corner struck alone against a rigid face (μ {mu}, ε {eps})"),
            columns,
            rows: rows(&corner),
            categories: (Corners::ALL.iter().zip([0, 4, 1, 7]))
                .map(|(c, color)| category(c.name(), c.glyph(), color))
                .collect(),
        },
    ]
}
