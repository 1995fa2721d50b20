//! Fitting tracked midlines: synthetic ground truth from `simulate`, written in every input
//! format, must give back ω, β and the mode shapes.

mod common;

use std::fmt::Write as _;
use std::io::Cursor;

use theory_search::dynamics::{simulate, Config};
use theory_search::fit::{fit, FitError, FitReport, FitSettings, Verdict};
use theory_search::modal::Params;
use theory_search::model::Model;
use theory_search::recording::InputKind;

use common::beam::{record, Body, FREE_BEAM};

/// Simulated larva at known scales: ω_b, ζ_b, kT, N points, `frames` frames every `dt`.
struct Truth {
    omega: f64,
    zeta: f64,
    kt: f64,
    points: usize,
    frames: u64,
    dt: f64,
    seed: u64,
}

impl Truth {
    fn params(&self) -> Params {
        let mut p = Params::default();
        p.set("omega_b", self.omega).unwrap();
        p.set("zeta_b", self.zeta).unwrap();
        p.set("omega_s", self.omega).unwrap();
        p.set("zeta_s", self.zeta).unwrap();
        p
    }

    /// Every frame: t, then the y field (midline) and the x field.
    fn run(&self, mut each: impl FnMut(f64, &[f64], &[f64])) {
        let config = Config {
            points: self.points,
            order: 4,
            dt: self.dt,
            steps: self.frames - 1,
            every: 1,
            temperature: self.kt,
            seed: self.seed,
            initial: Vec::new(),
            forcing: Vec::new(),
        };
        let model = Model::larva();
        simulate(&model, &self.params(), &config, |s| {
            each(s.t, &s.positions[2], &s.positions[0]);
            Ok(())
        })
        .unwrap();
    }

    /// Midline text: x = j (unit spacing), y from the simulation; `sep` between columns.
    fn midline(&self, sep: &str, header: bool) -> String {
        let mut out = String::new();
        if header {
            let cols: Vec<String> = (1..=self.points)
                .map(|j| format!("x{j}{sep}y{j}"))
                .collect();
            writeln!(out, "time{sep}{}", cols.join(sep)).unwrap();
        }
        self.run(|t, y, _| {
            let mut line = format!("{t}");
            for (j, v) in y.iter().enumerate() {
                write!(line, "{sep}{j}{sep}{v}").unwrap();
            }
            writeln!(out, "{line}").unwrap();
        });
        out
    }
}

/// One line `t,ℓ₁,…,ℓ_K` of the first `k` segment lengths 1 + x_{j+1} − x_j of the axial field
/// `x`, closed into a ring (`x` periodic) or not (free ends).
fn length_row(t: f64, x: &[f64], k: usize, ring: bool) -> String {
    let n = x.len();
    let next = |j: usize| if ring { (j + 1) % n } else { j + 1 };
    let cells: Vec<String> = (0..k)
        .map(|j| format!("{}", 1.0 + x[next(j)] - x[j]))
        .collect();
    format!("{t},{}\n", cells.join(","))
}

fn larva_fit(text: &str, settings: &FitSettings) -> Result<FitReport, FitError> {
    fit(
        Cursor::new(text),
        &Model::larva(),
        &Params::default(),
        settings,
    )
}

fn truth() -> Truth {
    Truth {
        omega: 1.0,
        zeta: 0.1,
        kt: 1e-4,
        points: 12,
        frames: 60_000,
        dt: 1.0,
        seed: 7,
    }
}

