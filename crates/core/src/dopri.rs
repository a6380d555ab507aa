//! Dormand–Prince 5(4) with FSAL and Hairer's 4th-order dense output
//! (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.5–6, code DOPRI5).

use nalgebra::DVector;

const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// b − b̂ (error estimator).
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];
/// Dense output coefficients d₁…d₇.
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// A right-hand side f(t, y) → out.
pub(crate) type Rhs<'a, E> = dyn FnMut(f64, &DVector<f64>, &mut DVector<f64>) -> Result<(), E> + 'a;

/// One attempted step with its dense output.
#[derive(Debug)]
pub struct Step {
    /// Start time.
    pub t0: f64,
    /// Step size.
    pub h: f64,
    /// y(t0).
    pub y0: DVector<f64>,
    /// y(t0 + h), the 5th-order solution.
    pub y1: DVector<f64>,
    /// f(t0 + h, y1): the next step's first stage (FSAL).
    pub f1: DVector<f64>,
    /// Weighted RMS error estimate (≤ 1 accepts).
    pub error: f64,
    /// The component with the largest weighted error: the one that sets the step size
    /// (`usize::MAX` without error control).
    pub worst: usize,
    cont: [DVector<f64>; 3],
}

impl Clone for Step {
    fn clone(&self) -> Self {
        Self {
            t0: self.t0,
            h: self.h,
            y0: self.y0.clone(),
            y1: self.y1.clone(),
            f1: self.f1.clone(),
            error: self.error,
            worst: self.worst,
            cont: self.cont.clone(),
        }
    }

    /// Into the vectors already there when they have the sizes (an island keeps every step
    /// of its window: no allocation per step).
    fn clone_from(&mut self, source: &Self) {
        (self.t0, self.h, self.error, self.worst) =
            (source.t0, source.h, source.error, source.worst);
        let pairs = [
            (&mut self.y0, &source.y0),
            (&mut self.y1, &source.y1),
            (&mut self.f1, &source.f1),
        ];
        let conts = self.cont.iter_mut().zip(&source.cont);
        for (to, from) in pairs.into_iter().chain(conts) {
            if to.len() == from.len() {
                to.as_mut_slice().copy_from_slice(from.as_slice());
            } else {
                *to = from.clone();
            }
        }
    }
}

impl Step {
    /// y(t0 + θh), 0 ≤ θ ≤ 1, written into `out`; y1 itself at θ = 1 (y0 + (y1 − y0) may
    /// differ from y1 in the last bit).
    pub(crate) fn dense_into(&self, theta: f64, out: &mut DVector<f64>) {
        let n = out.len();
        if theta == 1.0 {
            out.as_mut_slice().copy_from_slice(&self.y1.as_slice()[..n]);
            return;
        }
        let th1 = 1.0 - theta;
        let [r3, r4, r5] = self.cont.each_ref().map(|r| &r.as_slice()[..n]);
        let (y0, y1) = (&self.y0.as_slice()[..n], &self.y1.as_slice()[..n]);
        for (i, o) in out.as_mut_slice().iter_mut().enumerate() {
            let r2 = y1[i] - y0[i];
            *o = y0[i] + theta * (r2 + th1 * (r3[i] + theta * (r4[i] + th1 * r5[i])));
        }
    }

    /// Component i of y(t0 + θh).
    #[inline]
    pub(crate) fn dense_component(&self, theta: f64, i: usize) -> f64 {
        let th1 = 1.0 - theta;
        let [r3, r4, r5] = self.cont.each_ref().map(|r| r.as_slice()[i]);
        let (y0, y1) = (self.y0.as_slice()[i], self.y1.as_slice()[i]);
        let r2 = y1 - y0;
        y0 + theta * (r2 + th1 * (r3 + theta * (r4 + th1 * r5)))
    }

    /// The coefficients (y0, y1 − y0, r3, r4, r5) of component i of the dense output, for
    /// [`dense_value`].
    #[inline]
    pub(crate) fn dense_coefficients(&self, i: usize) -> [f64; 5] {
        let [r3, r4, r5] = self.cont.each_ref().map(|r| r.as_slice()[i]);
        let (y0, y1) = (self.y0.as_slice()[i], self.y1.as_slice()[i]);
        [y0, y1 - y0, r3, r4, r5]
    }

    /// y(t) for t in [t0, t0 + h], a new vector.
    pub fn dense(&self, t: f64) -> DVector<f64> {
        let mut out = self.y0.clone();
        self.dense_at_into(t, &mut out);
        out
    }

    /// y(t) for t in [t0, t0 + h], written into `out`.
    pub(crate) fn dense_at_into(&self, t: f64, out: &mut DVector<f64>) {
        let theta = if self.h == 0.0 {
            0.0
        } else {
            ((t - self.t0) / self.h).clamp(0.0, 1.0)
        };
        self.dense_into(theta, out);
    }

