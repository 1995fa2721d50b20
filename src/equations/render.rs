//! Equations as people and programs read them: text, LaTeX, JSON, and the reports that hold
//! them.

use num_rational::Rational64;
use num_traits::{One, Signed};
use serde_json::{json, Value};

use super::{Equation, NonlinearEquation, NotAForce};
use crate::active::NOT_A_FORCE;
use crate::markup::latex_symbol;
use crate::reduce::sign_joiner;
use crate::term::{superscript, Deriv};

/// `∂t∂s² x`: a derivative as the paper writes it in equations.
pub fn derivative_text(d: Deriv, symbol: &str) -> String {
    let part = |c: &str, k: u32| match k {
        0 => String::new(),
        1 => format!("∂{c}"),
        k => format!("∂{c}{}", superscript(k)),
    };
    let ops = part("t", d.t) + &part("s", d.s);
    if ops.is_empty() {
        symbol.to_string()
    } else {
        format!("{ops} {symbol}")
    }
}

fn latex_derivative(d: Deriv, symbol: &str) -> String {
    let part = |c: &str, k: u32| match k {
        0 => String::new(),
        1 => format!("\\partial_{c}"),
        k => format!("\\partial_{c}^{{{k}}}"),
    };
    let ops = part("t", d.t) + &part("s", d.s);
    if ops.is_empty() {
        symbol.to_string()
    } else {
        format!("{ops} {symbol}")
    }
}

/// `∂t² φ = a − b …` from (negative, body) terms.
fn equation_text(symbol: &str, terms: impl Iterator<Item = (bool, String)>) -> String {
    let mut out = format!("{} =", derivative_text(Deriv::new(2, 0), symbol));
    let mut empty = true;
    for (i, (negative, body)) in terms.enumerate() {
        out += &sign_joiner(i, negative, "−");
        out += &body;
        empty = false;
    }
    if empty {
        out += " 0";
    }
    out
}

/// The exact factor before a coefficient, as the general path prints it: nothing for 1, `2 `,
/// `3/2 ` (text) or `\tfrac{3}{2} ` (LaTeX).
fn factor(v: Rational64, latex: bool) -> String {
    if v.is_one() {
        String::new()
    } else if latex && !v.is_integer() {
        format!("\\tfrac{{{}}}{{{}}} ", v.numer(), v.denom())
    } else {
        format!("{v} ")
    }
}

impl Equation {
    /// `∂t² x = c_x ∂s² x + 2 c'_x ∂t∂s² x`: each term with its exact factor.
    pub fn text(&self) -> String {
        let sym = &self.field.symbol;
        equation_text(
            sym,
            self.rhs.iter().map(|t| {
                let coefficient = if t.coefficient == "1" {
                    String::new()
                } else {
                    format!("{} ", t.coefficient)
                };
                let body = format!(
                    "{}{coefficient}{}",
                    factor(t.prefactor, false),
                    derivative_text(t.deriv, sym)
                );
                (t.sign < 0, body)
            }),
        )
    }

    /// The equation in LaTeX math.
    pub fn latex(&self) -> String {
        let sym = latex_symbol(&self.field.symbol);
        let mut out = format!("{} &=", latex_derivative(Deriv::new(2, 0), &sym));
        if self.rhs.is_empty() {
            return out + " 0";
        }
        for (i, t) in self.rhs.iter().enumerate() {
            out += &sign_joiner(i, t.sign < 0, "-");
            let (base, _) = t
                .coefficient
                .split_once('_')
                .unwrap_or((&t.coefficient, ""));
            out += &format!(
                "{}{base}_{{{sym}}} {}",
                factor(t.prefactor, true),
                latex_derivative(t.deriv, &sym)
            );
        }
        out
    }
}

/// The JSON contract: `{"order": N, "equations": [{"field", "rhs": [{"t","s","sign","coefficient",
/// …, "kind"}]}]}`, `kind` one of `conservative`, `dissipative`, `active`.
pub fn json(order: u32, equations: &[Equation], notes: &[String]) -> Value {
    json!({
        "order": order,
        "equations": equations.iter().map(|e| json!({
            "field": e.field.id,
            "lhs": {"t": 2, "s": 0},
            "rhs": e.rhs.iter().map(|t| json!({
                "t": t.deriv.t,
                "s": t.deriv.s,
                "sign": t.sign,
                "coefficient": t.coefficient,
                "prefactor": t.prefactor.to_string(),
                "claim": t.claim,
                "kind": t.kind,
            })).collect::<Vec<_>>(),
            "text": e.text(),
            "not_forces": not_forces_json(&e.not_forces),
        })).collect::<Vec<_>>(),
        "notes": notes,
    })
}

