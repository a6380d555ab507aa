//! The per-body runs of [`super::ForceModel`] on compact tables: a run's elements split into
//! segments of one kind (axis, with or without a support, spring or hysteretic), each
//! evaluated by a loop without per-element branching. Per element, with ρ = R(θ)p:
//! e = (X − X₀ + ρ − p)·d − u_g, ė = (Ẋ + ω k×ρ)·d − u̇_g, f = k e + c ė (spring) or
//! f_h(e) + c ė (hysteretic); the run's J f summed per body, then subtracted from h.

use super::kinematics::{BodyState, Frame};
use crate::hysteresis::Hysteretic;
use nalgebra::Vector2;

/// Along x, along y, the rotation, any other direction, or a pair along x then y at one point.
const X: u8 = 0;
const Y: u8 = 1;
const ROT: u8 = 2;
const ANY: u8 = 3;
const XY: u8 = 4;

/// Sentinel of a missing DOF or support.
pub(super) const NONE: usize = usize::MAX;

/// One element of a run, as [`Runs::push`] receives it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Element {
    pub rotation: bool,
    pub point: Vector2<f64>,
    pub direction: Vector2<f64>,
    pub support: usize,
    pub stiffness: f64,
    pub damping: f64,
    /// Index of the hysteretic element (its law), None for a spring.
    pub law: Option<usize>,
}

/// An element's constants in a segment.
#[derive(Clone, Copy, Debug)]
struct Item {
    px: f64,
    py: f64,
    dx: f64,
    dy: f64,
    support: usize,
    stiffness: f64,
    damping: f64,
}

/// Items `start..end` of one kind; hysteretic ones have the laws `law..law + end − start`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Segment {
    axis: u8,
    support: bool,
    hysteretic: bool,
    start: usize,
    end: usize,
    law: usize,
}

/// Segments `start..end` on `body`, whose DOFs are `dofs` (NONE if fixed).
#[derive(Clone, Debug)]
struct Run {
    body: usize,
    reference: Vector2<f64>,
    dofs: [usize; 3],
    start: usize,
    end: usize,
}

/// The sums an evaluation accumulates over the elements: −Σ f u̇_g, Σ c ė², Σ f_h ė.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Sums {
    pub supports: f64,
    pub damping: f64,
    pub hysteretic: f64,
}

/// A segment as evaluated: its items, its body, and the DOFs its run's sums go to after its
/// last segment (`flush`).
#[derive(Clone, Debug)]
struct Block {
    /// 4 axis + 2 support + hysteretic.
    kind: u8,
    law: usize,
    body: usize,
    reference: Vector2<f64>,
    items: Vec<Item>,
    flush: Option<[usize; 3]>,
}

/// The runs of a force model: built by [`Runs::start`] and [`Runs::push`], evaluated as
/// blocks after [`Runs::finish`].
#[derive(Clone, Debug, Default)]
pub(super) struct Runs {
    items: Vec<Item>,
    segments: Vec<Segment>,
    runs: Vec<Run>,
    blocks: Vec<Block>,
}

impl Runs {
    /// Starts a run on `body`.
    pub(super) fn start(&mut self, body: usize, reference: Vector2<f64>, dofs: [usize; 3]) {
        let n = self.segments.len();
        self.runs.push(Run {
            body,
            reference,
            dofs,
            start: n,
            end: n,
        });
    }

