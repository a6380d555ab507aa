//! Event location on the dense output: sampling at θ = ¼, ½, ¾, 1, Illinois on the bracket,
//! coalescing of branch events within `branch_window`.

use super::engine::Engine;
use super::event_fn::EventFn;
use super::workspace::LocateScratch;
use crate::dopri;
use crate::hysteresis::Hysteretic;
use crate::run::SolverError;
use nalgebra::DVector;

/// First event in the step: sample the dense output at θ = ½, 1 (the gaps also at ¼, ¾ and
/// the output grid instants `grid` inside the step, so that no output sample shows a missed
/// crossing, and between samples by [`dip`]; the functions the step's ends show far from zero
/// only at 1), then Illinois on the bracketing interval down to
/// `event_time_tol`. Returns t_event, the bracket end where the
/// function has crossed, with the events to apply there in `eng.state.cluster` ([`coalesce`]).
/// Updates the armed flags.
pub(super) fn locate_event(
    eng: &mut Engine,
    step: &dopri::Step,
    fns: &[EventFn],
    armed: &mut [bool],
    grid: &[f64],
) -> Result<Option<f64>, SolverError> {
    if fns.is_empty() {
        return Ok(None);
    }
    let mut ls = std::mem::take(&mut eng.ws.locate);
    // sample instants: (θ, all functions or the gaps only)
    ls.thetas.clear();
    ls.thetas
        .extend([(0.25, false), (0.5, true), (0.75, false), (1.0, true)]);
    for &t in grid.iter().take(MAX_GRID_SAMPLES) {
        let theta = (t - step.t0) / step.h;
        if theta > 0.0 && theta < 1.0 && ls.thetas.iter().all(|(s, _)| (s - theta).abs() > 1e-9) {
            ls.thetas.push((theta, false));
        }
    }
    ls.thetas.sort_by(|a, b| a.0.total_cmp(&b.0));
    let r = locate_event_in(eng, step, fns, armed, &mut ls);
    eng.ws.locate = ls;
    r
}

/// Output instants of one step checked for gaps (more are left to the Hermite dip check).
const MAX_GRID_SAMPLES: usize = 16;

