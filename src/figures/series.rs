//! What a figure is made of, before it is drawn: series and how each is marked, panels and
//! their marker lines, their ranges (a point far off the rest left off scale, a curve cut at
//! the axis' edge), their colours and the text sizes (the kit in `plot` and the keys in `key`
//! draw them).

use plotters::coord::Shift;
use plotters::prelude::*;

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
    /// Its colour's place in the palette ([`color`]), when it means something across panels
    /// (mode 3 is mode 3 in every panel); otherwise its place in the panel.
    pub(super) hue: Option<usize>,
}

pub(super) fn series(name: impl Into<String>, points: Vec<(f64, f64)>, mark: Mark) -> Series {
    Series {
        name: name.into(),
        points,
        mark,
        hue: None,
    }
}

impl Series {
    /// The series drawn in the palette's colour `i` wherever it appears.
    pub(super) fn hue(mut self, i: usize) -> Series {
        self.hue = Some(i);
        self
    }

    /// Its colour as the `i`-th series of its panel.
    pub(super) fn color(&self, i: usize) -> RGBColor {
        color(self.hue.unwrap_or(i))
    }
}

/// log₁₀ PSD against frequency, the zero frequency and empty bins left out.
pub(super) fn log_spectrum(frequencies: &[f64], psd: &[f64]) -> Vec<(f64, f64)> {
    frequencies
        .iter()
        .zip(psd)
        .skip(1)
        .filter(|(_, p)| **p > 0.0)
        .map(|(f, p)| (*f, p.log10()))
        .collect()
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
    /// Let a point far from the others (farther than they spread) lie off the y axis, marked
    /// by an arrow at the edge with its value, rather than squash the rest.
    pub(super) outliers: bool,
}

