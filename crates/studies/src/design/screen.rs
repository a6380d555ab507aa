//! Screening before any run: what the impact law (eq. 5–7) says about a deck hitting an abutment,
//! in closed form — one corner (the 2 × 2 impact LCP of one contact) and a skewed end flush
//! against a parallel face (both corners) — and where over L/B × skew a deck rotates.

use crate::scene::{BodyRef, Scene};
use nalgebra::DVector;
use serde::Serialize;

/// Why a closed form has no answer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScreenError {
    #[error("the contact is not closing (ġ_N = {gap_rate:e} ≥ 0): no impact")]
    NotClosing { gap_rate: f64 },
    #[error("the contact's Delassus matrix is singular (det {det:e}): no unique impulse")]
    Singular { det: f64 },
    #[error(
        "no impulse satisfies Newton's and Coulomb's laws (a − μ s b ≤ 0 for both slip directions): the impact LCP has no solution"
    )]
    NoSolution,
}

/// One contact's impact (eq. 5–7 with one contact, solved in closed form).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CornerImpact {
    /// The contact sticks during the impact (|Λ_T| ≤ μ Λ_N).
    pub sticks: bool,
    /// Λ_N.
    pub normal_impulse: f64,
    /// Λ_T.
    pub tangential_impulse: f64,
    /// |Λ_T|/Λ_N of the sticking solution: the μ a stick needs.
    pub stick_mu: f64,
    /// q̇⁺ = q̇⁻ + M⁻¹ (W_N Λ_N + W_T Λ_T).
    #[serde(skip)]
    pub velocity_after: DVector<f64>,
}

/// The impact of one contact: with G = [a b; b c] = [W_N W_T]ᵀ M⁻¹ [W_N W_T] and pre-impact
/// rates ġ_N⁻ < 0, ġ_T⁻, stick solves G Λ = (−(1+ε) ġ_N⁻, −ġ_T⁻) and holds iff |Λ_T| ≤ μ Λ_N;
/// else Λ_T = −μ s Λ_N with Λ_N = −(1+ε) ġ_N⁻/(a − μ s b) and s the sign of
/// ġ_T⁺ = ġ_T⁻ + (b − μ s c) Λ_N (Newton's law in the normal, Coulomb's on the impulses).
pub(crate) fn corner_impact(
    minv: &[f64],
    w_n: &[f64],
    w_t: &[f64],
    qdot: &[f64],
    mu: f64,
    eps: f64,
) -> Result<CornerImpact, ScreenError> {
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(a, b)| a * b).sum::<f64>();
    let wdot = |x: &[f64], y: &[f64]| {
        x.iter()
            .zip(y)
            .zip(minv)
            .map(|((a, b), m)| a * b * m)
            .sum::<f64>()
    };
    let (gn, gt) = (dot(w_n, qdot), dot(w_t, qdot));
    if gn >= 0.0 || !gn.is_finite() {
        return Err(ScreenError::NotClosing { gap_rate: gn });
    }
    let (a, b, c) = (wdot(w_n, w_n), wdot(w_n, w_t), wdot(w_t, w_t));
    let target = -(1.0 + eps) * gn;
    let det = a * c - b * b;
    let after = |ln: f64, lt: f64| {
        DVector::from_iterator(
            qdot.len(),
            (0..qdot.len()).map(|i| qdot[i] + minv[i] * (w_n[i] * ln + w_t[i] * lt)),
        )
    };
    let (stick_mu, stuck) = if det > 1e-14 * (a * c).max(f64::MIN_POSITIVE) {
        let ln = (target * c + gt * b) / det;
        let lt = (-gt * a - target * b) / det;
        let need = if ln > 0.0 {
            lt.abs() / ln
        } else {
            f64::INFINITY
        };
        (need, (ln > 0.0 && lt.abs() <= mu * ln).then_some((ln, lt)))
    } else if c == 0.0 {
        // no tangential mobility: the tangential impulse does nothing, friction never slips
        (0.0, Some((target / a, 0.0)))
    } else {
        return Err(ScreenError::Singular { det });
    };
    if let Some((ln, lt)) = stuck {
        return Ok(CornerImpact {
            sticks: true,
            normal_impulse: ln,
            tangential_impulse: lt,
            stick_mu,
            velocity_after: after(ln, lt),
        });
    }
    for s in [1.0, -1.0] {
        let den = a - mu * s * b;
        if den <= 0.0 {
            continue;
        }
        let ln = target / den;
        let gt_after = gt + (b - mu * s * c) * ln;
        if s * gt_after >= 0.0 {
            let lt = -mu * s * ln;
            return Ok(CornerImpact {
                sticks: false,
                normal_impulse: ln,
                tangential_impulse: lt,
                stick_mu,
                velocity_after: after(ln, lt),
            });
        }
    }
    Err(ScreenError::NoSolution)
}

