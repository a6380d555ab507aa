//! Checks of a bridge file, in file order; every error names its file, line and field.

use super::layout::Frame;
use super::schema::BridgeFile;
use crate::model::check::{Check, ModelError};

/// Largest skew of a support line, degrees.
const MAX_SKEW: f64 = 60.0;
/// Largest change of heading between adjacent frames, degrees.
const MAX_KINK: f64 = 45.0;

/// Checks of the frames, joints, abutments, contacts, columns and damping, in file order.
pub(super) fn validate(f: &BridgeFile, frames: &[Frame], ck: &Check) -> Result<(), ModelError> {
    frame_tables(f, ck)?;
    for fr in frames {
        validate_frame(fr, ck)?;
    }
    validate_joints(f, frames, ck)?;
    let a = &f.abutment;
    for (field, skew) in [
        ("abutment.left_skew", a.left_skew),
        ("abutment.right_skew", a.right_skew),
    ] {
        if let Some(s) = skew {
            self::skew(ck, field, s)?;
        }
    }
    let c = &f.contacts;
    friction("contacts", c.mu, c.restitution, ck)?;
    for (i, g) in c.gaps.iter().enumerate() {
        ck.nonneg(&format!("contacts.gaps.{i}"), *g)?;
    }
    let col = &f.column;
    ck.positive("column.reference_height", col.reference_height)?;
    ck.positive("column.offset", col.offset)?;
    ck.nonneg("column.torsion_stiffness", col.torsion_stiffness)?;
    col.law
        .validate()
        .map_err(|e| ck.err("column.law", e.to_string()))?;
    if col.law.is_gap_law() {
        return Err(ck.err(
            "column.law",
            "a column law is linear, bilinear or takeda (backfill and key are compression-only \
             gap laws of abutments and keys)",
        ));
    }
    ck.positive("damping.ratio", f.damping.ratio).or_else(|e| {
        if f.damping.ratio == 0.0 {
            Ok(0.0)
        } else {
            Err(e)
        }
    })?;
    // a ratio of critical damping: a bridge is underdamped (0 ≤ ζ < 1; the paper: 0.02)
    if f.damping.ratio >= 1.0 {
        let z = f.damping.ratio;
        return Err(ck.err(
            "damping.ratio",
            format!("{z} is a ratio of critical damping: allowed 0 ≤ ζ < 1 (0.02 is 2 %)"),
        ));
    }
    for fr in frames {
        validate_layout(fr, f.column.offset, ck)?;
    }
    for (i, r) in f.runs.iter().enumerate() {
        ck.positive(&format!("run.{i}.pga_x"), r.pga_x)?;
        ck.positive(&format!("run.{i}.pga_y"), r.pga_y)?;
        if let Some(g) = &r.gaps {
            if g.len() != 4 {
                let why = format!(
                    "expected 4 gaps (corners 1–4, as contacts.gaps), got {}",
                    g.len()
                );
                return Err(ck.err(&format!("run.{i}.gaps"), why));
            }
            for (j, x) in g.iter().enumerate() {
                ck.nonneg(&format!("run.{i}.gaps.{j}"), *x)?;
            }
        }
    }
    Ok(())
}

