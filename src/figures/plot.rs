//! The plotting kit every figure uses: ticks, panels laid out in a grid under their title and
//! keys, axis names (on two lines where one would run past the chart), points off scale drawn
//! as arrows, and the SVG they are drawn into (the series, panels and ranges are `series`).

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::key::{common_keys, key_rows, keyed, own_keys, Key, KEY_ROW};
use super::script::{printed_len, spans};
pub(super) use super::series::*;
use super::{err, FigureError};

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

    /// One polyline of data `points` through the chart's linear map to pixels, cut where it
    /// leaves the y range ([`clip_runs`]: an SVG polyline is not clipped to the chart).
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
        for run in clip_runs(points, yr) {
            let _ = write!(
                self.svg,
                "<polyline fill=\"none\" stroke=\"#{r:02X}{g:02X}{b:02X}\" stroke-width=\"2\"{dash} points=\""
            );
            for (x, y) in run {
                let px = x0 + (x1 - x0) * (x - xr.start) / (xr.end - xr.start);
                let py = y0 + (y1 - y0) * (y - yr.start) / (yr.end - yr.start);
                if px.is_finite() && py.is_finite() {
                    let _ = write!(self.svg, "{px:.2},{py:.2} ");
                }
            }
            self.svg.push_str("\"/>\n");
        }
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

/// The caption lines and key rows panel `p` takes in an area `width` pixels wide, its key
/// being `own`.
fn heading_lines(p: &Panel, own: &[Key], width: u32) -> (usize, usize) {
    (
        wrap(p.title, width as f64 - 16.0, CAPTION).len(),
        key_rows(own, width as f64).1,
    )
}

/// Draw one panel into `area`: its caption (room for `lines.0` lines), its own key `own`
/// (room for `lines.1` rows; the entries it shares with other panels are the figure's), axes,
/// series, and marker lines (styled by their place in the figure's `marks`).
fn draw(
    area: &Area,
    p: &Panel,
    id: usize,
    (lines, own, marks): ((usize, usize), &[Key], &[String]),
) -> Result<Curves, FigureError> {
    let mut curves = Curves::new(id);
    let xr = x_range(p);
    let yr = y_range(p);
    let area = &headed_over(area, p.title, CAPTION, lines.0)?;
    let area = &keyed(area, own, lines.1)?;
    // A name longer than the chart is tall (or, below it, wide) goes on two lines: never over
    // the panel above or beside it.
    let first = plot_size(area, (1, 1))?;
    let y_lines = label_lines(p.y, first.1 - 8.0);
    // Centred under the chart, a name may reach into the right margin, not past it.
    let x_lines = label_lines(p.x, first.0 + 16.0);
    let names = (x_lines.len(), y_lines.len());
    let plot = plot_size(area, names)?;
    let mut chart = chart_builder(area, names)
        .build_cartesian_2d(xr.clone(), yr.clone())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(if x_lines.len() == 1 { p.x } else { "" })
        .y_desc(if y_lines.len() == 1 { p.y } else { "" })
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
    let pixels = chart.plotting_area().get_pixel_range();
    if y_lines.len() > 1 {
        y_label(area, &y_lines, &pixels)?;
    }
    if x_lines.len() > 1 {
        x_label(area, &x_lines, &pixels)?;
    }
    // Bars and error bars end at the axis' edge; dots beyond it are drawn there as arrows.
    let clamp = |y: f64| y.clamp(yr.start, yr.end);
    for (i, s) in p.series.iter().enumerate() {
        let c = s.color(i);
        match s.mark {
            Mark::Line | Mark::Dashed => {
                let dashed = matches!(s.mark, Mark::Dashed);
                curves.add(&s.points, &pixels, (&xr, &yr), (c, dashed));
            }
            Mark::Dots => {
                let (on, off): (Vec<_>, Vec<_>) = s.points.iter().partition(|q| yr.contains(&q.1));
                chart
                    .draw_series(on.iter().map(|&&q| Circle::new(q, 3, c.filled())))
                    .map_err(err)?;
                for &&(x, y) in &off {
                    let (edge, base, v) = off_scale(y, &yr);
                    // The value on the side of the arrow towards the chart's middle.
                    let (h, dx) = if x > (xr.start + xr.end) / 2.0 {
                        (HPos::Right, -7)
                    } else {
                        (HPos::Left, 7)
                    };
                    let style = TextStyle::from(("sans-serif", TEXT).into_font())
                        .color(&c)
                        .pos(Pos::new(h, v));
                    let arrow = EmptyElement::at((x, edge))
                        + Polygon::new(vec![(0, 0), (-5, base), (5, base)], c.filled())
                        + Text::new(off_value(y), (dx, base), style);
                    chart.draw_series(std::iter::once(arrow)).map_err(err)?;
                }
            }
            Mark::Bars(w) => {
                chart
                    .draw_series(s.points.iter().map(|&(x, h)| {
                        Rectangle::new([(x, clamp(0.0)), (x + w, clamp(h))], c.mix(0.45).filled())
                    }))
                    .map_err(err)?;
            }
            Mark::Errors => {
                chart
                    .draw_series(s.points.chunks_exact(2).map(|p| {
                        let ends = vec![(p[0].0, clamp(p[0].1)), (p[1].0, clamp(p[1].1))];
                        PathElement::new(ends, c.stroke_width(2))
                    }))
                    .map_err(err)?;
            }
        }
    }
    for (x, label) in merged_markers(p) {
        let (c, mark) = marker_style(&label, marks);
        let line = [(x, yr.start), (x, yr.end)];
        curves.add(&line, &pixels, (&xr, &yr), (c, mark == Mark::Dashed));
    }
    // The curves' place: after the grid, before the legend.
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(xr.start, yr.start), (xr.start, yr.start)],
            curves.marker.filled(),
        )))
        .map_err(err)?;
    Ok(curves)
}

