//! Fragility fits against independent truths: synthetic suites drawn from a known lognormal
//! recover θ and β within three standard errors of the Fisher information; small cases whose
//! maximum has a closed form; degenerate suites give typed errors, not panics or hangs.

use deckspin::design::fragility::{self, Method, Options, Outcome};
use deckspin::design::mle::{
    Capacity, Count, FitError, fit_ida, fit_stripes, ida_log_likelihood, stripes_log_likelihood,
};
use deckspin::design::{FragilityError, Suite, SuiteError};
use deckspin::model::limit_state::LimitState;
use std::path::Path;

const RESPONSES: &str = "peak_rotation,residual_rotation,peak_x,peak_y,min_seat_margin,\
key_failures,max_drift_ratio,impacts,energy_impacts,energy_friction,energy_columns";

/// A suite CSV: header (with swept `params`) and rows.
fn suite_text(params: &[&str], rows: &[String]) -> String {
    let mut s = String::from("pair,longitudinal,transverse,measure,level,scale,");
    for p in params {
        s += p;
        s += ",";
    }
    s += "status,";
    s += RESPONSES;
    s += "\n";
    for r in rows {
        s += r;
        s += "\n";
    }
    s
}

/// A row: `params` values, `status`, the peak rotation (empty: None) and no seats.
fn row(pair: &str, level: f64, params: &[&str], status: &str, rotation: Option<f64>) -> String {
    let mut s = format!(
        "{pair},{pair}-L.AT2,{pair}-T.AT2,pga,{level},{},",
        level / 0.4
    );
    for p in params {
        s += p;
        s += ",";
    }
    let rot = rotation.map_or(String::new(), |r| r.to_string());
    if status == "finished" {
        s += &format!("finished,{rot},1e-4,0.01,0.02,,0,0.01,3,1.5,0.2,4.0");
    } else {
        s += &format!("\"{status}\",,,,,,,,,,,");
    }
    s
}

fn suite(params: &[&str], rows: &[String]) -> Suite {
    Suite::parse(&suite_text(params, rows), Path::new("suite.csv")).unwrap()
}

fn limit() -> LimitState {
    LimitState::parse("peak_rotation>0.01").unwrap()
}

fn opts(method: Method, bootstrap: usize) -> Options {
    Options {
        method,
        bootstrap,
        seed: 7,
    }
}

