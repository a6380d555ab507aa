//! Light bodies on their free linear flow: a body held only by linear spring–dashpots to the
//! ground or to supports (an abutment on its actuators) moves, while its contacts are open,
//! by M q̈ + C q̇ + K q = F(t) (the elements linearised at q = 0, F from the support motions).
//! Each DP5 step is taken around that flow started from the step's own state
//! ([`dopri::Reference`]): the step integrates δ = y − y_ref, which carries only the
//! elements' geometric nonlinearity (sin θ) and nothing at the body's 28–36 Hz, so the
//! body's ringing and its driven motion no longer set the step size.
//!
//! y_ref is exact at knots τ apart (ω_max τ ≤ [`OMEGA_TAU`]), on the grid of the body's
//! record samples where it has one, so that u_g is one cubic between knots:
//! z(σ) = e^{Aσ} z₀ + Σₖ Ψₖ(σ) Fₖ for F(s) = Σ Fₖ sᵏ (variation of constants; e^{Aσ} and Ψₖ by their series,
//! converged to the last bit at ωσ ≤ 1), and a quintic Hermite in q (q, q̇, q̈ at both knots)
//! between them. The ledger's support work and damping of the body's elements are referenced
//! too: their powers along y_ref, polynomials between knots, integrated exactly.

#![allow(clippy::needless_range_loop)] // index arithmetic over small fixed arrays

mod span;

use crate::dopri::{MAX_REFERENCED, Reference};
use crate::scene::{Attachment, BodyRef, Scene, perp};
use nalgebra::{DMatrix, DVector};
pub(super) use span::Span;
use std::sync::Arc;

/// The largest ω_max τ of the knots (at rtol ≥ 1e-4): the quintic Hermite between exact
/// knots is then within 1e-6 of the linear flow, relative to the body's dynamic amplitude.
const OMEGA_TAU: f64 = 0.6;
/// Most knot intervals in one step (the step is held to that length while a reference may
/// be taken).
const MAX_INTERVALS: usize = 64;
/// Most knot intervals of one reference: a longer one starts again.
const MAX_SPAN: usize = 8192;
/// Terms of the series of e^{Aσ} and Ψₖ(σ): (ωσ)²²/22! < 1e-21 at ωσ ≤ 1.
const SERIES: usize = 22;

/// A linear element of a light body: e = J q − u_g, force k e + c ė.
#[derive(Clone, Debug)]
struct Linear {
    j: Vec<f64>,
    k: f64,
    c: f64,
    /// Index into the body's `supports`.
    support: Option<usize>,
}

/// A light body and its free flow over one knot interval.
#[derive(Clone, Debug)]
struct LightBody {
    /// Its DOFs (indices into q).
    dofs: Vec<usize>,
    mass: Vec<f64>,
    /// The contacts it takes part in: while all are open, it moves freely.
    contacts: Vec<usize>,
    k: DMatrix<f64>,
    c: DMatrix<f64>,
    loads: Vec<f64>,
    /// The scene supports its elements follow, and per support ∂F/∂u_g, ∂F/∂u̇_g.
    supports: Vec<usize>,
    fk: Vec<[f64; 3]>,
    fc: Vec<[f64; 3]>,
    elements: Vec<Linear>,
    /// Mass-proportional damping a₀ and its reference-velocity terms (dof, support, factor).
    alpha: f64,
    mass_ref: Vec<(usize, usize, f64)>,
    /// A = [0 I; −M⁻¹K −M⁻¹C], row-major (2m × 2m), and its largest |λ|.
    a: [f64; 36],
    omega: f64,
    /// The DOF index of θ in `dofs` and the largest offset |p| of a point element, when the
    /// body turns: its elements are then not linear (sin θ).
    turns: Option<(usize, f64)>,
    /// The knots' spacing, and the instant they are aligned to (a record's first sample).
    tau: f64,
    grid: Option<f64>,
    /// e^{Aτ} (2m × 2m) and Ψₖ(τ) M⁻¹ (2m × m: the response to F = sᵏ), row-major.
    phi: [f64; 36],
    psi: [[f64; 18]; 4],
}

/// Coefficients kept per component and interval: polynomials in s of degree ≤ 9.
const NC: usize = 10;

