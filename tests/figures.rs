//! The SVG figures: every one renders from the library, carries labelled axes and its data, and
//! the command stays quiet when its output is piped.

mod common;

use std::process::Command;

use theory_search::figures::{figure, FigureSettings, FIGURES};
use theory_search::modal::Params;
use theory_search::model::Model;
use theory_search::theory::Theory;

fn larva(points: usize) -> Theory {
    Theory::new(Model::larva(), 4, points, Params::default()).unwrap()
}

fn settings() -> FigureSettings {
    FigureSettings {
        samples: 20_000,
        ..FigureSettings::default()
    }
}

/// The larva's figures: every one but Fig. 11, which needs an `[active]` section (the
/// peristalsis model's; its own test below).
fn larva_figures() -> impl Iterator<Item = &'static str> {
    FIGURES.into_iter().filter(|n| *n != "forward_backward.svg")
}

#[test]
fn every_figure_renders_with_axes_and_data() {
    for name in larva_figures() {
        let svg = figure(name, &larva(settings().points), &settings()).unwrap();
        assert!(svg.starts_with("<svg"), "{name}");
        assert!(svg.trim_end().ends_with("</svg>"), "{name}");
        let drawn = svg.matches("<polyline").count()
            + svg.matches("<rect").count()
            + svg.matches("<circle").count();
        assert!(drawn > 20, "{name}: {drawn} elements");
        assert!(svg.matches("<text").count() > 10, "{name}: no labels");
        assert!(!svg.contains("NaN"), "{name} has NaN coordinates");
    }
}

#[test]
fn figures_carry_their_axis_units() {
    let s = settings();
    let has = |name: &str, label: &str| {
        let svg = figure(name, &larva(s.points), &s).unwrap();
        assert!(svg.contains(label), "{name} lacks {label:?}");
    };
    has("self_righting.svg", "time t (1/ωₜ)");
    has("self_righting.svg", "damping ratio ζ₁");
    has("mode_shapes.svg", "segment j (0 = tail)");
    has("mathieu.svg", "drive frequency ω/λ");
    has("bend_angle.svg", "bend angle (degrees)");
    has("free_energy.svg", "conserved momentum M");
}

/// The mode-shape figure draws the solver's shapes: one polyline of N points per mode.
#[test]
fn mode_shapes_draw_one_line_per_mode_of_n_points() {
    for n in [8usize, 15] {
        let s = FigureSettings {
            points: n,
            ..settings()
        };
        let svg = figure("mode_shapes.svg", &larva(s.points), &s).unwrap();
        let lines: Vec<&str> = svg
            .split("<polyline")
            .skip(1)
            .filter_map(|p| p.split("points=\"").nth(1))
            .map(|p| p.split('"').next().unwrap())
            .collect();
        // x is periodic on N − 1 distinct points; the others on N.
        let full = lines
            .iter()
            .filter(|l| l.split_whitespace().count() == n)
            .count();
        let periodic = lines
            .iter()
            .filter(|l| l.split_whitespace().count() == n - 1)
            .count();
        assert_eq!((periodic, full), (4, 12), "N = {n}");
    }
}

#[test]
fn unknown_figure_is_an_error() {
    let e = figure("nope.svg", &larva(12), &settings()).unwrap_err();
    assert!(e.to_string().contains("mode_shapes.svg"));
}

#[test]
fn the_command_writes_quietly_and_fails_cleanly() {
    let dir_held = common::scratch("figures");
    let dir = dir_held.path();
    let out = Command::new(env!("CARGO_BIN_EXE_theory-search"))
        .args(["figures", "--samples", "5000", "--out"])
        .arg(dir)
        .output()
        .unwrap();
    assert!(out.status.success());
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for name in larva_figures() {
        assert!(dir.join(name).is_file(), "{name}");
    }
    // The larva has no `[active]` section: Fig. 11 is skipped, and says why.
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        said.contains(
            "skipped forward_backward.svg: the \"larva\" model gives x no gyroscopic force"
        ),
        "{said}"
    );
    // In another format the skipped figure is named by the file it would have been.
    let png_held = common::scratch("figures-png");
    let out = Command::new(env!("CARGO_BIN_EXE_theory-search"))
        .args(["figures", "--samples", "5000", "--format", "png", "--out"])
        .arg(png_held.path())
        .output()
        .unwrap();
    assert!(out.status.success());
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.contains("skipped forward_backward.png: "), "{said}");
    assert!(!said.contains(".svg"), "{said}");
    // A file where the directory should be.
    let file = dir.join("mode_shapes.svg");
    let out = Command::new(env!("CARGO_BIN_EXE_theory-search"))
        .args(["figures", "--out"])
        .arg(&file)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: cannot create"), "{err}");
    let out = Command::new(env!("CARGO_BIN_EXE_theory-search"))
        .args(["figures", "--only", "x.svg", "--out"])
        .arg(dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

/// docs/commands.md shows `tables/figures/self_righting.svg`: it must be what the engine draws now.
#[test]
fn readme_figure_is_fresh() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let svg = figure("self_righting.svg", &larva(12), &FigureSettings::default()).unwrap();
    let path = root.join("tables/figures/self_righting.svg");
    theory_search::artifacts::ensure_file_contents(&path, &svg).unwrap();
}