    /// t0 + h.
    pub fn t1(&self) -> f64 {
        self.t0 + self.h
    }
}

/// Component i of y(t0 + θh), 0 ≤ θ < 1, from its [`Step::dense_coefficients`] `c`.
#[inline]
pub(crate) fn dense_value(c: &[f64; 5], theta: f64) -> f64 {
    let th1 = 1.0 - theta;
    c[0] + theta * (c[1] + th1 * (c[2] + theta * (c[3] + th1 * c[4])))
}

/// Take one DP5 step of size h from (t0, y0) with f0 = f(t0, y0). The error norm uses the first
/// `n_err` components with weights atol + rtol·max(|y0|, |y1|).
#[allow(clippy::too_many_arguments)]
pub fn step<E>(
    rhs: &mut Rhs<'_, E>,
    t0: f64,
    y0: &DVector<f64>,
    f0: &DVector<f64>,
    h: f64,
    rtol: f64,
    atol: f64,
    n_err: usize,
) -> Result<Step, E> {
    let mut ws = Workspace::default();
    step_into(&mut ws, rhs, t0, y0, f0, h, rtol, atol, n_err)?;
    Ok(ws.step)
}

/// Reusable storage of [`step_into`]: the stages and the last step.
#[derive(Clone, Debug)]
pub(crate) struct Workspace {
    k: [DVector<f64>; 7],
    /// The last step taken.
    pub step: Step,
}

impl Default for Workspace {
    fn default() -> Self {
        let z = || DVector::zeros(0);
        Self {
            k: std::array::from_fn(|_| z()),
            step: Step {
                t0: 0.0,
                h: 0.0,
                y0: z(),
                y1: z(),
                f1: z(),
                error: 0.0,
                worst: usize::MAX,
                cont: [z(), z(), z()],
            },
        }
    }
}

/// [`step`] without allocation: the result is `ws.step`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn step_into<E>(
    ws: &mut Workspace,
    rhs: &mut Rhs<'_, E>,
    t0: f64,
    y0: &DVector<f64>,
    f0: &DVector<f64>,
    h: f64,
    rtol: f64,
    atol: f64,
    n_err: usize,
) -> Result<(), E> {
    let n = y0.len();
    let Workspace { k, step } = ws;
    if k[0].len() != n {
        for ks in k.iter_mut() {
            *ks = DVector::zeros(n);
        }
        step.y0 = DVector::zeros(n);
        step.y1 = DVector::zeros(n);
        step.f1 = DVector::zeros(n);
        step.cont = std::array::from_fn(|_| DVector::zeros(n));
    }
    k[0].as_mut_slice().copy_from_slice(f0.as_slice());
    let y = &mut step.y1;
    for (s, c) in C.iter().enumerate().skip(1) {
        let (done, rest) = k.split_at_mut(s);
        match s {
            1 => stage_argument::<1>(y, y0, done, h),
            2 => stage_argument::<2>(y, y0, done, h),
            3 => stage_argument::<3>(y, y0, done, h),
            4 => stage_argument::<4>(y, y0, done, h),
            5 => stage_argument::<5>(y, y0, done, h),
            _ => stage_argument::<6>(y, y0, done, h),
        }
        rhs(t0 + c * h, y, &mut rest[0])?;
    }
    // y (stage 7 argument) is the 5th-order solution y1 (FSAL: k[6] = f(t1, y1)).
    let y1 = step.y1.as_slice();
    let y0s = y0.as_slice();
    let ks: [&[f64]; 7] = std::array::from_fn(|s| &k[s].as_slice()[..n]);
    let m = n_err.min(n);
    let mut err = 0.0;
    let (mut worst, mut worst_r2) = (usize::MAX, -1.0);
    for i in 0..m {
        let mut e = 0.0;
        for (s, kk) in ks.iter().enumerate() {
            if E[s] != 0.0 {
                e += E[s] * kk[i];
            }
        }
        let sc = atol + rtol * y0s[i].abs().max(y1[i].abs());
        let r = h * e / sc;
        let r2 = r * r;
        if r2 > worst_r2 {
            (worst, worst_r2) = (i, r2);
        }
        err += r2;
    }
    step.error = if m == 0 { 0.0 } else { (err / m as f64).sqrt() };
    step.worst = worst;
    let [r3, r4, r5] = &mut step.cont;
    let (r3, r4, r5) = (
        &mut r3.as_mut_slice()[..n],
        &mut r4.as_mut_slice()[..n],
        &mut r5.as_mut_slice()[..n],
    );
    for i in 0..n {
        let r2 = y1[i] - y0s[i];
        r3[i] = h * ks[0][i] - r2;
        r4[i] = r2 - h * ks[6][i] - r3[i];
        let mut d = 0.0;
        for (s, kk) in ks.iter().enumerate() {
            if D[s] != 0.0 {
                d += D[s] * kk[i];
            }
        }
        r5[i] = h * d;
    }
    step.f1.as_mut_slice().copy_from_slice(k[6].as_slice());
    step.y0.as_mut_slice().copy_from_slice(y0.as_slice());
    step.t0 = t0;
    step.h = h;
    Ok(())
}

