//! Text written into markup: LaTeX symbols, and escaping for Markdown tables and LaTeX, so
//! that text from a model file never changes the structure of what it is written into.

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

/// A cell of a Markdown table: `|` and `\\` escaped, so text from a model file never adds a
/// column.
pub fn markdown_cell(s: &str) -> String {
    s.replace('\\', "\\\\").replace('|', "\\|")
}

/// Fold a multi-line message (TOML errors quote the offending line) onto one line.
pub fn one_line(s: &str) -> String {
    s.split('\n')
        .map(str::trim)
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

/// One line of an error message, bounded: every word (a run without spaces, such as a quoted
/// value or a path) longer than 2 × [`QUOTE_LIMIT`] characters is cut to [`QUOTE_LIMIT`] with
/// its length said, and the line to [`LINE_LIMIT`] characters.
pub fn bound_line(s: &str) -> String {
    let words: Vec<String> = s
        .split(' ')
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