    /// Appends an element to the last run.
    pub(super) fn push(&mut self, el: &Element) {
        let mut axis = if el.rotation {
            ROT
        } else if el.direction == Vector2::new(1.0, 0.0) {
            X
        } else if el.direction == Vector2::new(0.0, 1.0) {
            Y
        } else {
            ANY
        };
        let (support, hysteretic) = (el.support != NONE, el.law.is_some());
        let law = el.law.unwrap_or(0);
        let i = self.items.len();
        let run = self.runs.last_mut().expect("a run is started");
        // the y element of an x element at the same point: the last segment's x item pairs
        let pairs = self.segments.last().is_some_and(|s| {
            let prev = &self.items[i - 1];
            run.end > run.start
                && axis == Y
                && s.axis == X
                && (s.support, s.hysteretic) == (support, hysteretic)
                && (prev.px, prev.py) == (el.point.x, el.point.y)
                && (!hysteretic || s.law + (s.end - s.start) == law)
        });
        if pairs {
            // the x item leaves its segment for the pair
            let s = self.segments.last_mut().expect("a segment");
            if s.end - s.start > 1 {
                s.end -= 1;
            } else {
                self.segments.pop();
                run.end -= 1;
            }
            axis = XY;
        }
        let item = |el: &Element| Item {
            px: el.point.x,
            py: el.point.y,
            dx: el.direction.x,
            dy: el.direction.y,
            support: el.support,
            stiffness: el.stiffness,
            damping: el.damping,
        };
        self.items.push(item(el));
        let (first, first_law) = if axis == XY {
            (i - 1, law - usize::from(hysteretic))
        } else {
            (i, law)
        };
        let n = i + 1 - first;
        match self.segments.last_mut() {
            Some(s)
                if run.end > run.start
                    && (s.axis, s.support, s.hysteretic) == (axis, support, hysteretic)
                    && (!hysteretic || s.law + (s.end - s.start) == first_law) =>
            {
                s.end += n
            }
            _ => {
                self.segments.push(Segment {
                    axis,
                    support,
                    hysteretic,
                    start: first,
                    end: i + 1,
                    law: first_law,
                });
                run.end += 1;
            }
        }
    }

    /// The blocks of the runs pushed.
    pub(super) fn finish(&mut self) {
        let mut blocks = Vec::new();
        for r in &self.runs {
            let segments = &self.segments[r.start..r.end];
            for (k, seg) in segments.iter().enumerate() {
                blocks.push(Block {
                    kind: 4 * seg.axis + 2 * u8::from(seg.support) + u8::from(seg.hysteretic),
                    law: seg.law,
                    body: r.body,
                    reference: r.reference,
                    items: self.items[seg.start..seg.end].to_vec(),
                    flush: (k + 1 == segments.len()).then_some(r.dofs),
                });
            }
        }
        self.blocks = blocks;
    }

    /// Adds −Σ J f of every run to `h`, writes (e, ė) of the hysteretic elements into
    /// `elements` and accumulates the sums.
    #[inline(never)]
    pub(super) fn eval(
        &self,
        fr: &Frame,
        laws: &[Hysteretic],
        h: &mut [f64],
        elements: &mut [(f64, f64)],
        sums: &mut Sums,
    ) {
        let mut acc = [0.0f64; 3];
        for bl in &self.blocks {
            let s = &fr.poses[bl.body];
            let b = Body {
                s,
                rel: s.position - bl.reference,
                fr,
            };
            let it = &bl.items[..];
            let (a, m) = (&mut acc, &mut *sums);
            let r = bl.law..bl.law + it.len();
            match bl.kind {
                0 => springs::<X, false>(it, &b, a, m),
                1 => {
                    let (l, o) = (&laws[r.clone()], &mut elements[r.clone()]);
                    hysteretic::<X, false>(it, &b, l, o, a, m)
                }
                2 => springs::<X, true>(it, &b, a, m),
                3 => {
                    let (l, o) = (&laws[r.clone()], &mut elements[r.clone()]);
                    hysteretic::<X, true>(it, &b, l, o, a, m)
                }
                4 => springs::<Y, false>(it, &b, a, m),
                5 => {
                    let (l, o) = (&laws[r.clone()], &mut elements[r.clone()]);
                    hysteretic::<Y, false>(it, &b, l, o, a, m)
                }
                6 => springs::<Y, true>(it, &b, a, m),
                7 => {
                    let (l, o) = (&laws[r.clone()], &mut elements[r.clone()]);
                    hysteretic::<Y, true>(it, &b, l, o, a, m)
                }
                8 => springs::<ROT, false>(it, &b, a, m),
                9 => {
                    let (l, o) = (&laws[r.clone()], &mut elements[r.clone()]);
                    hysteretic::<ROT, false>(it, &b, l, o, a, m)
                }
                10 => springs::<ROT, true>(it, &b, a, m),
                11 => {
                    let (l, o) = (&laws[r.clone()], &mut elements[r.clone()]);
                    hysteretic::<ROT, true>(it, &b, l, o, a, m)
                }
                12 => springs::<ANY, false>(it, &b, a, m),
                13 => {
                    let (l, o) = (&laws[r.clone()], &mut elements[r.clone()]);
                    hysteretic::<ANY, false>(it, &b, l, o, a, m)
                }
                14 => springs::<ANY, true>(it, &b, a, m),
                15 => {
                    let (l, o) = (&laws[r.clone()], &mut elements[r.clone()]);
                    hysteretic::<ANY, true>(it, &b, l, o, a, m)
                }
                16 => spring_pairs::<false>(it, &b, a, m),
                17 => {
                    let (l, o) = (&laws[r.clone()], &mut elements[r.clone()]);
                    hysteretic_pairs::<false>(it, &b, l, o, a, m)
                }
                18 => spring_pairs::<true>(it, &b, a, m),
                _ => {
                    let (l, o) = (&laws[r.clone()], &mut elements[r.clone()]);
                    hysteretic_pairs::<true>(it, &b, l, o, a, m)
                }
            }
            if let Some(dofs) = bl.flush {
                for (&k, a) in dofs.iter().zip(acc) {
                    if let Some(x) = h.get_mut(k) {
                        *x -= a;
                    }
                }
                acc = [0.0; 3];
            }
        }
    }
}