pub(super) fn locate_event_in(
    eng: &mut Engine,
    step: &dopri::Step,
    fns: &[EventFn],
    armed: &mut [bool],
    ls: &mut LocateScratch,
) -> Result<Option<f64>, SolverError> {
    relist(ls, eng, fns);
    eng.ws.probe.reset();
    let LocateScratch {
        thr,
        v_prev,
        t_prev,
        vals,
        v_end,
        r_prev,
        r_vals,
        r_end,
        y,
        roots,
        thetas,
        near,
        near_gaps,
        sub,
        ..
    } = ls;
    let shifted = |v: f64, k: usize, armed: &[bool]| if armed[k] { v } else { v + thr[k] };
    end_values(
        eng,
        step,
        fns,
        armed,
        (v_prev, r_prev, t_prev),
        (v_end, r_end),
    )?;
    // the functions the ends do not show far from zero at θ = ½ and 1; the gaps among them
    // (a corner may graze through in part of a step) also at ¼, ¾ and the output instants
    near_functions(
        eng,
        (step, fns, armed),
        (v_prev, r_prev),
        (v_end, r_end),
        near,
    );
    near_gaps.clear();
    near_gaps.extend(near.iter().filter(|&&k| matches!(fns[k], EventFn::Gap(_))));
    if y.len() != step.y0.len() {
        *y = DVector::zeros(step.y0.len());
    }
    for &(theta, full) in thetas.iter() {
        let list: &[usize] = if full { near } else { near_gaps };
        if list.is_empty() {
            continue;
        }
        let t = step.t0 + theta * step.h;
        if theta == 1.0 {
            vals.clear();
            vals.extend(list.iter().map(|&k| v_end[k]));
            r_vals.clear();
            r_vals.extend(list.iter().map(|&k| r_end[k]));
        } else {
            sample_values(eng, step, (fns, list), t, (y, sub), (vals, r_vals))?;
        }
        roots.clear();
        for (m, &k) in list.iter().enumerate() {
            let a = shifted(v_prev[k], k, armed);
            let b = shifted(vals[m], k, armed);
            if a > 0.0 && b <= 0.0 {
                let root = illinois(eng, step, fns, k, t_prev[k], t, a, b, armed[k], thr[k])?;
                roots.push((root, fns[k]));
            } else if a > 0.0
                && watched_between(fns[k], armed[k])
                && !stays_above(t - t_prev[k], (a, r_prev[k]), (b, r_vals[m]))
            {
                // both ends open: a corner may still have dipped through the face between (an
                // element through a branch bound and back)
                let ends = ((t_prev[k], a, r_prev[k]), (t, b, r_vals[m]));
                let shift = if armed[k] { 0.0 } else { thr[k] };
                if let Some((tc, gc)) = dip(eng, step, fns[k], shift, ends, 8)? {
                    let root = illinois(eng, step, fns, k, t_prev[k], tc, a, gc, armed[k], thr[k])?;
                    roots.push((root, fns[k]));
                }
            }
        }
        if !full && !roots.is_empty() {
            roots_of_the_others(eng, step, fns, armed, (thr, v_prev, t_prev), (t, y), roots)?;
        }
        if !roots.is_empty() {
            roots.sort_by(|a, b| a.0.total_cmp(&b.0));
            // a shear key failing drops its force: applied at its own instant, never later
            let window = match roots[0].1 {
                EventFn::Upper(j) if key_fails(&eng.state.laws[j]) => 0.0,
                _ => eng.scene.settings.branch_window,
            };
            return Ok(Some(coalesce(roots, window, &mut eng.state.cluster)));
        }
        for (m, &k) in list.iter().enumerate() {
            if !armed[k] && vals[m] > thr[k] {
                armed[k] = true;
            }
            v_prev[k] = vals[m];
            r_prev[k] = r_vals[m];
            t_prev[k] = t;
        }
    }
    // the step's end values of every function (the far ones were not sampled inside)
    std::mem::swap(v_prev, v_end);
    std::mem::swap(r_prev, r_end);
    let last = (step.t1(), std::mem::take(v_prev), std::mem::take(r_prev));
    eng.state.last_event_values = Some(last);
    Ok(None)
}

/// The thresholds of `fns`, made anew when the list of functions changed.
fn relist(ls: &mut LocateScratch, eng: &Engine, fns: &[EventFn]) {
    if ls.listed == eng.state.fns_generation && ls.thr.len() == fns.len() {
        return;
    }
    ls.listed = eng.state.fns_generation;
    ls.thr.clear();
    ls.thr.extend(fns.iter().map(|f| eng.threshold(*f)));
}

/// Values and rates at `t` on the step's dense output of the functions `fns[k]`, k in `list`:
/// each from the bodies it reads, or all from the dynamics there if one needs them.
fn sample_values(
    eng: &mut Engine,
    step: &dopri::Step,
    (fns, list): (&[EventFn], &[usize]),
    t: f64,
    (y, sub): (&mut DVector<f64>, &mut Vec<EventFn>),
    (vals, rates): (&mut Vec<f64>, &mut Vec<f64>),
) -> Result<(), SolverError> {
    vals.clear();
    rates.clear();
    if list.iter().any(|&k| !fns[k].probed()) {
        sub.clear();
        sub.extend(list.iter().map(|&k| fns[k]));
        step.dense_at_into(t, y);
        eng.event_values_into(t, y, sub, vals)?;
        rates.clone_from(&eng.ws.gap_rates);
    } else {
        for &k in list {
            let (v, r) = value(eng, step, fns[k], t)?;
            vals.push(v);
            rates.push(r);
        }
    }
    Ok(())
}

