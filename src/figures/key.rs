//! A figure's keys: the entries of a panel's key, laid out in rows and drawn in a strip above
//! the chart (never over data), and the entries several panels share, drawn once for the
//! figure (one meaning, one colour, one entry).

use std::borrow::Cow;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::series::{marker_style, merged_markers, Area, Mark, Panel, TEXT};
use super::{err, FigureError};

/// One entry of a key: its label, colour and mark (a marker line is a line or a dashed one).
#[derive(PartialEq)]
pub(super) struct Key<'p> {
    label: Cow<'p, str>,
    color: RGBColor,
    mark: Mark,
}

/// The pixel width of `label` at [`TEXT`], by DejaVu Sans' widths: digits 0.64 em, capitals
/// 0.7, a space 0.32, the rest 0.56 (at 0.55 em for every character a key with numbers ran
/// into the next panel's).
pub(super) fn text_width(label: &str) -> f64 {
    let em: f64 = (label.chars())
        .filter(|c| !super::script::is_mark(*c))
        .map(|c| match c {
            '0'..='9' => 0.64,
            'A'..='Z' => 0.7,
            ' ' => 0.32,
            _ => 0.56,
        })
        .sum();
    em * TEXT as f64 / 1.24
}

/// The key's entries laid out in rows across `width` pixels: (row, x) per entry, and rows.
pub(super) fn key_rows(keys: &[Key], width: f64) -> (Vec<(usize, f64)>, usize) {
    let (mut row, mut x) = (0, 8.0);
    let mut at = Vec::new();
    for k in keys {
        let w = 24.0 + text_width(&k.label) + 24.0;
        if x > 8.0 && x + w > width - 4.0 {
            row += 1;
            x = 8.0;
        }
        at.push((row, x));
        x += w;
    }
    (at, if keys.is_empty() { 0 } else { row + 1 })
}

/// Height of a key row, in pixels.
pub(super) const KEY_ROW: f64 = TEXT as f64 * 1.3;

/// Draw the key in a strip above the chart (it never covers data, and the axes stay on the
/// data): a swatch drawn as the series is, then its label. Returns the area below the strip.
pub(super) fn keyed<'a>(
    area: &Area<'a>,
    keys: &[Key],
    least: usize,
) -> Result<Area<'a>, FigureError> {
    let width = area.dim_in_pixel().0 as f64;
    let (at, rows) = key_rows(keys, width);
    let rows = rows.max(least);
    if rows == 0 {
        return Ok(area.clone());
    }
    let band = (rows as f64 * KEY_ROW + 8.0).ceil() as u32;
    let (strip, rest) = area.split_vertically(band);
    strip
        .draw(&Rectangle::new(
            [(2, 1), (width as i32 - 2, band as i32 - 2)],
            WHITE.mix(0.85).filled(),
        ))
        .map_err(err)?;
    let style =
        TextStyle::from(("sans-serif", TEXT).into_font()).pos(Pos::new(HPos::Left, VPos::Center));
    for (k, &(row, x)) in keys.iter().zip(&at) {
        let y = (4.0 + (row as f64 + 0.5) * KEY_ROW) as i32;
        let x = x as i32;
        let c = k.color;
        match k.mark {
            Mark::Line => strip
                .draw(&PathElement::new(
                    vec![(x, y), (x + 18, y)],
                    c.stroke_width(2),
                ))
                .map_err(err)?,
            Mark::Dashed => {
                strip
                    .draw(&PathElement::new(
                        vec![(x, y), (x + 7, y)],
                        c.stroke_width(2),
                    ))
                    .map_err(err)?;
                strip
                    .draw(&PathElement::new(
                        vec![(x + 11, y), (x + 18, y)],
                        c.stroke_width(2),
                    ))
                    .map_err(err)?
            }
            Mark::Dots => strip
                .draw(&Circle::new((x + 9, y), 3, c.filled()))
                .map_err(err)?,
            Mark::Bars(_) => strip
                .draw(&Rectangle::new(
                    [(x + 2, y - 5), (x + 16, y + 5)],
                    c.mix(0.45).filled(),
                ))
                .map_err(err)?,
            Mark::Errors => {
                strip
                    .draw(&PathElement::new(
                        vec![(x + 9, y - 6), (x + 9, y + 6)],
                        c.stroke_width(2),
                    ))
                    .map_err(err)?;
                strip
                    .draw(&PathElement::new(vec![(x + 6, y - 6), (x + 12, y - 6)], c))
                    .map_err(err)?
            }
        }
        strip
            .draw_text(&k.label, &style, (x + 24, y))
            .map_err(err)?;
    }
    Ok(rest)
}

