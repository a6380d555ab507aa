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

/// The runs of a force model.
#[derive(Clone, Debug, Default)]
pub(super) struct Runs {
    items: Vec<Item>,
    segments: Vec<Segment>,
    runs: Vec<Run>,
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

    /// Adds −Σ J f of every run to `h`, writes (e, ė) of the hysteretic elements into
    /// `elements` and accumulates the sums.
    pub(super) fn eval(
        &self,
        fr: &Frame,
        laws: &[Hysteretic],
        h: &mut [f64],
        elements: &mut [(f64, f64)],
        sums: &mut Sums,
    ) {
        for run in &self.runs {
            let s = &fr.poses[run.body];
            let rel = s.position - run.reference;
            let mut acc = [0.0f64; 3];
            for seg in &self.segments[run.start..run.end] {
                let items = &self.items[seg.start..seg.end];
                let b = Body { s, rel, fr };
                let laws = (seg.law, laws, &mut *elements);
                match seg.axis {
                    X => segment::<X>(seg, items, &b, laws, &mut acc, sums),
                    Y => segment::<Y>(seg, items, &b, laws, &mut acc, sums),
                    ROT => segment::<ROT>(seg, items, &b, laws, &mut acc, sums),
                    XY => pairs(seg, items, &b, laws, &mut acc, sums),
                    _ => segment::<ANY>(seg, items, &b, laws, &mut acc, sums),
                }
            }
            for (&k, a) in run.dofs.iter().zip(acc) {
                if let Some(x) = h.get_mut(k) {
                    *x -= a;
                }
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

/// The first law of a segment, the laws and the (e, ė) of the hysteretic elements.
type Laws<'a, 'b> = (usize, &'a [Hysteretic], &'b mut [(f64, f64)]);

/// One segment, by its support and law.
#[inline(always)]
fn segment<const A: u8>(
    seg: &Segment,
    items: &[Item],
    b: &Body,
    (law, laws, out): Laws,
    acc: &mut [f64; 3],
    sums: &mut Sums,
) {
    let n = items.len();
    match (seg.support, seg.hysteretic) {
        (true, true) => {
            let (laws, out) = (&laws[law..law + n], &mut out[law..law + n]);
            hysteretic::<A, true>(items, b, laws, out, acc, sums)
        }
        (false, true) => {
            let (laws, out) = (&laws[law..law + n], &mut out[law..law + n]);
            hysteretic::<A, false>(items, b, laws, out, acc, sums)
        }
        (true, false) => springs::<A, true>(items, b, acc, sums),
        (false, false) => springs::<A, false>(items, b, acc, sums),
    }
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

/// Pairs of hysteretic elements or springs along x then y at one point: ρ = R(θ)p once for
/// both, each element as alone.
#[inline(always)]
fn pairs(
    seg: &Segment,
    items: &[Item],
    b: &Body,
    (law, laws, out): Laws,
    acc: &mut [f64; 3],
    sums: &mut Sums,
) {
    let n = items.len();
    match (seg.support, seg.hysteretic) {
        (true, true) => {
            let (laws, out) = (&laws[law..law + n], &mut out[law..law + n]);
            pairs_of::<true, true>(items, b, laws, out, acc, sums)
        }
        (false, true) => {
            let (laws, out) = (&laws[law..law + n], &mut out[law..law + n]);
            pairs_of::<false, true>(items, b, laws, out, acc, sums)
        }
        (true, false) => pairs_of::<true, false>(items, b, &[], &mut [], acc, sums),
        (false, false) => pairs_of::<false, false>(items, b, &[], &mut [], acc, sums),
    }
}

/// [`pairs`] by support and law (H: hysteretic, `laws` and `out` two per pair).
#[inline(always)]
fn pairs_of<const S: bool, const H: bool>(
    items: &[Item],
    b: &Body,
    laws: &[Hysteretic],
    out: &mut [(f64, f64)],
    acc: &mut [f64; 3],
    sums: &mut Sums,
) {
    let (s, rel) = (b.s, b.rel);
    let (c, sn) = s.cs;
    let support = |it: &Item| {
        if S {
            let (u, v, _) = b.fr.supports[it.support];
            (u, v)
        } else {
            (0.0, 0.0)
        }
    };
    let mut element = |it: &Item, e: f64, ed: f64, vg: f64, k: usize| {
        let (f, fh) = if H {
            out[k] = (e, ed);
            let fh = laws[k].force(e);
            (fh + it.damping * ed, fh)
        } else {
            (it.stiffness * e + it.damping * ed, 0.0)
        };
        sums.supports -= f * vg;
        sums.damping += it.damping * ed * ed;
        if H {
            sums.hysteretic += fh * ed;
        }
        f
    };
    for (k, pair) in items.chunks_exact(2).enumerate() {
        let (ix, iy) = (&pair[0], &pair[1]);
        let (px, py) = (ix.px, ix.py);
        let rx = c * px - sn * py;
        let ry = sn * px + c * py;
        let (ug, vg) = support(ix);
        let arm = -ry;
        let ux = rel.x + rx - px;
        let ed = s.velocity.x + s.omega * arm - vg;
        let f = element(ix, ux - ug, ed, vg, 2 * k);
        acc[0] += f;
        acc[2] += f * arm;
        let (ug, vg) = support(iy);
        let uy = rel.y + ry - py;
        let ed = s.velocity.y + s.omega * rx - vg;
        let f = element(iy, uy - ug, ed, vg, 2 * k + 1);
        acc[1] += f;
        acc[2] += f * rx;
    }
}
