//! Text written into markup: LaTeX symbols, and escaping for Markdown tables and LaTeX, so
//! that text from a model file never changes the structure of what it is written into; and
//! what such text may be at all (printable, visible, bounded: [`TextError`]).

const GREEK: [(char, &str); 12] = [
    ('φ', "\\phi"),
    ('θ', "\\theta"),
    ('ψ', "\\psi"),
    ('χ', "\\chi"),
    ('α', "\\alpha"),
    ('β', "\\beta"),
    ('γ', "\\gamma"),
    ('ξ', "\\xi"),
    ('η', "\\eta"),
    ('ρ', "\\rho"),
    ('κ', "\\kappa"),
    ('ζ', "\\zeta"),
];

/// A symbol in LaTeX math: Greek letters to commands, LaTeX's special characters escaped, the
/// rest unchanged.
pub fn latex_symbol(s: &str) -> String {
    s.chars()
        .map(|c| {
            if let Some((_, l)) = GREEK.iter().find(|(g, _)| *g == c) {
                return format!("{l} ");
            }
            match c {
                '\\' => "\\backslash ".into(),
                '{' | '}' | '$' | '&' | '%' | '#' | '_' => format!("\\{c}"),
                '^' => "\\hat{} ".into(),
                '~' => "\\sim ".into(),
                c => c.to_string(),
            }
        })
        .collect::<String>()
        .trim_end()
        .to_string()
}

/// The most characters of untrusted input an error message quotes.
pub const QUOTE_LIMIT: usize = 80;

/// `s` quoted for an error message, cut to [`QUOTE_LIMIT`] characters (`"abc…" (1048576
/// characters)` when longer), so a megabyte of input is never echoed back.
pub fn clip(s: &str) -> String {
    let len = s.chars().count();
    if len <= QUOTE_LIMIT {
        format!("{s:?}")
    } else {
        let head: String = s.chars().take(QUOTE_LIMIT).collect();
        format!("{:?} ({len} characters)", head + "…")
    }
}

/// A word the shell reads as itself: plain words as they are, others in single quotes (a quote
/// inside as `'\''`); a word with control characters is clipped, never printed raw.
pub fn shell_word(s: &str) -> String {
    if s.chars().any(char::is_control) {
        return clip(s);
    }
    if !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "_./-+=:,".contains(c))
    {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}

/// `theory-search SUB FILE… [--model M]`, every word as the shell reads it: the start of a
/// command a report prints for the recordings it read (`FILE` when it does not know them).
pub fn command_line(sub: &str, inputs: &[String], model: Option<&str>) -> String {
    let mut line = format!("theory-search {sub}");
    if inputs.is_empty() {
        line += " FILE";
    }
    for i in inputs {
        line += " ";
        line += &shell_word(i);
    }
    if let Some(m) = model {
        line += " --model ";
        line += &shell_word(m);
    }
    line
}

/// A cell of a Markdown table: `|` and `\\` escaped, so text from a model file never adds a
/// column.
pub fn markdown_cell(s: &str) -> String {
    s.replace('\\', "\\\\").replace('|', "\\|")
}

/// `s` with every control or invisible formatting character ([`is_invisible`]) written as
/// its escape (`\u{202e}`), as Rust's `{:?}` writes them in a quoted model name: a quoted line
/// of input never reorders or hides the message around it.
pub fn visible(s: &str) -> String {
    if !s.chars().any(|c| c.is_control() || is_invisible(c)) {
        return s.to_string();
    }
    s.chars()
        .map(|c| match c.is_control() || is_invisible(c) {
            true => c.escape_unicode().to_string(),
            false => c.to_string(),
        })
        .collect()
}

