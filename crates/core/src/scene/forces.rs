//! The smooth (non-contact) forces h(t, q, q̇) of eq. 1 — springs, dashpots, hysteretic
//! columns, mass-proportional damping, loads — and the power terms of the energy ledger.

use super::force_runs::{Element, NONE, Runs, Sums};
use super::kinematics::{BodyState, Frame};
use super::{Attachment, Motion, Scene};
use crate::hysteresis::Hysteretic;
use nalgebra::{DVector, DVectorView, Vector2};
use std::sync::Arc;

/// Rates of the energy ledger's integrated terms.
#[derive(Clone, Copy, Debug, Default)]
pub struct PowerTerms {
    /// Work rate of constant loads.
    pub loads: f64,
    /// Power delivered by moving supports.
    pub supports: f64,
    /// Dissipation rate in dashpots and mass-proportional damping.
    pub damping: f64,
    /// Rate of work absorbed by hysteretic elements (stored + dissipated).
    pub hysteretic: f64,
}

/// Number of integrated ledger terms appended to the ODE state (loads, supports, damping,
/// hysteretic, sliding friction).
pub(crate) const LEDGER_TERMS: usize = 5;

/// Smooth (non-contact) generalized forces h(t, q, q̇) of eq. 1 (F_D + F_S + loads), and their powers.
pub fn smooth_forces(
    scene: &Scene,
    laws: Option<&[Hysteretic]>,
    t: f64,
    q: &DVector<f64>,
    v: &DVector<f64>,
    h: &mut DVector<f64>,
    jac: &mut DVector<f64>,
) -> PowerTerms {
    let _ = (q, jac);
    let fr = scene.frame(t, q, v);
    smooth_forces_in(scene, laws, &fr, v, h, None)
}

/// [`smooth_forces`] from a precomputed [`Frame`]; `elements` receives (e, ė) of each
/// hysteretic element.
pub fn smooth_forces_in(
    scene: &Scene,
    laws: Option<&[Hysteretic]>,
    fr: &Frame,
    v: &DVector<f64>,
    h: &mut DVector<f64>,
    mut elements: Option<&mut [(f64, f64)]>,
) -> PowerTerms {
    h.copy_from(&scene.loads);
    let mut p = PowerTerms {
        loads: scene.loads.dot(v),
        ..Default::default()
    };
    for s in &scene.springs {
        let (e, ed, vg, jj, nj) = scene.deformation(fr, &s.attachment, s.support);
        let f = s.stiffness * e + s.damping * ed;
        for &(k, c) in &jj[..nj] {
            h[k] -= f * c;
        }
        p.supports -= f * vg;
        p.damping += s.damping * ed * ed;
    }
    for (j, el) in scene.hysteretic.iter().enumerate() {
        let (e, ed, vg, jj, nj) = scene.deformation(fr, &el.attachment, el.support);
        if let Some(out) = elements.as_deref_mut() {
            out[j] = (e, ed);
        }
        let fh = laws.map_or(&el.law, |l| &l[j]).force(e);
        let f = fh + el.damping * ed;
        for &(k, c) in &jj[..nj] {
            h[k] -= f * c;
        }
        p.supports -= f * vg;
        p.damping += el.damping * ed * ed;
        p.hysteretic += fh * ed;
    }
    let (v, h) = (v.as_slice(), h.as_mut_slice());
    let (damping, supports) = mass_damping(scene, &scene.mass_damping.reference, fr, v, h);
    p.damping += damping;
    p.supports += supports;
    p
}