/// `[deck]` with `[[bent]]`, or `[[frame]]`s with their own bents and one `[[joint]]` between
/// each two: never both, never neither.
fn frame_tables(f: &BridgeFile, ck: &Check) -> Result<(), ModelError> {
    match (&f.deck, f.frames.len()) {
        (Some(_), 0) => {
            if !f.joints.is_empty() {
                return Err(ck.err("joint", "a [deck] bridge has one frame and no joints"));
            }
        }
        (Some(_), _) => {
            return Err(ck.err(
                "frame",
                "give either [deck] (one frame) or [[frame]] tables, not both",
            ));
        }
        (None, 0) => {
            return Err(ck.err(
                "deck",
                "missing: a bridge needs [deck] (one frame) or [[frame]] tables",
            ));
        }
        (None, n) => {
            if !f.bents.is_empty() {
                return Err(ck.err(
                    "bent",
                    "with [[frame]] tables each frame lists its own bents ([[frame.bent]])",
                ));
            }
            if f.joints.len() != n - 1 {
                return Err(ck.err(
                    "joint",
                    format!(
                        "{} [[joint]] tables for {n} frames: give one between each two frames \
                         ({})",
                        f.joints.len(),
                        n - 1
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn skew(ck: &Check, field: &str, s: f64) -> Result<f64, ModelError> {
    ck.finite(field, s)?;
    if s.abs() >= MAX_SKEW {
        return Err(ck.err(field, format!("|skew| must be below {MAX_SKEW}°, got {s}")));
    }
    Ok(s)
}

fn friction(table: &str, mu: f64, restitution: f64, ck: &Check) -> Result<(), ModelError> {
    ck.nonneg(&format!("{table}.mu"), mu)?;
    let field = format!("{table}.restitution");
    ck.nonneg(&field, restitution)?;
    if restitution > 1.0 {
        return Err(ck.err(&field, "must be in [0, 1]"));
    }
    Ok(())
}

fn validate_frame(fr: &Frame, ck: &Check) -> Result<(), ModelError> {
    let p = &fr.field;
    ck.positive(&format!("{p}.mass"), fr.mass)?;
    ck.positive(&format!("{p}.inertia"), fr.inertia)?;
    ck.positive(&format!("{p}.length"), fr.length)?;
    ck.positive(&format!("{p}.width"), fr.width)?;
    skew(ck, &format!("{p}.skew"), fr.skew)?;
    let heading = ck.finite(&format!("{p}.heading"), fr.heading)?;
    if heading.abs() > 90.0 {
        return Err(ck.err(
            &format!("{p}.heading"),
            format!("must be within ±90° of the x axis, got {heading}"),
        ));
    }
    if fr.bents.is_empty() {
        return Err(ck.err(&fr.bent_field, "at least one bent per frame"));
    }
    Ok(())
}

/// Joints: two gaps ≥ 0, μ and ε, skew, seats; frame names distinct; adjacent frames at most
/// [`MAX_KINK`] apart in heading.
fn validate_joints(f: &BridgeFile, frames: &[Frame], ck: &Check) -> Result<(), ModelError> {
    for (i, fr) in frames.iter().enumerate() {
        let clash = ["left_abutment", "right_abutment"].contains(&fr.name.as_str())
            || frames[..i].iter().any(|o| o.name == fr.name);
        if clash {
            return Err(ck.err(
                &format!("{}.name", fr.field),
                format!(
                    "'{}' names another body: give each frame its own name",
                    fr.name
                ),
            ));
        }
    }
    for (j, joint) in f.joints.iter().enumerate() {
        let p = format!("joint.{j}");
        for (i, g) in joint.gaps.iter().enumerate() {
            ck.nonneg(&format!("{p}.gaps.{i}"), *g)?;
        }
        let c = &f.contacts;
        friction(
            &p,
            joint.mu.unwrap_or(c.mu),
            joint.restitution.unwrap_or(c.restitution),
            ck,
        )?;
        if let Some(s) = joint.skew {
            skew(ck, &format!("{p}.skew"), s)?;
        }
        if let Some(w) = joint.seat_width {
            ck.positive(&format!("{p}.seat_width"), w)?;
        }
        if let Some(pc) = joint.seat_percent {
            ck.positive(&format!("{p}.seat_percent"), pc)?;
        }
        let kink = frames[j + 1].heading - frames[j].heading;
        if kink.abs() > MAX_KINK {
            return Err(ck.err(
                &format!("{}.heading", frames[j + 1].field),
                format!(
                    "turns {kink}° from the frame before it at joint {}: at most ±{MAX_KINK}°",
                    j + 1
                ),
            ));
        }
    }
    Ok(())
}

/// Bents and columns under the frame: |x| ≤ length/2, column offset ≤ width/2.
fn validate_layout(fr: &Frame, offset: f64, ck: &Check) -> Result<(), ModelError> {
    let (half_l, half_w) = (fr.length / 2.0, fr.width / 2.0);
    for (i, b) in fr.bents.iter().enumerate() {
        let field = format!("{}.{i}.x", fr.bent_field);
        let x = ck.finite(&field, b.x)?;
        if x.abs() > half_l {
            let length = format!("{}.length", fr.field);
            let by_length = ck.set_by(&length).is_some();
            return Err(ck.err(
                if by_length { &length } else { &field },
                format!(
                    "{field} = {x} m is off the deck: a bent must stand under it, |x| ≤ \
                     {length}/2 = {half_l} m"
                ),
            ));
        }
        ck.positive(&format!("{}.{i}.height", fr.bent_field), b.height)?;
    }
    if offset > half_w {
        let width = format!("{}.width", fr.field);
        let by_width = ck.set_by(&width).is_some();
        return Err(ck.err(
            if by_width { &width } else { "column.offset" },
            format!(
                "columns at ±{offset} m (column.offset) stand outside the deck: offset ≤ \
                 {width}/2 = {half_w} m"
            ),
        ));
    }
    Ok(())
}