/// Most supports a light body's elements may follow.
const MAX_SUPPORTS: usize = 8;

/// A body's state at a knot: z = (q, q̇), q̈ and its supports' (u_g, u̇_g).
#[derive(Clone, Copy, Debug)]
struct Knot {
    z: [f64; 6],
    a: [f64; 3],
    u: [(f64, f64); MAX_SUPPORTS],
}

/// The scene's light bodies.
#[derive(Debug)]
pub(super) struct Light {
    bodies: Vec<LightBody>,
    /// The scene's supports (their motions are shared, not copied).
    supports: Vec<crate::scene::Support>,
    /// The shortest knot spacing.
    tau: f64,
    /// Number of DOFs of the scene.
    n: usize,
}

impl Light {
    /// The light bodies of `scene` (None without any): bodies with DOFs, not driven, whose
    /// elements are all linear springs of their own (no hysteretic element, no key).
    pub(super) fn of(scene: &Scene) -> Option<Arc<Self>> {
        if !scene.settings.free_flow {
            return None;
        }
        // the quintic Hermite's error, (ωτ)⁶/46080 of the motion, within rtol/100
        let wt = (460.8 * scene.settings.rtol)
            .powf(1.0 / 6.0)
            .clamp(0.05, OMEGA_TAU);
        let bodies: Vec<LightBody> = (scene.bodies.iter().enumerate())
            .filter_map(|(b, body)| light_body(scene, b, body, wt))
            .collect();
        let tau = bodies.iter().map(|b| b.tau).fold(f64::INFINITY, f64::min);
        if bodies.is_empty() || !(tau > 0.0 && tau.is_finite()) {
            return None;
        }
        Some(Arc::new(Self {
            bodies,
            supports: scene.supports.clone(),
            tau,
            n: scene.ndof(),
        }))
    }

    /// The longest step around the free flow.
    pub(super) fn max_step(&self) -> f64 {
        MAX_INTERVALS as f64 * self.tau
    }

    /// The reference of a step from (t0, y0) over h: the free flow of every light body whose
    /// contacts are all open (`open(i)`), or None. The last one (`last`) goes on for the same
    /// bodies while y0 is on it within a hundredth of the tolerance (δ₀ ≈ 0: an event
    /// elsewhere, a branch change, leaves it valid); else a new one starts at (t0, y0).
    pub(super) fn span(
        self: &Arc<Self>,
        last: &mut Option<Arc<Span>>,
        scene: &Scene,
        t0: f64,
        h: f64,
        y0: &DVector<f64>,
        open: impl Fn(usize) -> bool,
    ) -> Option<Arc<dyn Reference>> {
        let fits = h / self.tau <= (MAX_INTERVALS + 1) as f64;
        if !fits {
            return None;
        }
        let mut active = [0usize; MAX_REFERENCED];
        let (mut na, mut count) = (0, 2);
        for (i, lb) in self.bodies.iter().enumerate() {
            let m = lb.dofs.len();
            if lb.contacts.iter().all(|&c| open(c))
                && count + 2 * m <= MAX_REFERENCED
                && lb.nearly_linear(y0, self.n, &scene.settings)
            {
                active[na] = i;
                na += 1;
                count += 2 * m;
            }
        }
        let active = &active[..na];
        if active.is_empty() {
            return None;
        }
        if let Some(sp) = last
            && sp.active == active
            && sp.t0 <= t0
            && t0 + h <= sp.t0 + (MAX_SPAN - 2) as f64 * self.tau
            && sp.holds(t0, y0, &scene.settings)
        {
            return Some(sp.clone());
        }
        let sp = Arc::new(Span::new(self.clone(), t0, active, y0));
        *last = Some(sp.clone());
        Some(sp)
    }
}