/// Independent of the library: xorshift64* uniforms, Box–Muller normals.
struct Rng(u64);
impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        ((x >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

/// Φ by Abramowitz & Stegun 26.2.17 (|error| < 7.5e-8), φ.
fn phi_cdf(z: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.231_641_9 * z.abs());
    let poly = t
        * (0.319_381_530
            + t * (-0.356_563_782
                + t * (1.781_477_937 + t * (-1.821_255_978 + t * 1.330_274_429))));
    let q = phi_pdf(z) * poly;
    if z >= 0.0 { 1.0 - q } else { q }
}
fn phi_pdf(z: f64) -> f64 {
    (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt()
}

/// 2×2 inverse.
fn inv(m: [[f64; 2]; 2]) -> [[f64; 2]; 2] {
    let d = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    [[m[1][1] / d, -m[0][1] / d], [-m[1][0] / d, m[0][0] / d]]
}

/// Standard errors of (ln θ̂, β̂) for stripes of `n` runs at `levels`: the probit Fisher
/// information in η = a + b ln x, wⱼ = nⱼφ(ηⱼ)²/(pⱼ(1 − pⱼ)), mapped by the delta method
/// (ln θ = −a/b, β = 1/b).
fn stripes_se(levels: &[f64], n: f64, theta: f64, beta: f64) -> (f64, f64) {
    let (a, b) = (-theta.ln() / beta, 1.0 / beta);
    let mut info = [[0.0; 2]; 2];
    for &x in levels {
        let u = x.ln();
        let eta = a + b * u;
        let p = phi_cdf(eta);
        let w = n * phi_pdf(eta).powi(2) / (p * (1.0 - p));
        let v = [1.0, u];
        for i in 0..2 {
            for j in 0..2 {
                info[i][j] += w * v[i] * v[j];
            }
        }
    }
    let c = inv(info);
    let jac = [[-1.0 / b, a / (b * b)], [0.0, -1.0 / (b * b)]];
    let var = |r: usize| {
        (0..2)
            .map(|i| (0..2).map(|j| jac[r][i] * c[i][j] * jac[r][j]).sum::<f64>())
            .sum::<f64>()
    };
    (var(0).sqrt(), var(1).sqrt())
}

/// A multiple-stripe suite: at each of 10 levels, `n` runs of their own records, each
/// exceeding when its capacity θ·exp(β ε) lies below the level.
fn synthetic_stripes(n: usize, theta: f64, beta: f64, seed: u64) -> (Suite, Vec<f64>) {
    let levels: Vec<f64> = (1..=10).map(|k| 0.1 * k as f64).collect();
    let mut rng = Rng(seed);
    let mut rows = Vec::new();
    for &x in &levels {
        for r in 0..n {
            let c = theta * (beta * rng.normal()).exp();
            let rot = if c < x { 0.02 } else { 0.005 };
            rows.push(row(&format!("p{x:.1}-{r}"), x, &[], "finished", Some(rot)));
        }
    }
    (suite(&[], &rows), levels)
}

#[test]
fn stripes_recover_a_known_lognormal_within_three_standard_errors() {
    let (theta, beta, n) = (0.5, 0.4, 100);
    let (s, levels) = synthetic_stripes(n, theta, beta, 0x5EED);
    let f = fragility::fragility(&s, &[], &limit(), &opts(Method::Stripes, 0)).unwrap();
    let (se_t, se_b) = stripes_se(&levels, n as f64, theta, beta);
    // the test can fail: the errors are a few percent
    assert!(se_t < 0.05 && se_b < 0.05, "{se_t} {se_b}");
    let (dt, db) = ((f.fit.theta / theta).ln(), f.fit.beta - beta);
    assert!(dt.abs() < 3.0 * se_t, "ln θ̂ − ln θ = {dt}, SE {se_t}");
    assert!(db.abs() < 3.0 * se_b, "β̂ − β = {db}, SE {se_b}");
    assert_eq!(f.records, 10 * n);
    assert_eq!(f.levels.len(), 10);
    assert!(f.levels.iter().all(|l| l.runs == n && l.failed == 0));
}

#[test]
fn the_bootstrap_band_matches_the_fisher_standard_error_and_is_reproducible() {
    let (theta, beta, n) = (0.5, 0.4, 100);
    let (s, levels) = synthetic_stripes(n, theta, beta, 0xB007);
    let o = opts(Method::Stripes, 400);
    let f = fragility::fragility(&s, &[], &limit(), &o).unwrap();
    let band = f.band.clone().unwrap();
    assert_eq!((band.replicates, band.fitted, band.seed), (400, 400, 7));
    let (se_t, se_b) = stripes_se(&levels, n as f64, theta, beta);
    // 5–95 % of a normal estimate: 2 × 1.645 standard errors
    let w_t = (band.theta[1] / band.theta[0]).ln() / (2.0 * 1.645 * se_t);
    let w_b = (band.beta[1] - band.beta[0]) / (2.0 * 1.645 * se_b);
    assert!((0.75..1.3).contains(&w_t), "θ band / Fisher = {w_t}");
    assert!((0.75..1.3).contains(&w_b), "β band / Fisher = {w_b}");
    assert!(band.theta[0] < f.fit.theta && f.fit.theta < band.theta[1]);
    assert!(band.at_theta[0] < 0.5 && 0.5 < band.at_theta[1]);
    // every curve point inside its band, the band ordered
    for p in &f.curve[1..] {
        let (lo, hi) = (p.lo.unwrap(), p.hi.unwrap());
        assert!(lo <= hi && lo <= p.p + 0.02 && p.p <= hi + 0.02, "{p:?}");
    }
    assert_eq!(f.curve.len(), fragility::CURVE_POINTS);
    assert_eq!((f.curve[0].x, f.curve[0].p), (0.0, 0.0));
    // the same seed: the same band; another: another
    let again = fragility::fragility(&s, &[], &limit(), &o).unwrap();
    assert_eq!(again, f);
    let other = fragility::fragility(&s, &[], &limit(), &Options { seed: 8, ..o }).unwrap();
    assert_eq!(other.fit, f.fit);
    assert_ne!(other.band, f.band);
}

/// Expected information of a normal sample right-censored at standardised ζ, per observation,
/// times σ², in (μ, σ): [Φ + φ(h − ζ), −φ + φζ(h − ζ); ·, 2Φ − ζφ + φζ²(h − ζ)],
/// h = φ/(1 − Φ) (from E[z·1{z<ζ}] = −φ, E[z²·1{z<ζ}] = Φ − ζφ and the censored term).
fn censored_info(zeta: f64) -> [[f64; 2]; 2] {
    let (p, d) = (phi_cdf(zeta), phi_pdf(zeta));
    let h = d / (1.0 - p);
    let k = h - zeta;
    let off = -d + d * zeta * k;
    [
        [p + d * k, off],
        [off, 2.0 * p - zeta * d + d * zeta * zeta * k],
    ]
}

#[test]
fn ida_recovers_a_known_lognormal_with_censoring_within_three_standard_errors() {
    let (theta, beta, n, top) = (0.5, 0.4, 400, 0.8);
    let mut rng = Rng(0x1DA);
    let mut rows = Vec::new();
    let mut censored = 0;
    for r in 0..n {
        let c = theta * (beta * rng.normal()).exp();
        let pair = format!("rec{r}");
        if c <= top {
            rows.push(row(&pair, 0.7 * c, &[], "finished", Some(0.004)));
            rows.push(row(&pair, c, &[], "finished", Some(0.02)));
        } else {
            censored += 1;
            rows.push(row(&pair, 0.5 * top, &[], "finished", Some(0.003)));
            rows.push(row(&pair, top, &[], "finished", Some(0.006)));
        }
    }
    let s = suite(&[], &rows);
    let f = fragility::fragility(&s, &[], &limit(), &opts(Method::Ida, 0)).unwrap();
    // ζ = ln(0.8/0.5)/0.4 = 1.175: about 12 % censored
    assert!((30..=70).contains(&censored), "{censored}");
    let zeta = (top / theta).ln() / beta;
    let c = inv(censored_info(zeta));
    let (se_mu, se_sigma) = (
        beta * (c[0][0] / n as f64).sqrt(),
        beta * (c[1][1] / n as f64).sqrt(),
    );
    assert!(se_mu < 0.03 && se_sigma < 0.03, "{se_mu} {se_sigma}");
    let (dt, db) = ((f.fit.theta / theta).ln(), f.fit.beta - beta);
    assert!(dt.abs() < 3.0 * se_mu, "ln θ̂ − ln θ = {dt}, SE {se_mu}");
    assert!(db.abs() < 3.0 * se_sigma, "β̂ − β = {db}, SE {se_sigma}");
    // a maximum: every nearby point is lower
    let caps = fragility::capacities(&fragility::records(&s, &[], &limit()).unwrap());
    assert_eq!(caps.iter().filter(|c| c.censored).count(), censored);
    let best = ida_log_likelihood(&caps, f.fit.theta, f.fit.beta);
    assert!((best - f.fit.log_likelihood).abs() < 1e-9);
    for (dt, db) in [(1e-3, 0.0), (-1e-3, 0.0), (0.0, 1e-3), (0.0, -1e-3)] {
        let l = ida_log_likelihood(&caps, f.fit.theta * (1.0 + dt), f.fit.beta + db);
        assert!(l < best, "({dt}, {db}): {l} ≥ {best}");
    }
}

#[test]
fn two_stripes_fit_exactly_the_observed_fractions() {
    // 1 of 4 at 0.2 g, 3 of 4 at 0.4 g: Φ((ln 0.2 − ln θ)/β) = 1/4, Φ((ln 0.4 − ln θ)/β) = 3/4,
    // so ln θ = (ln 0.2 + ln 0.4)/2 and β = ln 2/(2 z₀), z₀ = Φ⁻¹(3/4)
    let z0 = 0.674_489_750_196_081_7;
    let counts = [
        Count {
            level: 0.2,
            runs: 4,
            exceed: 1,
        },
        Count {
            level: 0.4,
            runs: 4,
            exceed: 3,
        },
    ];
    let f = fit_stripes(&counts).unwrap();
    assert!((f.theta - 0.08f64.sqrt()).abs() < 1e-9, "{}", f.theta);
    assert!((f.beta - 2f64.ln() / (2.0 * z0)).abs() < 1e-9, "{}", f.beta);
    // ℓ at the maximum: 2 ln ¼ + 6 ln ¾
    let want = 2.0 * 0.25f64.ln() + 6.0 * 0.75f64.ln();
    assert!((f.log_likelihood - want).abs() < 1e-9);
    // at θ = 0.4, β = ln 2/z₀: p = ¼ at 0.2 g and ½ at 0.4 g
    let l = stripes_log_likelihood(&counts, 0.4, 2f64.ln() / z0);
    let want = 0.25f64.ln() + 3.0 * 0.75f64.ln() + 4.0 * 0.5f64.ln();
    assert!((l - want).abs() < 1e-12, "{l} vs {want}");
}

#[test]
fn ida_without_censoring_is_the_mean_and_std_of_log_capacities() {
    // capacities 0.2, 0.4, 0.4, 0.8 g: ln θ = ln 0.4, β = √((ln²2 + ln²2)/4) = ln 2/√2,
    // through the suite: each pair run up the ladder 0.2, 0.4, 0.8 until it exceeds
    let ladder = [0.2, 0.4, 0.8];
    let caps = [0.2, 0.4, 0.4, 0.8];
    let mut rows = Vec::new();
    for (r, &c) in caps.iter().enumerate() {
        for &x in ladder.iter().filter(|&&x| x <= c) {
            let rot = if x >= c { 0.03 } else { 0.001 };
            rows.push(row(&format!("r{r}"), x, &[], "finished", Some(rot)));
        }
    }
    let s = suite(&[], &rows);
    let f = fragility::fragility(&s, &[], &limit(), &opts(Method::Ida, 0)).unwrap();
    assert!((f.fit.theta - 0.4).abs() < 1e-9, "{}", f.fit.theta);
    assert!(
        (f.fit.beta - 2f64.ln() / 2f64.sqrt()).abs() < 1e-9,
        "{}",
        f.fit.beta
    );
    // and the same directly, with a fifth capacity: mean and population std of the logs
    let c5 = [0.2, 0.4, 0.4, 0.8, 0.3];
    let logs: Vec<f64> = c5.iter().map(|c: &f64| c.ln()).collect();
    let m = logs.iter().sum::<f64>() / 5.0;
    let sd = (logs.iter().map(|l| (l - m).powi(2)).sum::<f64>() / 5.0).sqrt();
    let fit = fit_ida(&c5.map(|level| Capacity {
        level,
        censored: false,
    }))
    .unwrap();
    assert!((fit.theta - m.exp()).abs() < 1e-9 && (fit.beta - sd).abs() < 1e-9);
}

#[test]
fn failed_refused_and_not_applicable_runs_are_counted_and_left_out() {
    let mut rows: Vec<String> = Vec::new();
    let plan = [(0.2, 1, 4), (0.4, 3, 4)];
    for (x, hits, n) in plan {
        for r in 0..n {
            let rot = if r < hits { 0.02 } else { 0.001 };
            rows.push(row(&format!("r{r}"), x, &[], "finished", Some(rot)));
        }
    }
    let clean =
        fragility::fragility(&suite(&[], &rows), &[], &limit(), &opts(Method::Stripes, 0)).unwrap();
    rows.push(row("r9", 0.4, &[], "failed: t = 3.2 s: unstable", None));
    rows.push(row("r9", 0.2, &[], "failed: t = 1.0 s: unseated", None));
    rows.push(row("r8", 0.4, &[], "refused: more than 5e7 rows", None));
    rows.push(row("r7", 0.4, &[], "finished", None));
    let f =
        fragility::fragility(&suite(&[], &rows), &[], &limit(), &opts(Method::Stripes, 0)).unwrap();
    assert_eq!(f.fit, clean.fit);
    let l: Vec<(usize, usize, usize, usize, usize)> = (f.levels.iter())
        .map(|c| (c.runs, c.exceed, c.failed, c.refused, c.not_applicable))
        .collect();
    assert_eq!(l, [(4, 1, 1, 0, 0), (4, 3, 1, 1, 1)]);
    // the limit state on a column empty for every run (no seats): no run in the likelihood
    let seat = LimitState::parse("min_seat_margin<0").unwrap();
    let e = fragility::fragility(&suite(&[], &rows), &[], &seat, &opts(Method::Stripes, 0))
        .unwrap_err();
    match e {
        FragilityError::Fit {
            source: FitError::NoRuns,
            levels,
            ..
        } => assert_eq!(levels[1].not_applicable, 5),
        e => panic!("{e}"),
    }
}

#[test]
fn swept_parameters_make_one_curve_each() {
    let mut rows = Vec::new();
    for mu in ["0.3", "0.6"] {
        let shift = if mu == "0.3" { 0 } else { 1 };
        for (x, hits) in [(0.2, 1 + shift), (0.4, 3)] {
            for r in 0..4 {
                let rot = if r < hits { 0.02 } else { 0.001 };
                rows.push(row(&format!("r{r}"), x, &[mu], "finished", Some(rot)));
            }
        }
    }
    let s = suite(&["contacts.mu"], &rows);
    let groups = s.groups();
    assert_eq!(
        groups,
        vec![
            vec![("contacts.mu".to_string(), "0.3".to_string())],
            vec![("contacts.mu".to_string(), "0.6".to_string())]
        ]
    );
    let a = fragility::fragility(&s, &groups[0], &limit(), &opts(Method::Stripes, 0)).unwrap();
    let b = fragility::fragility(&s, &groups[1], &limit(), &opts(Method::Stripes, 0)).unwrap();
    assert!((a.fit.theta - 0.08f64.sqrt()).abs() < 1e-9);
    // 2 of 4 at 0.2 g: θ = 0.2 g exactly (Φ(0) = ½)
    assert!((b.fit.theta - 0.2).abs() < 1e-9, "{}", b.fit.theta);
}

#[test]
fn degenerate_data_give_typed_errors() {
    let c = |level, runs, exceed| Count {
        level,
        runs,
        exceed,
    };
    let cases: [(Vec<Count>, FitError); 7] = [
        (vec![], FitError::NoRuns),
        (
            vec![c(0.2, 4, 0), c(0.4, 4, 0)],
            FitError::NoExceedance { runs: 8 },
        ),
        (
            vec![c(0.2, 4, 4), c(0.4, 4, 4)],
            FitError::AllExceed { runs: 8 },
        ),
        (vec![c(0.3, 4, 2)], FitError::TooFewLevels { levels: 1 }),
        (
            vec![c(0.2, 4, 0), c(0.4, 4, 1), c(0.6, 4, 4)],
            FitError::Separated {
                highest_safe: 0.4,
                lowest_exceeding: 0.4,
            },
        ),
        (
            vec![c(0.2, 4, 4), c(0.4, 4, 0)],
            FitError::Falling {
                highest_exceeding: 0.2,
                lowest_safe: 0.4,
            },
        ),
        (
            vec![c(0.0, 4, 1), c(0.4, 4, 3)],
            FitError::BadLevel { level: 0.0 },
        ),
    ];
    for (counts, want) in cases {
        assert_eq!(fit_stripes(&counts), Err(want));
    }
    // the messages say which levels are all safe, all exceed, or mixed
    let mixed = fit_stripes(&[c(0.4, 19, 0), c(0.8, 19, 10)])
        .unwrap_err()
        .to_string();
    assert!(
        mixed.contains("every run below 0.8 is safe") && mixed.contains("mix only at 0.8"),
        "{mixed}"
    );
    let apart = fit_stripes(&[c(0.4, 19, 0), c(0.8, 19, 19)])
        .unwrap_err()
        .to_string();
    assert!(
        apart.contains("every run at 0.4 or below is safe")
            && apart.contains("every run at 0.8 or above exceeds"),
        "{apart}"
    );
    let cap = |level, censored| Capacity { level, censored };
    assert_eq!(fit_ida(&[]), Err(FitError::NoRuns));
    assert_eq!(
        fit_ida(&[cap(0.4, true), cap(0.4, true)]),
        Err(FitError::NoExceedance { runs: 2 })
    );
    // every record exceeds at the one level: no spread
    assert_eq!(
        fit_ida(&[cap(0.4, false), cap(0.4, false), cap(0.4, true)]),
        Err(FitError::NoSpread { capacity: 0.4 })
    );
    // one capacity and censoring above it: a finite maximum
    let f = fit_ida(&[cap(0.4, false), cap(0.8, true), cap(0.8, true)]).unwrap();
    assert!(f.theta > 0.4 && f.beta > 0.0 && f.beta.is_finite(), "{f:?}");
    // 40 % and 41 %: β = ln 2/(Φ⁻¹(0.41) − Φ⁻¹(0.40)) ≈ 27
    let e = fit_stripes(&[c(0.2, 100, 40), c(0.4, 100, 41)]).unwrap_err();
    assert!(
        matches!(e, FitError::Flat { beta, .. } if (beta - 26.9).abs() < 0.2),
        "{e}"
    );
    // a fraction that falls with the level but overlaps: b < 0 at the maximum
    let e = fit_stripes(&[c(0.2, 10, 8), c(0.4, 10, 5), c(0.6, 10, 2)]).unwrap_err();
    assert!(matches!(e, FitError::Falling { .. }), "{e}");
    // through the suite: the error names the limit state
    let rows: Vec<String> = (0..4)
        .flat_map(|r| [0.2, 0.4].map(|x| row(&format!("r{r}"), x, &[], "finished", Some(0.02))))
        .collect();
    let e =
        fragility::fragility(&suite(&[], &rows), &[], &limit(), &opts(Method::Ida, 0)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "limit state 'peak_rotation>0.01': every capacity is 0.2 and no record is censored \
         above it: β → 0 (no spread)"
    );
    // a suite that barely fits: a exceeds at 0.2 g, b is safe at 0.4 g; a bootstrap sample
    // without a or without b is separated, and its replicate is counted as not fitted
    let mut rows2 = Vec::new();
    for (pair, hits) in [("a", [true, true]), ("b", [false, false])]
        .into_iter()
        .chain(["c", "d", "e"].map(|p| (p, [false, true])))
    {
        for (x, hit) in [0.2, 0.4].into_iter().zip(hits) {
            rows2.push(row(
                pair,
                x,
                &[],
                "finished",
                Some(if hit { 0.02 } else { 0.001 }),
            ));
        }
    }
    let f = fragility::fragility(
        &suite(&[], &rows2),
        &[],
        &limit(),
        &opts(Method::Stripes, 200),
    )
    .unwrap();
    let band = f.band.unwrap();
    assert_eq!(band.replicates, 200);
    // P(a or b missing from 5 draws) = 2(4/5)⁵ − (3/5)⁵ ≈ 0.58
    assert!((50..=120).contains(&band.fitted), "{band:?}");
    let big = Options {
        bootstrap: fragility::MAX_BOOTSTRAP + 1,
        ..opts(Method::Stripes, 0)
    };
    assert!(matches!(
        fragility::fragility(&suite(&[], &rows2), &[], &limit(), &big),
        Err(FragilityError::Bootstrap { .. })
    ));
}

#[test]
fn bad_limit_states_name_their_text() {
    for (text, why) in [
        ("peak_rotation", "expected column>number"),
        (">0.1", "no column"),
        ("peak_rotation>abc", "'abc' after '>' is not a number"),
        ("peak_rotation>=0.1", "one comparison"),
        ("peak rotation>1", "not a column name"),
        ("peak_rotation>inf", "not finite"),
    ] {
        let e = LimitState::parse(text).unwrap_err().to_string();
        assert!(e.contains(&format!("'{text}'")) && e.contains(why), "{e}");
    }
    let l = LimitState::parse(" min_seat_margin < 0 ").unwrap();
    assert!(l.exceeded(-1e-3) && !l.exceeded(0.0));
    assert_eq!(l.expression(), "min_seat_margin<0");
    let s = suite(&[], &[row("a", 0.2, &[], "finished", Some(0.1))]);
    let e = fragility::records(&s, &[], &LimitState::parse("peak_rotaton>1").unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("'peak_rotaton'") && e.contains("peak_rotation, residual_rotation"),
        "{e}"
    );
}

#[test]
fn bad_suites_name_file_line_and_column() {
    let p = Path::new("s.csv");
    let good = row("a", 0.2, &[], "finished", Some(0.1));
    let err = |text: &str| Suite::parse(text, p).unwrap_err();
    let e = err("pair,level\n");
    assert!(matches!(e, SuiteError::Header { .. }), "{e}");
    assert!(e.to_string().contains("expected 'longitudinal'"), "{e}");
    let e = err(&suite_text(&[], &[]));
    assert!(matches!(e, SuiteError::Empty { .. }), "{e}");
    let e = err(&suite_text(
        &[],
        &[good.clone(), good.replace(",0.2,", ",-1,")],
    ));
    assert_eq!(
        e.to_string(),
        "s.csv:3: level: '-1': must be a finite intensity > 0"
    );
    let e = err(&suite_text(&[], &[good.replace("finished", "done")]));
    assert!(e.to_string().starts_with("s.csv:2: status: 'done'"), "{e}");
    let e = err(&suite_text(
        &[],
        &[good.clone(), good.replace(",pga,", ",sa1,")],
    ));
    assert!(
        matches!(e, SuiteError::MixedMeasures { line: 3, .. }),
        "{e}"
    );
    let e = err(&suite_text(&[], &[good.replace(",0.1,", ",NaN,")]));
    assert!(e.to_string().contains("peak_rotation: 'NaN'"), "{e}");
    let e = err(&suite_text(&[], &[format!("{good},extra")]));
    assert!(matches!(e, SuiteError::Csv { line: 2, .. }), "{e}");
    // a failed run's empty responses are not read
    let s = suite(
        &[],
        &[row("a", 0.2, &[], "failed: t = 1 s: unstable", None)],
    );
    let r = fragility::records(&s, &[], &limit()).unwrap();
    assert_eq!(r[0].runs, vec![(0.2, Outcome::Failed)]);
}

/// `deckspin args`.
fn deckspin(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_deckspin"))
        .args(args)
        .output()
        .expect("deckspin runs")
}

#[test]
fn the_command_prints_writes_and_draws_the_curves() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fragility-cli");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // the two-stripe case: 1 of 4 at 0.2 g, 3 of 4 at 0.4 g (θ = √0.08 g), a failed run,
    // and a model file naming a second limit state
    let mut rows = Vec::new();
    for (x, hits) in [(0.2, 1), (0.4, 3)] {
        for r in 0..4 {
            let rot = if r < hits { 0.02 } else { 0.001 };
            rows.push(row(&format!("r{r}"), x, &[], "finished", Some(rot)));
        }
    }
    rows.push(row("r9", 0.4, &[], "failed: t = 2 s: unstable", None));
    let csv = dir.join("suite.csv");
    std::fs::write(&csv, suite_text(&[], &rows)).unwrap();
    let model = dir.join("limits.toml");
    std::fs::write(
        &model,
        "[[limit_state]]\nname = \"drift\"\nexpression = \"max_drift_ratio>0.02\"\n",
    )
    .unwrap();
    let out = dir.join("out");
    let (c, m, o) = (
        csv.display().to_string(),
        model.display().to_string(),
        out.display().to_string(),
    );
    let r = deckspin(&[
        "fragility",
        &c,
        "--limit",
        "peak_rotation>0.01",
        "--model",
        &m,
        "--bootstrap",
        "200",
        "--out",
        &o,
    ]);
    let (stdout, stderr) = (
        String::from_utf8_lossy(&r.stdout),
        String::from_utf8_lossy(&r.stderr),
    );
    // drift never exceeds (0.01 in every run): a typed error, exit 1, the other curve written
    assert_eq!(r.status.code(), Some(1), "{stdout}{stderr}");
    assert!(
        stdout.contains("limit state 'drift': none of the 8 runs exceeds"),
        "{stdout}"
    );
    assert!(
        stdout.contains("peak_rotation>0.01             0.2828  0.5138"),
        "{stdout}"
    );
    assert!(
        stdout.contains("      0.4      1       0                 3/4             0/4"),
        "{stdout}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("fragility.json")).unwrap())
            .unwrap();
    let curve = &json["curves"][0];
    let theta = curve["fit"]["theta"].as_f64().unwrap();
    assert!((theta - 0.08f64.sqrt()).abs() < 1e-9, "{theta}");
    assert_eq!(curve["levels"][1]["failed"], 1);
    assert_eq!(curve["band"]["replicates"], 200);
    assert_eq!(json["errors"][0]["limit_state"], "drift");
    let points = std::fs::read_to_string(out.join("fragility.csv")).unwrap();
    assert_eq!(points.lines().count(), 1 + fragility::CURVE_POINTS);
    assert!(points.starts_with("limit_state,expression,method,theta,beta,im,p,p05,p95\n"));
    let svg = std::fs::read_to_string(out.join("fragility.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let count = |class: &str| {
        doc.descendants()
            .filter(|n| n.attribute("class") == Some(class))
            .count()
    };
    assert_eq!(
        (
            count("band"),
            count("ref"),
            count("series"),
            count("markers")
        ),
        (1, 1, 1, 1)
    );
    // errors name the bad text; no limit state at all is refused
    let r = deckspin(&["fragility", &c, "--limit", "peak_rotation=>1", "--out", &o]);
    assert_eq!(r.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&r.stderr).contains("'peak_rotation=>1'"));
    let r = deckspin(&["fragility", &c, "--out", &o]);
    assert_eq!(r.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&r.stderr).contains("no limit state"));
}

#[test]
fn a_run_stopped_by_a_lost_seat_exceeds_every_limit_state() {
    let mut rows: Vec<String> = Vec::new();
    for (x, hits) in [(0.2, 1), (0.4, 2)] {
        for r in 0..4 {
            let rot = if r < hits { 0.02 } else { 0.001 };
            rows.push(row(&format!("r{r}"), x, &[], "finished", Some(rot)));
        }
    }
    // at 0.4 g a fifth record unseats before its rotation grows: a collapse, an exceedance
    rows.push(row(
        "r4",
        0.4,
        &[],
        "failed: Unseated: t = 3.1 s: deck end left its seat",
        Some(0.001),
    ));
    rows.push(row("r4", 0.2, &[], "finished", Some(0.001)));
    let f =
        fragility::fragility(&suite(&[], &rows), &[], &limit(), &opts(Method::Stripes, 0)).unwrap();
    let l: Vec<(usize, usize, usize)> = (f.levels.iter())
        .map(|c| (c.runs, c.exceed, c.failed))
        .collect();
    assert_eq!(l, [(5, 1, 0), (5, 3, 0)]);
    // any other failure stays out of the likelihood
    let other = rows
        .iter()
        .map(|r| r.replace("Unseated", "StepCollapse"))
        .collect::<Vec<_>>();
    let g = fragility::fragility(
        &suite(&[], &other),
        &[],
        &limit(),
        &opts(Method::Stripes, 0),
    )
    .unwrap();
    let l: Vec<(usize, usize, usize)> = (g.levels.iter())
        .map(|c| (c.runs, c.exceed, c.failed))
        .collect();
    assert_eq!(l, [(5, 1, 0), (4, 2, 1)]);
}
