//! The unilateral contact law on every input: a closed contact never pulls, and its release is
//! located at its closed-form instant. A body on a spring and dashpot to a harmonically moving
//! support against a fixed stop with plastic impacts: each release leaves the body at the stop
//! at rest at a closed-form instant, and each flight from there has a closed form, so the event
//! sequence is an oracle cycle after cycle (Shaw & Holmes 1983; Wiercigroch 2000 for the
//! piecewise-linear impact oscillator).

mod common;

use deckspin::output::{EventKind, RunOutput, SampleKind};

/// m x'' + c (x' − u') + k (x − u) = 0, u = A sin(ω t + ψ), against a stop at x = d (g_N =
/// d − x) while open; at the stop at rest the stop's force is λ = k (u − d) + c u'.
#[derive(Clone, Copy)]
struct Oscillator {
    m: f64,
    k: f64,
    c: f64,
    a: f64,
    w: f64,
    psi: f64,
    d: f64,
}

impl Oscillator {
    fn u(&self, t: f64) -> (f64, f64) {
        let p = self.w * t + self.psi;
        (self.a * p.sin(), self.a * self.w * p.cos())
    }

    /// The stop's force on the body held at x = d at rest.
    fn force(&self, t: f64) -> f64 {
        let (u, ud) = self.u(t);
        self.k * (u - self.d) + self.c * ud
    }

    /// The particular solution P sin(ωt+ψ) + Q cos(ωt+ψ) of the free flight.
    fn particular(&self) -> (f64, f64) {
        let (kk, cw) = (self.k - self.m * self.w * self.w, self.c * self.w);
        // kk P − cw Q = k A; cw P + kk Q = c ω A
        let (fs, fc) = (self.k * self.a, self.c * self.w * self.a);
        let det = kk * kk + cw * cw;
        ((kk * fs + cw * fc) / det, (kk * fc - cw * fs) / det)
    }

    /// (x, x') at t of the free flight from (t0, x0, v0) (underdamped).
    fn flight(&self, (t0, x0, v0): (f64, f64, f64), t: f64) -> (f64, f64) {
        let (p, q) = self.particular();
        let xp = |t: f64| {
            let ph = self.w * t + self.psi;
            (
                p * ph.sin() + q * ph.cos(),
                self.w * (p * ph.cos() - q * ph.sin()),
            )
        };
        let alpha = self.c / (2.0 * self.m);
        let w0 = (self.k / self.m).sqrt();
        let wd = (w0 * w0 - alpha * alpha).sqrt();
        let (x_p0, v_p0) = xp(t0);
        let c1 = x0 - x_p0;
        let c2 = (v0 - v_p0 + alpha * c1) / wd;
        let tau = t - t0;
        let e = (-alpha * tau).exp();
        let (s, co) = (wd * tau).sin_cos();
        let (x_p, v_p) = xp(t);
        (
            x_p + e * (c1 * co + c2 * s),
            v_p + e * (-alpha * (c1 * co + c2 * s) + wd * (-c1 * s + c2 * co)),
        )
    }