/// Body `b` of `scene` as a light body, if it is one, with knots at ωτ ≤ `wt`.
fn light_body(scene: &Scene, b: usize, body: &crate::scene::Body, wt: f64) -> Option<LightBody> {
    if body.is_driven() || body.has_no_dofs() {
        return None;
    }
    let touches = |att: &Attachment| {
        let (a, o) = att.bodies();
        a == b || o == Some(b)
    };
    if scene.hysteretic.iter().any(|h| touches(&h.attachment)) {
        return None;
    }
    let axes: Vec<(usize, usize)> = (0..3)
        .filter_map(|a| body.dofs[a].map(|d| (a, d)))
        .collect();
    let m = axes.len();
    let dofs: Vec<usize> = axes.iter().map(|&(_, d)| d).collect();
    let mass: Vec<f64> = dofs.iter().map(|&d| scene.mass[d]).collect();
    if mass.iter().any(|&x| !(x > 0.0 && x.is_finite())) {
        return None;
    }
    let followed = |g: usize| {
        scene
            .springs
            .iter()
            .any(|s| touches(&s.attachment) && s.support == Some(g))
            || (scene.mass_damping.alpha != 0.0
                && (scene.mass_damping.reference.iter())
                    .any(|&(d, s, _)| s == g && body.dofs.contains(&Some(d))))
    };
    if (0..scene.supports.len()).filter(|&g| followed(g)).count() > MAX_SUPPORTS {
        return None;
    }
    let mut lb = LightBody {
        contacts: (scene.contacts.iter().enumerate())
            .filter(|(_, c)| c.point_body == BodyRef::Body(b) || c.face_body == BodyRef::Body(b))
            .map(|(i, _)| i)
            .collect(),
        k: DMatrix::zeros(m, m),
        c: DMatrix::zeros(m, m),
        loads: dofs.iter().map(|&d| scene.loads[d]).collect(),
        supports: Vec::new(),
        fk: Vec::new(),
        fc: Vec::new(),
        elements: Vec::new(),
        alpha: scene.mass_damping.alpha,
        mass_ref: Vec::new(),
        a: [0.0; 36],
        omega: 0.0,
        turns: None,
        tau: 0.0,
        grid: None,
        phi: [0.0; 36],
        psi: [[0.0; 18]; 4],
        dofs,
        mass,
    };
    for s in scene.springs.iter().filter(|s| touches(&s.attachment)) {
        let row = match s.attachment {
            Attachment::Point {
                point, direction, ..
            } => [direction.x, direction.y, direction.dot(&perp(point))],
            Attachment::Rotation { .. } => [0.0, 0.0, 1.0],
            Attachment::Relative { .. } => return None,
        };
        let j: Vec<f64> = axes.iter().map(|&(a, _)| row[a]).collect();
        let support = s.support.map(|g| lb.support_slot(g));
        for r in 0..m {
            for q in 0..m {
                lb.k[(r, q)] += s.stiffness * j[r] * j[q];
                lb.c[(r, q)] += s.damping * j[r] * j[q];
            }
            if let Some(i) = support {
                lb.fk[i][r] += s.stiffness * j[r];
                lb.fc[i][r] += s.damping * j[r];
            }
        }
        lb.elements.push(Linear {
            j,
            k: s.stiffness,
            c: s.damping,
            support,
        });
    }
    for r in 0..m {
        lb.c[(r, r)] += lb.alpha * lb.mass[r];
    }
    for &(d, s, f) in &scene.mass_damping.reference {
        if let Some(r) = lb.dofs.iter().position(|&x| x == d) {
            let i = lb.support_slot(s);
            lb.fc[i][r] += lb.alpha * lb.mass[r] * f;
            lb.mass_ref.push((r, i, f));
        }
    }
    let a = lb.state_matrix();
    let omega = (a.complex_eigenvalues().iter()).fold(0.0, |w: f64, l| w.max(l.norm()));
    if !(omega > 0.0 && omega.is_finite()) {
        return None;
    }
    for r in 0..2 * m {
        for q in 0..2 * m {
            lb.a[r * 2 * m + q] = a[(r, q)];
        }
    }
    lb.omega = omega;
    let radius = (scene.springs.iter().filter(|s| touches(&s.attachment)))
        .map(|s| match s.attachment {
            Attachment::Point { point, .. } => point.norm(),
            _ => 0.0,
        })
        .fold(0.0, f64::max);
    lb.turns = (axes.iter().position(|&(a, _)| a == 2)).map(|r| (r, radius));
    lb.knot_grid(scene, wt);
    lb.transitions();
    Some(lb)
}

