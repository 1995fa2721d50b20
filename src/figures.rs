//! SVG figures of the modes and the behaviour models (the paper's Figs. 2, 3, 6, 7, 8 and the
//! Mathieu chart of App. D), drawn with plotters' SVG backend.
//!
//! Text goes into the SVG as `<text>` elements, so no font library is needed to write a figure
//! (plotters' own font features stay off). Every figure is computed here from the library, never
//! read from a file; all quantities are dimensionless (time in units of the field's 1/ω, the
//! default scales ω = 1, ζ = 0.1 unless `params` says otherwise) and each axis says so.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::behaviour::{self, PairKind, RightingSettings};
use crate::theory::Theory;

/// Why a figure could not be made.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FigureError {
    /// A setting out of range, an unknown figure, or a model that cannot make it.
    #[error("{0}")]
    Invalid(String),
    /// The body cannot make this figure: it lacks a field role or the structure the figure's
    /// behaviour needs.
    #[error("{0}")]
    Body(String),
    /// A file or directory could not be written.
    #[error("{0}")]
    Io(String),
}

fn err(e: impl std::fmt::Display) -> FigureError {
    FigureError::Invalid(e.to_string())
}

/// Settings shared by the figures.
#[derive(Debug, Clone)]
pub struct FigureSettings {
    /// Points along the body.
    pub points: usize,
    /// Seed of the sampled figures.
    pub seed: u64,
    /// Samples of the sampled figures (pair density, 3-point bend).
    pub samples: usize,
}

impl Default for FigureSettings {
    fn default() -> Self {
        FigureSettings {
            points: 12,
            seed: 1,
            samples: 100_000,
        }
    }
}

/// The figures, by file name, in the order they are made.
pub const FIGURES: [&str; 11] = [
    "mode_shapes.svg",
    "spectrum.svg",
    "self_righting.svg",
    "rearing_hunching.svg",
    "asymmetry.svg",
    "equipartition.svg",
    "peristalsis.svg",
    "rolling.svg",
    "free_energy.svg",
    "bend_angle.svg",
    "mathieu.svg",
];

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Mark {
    Line,
    Dashed,
    Dots,
    /// Histogram bars of the given width; points are (left edge, height).
    Bars(f64),
}

struct Series {
    name: String,
    points: Vec<(f64, f64)>,
    mark: Mark,
}

fn series(name: impl Into<String>, points: Vec<(f64, f64)>, mark: Mark) -> Series {
    Series {
        name: name.into(),
        points,
        mark,
    }
}

/// Series drawn exactly over an earlier one join its legend entry ("y = z"), so no curve is
/// hidden without a word.
fn merge_identical(all: Vec<Series>) -> Vec<Series> {
    let mut out: Vec<Series> = Vec::new();
    for s in all {
        match out
            .iter_mut()
            .find(|o| o.points == s.points && o.mark == s.mark)
        {
            Some(o) => o.name = format!("{} = {}", o.name, s.name),
            None => out.push(s),
        }
    }
    out
}

struct Panel<'a> {
    title: &'a str,
    x: &'a str,
    y: &'a str,
    series: Vec<Series>,
    /// Vertical marker lines (x, label).
    markers: Vec<(f64, String)>,
    /// Force the y range to include 0.
    zero: bool,
}

fn panel<'a>(title: &'a str, x: &'a str, y: &'a str, series: Vec<Series>) -> Panel<'a> {
    Panel {
        title,
        x,
        y,
        series,
        markers: Vec::new(),
        zero: false,
    }
}

/// The padded range of `values` (never empty).
fn range(values: impl Iterator<Item = f64>, zero: bool) -> std::ops::Range<f64> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if zero {
        lo = lo.min(0.0);
        hi = hi.max(0.0);
    }
    if !lo.is_finite() {
        return 0.0..1.0;
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.5 * lo.abs().max(1.0)
    };
    (lo - pad)..(hi + pad)
}

/// A tick label: whole numbers without ".0", no "-0", at most four significant decimals.
fn tick(v: f64) -> String {
    if v.abs() < 1e-12 {
        return "0".into();
    }
    if (v - v.round()).abs() < 1e-9 * v.abs().max(1.0) && v.abs() < 1e9 {
        return format!("{}", v.round() as i64);
    }
    let text = format!("{v:.4}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Where the legend goes, and the y range that leaves room for it: the corner whose legend-sized
/// box holds the fewest data points; when every corner holds some, the y axis grows upward by
/// the legend's height so it sits above the data (upper right). `plot` is the plotting area's
/// size in pixels.
fn legend_place(
    p: &Panel,
    plot: (f64, f64),
    xr: &std::ops::Range<f64>,
    yr: &std::ops::Range<f64>,
) -> (SeriesLabelPosition, std::ops::Range<f64>) {
    let labels: Vec<&str> = p
        .series
        .iter()
        .map(|s| s.name.as_str())
        .chain(p.markers.iter().map(|m| m.1.as_str()))
        .filter(|n| !n.is_empty())
        .collect();
    let chars = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0);
    // plotters' legend: 11 px text rows about 15 px apart, a 16 px swatch, padding.
    let fw = ((chars as f64 * 6.5 + 50.0) / plot.0).min(0.9);
    let fh = ((labels.len() as f64 * 15.0 + 14.0) / plot.1).min(0.6);
    let (w, h) = (xr.end - xr.start, yr.end - yr.start);
    let count = |right: bool, upper: bool| {
        p.series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|&&(x, y)| {
                let fx = (x - xr.start) / w;
                let fy = (y - yr.start) / h;
                (if right { fx > 1.0 - fw } else { fx < fw })
                    && (if upper { fy > 1.0 - fh } else { fy < fh })
            })
            .count()
    };
    let (pos, n) = [
        (SeriesLabelPosition::UpperRight, count(true, true)),
        (SeriesLabelPosition::UpperLeft, count(false, true)),
        (SeriesLabelPosition::LowerRight, count(true, false)),
        (SeriesLabelPosition::LowerLeft, count(false, false)),
    ]
    .into_iter()
    .min_by_key(|(_, n)| *n)
    .unwrap_or((SeriesLabelPosition::UpperRight, 0));
    if n == 0 || labels.is_empty() {
        return (pos, yr.clone());
    }
    // Headroom: the data keep the lower 1 − fh of the axis.
    let top = yr.start + h / (1.0 - fh);
    (SeriesLabelPosition::UpperRight, yr.start..top)
}