/// The pose of a run's body, its displacement X − X₀ and the frame.
struct Body<'a> {
    s: &'a BodyState,
    rel: Vector2<f64>,
    fr: &'a Frame,
}

/// (e, ė, u̇_g, J) of an item along axis A: the expressions of the general direction with the
/// zero terms left out (J's zero entries are not added: f·0 leaves a sum unchanged).
#[inline(always)]
fn deformation<const A: u8, const S: bool>(it: &Item, b: &Body) -> (f64, f64, f64, f64) {
    let (ug, vg) = if S {
        let (u, v, _) = b.fr.supports[it.support];
        (u, v)
    } else {
        (0.0, 0.0)
    };
    let (s, rel) = (b.s, b.rel);
    let (c, sn) = s.cs;
    let (px, py) = (it.px, it.py);
    match A {
        X => {
            let ry = sn * px + c * py;
            let ux = rel.x + (c * px - sn * py) - px;
            let arm = -ry;
            (ux - ug, s.velocity.x + s.omega * arm - vg, vg, arm)
        }
        Y => {
            let rx = c * px - sn * py;
            let uy = rel.y + (sn * px + c * py) - py;
            (uy - ug, s.velocity.y + s.omega * rx - vg, vg, rx)
        }
        ROT => (s.angle - ug, s.omega - vg, vg, 1.0),
        _ => {
            let (dx, dy) = (it.dx, it.dy);
            let (rx, ry) = (c * px - sn * py, sn * px + c * py);
            let ux = rel.x + rx - px;
            let uy = rel.y + ry - py;
            let arm = dx * -ry + dy * rx;
            let e = dx * ux + dy * uy - ug;
            let ed = dx * s.velocity.x + dy * s.velocity.y + s.omega * arm - vg;
            (e, ed, vg, arm)
        }
    }
}

/// acc += J f for an item along axis A with J's last entry `arm`.
#[inline(always)]
fn add<const A: u8>(acc: &mut [f64; 3], it: &Item, f: f64, arm: f64) {
    match A {
        X => {
            acc[0] += f;
            acc[2] += f * arm;
        }
        Y => {
            acc[1] += f;
            acc[2] += f * arm;
        }
        ROT => acc[2] += f,
        _ => {
            acc[0] += f * it.dx;
            acc[1] += f * it.dy;
            acc[2] += f * arm;
        }
    }
}

/// Linear springs: f = k e + c ė.
#[inline(always)]
fn springs<const A: u8, const S: bool>(
    items: &[Item],
    b: &Body,
    acc: &mut [f64; 3],
    sums: &mut Sums,
) {
    for it in items {
        let (e, ed, vg, arm) = deformation::<A, S>(it, b);
        let f = it.stiffness * e + it.damping * ed;
        add::<A>(acc, it, f, arm);
        sums.supports -= f * vg;
        sums.damping += it.damping * ed * ed;
    }
}

/// Hysteretic elements: f = f_h(e) + c ė, f_h on the law's current branch.
#[inline(always)]
fn hysteretic<const A: u8, const S: bool>(
    items: &[Item],
    b: &Body,
    laws: &[Hysteretic],
    out: &mut [(f64, f64)],
    acc: &mut [f64; 3],
    sums: &mut Sums,
) {
    for ((it, law), out) in items.iter().zip(laws).zip(out) {
        let (e, ed, vg, arm) = deformation::<A, S>(it, b);
        *out = (e, ed);
        let fh = law.force(e);
        let f = fh + it.damping * ed;
        add::<A>(acc, it, f, arm);
        sums.supports -= f * vg;
        sums.damping += it.damping * ed * ed;
        sums.hysteretic += fh * ed;
    }
}