/// The functions that need a sample inside the step, into `near`: those its ends do not show
/// far from zero (armed, the rate known at both ends, the Hermite bound with three times the
/// rates' terms; a load reversal's rate d·ë where the dynamics were evaluated).
fn near_functions(
    eng: &Engine,
    (step, fns, armed): (&dopri::Step, &[EventFn], &[bool]),
    (v_prev, r_prev): (&[f64], &[f64]),
    (v_end, r_end): (&[f64], &mut [f64]),
    near: &mut Vec<usize>,
) {
    if fns.iter().any(|f| matches!(f, EventFn::Reversal(_))) {
        // at the step's end (at its start from the previous step's end, or the arming)
        eng.reversal_rates_into(step.t1(), &step.y1, fns, r_end);
    }
    let dt = 3.0 * step.h;
    near.clear();
    let ends = (v_prev.iter().zip(r_prev.iter())).zip(v_end.iter().zip(r_end.iter()));
    for (k, (&armed, ((&ga, &ra), (&gb, &rb)))) in armed.iter().zip(ends).enumerate() {
        if !(armed && stays_above(dt, (ga, ra), (gb, rb))) {
            near.push(k);
        }
    }
}

/// The values (and rates) of the functions at both ends of the step: the end first (the last
/// stage evaluated the dynamics there, FSAL, which any other evaluation would overwrite), the
/// start from the previous step's end when it is this step's start.
fn end_values(
    eng: &mut Engine,
    step: &dopri::Step,
    fns: &[EventFn],
    armed: &[bool],
    (v_prev, r_prev, t_prev): (&mut Vec<f64>, &mut Vec<f64>, &mut Vec<f64>),
    (v_end, r_end): (&mut Vec<f64>, &mut Vec<f64>),
) -> Result<(), SolverError> {
    eng.event_values_into(step.t1(), &step.y1, fns, v_end)?;
    r_end.clone_from(&eng.ws.gap_rates);
    match eng.state.last_event_values.take() {
        Some((t, v, r)) if t == step.t0 && v.len() == fns.len() => (*v_prev, *r_prev) = (v, r),
        _ => {
            eng.event_values_into(step.t0, &step.y0, fns, v_prev)?;
            r_prev.clone_from(&eng.ws.gap_rates);
        }
    };
    t_prev.clear();
    t_prev.resize(fns.len(), step.t0);
    for (k, v) in v_prev.iter_mut().enumerate() {
        if armed[k] && *v <= 0.0 {
            // positive just after t0 by construction
            *v = f64::MIN_POSITIVE;
        }
    }
    Ok(())
}

/// A gap's crossing found at an instant `t` where only the gaps are sampled (θ = ¼, ¾, an
/// output instant) ends the search there: the other functions are evaluated at (t, `y`) too and
/// their crossings in [t_prev, t] join `roots`, so that a branch end before the gap's root is
/// applied at its own instant, not after the impact.
fn roots_of_the_others(
    eng: &mut Engine,
    step: &dopri::Step,
    fns: &[EventFn],
    armed: &[bool],
    (thr, v_prev, t_prev): (&[f64], &[f64], &[f64]),
    (t, y): (f64, &mut DVector<f64>),
    roots: &mut Vec<(f64, EventFn)>,
) -> Result<(), SolverError> {
    step.dense_at_into(t, y);
    let vals = eng.event_values(t, y, fns)?;
    for (k, &val) in vals.iter().enumerate() {
        if matches!(fns[k], EventFn::Gap(_)) {
            continue;
        }
        let shifted = |v: f64| if armed[k] { v } else { v + thr[k] };
        let (a, b) = (shifted(v_prev[k]), shifted(val));
        if a > 0.0 && b <= 0.0 {
            let root = illinois(eng, step, fns, k, t_prev[k], t, a, b, armed[k], thr[k])?;
            roots.push((root, fns[k]));
        }
    }
    Ok(())
}