fn color(i: usize) -> RGBColor {
    const COLORS: [RGBColor; 8] = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(255, 127, 14),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
    ];
    COLORS[i % COLORS.len()]
}

/// Curves drawn at sub-pixel precision: plotters' SVG backend rounds every coordinate to a whole
/// pixel (jagged shallow curves), so lines are written as SVG polylines with float coordinates
/// by the figure itself, at the place in the drawing order a zero-size marker of a unique
/// colour holds for them (under the legend, over the grid).
struct Curves {
    /// The marker's colour, `#0102xx`.
    marker: RGBColor,
    /// The `<polyline>` elements.
    svg: String,
}

impl Curves {
    fn new(id: usize) -> Curves {
        Curves {
            marker: RGBColor(1, 2, (id % 250) as u8 + 3),
            svg: String::new(),
        }
    }

    /// One polyline of data `points` through the chart's linear map to pixels.
    fn add(
        &mut self,
        points: &[(f64, f64)],
        pixels: &(std::ops::Range<i32>, std::ops::Range<i32>),
        ranges: (&std::ops::Range<f64>, &std::ops::Range<f64>),
        (color, dashed): (RGBColor, bool),
    ) {
        use std::fmt::Write as _;
        // plotters' own map: x from the first to the last pixel column, y from the bottom row up.
        let (x0, x1) = (pixels.0.start as f64, (pixels.0.end - 1) as f64);
        let (y0, y1) = ((pixels.1.end - 1) as f64, pixels.1.start as f64);
        let (xr, yr) = ranges;
        let dash = if dashed {
            " stroke-dasharray=\"6 4\""
        } else {
            ""
        };
        let RGBColor(r, g, b) = color;
        let _ = write!(
            self.svg,
            "<polyline fill=\"none\" stroke=\"#{r:02X}{g:02X}{b:02X}\" stroke-width=\"2\"{dash} points=\""
        );
        for &(x, y) in points {
            let px = x0 + (x1 - x0) * (x - xr.start) / (xr.end - xr.start);
            let py = y0 + (y1 - y0) * (y - yr.start) / (yr.end - yr.start);
            if px.is_finite() && py.is_finite() {
                let _ = write!(self.svg, "{px:.2},{py:.2} ");
            }
        }
        self.svg.push_str("\"/>\n");
    }

    /// Put the curves where the marker is in `svg` (the marker goes).
    fn splice(&self, svg: &mut String) {
        let RGBColor(r, g, b) = self.marker;
        let tag = format!("fill=\"#{r:02X}{g:02X}{b:02X}\"");
        if let Some(at) = svg.find(&tag) {
            let start = svg[..at].rfind('<').unwrap_or(at);
            let end = svg[at..].find("/>").map_or(at, |e| at + e + 2);
            let end = if svg[end..].starts_with('\n') {
                end + 1
            } else {
                end
            };
            svg.replace_range(start..end, &self.svg);
        }
    }
}