pub(super) fn panel<'a>(title: &'a str, x: &'a str, y: &'a str, series: Vec<Series>) -> Panel<'a> {
    Panel {
        title,
        x,
        y,
        series,
        markers: Vec::new(),
        zero: false,
        outliers: false,
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

/// A panel's x range: its series (a bar's both edges) and its markers.
pub(super) fn x_range(p: &Panel) -> std::ops::Range<f64> {
    let xs = p.series.iter().flat_map(|s| {
        s.points.iter().flat_map(move |q| match s.mark {
            Mark::Bars(w) => vec![q.0, q.0 + w],
            _ => vec![q.0],
        })
    });
    range(xs.chain(p.markers.iter().map(|m| m.0)), false)
}

/// A panel's y range: every value (and 0 where asked or under bars), or with `outliers` the
/// values but those far from the rest ([`far_out`]), with every line and interval kept whole.
pub(super) fn y_range(p: &Panel) -> std::ops::Range<f64> {
    let bars = p.series.iter().any(|s| matches!(s.mark, Mark::Bars(_)));
    let all = p.series.iter().flat_map(|s| s.points.iter().map(|q| q.1));
    if !p.outliers {
        return range(all, p.zero || bars);
    }
    let dots: Vec<f64> = (p.series.iter())
        .filter(|s| s.mark == Mark::Dots)
        .flat_map(|s| s.points.iter().map(|q| q.1))
        .filter(|v| v.is_finite())
        .collect();
    let far = far_out(&dots);
    let rest = (p.series.iter())
        .filter(|s| s.mark != Mark::Dots)
        .flat_map(|s| s.points.iter().map(|q| q.1));
    let kept = dots.iter().copied().filter(|v| !far.contains(v));
    range(kept.chain(rest), p.zero || bars)
}

/// The values of `values` that lie off the others: the lowest (or highest), while its gap to
/// the next is wider than the rest spread, up to a third of them (one point at −10 among
/// points from −3 to 1 is one; points spread evenly are none).
pub(super) fn far_out(values: &[f64]) -> Vec<f64> {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let mut far = Vec::new();
    while v.len() >= 3 && far.len() < values.len() / 3 {
        let n = v.len();
        let (low, high) = (v[1] - v[0], v[n - 1] - v[n - 2]);
        if low >= high && low > v[n - 1] - v[1] {
            far.push(v.remove(0));
        } else if high > low && high > v[n - 2] - v[0] {
            far.push(v.remove(n - 1));
        } else {
            break;
        }
    }
    far
}

/// The runs of `points` (finite ones) within the y range `yr`: a segment that leaves it ends
/// on its edge, one that comes back starts there, one that crosses it runs edge to edge.
pub(super) fn clip_runs(points: &[(f64, f64)], yr: &std::ops::Range<f64>) -> Vec<Vec<(f64, f64)>> {
    let inside = |y: f64| y >= yr.start && y <= yr.end;
    // Where the segment from `a` towards `b` (outside) meets the range's edge.
    let edge = |a: (f64, f64), b: (f64, f64)| {
        let e = if b.1 > yr.end { yr.end } else { yr.start };
        let t = (e - a.1) / (b.1 - a.1);
        (a.0 + t * (b.0 - a.0), e)
    };
    let finite: Vec<(f64, f64)> = (points.iter().copied())
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .collect();
    let (mut runs, mut run) = (Vec::new(), Vec::new());
    for (k, &p) in finite.iter().enumerate() {
        let before = k.checked_sub(1).map(|j| finite[j]);
        match (before, inside(p.1)) {
            (Some(q), true) if !inside(q.1) => run.extend([edge(p, q), p]),
            (_, true) => run.push(p),
            (Some(q), false) if inside(q.1) => {
                run.push(edge(q, p));
                runs.push(std::mem::take(&mut run));
            }
            // Below to above (or back) between two samples: the segment crosses the chart.
            (Some(q), false) if (q.1 < yr.start) != (p.1 < yr.start) => {
                runs.push(vec![edge(p, q), edge(q, p)])
            }
            _ => {}
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    runs
}

/// A panel's marker lines, those that would be drawn within 0.5 % of the x axis of each other
/// drawn once with their labels joined ("simulated 1 : 2 at G = 0.7071 = App. C: √2/2"), as
/// [`merge_identical`] joins series: no line is hidden under another without a word.
pub(super) fn merged_markers(p: &Panel) -> Vec<(f64, String)> {
    let r = x_range(p);
    let near = 0.005 * (r.end - r.start);
    let mut out: Vec<(f64, String)> = Vec::new();
    for (x, label) in &p.markers {
        match out.iter_mut().find(|m| (m.0 - x).abs() <= near) {
            Some(m) => m.1 = format!("{} = {label}", m.1),
            None => out.push((*x, label.clone())),
        }
    }
    out
}

/// The labels of a figure's marker lines ([`merged_markers`]), each once, in the order they
/// first appear: a marker's place here is its style ([`marker_style`]) in every panel.
pub(super) fn figure_markers(panels: &[Panel]) -> Vec<String> {
    let mut all: Vec<String> = Vec::new();
    for (_, label) in panels.iter().flat_map(merged_markers) {
        if !all.contains(&label) {
            all.push(label);
        }
    }
    all
}

/// How the marker line `label` is drawn, its place in the figure's markers `all` alternating:
/// black, then grey and dashed, so that no marker takes a series' colour or the pale tint of
/// one, and two markers of a figure differ.
pub(super) fn marker_style(label: &str, all: &[String]) -> (RGBColor, Mark) {
    if all.iter().position(|l| l == label).unwrap_or(0) % 2 == 0 {
        (RGBColor(0, 0, 0), Mark::Line)
    } else {
        (RGBColor(105, 105, 105), Mark::Dashed)
    }
}

/// Text size in plotters' units (it writes `font-size` = size / 1.24: 14.5 px, 7.4 pt in print
/// at [`super::page::PX_PER_MM`]); the smallest text of every figure.
pub(super) const TEXT: u32 = 18;
/// A panel's caption.
pub(super) const CAPTION: u32 = 20;
/// A figure's title.
pub(super) const TITLE: u32 = 22;
/// The colour of a panel's i-th series (its key swatch is drawn in it too).
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