    /// The first instant after `from.0` at which the flight from `from` reaches the stop,
    /// approaching (scan by `dt`, then bisection to rounding).
    fn impact_after(&self, from: (f64, f64, f64), t_end: f64) -> Option<f64> {
        let dt = 1e-4;
        let mut ta = from.0 + 1e-9;
        while ta < t_end {
            let tb = ta + dt;
            if self.flight(from, tb).0 >= self.d {
                let (mut lo, mut hi) = (ta, tb);
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    if self.flight(from, mid).0 >= self.d {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                return Some(hi);
            }
            ta = tb;
        }
        None
    }

    /// The first instant after `t` at which the held force λ(t) = R sin(ωt + ψ + φ) − k d
    /// crosses zero decreasing (closed form).
    fn release_after(&self, t: f64) -> f64 {
        let r = self.a * self.k.hypot(self.c * self.w);
        let phi = (self.c * self.w).atan2(self.k);
        let root = std::f64::consts::PI - (self.k * self.d / r).asin() - phi - self.psi;
        let period = std::f64::consts::TAU / self.w;
        let n = ((t - root / self.w) / period).floor() + 1.0;
        root / self.w + n * period
    }

    /// The closed-form events of a plastic stop from (t0, x0, v0) open, to `t_end`: (impact
    /// instant, speed) and release instants.
    fn schedule(&self, mut from: (f64, f64, f64), t_end: f64) -> (Vec<(f64, f64)>, Vec<f64>) {
        let (mut impacts, mut releases) = (Vec::new(), Vec::new());
        while let Some(ti) = self.impact_after(from, t_end) {
            impacts.push((ti, self.flight(from, ti).1));
            if self.force(ti) > 0.0 {
                let tr = self.release_after(ti);
                if tr >= t_end {
                    break;
                }
                releases.push(tr);
                from = (tr, self.d, 0.0);
            } else {
                from = (ti, self.d, 0.0);
            }
        }
        (impacts, releases)
    }

    fn scene(&self, t_end: f64, eps: f64, mu: f64, x0: f64) -> String {
        let dofs = if mu > 0.0 {
            r#"["x", "y"]"#
        } else {
            r#"["x"]"#
        };
        let y_spring = if mu > 0.0 {
            "[[spring]]\nname = \"lateral\"\nbody = \"mass\"\ndirection = [0.0, 1.0]\nstiffness = 10.0\nsupport = \"table\"\n"
        } else {
            ""
        };
        format!(
            r#"title = "forced oscillator against a stop"
[solver]
t_end = {t_end}
output_dt = 0.01
rtol = 1e-10
atol = 1e-12
[[support]]
name = "table"
kind = "harmonic"
amplitude = {a}
frequency = {f}
phase = {psi}
[[body]]
name = "mass"
mass = {m}
dofs = {dofs}
initial_displacement = [{x0}, 0.0, 0.0]
[[spring]]
name = "spring"
body = "mass"
direction = [1.0, 0.0]
stiffness = {k}
damping = {c}
support = "table"
{y_spring}
[[contact]]
name = "stop"
body = "mass"
normal = [-1.0, 0.0]
gap = {gap}
restitution = {eps}
mu = {mu}
"#,
            a = self.a,
            f = self.w / std::f64::consts::TAU,
            psi = self.psi,
            m = self.m,
            k = self.k,
            c = self.c,
            gap = self.d,
        )
    }
}

fn run(text: &str) -> RunOutput {
    common::run_text(text, "oscillator.toml").unwrap_or_else(|e| panic!("{e}"))
}

fn events(r: &RunOutput, kind: EventKind) -> Vec<(f64, f64)> {
    (r.events.iter())
        .filter(|e| e.kind == kind)
        .map(|e| (e.t, e.gap_rate_before))
        .collect()
}

/// No sample of a closed contact pulls: λ_N ≥ −1e-9 of the run's largest normal force (the
/// pre-event sample at a release is on λ_N = 0 to the event's accuracy).
#[track_caller]
fn assert_never_pulls(r: &RunOutput, what: &str) -> f64 {
    let scale = (r.samples.iter())
        .flat_map(|s| s.contacts.iter().map(|c| c.normal_force.abs()))
        .fold(0.0f64, f64::max)
        .max(1e-300);
    let mut worst = 0.0f64;
    for s in &r.samples {
        for (i, c) in s.contacts.iter().enumerate() {
            let pull = -c.normal_force / scale;
            assert!(
                pull <= 1e-9,
                "{what}: contact {i} pulls at t = {} ({:?}): λ_N = {:e} of {scale:e}",
                s.t,
                s.kind,
                c.normal_force
            );
            worst = worst.max(pull);
        }
    }
    worst
}

/// The run's impacts and releases against the closed-form schedule.
#[track_caller]
fn assert_schedule(osc: &Oscillator, r: &RunOutput, from: (f64, f64, f64), t_end: f64) {
    let (impacts, releases) = osc.schedule(from, t_end);
    let got_i = events(r, EventKind::Impact);
    let got_r: Vec<f64> = events(r, EventKind::Release).iter().map(|e| e.0).collect();
    assert!(
        releases.len() >= 10,
        "a test of few cycles: {}",
        releases.len()
    );
    assert_eq!(
        got_r.len(),
        releases.len(),
        "releases {got_r:?}\nexpected {releases:?}"
    );
    assert_eq!(
        got_i.len(),
        impacts.len(),
        "impacts {got_i:?}\nexpected {impacts:?}"
    );
    for (k, (got, want)) in got_r.iter().zip(&releases).enumerate() {
        assert!(
            (got - want).abs() <= 1e-9,
            "release {k}: {got} against {want}"
        );
    }
    for (k, ((t, v), (tw, vw))) in got_i.iter().zip(&impacts).enumerate() {
        assert!((t - tw).abs() <= 1e-8, "impact {k}: {t} against {tw}");
        // the gap rate before the impact is −ẋ
        assert!(
            (-v - vw).abs() <= 1e-8 * vw.abs(),
            "impact {k}: speed {} against {vw}",
            -v
        );
    }
}

fn oscillator() -> Oscillator {
    Oscillator {
        m: 1.0,
        k: 39.47841760435743,
        c: 0.5,
        a: 0.1,
        w: std::f64::consts::TAU,
        psi: 0.0,
        d: 0.02,
    }
}

#[test]
fn a_frictionless_plastic_stop_releases_at_the_closed_form_instant_every_cycle() {
    let osc = oscillator();
    let r = run(&osc.scene(20.0, 0.0, 0.0, 0.0));
    assert_schedule(&osc, &r, (0.0, 0.0, 0.0), 20.0);
    assert_never_pulls(&r, "μ = 0, ε = 0");
    assert!(
        r.summary.energy_closure_rel.abs() < 1e-6,
        "{}",
        r.summary.energy_closure_rel
    );
}

#[test]
fn a_frictional_plastic_stop_releases_at_the_same_instants() {
    // the body free in y too, held there by friction while pressed (it sticks: nothing drives y)
    let osc = oscillator();
    let r = run(&osc.scene(20.0, 0.0, 0.3, 0.0));
    assert_schedule(&osc, &r, (0.0, 0.0, 0.0), 20.0);
    assert_never_pulls(&r, "μ = 0.3, ε = 0");
}

#[test]
fn subharmonic_and_one_touch_orbits_follow_the_closed_form() {
    // a stiffer, lightly damped oscillator driven below resonance, the stop far out: flights of
    // several periods and impacts whose force is a pull at once (the body touches and leaves)
    let mut kinds = Vec::new();
    for (k, c, a, d) in [
        (200.0, 0.2, 0.1, 0.11),
        (20.0, 0.05, 0.1, 0.05),
        (39.5, 0.0, 0.08, 0.0),
    ] {
        let osc = Oscillator {
            k,
            c,
            a,
            d,
            ..oscillator()
        };
        let from = (0.0, d - 0.03, 0.0);
        let r = run(&osc.scene(30.0, 0.0, 0.0, from.1));
        let (impacts, releases) = osc.schedule(from, 30.0);
        let got_r: Vec<f64> = events(&r, EventKind::Release).iter().map(|e| e.0).collect();
        assert_eq!(
            got_r.len(),
            releases.len(),
            "k {k}: {got_r:?} against {releases:?}"
        );
        assert_eq!(events(&r, EventKind::Impact).len(), impacts.len(), "k {k}");
        for (got, want) in got_r.iter().zip(&releases) {
            assert!(
                (got - want).abs() <= 1e-8,
                "k {k}: release {got} against {want}"
            );
        }
        assert_never_pulls(&r, "subharmonic");
        kinds.push((impacts.len(), releases.len()));
    }
    // orbits of one-touch impacts only (the stop beyond the held force's reach, kd > R), of
    // both kinds, and held at every impact
    assert!(kinds.iter().all(|&(i, _)| i >= 10), "{kinds:?}");
    assert!(kinds.iter().any(|&(i, r)| i > 0 && r == 0), "{kinds:?}");
    assert!(kinds.iter().any(|&(i, r)| i > r && r > 0), "{kinds:?}");
    assert!(kinds.iter().any(|&(i, r)| i == r && r >= 10), "{kinds:?}");
}

#[test]
fn a_nearly_plastic_stop_releases_too() {
    // ε = 1e-4: each impact is followed by a short burst that the accumulation rule closes;
    // the contact then releases at the closed-form instant
    let osc = oscillator();
    let r = run(&osc.scene(20.0, 1e-4, 0.0, 0.0));
    let want: Vec<f64> = osc.schedule((0.0, 0.0, 0.0), 20.0).1;
    let got: Vec<f64> = events(&r, EventKind::Release).iter().map(|e| e.0).collect();
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(&want) {
        assert!((g - w).abs() <= 1e-6, "release {g} against {w}");
    }
    assert_never_pulls(&r, "ε = 1e-4");
}

#[test]
fn a_force_that_starts_at_zero_holds_while_it_grows_and_releases_when_it_falls() {
    // the body at rest on the stop (d = 0) and the support starting at its centre, c = 0:
    // λ = k A sin(ωt + ψ) starts at 0. Pushing (ψ = 0): held until T/2; pulling (ψ = π): free
    // at once, first at the stop again at the free response's closed-form instant.
    let base = Oscillator {
        c: 0.0,
        d: 0.0,
        w: 0.8 * std::f64::consts::TAU,
        ..oscillator()
    };
    let push = base;
    let r = run(&push.scene(2.0, 0.0, 0.0, 0.0));
    let rel = events(&r, EventKind::Release);
    assert!(!rel.is_empty(), "no release");
    let half = 0.5 / 0.8;
    assert!(
        (rel[0].0 - half).abs() <= 1e-9,
        "held until T/2: released at {}",
        rel[0].0
    );
    assert!(events(&r, EventKind::Impact).is_empty() || events(&r, EventKind::Impact)[0].0 > half);
    assert_never_pulls(&r, "pushing from zero");

    let pull = Oscillator {
        psi: std::f64::consts::PI,
        ..base
    };
    let r = run(&pull.scene(2.0, 0.0, 0.0, 0.0));
    let first = pull.impact_after((0.0, 0.0, 0.0), 2.0).expect("comes back");
    let imp = events(&r, EventKind::Impact);
    assert!(!imp.is_empty(), "never came back");
    assert!(
        (imp[0].0 - first).abs() <= 1e-8,
        "first impact {} against {first}",
        imp[0].0
    );
    assert_never_pulls(&r, "pulling from zero");
    // no sample before the first impact is closed
    for s in r
        .samples
        .iter()
        .filter(|s| s.t > 1e-9 && s.t < first - 1e-6)
    {
        assert!(s.contacts[0].gap > 0.0, "t = {}: {:?}", s.t, s.contacts[0]);
    }
}

/// The invariant on every validation scene and shipped model (default settings): no sample's
/// normal force pulls beyond 1e-9 of the run's largest.
#[test]
fn no_validation_scene_or_shipped_model_pulls() {
    let mut models: Vec<String> = Vec::new();
    for dir in ["models", "models/validation"] {
        let mut files: Vec<String> = std::fs::read_dir(common::model(dir))
            .unwrap()
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "toml"))
            .map(|p| format!("{dir}/{}", p.file_name().unwrap().to_string_lossy()))
            .collect();
        files.sort();
        models.extend(files);
    }
    let mut checked = 0;
    for m in &models {
        let scene = deckspin::load(&common::model(m), &[]).unwrap();
        for set in [&[][..], &["contacts.mu=0".to_string()][..]] {
            if !set.is_empty() && !scene.bridge {
                continue;
            }
            let scene = deckspin::load(&common::model(m), set).unwrap();
            // a failed run (painleve.toml) keeps its samples: they are checked too
            let out = deckspin::simulate::integrate(&scene, &mut deckspin::Silent).output;
            assert_never_pulls(&out, &format!("{m} {set:?}"));
            assert!(
                out.summary.max_pull <= 1e-9 * scale_of(&out),
                "{m}: summary"
            );
            checked += 1;
        }
    }
    assert!(checked >= 12, "{checked}");
}

fn scale_of(r: &RunOutput) -> f64 {
    (r.samples.iter())
        .flat_map(|s| s.contacts.iter().map(|c| c.normal_force.abs()))
        .fold(1e-300, f64::max)
}

#[test]
fn pre_event_samples_at_releases_sit_on_zero_force() {
    // the specimen without friction releases 38 times; each pre-event sample at a release is
    // on λ_N = 0 to 1e-9 of the force scale (the release is located on the re-stepped state)
    let r = common::run("models/four-span.toml", &["contacts.mu=0"]);
    let scale = scale_of(&r);
    let releases: Vec<(f64, usize)> = (r.events.iter())
        .filter(|e| e.kind == EventKind::Release)
        .map(|e| (e.t, e.contact))
        .collect();
    assert!(releases.len() > 10, "{}", releases.len());
    for (t, i) in releases {
        let pre = (r.samples.iter())
            .find(|s| s.kind == SampleKind::PreEvent && s.t == t)
            .expect("pre-event sample");
        let lam = pre.contacts[i].normal_force;
        assert!(
            lam.abs() <= 1e-9 * scale,
            "t = {t}: λ_N {lam:e} of {scale:e}"
        );
    }
}
