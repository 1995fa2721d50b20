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
    has("mode_shapes.svg", "point j (0 = tail)");
    has("self_righting.svg", "point j (0 = tail)");
    has("self_righting.svg", "Q (rad·ωₜ²)");
    has("self_righting.svg", "Θ₁ (rad)");
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

/// The text of each `<text>` element of `svg`, its scripts (`<tspan>`) joined in.
fn texts(svg: &str) -> Vec<String> {
    common::svg_texts(svg).into_iter().map(|t| t.1).collect()
}

/// How many `<text>` elements of `svg` read exactly `label`.
fn count(svg: &str, label: &str) -> usize {
    texts(svg).iter().filter(|t| *t == label).count()
}

/// A mode number keeps its colour in every panel, so each "mode k" is one entry of one key for
/// the whole figure (a mode drawn in another colour in another row would need a key of its
/// own there): at 85 mm and at 180 mm.
#[test]
fn a_mode_keeps_its_colour_across_panels() {
    for width_mm in [85.0, 180.0] {
        let mut s = settings();
        s.page.width_mm = width_mm;
        let svg = figure("mode_shapes.svg", &larva(12), &s).unwrap();
        for k in 1..=5 {
            let label = format!("mode {k}");
            assert_eq!(count(&svg, &label), 1, "{label} at {width_mm} mm");
        }
        // One word for the body's places, as in the fit's figures.
        assert!(!svg.contains("segment"), "at {width_mm} mm");
    }
}

/// The lines of the panel captions of `svg` (text at the caption's size), grouped by panel:
/// lines of one caption are one line apart at the same x.
fn caption_lines(svg: &str, size: &str) -> Vec<usize> {
    let mut at: Vec<(i64, f64)> = svg
        .split("<text")
        .skip(1)
        .filter(|t| {
            t.split('>')
                .next()
                .unwrap()
                .contains(&format!("font-size=\"{size}"))
        })
        .map(|t| {
            let get = |name: &str| -> f64 {
                let v = t.split(&format!(" {name}=\"")).nth(1).unwrap();
                v.split('"').next().unwrap().parse().unwrap()
            };
            (get("x") as i64, get("y"))
        })
        .collect();
    at.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut groups: Vec<(i64, f64, usize)> = Vec::new();
    for (x, y) in at {
        match groups.last_mut() {
            Some(g) if g.0 == x && y - g.1 < 30.0 => {
                g.1 = y;
                g.2 += 1;
            }
            _ => groups.push((x, y, 1)),
        }
    }
    groups.into_iter().map(|g| g.2).collect()
}

/// At 85 mm the mode-shape panels' captions take at most two lines each.
#[test]
fn mode_shape_captions_take_two_lines_at_85_mm() {
    let mut s = settings();
    s.page.width_mm = 85.0;
    let svg = figure("mode_shapes.svg", &larva(12), &s).unwrap();
    // CAPTION (20) as plotters writes it: 20 / 1.24 px.
    let lines = caption_lines(&svg, "16.129");
    assert_eq!(lines.len(), 4, "{lines:?}");
    assert!(lines.iter().all(|&n| n <= 2), "{lines:?}");
}

/// Self-righting: the hooks' attachment, marked in four panels, is one key entry for the
/// figure, drawn in black (not a pale tint of the tail's blue), and the torque and the mode
/// carry their units.
#[test]
fn self_righting_marks_the_attachment_once_in_its_own_colour() {
    for width_mm in [85.0, 180.0] {
        let mut s = settings();
        s.page.width_mm = width_mm;
        let svg = figure("self_righting.svg", &larva(12), &s).unwrap();
        assert_eq!(count(&svg, "mouth hooks attach"), 1, "at {width_mm} mm");
        // The old marker: plotters' BLUE at 0.6 opacity.
        assert!(!svg.contains("stroke=\"#0000FF\""), "at {width_mm} mm");
        let markers = svg
            .matches("<polyline fill=\"none\" stroke=\"#000000\"")
            .count();
        assert_eq!(markers, 4, "the attachment in four panels at {width_mm} mm");
        // The sweep's critical damping is the figure's second marker: grey and dashed.
        assert!(svg.contains("stroke=\"#696969\" stroke-width=\"2\" stroke-dasharray"));
    }
}