/// Draw one panel: axes with labels, its series and a legend; its line series come back as
/// [`Curves`] to splice into the SVG.
fn draw(area: &Area, p: &Panel, id: usize) -> Result<Curves, FigureError> {
    let mut curves = Curves::new(id);
    let xs = p.series.iter().flat_map(|s| {
        s.points.iter().flat_map(move |q| match s.mark {
            Mark::Bars(w) => vec![q.0, q.0 + w],
            _ => vec![q.0],
        })
    });
    let xr = range(xs.chain(p.markers.iter().map(|m| m.0)), false);
    let bars = p.series.iter().any(|s| matches!(s.mark, Mark::Bars(_)));
    let yr = range(
        p.series.iter().flat_map(|s| s.points.iter().map(|q| q.1)),
        p.zero || bars,
    );
    // The plotting area: the panel less the label areas, caption and margins below.
    let (pw, ph) = area.dim_in_pixel();
    let plot = (
        (pw as f64 - 56.0 - 16.0).max(50.0),
        (ph as f64 - 36.0 - 16.0 - 30.0).max(50.0),
    );
    let (legend_at, yr) = legend_place(p, plot, &xr, &yr);
    let mut chart = ChartBuilder::on(area)
        .caption(p.title, ("sans-serif", 16))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(56)
        .build_cartesian_2d(xr.clone(), yr.clone())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(p.x)
        .y_desc(p.y)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .light_line_style(WHITE)
        .draw()
        .map_err(err)?;
    for (i, s) in p.series.iter().enumerate() {
        let c = color(i);
        // The legend swatch is drawn as the series is: a line, two dashes, a dot, a bar.
        let mark = s.mark;
        let legend = move |(x, y): (i32, i32)| {
            let at = EmptyElement::at((x, y));
            match mark {
                Mark::Line => {
                    at + PathElement::new(vec![(0, 0), (8, 0)], c.stroke_width(2))
                        + PathElement::new(vec![(8, 0), (16, 0)], c.stroke_width(2))
                }
                Mark::Dashed => {
                    at + PathElement::new(vec![(0, 0), (6, 0)], c.stroke_width(2))
                        + PathElement::new(vec![(10, 0), (16, 0)], c.stroke_width(2))
                }
                Mark::Dots => {
                    at + PathElement::new(vec![(8, 0), (8, 0)], c)
                        + PathElement::new(vec![(5, 0), (11, 0)], c.stroke_width(5))
                }
                Mark::Bars(_) => {
                    at + PathElement::new(vec![(2, 0), (14, 0)], c.mix(0.45).stroke_width(8))
                        + PathElement::new(vec![(2, 0), (2, 0)], c)
                }
            }
        };
        let pixels = chart.plotting_area().get_pixel_range();
        let drawn =
            match s.mark {
                Mark::Line | Mark::Dashed => {
                    let dashed = matches!(s.mark, Mark::Dashed);
                    curves.add(&s.points, &pixels, (&xr, &yr), (c, dashed));
                    // Nothing drawn by plotters: the series only takes its legend entry.
                    chart
                        .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
                        .map_err(err)?
                }
                Mark::Dots => chart
                    .draw_series(s.points.iter().map(|&q| Circle::new(q, 3, c.filled())))
                    .map_err(err)?,
                Mark::Bars(w) => chart
                    .draw_series(s.points.iter().map(|&(x, h)| {
                        Rectangle::new([(x, 0.0), (x + w, h)], c.mix(0.45).filled())
                    }))
                    .map_err(err)?,
            };
        if !s.name.is_empty() {
            drawn.label(s.name.as_str()).legend(legend);
        }
    }
    for (x, label) in &p.markers {
        chart
            .draw_series(LineSeries::new(
                vec![(*x, yr.start), (*x, yr.end)],
                BLUE.mix(0.6),
            ))
            .map_err(err)?
            .label(label.as_str())
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLUE.mix(0.6)));
    }
    // The curves' place: after the grid and markers, before the legend.
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(xr.start, yr.start), (xr.start, yr.start)],
            curves.marker.filled(),
        )))
        .map_err(err)?;
    if p.series.iter().any(|s| !s.name.is_empty()) || !p.markers.is_empty() {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(("sans-serif", 11))
            .position(legend_at)
            .draw()
            .map_err(err)?;
    }
    Ok(curves)
}

/// Render panels in a grid of `rows × cols` under a title, returning the SVG text.
fn render(
    title: &str,
    size: (u32, u32),
    grid: (usize, usize),
    panels: &[Panel],
) -> Result<String, FigureError> {
    let mut svg = String::new();
    let mut curves = Vec::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = root.titled(title, ("sans-serif", 20)).map_err(err)?;
        for (id, (area, p)) in root.split_evenly(grid).iter().zip(panels).enumerate() {
            curves.push(draw(area, p, id)?);
        }
        root.present().map_err(err)?;
    }
    for c in &curves {
        c.splice(&mut svg);
    }
    Ok(svg)
}

/// Curves of `f` on `n + 1` points of [a, b].
fn curve(a: f64, b: f64, n: usize, f: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    (0..=n)
        .map(|i| {
            let x = a + (b - a) * i as f64 / n as f64;
            (x, f(x))
        })
        .collect()
}

/// A normalised histogram of `values` on `bins` bins: (left edges, density), width.
fn histogram(values: &[f64], bins: usize) -> (Vec<(f64, f64)>, f64) {
    let r = range(values.iter().cloned(), false);
    let w = (r.end - r.start) / bins as f64;
    let mut counts = vec![0usize; bins];
    for v in values.iter().filter(|v| v.is_finite()) {
        let k = (((v - r.start) / w) as usize).min(bins - 1);
        counts[k] += 1;
    }
    let total = values.len().max(1) as f64 * w;
    let pts = counts
        .iter()
        .enumerate()
        .map(|(k, &c)| (r.start + k as f64 * w, c as f64 / total))
        .collect();
    (pts, w)
}

fn bh(e: behaviour::BehaviourError) -> FigureError {
    match e {
        e @ (behaviour::BehaviourError::Role(_) | behaviour::BehaviourError::Body(_)) => {
            FigureError::Body(e.to_string())
        }
        other => err(other),
    }
}

/// Fig. 2A: the first four non-zero mode shapes of every field.
fn mode_shapes(theory: &Theory) -> Result<String, FigureError> {
    let n = theory.points;
    let fields = &theory.modes;
    let titles: Vec<String> = fields
        .iter()
        .map(|f| {
            let ends = match f.field.boundary {
                crate::model::Boundary::Ends { tail, head } if tail != head => {
                    f.field.boundary.name()
                }
                b => format!("{b} ends"),
            };
            format!("{} ({}, {ends})", f.field.symbol, f.field.meaning).to_lowercase()
        })
        .collect();
    let mut panels = Vec::new();
    for (f, title) in fields.iter().zip(&titles) {
        let shapes = f.spectrum.shapes.as_ref().ok_or_else(|| err("no shapes"))?;
        let first = f.spectrum.nullity;
        let series = (first..(first + 4).min(shapes.ncols()))
            .map(|i| {
                let pts = (0..shapes.nrows())
                    .map(|j| (j as f64, shapes[(j, i)]))
                    .collect();
                self::series(format!("mode {i}"), pts, Mark::Line)
            })
            .collect();
        panels.push(panel(
            title,
            "segment j (0 = tail)",
            "vᵢ(j), unit norm",
            series,
        ));
    }
    let rows = fields.len().div_ceil(2);
    render(
        &format!("Mode shapes on N = {n} points (paper Fig. 2A)"),
        (1000, 380 * rows as u32),
        (rows, 2),
        &panels,
    )
}

