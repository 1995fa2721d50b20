//! Figures on paper: text of at least 7 pt at every printed width, every character in the
//! embedded font, no legend over data, and PNG/PDF files of the width asked for. Each check reads
//! the written SVG, PNG or PDF back (geometry from the output, not from the layout code).

use std::sync::{Arc, Mutex};

use theory_search::figures::{figure, FigureError, FigureSettings, Format, Page, FIGURES};
use theory_search::modal::Params;
use theory_search::model::Model;
use theory_search::theory::Theory;

const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models");

fn settings(width_mm: f64) -> FigureSettings {
    FigureSettings {
        samples: 5_000,
        page: Page {
            width_mm,
            ..Page::default()
        },
        ..FigureSettings::default()
    }
}

/// (what, SVG text) of each figure.
type Svgs = Vec<(String, String)>;

/// Every figure every shipped model can make, at `width_mm`, as the SVG file says it; made once
/// per width for all the tests of this file.
fn all_svgs(width_mm: f64) -> Arc<Svgs> {
    static MADE: Mutex<Vec<(u64, Arc<Svgs>)>> = Mutex::new(Vec::new());
    // Held while making: one test makes a width, the others wait for it (the fit's figures go
    // through a directory named by the width).
    let mut made = MADE.lock().unwrap();
    let key = width_mm.to_bits();
    if let Some((_, svgs)) = made.iter().find(|(k, _)| *k == key) {
        return svgs.clone();
    }
    let svgs = Arc::new(make_svgs(width_mm));
    made.push((key, svgs.clone()));
    svgs
}

fn make_svgs(width_mm: f64) -> Svgs {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(MODELS).unwrap() {
        let path = entry.unwrap().path();
        let model = Model::from_toml(&std::fs::read_to_string(&path).unwrap()).unwrap();
        // The tethered filament is nonlinear: it has no modal theory to draw.
        let Ok(theory) = Theory::new(model, 4, 12, Params::default()) else {
            continue;
        };
        let s = settings(width_mm);
        for name in FIGURES {
            match figure(name, &theory, &s) {
                Ok(svg) => out.push((
                    format!("{} {name} at {width_mm} mm", path.display()),
                    String::from_utf8(s.page.encode(&svg).unwrap()).unwrap(),
                )),
                Err(FigureError::Behaviour(b)) if b.is_missing_structure() => {}
                Err(e) => panic!("{name}: {e}"),
            }
        }
    }
    out.extend(fit_svgs(width_mm));
    out.extend(recording_svgs(width_mm));
    out
}

/// The fit's and `discover`'s figures of a real worm (WormPose), in seconds.
fn recording_svgs(width_mm: f64) -> Vec<(String, String)> {
    let data = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/data/celegans_wormpose_15fps_52pts.csv"
    );
    let crawler = format!("{MODELS}/crawler.toml");
    let width = width_mm.to_string();
    let runs: [(&[&str], &[&str]); 2] = [
        (
            &["fit", data, "--time-unit", "s"],
            &["fit_summary.svg", "fit_verdict.svg"],
        ),
        (
            &[
                "discover",
                data,
                "--model",
                &crawler,
                "--active",
                "--time-unit",
                "s",
            ],
            &["discover_spectra.svg"],
        ),
    ];
    let mut svgs = Vec::new();
    for (args, names) in runs {
        let args = [args, &["--figure-width", &width]].concat();
        for (name, svg) in names.iter().zip(common::figures_written(&args, names)) {
            svgs.push((format!("the worm's {name} at {width_mm} mm"), svg));
        }
    }
    svgs
}

/// The fit's figures of the example recording, written by the command.
fn fit_svgs(width_mm: f64) -> Vec<(String, String)> {
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/examples/midlines.csv");
    let width = width_mm.to_string();
    let names = ["fit_shapes.svg", "fit_summary.svg", "fit_verdict.svg"];
    let args = ["fit", example, "--figure-width", &width];
    let mut svgs = Vec::new();
    for (name, svg) in names.iter().zip(common::figures_written(&args, &names)) {
        svgs.push((format!("{name} at {width_mm} mm"), svg));
    }
    svgs
}

/// The value of attribute `name` in the element text `tag`.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let at = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    tag[at..].split('"').next()
}

fn num(tag: &str, name: &str) -> f64 {
    attr(tag, name).unwrap().parse().unwrap()
}

/// Each element `<kind …>` of the SVG, in document order, with its text content.
fn elements(svg: &str) -> Vec<(&str, &str, &str)> {
    svg.split('<')
        .skip(1)
        .filter(|e| !e.starts_with('/'))
        .map(|e| {
            let kind = e.split([' ', '>', '/']).next().unwrap();
            let (tag, text) = e.split_once('>').unwrap_or((e, ""));
            (kind, tag, text.trim())
        })
        .collect()
}

