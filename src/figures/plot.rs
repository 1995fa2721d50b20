//! The plotting kit every figure uses: ranges and ticks, panels laid out in a grid under their
//! title and keys, and the SVG they are drawn into (the series and panels are `series`).

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::key::{key_rows, keyed, keys, shared_key, KEY_ROW};
pub(super) use super::series::*;
use super::{err, FigureError};

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
    let text = if (v - v.round()).abs() < 1e-9 * v.abs().max(1.0) && v.abs() < 1e9 {
        format!("{}", v.round() as i64)
    } else {
        let text = format!("{v:.4}");
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    };
    // The typographic minus, as a printed page has it (not the hyphen).
    text.replace('-', "\u{2212}")
}

/// The narrowest panel, in pixels: a figure narrower than its columns need takes fewer columns.
const MIN_PANEL: u32 = 320;

/// The narrowest a panel may be when the page is narrow: a figure at 85 mm takes two columns
/// of these rather than stacking its panels into a column.
const NARROW_PANEL: u32 = 230;

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

/// The caption lines and key rows panel `p` takes in an area `width` pixels wide.
fn heading_lines(p: &Panel, width: u32) -> (usize, usize) {
    (
        wrap(p.title, width as f64 - 16.0, CAPTION).len(),
        key_rows(&keys(p), width as f64).1,
    )
}

/// Draw one panel into `area`: its caption (room for `lines.0` lines), its key (`lines.1`
/// rows; none when `own_key` is false: the figure shows a shared one), axes, series.
fn draw(
    area: &Area,
    p: &Panel,
    id: usize,
    (lines, own_key): ((usize, usize), bool),
) -> Result<Curves, FigureError> {
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
    let area = &headed_over(area, p.title, CAPTION, lines.0)?;
    let area = &if own_key {
        keyed(area, &keys(p), lines.1)?
    } else {
        area.clone()
    };
    let plot = plot_size(area)?;
    let data_top = yr.end;
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
        let pixels = chart.plotting_area().get_pixel_range();
        match s.mark {
            Mark::Line | Mark::Dashed => {
                let dashed = matches!(s.mark, Mark::Dashed);
                curves.add(&s.points, &pixels, (&xr, &yr), (c, dashed));
            }
            Mark::Dots => {
                chart
                    .draw_series(s.points.iter().map(|&q| Circle::new(q, 3, c.filled())))
                    .map_err(err)?;
            }
            Mark::Bars(w) => {
                chart
                    .draw_series(s.points.iter().map(|&(x, h)| {
                        Rectangle::new([(x, 0.0), (x + w, h)], c.mix(0.45).filled())
                    }))
                    .map_err(err)?;
            }
            Mark::Errors => {
                chart
                    .draw_series(
                        s.points
                            .chunks_exact(2)
                            .map(|p| PathElement::new(vec![p[0], p[1]], c.stroke_width(2))),
                    )
                    .map_err(err)?;
            }
        }
    }
    for (x, _) in &p.markers {
        chart
            .draw_series(LineSeries::new(
                vec![(*x, yr.start), (*x, data_top)],
                BLUE.mix(0.6),
            ))
            .map_err(err)?;
    }
    // The curves' place: after the grid and markers, before the legend.
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(xr.start, yr.start), (xr.start, yr.start)],
            curves.marker.filled(),
        )))
        .map_err(err)?;
    Ok(curves)
}

/// A panel's chart: margins and label areas (room for [`TEXT`]-sized ticks and axis names).
pub(super) fn chart_builder<'a, 'b>(area: &'a Area<'b>) -> ChartBuilder<'a, 'b, SVGBackend<'b>> {
    let mut b = ChartBuilder::on(area);
    // A wider right margin keeps the last x tick label (centred on the edge) on the canvas.
    b.margin(8)
        .margin_right(22)
        .x_label_area_size(52)
        .y_label_area_size(86);
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
    headed_over(area, text, size, 0)
}

/// [`headed`] with room for at least `lines` lines (the panels of a row align their charts).
fn headed_over<'a>(
    area: &Area<'a>,
    text: &str,
    size: u32,
    lines: usize,
) -> Result<Area<'a>, FigureError> {
    let width = area.dim_in_pixel().0;
    let text_lines = wrap(text, width as f64 - 16.0, size);
    let band = 10 + text_lines.len().max(lines) as u32 * (size + 4);
    let lines = text_lines;
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
    // The title's lines, measured as `headed` will wrap them, and the shared key's rows.
    let shared = shared_key(panels);
    let key_band = shared.as_ref().map_or(0, |k| {
        (key_rows(k, width as f64).1 as f64 * KEY_ROW + 8.0).ceil() as u32
    });
    let band = 10 + wrap(title, width as f64 - 16.0, TITLE).len() as u32 * (TITLE + 4) + key_band;
    let (rows, cols, row_height) = layout(width, band, row_height, grid, panels.len());
    let size = (width, row_height * rows as u32 + band);
    let mut svg = String::new();
    let mut curves = Vec::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = headed(&root, title, TITLE)?;
        let root = match &shared {
            Some(k) => keyed(&root, k, 0)?,
            None => root,
        };
        // A row whose panels share every key entry shows it once, across the row.
        let mut id = 0;
        for (ps, row) in panels.chunks(cols).zip(root.split_evenly((rows, 1))) {
            let row_key = shared.is_none().then(|| shared_key(ps)).flatten();
            let row = match &row_key {
                Some(k) => keyed(&row, k, 0)?,
                None => row,
            };
            let own = shared.is_none() && row_key.is_none();
            let areas = row.split_evenly((1, cols));
            // The row's panels take its most caption lines and key rows: their charts align.
            let lines = ps
                .iter()
                .zip(&areas)
                .map(|(p, a)| {
                    let (caption, key) = heading_lines(p, a.dim_in_pixel().0);
                    (caption, if own { key } else { 0 })
                })
                .fold((0, 0), |m, l| (m.0.max(l.0), m.1.max(l.1)));
            for (area, p) in areas.iter().zip(ps) {
                curves.push(draw(area, p, id, (lines, own))?);
                id += 1;
            }
        }
        root.present().map_err(err)?;
    }
    for c in &curves {
        c.splice(&mut svg);
    }
    Ok(svg)
}

/// Rows, columns and row height of `count` panels asked as `grid` on a canvas `width` pixels
/// wide under a title `band` high: the columns asked where they fit ([`MIN_PANEL`] each), and
/// more, down to [`NARROW_PANEL`], while the figure would be taller than twice its width; a
/// row then takes at most 1.5 times the column width (and at least 340 px), and less (down to
/// 280 px) if the figure is still taller than twice its width.
fn layout(
    width: u32,
    band: u32,
    row_height: u32,
    grid: (usize, usize),
    count: usize,
) -> (usize, usize, u32) {
    let asked = grid.1.min((width / MIN_PANEL).max(1) as usize).max(1);
    let mut cols = asked;
    let mut row_height = row_height;
    let rows = |cols: usize| grid.0.max(count.div_ceil(cols));
    while row_height * rows(cols) as u32 + band > 2 * width
        && cols < count
        && width / (cols as u32 + 1) >= NARROW_PANEL
    {
        cols += 1;
        row_height = row_height.min((width / cols as u32 * 3 / 2).max(340));
    }
    // Still too tall: the rows give way, down to 280 px.
    let most = (2 * width).saturating_sub(band) / rows(cols) as u32;
    if row_height > most && cols > asked {
        row_height = most.max(280);
    }
    (rows(cols), cols, row_height)
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