impl LightBody {
    /// Knots ωτ ≤ `wt` apart, on the samples of the body's records when they share one grid
    /// (u_g is then one cubic between knots), else anywhere.
    fn knot_grid(&mut self, scene: &Scene, wt: f64) {
        let grids: Vec<Option<(f64, f64)>> = (self.supports.iter())
            .map(|&g| match &scene.supports[g].motion {
                crate::scene::Motion::Record(r) => Some((r.t0, r.dt)),
                crate::scene::Motion::Harmonic { .. } => None,
            })
            .collect();
        let on_grid = |(o, dt): (f64, f64), (o2, dt2): (f64, f64)| {
            let k = (o2 - o) / dt;
            dt == dt2 && (k - k.round()).abs() < 1e-9
        };
        self.tau = wt / self.omega;
        if let Some(Some(first)) = grids.first()
            && grids.iter().all(|g| g.is_some_and(|g| on_grid(*first, g)))
            && first.1 > 0.0
        {
            self.tau = first.1 / (first.1 / self.tau).ceil();
            self.grid = Some(first.0);
        }
    }

    /// The slot of scene support `g` in `supports` (added if new).
    fn support_slot(&mut self, g: usize) -> usize {
        match self.supports.iter().position(|&x| x == g) {
            Some(i) => i,
            None => {
                self.supports.push(g);
                self.fk.push([0.0; 3]);
                self.fc.push([0.0; 3]);
                self.supports.len() - 1
            }
        }
    }

    /// A = [0 I; −M⁻¹K −M⁻¹C].
    fn state_matrix(&self) -> DMatrix<f64> {
        let m = self.dofs.len();
        let mut a = DMatrix::zeros(2 * m, 2 * m);
        for r in 0..m {
            a[(r, m + r)] = 1.0;
            for q in 0..m {
                a[(m + r, q)] = -self.k[(r, q)] / self.mass[r];
                a[(m + r, m + q)] = -self.c[(r, q)] / self.mass[r];
            }
        }
        a
    }

    /// Whether the body's elements at y are linear to within a hundredth of the tolerance:
    /// with θ up to ϑ = |θ| + |θ̇|/ω, e departs from its linearisation by |p|ϑ²/2 and the
    /// motion by about as much (K⁻¹ of that force), θ by ϑ³/6.
    fn nearly_linear(&self, y: &DVector<f64>, n: usize, st: &crate::scene::Settings) -> bool {
        let Some((r, radius)) = self.turns else {
            return true;
        };
        let d = self.dofs[r];
        let th = y[d].abs() + y[n + d].abs() / self.omega;
        let bound = 0.5 * radius * th * th + th * th * th / 6.0;
        let tol =
            (self.dofs.iter()).fold(f64::INFINITY, |t, &i| t.min(st.atol + st.rtol * y[i].abs()));
        bound <= 0.01 * tol
    }

    /// Φ = e^{Aτ} and Ψₖ(τ) M⁻¹, column by column from [`LightBody::series`].
    fn transitions(&mut self) {
        let m = self.dofs.len();
        let w = 2 * m;
        for q in 0..w {
            let mut e = [0.0; 6];
            e[q] = 1.0;
            let col = self.series(self.tau, &e, &[[0.0; 3]; 4]);
            for r in 0..w {
                self.phi[r * w + q] = col[r];
            }
        }
        for k in 0..4 {
            for q in 0..m {
                let mut f = [[0.0; 3]; 4];
                f[k][q] = 1.0;
                let col = self.series(self.tau, &[0.0; 6], &f);
                for r in 0..w {
                    self.psi[k][r * m + q] = col[r];
                }
            }
        }
    }