#[test]
fn text_prints_at_seven_points_or_more_at_every_width() {
    for width in [60.0, 85.0, 180.0, 300.0] {
        for (what, svg) in all_svgs(width).iter() {
            let root = elements(svg)[0].1;
            let printed: f64 = attr(root, "width")
                .and_then(|w| w.strip_suffix("mm"))
                .unwrap_or_else(|| panic!("{what}: width not in mm"))
                .parse()
                .unwrap();
            assert_eq!(printed, width, "{what}");
            let view_w: f64 = attr(root, "viewBox")
                .unwrap()
                .split(' ')
                .nth(2)
                .unwrap()
                .parse()
                .unwrap();
            // Scripts (`<tspan>`, c_y's y) too: none under 7 pt.
            let smallest = elements(svg)
                .iter()
                .filter(|e| e.0 == "text" || e.0 == "tspan")
                .map(|e| num(e.1, "font-size"))
                .fold(f64::INFINITY, f64::min);
            let points = smallest * printed / view_w / 25.4 * 72.0;
            assert!(points >= 7.0, "{what}: {points:.2} pt");
        }
    }
}

#[test]
fn at_a_single_column_no_figure_is_taller_than_twice_its_width() {
    for (what, svg) in all_svgs(85.0).iter() {
        let root = elements(svg)[0].1;
        let view: Vec<f64> = attr(root, "viewBox")
            .unwrap()
            .split(' ')
            .map(|v| v.parse().unwrap())
            .collect();
        let (w, h) = (view[2], view[3]);
        assert!(h <= 2.0 * w, "{what}: {h} tall on {w} wide");
    }
}

#[test]
fn every_character_has_a_glyph_in_the_embedded_font() {
    let font = ttf_parser::Face::parse(dejavu::sans::regular(), 0).unwrap();
    let mut seen = std::collections::BTreeSet::new();
    for (what, svg) in all_svgs(180.0).iter() {
        let texts = elements(svg);
        for (_, _, text) in texts.iter().filter(|e| e.0 == "text" || e.0 == "tspan") {
            for c in text.chars() {
                if seen.insert(c) {
                    assert!(font.glyph_index(c).is_some(), "{what}: no glyph for {c:?}");
                }
            }
        }
    }
    assert!(
        seen.contains(&'θ') && seen.contains(&'√'),
        "Greek and maths were checked"
    );
}

/// Whether the segment p–q comes into the open box (x0, y0, x1, y1).
fn crosses(p: (f64, f64), q: (f64, f64), b: (f64, f64, f64, f64)) -> bool {
    let steps = ((q.0 - p.0).hypot(q.1 - p.1) / 0.5).ceil().max(1.0) as usize;
    (0..=steps).any(|k| {
        let t = k as f64 / steps as f64;
        let (x, y) = (p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1));
        x > b.0 && x < b.2 && y > b.1 && y < b.3
    })
}

#[test]
fn no_legend_covers_data() {
    let mut legends = 0;
    for width in [85.0, 180.0] {
        for (what, svg) in all_svgs(width).iter() {
            let all = elements(svg);
            for (k, legend) in all.iter().enumerate() {
                // plotters' legend: a white box at opacity 0.85, drawn after the panel's data.
                if !(legend.0 == "rect" && attr(legend.1, "opacity") == Some("0.85")) {
                    continue;
                }
                legends += 1;
                let (x, y) = (num(legend.1, "x"), num(legend.1, "y"));
                let b = (
                    x,
                    y,
                    x + num(legend.1, "width"),
                    y + num(legend.1, "height"),
                );
                for (kind, tag, _) in &all[..k] {
                    let hit = match *kind {
                        "polyline" => {
                            let pts: Vec<(f64, f64)> = attr(tag, "points")
                                .unwrap()
                                .split_whitespace()
                                .map(|p| {
                                    let (a, c) = p.split_once(',').unwrap();
                                    (a.parse().unwrap(), c.parse().unwrap())
                                })
                                .collect();
                            pts.windows(2).any(|w| crosses(w[0], w[1], b))
                        }
                        "circle" => {
                            let (cx, cy, r) = (num(tag, "cx"), num(tag, "cy"), num(tag, "r"));
                            cx + r > b.0 && cx - r < b.2 && cy + r > b.1 && cy - r < b.3
                        }
                        // Bars and chart cells; not the white background or another legend.
                        "rect" if attr(tag, "fill") != Some("#FFFFFF") => {
                            let (rx, ry) = (num(tag, "x"), num(tag, "y"));
                            let (rw, rh) = (num(tag, "width"), num(tag, "height"));
                            rx + rw > b.0 && rx < b.2 && ry + rh > b.1 && ry < b.3
                        }
                        _ => false,
                    };
                    assert!(
                        !hit,
                        "{what}: the legend at {b:?} covers a {kind}: {tag:.120}"
                    );
                }
            }
        }
    }
    assert!(legends > 50, "{legends} legends checked");
}

