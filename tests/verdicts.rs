//! The fit against recordings of known physics, simulated here independently of the engine: a
//! continuous Euler–Bernoulli beam (free–free or clamped–free, its modes from the beam's own
//! characteristic equation) whose modes are thermally driven damped oscillators, sampled
//! exactly, tracked at K points with position noise. The fit must give back κ within its
//! interval whatever the model points and the window, call all three predictions consistent,
//! and reject the dispersion of a driven travelling wave.

use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use theory_search::fit::{fit, FitReport, FitSettings, InputKind, Verdict};
use theory_search::modal::Params;
use theory_search::model::Model;

/// A simulated body: its ends, κ (ωₙ = κ rₙ², body length 1), the first mode's damping ratio
/// (ζₙ ∝ rₙ², Kelvin damping), the first mode's rms amplitude, tracked points, position noise
/// (body lengths), frames.
#[derive(Clone, Copy)]
struct Body {
    clamped: bool,
    kappa: f64,
    zeta1: f64,
    amplitude: f64,
    points: usize,
    noise: f64,
    frames: usize,
    modes: usize,
}

/// The n-th root (n = 1, 2, …) of cos r cosh r = 1 (free–free) or −1 (clamped–free).
fn root(clamped: bool, n: usize) -> f64 {
    let target = if clamped { -1.0 } else { 1.0 };
    let centre = if clamped {
        n as f64 - 0.5
    } else {
        n as f64 + 0.5
    } * std::f64::consts::PI;
    let g = |r: f64| r.cos() - target / r.cosh();
    let (mut a, mut b) = (centre - 0.5, centre + 0.5);
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if g(a) * g(m) <= 0.0 {
            b = m
        } else {
            a = m
        }
    }
    0.5 * (a + b)
}

/// The n-th mode shape at s ∈ [0, 1] (unit mean square).
fn shape(clamped: bool, r: f64, s: f64) -> f64 {
    let x = r * s;
    if clamped {
        let sigma = (r.cosh() + r.cos()) / (r.sinh() + r.sin());
        x.cosh() - x.cos() - sigma * (x.sinh() - x.sin())
    } else {
        let sigma = (r.cosh() - r.cos()) / (r.sinh() - r.sin());
        x.cosh() + x.cos() - sigma * (x.sinh() + x.sin())
    }
}

/// Exact samples (interval 1) of a damped oscillator of stationary variance `var`.
fn oscillator(omega: f64, zeta: f64, var: f64, n: usize, rng: &mut impl rand::Rng) -> Vec<f64> {
    let g = zeta * omega;
    let d = (omega * omega - g * g).sqrt();
    let (c, s, e) = (d.cos(), d.sin(), (-g).exp());
    let phi = [
        [e * (c + g * s / d), e * s / d],
        [-e * omega * omega * s / d, e * (c - g * s / d)],
    ];
    let sig = [var, omega * omega * var];
    let q = |i: usize, j: usize| {
        let m = if i == j { sig[i] } else { 0.0 };
        m - (0..2).map(|k| phi[i][k] * sig[k] * phi[j][k]).sum::<f64>()
    };
    let l00 = q(0, 0).sqrt();
    let l10 = q(1, 0) / l00;
    let l11 = (q(1, 1) - l10 * l10).max(0.0).sqrt();
    let mut z = || -> f64 { StandardNormal.sample(rng) };
    let (mut x, mut v) = (var.sqrt() * z(), sig[1].sqrt() * z());
    (0..n)
        .map(|_| {
            let (a, b) = (z(), z());
            let nx = phi[0][0] * x + phi[0][1] * v + l00 * a;
            let nv = phi[1][0] * x + phi[1][1] * v + l10 * a + l11 * b;
            (x, v) = (nx, nv);
            x
        })
        .collect()
}

/// The recording as the CSV `fit` reads: `t, x₁, y₁, …`, body length 100 length units.
fn record(body: &Body, seed: u64) -> String {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let r1 = root(body.clamped, 1);
    let s: Vec<f64> = (0..body.points)
        .map(|j| j as f64 / (body.points - 1) as f64)
        .collect();
    let mut y = vec![vec![0.0; body.points]; body.frames];
    for n in 1..=body.modes {
        let r = root(body.clamped, n);
        let omega = body.kappa * r * r;
        let zeta = body.zeta1 * (r / r1).powi(2);
        if zeta >= 0.95 {
            // Past critical damping this simulation has no oscillator; such modes are left out.
            break;
        }
        // Equipartition: variance ∝ 1/λ ∝ r⁻⁴.
        let var = body.amplitude.powi(2) * (r1 / r).powi(4);
        let phi: Vec<f64> = s.iter().map(|&s| shape(body.clamped, r, s)).collect();
        let a = oscillator(omega, zeta, var, body.frames, &mut rng);
        for (row, a) in y.iter_mut().zip(&a) {
            for (v, p) in row.iter_mut().zip(&phi) {
                *v += a * p;
            }
        }
    }
    let mut out = String::from("t");
    for j in 1..=body.points {
        out += &format!(",x{j},y{j}");
    }
    out.push('\n');
    let mut noise = || -> f64 {
        let e: f64 = StandardNormal.sample(&mut rng);
        body.noise * e
    };
    for (t, row) in y.iter().enumerate() {
        out += &t.to_string();
        for (s, y) in s.iter().zip(row) {
            out += &format!(",{},{}", 100.0 * (s + noise()), 100.0 * (y + noise()));
        }
        out.push('\n');
    }
    out
}