/// A panel's key: its named series that have points (the key says what is drawn), then its
/// marker lines, styled by their place in the figure's markers `marks`.
pub(super) fn keys<'p>(p: &'p Panel, marks: &[String]) -> Vec<Key<'p>> {
    let series = p.series.iter().enumerate();
    series
        .filter(|(_, s)| !s.name.is_empty() && !s.points.is_empty())
        .map(|(i, s)| Key {
            label: Cow::Borrowed(&s.name),
            color: s.color(i),
            mark: s.mark,
        })
        .chain(merged_markers(p).into_iter().map(|m| {
            let (color, mark) = marker_style(&m.1, marks);
            Key {
                label: Cow::Owned(m.1),
                color,
                mark,
            }
        }))
        .collect()
}

/// The entries two or more of `panels` have alike (label, colour and mark), in the order they
/// first appear: the figure shows them once, under its title, and no panel repeats them.
pub(super) fn common_keys<'p>(panels: &'p [Panel], marks: &[String]) -> Vec<Key<'p>> {
    let each: Vec<Vec<Key>> = panels.iter().map(|p| keys(p, marks)).collect();
    let mut common: Vec<Key> = Vec::new();
    for (i, ks) in each.iter().enumerate() {
        for k in ks {
            let again = each[i + 1..].iter().any(|o| o.contains(k));
            if again && !common.contains(k) {
                common.push(Key {
                    label: k.label.clone(),
                    color: k.color,
                    mark: k.mark,
                });
            }
        }
    }
    common
}

/// Panel `p`'s own key: its entries that the figure's key (`common`) does not show.
pub(super) fn own_keys<'p>(p: &'p Panel, common: &[Key], marks: &[String]) -> Vec<Key<'p>> {
    keys(p, marks)
        .into_iter()
        .filter(|k| !common.contains(k))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figures::series::{panel, series};

    #[test]
    fn a_series_with_nothing_drawn_has_no_entry() {
        let p = panel(
            "",
            "",
            "",
            vec![
                series("voting modes", vec![], Mark::Dots),
                series("other modes", vec![(1.0, 2.0)], Mark::Dots),
            ],
        );
        let k = keys(&p, &[]);
        assert_eq!(k.len(), 1);
        assert_eq!(k[0].label, "other modes");
    }

    #[test]
    fn entries_two_panels_share_are_the_figures() {
        let p = |hue: usize| {
            let mut p = panel(
                "",
                "",
                "",
                vec![series("other modes", vec![(1.0, 2.0)], Mark::Dots).hue(hue)],
            );
            p.markers = vec![(1.0, "attach".into())];
            p
        };
        let marks = vec!["attach".to_string()];
        // One colour: one entry for both panels, each keeping none of its own.
        let same = [p(7), p(7)];
        let common = common_keys(&same, &marks);
        assert_eq!(common.len(), 2);
        assert!(own_keys(&same[1], &common, &marks).is_empty());
        // Two colours for one label: the entry is each panel's own.
        let differ = [p(7), p(2)];
        let common = common_keys(&differ, &marks);
        assert_eq!(common.len(), 1, "only the marker is shared");
        assert_eq!(own_keys(&differ[1], &common, &marks).len(), 1);
    }
}