/// Mass-proportional damping −a₀ M (q̇ − q̇_ref) added to h, with q̇_ref from the (dof,
/// support, factor) terms `reference`; returns its dissipation rate and the support power.
fn mass_damping(
    scene: &Scene,
    reference: &[(usize, usize, f64)],
    fr: &Frame,
    v: &[f64],
    h: &mut [f64],
) -> (f64, f64) {
    let alpha = scene.mass_damping.alpha;
    if alpha == 0.0 {
        return (0.0, 0.0);
    }
    let n = h.len();
    let mut stack = [0.0f64; 16];
    let mut heap = Vec::new();
    let vref: &mut [f64] = if n <= 16 {
        &mut stack[..n]
    } else {
        heap.resize(n, 0.0);
        &mut heap
    };
    for &(k, s, f) in reference {
        vref[k] += f * fr.supports[s].1;
    }
    let (mut damping, mut supports) = (0.0, 0.0);
    let mass = scene.mass.as_slice();
    for k in 0..n {
        let rel = v[k] - vref[k];
        let f = alpha * mass[k] * rel;
        h[k] -= f;
        damping += f * rel;
        supports -= f * vref[k];
    }
    (damping, supports)
}

impl Scene {
    /// Elastic energy stored in the linear springs.
    pub fn spring_energy(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>) -> f64 {
        let fr = self.frame(t, q, v);
        self.springs
            .iter()
            .map(|s| {
                let (e, ..) = self.deformation(&fr, &s.attachment, s.support);
                0.5 * s.stiffness * e * e
            })
            .sum()
    }
}

/// One element of a [`ForceModel`]: e = d·(X − X₀ + R(θ)p − p) − u_g (point) or θ − u_g
/// (rotation), with generalized direction J = ∂e/∂q.
#[derive(Clone, Debug)]
struct FlatElement {
    body: usize,
    rotation: bool,
    point: Vector2<f64>,
    direction: Vector2<f64>,
    /// DOF of x, y, θ of the body (NONE if fixed).
    dofs: [usize; 3],
    support: usize,
    stiffness: f64,
    damping: f64,
    /// Direction along x (1) or y (2) exactly, else 0: half the kinematics suffices.
    axis: u8,
    /// Between two bodies, or on a body without DOFs: evaluated apart ([`GeneralElement`]).
    general: bool,
}

impl FlatElement {
    fn new(scene: &Scene, att: &Attachment, support: Option<usize>, k: f64, c: f64) -> Self {
        let (body, rotation, point, direction) = match *att {
            Attachment::Point {
                body,
                point,
                direction,
            }
            | Attachment::Relative {
                body,
                point,
                direction,
                ..
            } => (body, false, point, direction),
            Attachment::Rotation { body } => (body, true, Vector2::zeros(), Vector2::zeros()),
        };
        let general =
            matches!(att, Attachment::Relative { .. }) || scene.bodies[body].has_no_dofs();
        Self {
            body,
            rotation,
            point,
            direction,
            dofs: scene.bodies[body].dofs.map(|d| d.unwrap_or(NONE)),
            support: support.unwrap_or(NONE),
            stiffness: k,
            damping: c,
            axis: if direction == Vector2::new(1.0, 0.0) {
                1
            } else if direction == Vector2::new(0.0, 1.0) {
                2
            } else {
                0
            },
            general,
        }
    }

    /// Same deformation measure: springs on it add up.
    fn same_as(&self, o: &Self) -> bool {
        self.body == o.body
            && self.rotation == o.rotation
            && self.point == o.point
            && self.direction == o.direction
            && self.support == o.support
    }

    /// (e, ė, u̇_g, J over x, y, θ).
    #[inline(always)]
    fn deformation(&self, fr: &Frame, reference: Vector2<f64>) -> (f64, f64, f64, [f64; 3]) {
        let s = &fr.poses[self.body];
        self.deformation_of(s, s.position - reference, fr)
    }