fn model(clamped: bool) -> Model {
    if clamped {
        Model::from_toml(include_str!("../tables/models/zebrafish.toml")).expect("shipped model")
    } else {
        Model::larva()
    }
}

fn fitted(text: &str, clamped: bool, points: usize, window: Option<usize>) -> FitReport {
    let mut s = FitSettings::new(InputKind::Midline);
    s.points = points;
    s.window = window;
    // Point 1 (s = 0 here, the clamped end) is read as the head: the zebrafish model clamps
    // its head.
    fit(
        std::io::Cursor::new(text.as_bytes()),
        &model(clamped),
        &Params::default(),
        &s,
    )
    .expect("fits")
}

const BODY: Body = Body {
    clamped: false,
    kappa: 0.01,
    zeta1: 0.05,
    amplitude: 0.01,
    points: 25,
    noise: 2e-5,
    frames: 20_000,
    modes: 6,
};

/// A clamped–free body: its modes spread faster (rₙ² grows from 3.5), so κ is larger to keep
/// three of them under Nyquist, and its position noise smaller.
const CLAMPED: Body = Body {
    clamped: true,
    kappa: 0.04,
    zeta1: 0.03,
    noise: 5e-6,
    points: 41,
    ..BODY
};

fn check_recovered(body: Body, seed: u64, window: usize) {
    let text = record(&body, seed);
    for points in [12, 24, 48] {
        for window in [None, Some(window)] {
            let r = fitted(&text, body.clamped, points, window);
            let c = r.continuum.as_ref().expect("a continuum constant");
            let [lo, hi] = c.interval.expect("an interval");
            let what = format!(
                "clamped {} N = {points} window {window:?}: κ = {} [{lo}, {hi}], tests {:?}",
                body.clamped, c.constant, r.tests
            );
            assert!(lo <= body.kappa && body.kappa <= hi, "{what}");
            assert!((c.constant / body.kappa - 1.0).abs() < 0.05, "{what}");
            for t in [
                &r.tests.equipartition,
                &r.tests.dispersion,
                &r.tests.damping,
            ] {
                assert_eq!(t.verdict, Verdict::Consistent, "{what}");
            }
        }
    }
}

#[test]
fn a_free_beam_of_known_kappa_is_recovered_at_every_grid_and_window() {
    check_recovered(BODY, 1, 1024);
}

#[test]
fn a_clamped_beam_of_known_kappa_is_recovered_at_every_grid_and_window() {
    check_recovered(CLAMPED, 2, 2048);
}

#[test]
fn a_driven_travelling_wave_is_not_a_passive_beam() {
    // Every mode at the one frequency of the wave, with a little thermal noise on top.
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let (k, w) = (2.0 * std::f64::consts::PI / 0.7, 0.35f64);
    let mut text = String::from("t");
    let points = 33;
    for j in 1..=points {
        text += &format!(",x{j},y{j}");
    }
    text.push('\n');
    let mut phase = 0.0;
    for t in 0..12_000 {
        text += &t.to_string();
        // A diffusing phase: a rhythm with a finite bandwidth, as a crawling animal's.
        let kick: f64 = StandardNormal.sample(&mut rng);
        phase += w + 0.05 * kick;
        for j in 0..points {
            let s = j as f64 / (points - 1) as f64;
            let e: f64 = StandardNormal.sample(&mut rng);
            let y = 0.02 * (k * s - phase).sin() + 1e-4 * e;
            text += &format!(",{},{}", 100.0 * s, 100.0 * y);
        }
        text.push('\n');
    }
    let r = fitted(&text, false, 12, None);
    assert_eq!(
        r.tests.dispersion.verdict,
        Verdict::Rejected,
        "{:?}",
        r.tests
    );
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("not constants of the body")),
        "{:?}",
        r.warnings
    );
}