/// Where a dot off the y axis is drawn: the edge it lies beyond, and the arrow's base and its
/// value's anchor there (the arrow points out of the chart).
fn off_scale(y: f64, yr: &std::ops::Range<f64>) -> (f64, i32, VPos) {
    if y < yr.start {
        (yr.start, -9, VPos::Bottom)
    } else {
        (yr.end, 9, VPos::Top)
    }
}

/// An off-scale value as its label says it: three significant digits.
fn off_value(y: f64) -> String {
    let digits = (2 - y.abs().log10().floor() as i32).clamp(0, 6) as usize;
    tick(format!("{y:.digits$}").parse().unwrap_or(y))
}

/// The lines of axis name `name` along `room` pixels: one when it fits, else two.
fn label_lines(name: &str, room: f64) -> Vec<String> {
    if super::key::text_width(name) <= room {
        return vec![name.to_string()];
    }
    // Two lines as even as the words allow.
    let half = printed_len(name) / 2;
    let mut first = String::new();
    let mut rest = name;
    for word in name.split(' ') {
        if printed_len(&first) >= half {
            break;
        }
        first = if first.is_empty() {
            word.into()
        } else {
            format!("{first} {word}")
        };
        rest = rest[word.len()..].trim_start();
    }
    // One long word stays one line: nothing to split.
    match rest {
        "" => vec![first],
        _ => vec![first, rest.to_string()],
    }
}

/// Draw the y axis name in `lines`, turned, centred on the chart's rows `pixels.1`, at the
/// left of `area` (where plotters draws a one-line name).
fn y_label(
    area: &Area,
    lines: &[String],
    pixels: &(std::ops::Range<i32>, std::ops::Range<i32>),
) -> Result<(), FigureError> {
    let base = area.get_base_pixel();
    let middle = (pixels.1.start + pixels.1.end) / 2 - base.1;
    let style = TextStyle::from(("sans-serif", TEXT).into_font())
        .transform(FontTransform::Rotate270)
        .pos(Pos::new(HPos::Center, VPos::Top));
    for (k, line) in lines.iter().enumerate() {
        let x = 8 + k as i32 * (TEXT as i32 - 1);
        area.draw_text(line, &style, (x, middle)).map_err(err)?;
    }
    Ok(())
}

/// Draw the x axis name in `lines`, centred under the chart's columns `pixels.0`, at the
/// bottom of `area` (where plotters draws a one-line name).
fn x_label(
    area: &Area,
    lines: &[String],
    pixels: &(std::ops::Range<i32>, std::ops::Range<i32>),
) -> Result<(), FigureError> {
    let base = area.get_base_pixel();
    let middle = (pixels.0.start + pixels.0.end) / 2 - base.0;
    let bottom = area.dim_in_pixel().1 as i32 - 8;
    let style =
        TextStyle::from(("sans-serif", TEXT).into_font()).pos(Pos::new(HPos::Center, VPos::Bottom));
    for (k, line) in lines.iter().enumerate() {
        let y = bottom - (lines.len() - 1 - k) as i32 * (TEXT as i32 - 1);
        area.draw_text(line, &style, (middle, y)).map_err(err)?;
    }
    Ok(())
}

/// A panel's chart: margins and label areas (room for [`TEXT`]-sized ticks and axis names of
/// `names` = (x, y) lines).
pub(super) fn chart_builder<'a, 'b>(
    area: &'a Area<'b>,
    names: (usize, usize),
) -> ChartBuilder<'a, 'b, SVGBackend<'b>> {
    let more = |lines: usize| 17 * lines.saturating_sub(1) as u32;
    let mut b = ChartBuilder::on(area);
    // A wider right margin keeps the last x tick label (centred on the edge) on the canvas.
    b.margin(8)
        .margin_right(22)
        .x_label_area_size(52 + more(names.0))
        .y_label_area_size(86 + more(names.1));
    b
}