    /// z(σ) = e^{Aσ} z₀ + Σₖ Ψₖ(σ) M⁻¹ Fₖ, Ψₖ(σ) = ∫₀^σ e^{A(σ−s)} sᵏ ds, by the series
    /// Σⱼ Aʲ [σʲ/j! z₀ + Σₖ k! σʲ⁺ᵏ⁺¹/(j+k+1)! g_k] (g_k = (0, M⁻¹Fₖ)), summed by Horner.
    fn series(&self, sigma: f64, z0: &[f64; 6], f: &[[f64; 3]; 4]) -> [f64; 6] {
        let m = self.dofs.len();
        let w = 2 * m;
        // c[i] = σⁱ/i!; the force terms k! σʲ⁺ᵏ⁺¹/(j+k+1)! M⁻¹Fₖ
        let mut c = [1.0; SERIES + 5];
        for i in 1..c.len() {
            c[i] = c[i - 1] * sigma / i as f64;
        }
        let mut g = [[0.0; 3]; 4];
        for (k, (gk, fk)) in g.iter_mut().zip(f).enumerate() {
            let fact = [1.0, 1.0, 2.0, 6.0][k];
            for r in 0..m {
                gk[r] = fact * fk[r] / self.mass[r];
            }
        }
        let mut acc = [0.0; 6];
        for j in (0..=SERIES).rev() {
            let mut next = [0.0; 6];
            for r in 0..w {
                let mut x = c[j] * z0[r];
                for q in 0..w {
                    x += self.a[r * w + q] * acc[q];
                }
                next[r] = x;
            }
            for r in 0..m {
                next[m + r] += (0..4).map(|k| c[j + k + 1] * g[k][r]).sum::<f64>();
            }
            acc = next;
        }
        acc
    }
}

impl LightBody {
    /// The knot at t with state z.
    fn knot(&self, supports: &[crate::scene::Support], t: f64, z: [f64; 6]) -> Knot {
        let mut u = [(0.0, 0.0); MAX_SUPPORTS];
        for (x, &g) in u.iter_mut().zip(&self.supports) {
            *x = at2(supports, g, t);
        }
        self.knot_with(z, u)
    }

    /// The knot of state z and supports u: q̈ = M⁻¹(F − K q − C q̇), the q̈ rows of A z
    /// and M⁻¹F.
    fn knot_with(&self, z: [f64; 6], u: [(f64, f64); MAX_SUPPORTS]) -> Knot {
        let m = self.dofs.len();
        let w = 2 * m;
        let mut a = [0.0; 3];
        for (r, ar) in a.iter_mut().enumerate().take(m) {
            let mut force = self.loads[r];
            for ((fk, fc), &(d, v)) in self.fk.iter().zip(&self.fc).zip(&u) {
                force += fk[r] * d + fc[r] * v;
            }
            let row = &self.a[(m + r) * w..(m + r + 1) * w];
            *ar = force / self.mass[r] + row.iter().zip(&z).map(|(x, y)| x * y).sum::<f64>();
        }
        Knot { z, a, u }
    }

    /// F(s) = F₀ + F₁s + F₂s² + F₃s³ from the supports' cubics `cu` (and the loads).
    fn forcing(&self, cu: &[[f64; 4]]) -> [[f64; 3]; 4] {
        let m = self.dofs.len();
        let mut f = [[0.0; 3]; 4];
        f[0][..m].copy_from_slice(&self.loads);
        for (i, c) in cu.iter().enumerate() {
            for r in 0..m {
                let (a, b) = (self.fk[i][r], self.fc[i][r]);
                f[0][r] += a * c[0] + b * c[1];
                f[1][r] += a * c[1] + 2.0 * b * c[2];
                f[2][r] += a * c[2] + 3.0 * b * c[3];
                f[3][r] += a * c[3];
            }
        }
        f
    }

    /// z(τ) = Φ z₀ + Σₖ Ψₖ M⁻¹ Fₖ.
    fn advance(&self, z0: &[f64; 6], f: &[[f64; 3]; 4]) -> [f64; 6] {
        let m = self.dofs.len();
        let w = 2 * m;
        let mut z1 = [0.0; 6];
        for (r, zr) in z1.iter_mut().enumerate().take(w) {
            let mut acc = 0.0;
            for q in 0..w {
                acc += self.phi[r * w + q] * z0[q];
            }
            for (p, fk) in self.psi.iter().zip(f) {
                for q in 0..m {
                    acc += p[r * m + q] * fk[q];
                }
            }
            *zr = acc;
        }
        z1
    }