/// (u_g, u̇_g) of an item's support (0 without: S false).
#[inline(always)]
fn support<const S: bool>(it: &Item, fr: &Frame) -> (f64, f64) {
    if S {
        let (u, v, _) = fr.supports[it.support];
        (u, v)
    } else {
        (0.0, 0.0)
    }
}

/// (e, ė, u̇_g) of the x and y items of a pair at one point, ρ = R(θ)p computed once; and
/// the arms J_θ of both (−ρ_y, ρ_x).
#[inline(always)]
fn pair<const S: bool>(ix: &Item, iy: &Item, b: &Body) -> [(f64, f64, f64, f64); 2] {
    let (s, rel) = (b.s, b.rel);
    let (c, sn) = s.cs;
    let (px, py) = (ix.px, ix.py);
    let rx = c * px - sn * py;
    let ry = sn * px + c * py;
    let (ugx, vgx) = support::<S>(ix, b.fr);
    let arm = -ry;
    let ux = rel.x + rx - px;
    let edx = s.velocity.x + s.omega * arm - vgx;
    let (ugy, vgy) = support::<S>(iy, b.fr);
    let uy = rel.y + ry - py;
    let edy = s.velocity.y + s.omega * rx - vgy;
    [(ux - ugx, edx, vgx, arm), (uy - ugy, edy, vgy, rx)]
}

/// Pairs of hysteretic elements along x then y at one point, each element as alone.
#[inline(always)]
fn hysteretic_pairs<const S: bool>(
    items: &[Item],
    b: &Body,
    laws: &[Hysteretic],
    out: &mut [(f64, f64)],
    acc: &mut [f64; 3],
    sums: &mut Sums,
) {
    let (st, rel) = (b.s, b.rel);
    let (c, sn) = st.cs;
    let (vx, vy, om) = (st.velocity.x, st.velocity.y, st.omega);
    let (mut a0, mut a1, mut a2) = (acc[0], acc[1], acc[2]);
    let (mut sup, mut dmp, mut hys) = (sums.supports, sums.damping, sums.hysteretic);
    let rows = (items.chunks_exact(2).zip(laws.chunks_exact(2))).zip(out.chunks_exact_mut(2));
    for ((it, law), out) in rows {
        let (ix, iy) = (&it[0], &it[1]);
        let (px, py) = (ix.px, ix.py);
        let rx = c * px - sn * py;
        let ry = sn * px + c * py;
        let (ugx, vgx) = support::<S>(ix, b.fr);
        let arm = -ry;
        let ex = rel.x + rx - px - ugx;
        let edx = vx + om * arm - vgx;
        out[0] = (ex, edx);
        let fhx = law[0].force(ex);
        let fx = fhx + ix.damping * edx;
        a0 += fx;
        a2 += fx * arm;
        sup -= fx * vgx;
        dmp += ix.damping * edx * edx;
        hys += fhx * edx;
        let (ugy, vgy) = support::<S>(iy, b.fr);
        let ey = rel.y + ry - py - ugy;
        let edy = vy + om * rx - vgy;
        out[1] = (ey, edy);
        let fhy = law[1].force(ey);
        let fy = fhy + iy.damping * edy;
        a1 += fy;
        a2 += fy * rx;
        sup -= fy * vgy;
        dmp += iy.damping * edy * edy;
        hys += fhy * edy;
    }
    *acc = [a0, a1, a2];
    (sums.supports, sums.damping, sums.hysteretic) = (sup, dmp, hys);
}

/// Pairs of springs along x then y at one point.
#[inline(always)]
fn spring_pairs<const S: bool>(items: &[Item], b: &Body, acc: &mut [f64; 3], sums: &mut Sums) {
    for it in items.chunks_exact(2) {
        let d = pair::<S>(&it[0], &it[1], b);
        for k in 0..2 {
            let (e, ed, vg, arm) = d[k];
            let f = it[k].stiffness * e + it[k].damping * ed;
            acc[k] += f;
            acc[2] += f * arm;
            sums.supports -= f * vg;
            sums.damping += it[k].damping * ed * ed;
        }
    }
}
