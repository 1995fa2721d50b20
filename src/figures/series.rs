//! What a figure is made of, before it is drawn: series and how each is marked, panels,
//! their colours and the text sizes (the kit in `plot` and the keys in `key` draw them).

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
}

pub(super) fn series(name: impl Into<String>, points: Vec<(f64, f64)>, mark: Mark) -> Series {
    Series {
        name: name.into(),
        points,
        mark,
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