/// The plotting area's size in pixels that [`chart_builder`] leaves on `area`, measured on a
/// scratch canvas (the legend is placed before the chart is built).
fn plot_size(area: &Area, names: (usize, usize)) -> Result<(f64, f64), FigureError> {
    let mut scratch = String::new();
    let root = SVGBackend::with_string(&mut scratch, area.dim_in_pixel()).into_drawing_area();
    let chart = chart_builder(&root, names)
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
/// the columns takes fewer (panels in reading order). The key entries several panels share are
/// drawn once, under the title ([`common_keys`]). Returns the SVG text, its scripts set
/// ([`spans`]).
pub(super) fn render(
    width: u32,
    title: &str,
    row_height: u32,
    grid: (usize, usize),
    panels: &[Panel],
) -> Result<String, FigureError> {
    // The title's lines, measured as `headed` will wrap them, and the shared key's rows.
    let marks = figure_markers(panels);
    let common = common_keys(panels, &marks);
    let key_band = match key_rows(&common, width as f64).1 {
        0 => 0,
        rows => (rows as f64 * KEY_ROW + 8.0).ceil() as u32,
    };
    let band = 10 + wrap(title, width as f64 - 16.0, TITLE).len() as u32 * (TITLE + 4) + key_band;
    let (rows, cols, row_height) = layout(width, band, row_height, grid, panels.len());
    let size = (width, row_height * rows as u32 + band);
    let mut svg = String::new();
    let mut curves = Vec::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = headed(&root, title, TITLE)?;
        let root = keyed(&root, &common, 0)?;
        let mut id = 0;
        for (ps, row) in panels.chunks(cols).zip(root.split_evenly((rows, 1))) {
            let areas = row.split_evenly((1, cols));
            let own: Vec<Vec<Key>> = ps.iter().map(|p| own_keys(p, &common, &marks)).collect();
            // The row's panels take its most caption lines and key rows: their charts align.
            let lines = (ps.iter().zip(&areas).zip(&own))
                .map(|((p, a), k)| heading_lines(p, k, a.dim_in_pixel().0))
                .fold((0, 0), |m, l| (m.0.max(l.0), m.1.max(l.1)));
            for ((area, p), k) in areas.iter().zip(ps).zip(&own) {
                curves.push(draw(area, p, id, (lines, k, &marks))?);
                id += 1;
            }
        }
        root.present().map_err(err)?;
    }
    for c in &curves {
        c.splice(&mut svg);
    }
    Ok(spans(&svg))
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
            Some(line) if printed_len(line) + 1 + printed_len(word) <= most => {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_far_from_the_rest_is_off_scale_and_an_even_spread_is_not() {
        // The WormPose verdict's variances: one at −10.3 among −3.2 … 1.1.
        let v = [1.1, 0.6, 0.1, -0.8, -1.9, -2.1, -2.7, -3.2, -3.2, -10.3];
        assert_eq!(far_out(&v), vec![-10.3]);
        assert!(far_out(&[0.0, 1.0, 2.0, 3.0, 4.0]).is_empty());
        assert_eq!(far_out(&[0.0, 0.1, 0.2, 9.0]), vec![9.0]);
        assert!(far_out(&[0.0, 5.0]).is_empty(), "two points have no rest");
        assert_eq!(off_value(-10.3118), "−10.3");
        assert_eq!(off_value(0.012345), "0.0123");
    }

    #[test]
    fn a_curve_is_cut_at_the_axis_edges() {
        let yr = 0.0..1.0;
        // Inside, out above, back: two runs, each ending or starting on the edge.
        let runs = clip_runs(&[(0.0, 0.5), (1.0, 1.5), (2.0, 0.5)], &yr);
        assert_eq!(
            runs,
            vec![vec![(0.0, 0.5), (0.5, 1.0)], vec![(1.5, 1.0), (2.0, 0.5)]]
        );
        // Below to above between two samples: edge to edge.
        let runs = clip_runs(&[(0.0, -1.0), (2.0, 2.0)], &yr);
        assert_eq!(runs.len(), 1);
        assert!((runs[0][0].0 - 2.0 / 3.0).abs() < 1e-12 && runs[0][1].1 == 1.0);
        assert!(clip_runs(&[(0.0, 3.0), (1.0, 4.0)], &yr).is_empty());
    }

    #[test]
    fn a_long_axis_name_takes_two_even_lines() {
        assert_eq!(label_lines("log₁₀ λᵢ", 200.0).len(), 1);
        let two = label_lines("log₁₀ PSD (point spacings²·s)", 100.0);
        assert_eq!(two, vec!["log₁₀ PSD (point", "spacings²·s)"]);
    }
}