/// Fig. 2B–C: eigenvalues and equipartition variance shares.
fn spectrum(theory: &Theory) -> Result<String, FigureError> {
    let n = theory.points;
    let fields = &theory.modes;
    let nonzero = |f: &crate::modal::FieldModes| -> Vec<(usize, f64, f64)> {
        f.modes
            .iter()
            .filter(|m| m.eigenvalue > 0.0 && m.zero_mode.is_none())
            .map(|m| (m.index, m.eigenvalue, m.variance_share))
            .collect()
    };
    let eig = fields
        .iter()
        .map(|f| {
            let pts = nonzero(f)
                .iter()
                .map(|&(i, l, _)| (i as f64, l.log10()))
                .collect();
            series(f.field.symbol.clone(), pts, Mark::Dots)
        })
        .collect();
    let eig = merge_identical(eig);
    let share = fields
        .iter()
        .map(|f| {
            let mut acc = 0.0;
            let pts = nonzero(f)
                .iter()
                .map(|&(i, _, s)| {
                    acc += s;
                    (i as f64, 100.0 * acc)
                })
                .collect();
            series(f.field.symbol.clone(), pts, Mark::Line)
        })
        .collect();
    let share = merge_identical(share);
    let mut right = panel(
        "cumulative variance share at equipartition",
        "mode index i",
        "Σ share (%)",
        share,
    );
    right.zero = true;
    render(
        &format!("Eigenvalues and variance shares, N = {n} (paper Fig. 2B–C)"),
        (1000, 420),
        (1, 2),
        &[
            panel(
                "eigenvalues λᵢ of each operator",
                "mode index i",
                "log₁₀ λᵢ",
                eig,
            ),
            right,
        ],
    )
}

/// Fig. 3: the two stages of self-righting.
fn self_righting(theory: &Theory) -> Result<String, FigureError> {
    let n = theory.points;
    let settings = RightingSettings::default();
    let r = behaviour::self_righting(theory, &settings).map_err(bh)?;
    let pick = |g: &dyn Fn(&behaviour::RightingFrame) -> f64| -> Vec<(f64, f64)> {
        r.frames.iter().map(|f| (f.t, g(f))).collect()
    };
    let attach = vec![(r.attachment_time, "mouth hooks attach".to_string())];
    let t = "time t (1/ω_t)";
    let mut panels = vec![
        panel(
            "generalised torque on the first torsional mode",
            t,
            "Q",
            vec![series("", pick(&|f| f.torque), Mark::Line)],
        ),
        panel(
            "first twisting mode",
            t,
            "Θ₁",
            vec![series("", pick(&|f| f.mode), Mark::Line)],
        ),
        panel(
            "mean rotation of the segments",
            t,
            "mean θ (rad)",
            vec![series("", pick(&|f| f.mean_rotation), Mark::Line)],
        ),
    ];
    let segments = (0..n)
        .filter(|j| n <= 8 || j % (n / 6).max(1) == 0 || *j == n - 1)
        .map(|j| {
            let name = if j == n - 1 {
                "head".to_string()
            } else if j == 0 {
                "tail".to_string()
            } else {
                format!("segment {j}")
            };
            series(name, pick(&|f| f.angles[j]), Mark::Line)
        })
        .collect();
    panels.push(panel("rotation of each segment", t, "θⱼ (rad)", segments));
    let align = r
        .alignment_times
        .iter()
        .enumerate()
        .map(|(j, &a)| (j as f64, a))
        .collect();
    let align_title = format!("time to align within δ = {} rad", settings.tolerance);
    panels.push(panel(
        &align_title,
        "segment j (0 = tail)",
        "alignment time (1/ω_t)",
        vec![series("", align, Mark::Dots)],
    ));
    let zs: Vec<f64> = curve(0.3, 3.0, 18, |z| z).iter().map(|p| p.0).collect();
    let points = behaviour::righting_sweep(theory, &settings, &zs).map_err(bh)?;
    let attach_at = points
        .iter()
        .map(|p| (p.mode_damping, p.attachment_time))
        .collect();
    let righted_at = points
        .iter()
        .map(|p| (p.mode_damping, p.righting_time))
        .collect();
    let mut sweep = panel(
        "righting time against the first mode's damping",
        "damping ratio ζ₁",
        "time (1/ω_t)",
        vec![
            series("body aligned", righted_at, Mark::Line),
            series("hooks attach", attach_at, Mark::Dashed),
        ],
    );
    sweep.markers = vec![(1.0, "critical damping".into())];
    sweep.zero = true;
    panels.push(sweep);
    for p in panels.iter_mut().take(4) {
        p.markers = attach.clone();
        p.zero = true;
    }
    panels[4].zero = true;
    render(
        &format!(
            "Self-righting, N = {n}, ζ₁ = {} (paper Fig. 3); attach at {:.1}, righted at {:.1}",
            r.damping_ratio, r.attachment_time, r.righting_time
        ),
        (1000, 1050),
        (3, 2),
        &panels,
    )
}