/// What a flush impact of a skewed end does.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Flush {
    /// The deck stays straight (the impulses' moment balances).
    Straight,
    /// It rotates with both corners sticking.
    RotatesSticking,
    /// It rotates with both corners sliding.
    RotatesSliding,
}

impl Flush {
    /// Every outcome, in the maps' legend order.
    pub const ALL: [Flush; 3] = [
        Flush::Straight,
        Flush::RotatesSticking,
        Flush::RotatesSliding,
    ];

    /// Its character on the text maps.
    pub fn glyph(self) -> char {
        match self {
            Flush::Straight => '.',
            Flush::RotatesSticking => 's',
            Flush::RotatesSliding => 'S',
        }
    }

    /// Its name in the legends.
    pub fn name(self) -> &'static str {
        match self {
            Flush::Straight => "stays straight",
            Flush::RotatesSticking => "rotates, corners stick",
            Flush::RotatesSliding => "rotates, corners slide",
        }
    }
}

/// Which corners of an end stick when each is struck alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Corners {
    Both,
    Acute,
    Obtuse,
    Neither,
}

impl Corners {
    /// Every outcome, in the maps' legend order.
    pub const ALL: [Corners; 4] = [
        Corners::Both,
        Corners::Acute,
        Corners::Obtuse,
        Corners::Neither,
    ];

    /// Its character on the text maps.
    pub fn glyph(self) -> char {
        match self {
            Corners::Both => 'B',
            Corners::Acute => 'a',
            Corners::Obtuse => 'o',
            Corners::Neither => '-',
        }
    }

    /// Its name in the legends.
    pub fn name(self) -> &'static str {
        match self {
            Corners::Both => "both corners stick",
            Corners::Acute => "only the acute corner sticks",
            Corners::Obtuse => "only the obtuse corner sticks",
            Corners::Neither => "neither sticks",
        }
    }
}

/// A rigid deck (length L, width B, ends skewed φ) moving along its axis hits a face parallel to
/// its end, flush: no rotation is possible iff |sin φ + cos φ Λ_T/Λ_N| cos φ ≤ B/L, with
/// Λ_T/Λ_N = −sin φ/((1+ε) cos φ) when the corners stick (tan φ ≤ μ(1+ε)), else −μ. So it
/// rotates iff ε sin φ cos φ/(1+ε) > B/L (stick) or |sin φ − μ cos φ| cos φ > B/L (slide).
/// Returns the outcome and the margin |lhs·L/B − 1| (how far from the boundary).
pub fn flush_impact(l_over_b: f64, skew: f64, mu: f64, eps: f64) -> (Flush, f64) {
    let (s, c) = skew.sin_cos();
    let sticks = s <= mu * (1.0 + eps) * c;
    let lhs = if sticks {
        eps * s * c / (1.0 + eps)
    } else {
        (s - mu * c).abs() * c
    };
    let margin = (lhs * l_over_b - 1.0).abs();
    let out = match (lhs > 1.0 / l_over_b, sticks) {
        (false, _) => Flush::Straight,
        (true, true) => Flush::RotatesSticking,
        (true, false) => Flush::RotatesSliding,
    };
    (out, margin)
}