/// `job(r)` for r = 0 … runs − 1 on two threads, the results in no particular order.
fn on_two_cores<T: Send>(runs: u64, job: impl Fn(u64) -> T + Sync) -> Vec<T> {
    std::thread::scope(|scope| {
        let job = &job;
        let workers: Vec<_> = (0..2u64)
            .map(|w| {
                scope.spawn(move || {
                    (0..runs)
                        .filter(|r| r % 2 == w)
                        .map(job)
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|h| h.join().expect("a worker"))
            .collect()
    })
}

#[test]
fn nominal_95_percent_intervals_cover_the_truth() {
    // 100 recordings of the free beam, shorter than above; every interval the fit gives for κ
    // and for the three exponents is counted.
    let body = Body {
        frames: 6000,
        ..BODY
    };
    let runs = 100u64;
    let results = on_two_cores(runs, |r| fitted(&record(&body, 1000 + r), false, 12, None));
    let covers = |pick: &dyn Fn(&FitReport) -> Option<[f64; 2]>, truth: f64| -> (usize, usize) {
        let intervals: Vec<[f64; 2]> = results.iter().filter_map(pick).collect();
        let n = intervals.len();
        (
            intervals
                .iter()
                .filter(|[lo, hi]| *lo <= truth && truth <= *hi)
                .count(),
            n,
        )
    };
    let kappa = covers(
        &|r| r.continuum.as_ref().and_then(|c| c.interval),
        body.kappa,
    );
    let equi = covers(&|r| r.tests.equipartition.interval, -1.0);
    let disp = covers(&|r| r.tests.dispersion.interval, 0.5);
    let damp = covers(&|r| r.tests.damping.interval, 0.5);
    println!("covered: κ {kappa:?}, equipartition {equi:?}, dispersion {disp:?}, damping {damp:?}");
    for (name, (hit, n)) in [
        ("κ", kappa),
        ("equipartition", equi),
        ("dispersion", disp),
        ("damping", damp),
    ] {
        assert!(n >= 90, "{name}: only {n} of {runs} fits gave an interval");
        assert!(
            hit * 100 >= 90 * n,
            "{name}: {hit} of {n} intervals cover the truth"
        );
    }
}

#[test]
fn moving_block_bootstrap_intervals_of_kappa_cover_the_truth() {
    // One animal each: its κ interval from 100 moving-block resamples over time.
    let body = Body {
        frames: 6000,
        ..BODY
    };
    let hits = on_two_cores(100, |r| {
        let mut s = FitSettings::new(InputKind::Midline);
        s.bootstrap = 100;
        s.seed = r;
        let text = record(&body, 5000 + r);
        let fit = fit(
            std::io::Cursor::new(text.as_bytes()),
            &Model::larva(),
            &Params::default(),
            &s,
        )
        .expect("fits");
        fit.intervals
            .and_then(|i| i.continuum)
            .map(|[lo, hi]| lo <= body.kappa && body.kappa <= hi)
    });
    let drawn: Vec<bool> = hits.iter().flatten().copied().collect();
    let covered = drawn.iter().filter(|&&h| h).count();
    println!("moving blocks: κ covered {covered} of {}", drawn.len());
    assert!(drawn.len() >= 95, "only {} bootstraps drawn", drawn.len());
    // Percentile intervals of a moving-block bootstrap run a little short (88–89 of 100 here,
    // seeds fixed); κ's own interval is the modes' errors' (95 of 100 above), and
    // docs/fit.md says so. This guards against worse.
    assert!(
        covered * 100 >= 85 * drawn.len(),
        "{covered} of {}",
        drawn.len()
    );
}

#[test]
fn the_json_contract_of_a_fit() {
    let example = format!(
        "{}/tables/examples/midlines.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut out = Vec::new();
    theory_search::cli::run(
        ["theory-search", "fit", example.as_str(), "--format", "json"],
        &mut out,
    )
    .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out).unwrap();
    let keys: Vec<&str> = v.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    // The contract's keys first, in order.
    assert_eq!(
        keys[..12],
        [
            "frames",
            "points",
            "pca_variance_share",
            "theory_variance_share",
            "overlap",
            "omega",
            "beta",
            "continuum",
            "modes_fit",
            "tests",
            "noise_floor",
            "window"
        ]
    );
    let c = &v["continuum"];
    assert_eq!(c["name"], "kappa");
    assert!(c["constant"].as_f64().unwrap() > 0.0 && c["unit"].is_string());
    assert_eq!(c["interval"].as_array().unwrap().len(), 2);
    let modes = v["modes_fit"].as_array().unwrap();
    assert_eq!(modes.len(), 10);
    for m in modes {
        for key in ["mode", "lambda", "omega", "zeta", "variance"] {
            assert!(m[key].is_number(), "{key} in {m}");
        }
        for key in ["omega_error", "zeta_error"] {
            assert!(m[key].is_number() || m[key].is_null(), "{key} in {m}");
        }
        assert!(m["resolved"].is_boolean());
    }
    for name in ["equipartition", "dispersion", "damping"] {
        let t = &v["tests"][name];
        assert!(t["expected"].is_number());
        assert!(
            ["consistent", "rejected", "undetermined"].contains(&t["verdict"].as_str().unwrap())
        );
        assert!(t["exponent"].is_number() || t["exponent"].is_null());
        assert!(t["interval"].is_array() || t["interval"].is_null());
    }
    assert!(v["noise_floor"].is_number());
    assert_eq!(v["window"]["frames"], 1024);
    assert_eq!(v["window"]["how"], "chosen");
    assert!(v["window"]["why"].as_str().unwrap().contains("16 bins"));
}