#[test]
fn synthetic_midlines_give_back_omega_beta_and_shapes() {
    let t = truth();
    let mut settings = FitSettings::new(InputKind::Midline);
    settings.window = Some(2048);
    settings.fit_modes = 3;
    for (sep, header) in [(",", true), (" ", false), ("\t", false)] {
        let r = larva_fit(&t.midline(sep, header), &settings).unwrap();
        assert_eq!((r.frames, r.points, r.model_points), (60_000, 12, 12));
        assert!(
            (r.omega - t.omega).abs() < 0.02 * t.omega,
            "ω = {}",
            r.omega
        );
        assert!(
            (r.beta * t.kt - 1.0).abs() < 0.08,
            "β = {} (true {})",
            r.beta,
            1.0 / t.kt
        );
        for k in 0..3 {
            assert!(r.overlap[k][k] > 0.99, "PC {k}: {:?}", r.overlap[k]);
        }
        for (a, b) in r
            .pca_variance_share
            .iter()
            .zip(&r.theory_variance_share)
            .take(3)
        {
            assert!((a - b).abs() < 0.05, "{a} vs {b}");
        }
    }
}

#[test]
fn other_scales_and_sampling() {
    let t = Truth {
        omega: 2.5,
        zeta: 0.05,
        kt: 1e-3,
        points: 9,
        frames: 40_000,
        dt: 0.25,
        seed: 3,
    };
    let mut settings = FitSettings::new(InputKind::Midline);
    settings.recording.points = 9;
    settings.window = Some(2048);
    settings.fit_modes = 3;
    let r = larva_fit(&t.midline(",", false), &settings).unwrap();
    assert!((r.sample_interval - 0.25).abs() < 1e-12);
    assert!((r.omega / t.omega - 1.0).abs() < 0.02, "ω = {}", r.omega);
    assert!(
        (r.beta * t.kt - 1.0).abs() < 0.1,
        "β kT = {}",
        r.beta * t.kt
    );
    assert!(r.overlap[0][0] > 0.99 && r.overlap[1][1] > 0.99);
    // Fixing ω leaves only β to fit.
    settings.omega = Some(t.omega);
    let fixed = larva_fit(&t.midline(",", false), &settings).unwrap();
    assert_eq!(fixed.omega, t.omega);
    assert!((fixed.beta * t.kt - 1.0).abs() < 0.1);
}

/// Angles between segments remove translation and rotation: moving every frame rigidly, each
/// by a different amount, changes nothing.
#[test]
fn rigid_motions_of_each_frame_change_nothing() {
    let mut t = truth();
    t.frames = 3000;
    let plain = t.midline(",", false);
    let mut moved = String::new();
    for (n, line) in plain.lines().enumerate() {
        let v: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
        let (a, dx, dy) = (
            0.7 * n as f64,
            3.0 * (n as f64).sin(),
            -2.0 + 0.001 * n as f64,
        );
        let mut out = format!("{}", v[0]);
        for p in v[1..].chunks(2) {
            let (x, y) = (
                p[0] * a.cos() - p[1] * a.sin() + dx,
                p[0] * a.sin() + p[1] * a.cos() + dy,
            );
            out += &format!(",{x},{y}");
        }
        moved += &(out + "\n");
    }
    let s = FitSettings::new(InputKind::Midline);
    let (a, b) = (
        larva_fit(&plain, &s).unwrap(),
        larva_fit(&moved, &s).unwrap(),
    );
    for (x, y) in a.modes.iter().zip(&b.modes) {
        assert!((x.variance - y.variance).abs() <= 1e-9 * x.variance);
    }
    assert!((a.beta - b.beta).abs() <= 1e-6 * a.beta);
}