/// Fig. 4: a constant force on the first dorsoventral bending mode (rearing) and on the first
/// axial mode (hunching): the transient and the shifted equilibrium shape.
fn rearing_hunching(theory: &Theory) -> Result<String, FigureError> {
    let n = theory.points;
    let mut panels = Vec::new();
    let field = |behaviour: &str| -> Result<(usize, String), FigureError> {
        let i = behaviour::role_fields(&theory.model, behaviour)
            .map_err(|e| FigureError::Body(e.to_string()))?[0];
        let f = &theory.model.fields[i];
        let role = f.role.map(|r| r.name()).unwrap_or_default();
        Ok((i, format!("{role} {}", f.symbol)))
    };
    let (rear, hunch) = (field("behave rearing")?, field("behave hunching")?);
    let labels = [("rearing", rear.0, rear.1), ("hunching", hunch.0, hunch.1)];
    // Each run again over its own settling time, so a fast mode's panel shows its settling
    // at the same resolution (400 samples) as a slow one's.
    let runs = labels
        .iter()
        .map(|(what, index, _)| {
            let r = behaviour::step_response(theory, what, *index, 0.02, 2000.0)?;
            match settling_end(&r.transient, r.equilibrium) {
                end if end > 0.0 && end < 1500.0 => {
                    behaviour::step_response(theory, what, *index, 0.02, end)
                }
                _ => Ok(r),
            }
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(bh)?;
    let titles: Vec<(String, String)> = labels
        .iter()
        .zip(&runs)
        .map(|((what, _, _), r)| {
            (
                format!("{what}: force 0.02 on mode {}", r.mode),
                format!("{what}: shifted equilibrium Q*·vᵢ"),
            )
        })
        .collect();
    for (((_, _, axis), r), (t1, t2)) in labels.iter().zip(&runs).zip(&titles) {
        let q = vec![
            (0.0, r.equilibrium),
            (r.transient.last().map_or(1.0, |x| x.0), r.equilibrium),
        ];
        let mut a = panel(
            t1,
            "time t (1/ω)",
            "modal coordinate Q",
            vec![
                series("transient", r.transient.clone(), Mark::Line),
                series("Q* = F/ωᵢ²", q, Mark::Dashed),
            ],
        );
        a.zero = true;
        let shape = r
            .shape
            .iter()
            .enumerate()
            .map(|(j, v)| (j as f64, *v))
            .collect();
        let mut b = panel(
            t2,
            "segment j (0 = tail)",
            axis,
            vec![series("", shape, Mark::Line)],
        );
        b.zero = true;
        panels.push(a);
        panels.push(b);
    }
    render(
        &format!("Rearing and hunching, N = {n} (paper §3.3.2, Fig. 4)"),
        (1000, 760),
        (2, 2),
        &panels,
    )
}

/// A third past the transient's settling time (the last moment it is more than 1 % of Q* away
/// from Q*): a fast mode settles in a tenth of a slow one's time, and its panel should show the
/// settling, not a flat line.
fn settling_end(transient: &[(f64, f64)], equilibrium: f64) -> f64 {
    let tolerance = 0.01 * equilibrium.abs();
    transient
        .iter()
        .rev()
        .find(|&&(_, q)| (q - equilibrium).abs() > tolerance)
        .map_or(0.0, |p| p.0 * 4.0 / 3.0)
}

/// App. C: forward and backward frequencies of the self-interacting axial pair against the
/// amplitude, with the nonlinear pair's simulated frequencies.
fn asymmetry() -> Result<String, FigureError> {
    let c = -std::f64::consts::FRAC_1_SQRT_2;
    let roots = |a: f64| behaviour::asymmetry_roots(c, a, 1.0);
    let mut sim = (Vec::new(), Vec::new());
    for a in [0.25, 0.5, 0.75, 1.0, 1.25, 1.5] {
        let x = behaviour::asymmetry(c, a, 1.0).map_err(bh)?;
        sim.0.push((a, x.simulated_forward));
        sim.1.push((a, x.simulated_backward));
    }
    let mut p = panel(
        "roots of ω_s² + cA²ω_s − ω² = 0, c = −√2/2, ω = 1",
        "wave amplitude A",
        "travelling-wave frequency ω_s (units of ω)",
        vec![
            series(
                "forward root",
                curve(0.0, 1.6, 160, |a| roots(a).0),
                Mark::Line,
            ),
            series(
                "backward root",
                curve(0.0, 1.6, 160, |a| roots(a).1),
                Mark::Line,
            ),
            series("simulated forward", sim.0, Mark::Dots),
            series("simulated backward", sim.1, Mark::Dots),
        ],
    );
    p.zero = true;
    render(
        "Forward/backward asymmetry of the axial pair (paper App. C, corrected cA²)",
        (760, 520),
        (1, 1),
        &[p],
    )
}

/// App. B: PCA of Langevin postures against the modes and the equipartition shares.
fn equipartition(theory: &Theory, settings: &FigureSettings) -> Result<String, FigureError> {
    let n = theory.points;
    let kt = 0.5;
    // 200 000 steps, fewer on long bodies so that the figure takes seconds (the title says how
    // many postures went in).
    let steps = ((2e9 / (n as f64).powi(2)) as u64).clamp(1000, 200_000);
    let c = behaviour::equipartition_from_dynamics(theory, None, steps, kt, settings.seed)
        .map_err(bh)?;
    let k = |v: &[f64], f: fn(f64) -> f64| -> Vec<(f64, f64)> {
        v.iter()
            .enumerate()
            .map(|(i, x)| ((i + 1) as f64, f(*x)))
            .collect()
    };
    let mut shares = panel(
        "variance share of each principal component",
        "component k (k-th non-zero mode)",
        "log₁₀ share",
        vec![
            series(
                "PCA of simulated postures",
                k(&c.pca_variance_share, f64::log10),
                Mark::Dots,
            ),
            series(
                "equipartition λₖ⁻¹/Σλ⁻¹",
                k(&c.theory_variance_share, f64::log10),
                Mark::Line,
            ),
        ],
    );
    shares.zero = true;
    let mut overlap = panel(
        "|cos| between principal component k and mode k",
        "component k",
        "overlap",
        vec![series("", k(&c.overlap, |x| x), Mark::Dots)],
    );
    overlap.zero = true;
    render(
        &format!(
            "Equipartition from Langevin dynamics: {} postures of y, N = {n}, kT = {kt} (paper App. B)",
            c.frames
        ),
        (1000, 420),
        (1, 2),
        &[shares, overlap],
    )
}

/// Figs. 6–7: a degenerate pair's minimum-energy orbit, the body it moves, and its densities.
fn pair(theory: &Theory, kind: PairKind, settings: &FigureSettings) -> Result<String, FigureError> {
    let n = theory.points;
    let m = 0.1;
    let o = behaviour::pair_orbit(theory, kind, m, 2.0).map_err(bh)?;
    let orbit: Vec<(f64, f64)> = o.trajectory.iter().map(|&(_, a, b)| (a, b)).collect();
    let postures = o
        .postures
        .iter()
        .map(|(t, a, b)| {
            let pts = match kind {
                PairKind::Peristalsis => {
                    a.iter().enumerate().map(|(j, v)| (j as f64, *v)).collect()
                }
                PairKind::Rolling => a.iter().zip(b).map(|(y, z)| (*y, *z)).collect(),
            };
            series(format!("t = {t:.2}"), pts, Mark::Line)
        })
        .collect();
    // p(A) ∝ exp(−β(M²/A² + ω²A²)/2) on A > 0, normalised by quadrature.
    let beta: f64 = 100.0;
    let w = o.omega;
    let amax = (0.4 / w).sqrt() + 5.0 / (w * beta.sqrt());
    let mut dens = Vec::new();
    for (k, mm) in [0.0, 0.05, 0.1, 0.2].iter().enumerate() {
        let g = |a: f64| behaviour::pair_amplitude_weight(w, beta, *mm, a);
        let z = behaviour::integrate(&g, 0.0, amax * 2.0, 1e-12);
        dens.push(series(
            format!("M = {mm}"),
            curve(0.0, amax, 200, |a| g(a) / z),
            if k == 2 { Mark::Line } else { Mark::Dashed },
        ));
    }
    let s = behaviour::sample_pair(w, beta, m, settings.samples, settings.seed).map_err(bh)?;
    let (hist, bw) = histogram(&s.amplitude, 40);
    dens.push(series(format!("Metropolis, M = {m}"), hist, Mark::Bars(bw)));
    let (what, pfield, title) = match kind {
        PairKind::Peristalsis => (
            "Peristalsis",
            "axial displacement x",
            "travelling compression wave",
        ),
        PairKind::Rolling => (
            "Rolling",
            "dorsoventral z",
            "midline seen along the axis: a C-bend turning",
        ),
    };
    let px = match kind {
        PairKind::Peristalsis => "segment j (0 = tail)",
        PairKind::Rolling => "mediolateral y",
    };
    let mut orbit_panel = panel(
        "minimum-energy orbit A* = √(|M|/ω)",
        "Q_a",
        "Q_b",
        vec![series("", orbit, Mark::Line)],
    );
    orbit_panel.zero = true;
    let mut dens_panel = panel("amplitude density at β = 100", "amplitude A", "p(A)", dens);
    dens_panel.zero = true;
    render(
        &format!(
            "{what}: pair frequency ω = {:.4}, M = {m}, N = {n} (paper Figs. 6–7)",
            o.omega
        ),
        (1200, 420),
        (1, 3),
        &[orbit_panel, panel(title, px, pfield, postures), dens_panel],
    )
}

/// Fig. 8A: the free energy of a pair across M = 0.
fn free_energy(theory: &Theory) -> Result<String, FigureError> {
    let o = behaviour::pair_orbit(theory, PairKind::Peristalsis, 0.1, 1.0).map_err(bh)?;
    let mut lines = Vec::new();
    for beta in [1.0, 3.0, 10.0] {
        let mut pts = Vec::new();
        for (m, _) in curve(-1.0, 1.0, 200, |m| m) {
            pts.push((
                m,
                behaviour::pair_statistics(o.omega, beta, m)
                    .map_err(bh)?
                    .free_energy,
            ));
        }
        lines.push(series(format!("β = {beta}"), pts, Mark::Line));
    }
    render(
        &format!(
            "Free energy of the first axial pair, ω = {:.4} (paper Fig. 8A)",
            o.omega
        ),
        (700, 480),
        (1, 1),
        &[panel(
            "F(M) = ln(βω/2π²)/β + |M|ω: a kink at M = 0",
            "conserved momentum M",
            "free energy F",
            lines,
        )],
    )
}

/// Fig. 8D: the 3-point bend angle of unbiased exploration against its linearised Gaussian.
fn bend_angle(theory: &Theory, settings: &FigureSettings) -> Result<String, FigureError> {
    let n = theory.points;
    let beta = 10_000.0;
    let e = behaviour::explore(theory, beta, settings.samples, settings.seed).map_err(bh)?;
    let deg: Vec<f64> = e.bend.iter().map(|b| b.to_degrees()).collect();
    let (hist, w) = histogram(&deg, 60);
    let sd = e.bend_sd_linear.to_degrees();
    let lim = 4.0 * sd;
    let gauss = curve(-lim, lim, 200, |x| {
        (-0.5 * (x / sd).powi(2)).exp() / (sd * (2.0 * std::f64::consts::PI).sqrt())
    });
    render(
        &format!("3-point body bend in unbiased exploration, β = {beta}, N = {n} (paper Fig. 8D)"),
        (700, 480),
        (1, 1),
        &[panel(
            "tail–midpoint–head turning angle",
            "bend angle (degrees)",
            "density (1/degree)",
            vec![
                series(
                    format!("{} sampled postures", e.bend.len()),
                    hist,
                    Mark::Bars(w),
                ),
                series("linearised Gaussian", gauss, Mark::Line),
            ],
        )],
    )
}

/// App. D: the Mathieu stability chart with the first tongue's small-ε edges.
fn mathieu() -> Result<String, FigureError> {
    let (nx, ny, emax) = (161usize, 61usize, 0.6);
    let (lo, hi) = (0.5, 4.5);
    let chart_points = behaviour::stability_chart(1.0, (lo, hi), emax, (nx, ny)).map_err(bh)?;
    let mut svg = String::new();
    let mut curves = Curves::new(0);
    {
        let root = SVGBackend::with_string(&mut svg, (800, 520)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "Mathieu stability: Φ̈ + λ²[1 − 2ε cos ωt]Φ = 0 (paper App. D)",
                ("sans-serif", 18),
            )
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(lo..hi, 0.0..emax)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("drive frequency ω/λ")
            .y_desc("modulation depth ε")
            .light_line_style(WHITE)
            .draw()
            .map_err(err)?;
        let (dx, dy) = ((hi - lo) / (nx - 1) as f64, emax / (ny - 1) as f64);
        chart
            .draw_series(chart_points.iter().filter(|p| !p.stable).map(|p| {
                let (x, y) = (p.frequency_ratio, p.epsilon);
                Rectangle::new(
                    [(x - dx / 2.0, y - dy / 2.0), (x + dx / 2.0, y + dy / 2.0)],
                    RGBColor(214, 39, 40).mix(0.5).filled(),
                )
            }))
            .map_err(err)?
            .label("unstable (|tr M| > 2)")
            .legend(|(x, y)| {
                Rectangle::new(
                    [(x, y - 5), (x + 16, y + 5)],
                    RGBColor(214, 39, 40).mix(0.5).filled(),
                )
            });
        let pixels = chart.plotting_area().get_pixel_range();
        for (sign, name) in [(-1.0, "2√(1 − ε)"), (1.0, "2√(1 + ε)")] {
            let edge: Vec<(f64, f64)> = curve(0.0, emax, 100, |e| e)
                .into_iter()
                .map(|(e, _)| (2.0 * (1.0 + sign * e).sqrt(), e))
                .collect();
            curves.add(&edge, &pixels, (&(lo..hi), &(0.0..emax)), (BLACK, false));
            chart
                .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
                .map_err(err)?
                .label(format!("first tongue edge {name}"))
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLACK));
        }
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(lo, 0.0), (lo, 0.0)],
                curves.marker.filled(),
            )))
            .map_err(err)?;
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    curves.splice(&mut svg);
    Ok(svg)
}