/// Equations as one LaTeX `align*` block.
fn align(lines: impl Iterator<Item = String>) -> String {
    let lines: Vec<String> = lines.collect();
    format!(
        "\\begin{{align*}}\n{}\n\\end{{align*}}\n",
        lines.join(" \\\\\n")
    )
}

/// The heading line and one indented line per equation, each followed by the terms on its
/// right that are not forces, if any, and why.
fn heading<'a>(
    model: &str,
    order: u32,
    how: &str,
    lines: impl Iterator<Item = (String, &'a [NotAForce])>,
) -> String {
    let mut out = format!("Equations of motion of the {model} model at order {order} ({how}):\n");
    for (l, not_forces) in lines {
        out += &format!("  {l}\n");
        if !not_forces.is_empty() {
            let terms: Vec<String> = not_forces
                .iter()
                .map(|n| format!("{} {}", n.coefficient, n.term))
                .collect();
            out += &format!("    not forces: {}: {NOT_A_FORCE}\n", terms.join(", "));
        }
    }
    out
}

/// The terms that are not forces, as JSON: coefficient, term and why.
fn not_forces_json(not_forces: &[NotAForce]) -> Value {
    not_forces
        .iter()
        .map(|n| json!({"coefficient": n.coefficient, "term": n.term, "why": NOT_A_FORCE}))
        .collect()
}

/// An equation that can be shown as text and LaTeX.
pub trait Shown {
    /// One line of text.
    fn line(&self) -> String;
    /// One LaTeX `align` row.
    fn latex_row(&self) -> String;
    /// The terms on its right that are not forces.
    fn not_forces(&self) -> &[NotAForce];
}

impl Shown for Equation {
    fn line(&self) -> String {
        self.text()
    }
    fn latex_row(&self) -> String {
        self.latex()
    }
    fn not_forces(&self) -> &[NotAForce] {
        &self.not_forces
    }
}

impl Shown for NonlinearEquation {
    fn line(&self) -> String {
        self.text()
    }
    fn latex_row(&self) -> String {
        self.latex()
    }
    fn not_forces(&self) -> &[NotAForce] {
        &self.not_forces
    }
}

/// `equations`: the equations of motion of a model at an order, with the engine's notes.
pub struct EquationReport<E = Equation> {
    /// The model's name.
    pub model: String,
    /// The order.
    pub order: u32,
    /// One equation per field.
    pub equations: Vec<E>,
    /// What could not be derived or was dropped, and why.
    pub notes: Vec<String>,
}

/// `equations` for survivors that are not all quadratic: the exact nonlinear equations.
pub type NonlinearReport = EquationReport<NonlinearEquation>;

impl<E: Shown> EquationReport<E> {
    /// The equations as a LaTeX `align*` block.
    pub fn latex(&self) -> String {
        align(self.equations.iter().map(|e| e.latex_row()))
    }

    fn heading(&self, how: &str) -> String {
        heading(
            &self.model,
            self.order,
            how,
            self.equations.iter().map(|e| (e.line(), e.not_forces())),
        )
    }
}

impl crate::report::Report for EquationReport<Equation> {
    fn text(&self) -> String {
        let mut out = self.heading("δL/δφ = δR/δ(∂tφ)");
        out += "Signs (derived from the dispersion relation, not assumed):\n";
        for t in self.equations.iter().flat_map(|e| &e.rhs) {
            out += &format!("  {}\n", t.claim.describe(&t.coefficient));
        }
        for n in &self.notes {
            out += &format!("note: {n}\n");
        }
        out
    }

    fn json(&self) -> Value {
        json(self.order, &self.equations, &self.notes)
    }

    /// One row per right-hand-side term: field, the derivative's orders, sign, exact prefactor
    /// and the free parameter.
    fn csv(&self) -> Option<String> {
        Some(crate::report::csv_table(
            &["field", "t", "s", "sign", "prefactor", "coefficient"],
            self.equations.iter().flat_map(|e| {
                e.rhs.iter().map(|t| {
                    vec![
                        e.field.id.clone(),
                        t.deriv.t.to_string(),
                        t.deriv.s.to_string(),
                        t.sign.to_string(),
                        t.prefactor.to_string(),
                        t.coefficient.clone(),
                    ]
                })
            }),
        ))
    }
}