/// Tracker output with more points than the model: the midline is resampled by arc length.
/// Inserting the midpoint of every segment leaves the same polyline, so the fit barely moves.
#[test]
fn denser_midlines_are_resampled() {
    let mut t = truth();
    t.frames = 20_000;
    let plain = t.midline(" ", false);
    let mut dense = String::new();
    for line in plain.lines() {
        let v: Vec<f64> = line.split(' ').map(|c| c.parse().unwrap()).collect();
        let pts: Vec<(f64, f64)> = v[1..].chunks(2).map(|p| (p[0], p[1])).collect();
        let mut out = format!("{}", v[0]);
        for (i, p) in pts.iter().enumerate() {
            out += &format!(" {} {}", p.0, p.1);
            if let Some(q) = pts.get(i + 1) {
                out += &format!(" {} {}", 0.5 * (p.0 + q.0), 0.5 * (p.1 + q.1));
            }
        }
        dense += &(out + "\n");
    }
    let s = FitSettings::new(InputKind::Midline);
    let (a, b) = (
        larva_fit(&plain, &s).unwrap(),
        larva_fit(&dense, &s).unwrap(),
    );
    assert_eq!(b.points, 23);
    assert_eq!(b.model_points, 12);
    for k in 0..3 {
        assert!(b.overlap[k][k] > 0.999, "{:?}", b.overlap[k]);
        let (x, y) = (a.modes[k].variance, b.modes[k].variance);
        assert!((x - y).abs() < 0.01 * x, "mode {k}: {x} vs {y}");
    }
}

/// Axial data: segment lengths around the body observe the periodic first differences.
#[test]
fn segment_lengths_give_back_the_axial_scales() {
    let t = Truth {
        omega: 1.5,
        zeta: 0.1,
        kt: 1e-4,
        points: 9,
        frames: 40_000,
        dt: 0.5,
        seed: 11,
    };
    let mut text = String::from("t,l1,l2,l3,l4,l5,l6,l7,l8\n");
    t.run(|time, _, x| text += &length_row(time, x, x.len(), true));
    let mut s = FitSettings::new(InputKind::Lengths);
    s.window = Some(2048);
    s.fit_modes = 2;
    let r = larva_fit(&text, &s).unwrap();
    assert_eq!((r.points, r.model_points, r.field.as_str()), (8, 9, "x"));
    assert!((r.omega / t.omega - 1.0).abs() < 0.02, "ω = {}", r.omega);
    assert!(
        (r.beta * t.kt - 1.0).abs() < 0.1,
        "β kT = {}",
        r.beta * t.kt
    );
}

#[test]
fn lost_frames_split_the_recording_into_runs() {
    // No bridging first (the default bridges gaps of ≤ 2 frames).
    let mut s = FitSettings::new(InputKind::Midline);
    s.recording.fill_gaps = 0;
    // Six tracked points resolve at most six model points.
    s.recording.points = 6;
    let frame = |t: usize, lost: bool| -> String {
        let mut c = vec![format!("{t}")];
        for j in 0..6 {
            c.push(format!("{j}"));
            c.push(if lost {
                "NaN".into()
            } else {
                format!("{:.5}", 0.05 * (0.7 * t as f64 + j as f64).sin())
            });
        }
        c.join(",") + "\n"
    };
    // 60 frames: 20 good, 2 lost (NaN rows), 18 good, then 5 frames skipped by the time step,
    // then 15 good.
    let mut text = String::new();
    for t in 0..40 {
        text += &frame(t, (20..22).contains(&t));
    }
    for t in 45..60 {
        text += &frame(t, false);
    }
    let r = larva_fit(&text, &s).unwrap();
    let rec = &r.recording;
    assert_eq!(rec.frames_read, 55);
    assert_eq!(rec.frames_lost, 7);
    assert_eq!((rec.gaps, rec.runs, rec.longest_run), (2, 3, 20));
    assert_eq!(r.frames, 53);
    // Bridging gaps of up to 2 frames joins the first two runs; the 5-frame gap stays.
    let mut fill = s.clone();
    fill.recording.fill_gaps = 2;
    let r = larva_fit(&text, &fill).unwrap();
    assert_eq!((r.recording.gaps, r.recording.frames_filled), (1, 2));
    assert_eq!(r.recording.longest_run, 40);
    assert_eq!(r.frames, 55);
    // Nothing usable is one error.
    let all_lost: String = (0..10).map(|t| frame(t, true)).collect();
    let e = larva_fit(&all_lost, &s).unwrap_err().to_string();
    assert!(e.contains("none of the 10 frames is usable"), "{e}");
}