    /// [`FlatElement::deformation`] from the pose `s` of the element's body and its
    /// displacement `rel` = X − X₀.
    #[inline(always)]
    fn deformation_of(
        &self,
        s: &BodyState,
        rel: Vector2<f64>,
        fr: &Frame,
    ) -> (f64, f64, f64, [f64; 3]) {
        let (ug, vg) = if self.support == NONE {
            (0.0, 0.0)
        } else {
            let (u, v, _) = fr.supports[self.support];
            (u, v)
        };
        if self.rotation {
            return (s.angle - ug, s.omega - vg, vg, [0.0, 0.0, 1.0]);
        }
        let (dx, dy) = (self.direction.x, self.direction.y);
        let (px, py) = (self.point.x, self.point.y);
        let (c, sn) = s.cs;
        // d = x or y: the general expressions below with the zero terms left out
        match self.axis {
            1 => {
                let ry = sn * px + c * py;
                let ux = rel.x + (c * px - sn * py) - px;
                let arm = -ry;
                return (
                    ux - ug,
                    s.velocity.x + s.omega * arm - vg,
                    vg,
                    [1.0, 0.0, arm],
                );
            }
            2 => {
                let rx = c * px - sn * py;
                let uy = rel.y + (sn * px + c * py) - py;
                return (
                    uy - ug,
                    s.velocity.y + s.omega * rx - vg,
                    vg,
                    [0.0, 1.0, rx],
                );
            }
            _ => {}
        }
        let (rx, ry) = (c * px - sn * py, sn * px + c * py);
        let ux = rel.x + rx - px;
        let uy = rel.y + ry - py;
        let arm = dx * -ry + dy * rx; // d·perp(ρ)
        let e = dx * ux + dy * uy - ug;
        let ed = dx * s.velocity.x + dy * s.velocity.y + s.omega * arm - vg;
        (e, ed, vg, [dx, dy, arm])
    }
}

/// An element the per-body runs leave out: between two bodies, or on a body driven by the
/// ground (ė = J q̇ − u̇ with u̇ ≠ u̇_g); evaluated by [`Scene::deformation`] after the runs.
#[derive(Clone, Debug)]
struct GeneralElement {
    attachment: Attachment,
    support: Option<usize>,
    stiffness: f64,
    damping: f64,
    /// Index of a hysteretic element (its law), None for a linear spring.
    hysteretic: Option<usize>,
}

/// Mass-proportional damping of one DOF: a₀ m_k and q̇_ref,k = `reference` u̇ of `support`.
#[derive(Clone, Copy, Debug)]
struct MassDof {
    factor: f64,
    support: usize,
    reference: f64,
}

/// The smooth forces of a scene flattened for repeated evaluation: the same h(t, q, q̇) and
/// power terms as [`smooth_forces_in`], with linear springs of identical attachment and support
/// merged (their stiffnesses and dampings add).
#[derive(Clone, Debug)]
pub struct ForceModel {
    springs: Vec<FlatElement>,
    elements: Vec<FlatElement>,
    references: Vec<Vector2<f64>>,
    /// Consecutive elements (springs, then hysteretic elements) on one body: their forces are
    /// summed before they touch h.
    runs: Runs,
    /// (dof, support, factor) of q̇_ref with supports that move alike merged.
    mass_reference: Vec<(usize, usize, f64)>,
    /// Per DOF, a₀ m_k and the one (support, factor) of q̇_ref,k (NONE: q̇_ref,k = 0); empty
    /// when a₀ = 0 or a DOF has several reference terms.
    mass_dofs: Vec<MassDof>,
    /// Every load is zero.
    no_loads: bool,
    /// Elements between two bodies or on driven bodies (not in the runs).
    general: Vec<GeneralElement>,
    /// Some body of the scene is driven by the ground.
    driven_bodies: bool,
}