/// Make figure `name` (one of [`FIGURES`]) as SVG text.
pub fn figure(
    name: &str,
    theory: &Theory,
    settings: &FigureSettings,
) -> Result<String, FigureError> {
    match name {
        "mode_shapes.svg" => mode_shapes(theory),
        "spectrum.svg" => spectrum(theory),
        "self_righting.svg" => self_righting(theory),
        "rearing_hunching.svg" => rearing_hunching(theory),
        "asymmetry.svg" => asymmetry(),
        "equipartition.svg" => equipartition(theory, settings),
        "peristalsis.svg" => pair(theory, PairKind::Peristalsis, settings),
        "rolling.svg" => pair(theory, PairKind::Rolling, settings),
        "free_energy.svg" => free_energy(theory),
        "bend_angle.svg" => bend_angle(theory, settings),
        "mathieu.svg" => mathieu(),
        _ => Err(FigureError::Invalid(format!(
            "unknown figure {name:?} (figures: {})",
            FIGURES.join(", ")
        ))),
    }
}

/// What [`write_figures`] did: the files written, and the figures skipped because the model
/// lacks a role they need (with the reason).
#[derive(Debug, Default)]
pub struct Written {
    /// Paths written.
    pub written: Vec<PathBuf>,
    /// (figure, why) of each figure the body cannot make.
    pub skipped: Vec<(String, String)>,
}