/// `c·(∂s y)²·∂ss y` with the field's symbol.
fn monomial_text(m: &crate::parts::JetMono, symbol: &str) -> String {
    if m.is_empty() {
        return "1".into();
    }
    m.iter()
        .map(|&(d, n)| {
            let f = derivative_text(d, symbol);
            match n {
                1 => f,
                n if d.order() == 0 => format!("{f}{}", superscript(n)),
                n => format!("({f}){}", superscript(n)),
            }
        })
        .collect::<Vec<_>>()
        .join("·")
}

impl NonlinearEquation {
    /// The equation in LaTeX math.
    pub fn latex(&self) -> String {
        let sym = latex_symbol(&self.field.symbol);
        let mut out = format!("{} &=", latex_derivative(Deriv::new(2, 0), &sym));
        if self.rhs.is_empty() {
            return out + " 0";
        }
        for (i, t) in self.rhs.iter().enumerate() {
            out += &sign_joiner(i, t.value.is_negative(), "-");
            let v = t.value.abs();
            out += &factor(v, true);
            if t.coefficient != "1" {
                let (base, _) = t
                    .coefficient
                    .split_once('_')
                    .unwrap_or((&t.coefficient, ""));
                out += &format!("{base}_{{{sym}}} ");
            }
            let factors: Vec<String> = t
                .monomial
                .iter()
                .map(|&(d, n)| {
                    let f = latex_derivative(d, &sym);
                    match n {
                        1 => f,
                        n if d.order() == 0 => format!("{f}^{{{n}}}"),
                        n => format!("({f})^{{{n}}}"),
                    }
                })
                .collect();
            if !factors.is_empty() {
                out += &factors.join(" ");
            } else if v.is_one() && t.coefficient == "1" {
                out += "1";
            } else {
                let kept = out.trim_end().len();
                out.truncate(kept);
            }
        }
        out
    }
}

impl crate::report::Report for NonlinearReport {
    fn text(&self) -> String {
        let mut out =
            self.heading("δL/δφ = δR/δ(∂tφ), exact; the surviving terms are not all quadratic");
        out += "Each parameter multiplies its term as printed; the exact rational factors are shown.\n";
        for n in &self.notes {
            out += &format!("note: {n}\n");
        }
        out
    }

    fn json(&self) -> Value {
        json!({
            "order": self.order,
            "nonlinear": true,
            "equations": self.equations.iter().map(|e| e.json()).collect::<Vec<_>>(),
            "notes": self.notes,
        })
    }

    /// One row per right-hand-side term: field, exact value, parameter and the monomial.
    fn csv(&self) -> Option<String> {
        Some(crate::report::csv_table(
            &["field", "value", "coefficient", "monomial"],
            self.equations.iter().flat_map(|e| {
                e.rhs.iter().map(|t| {
                    vec![
                        e.field.id.clone(),
                        t.value.to_string(),
                        t.coefficient.clone(),
                        monomial_text(&t.monomial, &e.field.symbol),
                    ]
                })
            }),
        ))
    }
}

impl NonlinearEquation {
    /// `∂t² y = −c_y ∂s⁴ y − 6 c₃ ∂s y·∂ss y`.
    pub fn text(&self) -> String {
        let sym = &self.field.symbol;
        equation_text(
            sym,
            self.rhs.iter().map(|t| {
                let v = t.value.abs();
                let number = if v.is_one() {
                    String::new()
                } else {
                    format!("{v} ")
                };
                let coefficient = if t.coefficient == "1" {
                    String::new()
                } else {
                    format!("{} ", t.coefficient)
                };
                // A constant force is its number and coefficient alone ("1" only when bare).
                let monomial = match (
                    t.monomial.is_empty(),
                    number.is_empty() && coefficient.is_empty(),
                ) {
                    (true, false) => String::new(),
                    _ => monomial_text(&t.monomial, sym),
                };
                let body = format!("{number}{coefficient}{monomial}");
                (t.value.is_negative(), body.trim_end().to_string())
            }),
        )
    }

    /// JSON: each term's value, coefficient and factors.
    pub fn json(&self) -> Value {
        json!({
            "field": self.field.id,
            "lhs": {"t": 2, "s": 0},
            "rhs": self.rhs.iter().map(|t| json!({
                "value": t.value.to_string(),
                "coefficient": t.coefficient,
                "factors": t.monomial.iter().map(|(d, n)| json!({"t": d.t, "s": d.s, "power": n})).collect::<Vec<_>>(),
                "kind": t.kind,
            })).collect::<Vec<_>>(),
            "text": self.text(),
            "not_forces": not_forces_json(&self.not_forces),
        })
    }
}