impl ForceModel {
    /// The scene's smooth forces, flattened once.
    pub fn new(scene: &Scene) -> Self {
        let mut springs: Vec<FlatElement> = Vec::new();
        let mut general = Vec::new();
        for s in &scene.springs {
            let f = FlatElement::new(scene, &s.attachment, s.support, s.stiffness, s.damping);
            if f.general {
                general.push(GeneralElement {
                    attachment: s.attachment.clone(),
                    support: s.support,
                    stiffness: s.stiffness,
                    damping: s.damping,
                    hysteretic: None,
                });
                continue;
            }
            match springs.iter_mut().find(|o| o.same_as(&f)) {
                Some(o) => {
                    o.stiffness += f.stiffness;
                    o.damping += f.damping;
                }
                None => springs.push(f),
            }
        }
        let elements: Vec<FlatElement> = scene
            .hysteretic
            .iter()
            .map(|h| FlatElement::new(scene, &h.attachment, h.support, 0.0, h.damping))
            .collect();
        for (j, (h, el)) in scene.hysteretic.iter().zip(&elements).enumerate() {
            if el.general {
                general.push(GeneralElement {
                    attachment: h.attachment.clone(),
                    support: h.support,
                    stiffness: 0.0,
                    damping: h.damping,
                    hysteretic: Some(j),
                });
            }
        }
        // supports driven by the same record with the same factor move alike
        let alias: Vec<usize> = scene
            .supports
            .iter()
            .enumerate()
            .map(|(i, s)| match &s.motion {
                Motion::Record(g) => scene.supports[..i]
                    .iter()
                    .position(|o| {
                        matches!(&o.motion, Motion::Record(h) if Arc::ptr_eq(g, h))
                            && o.factor == s.factor
                    })
                    .unwrap_or(i),
                Motion::Harmonic { .. } => i,
            })
            .collect();
        let mut mass_reference: Vec<(usize, usize, f64)> = Vec::new();
        for &(k, s, f) in &scene.mass_damping.reference {
            let root = alias.get(s).copied().unwrap_or(s);
            match mass_reference
                .iter_mut()
                .find(|(k2, s2, _)| *k2 == k && *s2 == root)
            {
                Some(e) => e.2 += f,
                None => mass_reference.push((k, root, f)),
            }
        }
        let mut runs = Runs::default();
        let mut last: Option<(usize, usize)> = None;
        for (i, el) in springs.iter().chain(&elements).enumerate() {
            if el.general {
                continue;
            }
            if !matches!(last, Some((b, end)) if b == el.body && end == i) {
                runs.start(el.body, scene.bodies[el.body].reference, el.dofs);
            }
            last = Some((el.body, i + 1));
            runs.push(&Element {
                rotation: el.rotation,
                point: el.point,
                direction: el.direction,
                support: el.support,
                stiffness: el.stiffness,
                damping: el.damping,
                law: i.checked_sub(springs.len()),
            });
        }
        runs.finish();
        let alpha = scene.mass_damping.alpha;
        let terms = |k: usize| mass_reference.iter().filter(move |r| r.0 == k);
        let mass_dofs = if alpha == 0.0 || (0..scene.mass.len()).any(|k| terms(k).count() > 1) {
            Vec::new()
        } else {
            (scene.mass.iter().enumerate())
                .map(|(k, m)| {
                    let (support, factor) = terms(k).next().map_or((NONE, 0.0), |r| (r.1, r.2));
                    MassDof {
                        factor: alpha * m,
                        support,
                        reference: factor,
                    }
                })
                .collect()
        };
        Self {
            springs,
            elements,
            references: scene.bodies.iter().map(|b| b.reference).collect(),
            runs,
            mass_reference,
            mass_dofs,
            no_loads: scene.loads.iter().all(|&l| l == 0.0),
            general,
            driven_bodies: scene.bodies.iter().any(|b| b.is_driven()),
        }
    }

    /// Some body of the scene is driven by the ground ([`super::Body::drive`]).
    pub(crate) fn driven_bodies(&self) -> bool {
        self.driven_bodies
    }

    /// h(t, q, q̇) into `h` (eq. 1: F_D + F_S + loads) and the ledger's power terms; (e, ė) of
    /// each hysteretic element into `elements`.
    pub fn eval(
        &self,
        scene: &Scene,
        laws: &[Hysteretic],
        fr: &Frame,
        v: &DVector<f64>,
        h: &mut DVector<f64>,
        elements: &mut [(f64, f64)],
    ) -> PowerTerms {
        let (v, h) = (v.as_slice(), h.as_mut_slice());
        self.eval_in(scene, laws, fr, v, h, elements)
    }