/// Write the figures `names` (from [`FIGURES`]) into `dir` (created if missing), calling
/// `progress` before each one. Unknown names are refused before anything is written. When
/// several are asked, a figure the body cannot make (a missing role, no degenerate pair, …) is
/// skipped and reported; a single one asked for is an error.
pub fn write_figures(
    dir: &Path,
    names: &[&str],
    theory: &Theory,
    settings: &FigureSettings,
    mut progress: impl FnMut(&str),
) -> Result<Written, FigureError> {
    if let Some(bad) = names.iter().find(|n| !FIGURES.contains(n)) {
        return Err(FigureError::Invalid(format!(
            "unknown figure {bad:?} (figures: {})",
            FIGURES.join(", ")
        )));
    }
    create_dir(dir)?;
    let mut out = Written::default();
    for name in names {
        progress(name);
        match figure(name, theory, settings) {
            Ok(svg) => out.written.push(write_svg(dir, name, &svg)?),
            Err(FigureError::Body(why)) if names.len() > 1 => {
                out.skipped.push((name.to_string(), why))
            }
            Err(e) => return Err(e),
        }
    }
    Ok(out)
}

fn create_dir(dir: &Path) -> Result<(), FigureError> {
    std::fs::create_dir_all(dir)
        .map_err(|e| FigureError::Io(format!("cannot create {}: {e}", dir.display())))
}

fn write_svg(dir: &Path, name: &str, svg: &str) -> Result<PathBuf, FigureError> {
    let path = dir.join(name);
    std::fs::write(&path, svg)
        .map_err(|e| FigureError::Io(format!("cannot write {}: {e}", path.display())))?;
    Ok(path)
}