/// A gap g that is positive at both ends of [ta, tb] may have dipped below zero in between
/// (approaching at ta and opening at tb, or just released with a small opening rate and
/// pulled back by the contact next to it); so may a branch bound's e − lower or upper − e (an
/// element through the kink of its law and back). The cubic Hermite interpolant of
/// (g, ġ) at the ends predicts the minimum; where it predicts g ≤ 0 the gap is evaluated there
/// on the dense output, and the two halves are searched again (to `depth` levels) while it is
/// still positive. g is the function plus `shift` (its threshold while unarmed). Returns
/// (t, g(t)) with g(t) ≤ 0: the far end of a bracket [ta, t] of the crossing.
fn dip(
    eng: &mut Engine,
    step: &dopri::Step,
    f: EventFn,
    shift: f64,
    ((ta, ga, ra), (tb, gb, rb)): ((f64, f64, f64), (f64, f64, f64)),
    depth: u32,
) -> Result<Option<(f64, f64)>, SolverError> {
    if !(ra.is_finite() && rb.is_finite() && tb > ta) {
        return Ok(None);
    }
    let (da, db) = (ra * (tb - ta), rb * (tb - ta));
    if hermite_stays_above(ga, da, gb, db) {
        return Ok(None);
    }
    let Some((s, p)) = hermite_min(ga, da, gb, db) else {
        return Ok(None);
    };
    if p > 0.0 {
        return Ok(None);
    }
    let tm = ta + s * (tb - ta);
    let (gm, rm) = value(eng, step, f, tm)?;
    let gm = gm + shift;
    if gm <= 0.0 {
        return Ok(Some((tm, gm)));
    }
    if depth == 0 {
        return Ok(None);
    }
    if let Some(hit) = dip(eng, step, f, shift, ((ta, ga, ra), (tm, gm, rm)), depth - 1)? {
        return Ok(Some(hit));
    }
    dip(eng, step, f, shift, ((tm, gm, rm), (tb, gb, rb)), depth - 1)
}

/// [`hermite_stays_above`] for values and rates (`ga`, `ra`), (`gb`, `rb`) a time `dt`
/// apart: false when a rate is not finite (then [`dip`] decides).
#[inline]
fn stays_above(dt: f64, (ga, ra): (f64, f64), (gb, rb): (f64, f64)) -> bool {
    hermite_stays_above(ga, ra * dt, gb, rb * dt)
}

/// The cubic Hermite interpolant of [`hermite_min`] is positive on [0, 1] by a bound alone:
/// p = h₀₀g₀ + h₀₁g₁ + h₁₀d₀ + h₁₁d₁ with h₀₀ + h₀₁ = 1, h₀₀, h₀₁ ≥ 0 and |h₁₀|, |h₁₁| ≤ 4/27,
/// so p ≥ min(g₀, g₁) − 4/27 (|d₀| + |d₁|). The bound has a margin of 1 % against rounding.
#[inline]
pub(super) fn hermite_stays_above(g0: f64, d0: f64, g1: f64, d1: f64) -> bool {
    g0.min(g1) > 0.15 * (d0.abs() + d1.abs())
}

/// Minimum over s ∈ (0, 1) of the cubic Hermite interpolant with values `g0`, `g1` and
/// slopes `d0`, `d1` (per unit s) at the ends: (s, p(s)), or None without an interior minimum.
pub(super) fn hermite_min(g0: f64, d0: f64, g1: f64, d1: f64) -> Option<(f64, f64)> {
    let p = |s: f64| {
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * g0
            + (s3 - 2.0 * s2 + s) * d0
            + (-2.0 * s3 + 3.0 * s2) * g1
            + (s3 - s2) * d1
    };
    // p'(s) = a s² + b s + c
    let a = 6.0 * g0 + 3.0 * d0 - 6.0 * g1 + 3.0 * d1;
    let b = -6.0 * g0 - 4.0 * d0 + 6.0 * g1 - 2.0 * d1;
    let c = d0;
    let mut cands = [f64::NAN; 2];
    if a.abs() <= 1e-14 * (b.abs() + c.abs()) {
        cands[0] = -c / b;
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            let q = -0.5 * (b + b.signum() * disc.sqrt());
            cands = [q / a, c / q];
        }
    }
    cands
        .into_iter()
        .filter(|s| s.is_finite() && *s > 0.0 && *s < 1.0)
        .map(|s| (s, p(s)))
        .min_by(|x, y| x.1.total_cmp(&y.1))
}