    /// [`ForceModel::eval`] with q̇ and h as slices.
    pub(crate) fn eval_in(
        &self,
        scene: &Scene,
        laws: &[Hysteretic],
        fr: &Frame,
        v: &[f64],
        hs: &mut [f64],
        elements: &mut [(f64, f64)],
    ) -> PowerTerms {
        hs.copy_from_slice(scene.loads.as_slice());
        // without loads Σ 0·q̇_k = 0
        let loads = if self.no_loads {
            0.0
        } else {
            scene.loads.dot(&DVectorView::from_slice(v, v.len()))
        };
        let mut p = PowerTerms {
            loads,
            ..Default::default()
        };
        // generalized forces summed per run of elements on one body, then subtracted from h
        // once per run
        let mut sums = Sums::default();
        self.runs.eval(fr, laws, hs, elements, &mut sums);
        let Sums {
            mut supports,
            mut damping,
            mut hysteretic,
        } = sums;
        for g in &self.general {
            let (e, ed, vg, jj, nj) = scene.deformation(fr, &g.attachment, g.support);
            let fh = match g.hysteretic {
                Some(j) => {
                    elements[j] = (e, ed);
                    laws[j].force(e)
                }
                None => g.stiffness * e,
            };
            let f = fh + g.damping * ed;
            for &(k, c) in &jj[..nj] {
                hs[k] -= f * c;
            }
            supports -= f * vg;
            damping += g.damping * ed * ed;
            if g.hysteretic.is_some() {
                hysteretic += fh * ed;
            }
        }
        p.supports += supports;
        p.damping += damping;
        p.hysteretic += hysteretic;
        let (damping, supports) = self.mass_damping(scene, fr, v, hs);
        p.damping += damping;
        p.supports += supports;
        p
    }

    /// [`mass_damping`] from `mass_dofs`: q̇_ref,k = 0 + c u̇_g (or 0), f_k = (a₀ m_k)(q̇_k −
    /// q̇_ref,k), h_k −= f_k.
    fn mass_damping(&self, scene: &Scene, fr: &Frame, v: &[f64], h: &mut [f64]) -> (f64, f64) {
        if self.mass_dofs.len() != h.len() {
            return mass_damping(scene, &self.mass_reference, fr, v, h);
        }
        let (mut damping, mut supports) = (0.0, 0.0);
        for ((h, v), d) in h.iter_mut().zip(v).zip(&self.mass_dofs) {
            if d.support == NONE {
                let f = d.factor * v;
                *h -= f;
                damping += f * v;
            } else {
                let vr = 0.0 + d.reference * fr.supports[d.support].1;
                let rel = v - vr;
                let f = d.factor * rel;
                *h -= f;
                damping += f * rel;
                supports -= f * vr;
            }
        }
        (damping, supports)
    }

    /// (e, ė) of each hysteretic element, as [`ForceModel::eval`] writes them.
    pub fn deformations(&self, scene: &Scene, fr: &Frame, elements: &mut [(f64, f64)]) {
        for (el, out) in self.elements.iter().zip(elements.iter_mut()) {
            if !el.general {
                let (e, ed, ..) = el.deformation(fr, self.references[el.body]);
                *out = (e, ed);
            }
        }
        for g in &self.general {
            if let Some(j) = g.hysteretic {
                let (e, ed, ..) = scene.deformation(fr, &g.attachment, g.support);
                elements[j] = (e, ed);
            }
        }
    }

    /// Elastic energy of the linear springs, Σ ½ k e².
    pub fn spring_energy(&self, scene: &Scene, fr: &Frame) -> f64 {
        let fast = self.springs.iter().map(|s| {
            let e = s.deformation(fr, self.references[s.body]).0;
            0.5 * s.stiffness * e * e
        });
        let general = (self.general.iter())
            .filter(|g| g.hysteretic.is_none())
            .map(|g| {
                let e = scene.deformation(fr, &g.attachment, g.support).0;
                0.5 * g.stiffness * e * e
            });
        fast.chain(general).sum()
    }
}