/// A rectangle of unit mass, length `l_over_b`, width 1 and uniform inertia (L² + B²)/12, ends
/// skewed φ, moving at unit speed along −x into the face parallel to its left end: the impact of
/// its acute (`acute`) or obtuse corner alone. Scale-free: a function of L/B, φ, μ, ε.
pub fn rectangle_corner(
    l_over_b: f64,
    skew: f64,
    acute: bool,
    mu: f64,
    eps: f64,
) -> Result<CornerImpact, ScreenError> {
    let (hl, hw, tan) = (0.5 * l_over_b, 0.5, skew.tan());
    // the left end's corners: top (−hl + hw tan φ, hw) is obtuse for φ > 0, bottom acute
    let r = if acute {
        [-hl - hw * tan, -hw]
    } else {
        [-hl + hw * tan, hw]
    };
    let n = [skew.cos(), -skew.sin()];
    let t = [-n[1], n[0]];
    // W for q = (x, y, θ): a point velocity v + θ̇ ẑ × r, so W·e = (e, r × e)
    let w = |e: [f64; 2]| [e[0], e[1], r[0] * e[1] - r[1] * e[0]];
    let inertia = (l_over_b * l_over_b + 1.0) / 12.0;
    corner_impact(
        &[1.0, 1.0, 1.0 / inertia],
        &w(n),
        &w(t),
        &[-1.0, 0.0, 0.0],
        mu,
        eps,
    )
}

/// One cell of the screening map.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MapCell {
    pub l_over_b: f64,
    /// Skew φ, degrees.
    pub skew_deg: f64,
    pub flush: Flush,
    /// The acute corner alone sticks.
    pub acute_sticks: Option<bool>,
    /// The obtuse corner alone sticks.
    pub obtuse_sticks: Option<bool>,
    /// θ̇⁺ L / v after the acute corner's impact alone (the end's spin per approach speed).
    pub acute_spin: f64,
}

impl MapCell {
    /// Which corners stick when struck alone.
    pub fn corners(&self) -> Corners {
        match (self.acute_sticks, self.obtuse_sticks) {
            (Some(true), Some(true)) => Corners::Both,
            (Some(true), _) => Corners::Acute,
            (_, Some(true)) => Corners::Obtuse,
            _ => Corners::Neither,
        }
    }
}

/// The screening map over `l_over_b` × `skew_deg` for μ and ε.
pub fn screening_map(l_over_b: &[f64], skew_deg: &[f64], mu: f64, eps: f64) -> Vec<MapCell> {
    let mut out = Vec::with_capacity(l_over_b.len() * skew_deg.len());
    for &phi_deg in skew_deg {
        for &lb in l_over_b {
            let phi = phi_deg.to_radians();
            let acute = rectangle_corner(lb, phi, true, mu, eps).ok();
            let obtuse = rectangle_corner(lb, phi, false, mu, eps).ok();
            out.push(MapCell {
                l_over_b: lb,
                skew_deg: phi_deg,
                flush: flush_impact(lb, phi, mu, eps).0,
                acute_sticks: acute.as_ref().map(|c| c.sticks),
                obtuse_sticks: obtuse.as_ref().map(|c| c.sticks),
                acute_spin: acute.map_or(f64::NAN, |c| c.velocity_after[2] * lb),
            });
        }
    }
    out
}

/// A corner contact of the model, struck alone: its frame moving at 1 m/s along its axis into
/// the face, everything else at rest, in the reference configuration; the face's body with its
/// own mass, or held fixed (a rigid abutment).
#[derive(Clone, Debug, Serialize)]
pub struct ModelCorner {
    pub contact: String,
    pub impact: Option<CornerImpact>,
    /// Why there is no closed form (a face along the axis, a singular G …).
    pub note: Option<String>,
    /// θ̇⁺ of the struck frame, rad/s per m/s of approach.
    pub spin: f64,
    pub mu: f64,
    pub restitution: f64,
}

/// An end of a frame flush against a face: the rectangle the corner pair spans.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelEnd {
    /// The two corners' contacts.
    pub contacts: [String; 2],
    pub l_over_b: f64,
    pub skew_deg: f64,
    pub mu: f64,
    pub restitution: f64,
    pub flush: Flush,
}

