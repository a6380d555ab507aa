//! The structure under the frames: the bents'
//! columns (paper §4.1: Takeda in x and y, uncoupled; elastic torsion).

use super::layout::{Frame, Plan, frame_body};
use super::schema::ColumnSpec;
use crate::hysteresis::{Hysteretic, Law};
use crate::model::check::{Check, ModelError};
use crate::scene::{Attachment, HystereticElement, Spring};
use nalgebra::Vector2;

/// Scale a column law from the reference height to height h (fixed–fixed: k ∝ h⁻³, V_y ∝ h⁻¹).
fn scale_law(law: &Law, kf: f64, ff: f64) -> Law {
    match law.clone() {
        Law::Linear { stiffness } => Law::Linear {
            stiffness: stiffness * kf,
        },
        Law::Bilinear {
            stiffness,
            yield_force,
            post_yield_ratio,
        } => Law::Bilinear {
            stiffness: stiffness * kf,
            yield_force: yield_force * ff,
            post_yield_ratio,
        },
        Law::Takeda {
            stiffness,
            yield_force,
            post_yield_ratio,
            crack_force,
            yield_displacement,
            unloading_exponent,
        } => Law::Takeda {
            stiffness: stiffness * kf,
            yield_force: yield_force * ff,
            post_yield_ratio,
            crack_force: crack_force.map(|c| c * ff),
            yield_displacement: yield_displacement.map(|d| d * ff / kf),
            unloading_exponent,
        },
        // the compression-only gap laws are refused as column laws (validate.rs)
        law @ (Law::Backfill { .. } | Law::Key { .. }) => law,
    }
}

/// Two columns per bent, hysteretic in x and y (law scaled to the bent height; circular
/// columns: the world axes), elastic in torsion (torsion springs appended to `springs`; none
/// under a frame without θ).
/// Bents are numbered across the frames in order; bent b is driven by supports 2b (x), 2b+1 (y).
pub(super) fn bent_columns(
    col: &ColumnSpec,
    frames: &[Frame],
    plan: &Plan,
    ck: &Check,
    driven: bool,
    springs: &mut Vec<Spring>,
) -> Result<Vec<HystereticElement>, ModelError> {
    let mut hysteretic = Vec::new();
    let mut bi = 0;
    for (k, fr) in frames.iter().enumerate() {
        let body = frame_body(k);
        for b in fr.bents {
            let ratio = col.reference_height / b.height;
            let law = scale_law(&col.law, ratio.powi(3), ratio);
            for (sgn, tag) in [(1.0, "top"), (-1.0, "bottom")] {
                let point = plan.bent_point(fr, k, b.x, sgn * col.offset);
                for (dir, axis, s) in [
                    (Vector2::new(1.0, 0.0), "x", 2 * bi),
                    (Vector2::new(0.0, 1.0), "y", 2 * bi + 1),
                ] {
                    hysteretic.push(HystereticElement {
                        name: format!("{}_{tag}.{axis}", b.name),
                        attachment: Attachment::Point {
                            body,
                            point,
                            direction: dir,
                        },
                        law: Hysteretic::new(law.clone())
                            .map_err(|e| ck.err("column.law", e.to_string()))?,
                        damping: 0.0,
                        support: driven.then_some(s),
                    });
                }
                // a translating frame has no θ to twist the columns
                if col.torsion_stiffness > 0.0 && fr.rotation {
                    springs.push(Spring {
                        name: format!("{}_{tag}.torsion", b.name),
                        attachment: Attachment::Rotation { body },
                        stiffness: col.torsion_stiffness * ratio,
                        damping: 0.0,
                        support: None,
                    });
                }
            }
            bi += 1;
        }
    }
    Ok(hysteretic)
}