/// The fit's principal components against the mode shapes (Fig. 2A style).
fn fit_shapes(r: &crate::fit::FitReport) -> Result<String, FigureError> {
    let shown = r.modes.len().min(4);
    let mut shape_panels = Vec::new();
    let titles: Vec<String> = (0..shown)
        .map(|k| {
            format!(
                "PC {} against mode {} (overlap {:.4})",
                k + 1,
                r.modes[k].index,
                r.mode_overlap[k]
            )
        })
        .collect();
    for (k, title) in titles.iter().enumerate() {
        let mode: Vec<f64> = r.shapes[k].clone();
        // The PC on the model's points, signed to agree with the mode.
        let mut pc: Vec<f64> = (0..mode.len())
            .map(|p| {
                (0..r.shapes.len())
                    .map(|j| r.components[k][j] * r.shapes[j][p])
                    .sum()
            })
            .collect();
        if pc.iter().zip(&mode).map(|(a, b)| a * b).sum::<f64>() < 0.0 {
            pc.iter_mut().for_each(|v| *v = -*v);
        }
        let pts = |v: &[f64]| v.iter().enumerate().map(|(p, x)| (p as f64, *x)).collect();
        shape_panels.push(panel(
            title,
            "point j (0 = tail)",
            "unit-norm shape",
            vec![
                series("mode shape", pts(&mode), Mark::Line),
                series("principal component", pts(&pc), Mark::Dashed),
            ],
        ));
    }
    render(
        &format!(
            "Principal components of {} frames against the theory's modes",
            r.frames
        ),
        (1000, 760),
        (2, 2),
        &shape_panels,
    )
}

/// The fit's figures (Fig. 2 style): principal components against mode shapes, variance shares,
/// spectra, and measured against fitted modal frequencies.
pub fn fit_figures(r: &crate::fit::FitReport) -> Result<Vec<(&'static str, String)>, FigureError> {
    let shown = r.modes.len().min(4);
    let shapes = fit_shapes(r)?;
    let idx = |k: usize| r.modes[k].index as f64;
    let share = |v: &[f64]| -> Vec<(f64, f64)> {
        v.iter()
            .enumerate()
            .map(|(k, s)| (idx(k), 100.0 * s))
            .collect()
    };
    let mut shares = panel(
        "variance share of each principal component",
        "mode index i",
        "share (%)",
        vec![
            series("PCA of the data", share(&r.pca_variance_share), Mark::Dots),
            series(
                "equipartition λᵢ⁻¹/Σλⱼ⁻¹",
                share(&r.theory_variance_share),
                Mark::Line,
            ),
        ],
    );
    shares.zero = true;
    let mut freq = panel(
        "modal frequencies",
        "mode index i",
        "angular frequency (rad per time unit)",
        vec![
            series(
                "measured",
                (0..r.modes.len())
                    .map(|k| (idx(k), r.modes[k].angular_frequency))
                    .collect(),
                Mark::Dots,
            ),
            series(
                format!("ω√λᵢ, ω = {:.4}", r.omega),
                (0..r.modes.len())
                    .map(|k| (idx(k), r.modes[k].theory_angular_frequency))
                    .collect(),
                Mark::Line,
            ),
        ],
    );
    freq.zero = true;
    let ratio = |f: &dyn Fn(&crate::fit::ModeFit) -> f64| -> Vec<(f64, f64)> {
        let first = f(&r.modes[0]);
        (0..r.modes.len())
            .map(|k| (idx(k), f(&r.modes[k]) / first))
            .collect()
    };
    let mut ratios = panel(
        "frequency ratios ωᵢ/ω₁ (independent of ω)",
        "mode index i",
        "ωᵢ / ω of the first mode",
        vec![
            series("measured", ratio(&|m| m.angular_frequency), Mark::Dots),
            series(
                "theory √(λᵢ/λ₁)",
                ratio(&|m| m.eigenvalue.sqrt()),
                Mark::Line,
            ),
        ],
    );
    ratios.zero = true;
    let spectra: Vec<Series> = (0..shown)
        .map(|k| {
            let pts = r
                .frequencies
                .iter()
                .zip(&r.psd[k])
                .skip(1)
                .filter(|(_, p)| **p > 0.0)
                .map(|(f, p)| (*f, p.log10()))
                .collect();
            series(format!("mode {}", r.modes[k].index), pts, Mark::Line)
        })
        .collect();
    let summary = render(
        &format!(
            "Fit of {} frames: ω = {:.4}, β = {:.4} (paper Fig. 2)",
            r.frames, r.omega, r.beta
        ),
        (1000, 780),
        (2, 2),
        &[
            shares,
            panel(
                "Welch spectra of the modal coordinates",
                "frequency (cycles per time unit)",
                "log₁₀ PSD",
                spectra,
            ),
            freq,
            ratios,
        ],
    )?;
    Ok(vec![
        ("fit_shapes.svg", shapes),
        ("fit_summary.svg", summary),
    ])
}

/// Write [`fit_figures`] into `dir`.
pub fn write_fit(dir: &Path, r: &crate::fit::FitReport) -> Result<Vec<PathBuf>, FigureError> {
    create_dir(dir)?;
    fit_figures(r)?
        .iter()
        .map(|(name, svg)| write_svg(dir, name, svg))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::settling_end;

    #[test]
    fn a_transient_ends_a_third_past_its_settling_time() {
        // Q(t) = 1 − e^{−t}cos t settles within 1 % at t ≈ ln 100 ≈ 4.6, sampled to t = 100.
        let transient: Vec<(f64, f64)> = (0..=10_000)
            .map(|i| {
                let t = i as f64 / 100.0;
                (t, 1.0 - (-t).exp() * t.cos())
            })
            .collect();
        let end = settling_end(&transient, 1.0);
        assert!(end > 4.0 * 4.0 / 3.0 && end < 4.7 * 4.0 / 3.0, "{end}");
        // One that never leaves its equilibrium has nothing to show; one that never settles, all.
        assert_eq!(settling_end(&[(0.0, 1.0), (1.0, 1.0)], 1.0), 0.0);
        assert_eq!(settling_end(&transient, 5.0), 100.0 * 4.0 / 3.0);
    }
}