/// The box (x0, y0, x1, y1) a `<text>` element's text takes, from its anchor, size and turn
/// (DejaVu Sans' 0.6 em a character; its scripts counted as characters).
fn text_box(tag: &str, text: &str) -> (f64, f64, f64, f64) {
    let (x, y, size) = (num(tag, "x"), num(tag, "y"), num(tag, "font-size"));
    let len = 0.6 * size * text.chars().count() as f64;
    if attr(tag, "transform").is_some_and(|t| t.starts_with("rotate(270")) {
        // Turned a quarter left about (x, y), centred there, its top towards x.
        return (x, y - len / 2.0, x + size, y + len / 2.0);
    }
    let x0 = match attr(tag, "text-anchor") {
        Some("middle") => x - len / 2.0,
        Some("end") => x - len,
        _ => x,
    };
    let (y0, y1) = match attr(tag, "dy") {
        Some("0.76em") => (y, y + size),
        Some("0.5ex") => (y - size / 2.0, y + size / 2.0),
        _ => (y - size, y),
    };
    (x0, y0, x0 + len, y1)
}

/// An axis name runs along its chart, never into a caption, a key or the panel beside it: no
/// turned text (a y axis' name) overlaps any other text, at 85 and 180 mm.
#[test]
fn no_axis_name_runs_into_other_text() {
    let mut names = 0;
    for width in [85.0, 180.0] {
        for (what, svg) in all_svgs(width).iter() {
            let all = common::svg_texts(svg);
            let boxes: Vec<_> = all
                .iter()
                .map(|(tag, t)| (tag, t, text_box(tag, t)))
                .collect();
            for (tag, text, b) in boxes.iter().filter(|b| b.0.contains("rotate(270")) {
                names += 1;
                for (other, o, c) in boxes.iter().filter(|o| !o.0.contains("rotate(")) {
                    let overlap =
                        b.0 < c.2 - 1.0 && c.0 < b.2 - 1.0 && b.1 < c.3 - 1.0 && c.1 < b.3 - 1.0;
                    assert!(
                        !overlap,
                        "{what}: the axis name {text:?} ({tag:.60}) runs into {o:?} ({other:.60})"
                    );
                }
            }
        }
    }
    assert!(names > 100, "{names} axis names checked");
}

mod common;

use common::binary as cli;

#[test]
fn the_command_writes_png_and_pdf_of_the_width_asked_for() {
    let dir_held = common::scratch("png");
    let dir = dir_held.path();
    let d = dir.to_str().unwrap();
    let (code, out, err) = cli(&[
        "figures",
        "--only",
        "spectrum",
        "--format",
        "png",
        "--width",
        "85",
        "--dpi",
        "200",
        "--figures",
        d,
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(
        out,
        format!("wrote {}\n", dir.join("spectrum.png").display())
    );
    let png = resvg::tiny_skia::Pixmap::load_png(dir.join("spectrum.png")).unwrap();
    // 85 mm at 200 dpi.
    assert_eq!(png.width(), (85.0f64 / 25.4 * 200.0).ceil() as u32);
    let dark = png.pixels().iter().filter(|p| p.red() < 100).count();
    assert!(dark > 1000, "text and axes are drawn: {dark}");
    let (code, _, err) = cli(&[
        "figures",
        "--only",
        "mathieu.svg",
        "--format",
        "pdf",
        "--width",
        "120",
        "--figures",
        d,
    ]);
    assert_eq!(code, 0, "{err}");
    let pdf = std::fs::read(dir.join("mathieu.pdf")).unwrap();
    let text = String::from_utf8_lossy(&pdf);
    assert!(text.starts_with("%PDF-"));
    // 120 mm = 340.157 pt.
    assert!(text.contains("/MediaBox [0 0 340.15"), "{:.300}", text);
    // Gone, so that the refusals below are seen to write nothing.
    std::fs::remove_dir_all(dir).unwrap();
    for (args, says) in [
        (
            vec!["--width", "NaN"],
            "figure width NaN mm is not in 60..=600 mm",
        ),
        (
            vec!["--width", "10"],
            "figure width 10 mm is not in 60..=600 mm",
        ),
        (
            vec!["--dpi", "1e6"],
            "resolution 1000000 dpi is not in 30..=1200 dpi",
        ),
        (vec!["--format", "gif"], "invalid value 'gif'"),
    ] {
        let mut all = vec!["figures", "--figures", d];
        all.extend(args);
        let (code, _, err) = cli(&all);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(says), "{err}");
        assert!(
            !dir.exists(),
            "nothing written before the settings are checked"
        );
    }
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/examples/midlines.csv");
    let (code, _, err) = cli(&["fit", example, "--figures", d, "--figure-width=-1"]);
    assert_eq!(code, 2);
    assert_eq!(err, "error: figure width -1 mm is not in 60..=600 mm\n");
    assert!(Page {
        format: Format::Png,
        ..Page::default()
    }
    .check()
    .is_ok());
}