/// Functions that [`dip`] looks at between two positive values: an armed gap (ġ_N), a branch
/// bound armed or at its bound (±ė; watched for v ≤ −ε, [`super::events::arm`]).
fn watched_between(f: EventFn, armed: bool) -> bool {
    match f {
        EventFn::Gap(_) => armed,
        EventFn::Lower(_) | EventFn::Upper(_) => true,
        _ => false,
    }
}

/// The upper end of this law's branch is a shear key's failure point (rule G5).
fn key_fails(law: &Hysteretic) -> bool {
    law.fails_at(law.branch().upper, 1.0)
}

/// The events applied at once from the roots found in one sub-interval (sorted by time):
/// the first, and the branch events of other elements that follow it by at most `window` with
/// no contact event between (all at the time of the last of them, so that each element's
/// branch end has been reached when it changes branch). Returns that time; the events go into
/// `cluster`.
pub(super) fn coalesce(roots: &[(f64, EventFn)], window: f64, cluster: &mut Vec<EventFn>) -> f64 {
    let element = |f: EventFn| match f {
        EventFn::Lower(j) | EventFn::Upper(j) | EventFn::Reversal(j) => Some(j),
        _ => None,
    };
    cluster.clear();
    let (t0, f0) = roots[0];
    cluster.push(f0);
    let mut t = t0;
    if element(f0).is_none() || window <= 0.0 {
        return t;
    }
    for &(tr, f) in &roots[1..] {
        let Some(j) = element(f) else { break };
        if tr - t0 > window {
            break;
        }
        if cluster.iter().any(|&g| element(g) == Some(j)) {
            continue;
        }
        cluster.push(f);
        t = tr;
    }
    t
}

#[allow(clippy::too_many_arguments)]
pub(super) fn illinois(
    eng: &mut Engine,
    step: &dopri::Step,
    fns: &[EventFn],
    k: usize,
    ta: f64,
    tb: f64,
    fa: f64,
    fb: f64,
    armed: bool,
    thr: f64,
) -> Result<f64, SolverError> {
    let st = &eng.scene.settings;
    // a branch change applied up to `branch_window` late needs its instant no closer than
    // min(1 %, 100 rtol) of that (a key's failure, applied at its own instant, to
    // `event_time_tol`)
    let tol = match fns[k] {
        EventFn::Upper(j) if key_fails(&eng.state.laws[j]) => st.event_time_tol,
        EventFn::Lower(_) | EventFn::Upper(_) | EventFn::Reversal(_) => st
            .event_time_tol
            .max((1e2 * st.rtol).min(1e-2) * st.branch_window),
        _ => st.event_time_tol,
    };
    let r = bracket_root(ta, tb, fa, fb, tol, |tm| {
        let mut fm = value(eng, step, fns[k], tm)?.0;
        if !armed {
            fm += thr;
        }
        Ok(fm)
    });
    Ok(r?.1)
}