/// Every corner contact of `scene` struck alone ([`corner_impact`]; with `rigid_faces` the
/// face's body held fixed) and every pair of corners of one frame on one face as a flush end
/// ([`flush_impact`], from the pair's geometry).
pub fn model_screen(scene: &Scene, rigid_faces: bool) -> (Vec<ModelCorner>, Vec<ModelEnd>) {
    let n = scene.ndof();
    let fr = scene.frame(0.0, &scene.q0, &DVector::zeros(n));
    let inverse: Vec<f64> = (scene.mass.iter())
        .map(|m| if *m > 0.0 { 1.0 / m } else { 0.0 })
        .collect();
    let mut corners = Vec::new();
    for c in &scene.contacts {
        let mut minv = inverse.clone();
        if let (true, Some(f)) = (rigid_faces, body_index(c.face_body)) {
            for d in scene.bodies[f].dofs.into_iter().flatten() {
                minv[d] = 0.0;
            }
        }
        let k = scene.contact_kinematics(&fr, c);
        let body = body_index(c.point_body);
        let xdof = body.and_then(|b| scene.bodies[b].dofs[0]);
        let thdof = body.and_then(|b| scene.bodies[b].dofs[2]);
        let mut qdot = vec![0.0; n];
        let mut note = None;
        let mut impact = None;
        match xdof {
            Some(d) if k.w_n[d] != 0.0 => {
                qdot[d] = -k.w_n[d].signum();
                match corner_impact(
                    &minv,
                    k.w_n.as_slice(),
                    k.w_t.as_slice(),
                    &qdot,
                    c.law.mu,
                    c.law.restitution,
                ) {
                    Ok(i) => impact = Some(i),
                    Err(e) => note = Some(e.to_string()),
                }
            }
            _ => note = Some("the frame's axis does not close this contact".into()),
        }
        let spin = match (&impact, thdof) {
            (Some(i), Some(d)) => i.velocity_after[d],
            _ => f64::NAN,
        };
        corners.push(ModelCorner {
            contact: c.name.clone(),
            impact,
            note,
            spin,
            mu: c.law.mu,
            restitution: c.law.restitution,
        });
    }
    (corners, model_ends(scene))
}

/// Pairs of contacts of one body on one face with the same normal: the rectangle they span
/// (corners (−hl ± hw tan φ, ±hw) turned to the face).
fn model_ends(scene: &Scene) -> Vec<ModelEnd> {
    let mut ends = Vec::new();
    let cs = &scene.contacts;
    for i in 0..cs.len() {
        for j in i + 1..cs.len() {
            let (a, b) = (&cs[i], &cs[j]);
            let same = a.point_body == b.point_body
                && a.face_body == b.face_body
                && (a.face_normal - b.face_normal).norm() < 1e-12
                && body_index(a.point_body).is_some();
            if !same {
                continue;
            }
            // in the body's frame: the end line joins the corners, the axis is x
            let d = a.point - b.point;
            let mid = 0.5 * (a.point + b.point);
            if d.y.abs() < 1e-12 || mid.x.abs() < 1e-12 {
                continue;
            }
            let width = d.y.abs();
            let skew = (d.x / d.y).atan().abs();
            let l_over_b = 2.0 * mid.x.abs() / width;
            let (mu, eps) = (
                a.law.mu.min(b.law.mu),
                a.law.restitution.min(b.law.restitution),
            );
            ends.push(ModelEnd {
                contacts: [a.name.clone(), b.name.clone()],
                l_over_b,
                skew_deg: skew.to_degrees(),
                mu,
                restitution: eps,
                flush: flush_impact(l_over_b, skew, mu, eps).0,
            });
        }
    }
    ends
}

fn body_index(b: BodyRef) -> Option<usize> {
    match b {
        BodyRef::Body(i) => Some(i),
        BodyRef::Ground => None,
    }
}

/// The axes of the screening map of `deckspin screen`: 31 values of L/B from 1 to 31.6 on a
/// log scale (20 per decade) and the skews 0°, 5°, …, 60°.
pub fn map_axes() -> (Vec<f64>, Vec<f64>) {
    let lb = (0..=30).map(|i| 10f64.powf(i as f64 / 20.0)).collect();
    let skew = (0..=12).map(|i| 5.0 * i as f64).collect();
    (lb, skew)
}