#[test]
fn bad_input_names_the_line() {
    let mut s = FitSettings::new(InputKind::Midline);
    s.recording.points = 6;
    let cells = |t: f64| -> Vec<String> {
        let mut c = vec![format!("{t}")];
        for j in 0..6 {
            c.push(format!("{j}"));
            c.push(format!("{:.5}", 0.05 * (0.7 * t + j as f64).sin()));
        }
        c
    };
    let join =
        |rows: &[Vec<String>]| -> String { rows.iter().map(|r| r.join(",") + "\n").collect() };
    let rows: Vec<Vec<String>> = (0..20).map(|i| cells(i as f64)).collect();
    assert!(larva_fit(&join(&rows), &s).is_ok());
    let with = |line: usize, col: usize, v: &str| {
        let mut r = rows.clone();
        r[line][col] = v.to_string();
        join(&r)
    };
    let good = join(&rows);
    let cases = [
        (with(0, 2, "abc"), "not a number"),
        (with(4, 0, "NaN"), "line 5: column 1: time"),
        (
            format!("{good}{}\n", cells(19.0).join(",")),
            "line 21: time 19 does not increase",
        ),
        (
            format!("{good}{}\n", cells(21.5).join(",")),
            "not a whole number of sampling intervals",
        ),
        (
            format!("{good}1,2,3\n"),
            "line 21: 3 columns where the first frame had 13",
        ),
        ("0,1,2,3,4,5\n".repeat(3), "odd"),
        (
            "0,0,0,1,0,2,0,3,0\n".to_string(),
            "4 points per frame; at least 5",
        ),
        (String::new(), "no frames"),
        ("# only a comment\nt,x1,y1\n".into(), "no frames"),
        (join(&rows[..5]), "5 usable frames; at least 8"),
        (
            join(
                &(0..10)
                    .map(|i| {
                        let mut c = cells(0.0);
                        c[0] = format!("{i}");
                        c
                    })
                    .collect::<Vec<_>>(),
            ),
            "do not vary",
        ),
    ];
    for (text, needle) in cases {
        let e = larva_fit(&text, &s).unwrap_err().to_string();
        assert!(e.contains(needle), "{needle:?} not in {e:?}");
    }
    // Without resampling (K = N) a repeated point leaves a segment with no direction.
    let mut twelve = s.clone();
    twelve.recording.points = 6;
    assert!(larva_fit(&good, &twelve).is_ok());
    let mut r = rows.clone();
    r[2][3] = r[2][1].clone();
    r[2][4] = r[2][2].clone();
    let e = larva_fit(&join(&r), &twelve).unwrap_err().to_string();
    assert!(
        e.contains("line 3: two consecutive midline points coincide"),
        "{e}"
    );
    let mut bad = s.clone();
    bad.window = Some(2);
    assert!(larva_fit(&good, &bad)
        .unwrap_err()
        .to_string()
        .contains("window"));
    bad = s.clone();
    bad.omega = Some(f64::NAN);
    assert!(larva_fit(&good, &bad).is_err());
    bad = s.clone();
    bad.recording.field = Some("w".into());
    assert!(larva_fit(&good, &bad)
        .unwrap_err()
        .to_string()
        .contains("no field"));
}

/// A reader that makes frames on demand: a million frames go through without ever being held.
struct Frames {
    next: u64,
    total: u64,
    buf: Vec<u8>,
    pos: usize,
}