/// The marks a figure sets its scripts with never reach the file: every one became a span.
#[test]
fn no_script_mark_is_left_in_a_figure() {
    for name in larva_figures() {
        let svg = figure(name, &larva(12), &settings()).unwrap();
        let left = svg
            .chars()
            .filter(|c| ('\u{E000}'..='\u{E002}').contains(c));
        assert_eq!(left.count(), 0, "{name}");
        assert_eq!(
            svg.matches("<tspan").count(),
            svg.matches("</tspan>").count()
        );
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
    for width_mm in [85.0, 180.0] {
        let mut s = settings();
        s.page.width_mm = width_mm;
        let svg = figure("forward_backward.svg", &theory, &s).unwrap();
        // The simulated 1 : 2 point is App. C's: one line, its key naming both, drawn in black
        // (no series' colour).
        let said = texts(&svg);
        let joined = said
            .iter()
            .filter(|t| {
                t.starts_with("simulated 1 : 2 at G = 0.70") && t.ends_with("= App. C: √2/2")
            })
            .count();
        assert_eq!(joined, 1, "{said:?}");
        let lines = svg
            .matches("<polyline fill=\"none\" stroke=\"#000000\"")
            .count();
        assert_eq!(lines, 1, "one marker line at {width_mm} mm");
        // Typeset: ω with subscripts b and f, g with subscript x; no raw underscores.
        assert!(said.iter().any(|t| t == "ωb/ωf"), "{said:?}");
        assert!(svg.contains(">b</tspan>/ω<tspan"), "ω_b/ω_f not typeset");
        assert!(!said.iter().any(|t| t.contains('_')), "{said:?}");
        // The title (TITLE, 22 / 1.24 px) on at most two lines at 85 mm.
        let title = caption_lines(&svg, "17.74");
        assert_eq!(title.len(), 1, "{title:?}");
        assert!(title[0] <= 2, "{title:?} at {width_mm} mm");
    }
}

const WORMPOSE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../shared/data/celegans_wormpose_15fps_52pts.csv"
);

/// Run the binary with `args` and `--figures` a scratch directory; the SVG `name` it wrote.
fn written(args: &[&str], name: &str) -> String {
    common::figures_written(args, &[name]).remove(0)
}

/// The fit of a real worm (WormPose, in seconds): the verdict's marks keep one colour across
/// its panels ("other modes" one entry), its exponents are superscripts, its variances carry a
/// unit, the mode whose fit failed (σ² ≈ 10⁻¹⁰) lies off scale as an arrow with its value and
/// squashes nothing; each figure names its frequency estimate; ω and β carry units.
#[test]
fn the_fit_figures_of_a_worm_say_units_estimates_and_off_scale_points() {
    let args = ["fit", WORMPOSE, "--time-unit", "s"];
    let verdict = written(&args, "fit_verdict.svg");
    let said = texts(&verdict);
    // Every word of the figure, axis names on two lines joined.
    let words = said.join(" ");
    assert_eq!(count(&verdict, "other modes"), 1, "{said:?}");
    assert!(!verdict.contains("λ^"), "a raw exponent");
    assert!(verdict.contains("<tspan baseline-shift=\"super\""));
    assert!(words.contains("spacings²)"), "{words}");
    assert!(words.contains("fitted Ωᵢ (rad per s)"), "{words}");
    assert_eq!(
        verdict.matches("<polygon").count(),
        1,
        "one point off scale"
    );
    assert_eq!(count(&verdict, "−10.3"), 1, "{said:?}");
    // The axis reaches the rest, not the point off it: no tick at −10 or below −5.
    assert!(
        !said.iter().any(|t| t == "−10" || t == "−8" || t == "−6"),
        "{said:?}"
    );
    let summary = written(&args, "fit_summary.svg");
    let said = texts(&summary);
    let title = said[..2].join(" ");
    assert!(
        title.contains("rad per s, β = ") && title.contains(" s² (paper Fig. 2)"),
        "{title}"
    );
    let words = said.join(" ");
    assert!(words.contains("2π × each spectrum's peak"), "{words}");
    // The estimate `--estimator` chose, as the report holds it.
    let centroid = written(
        &[
            "fit",
            WORMPOSE,
            "--time-unit",
            "s",
            "--estimator",
            "centroid",
        ],
        "fit_summary.svg",
    );
    let words = texts(&centroid).join(" ");
    assert!(words.contains("2π × each spectrum's centroid"), "{words}");
}

/// `discover`'s figure of a real worm in seconds: its axes in seconds (no "time unit"), the
/// equation's coefficients typeset (c with a subscript y, never `c_y`), the variance with a
/// unit, and every axis name within its chart (on two lines where one would run past it).
#[test]
fn the_discover_figure_of_a_worm_is_typeset_in_its_units() {
    let crawler = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/crawler.toml");
    let args = [
        "discover",
        WORMPOSE,
        "--model",
        crawler,
        "--active",
        "--time-unit",
        "s",
    ];
    let svg = written(&args, "discover_spectra.svg");
    let said = texts(&svg);
    assert!(!said.iter().any(|t| t.contains('_')), "{said:?}");
    assert!(svg.contains(">y</tspan>"), "no subscript y");
    assert!(!svg.contains("time unit"));
    assert!(said
        .iter()
        .any(|t| t == "frequency (cycles per s)" || t == "per s)"));
    assert!(said.iter().any(|t| t.contains("spacings²)")), "{said:?}");
}