/// (value, rate) of one event function on the dense output at `t`: from the bodies it reads
/// ([`Engine::probe`]), else from the dynamics there, without allocation.
fn value(
    eng: &mut Engine,
    step: &dopri::Step,
    f: EventFn,
    t: f64,
) -> Result<(f64, f64), SolverError> {
    if let Some(v) = eng.probe(step, f, t) {
        return Ok(v);
    }
    let mut y = std::mem::take(&mut eng.ws.dense_y);
    if y.len() != step.y0.len() {
        y = step.y0.clone();
    }
    step.dense_at_into(t, &mut y);
    let mut v = std::mem::take(&mut eng.ws.one_value);
    let r = eng.event_values_into(t, &y, &[f], &mut v);
    eng.ws.dense_y = y;
    let val = v.first().copied();
    eng.ws.one_value = v;
    r?;
    Ok((val.unwrap_or(f64::NAN), eng.ws.gap_rates[0]))
}

/// Illinois (modified regula falsi) on [a, b] with f(a) = fa > 0 ≥ fb = f(b), until the
/// bracket is narrower than `tol` (or 4 ulp of b): the final bracket, b on the far side.
pub(super) fn bracket_root<E>(
    mut a: f64,
    mut b: f64,
    mut fa: f64,
    mut fb: f64,
    tol: f64,
    mut f: impl FnMut(f64) -> Result<f64, E>,
) -> Result<(f64, f64), E> {
    let mut side = 0i32;
    for _ in 0..200 {
        if b - a <= tol.max(4.0 * f64::EPSILON * b.abs()) {
            break;
        }
        let mut m = (a * fb - b * fa) / (fb - fa);
        if !(m > a && m < b) {
            m = 0.5 * (a + b);
        }
        let fm = f(m)?;
        if fm > 0.0 {
            a = m;
            fa = fm;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = m;
            fb = fm;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
        if fm == 0.0 {
            break;
        }
    }
    Ok((a, b))
}

#[cfg(test)]
mod tests {
    use super::hermite_min;

    #[test]
    fn hermite_minimum_of_a_parabola_is_exact() {
        // g(s) = (s − 0.3)² − 0.01 on [0, 1]: g(0) = 0.08, g'(0) = −0.6, g(1) = 0.48, g'(1) = 1.4
        let (s, p) = hermite_min(0.08, -0.6, 0.48, 1.4).unwrap();
        assert!(
            (s - 0.3).abs() < 1e-15 && (p + 0.01).abs() < 1e-15,
            "{s} {p}"
        );
        // monotone: no interior minimum
        assert_eq!(hermite_min(0.1, 0.2, 0.5, 0.3), None);
        // a cubic is reproduced: g(s) = s³ − s² + 0.1 (minimum at s = 2/3)
        let (s, p) = hermite_min(0.1, 0.0, 0.1, 1.0).unwrap();
        assert!((s - 2.0 / 3.0).abs() < 1e-15 && (p - (0.1 - 4.0 / 27.0)).abs() < 1e-15);
    }

    #[test]
    fn the_bound_never_hides_a_minimum_below_zero() {
        use super::hermite_stays_above;
        // the bound is reached: s³ − 2s² + s has its maximum 4/27 at s = 1/3
        let (g, d) = (4.0 / 27.0, -1.0);
        assert!(hermite_min(g, d, g, 0.0).unwrap().1.abs() < 1e-15);
        assert!(!hermite_stays_above(g, d, g, 0.0));
        // a grid of ends: wherever the bound says "positive", the minimum is positive
        let vals = [-1.0, -0.3, -0.05, 0.0, 0.02, 0.1, 0.4, 1.0, 3.0];
        let mut skipped = 0;
        for &g0 in &vals[3..] {
            for &g1 in &vals[3..] {
                for &d0 in &vals {
                    for &d1 in &vals {
                        if hermite_stays_above(g0, d0, g1, d1) {
                            skipped += 1;
                            let m = hermite_min(g0, d0, g1, d1).map_or(g0.min(g1), |x| x.1);
                            assert!(m > 0.0, "{g0} {d0} {g1} {d1}: {m}");
                        }
                    }
                }
            }
        }
        assert!(skipped > 100, "{skipped}");
    }
}
