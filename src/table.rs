//! Render analyses as the seed's Table 1 and its Rayleigh twin: aligned Unicode text, Markdown,
//! CSV, JSON (the contract other tools read) and a LaTeX `tabular`.
//!
//! Every cell comes from an [`Analysis`]; nothing here decides anything. A mark `x` means the term
//! satisfies the requirement (rule columns) or survives in that field's density (field columns),
//! as in the seed.

use serde_json::{json, Map, Value};

use crate::model::{Density, Model};
use crate::reduce::{prefactor_text, sign_joiner, Analysis, FieldResult};

/// An output format of the table command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    /// Aligned Unicode text for the terminal.
    Text,
    /// Markdown tables, as in `tables/`.
    Markdown,
    /// One CSV table, one row per candidate and density.
    Csv,
    /// The JSON contract.
    Json,
    /// LaTeX `tabular` environments and an `align*` of the densities.
    Latex,
}

const MARK: &str = "x";

fn mark(b: bool) -> String {
    if b { MARK } else { "" }.to_string()
}

/// The cells of one density's table: header, then one row per candidate.
fn cells(model: &Model, a: &Analysis) -> (Vec<String>, Vec<Vec<String>>) {
    let mut header: Vec<String> = ["term", "δ", "ε", "τ", "σ"].map(String::from).to_vec();
    header.extend(a.columns.iter().map(|r| r.code.to_string()));
    header.extend(model.fields.iter().map(|f| f.symbol.clone()));
    let rows = a
        .rows
        .iter()
        .map(|r| {
            let o = r.orders;
            let mut row = vec![r.term.to_string()];
            row.extend([o.delta, o.epsilon, o.tau, o.sigma].map(|v| v.to_string()));
            row.extend(r.passed.iter().map(|&ok| mark(ok)));
            row.extend(r.included.iter().map(|&b| mark(b)));
            row
        })
        .collect();
    (header, rows)
}

fn title(a: &Analysis) -> String {
    let kind = match a.basis {
        crate::enumerate::Basis::Powers => "candidate terms",
        crate::enumerate::Basis::Monomials => "candidate monomials",
    };
    format!(
        "{} density: {} {kind} with {}",
        a.density,
        a.rows.len(),
        a.bounds
    )
}

fn requirement_line(model: &Model, a: &Analysis) -> String {
    // Group fields with the same requirements, as the seed does ("x, θ: …; y, z: …").
    let mut groups: Vec<(Vec<String>, Vec<&str>)> = Vec::new();
    for f in &model.fields {
        let codes: Vec<&str> = model
            .requirements(a.density, &f.id)
            .iter()
            .map(|r| r.code)
            .collect();
        match groups.iter_mut().find(|(_, c)| *c == codes) {
            Some((names, _)) => names.push(f.symbol.clone()),
            None => groups.push((vec![f.symbol.clone()], codes)),
        }
    }
    let parts: Vec<String> = groups
        .iter()
        .map(|(names, codes)| {
            let codes = if codes.is_empty() {
                "none".to_string()
            } else {
                codes.join(" ")
            };
            format!("{}: {codes}", names.join(", "))
        })
        .collect();
    format!("Required: {}", parts.join("; "))
}

fn notes(a: &Analysis) -> Vec<String> {
    a.fields.iter().flat_map(|f| f.missing.clone()).collect()
}

fn width(s: &str) -> usize {
    if s.is_ascii() {
        s.len()
    } else {
        s.chars().count()
    }
}

fn spaces(out: &mut String, n: usize) {
    out.extend(std::iter::repeat_n(' ', n));
}

