//! The free flow of the active light bodies over a run of steps, made as it is asked for.

use super::{Knot, Light, MAX_SPAN, MAX_SUPPORTS, NC, at2, hermite3, horner, quintic};
use crate::dopri::{MAX_REFERENCED, Reference};
use nalgebra::DVector;
use std::sync::{Arc, Mutex};

/// The free flow of the active light bodies from `t0`, made as it is asked for: per body its
/// knots, and on each interval its q, q̇ and ledger terms as polynomials in the time s into
/// it.
#[derive(Debug)]
pub(in crate::event_driven) struct Span {
    light: Arc<Light>,
    pub(super) t0: f64,
    /// The light bodies it moves.
    pub(super) active: Vec<usize>,
    /// q and q̇ of each active body in turn, then the ledger's support work and damping.
    comps: Vec<usize>,
    flows: Mutex<Vec<Flow>>,
}

/// One body's flow in a [`Span`]: interval 0 from t0 to the first knot, then knots τ apart.
#[derive(Debug)]
struct Flow {
    first: f64,
    /// [interval][q… q̇… support work, damping][NC].
    coef: Vec<f64>,
    /// The knot at the end of the last interval made, and the ledger terms there.
    end: Knot,
    ledger: [f64; 2],
}

impl Span {
    /// The flow of bodies `active` from (q, q̇) of `y0` at t0.
    pub(super) fn new(light: Arc<Light>, t0: f64, active: &[usize], y0: &DVector<f64>) -> Self {
        let n = light.n;
        let mut comps = Vec::new();
        let mut flows = Vec::new();
        for &b in active {
            let lb = &light.bodies[b];
            let m = lb.dofs.len();
            comps.extend(lb.dofs.iter().copied());
            comps.extend(lb.dofs.iter().map(|d| n + d));
            let mut z = [0.0; 6];
            for (r, &d) in lb.dofs.iter().enumerate() {
                z[r] = y0[d];
                z[m + r] = y0[n + d];
            }
            // the first knot: on the grid, at least a thousandth of τ after t0
            let first = match lb.grid {
                Some(o) => {
                    let k = ((t0 - o) / lb.tau).ceil();
                    let t = o + k * lb.tau;
                    if t - t0 < 1e-3 * lb.tau {
                        t + lb.tau
                    } else {
                        t
                    }
                }
                None => t0 + lb.tau,
            };
            flows.push(Flow {
                first,
                coef: Vec::new(),
                end: lb.knot(&light.supports, t0, z),
                ledger: [0.0; 2],
            });
        }
        comps.extend([2 * n + 1, 2 * n + 2]);
        Self {
            t0,
            active: active.to_vec(),
            comps,
            flows: Mutex::new(flows),
            light,
        }
    }

    /// Body `ai`'s interval of t, the time into it, and the interval's start.
    fn interval(&self, ai: usize, first: f64, t: f64) -> (usize, f64) {
        let tau = self.light.bodies[self.active[ai]].tau;
        if t < first {
            return (0, t - self.t0);
        }
        let k = (((t - first) / tau).floor() as usize + 1).min(MAX_SPAN);
        (k, t - (first + (k - 1) as f64 * tau))
    }

    /// Makes body `ai`'s intervals up to k: an exact step to the next knot, q the quintic
    /// Hermite of (q, q̇, q̈) at its ends, q̇ its derivative, the ledger terms the integrals
    /// of their powers along it.
    fn make(&self, ai: usize, flow: &mut Flow, k: usize) {
        let lb = &self.light.bodies[self.active[ai]];
        let (m, ns) = (lb.dofs.len(), lb.supports.len());
        let row_len = (2 * m + 2) * NC;
        while flow.coef.len() < (k + 1) * row_len {
            let i = flow.coef.len() / row_len;
            let (ta, tb) = match i {
                0 => (self.t0, flow.first),
                _ => (
                    flow.first + (i - 1) as f64 * lb.tau,
                    flow.first + i as f64 * lb.tau,
                ),
            };
            let sigma = tb - ta;
            let k0 = flow.end;
            let mut u1 = [(0.0, 0.0); MAX_SUPPORTS];
            for (u, &g) in u1.iter_mut().zip(&lb.supports) {
                *u = at2(&self.light.supports, g, tb);
            }
            let mut cu = [[0.0; 4]; MAX_SUPPORTS];
            for i in 0..ns {
                cu[i] = hermite3(k0.u[i], u1[i], sigma);
            }
            let f = lb.forcing(&cu[..ns]);
            let z1 = if i == 0 {
                lb.series(sigma, &k0.z, &f)
            } else {
                lb.advance(&k0.z, &f)
            };
            let k1 = lb.knot_with(z1, u1);
            let mut qs = [[0.0; 6]; 3];
            let mut row = [0.0; 8 * NC];
            for r in 0..m {
                qs[r] = quintic(
                    (k0.z[r], k0.z[m + r], k0.a[r]),
                    (k1.z[r], k1.z[m + r], k1.a[r]),
                    sigma,
                );
                row[r * NC..r * NC + 6].copy_from_slice(&qs[r]);
                for d in 0..5 {
                    row[(m + r) * NC + d] = (d + 1) as f64 * qs[r][d + 1];
                }
            }
            let mut power = [[0.0; NC]; 2];
            lb.power_poly(&qs[..m], &cu[..ns], &mut power);
            for (l, p) in power.iter().enumerate() {
                let c = &mut row[(2 * m + l) * NC..(2 * m + l + 1) * NC];
                c[0] = flow.ledger[l];
                for d in 0..NC - 1 {
                    c[d + 1] = p[d] / (d + 1) as f64;
                }
                flow.ledger[l] = horner(c, sigma);
            }
            flow.coef.extend_from_slice(&row[..row_len]);
            flow.end = k1;
        }
    }

