//! The plotting kit every figure uses: series and panels, ranges and ticks, legends placed
//! where they hide no data, and the SVG they are drawn into.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{err, FigureError};

pub(super) type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Mark {
    Line,
    Dashed,
    Dots,
    /// Histogram bars of the given width; points are (left edge, height).
    Bars(f64),
    /// Error bars: points in pairs (x, low), (x, high), each pair one vertical segment.
    Errors,
}

pub(super) struct Series {
    pub(super) name: String,
    pub(super) points: Vec<(f64, f64)>,
    pub(super) mark: Mark,
}

pub(super) fn series(name: impl Into<String>, points: Vec<(f64, f64)>, mark: Mark) -> Series {
    Series {
        name: name.into(),
        points,
        mark,
    }
}

/// Series drawn exactly over an earlier one join its legend entry ("y = z"), so no curve is
/// hidden without a word.
pub(super) fn merge_identical(all: Vec<Series>) -> Vec<Series> {
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

pub(super) struct Panel<'a> {
    pub(super) title: &'a str,
    pub(super) x: &'a str,
    pub(super) y: &'a str,
    pub(super) series: Vec<Series>,
    /// Vertical marker lines (x, label).
    pub(super) markers: Vec<(f64, String)>,
    /// Force the y range to include 0.
    pub(super) zero: bool,
}