/// A corner struck alone, as a table row: against a rigid face or against the face's own body.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CornerAlone {
    pub contact: String,
    /// The face held fixed (a rigid abutment); else the face's body with its own mass.
    pub rigid_face: bool,
    pub mu: f64,
    pub restitution: f64,
    /// Sticks during the impact; None when there is no closed form (`note` says why).
    pub sticks: Option<bool>,
    /// The μ a stick needs (NaN without a closed form).
    pub stick_mu: f64,
    /// θ̇⁺ of the struck frame, rad/s per m/s of approach (NaN without a closed form).
    pub spin: f64,
    pub note: Option<String>,
}

impl CornerAlone {
    fn of(c: &ModelCorner, rigid_face: bool) -> Self {
        Self {
            contact: c.contact.clone(),
            rigid_face,
            mu: c.mu,
            restitution: c.restitution,
            sticks: c.impact.as_ref().map(|i| i.sticks),
            stick_mu: c.impact.as_ref().map_or(f64::NAN, |i| i.stick_mu),
            spin: c.spin,
            note: c.note.clone(),
        }
    }
}

/// The screening of a model, all `deckspin screen` reports without `--equivalence`: the map
/// over L/B × skew ([`map_axes`]) at the model's μ and ε (those of its first end, else of its
/// first corner), its flush ends, and its corners struck alone against a rigid face and
/// against the face's own body.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScreenStudy {
    pub mu: f64,
    pub restitution: f64,
    pub l_over_b: Vec<f64>,
    pub skew_deg: Vec<f64>,
    /// Row by row of skew: the cell of `l_over_b[i]` and `skew_deg[j]` is at
    /// `j · l_over_b.len() + i` ([`screening_map`]'s order).
    pub cells: Vec<MapCell>,
    pub ends: Vec<ModelEnd>,
    /// Each corner against a rigid face, then each against the face's own body.
    pub corners: Vec<CornerAlone>,
}

/// [`ScreenStudy`] of a compiled model.
pub(crate) fn screen_study(scene: &Scene) -> ScreenStudy {
    let (rigid, ends) = model_screen(scene, true);
    let body = model_screen(scene, false).0;
    let (mu, restitution) = ends
        .first()
        .map(|e| (e.mu, e.restitution))
        .or_else(|| rigid.first().map(|c| (c.mu, c.restitution)))
        .unwrap_or((0.0, 0.0));
    let (l_over_b, skew_deg) = map_axes();
    let cells = screening_map(&l_over_b, &skew_deg, mu, restitution);
    let corners = (rigid.iter().map(|c| CornerAlone::of(c, true)))
        .chain(body.iter().map(|c| CornerAlone::of(c, false)))
        .collect();
    ScreenStudy {
        mu,
        restitution,
        l_over_b,
        skew_deg,
        cells,
        ends,
        corners,
    }
}

impl ScreenStudy {
    /// The cell nearest the model's first end, `(L/B index, skew index)`: nearest in log L/B
    /// and in skew. None without ends or without cells.
    pub fn mark(&self) -> Option<(usize, usize)> {
        let e = self.ends.first()?;
        let nearest = |v: f64, axis: &[f64], f: fn(f64) -> f64| {
            (0..axis.len()).min_by(|&i, &j| {
                let (a, b) = ((f(axis[i]) - f(v)).abs(), (f(axis[j]) - f(v)).abs());
                a.total_cmp(&b)
            })
        };
        Some((
            nearest(e.l_over_b, &self.l_over_b, f64::ln)?,
            nearest(e.skew_deg, &self.skew_deg, |x| x)?,
        ))
    }

    /// The map cell of `l_over_b[i]` and `skew_deg[j]`.
    pub fn cell(&self, i: usize, j: usize) -> Option<&MapCell> {
        (i < self.l_over_b.len())
            .then(|| self.cells.get(j * self.l_over_b.len() + i))
            .flatten()
    }
}