impl std::io::Read for Frames {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        use std::io::BufRead;
        let avail = self.fill_buf()?;
        let n = avail.len().min(out.len());
        out[..n].copy_from_slice(&avail[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl std::io::BufRead for Frames {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        if self.pos == self.buf.len() && self.next < self.total {
            let t = self.next as f64;
            let mut line = format!("{t}");
            for j in 0..12 {
                let y =
                    0.01 * (0.3 * t + j as f64).sin() + 0.005 * (0.11 * t * (j as f64 + 1.0)).cos();
                line += &format!(" {j} {y}");
            }
            line.push('\n');
            self.buf = line.into_bytes();
            self.pos = 0;
            self.next += 1;
        }
        Ok(&self.buf[self.pos..])
    }

    fn consume(&mut self, n: usize) {
        self.pos += n;
    }
}

#[test]
fn a_million_frames_stream() {
    let reader = Frames {
        next: 0,
        total: 1_000_000,
        buf: Vec::new(),
        pos: 0,
    };
    let mut s = FitSettings::new(InputKind::Midline);
    s.window = Some(256);
    let r = fit(reader, &Model::larva(), &Params::default(), &s).unwrap();
    assert_eq!(r.frames, 1_000_000);
    assert_eq!(r.welch.1, 2 * 1_000_000 / 256 - 1);
}

/// `tables/examples/midlines.csv`, the README's worked example: 3000 frames of a continuum
/// free–free beam made independently of the engine (tests/common/beam.rs: κ = 0.01 body
/// lengths² per frame, ζ₁ = 0.05, six thermal modes, 12 tracked points with position noise
/// 2e-5 body lengths, seed 7), four decimals. Regenerated when it drifts; at the defaults its
/// κ interval covers the truth and no law of the theory is rejected.
#[test]
fn shipped_example_is_fresh_and_fits() {
    let body = Body {
        points: 12,
        frames: 3000,
        ..FREE_BEAM
    };
    let mut text = String::from(
        "# Simulated larva midline (theory-search tests/common/beam.rs): a continuum free-free beam, \
         kappa = 0.01 body lengths^2 per frame, zeta_1 = 0.05, 12 points, seed 7\n",
    );
    for (i, line) in record(&body, 7).lines().enumerate() {
        let cells: Vec<String> = line
            .split(',')
            .enumerate()
            .map(|(j, c)| match (i, j) {
                (0, _) | (_, 0) => c.to_string(),
                _ => format!("{:.4}", c.parse::<f64>().unwrap()),
            })
            .collect();
        text += &cells.join(",");
        text.push('\n');
    }
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tables/examples/midlines.csv");
    theory_search::artifacts::ensure_file_contents(&path, &text).unwrap();
    let r = larva_fit(&text, &FitSettings::new(InputKind::Midline)).unwrap();
    let c = r.continuum.expect("a beam has continuum roots");
    let [lo, hi] = c.interval.expect("an interval");
    assert!(
        lo < body.kappa && body.kappa < hi,
        "κ {} [{lo}, {hi}]",
        c.constant
    );
    for t in [
        &r.tests.equipartition,
        &r.tests.dispersion,
        &r.tests.damping,
    ] {
        assert_ne!(t.verdict, Verdict::Rejected, "{:?}", r.tests);
    }
    assert!(r.overlap[0][0] > 0.99);
}

/// The continuum constant does not move with the model points, where ω does: on the shipped
/// example (12 tracked points) κ agrees within 1 % at N = 7, 9 and 12, while ω grows about as
/// (N − 1)².
#[test]
fn the_continuum_constant_does_not_depend_on_the_model_points() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tables/examples/midlines.csv");
    let text = std::fs::read_to_string(path).unwrap();
    let fits: Vec<(f64, f64)> = [12, 9, 7]
        .into_iter()
        .map(|n| {
            let mut s = FitSettings::new(InputKind::Midline);
            s.recording.points = n;
            let r = larva_fit(&text, &s).unwrap();
            let c = r.continuum.expect("a beam has continuum roots");
            assert_eq!(c.name, "kappa");
            // The roots of the modes that gave κ: resolved ones among the fitted.
            assert!(!c.roots.is_empty() && c.roots.len() <= r.fitted_modes);
            assert!((c.roots[0] - 4.730040745).abs() < 1e-6, "{:?}", c.roots);
            (r.omega, c.constant)
        })
        .collect();
    assert_eq!(fits.len(), 3);
    let kappa = fits[0].1;
    // The generator's κ is 0.01 (tests/common/beam.rs).
    for &(omega, k) in &fits {
        assert!((k / kappa - 1.0).abs() < 0.01, "{fits:?}");
        assert!((k / 0.01 - 1.0).abs() < 0.02, "{fits:?}");
        assert!(omega > 0.0);
    }
    // ω is the N-point constant: it scales with (N − 1)², 11² : 8² : 6².
    assert!(
        fits[0].0 / fits[1].0 > 1.5 && fits[1].0 / fits[2].0 > 1.4,
        "{fits:?}"
    );
}

/// Peristalsis-like data: a compression wave travelling round 7 segments. Its two modes form a
/// degenerate cos/sin pair, so the principal components may be any rotation within the pair;
/// `mode_overlap` measures them against the pair's plane, and the peak sits at the wave's
/// frequency.
#[test]
fn a_travelling_wave_fills_the_first_axial_pair() {
    let mut text = String::new();
    for n in 0..4000 {
        let t = 0.1 * n as f64;
        let lengths: Vec<String> = (0..7)
            .map(|j| {
                let phase = 2.0 * std::f64::consts::PI * (0.8 * t - j as f64 / 7.0);
                format!(
                    "{}",
                    1.0 + 0.05 * phase.sin() + 0.002 * (3.1 * phase + 0.4).cos()
                )
            })
            .collect();
        text += &format!("{t} {}\n", lengths.join(" "));
    }
    let mut s = FitSettings::new(InputKind::Lengths);
    s.window = Some(512);
    s.fit_modes = 2;
    let r = larva_fit(&text, &s).unwrap();
    assert_eq!((r.points, r.model_points), (7, 8));
    assert!(r.pca_variance_share[0] > 0.45 && r.pca_variance_share[1] > 0.45);
    assert!(r.mode_overlap[0] > 0.999 && r.mode_overlap[1] > 0.999);
    for m in &r.modes[..2] {
        assert!(
            (m.peak_frequency - 0.8).abs() < 0.004,
            "{}",
            m.peak_frequency
        );
    }
    // ω√λ₁ is then the wave's angular frequency.
    let w1 = r.modes[0].theory_angular_frequency;
    assert!((w1 - 2.0 * std::f64::consts::PI * 0.8).abs() < 0.03, "{w1}");
}

/// The projector inverts the observation map on the body's own modes: a midline built from
/// the free–free beam's continuum modes (plus a translation and a rotation) gives back each
/// mode's amplitude in its own coordinate alone, times that coordinate's gain, to the second
/// order in the amplitude that the small-angle reading neglects.
#[test]
fn projection_recovers_modal_coordinates_at_every_size() {
    use theory_search::recording::Projector;
    let model = Model::larva();
    let params = Params::default();
    for n in [5usize, 7, 12, 25, 40] {
        let mut s = FitSettings::new(InputKind::Midline);
        s.recording.points = n;
        let p = Projector::new(&model, &params, &s.recording, 2 * n).unwrap();
        assert_eq!(p.eigenvalues.len(), n - 2);
        let gains = p.continuum_gains();
        let amp = 1e-5;
        let a: Vec<f64> = (0..n - 2)
            .map(|j| amp * ((j * 7 + n) as f64 * 0.37).sin())
            .collect();
        // The continuum shapes, linearly interpolated from their fine sampling.
        let shapes: Vec<Vec<f64>> = (0..n - 2)
            .map(|j| {
                theory_search::modal::continuum_shape(2, p.boundary, j + 1).expect("a beam mode")
            })
            .collect();
        let at = |shape: &[f64], u: f64| {
            let x = u * (shape.len() - 1) as f64;
            let (i, f) = (x.floor() as usize, x - x.floor());
            shape[i] + f * (shape[(i + 1).min(shape.len() - 1)] - shape[i])
        };
        let (turn, length) = (1.1f64, (n - 1) as f64);
        let mut values = Vec::new();
        for i in 0..n {
            let u = i as f64 / (n - 1) as f64;
            let y: f64 = 0.3
                + length
                    * a.iter()
                        .zip(&shapes)
                        .map(|(aj, v)| aj * at(v, u))
                        .sum::<f64>();
            let x = i as f64;
            values.push(x * turn.cos() - y * turn.sin() + 5.0);
            values.push(x * turn.sin() + y * turn.cos() - 2.0);
        }
        let got = p.modal(&values).unwrap();
        for ((g, want), gain) in got.iter().zip(&a).zip(&gains) {
            let gain = gain.expect("a gain");
            // Signed: the gain's sign makes the coordinate the shape's own amplitude.
            assert!(
                (g - gain * want).abs() < 1e-3 * gain.abs() * amp,
                "N = {n}: {g} vs {gain} × {want}"
            );
        }
    }
    // A free axial field (the worm): strains against a fixed rest length, exact.
    let worm = Model::from_toml(include_str!("../tables/models/worm.toml")).unwrap();
    for k in [3usize, 8, 15] {
        let s = FitSettings::new(InputKind::Lengths);
        let mut p = Projector::new(&worm, &params, &s.recording, k).unwrap();
        p.reference_length = Some(1.0);
        assert_eq!((p.points, p.eigenvalues.len()), (k + 1, k));
        let q: Vec<f64> = (0..k).map(|j| 0.01 * (j as f64 + 0.5).cos()).collect();
        let x: Vec<f64> = (0..=k)
            .map(|i| q.iter().zip(&p.shapes).map(|(qj, v)| qj * v[i]).sum())
            .collect();
        let lengths: Vec<f64> = (0..k).map(|i| 1.0 + x[i + 1] - x[i]).collect();
        let got = p.modal(&lengths).unwrap();
        for (g, want) in got.iter().zip(&q) {
            assert!((g - want).abs() < 1e-12, "free K = {k}: {g} vs {want}");
        }
    }
    // Segment strains are linear in x: exact.
    for k in [3usize, 7, 16] {
        let s = FitSettings::new(InputKind::Lengths);
        let p = Projector::new(&model, &params, &s.recording, k).unwrap();
        assert_eq!((p.points, p.eigenvalues.len()), (k + 1, k - 1));
        let q: Vec<f64> = (0..k - 1).map(|j| 0.01 * (j as f64 + 0.5).cos()).collect();
        let x: Vec<f64> = (0..k)
            .map(|i| q.iter().zip(&p.shapes).map(|(qj, v)| qj * v[i]).sum())
            .collect();
        let lengths: Vec<f64> = (0..k).map(|i| 1.0 + x[(i + 1) % k] - x[i]).collect();
        let got = p.modal(&lengths).unwrap();
        for (g, want) in got.iter().zip(&q) {
            assert!((g - want).abs() < 1e-12, "K = {k}: {g} vs {want}");
        }
    }
}

/// The seed's axial data measure only some segments of the ring. With `ring`, the first K
/// segments of a ring of R are fitted by least squares to the lowest whole modes (and a constant
/// for the unknown mean strain). Simulated peristalsis on R = 10 segments: the first axial pair
/// driven at its own frequency as a travelling wave, over weak thermal noise; only K = 7
/// segments written. (Under pure equipartition every mode carries the same strain variance, so
/// the unresolved modes alias into the fitted ones: a truncated fit needs a dominant rhythm,
/// as the seed's band-pass filter acknowledges.)
#[test]
fn a_partial_ring_of_segments() {
    use theory_search::dynamics::Forcing;
    let (omega, lambda1) = (1.0f64, 2.0 - 2.0 * (std::f64::consts::PI / 5.0).cos());
    let w1 = omega * lambda1.sqrt();
    let drive = |mode: usize, phase: f64| Forcing {
        field: "x".into(),
        mode,
        constant: 0.0,
        amplitude: 1e-3,
        frequency: w1,
        phase,
    };
    let config = Config {
        points: 11,
        order: 4,
        dt: 0.5,
        steps: 39_999,
        every: 1,
        temperature: 1e-7,
        seed: 5,
        initial: Vec::new(),
        forcing: vec![drive(1, 0.0), drive(2, -std::f64::consts::FRAC_PI_2)],
    };
    let mut params = Params::default();
    params.set("omega_s", omega).unwrap();
    let mut text = String::new();
    simulate(&Model::larva(), &params, &config, |smp| {
        assert_eq!(smp.positions[0].len(), 10);
        text += &length_row(smp.t, &smp.positions[0], 7, true);
        Ok(())
    })
    .unwrap();
    let mut s = FitSettings::new(InputKind::Lengths);
    s.window = Some(2048);
    s.fit_modes = 2;
    s.recording.ring = Some(10);
    let r = larva_fit(&text, &s).unwrap();
    // Six unknowns from seven strains: the three lowest pairs.
    assert_eq!((r.points, r.model_points, r.modes.len()), (7, 11, 6));
    assert!((r.omega / omega - 1.0).abs() < 0.01, "ω = {}", r.omega);
    assert!(
        r.mode_overlap[0] > 0.99 && r.mode_overlap[1] > 0.99,
        "{:?}",
        r.mode_overlap
    );
    assert!(r.pca_variance_share[0] + r.pca_variance_share[1] > 0.95);
    // A truncated ring says what its numbers can mean; a whole ring has no such caution.
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("7 of 10 ring segments")),
        "{:?}",
        r.warnings
    );
    // Without the ring the same data are read as a closed ring of 7: a different body.
    s.recording.ring = None;
    let whole = larva_fit(&text, &s).unwrap();
    assert_eq!(whole.model_points, 8);
    // No ring caution; the driven peristaltic wave (the first axial pair driven in quadrature)
    // is named as such (`fit/wave.rs`).
    assert!(
        !whole.warnings.iter().any(|w| w.contains("ring segments")),
        "{:?}",
        whole.warnings
    );
    assert!(
        whole
            .warnings
            .iter()
            .any(|w| w.contains("a driven travelling wave")),
        "{:?}",
        whole.warnings
    );
    s.recording.ring = Some(6);
    assert!(larva_fit(&text, &s)
        .unwrap_err()
        .to_string()
        .contains("cannot hold"));
}