/// Columns padded to their widest cell, written into one string (no string per cell: the
/// modes table at N = 10⁵ has millions of cells).
fn aligned(header: &[String], rows: &[Vec<String>]) -> String {
    let widths: Vec<usize> = (0..header.len())
        .map(|c| {
            rows.iter()
                .map(|r| width(&r[c]))
                .chain([width(&header[c])])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let total = widths.iter().sum::<usize>() + 2 * (widths.len() - 1);
    let mut out = String::with_capacity((rows.len() + 2) * (total + 3));
    let line = |cells: &[String], out: &mut String| {
        out.push_str("  ");
        for (i, (c, &w)) in cells.iter().zip(&widths).enumerate() {
            let pad = w - width(c);
            // Terms read left to right; numbers and marks are centred under short headers.
            if i == 0 {
                out.push_str(c);
                spaces(out, pad);
            } else {
                out.push_str("  ");
                spaces(out, pad / 2);
                out.push_str(c);
                spaces(out, pad - pad / 2);
            }
        }
        let kept = out.trim_end_matches(' ').len();
        out.truncate(kept);
        out.push('\n');
    };
    line(header, &mut out);
    out.push_str("  ");
    out.extend(std::iter::repeat_n('─', total));
    out.push('\n');
    for r in rows {
        line(r, &mut out);
    }
    out
}

fn text(model: &Model, analyses: &[Analysis]) -> String {
    let mut out = String::new();
    for a in analyses {
        let (header, rows) = cells(model, a);
        out += &format!("{}\n", title(a));
        out += &format!("{}\n\n", requirement_line(model, a));
        out += &aligned(&header, &rows);
        out += "\n";
    }
    for a in analyses {
        out += &format!(
            "Surviving {} densities (lowest order in τ and σ):\n",
            a.density
        );
        for f in &a.fields {
            out += &format!("  {}\n", f.formula(a.density));
        }
        for n in notes(a) {
            out += &format!("  note: {n}\n");
        }
        out += "\n";
    }
    out.trim_end().to_string() + "\n"
}

fn markdown(model: &Model, analyses: &[Analysis]) -> String {
    let mut out = String::new();
    for a in analyses {
        let (header, rows) = cells(model, a);
        out += &format!("## {}\n\n{}.\n\n", title(a), requirement_line(model, a));
        let line = |c: &[String]| format!("| {} |\n", c.join(" | "));
        out += &line(&header);
        out += &format!("|{}\n", "---|".repeat(header.len()));
        for r in &rows {
            out += &line(r);
        }
        out += &format!(
            "\nSurviving {} densities (lowest order in τ and σ):\n\n",
            a.density
        );
        for f in &a.fields {
            out += &format!("- `{}`\n", f.formula(a.density));
        }
        for n in notes(a) {
            out += &format!("- note: {n}\n");
        }
        out += "\n";
    }
    out.trim_end().to_string() + "\n"
}

fn csv(model: &Model, analyses: &[Analysis]) -> String {
    // One table for all densities: the union of rule columns, empty where a rule is not a
    // requirement column of that density; 1/0 for satisfied/failed and included/not.
    let mut codes: Vec<&str> = Vec::new();
    for a in analyses {
        for r in &a.columns {
            if !codes.contains(&r.code) {
                codes.push(r.code);
            }
        }
    }
    let mut header: Vec<String> = ["density", "term", "delta", "epsilon", "tau", "sigma"]
        .map(String::from)
        .to_vec();
    header.extend(codes.iter().map(|c| c.to_string()));
    header.extend(model.fields.iter().map(|f| f.id.clone()));
    let bit = |b: bool| if b { "1" } else { "0" }.to_string();
    let mut rows = Vec::new();
    for a in analyses {
        for r in &a.rows {
            let o = r.orders;
            let mut row = vec![a.density.key().to_string(), r.term.to_string()];
            row.extend([o.delta, o.epsilon, o.tau, o.sigma].map(|v| v.to_string()));
            for code in &codes {
                let v = a.columns.iter().position(|c| c.code == *code);
                row.push(v.map(|i| bit(r.passed[i])).unwrap_or_default());
            }
            row.extend(r.included.iter().map(|&b| bit(b)));
            rows.push(row);
        }
    }
    crate::report::csv_table(&header, rows)
}

fn field_map<T: Into<Value>>(
    fields: &[FieldResult],
    value: impl Fn(usize, &FieldResult) -> T,
) -> Value {
    let mut m = Map::new();
    for (i, f) in fields.iter().enumerate() {
        m.insert(f.field.id.clone(), value(i, f).into());
    }
    Value::Object(m)
}

/// The JSON of one density (the contract's `"lagrangian"` / `"rayleigh"` object).
fn json_density(model: &Model, a: &Analysis) -> Value {
    let rows: Vec<Value> = a
        .rows
        .iter()
        .map(|r| {
            let o = r.orders;
            let factors: Vec<Value> = r
                .term
                .factors()
                .iter()
                .map(|f| {
                    let mut v = json!({"t": f.deriv.t, "s": f.deriv.s, "power": f.power});
                    if f.field != 0 {
                        v["field"] = json!(f.field);
                    }
                    v
                })
                .collect();
            let mut satisfies = Map::new();
            let mut rejected = Map::new();
            for (i, (rule, &ok)) in a.columns.iter().zip(&r.passed).enumerate() {
                satisfies.insert(rule.code.into(), ok.into());
                if let Some(why) = r.why(a, i) {
                    rejected.insert(rule.code.into(), why.into());
                }
            }
            json!({
                "term": r.term.to_string(),
                "factors": factors,
                "delta": o.delta, "epsilon": o.epsilon, "tau": o.tau, "sigma": o.sigma,
                "satisfies": satisfies,
                "included": field_map(&a.fields, |i, _| r.included[i]),
                "admitted": field_map(&a.fields, |i, _| r.admitted[i]),
                "rejected": rejected,
            })
        })
        .collect();
    let codes = |f: &FieldResult| -> Vec<Value> {
        model
            .requirements(a.density, &f.field.id)
            .iter()
            .map(|r| r.code.into())
            .collect()
    };
    json!({
        "basis": match a.basis {
            crate::enumerate::Basis::Powers => "powers",
            crate::enumerate::Basis::Monomials => "monomials",
        },
        "bound": a.bounds.to_string(),
        "requirements": a.columns.iter().map(|r| r.code).collect::<Vec<_>>(),
        "fields": model.fields.iter().map(|f| f.id.as_str()).collect::<Vec<_>>(),
        "rows": rows,
        "survivors": field_map(&a.fields, |_, f| {
            f.survivors.iter().map(|t| Value::from(t.to_string())).collect::<Vec<_>>()
        }),
        "field_requirements": field_map(&a.fields, |_, f| codes(f)),
        "densities": field_map(&a.fields, |_, f| f.formula(a.density)),
        "notes": notes(a),
    })
}

/// The JSON report: `{"order": N, "model": …, "lagrangian": {…}, "rayleigh": {…}}`, with only
/// the densities analysed.
pub fn json_report(model: &Model, analyses: &[Analysis]) -> Value {
    let mut top = Map::new();
    top.insert(
        "order".into(),
        analyses.first().map(|a| a.order).unwrap_or(0).into(),
    );
    top.insert("model".into(), model.name.clone().into());
    for a in analyses {
        top.insert(a.density.key().into(), json_density(model, a));
    }
    Value::Object(top)
}

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

/// A symbol in LaTeX math: Greek letters to commands, the rest unchanged.
pub fn latex_symbol(s: &str) -> String {
    s.chars()
        .map(|c| {
            GREEK
                .iter()
                .find(|(g, _)| *g == c)
                .map(|(_, l)| format!("{l} "))
                .unwrap_or_else(|| c.to_string())
        })
        .collect::<String>()
        .trim_end()
        .to_string()
}

fn latex_formula(density: Density, f: &FieldResult) -> String {
    let sym = latex_symbol(&f.field.symbol);
    let mut out = format!("{}_{{{sym}}} &=", density.letter());
    if f.density.is_empty() {
        return out + " 0";
    }
    for (i, dt) in f.density.iter().enumerate() {
        out += &sign_joiner(i, dt.sign < 0, "-");
        let p = prefactor_text(dt.prefactor);
        let mut pieces: Vec<String> = Vec::new();
        if let Some((n, d)) = p.split_once('/') {
            pieces.push(format!("\\tfrac{{{n}}}{{{d}}}"));
        } else if p == "½" {
            pieces.push("\\tfrac{1}{2}".to_string());
        } else if !p.is_empty() {
            pieces.push(p);
        }
        if let Some(param) = &dt.parameter {
            let (base, _) = param.split_once('_').unwrap_or((param, ""));
            pieces.push(format!("{base}_{{{sym}}}"));
        }
        pieces.push(dt.term.render_latex(&|_| sym.clone()));
        out += &pieces.join(" ");
    }
    out
}

fn latex(model: &Model, analyses: &[Analysis]) -> String {
    let mut out =
        String::from("% Generated by theory-search; needs no package beyond LaTeX itself.\n");
    for a in analyses {
        let (_, rows) = cells(model, a);
        let ncols = a.columns.len();
        let nfields = model.fields.len();
        out += &format!("% {}\n", title(a));
        out += &format!(
            "\\begin{{tabular}}{{l|cccc|{}|{}}}\n\\hline\n",
            "c".repeat(ncols),
            "c".repeat(nfields)
        );
        let mut header: Vec<String> = ["Term", "$\\delta$", "$\\epsilon$", "$\\tau$", "$\\sigma$"]
            .map(String::from)
            .to_vec();
        header.extend(a.columns.iter().map(|r| r.code.to_string()));
        header.extend(
            model
                .fields
                .iter()
                .map(|f| format!("${}$", latex_symbol(&f.symbol))),
        );
        out += &format!("{} \\\\\n\\hline\n", header.join(" & "));
        for (row, r) in rows.iter().zip(&a.rows) {
            let mut cells = row.clone();
            cells[0] = format!("${}$", r.term.render_latex(&|_| "\\phi".to_string()));
            out += &format!("{} \\\\\n", cells.join(" & "));
        }
        out += "\\hline\n\\end{tabular}\n\n";
        out += "\\begin{align*}\n";
        let lines: Vec<String> = a
            .fields
            .iter()
            .map(|f| latex_formula(a.density, f))
            .collect();
        out += &lines.join(" \\\\\n");
        out += "\n\\end{align*}\n";
        for n in notes(a) {
            out += &format!("% note: {n}\n");
        }
        out += "\n";
    }
    out.trim_end().to_string() + "\n"
}

/// Render `analyses` (one per density, same order) of `model` in `format`.
pub fn render(model: &Model, analyses: &[Analysis], format: Format) -> String {
    match format {
        Format::Text => text(model, analyses),
        Format::Markdown => markdown(model, analyses),
        Format::Csv => csv(model, analyses),
        Format::Json => {
            let mut s = serde_json::to_string_pretty(&json_report(model, analyses))
                .unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"));
            s.push('\n');
            s
        }
        Format::Latex => latex(model, analyses),
    }
}

/// `0.1234` style: 6 significant digits, scientific outside 1e-4…1e6.
fn num(v: f64) -> String {
    if v == 0.0 {
        "0".to_string()
    } else if v.abs() >= 1e-4 && v.abs() < 1e6 {
        let digits = (5 - v.abs().log10().floor() as i32).clamp(0, 10) as usize;
        let s = format!("{v:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.5e}")
    }
}

fn percent(v: f64) -> String {
    format!("{:.2} %", 100.0 * v)
}

/// The modes of every field, a table each, readable at a glance.
pub fn modes_text(model: &Model, points: usize, modes: &[crate::modal::FieldModes]) -> String {
    let mut out = format!("Modes of the {} model on N = {points} points\n", model.name);
    out += "ωᵢ = ω√λᵢ, ζᵢ = ζ√λᵢ, ω_d = ωᵢ√(1−ζᵢ²); share = λᵢ⁻¹/Σλⱼ⁻¹ over all non-zero modes (equipartition).\n";
    for f in modes {
        let sp = &f.spectrum;
        let scale = f.field.scale();
        out += &format!(
            "\n{} ({}) · {} boundary · Δ{} operator, {} modes ({}) · ω_{scale} = {}, ζ_{scale} = {} · Σλ⁻¹ = {}\n",
            f.field.id,
            f.field.meaning,
            crate::discretise::boundary_name(f.field.boundary),
            crate::term::superscript(f.k),
            sp.size,
            sp.method.name(),
            num(f.omega),
            num(f.zeta),
            num(sp.inverse_trace),
        );
        let beam = !f.beam.is_empty();
        let eq17 = f.beam.iter().any(|b| b.seed_eq17.is_some());
        // Each mode's beam comparison by index: one lookup per row, not a scan (O(N²) at N = 10⁵).
        let beams: std::collections::HashMap<usize, &crate::modal::BeamComparison> =
            f.beam.iter().map(|b| (b.index, b)).collect();
        let mut header: Vec<String> = [
            "i",
            "λᵢ",
            "ωᵢ",
            "ζᵢ",
            "ω_d",
            "regime",
            "share",
            "cumulative",
        ]
        .map(String::from)
        .to_vec();
        if eq17 {
            header.extend(["Eq. 17", "off"].map(String::from));
        }
        if beam {
            header.extend(["beam limit", "off"].map(String::from));
        }
        let rows: Vec<Vec<String>> = f
            .modes
            .iter()
            .map(|m| {
                let mut row = vec![
                    m.index.to_string(),
                    num(m.eigenvalue),
                    num(m.frequency),
                    num(m.damping_ratio),
                    m.damped_frequency.map(num).unwrap_or_else(|| "—".into()),
                    m.zero_mode
                        .as_ref()
                        .map(|z| format!("zero mode: {z}"))
                        .unwrap_or_else(|| m.regime.name().to_string()),
                    percent(m.variance_share),
                    percent(m.cumulative_share),
                ];
                if beam {
                    match beams.get(&m.index) {
                        Some(b) => {
                            let off = |x: f64| {
                                let r = 100.0 * (x - b.eigenvalue) / b.eigenvalue;
                                if r.abs() >= 0.01 {
                                    format!("{r:+.2} %")
                                } else {
                                    format!("{r:+.1e} %")
                                }
                            };
                            if let Some(e) = b.seed_eq17 {
                                row.extend([num(e), off(e)]);
                            }
                            row.extend([num(b.continuum), off(b.continuum)]);
                        }
                        None => {
                            let blanks = if eq17 { 4 } else { 2 };
                            row.extend(std::iter::repeat_n(String::new(), blanks));
                        }
                    }
                }
                row
            })
            .collect();
        out += &aligned(&header, &rows);
        if !f.degenerate_pairs.is_empty() {
            let pairs: Vec<String> = f
                .degenerate_pairs
                .iter()
                .map(|(i, j)| format!("({i}, {j})"))
                .collect();
            out += &format!("  degenerate pairs: {}\n", pairs.join(" "));
        }
        if let Some(other) = &f.same_frequencies_as {
            out += &format!("  same operator and scales as {other}: identical frequencies\n");
        }
        if eq17 {
            // Eq. 17's limit (iπ)⁴ against the beam's (β₁L)⁴, for the first mode.
            let gap = 100.0 * ((std::f64::consts::PI / crate::modal::beam_beta(1)).powi(4) - 1.0);
            out += "  Eq. 17 is the seed's 16 sin⁴(πi/(2(N−1))); the beam limit is (βᵢL)⁴/(N−1)⁴ with cos βL cosh βL = 1.\n";
            out += &format!("  As N grows the numerics converge to the beam limit; Eq. 17 tends to (iπ)⁴/(N−1)⁴ and stays off\n  ({gap:+.1} % for the first mode): the seed's claim that it becomes exact is false.\n").replace('-', "−");
        } else if beam {
            out += &format!(
                "  The beam limit is (βᵢL)⁴/(N−1)⁴ of the continuous Euler–Bernoulli beam with these ends ({}).\n",
                crate::discretise::boundary_name(f.field.boundary)
            );
        }
        if let Some(v) = &sp.shapes {
            out += "  shapes (columns = modes):\n";
            for i in 0..v.nrows() {
                let cells: Vec<String> = (0..v.ncols())
                    .map(|c| format!("{:>9.5}", v[(i, c)]))
                    .collect();
                out += &format!("  {}\n", cells.join(" "));
            }
        }
    }
    out
}

/// The JSON contract of `modes`.
pub fn modes_json(points: usize, modes: &[crate::modal::FieldModes]) -> Value {
    let fields: Vec<Value> = modes
        .iter()
        .map(|f| {
            let col = |g: &dyn Fn(&crate::modal::Mode) -> Value| f.modes.iter().map(g).collect::<Vec<_>>();
            let mut v = json!({
                "field": f.field.id,
                "boundary": crate::discretise::boundary_name(f.field.boundary),
                "size": f.spectrum.size,
                "method": f.spectrum.method.name(),
                "omega": f.omega,
                "zeta": f.zeta,
                "eigenvalues": col(&|m| m.eigenvalue.into()),
                "frequencies": col(&|m| m.frequency.into()),
                "damping_ratios": col(&|m| m.damping_ratio.into()),
                "damped_frequencies": col(&|m| m.damped_frequency.map_or(Value::Null, Value::from)),
                "regimes": col(&|m| m.regime.name().into()),
                "variance_share": col(&|m| m.variance_share.into()),
                "cumulative_share": col(&|m| m.cumulative_share.into()),
                "inverse_eigenvalue_sum": f.spectrum.inverse_trace,
                "zero_modes": f.modes.iter().filter(|m| m.zero_mode.is_some()).map(|m| m.index).collect::<Vec<_>>(),
                "zero_mode_names": f.modes.iter().filter_map(|m| m.zero_mode.clone()).collect::<Vec<_>>(),
                "degenerate_pairs": f.degenerate_pairs.iter().map(|&(i, j)| json!([i, j])).collect::<Vec<_>>(),
                "same_frequencies_as": f.same_frequencies_as,
            });
            if !f.beam.is_empty() {
                v["beam_comparison"] = f
                    .beam
                    .iter()
                    .map(|b| json!({"index": b.index, "eigenvalue": b.eigenvalue, "seed_eq17": b.seed_eq17, "continuum": b.continuum}))
                    .collect::<Vec<_>>()
                    .into();
            }
            if let Some(s) = &f.spectrum.shapes {
                v["shapes"] = (0..s.ncols())
                    .map(|c| (0..s.nrows()).map(|i| s[(i, c)]).collect::<Vec<f64>>())
                    .collect::<Vec<_>>()
                    .into();
            }
            v
        })
        .collect();
    json!({"points": points, "fields": fields})
}

/// One CSV row per mode (and, with shapes, the shape's components on the body's points as
/// `v0 … v(n−1)`), written with the `csv` crate (zero-mode names come from the model file).
pub fn modes_csv(modes: &[crate::modal::FieldModes], shapes: bool) -> String {
    let mut header: Vec<String> = [
        "field",
        "index",
        "eigenvalue",
        "frequency",
        "damping_ratio",
        "damped_frequency",
        "regime",
        "variance_share",
        "cumulative_share",
        "zero_mode",
    ]
    .iter()
    .map(|h| h.to_string())
    .collect();
    let width = modes
        .iter()
        .filter_map(|f| f.spectrum.shapes.as_ref().map(|s| s.nrows()))
        .max()
        .unwrap_or(0);
    if shapes {
        header.extend((0..width).map(|i| format!("v{i}")));
    }
    let rows = modes.iter().flat_map(|f| {
        f.modes.iter().map(move |m| {
            let mut row = vec![
                f.field.id.clone(),
                m.index.to_string(),
                m.eigenvalue.to_string(),
                m.frequency.to_string(),
                m.damping_ratio.to_string(),
                m.damped_frequency
                    .map(|v| v.to_string())
                    .unwrap_or_default(),
                m.regime.name().to_string(),
                m.variance_share.to_string(),
                m.cumulative_share.to_string(),
                m.zero_mode.clone().unwrap_or_default(),
            ];
            if let Some(s) = f.spectrum.shapes.as_ref().filter(|_| shapes) {
                row.extend((0..width).map(|i| {
                    if i < s.nrows() {
                        s[(i, m.index)].to_string()
                    } else {
                        String::new()
                    }
                }));
            }
            row
        })
    });
    crate::report::csv_table(&header, rows)
}

/// `modes`: every field's modes on N points, with shapes when asked.
pub struct ModesReport<'a> {
    /// The model.
    pub model: &'a Model,
    /// Points along the body.
    pub points: usize,
    /// The modes of each field.
    pub modes: &'a [crate::modal::FieldModes],
    /// Whether the shapes go into the CSV.
    pub shapes: bool,
}

impl crate::report::Report for ModesReport<'_> {
    fn check(&self) -> Result<(), crate::report::NonFinite> {
        for f in self.modes {
            let numbers: Vec<[f64; 4]> = f
                .modes
                .iter()
                .map(|m| [m.eigenvalue, m.frequency, m.damping_ratio, m.variance_share])
                .collect();
            crate::report::check_finite(&(&f.field.id, numbers, f.spectrum.inverse_trace))?;
        }
        Ok(())
    }

    fn text(&self) -> String {
        modes_text(self.model, self.points, self.modes)
    }

    fn json(&self) -> Value {
        modes_json(self.points, self.modes)
    }

    fn csv(&self) -> Option<String> {
        Some(modes_csv(self.modes, self.shapes))
    }
}