/// Fold a multi-line message (TOML errors quote the offending line) onto one line, each line
/// bounded as [`bound_line`] bounds one (invisible characters escaped, long words cut, long
/// numbers in short form): the Python exceptions of library errors are as bounded as the
/// command line's.
pub fn one_line(s: &str) -> String {
    s.split('\n')
        .map(|l| bound_line(l.trim()))
        .filter(|l| !l.is_empty() && l.chars().any(|c| c.is_alphanumeric()))
        .map(|l| {
            // A quoted line of input is cut: a 1 MB line is not echoed back.
            let limit = 2 * QUOTE_LIMIT;
            if l.chars().count() > limit {
                l.chars().take(limit).collect::<String>() + "…"
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// The longest error line printed, in characters.
pub const LINE_LIMIT: usize = 1000;

/// One line of an error message, bounded: invisible characters escaped ([`visible`]), numbers
/// printed out in hundreds of digits put in short form ([`short_numbers`]), every word (a run
/// without spaces, such as a quoted value or a path) longer than 2 × [`QUOTE_LIMIT`]
/// characters cut to [`QUOTE_LIMIT`] with its length said, and the line to [`LINE_LIMIT`]
/// characters.
pub fn bound_line(s: &str) -> String {
    let words: Vec<String> = s
        .split(' ')
        .map(|w| short_numbers(&visible(w)))
        .map(|w| {
            let len = w.chars().count();
            if len > 2 * QUOTE_LIMIT {
                let head: String = w.chars().take(QUOTE_LIMIT).collect();
                format!("{head}… ({len} characters)")
            } else {
                w.to_string()
            }
        })
        .collect();
    let line = words.join(" ");
    if line.chars().count() > LINE_LIMIT {
        line.chars().take(LINE_LIMIT).collect::<String>() + "…"
    } else {
        line
    }
}

/// Digits in a number's plain form beyond which it is written in exponent form: more than
/// any `u64` has, so a count or an index is never rewritten.
const LONG_NUMBER: usize = 20;

/// `w` with every number that `{}` wrote out for an `f64` in more than [`LONG_NUMBER`]
/// digits (1e300: 301 digits, at most 17 of them significant) in short form
/// ([`crate::report::number`]). Digits that are part of a name or a path (`x1000…`, `/1000…/`),
/// or carry more significant digits than an `f64` prints, are left alone.
pub fn short_numbers(w: &str) -> String {
    let named = |c: Option<&char>| c.is_some_and(|&c| c.is_alphanumeric() || "_/\\".contains(c));
    let chars: Vec<char> = w.chars().collect();
    let mut out = String::with_capacity(w.len());
    let mut i = 0;
    while i < chars.len() {
        if !chars[i].is_ascii_digit() || named(i.checked_sub(1).map(|j| &chars[j])) {
            out.push(chars[i]);
            i += 1;
            continue;
        }
        let mut end = i + 1;
        while end < chars.len()
            && (chars[end].is_ascii_digit() || (chars[end] == '.' && !chars[i..end].contains(&'.')))
        {
            end += 1;
        }
        // A trailing full stop ends a sentence, not the number.
        let stop = usize::from(chars[end - 1] == '.');
        let text: String = chars[i..end - stop].iter().collect();
        let digits: String = text.chars().filter(char::is_ascii_digit).collect();
        let significant = digits.trim_matches('0').len();
        match text.parse::<f64>() {
            // Typed digits past f64's range stay digits (cut as a word), never `inf`.
            Ok(v)
                if digits.len() > LONG_NUMBER
                    && significant <= 17
                    && v.is_finite()
                    && !named(chars.get(end)) =>
            {
                out.push_str(&crate::report::number(v));
            }
            _ => out.push_str(&text),
        }
        out.extend(&chars[end - stop..end]);
        i = end;
    }
    out
}

/// Markdown as plain aligned text: headings lose their `#`s, tables become columns padded to
/// their widest cell (the separator row dropped), inline code loses its backticks.
pub fn plain_from_markdown(md: &str) -> String {
    fn flush(table: &mut Vec<Vec<String>>, out: &mut String) {
        let columns = table.iter().map(Vec::len).max().unwrap_or(0);
        let widths: Vec<usize> = (0..columns)
            .map(|c| {
                table
                    .iter()
                    .filter_map(|r| r.get(c))
                    .map(|x| x.chars().count())
                    .max()
                    .unwrap_or(0)
            })
            .collect();
        for row in table.drain(..) {
            let cells: Vec<String> = row
                .iter()
                .zip(&widths)
                .map(|(x, w)| format!("{x:<w$}"))
                .collect();
            *out += cells.join("  ").trim_end();
            out.push('\n');
        }
    }
    let mut out = String::new();
    let mut table: Vec<Vec<String>> = Vec::new();
    for line in md.lines() {
        let line = line.replace('`', "");
        if let Some(inner) = line.strip_prefix('|') {
            let cells: Vec<String> = inner
                .trim_end_matches('|')
                .split('|')
                .map(|c| c.trim().to_string())
                .collect();
            if !cells
                .iter()
                .all(|c| !c.is_empty() && c.chars().all(|x| x == '-' || x == ':'))
            {
                table.push(cells);
            }
            continue;
        }
        flush(&mut table, &mut out);
        out += line.trim_start_matches('#').trim_start();
        out.push('\n');
    }
    flush(&mut table, &mut out);
    out
}

/// Why a piece of model text is refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TextError {
    /// A control character (it could end a line of generated code or CSV).
    #[error("{key} contains the control character U+{code:04X}")]
    Control {
        /// Which text.
        key: String,
        /// The character's code point.
        code: u32,
    },
    /// An invisible formatting character (bidirectional overrides and isolates, zero-width
    /// characters, line separators): rustc refuses them in generated code, and a reader cannot
    /// see them.
    #[error("{key} contains the invisible formatting character U+{code:04X}")]
    Invisible {
        /// Which text.
        key: String,
        /// The character's code point.
        code: u32,
    },
    /// Longer than its limit.
    #[error("{key} has {len} characters; at most {max}")]
    TooLong {
        /// Which text.
        key: String,
        /// Its length in characters.
        len: usize,
        /// The limit.
        max: usize,
    },
    /// Not an identifier.
    #[error("{key} {} must be an ASCII letter or '_' then letters, digits or '_' (at most 32)", crate::markup::clip(.value))]
    NotIdentifier {
        /// Which text.
        key: String,
        /// The text.
        value: String,
    },
}

/// Characters that change how text is displayed without being seen: bidirectional controls
/// (U+202A–U+202E, U+2066–U+2069, U+061C, U+200E, U+200F), zero-width and joiner characters,
/// word joiners and invisible operators, the byte-order mark, the soft hyphen, and the line
/// and paragraph separators.
pub fn is_invisible(c: char) -> bool {
    matches!(c,
        '\u{00AD}' | '\u{061C}' | '\u{180E}' | '\u{200B}'..='\u{200F}' | '\u{2028}'..='\u{202E}'
        | '\u{2060}'..='\u{206F}' | '\u{FEFF}' | '\u{FFF9}'..='\u{FFFB}')
}

/// Model text (names, symbols, meanings) reaches generated code, CSV and SVG: it must be
/// printable (no control or invisible formatting characters) and at most `max` characters.
pub(crate) fn text(key: &str, value: &str, max: usize) -> Result<(), TextError> {
    if let Some(c) = value.chars().find(|c| c.is_control()) {
        return Err(TextError::Control {
            key: key.into(),
            code: c as u32,
        });
    }
    if let Some(c) = value.chars().find(|&c| is_invisible(c)) {
        return Err(TextError::Invisible {
            key: key.into(),
            code: c as u32,
        });
    }
    let len = value.chars().count();
    if len > max {
        return Err(TextError::TooLong {
            key: key.into(),
            len,
            max,
        });
    }
    Ok(())
}

/// Ids and scale names: an ASCII letter or `_`, then letters, digits or `_`, at most 32.
pub(crate) fn identifier(key: &str, value: &str) -> Result<(), TextError> {
    let mut chars = value.chars();
    let first_ok = chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
    if !first_ok || !chars.all(|c| c.is_ascii_alphanumeric() || c == '_') || value.len() > 32 {
        return Err(TextError::NotIdentifier {
            key: key.into(),
            value: value.into(),
        });
    }
    Ok(())
}