/// A worm's axial field has free ends: its strains do not sum to zero, so dividing each frame by
/// its own mean length would hide the total stretch. The fit measures strains against one rest
/// length (the first frame's mean) and gives back the scales.
#[test]
fn segment_lengths_of_a_free_axial_field() {
    let worm = Model::from_toml(include_str!("../tables/models/worm.toml")).unwrap();
    let mut params = Params::default();
    params.set("omega_s", 1.5).unwrap();
    let config = Config {
        points: 9,
        order: 4,
        dt: 0.5,
        steps: 39_999,
        every: 1,
        temperature: 1e-4,
        seed: 13,
        initial: Vec::new(),
        forcing: Vec::new(),
    };
    let mut text = String::new();
    simulate(&worm, &params, &config, |smp| {
        text += &length_row(smp.t, &smp.positions[0], 8, false);
        Ok(())
    })
    .unwrap();
    let mut s = FitSettings::new(InputKind::Lengths);
    s.window = Some(2048);
    s.fit_modes = 2;
    let r = fit(Cursor::new(&text), &worm, &Params::default(), &s).unwrap();
    assert_eq!((r.points, r.model_points, r.modes.len()), (8, 9, 8));
    assert!((r.omega / 1.5 - 1.0).abs() < 0.03, "ω = {}", r.omega);
    assert!(
        r.mode_overlap[0] > 0.98 && r.mode_overlap[1] > 0.98,
        "{:?}",
        r.mode_overlap
    );
}