/// y = y0 + h Σⱼ A[S][j] k[j] (j < S, nonzero coefficients, summed in order), one pass over
/// the components.
#[inline(always)]
fn stage_argument<const S: usize>(
    y: &mut DVector<f64>,
    y0: &DVector<f64>,
    k: &[DVector<f64>],
    h: f64,
) {
    let c: [f64; S] = std::array::from_fn(|j| h * A[S][j]);
    let y0 = y0.as_slice();
    let n = y0.len();
    let ks: [&[f64]; S] = std::array::from_fn(|j| &k[j].as_slice()[..n]);
    let ys = &mut y.as_mut_slice()[..n];
    for i in 0..n {
        let mut acc = y0[i];
        for j in 0..S {
            if A[S][j] != 0.0 {
                acc += c[j] * ks[j][i];
            }
        }
        ys[i] = acc;
    }
}

/// Step-size controller (PI, Hairer's DOPRI5 defaults): new h from the error of the last step.
#[derive(Clone, Debug)]
pub(crate) struct Controller {
    prev_error: f64,
}

impl Default for Controller {
    fn default() -> Self {
        Self { prev_error: 1e-4 }
    }
}

impl Controller {
    /// The next step size after a step of size `h` with error estimate `error` (PI control,
    /// Hairer's β = 0.04, α = 0.2 − 0.75 β; safety 0.9, growth 0.2 … 10, after a rejection
    /// 0.1 … 1).
    pub(crate) fn next_h(&mut self, h: f64, error: f64, accepted: bool) -> f64 {
        let (beta, alpha) = (0.04, 0.2 - 0.04 * 0.75);
        let err = error.max(1e-10);
        let mut fac = 0.9 * err.powf(-alpha);
        if accepted {
            fac *= self.prev_error.powf(beta);
            self.prev_error = err.max(1e-4);
            h * fac.clamp(0.2, 10.0)
        } else {
            h * fac.clamp(0.1, 1.0)
        }
    }
}

/// Initial step guess (Hairer's `hinit`, simplified).
pub(crate) fn initial_h(
    y0: &DVector<f64>,
    f0: &DVector<f64>,
    rtol: f64,
    atol: f64,
    n_err: usize,
) -> f64 {
    let mut d0 = 0.0;
    let mut d1 = 0.0;
    for i in 0..n_err.min(y0.len()) {
        let sc = atol + rtol * y0[i].abs();
        d0 += (y0[i] / sc).powi(2);
        d1 += (f0[i] / sc).powi(2);
    }
    let (d0, d1) = (d0.sqrt(), d1.sqrt());
    if d0 < 1e-5 || d1 < 1e-5 {
        1e-6
    } else {
        0.01 * d0 / d1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A step of y' = A y (a damped oscillator and a decay) from y0 over h.
    fn oscillator_step(y0: &[f64], h: f64) -> Step {
        let mut rhs = |_t: f64, y: &DVector<f64>, out: &mut DVector<f64>| -> Result<(), ()> {
            out[0] = y[1];
            out[1] = -4.0 * y[0] - 0.1 * y[1];
            for i in 2..y.len() {
                out[i] = -y[i];
            }
            Ok(())
        };
        let y0 = DVector::from_column_slice(y0);
        let mut f0 = y0.clone();
        rhs(0.3, &y0, &mut f0).unwrap();
        step(&mut rhs, 0.3, &y0, &f0, h, 1e-6, 1e-9, y0.len()).unwrap()
    }

    /// `clone_from` into a step of the same size (storage reused) or another size gives the
    /// source's step: its fields and its dense output, bit for bit.
    #[test]
    fn a_step_copied_over_another_is_its_source() {
        let source = oscillator_step(&[1.0, -0.5, 2.0], 0.2);
        for target_y0 in [
            &[0.1, 0.2, 0.3][..],
            &[0.1, 0.2][..],
            &[0.1, 0.2, 0.3, 0.4][..],
        ] {
            let mut target = oscillator_step(target_y0, 0.05);
            target.clone_from(&source);
            assert_eq!((target.t0, target.h), (source.t0, source.h));
            assert_eq!((target.error, target.worst), (source.error, source.worst));
            assert_eq!(
                (&target.y0, &target.y1, &target.f1),
                (&source.y0, &source.y1, &source.f1)
            );
            for theta in [0.0, 0.25, 0.5, 0.9, 1.0] {
                let (mut a, mut b) = (source.y0.clone(), source.y0.clone());
                source.dense_into(theta, &mut a);
                target.dense_into(theta, &mut b);
                assert_eq!(a, b, "θ = {theta}");
            }
            assert_ne!(
                source.dense_component(0.5, 0),
                source.y0[0],
                "the dense output moves"
            );
        }
    }
}