    /// Runs `f` on each active body's coefficients of the interval of t (q…, q̇…, support
    /// work, damping; NC each) and the time into it.
    fn each_at(&self, t: f64, mut f: impl FnMut(usize, &[f64], f64)) {
        let mut flows = self.flows.lock().unwrap_or_else(|e| e.into_inner());
        for (ai, flow) in flows.iter_mut().enumerate() {
            let (k, s) = self.interval(ai, flow.first, t);
            self.make(ai, flow, k);
            let row_len = (2 * self.light.bodies[self.active[ai]].dofs.len() + 2) * NC;
            f(ai, &flow.coef[k * row_len..(k + 1) * row_len], s);
        }
    }

    /// Whether y's referenced q and q̇ are on the flow at t within a hundredth of the
    /// tolerance.
    pub(super) fn holds(&self, t: f64, y: &DVector<f64>, st: &crate::scene::Settings) -> bool {
        let mut val = [0.0; MAX_REFERENCED];
        self.eval(t, 2 * self.light.n, &mut val, None);
        let nq = self.comps.len() - 2;
        (0..nq).all(|j| {
            let i = self.comps[j];
            (y[i] - val[j]).abs() <= 0.01 * (st.atol + st.rtol * y[i].abs())
        })
    }
}

impl Reference for Span {
    fn components(&self) -> &[usize] {
        &self.comps
    }

    fn eval(&self, t: f64, upto: usize, val: &mut [f64], mut rate: Option<&mut [f64]>) {
        let nq = self.comps.len() - 2;
        let ledger = upto > self.comps[nq];
        if ledger {
            val[nq..nq + 2].fill(0.0);
        }
        if let Some(rt) = rate.as_deref_mut() {
            rt[nq..nq + 2].fill(0.0);
        }
        let mut j = 0;
        self.each_at(t, |_, row, s| {
            let w = row.len() / NC - 2;
            for c in 0..w + 2 {
                let p = &row[c * NC..(c + 1) * NC];
                let at = if c < w { j + c } else { nq + c - w };
                if c < w {
                    val[at] = horner(p, s);
                } else if ledger {
                    val[at] += horner(p, s);
                }
                if let Some(rt) = rate.as_deref_mut() {
                    let mut acc = 0.0;
                    for d in (1..NC).rev() {
                        acc = acc * s + d as f64 * p[d];
                    }
                    rt[at] += if c < w { acc - rt[at] } else { acc };
                }
            }
            j += w;
        });
    }

    fn eval_one(&self, t: f64, j: usize) -> f64 {
        let nq = self.comps.len() - 2;
        let mut flows = self.flows.lock().unwrap_or_else(|e| e.into_inner());
        let (mut start, mut out) = (0, 0.0);
        for (ai, flow) in flows.iter_mut().enumerate() {
            let w = 2 * self.light.bodies[self.active[ai]].dofs.len();
            let c = match j {
                _ if j >= nq => w + j - nq,
                _ if j < start + w => j - start,
                _ => {
                    start += w;
                    continue;
                }
            };
            let (k, s) = self.interval(ai, flow.first, t);
            self.make(ai, flow, k);
            let at = (k * (w + 2) + c) * NC;
            out += horner(&flow.coef[at..at + NC], s);
            if j < nq {
                break;
            }
            start += w;
        }
        out
    }
}
