//! Sub- and superscripts in a figure's text: `c_y`, `ω_b` and `λ^0.079` as a page prints them.
//!
//! Unicode has superscript digits but no subscript y or z and no raised decimal point, so a
//! figure marks a script with private-use characters ([`sub`], [`sup`]) in the text it hands
//! to plotters, and [`spans`] turns each marked run into an SVG `<tspan>` once plotters has
//! written (and escaped) the text. Only a run closed on the same `<text>` becomes a span; a stray
//! mark, whatever text brought it, is dropped, so no text can open an element. A script is set
//! at three quarters of its text's size, but never under 7 pt in print.

/// Opens a subscript run.
const SUB: char = '\u{E000}';
/// Opens a superscript run.
const SUP: char = '\u{E001}';
/// Closes a run.
const END: char = '\u{E002}';

/// Whether `c` is one of the marks (not printed, not counted in a text's width).
pub(super) fn is_mark(c: char) -> bool {
    matches!(c, SUB | SUP | END)
}

/// The characters `text` prints: its length without the marks.
pub(super) fn printed_len(text: &str) -> usize {
    text.chars().filter(|c| !is_mark(*c)).count()
}

/// `s` set as a subscript.
pub(super) fn sub(s: &str) -> String {
    format!("{SUB}{s}{END}")
}

/// `s` set as a superscript.
pub(super) fn sup(s: &str) -> String {
    format!("{SUP}{s}{END}")
}

/// A name as the engine writes it (`c_y`, `cp_y`, `c'_y`, `ω_b`) with its subscript set: the
/// part after the last `_` of each word, when it is letters or digits. Text with no such word
/// comes back unchanged.
pub(super) fn symbols(text: &str) -> String {
    text.split(' ')
        .map(|word| match word.rsplit_once('_') {
            Some((base, tail)) if !base.is_empty() && !tail.is_empty() => {
                // The subscript ends where its letters do ("c_y," keeps its comma outside).
                let end = tail
                    .char_indices()
                    .find(|(_, c)| !c.is_alphanumeric())
                    .map_or(tail.len(), |(i, _)| i);
                if end == 0 {
                    word.to_string()
                } else {
                    format!("{base}{}{}", sub(&tail[..end]), &tail[end..])
                }
            }
            _ => word.to_string(),
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// 7 pt in pixels of the canvas ([`super::page::PX_PER_MM`] at every printed width), with 1 %
/// to spare: a canvas is a whole number of pixels wide, a little more than the width asks.
const LEAST_PX: f64 = 1.01 * 7.0 / 72.0 * 25.4 * super::page::PX_PER_MM;

/// The size of a script in the text whose opening tag ends at `before`'s end: three quarters of
/// the text's `font-size`, at least [`LEAST_PX`].
fn script_size(before: &str) -> f64 {
    let tag = before.rfind("<text").map_or("", |at| &before[at..]);
    let size = (tag.split("font-size=\"").nth(1))
        .and_then(|v| v.split('"').next())
        .and_then(|v| v.parse::<f64>().ok())
        .unwrap_or(LEAST_PX);
    // Rounded up to the hundredth the tag is written with: never a hair under 7 pt.
    ((0.75 * size).max(LEAST_PX) * 100.0).ceil() / 100.0
}

/// The SVG `svg` with every marked run turned into a `<tspan>` and every stray mark dropped.
pub(super) fn spans(svg: &str) -> String {
    let mut out = String::with_capacity(svg.len());
    let mut rest = svg;
    while let Some(at) = rest.find(is_mark) {
        out.push_str(&rest[..at]);
        let mark = rest[at..].chars().next().unwrap_or(END);
        rest = &rest[at + mark.len_utf8()..];
        if mark == END {
            continue;
        }
        // The run: up to its END, with no other mark and no markup in between.
        let close = rest.find(|c: char| is_mark(c) || c == '<');
        match close {
            Some(e) if rest[e..].starts_with(END) => {
                let shift = if mark == SUB { "sub" } else { "super" };
                let size = script_size(&out);
                out.push_str(&format!(
                    "<tspan baseline-shift=\"{shift}\" font-size=\"{size:.2}\">{}</tspan>",
                    &rest[..e]
                ));
                rest = &rest[e + END.len_utf8()..];
            }
            // An unclosed run: the mark is dropped, its text stays as it was.
            _ => {}
        }
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_take_their_subscripts() {
        assert_eq!(symbols("−c_y ∂s⁴y"), format!("−c{} ∂s⁴y", sub("y")));
        assert_eq!(
            symbols("c_y, g_x."),
            format!("c{}, g{}.", sub("y"), sub("x"))
        );
        assert_eq!(symbols("no_ _x plain"), "no_ _x plain");
        assert_eq!(printed_len(&symbols("c_y")), 2);
    }

    #[test]
    fn runs_become_spans_and_stray_marks_go() {
        let svg = format!("<text>ω{}/ω{}</text>", sub("b"), sub("f"));
        let out = spans(&svg);
        assert_eq!(out.matches("<tspan baseline-shift=\"sub\"").count(), 2);
        assert!(out.contains(">b</tspan>/ω<tspan"), "{out}");
        let sup = spans(&format!("<text font-size=\"20\">λ{}</text>", sup("0.079")));
        assert!(sup.contains("baseline-shift=\"super\" font-size=\"15.00\">0.079</tspan>"));
        // A script of small text keeps 7 pt.
        assert!(
            out.contains(&format!("font-size=\"{LEAST_PX:.2}\"")),
            "{out}"
        );
        // Unclosed, closed on another element, nested or lone: dropped, never an open tag.
        for bad in [
            format!("<text>a{SUB}b</text><text>c{END}</text>"),
            format!("<text>{SUB}{SUP}x{END}</text>"),
            format!("<text>{END}{END}x{SUB}</text>"),
        ] {
            let out = spans(&bad);
            assert_eq!(
                out.matches("<tspan").count(),
                out.matches("</tspan>").count(),
                "{out}"
            );
            assert!(!out.contains(is_mark), "{out}");
        }
    }
}