/// Every figure rendered to pixels (resvg, without text): it parses, and its drawing covers
/// more than 1 % of the canvas in more than three colours.
#[test]
fn every_figure_renders_to_pixels() {
    let s = settings();
    let theory = larva(s.points);
    for name in larva_figures() {
        let svg = figure(name, &theory, &s).unwrap();
        let tree = resvg::usvg::Tree::from_str(&svg, &resvg::usvg::Options::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let size = tree.size().to_int_size();
        let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height()).unwrap();
        resvg::render(
            &tree,
            resvg::tiny_skia::Transform::default(),
            &mut pixmap.as_mut(),
        );
        let pixels = pixmap.pixels();
        // Not white (nor transparent): axes, grid and data.
        let inked = pixels
            .iter()
            .filter(|p| p.alpha() > 0 && (p.red() < 200 || p.green() < 200 || p.blue() < 200))
            .count();
        let share = inked as f64 / pixels.len() as f64;
        assert!(
            share > 0.01,
            "{name}: only {:.2} % of the canvas is drawn",
            100.0 * share
        );
        let colours: std::collections::HashSet<(u8, u8, u8)> = pixels
            .iter()
            .filter(|p| p.alpha() == 255)
            .map(|p| (p.red() / 32, p.green() / 32, p.blue() / 32))
            .collect();
        assert!(colours.len() > 3, "{name}: {} colours", colours.len());
    }
}

/// The fit's figures speak the recording's time unit (`--time-unit`), as its report does; a
/// unit that could break the markup is refused (from either face: the library checks it).
#[test]
fn fit_figures_carry_the_time_unit() {
    let dir_held = common::scratch("fit-units");
    let dir = dir_held.path();
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/examples/midlines.csv");
    let run = |unit: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_theory-search"))
            .args(["fit", example, "--time-unit", unit, "--figures"])
            .arg(dir)
            .output()
            .unwrap()
    };
    assert!(run("s").status.success());
    for name in ["fit_verdict.svg", "fit_summary.svg"] {
        let svg = std::fs::read_to_string(dir.join(name)).unwrap();
        assert!(svg.contains("per s)"), "{name} does not speak seconds");
        assert!(!svg.contains("per time unit"), "{name}");
    }
    let bad = run("<s>");
    assert_eq!(bad.status.code(), Some(2));
}

/// Panels that share every series show their key once: the bending fields y and z draw modes
/// 2–5 alike, so "mode 5" is written once (one key across their row), not once a panel; the
/// axial and torsional panels (modes 1–4) share theirs too. At 85 mm and at 180 mm.
#[test]
fn panels_sharing_series_share_one_key() {
    for width_mm in [85.0, 180.0] {
        let mut s = settings();
        s.page.width_mm = width_mm;
        let svg = figure("mode_shapes.svg", &larva(12), &s).unwrap();
        for label in ["mode 5", "mode 1"] {
            assert_eq!(svg.matches(label).count(), 1, "{label} at {width_mm} mm");
        }
        // Modes 2–4 are in both keys.
        assert_eq!(svg.matches("mode 2").count(), 2, "at {width_mm} mm");
    }
}

/// Fig. 11 from simulation: the peristalsis model's ring under its gyroscopic force, every
/// simulated frequency on the dispersion relation ω₁(√(G² + 4) ± G)/2 (an independent oracle:
/// the analytic roots, not the integrator), the 1 : 2 point at App. C's √2/2, and the figure.
#[test]
fn forward_and_backward_peristalsis_split_as_app_c_says() {
    use theory_search::behaviour::{forward_backward, PAPER_COUPLING};
    let model = Model::from_toml(include_str!("../tables/models/peristalsis.toml")).unwrap();
    for points in [4, 12, 31] {
        let theory = Theory::new(model.clone(), 4, points, Params::default()).unwrap();
        let r = forward_backward(&theory, &[0.0, 0.3, 0.9, 1.4]).unwrap();
        for s in &r.sweep {
            let s2 = (s.coupling * s.coupling + 4.0).sqrt();
            let (f, b) = ((s2 + s.coupling) / 2.0, (s2 - s.coupling) / 2.0);
            assert!(
                (s.forward / f - 1.0).abs() < 1e-9,
                "{points}: {s:?} against {f}"
            );
            assert!(
                (s.backward / b - 1.0).abs() < 1e-9,
                "{points}: {s:?} against {b}"
            );
        }
        assert!(
            (r.half / PAPER_COUPLING - 1.0).abs() < 1e-7,
            "1 : 2 at {}",
            r.half
        );
        assert_eq!(r.coefficient, "g_x");
    }
    // A ring of two distinct points has only k = π: no wave runs either way.
    let tiny = Theory::new(model.clone(), 4, 3, Params::default()).unwrap();
    let e = forward_backward(&tiny, &[0.5]).unwrap_err();
    assert!(
        e.is_missing_structure() && e.to_string().contains("at least 4 points"),
        "{e}"
    );
    let theory = Theory::new(model, 4, 12, Params::default()).unwrap();
    let svg = figure("forward_backward.svg", &theory, &settings()).unwrap();
    assert!(svg.contains("App. C: √2/2") && svg.contains("simulated 1 : 2 at G = 0.70"));
}