pub(super) fn panel<'a>(title: &'a str, x: &'a str, y: &'a str, series: Vec<Series>) -> Panel<'a> {
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
pub(super) fn range(values: impl Iterator<Item = f64>, zero: bool) -> std::ops::Range<f64> {
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
pub(super) fn tick(v: f64) -> String {
    if v.abs() < 1e-12 {
        return "0".into();
    }
    if (v - v.round()).abs() < 1e-9 * v.abs().max(1.0) && v.abs() < 1e9 {
        return format!("{}", v.round() as i64);
    }
    let text = format!("{v:.4}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// Text size in plotters' units (it writes `font-size` = size / 1.24: 14.5 px, 7.4 pt in print
/// at [`super::page::PX_PER_MM`]); the smallest text of every figure.
pub(super) const TEXT: u32 = 18;
/// A panel's caption.
pub(super) const CAPTION: u32 = 20;
/// A figure's title.
pub(super) const TITLE: u32 = 22;
/// The narrowest panel, in pixels: a figure narrower than its columns need takes fewer columns.
const MIN_PANEL: u32 = 320;

/// The size plotters gives the legend box of `labels` at [`TEXT`]: its own naive font metrics
/// (em = size / 1.24², 0.7 em a byte, lines 1.25 size apart), a 30 px swatch column and 10 px
/// margins. The box is drawn 5 px inside a corner of the plotting area.
fn legend_box(labels: &[&str]) -> (f64, f64) {
    let size = TEXT as f64;
    let em = size / 1.24 / 1.24;
    let width = labels
        .iter()
        .map(|l| (em * 0.7 * l.len() as f64).round())
        .fold(0.0, f64::max);
    let rows = labels.len().saturating_sub(1) as f64;
    let height = (rows * size * 1.25).round() + em.round() + (em * 0.24).round();
    (width + 30.0 + 20.0, height + 20.0)
}

/// Whether anything of series `s` (in pixels of a plot `xr × yr` mapped onto `plot`) comes
/// within a few pixels of the box `[x0, x1] × [y0, y1]` (pixels, y down).
fn touches(
    s: &Series,
    map: &dyn Fn(f64, f64) -> (f64, f64),
    (x0, x1, y0, y1): (f64, f64, f64, f64),
) -> bool {
    let pad = 4.0;
    let inside = |(x, y): (f64, f64), r: f64| {
        x > x0 - pad - r && x < x1 + pad + r && y > y0 - pad - r && y < y1 + pad + r
    };
    // A segment, walked in steps of at most 2 px.
    let segment = |a: (f64, f64), b: (f64, f64)| {
        let (p, q) = (map(a.0, a.1), map(b.0, b.1));
        let steps = ((q.0 - p.0).hypot(q.1 - p.1) / 2.0).ceil().clamp(1.0, 1e5) as usize;
        (0..=steps).any(|k| {
            let t = k as f64 / steps as f64;
            inside((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)), 1.0)
        })
    };
    match s.mark {
        Mark::Line | Mark::Dashed => s.points.windows(2).any(|w| segment(w[0], w[1])),
        Mark::Dots => s.points.iter().any(|&(x, y)| inside(map(x, y), 3.0)),
        Mark::Errors => s.points.chunks_exact(2).any(|p| segment(p[0], p[1])),
        Mark::Bars(w) => s.points.iter().any(|&(x, h)| {
            let (a, b) = (map(x, 0.0), map(x + w, h));
            a.0.min(b.0) < x1 + pad
                && a.0.max(b.0) > x0 - pad
                && a.1.min(b.1) < y1 + pad
                && a.1.max(b.1) > y0 - pad
        }),
    }
}

/// Where the legend goes, and the y range that leaves room for it: the first corner whose
/// legend box touches no data or marker line; when every corner would, the y axis grows upward
/// by the legend's height so it sits above the data (upper right). `plot` is the plotting
/// area's size in pixels.
pub(super) fn legend_place(
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
    if labels.is_empty() {
        return (SeriesLabelPosition::UpperRight, yr.clone());
    }
    let (bw, bh) = legend_box(&labels);
    // Data to pixels of the plotting area (y down).
    let map = |x: f64, y: f64| {
        (
            plot.0 * (x - xr.start) / (xr.end - xr.start),
            plot.1 * (1.0 - (y - yr.start) / (yr.end - yr.start)),
        )
    };
    let free = |right: bool, upper: bool| {
        let x0 = if right { plot.0 - bw - 5.0 } else { 5.0 };
        let y0 = if upper { 5.0 } else { plot.1 - bh - 5.0 };
        let b = (x0, x0 + bw, y0, y0 + bh);
        !p.series.iter().any(|s| touches(s, &map, b))
            && !p.markers.iter().any(|&(x, _)| {
                let px = map(x, 0.0).0;
                px > b.0 - 4.0 && px < b.1 + 4.0
            })
    };
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    if let Some((pos, _, _)) = corners.into_iter().find(|&(_, r, u)| free(r, u)) {
        return (pos, yr.clone());
    }
    // Headroom: the data keep the plot below the box (and its 5 px gap and padding).
    let fh = ((bh + 12.0) / plot.1).min(0.8);
    let top = yr.start + (yr.end - yr.start) / (1.0 - fh);
    (SeriesLabelPosition::UpperRight, yr.start..top)
}

pub(super) fn color(i: usize) -> RGBColor {
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
pub(super) struct Curves {
    /// The marker's colour, `#0102xx`.
    pub(super) marker: RGBColor,
    /// The `<polyline>` elements.
    pub(super) svg: String,
}

impl Curves {
    pub(super) fn new(id: usize) -> Curves {
        Curves {
            marker: RGBColor(1, 2, (id % 250) as u8 + 3),
            svg: String::new(),
        }
    }

    /// One polyline of data `points` through the chart's linear map to pixels.
    pub(super) fn add(
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
    pub(super) fn splice(&self, svg: &mut String) {
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
pub(super) fn draw(area: &Area, p: &Panel, id: usize) -> Result<Curves, FigureError> {
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
    let area = &headed(area, p.title, CAPTION)?;
    let plot = plot_size(area)?;
    // Markers span the data's range, not headroom made for the legend.
    let data_top = yr.end;
    let (legend_at, yr) = legend_place(p, plot, &xr, &yr);
    let mut chart = chart_builder(area)
        .build_cartesian_2d(xr.clone(), yr.clone())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(p.x)
        .y_desc(p.y)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        // As many ticks as fit a label of ~6 characters (x) or a line of text (y) apart.
        .x_labels(((plot.0 / 50.0) as usize).clamp(5, 10))
        .y_labels(((plot.1 / 32.0) as usize).clamp(5, 10))
        .label_style(("sans-serif", TEXT))
        .axis_desc_style(("sans-serif", TEXT))
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
                Mark::Errors => {
                    at + PathElement::new(vec![(8, -6), (8, 6)], c.stroke_width(2))
                        + PathElement::new(vec![(5, -6), (11, -6)], c)
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
                Mark::Errors => chart
                    .draw_series(
                        s.points
                            .chunks_exact(2)
                            .map(|p| PathElement::new(vec![p[0], p[1]], c.stroke_width(2))),
                    )
                    .map_err(err)?,
            };
        if !s.name.is_empty() {
            drawn.label(s.name.as_str()).legend(legend);
        }
    }
    for (x, label) in &p.markers {
        chart
            .draw_series(LineSeries::new(
                vec![(*x, yr.start), (*x, data_top)],
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
            .label_font(("sans-serif", TEXT))
            .position(legend_at)
            .draw()
            .map_err(err)?;
    }
    Ok(curves)
}

/// A panel's chart: margins and label areas (room for [`TEXT`]-sized ticks and axis names).
pub(super) fn chart_builder<'a, 'b>(area: &'a Area<'b>) -> ChartBuilder<'a, 'b, SVGBackend<'b>> {
    let mut b = ChartBuilder::on(area);
    b.margin(8).x_label_area_size(52).y_label_area_size(86);
    b
}

/// The plotting area's size in pixels that [`chart_builder`] leaves on `area`, measured on a
/// scratch canvas (the legend is placed before the chart is built).
fn plot_size(area: &Area) -> Result<(f64, f64), FigureError> {
    let mut scratch = String::new();
    let root = SVGBackend::with_string(&mut scratch, area.dim_in_pixel()).into_drawing_area();
    let chart = chart_builder(&root)
        .build_cartesian_2d(0.0..1.0, 0.0..1.0)
        .map_err(err)?;
    let (w, h) = chart.plotting_area().dim_in_pixel();
    Ok((w as f64, h as f64))
}

/// Write `text` centred at the top of `area` in plotters' `size`, wrapped to its width
/// ([`wrap`]); the area below it comes back.
pub(super) fn headed<'a>(area: &Area<'a>, text: &str, size: u32) -> Result<Area<'a>, FigureError> {
    let width = area.dim_in_pixel().0;
    let lines = wrap(text, width as f64 - 16.0, size);
    let band = 10 + lines.len() as u32 * (size + 4);
    let (head, rest) = area.split_vertically(band);
    let style =
        TextStyle::from(("sans-serif", size).into_font()).pos(Pos::new(HPos::Center, VPos::Top));
    for (k, line) in lines.iter().enumerate() {
        let y = 6 + k as i32 * (size + 4) as i32;
        head.draw_text(line, &style, (width as i32 / 2, y))
            .map_err(err)?;
    }
    Ok(rest)
}

/// Render panels under a title, `grid` = (rows, columns) of `row_height` pixels each on a
/// canvas `width` pixels wide ([`super::page::Page::canvas_width`]); a canvas too narrow for
/// the columns takes fewer (panels in reading order). Returns the SVG text.
pub(super) fn render(
    width: u32,
    title: &str,
    row_height: u32,
    grid: (usize, usize),
    panels: &[Panel],
) -> Result<String, FigureError> {
    let cols = grid.1.min((width / MIN_PANEL).max(1) as usize).max(1);
    let rows = grid.0.max(panels.len().div_ceil(cols));
    // The title's lines, measured as `headed` will wrap them.
    let band = 10 + wrap(title, width as f64 - 16.0, TITLE).len() as u32 * (TITLE + 4);
    let size = (width, row_height * rows as u32 + band);
    let mut svg = String::new();
    let mut curves = Vec::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = headed(&root, title, TITLE)?;
        for (id, (area, p)) in root
            .split_evenly((rows, cols))
            .iter()
            .zip(panels)
            .enumerate()
        {
            curves.push(draw(area, p, id)?);
        }
        root.present().map_err(err)?;
    }
    for c in &curves {
        c.splice(&mut svg);
    }
    Ok(svg)
}

/// `text` in lines of at most `width` pixels at plotters' `size` (words kept whole; the
/// rendered font's 0.55 em a character is the measure).
pub(super) fn wrap(text: &str, width: f64, size: u32) -> Vec<String> {
    let per_char = 0.55 * size as f64 / 1.24;
    let most = ((width / per_char) as usize).max(10);
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(line) if line.chars().count() + 1 + word.chars().count() <= most => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// Curves of `f` on `n + 1` points of [a, b].
pub(super) fn curve(a: f64, b: f64, n: usize, f: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    (0..=n)
        .map(|i| {
            let x = a + (b - a) * i as f64 / n as f64;
            (x, f(x))
        })
        .collect()
}

/// A normalised histogram of `values` on `bins` bins: (left edges, density), width.
pub(super) fn histogram(values: &[f64], bins: usize) -> (Vec<(f64, f64)>, f64) {
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