    /// Adds the power polynomials (support work, damping) of the body's elements with q(s)
    /// = `qs` and supports `cu` (cubics), as `scene::smooth_forces_in` with e linearised.
    fn power_poly(&self, qs: &[[f64; 6]], cu: &[[f64; 4]], out: &mut [[f64; NC]; 2]) {
        let m = qs.len();
        let mut vs = [[0.0; 5]; 3];
        for (v, q) in vs.iter_mut().zip(qs) {
            for d in 0..5 {
                v[d] = (d + 1) as f64 * q[d + 1];
            }
        }
        let mut uds = [[0.0; 3]; MAX_SUPPORTS];
        for (u, c) in uds.iter_mut().zip(cu) {
            *u = [c[1], 2.0 * c[2], 3.0 * c[3]];
        }
        for el in &self.elements {
            let (mut e, mut ed) = ([0.0; 6], [0.0; 5]);
            for r in 0..m {
                for d in 0..6 {
                    e[d] += el.j[r] * qs[r][d];
                }
                for d in 0..5 {
                    ed[d] += el.j[r] * vs[r][d];
                }
            }
            let mut ud = [0.0; 3];
            if let Some(i) = el.support {
                for d in 0..4 {
                    e[d] -= cu[i][d];
                }
                for d in 0..3 {
                    ed[d] -= uds[i][d];
                }
                ud = uds[i];
            }
            let mut f = [0.0; 6];
            for d in 0..6 {
                f[d] = el.k * e[d] + if d < 5 { el.c * ed[d] } else { 0.0 };
            }
            mul_add(&mut out[0], &f, &ud, -1.0);
            mul_add(&mut out[1], &ed, &ed, el.c);
        }
        if self.alpha != 0.0 {
            for r in 0..m {
                let mut vref = [0.0; 3];
                for &(rr, i, f) in &self.mass_ref {
                    if rr == r {
                        for d in 0..3 {
                            vref[d] += f * uds[i][d];
                        }
                    }
                }
                let mut rel = vs[r];
                for d in 0..3 {
                    rel[d] -= vref[d];
                }
                let am = self.alpha * self.mass[r];
                mul_add(&mut out[1], &rel, &rel, am);
                mul_add(&mut out[0], &rel, &vref, -am);
            }
        }
    }
}

/// out += scale · a · b (polynomial product).
fn mul_add<const A: usize, const B: usize>(
    out: &mut [f64; NC],
    a: &[f64; A],
    b: &[f64; B],
    scale: f64,
) {
    for i in 0..A {
        let x = scale * a[i];
        for j in 0..B {
            out[i + j] += x * b[j];
        }
    }
}

fn horner(p: &[f64], s: f64) -> f64 {
    p.iter().rev().fold(0.0, |acc, c| acc * s + c)
}

/// (u_g, u̇_g) of support g at t.
fn at2(supports: &[crate::scene::Support], g: usize, t: f64) -> (f64, f64) {
    let (d, v, _) = supports[g].at(t);
    (d, v)
}

/// Coefficients of the quintic with (q, q̇, q̈) = `a` at 0 and `b` at τ.
fn quintic(a: (f64, f64, f64), b: (f64, f64, f64), tau: f64) -> [f64; 6] {
    let ((p0, v0, a0), (p1, v1, a1)) = (a, b);
    let d = p1 - (p0 + tau * (v0 + 0.5 * tau * a0));
    let dv = (v1 - (v0 + tau * a0)) * tau;
    let da = (a1 - a0) * tau * tau;
    let t3 = tau * tau * tau;
    [
        p0,
        v0,
        0.5 * a0,
        (10.0 * d - 4.0 * dv + 0.5 * da) / t3,
        (-15.0 * d + 7.0 * dv - da) / (t3 * tau),
        (6.0 * d - 3.0 * dv + 0.5 * da) / (t3 * tau * tau),
    ]
}

/// Coefficients of the cubic with (u, u̇) = `a` at 0 and `b` at τ.
fn hermite3(a: (f64, f64), b: (f64, f64), tau: f64) -> [f64; 4] {
    let (u0, v0) = a;
    let (u1, v1) = b;
    let c2 = (3.0 * (u1 - u0) / tau - 2.0 * v0 - v1) / tau;
    let c3 = (2.0 * (u0 - u1) / tau + v0 + v1) / (tau * tau);
    [u0, v0, c2, c3]
}
