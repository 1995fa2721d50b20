//! Continuum equations of motion derived from the surviving densities.
//!
//! For each field, with `v = ∂tφ`, the dissipative Euler–Lagrange equation is
//!
//! ```text
//! δL/δφ = δR/δv,      δF/δu = Σ_α (−1)^|α| ∂^α ∂F/∂(∂^α u)
//! ```
//!
//! (integration by parts, boundary terms dropped). For a quadratic term `C·∂^αφ·∂^βφ` the
//! variational derivative is `C[(−1)^|α| + (−1)^|β|] ∂^{α+β}φ`; a Rayleigh factor `∂^αφ` with
//! `α_t ≥ 1` is `∂^{α−t}v`. The standard kinetic term `½(∂tφ)²` gives `−∂t²φ`; solving for it
//! gives `∂t²φ = Σ sign·prefactor·coefficient·∂tᵗ∂sˢφ`, exact. For the larva:
//! `∂t²x = c_x ∂s²x + 2c'_x ∂t∂s²x` and `∂t²y = −c_y ∂s⁴y − 2c'_y ∂t∂s⁴y`.
//! The printed coefficients fold the rational prefactor into the free parameter; the prefactor
//! is kept in [`RhsTerm::prefactor`]. Whether a parameter's sign is fixed is derived, with its
//! reason, by [`SignClaim`].

use std::collections::BTreeMap;

use num_rational::Rational64;
use num_traits::{One, Signed, Zero};
use serde_json::{json, Value};

use crate::enumerate::Basis;
use crate::model::{Density, Field, Model};
use crate::reduce::{analyse_basis, sign_joiner, Analysis, DensityTerm, OrderError};
use crate::table::latex_symbol;
use crate::term::{superscript, Deriv, Term};

/// One term `sign · prefactor · coefficient · ∂tᵗ∂sˢφ` of a right-hand side.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RhsTerm {
    /// Derivative of the field.
    pub deriv: Deriv,
    /// +1 or −1.
    pub sign: i64,
    /// Exact positive prefactor, folded into `coefficient` when printed.
    pub prefactor: Rational64,
    /// The free parameter (`c_x`, `c'_x`).
    pub coefficient: String,
    /// What fixes the parameter's sign, if anything.
    pub claim: SignClaim,
}

/// Whether a parameter's sign is fixed, and by what.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(tag = "sign", content = "reason", rename_all = "kebab-case")]
pub enum SignClaim {
    /// Positive as printed, for the reason given.
    Positive(&'static str),
    /// Negative as printed would be stable: the parameter must be negative.
    Negative(&'static str),
    /// Either sign is allowed, for the reason given.
    Free(&'static str),
}

impl SignClaim {
    /// Derived from the dispersion relation of ∂t²φ = Σ: with φ ∝ e^{i(qs−ωt)}, a term
    /// c·∂sᵇφ (b even) adds (−1)^{b/2} c qᵇ to −ω², and c·∂t∂sᵇφ adds a damping rate. The lowest
    /// and highest even b of each kind dominate as q → 0 and q → ∞, so their signs are fixed:
    /// the stable sign is (−1)^{b/2+1}. Odd b is odd under s → −s and no square's variation:
    /// nothing fixes it. Other terms are bounded only jointly.
    fn of(deriv: Deriv, sign: i64, extreme: bool) -> SignClaim {
        if deriv.s % 2 == 1 {
            return SignClaim::Free("odd in ∂s, not the variation of a square: neither energy nor dissipation fixes its sign, and s → −s flips it");
        }
        let reason = match deriv.t {
            0 if extreme => "the energy must be bounded below, ω² > 0 as q → 0 and as q → ∞",
            1 if extreme => "dissipation cannot be negative, by the second law",
            0 | 1 => {
                return SignClaim::Free(
                    "stability bounds it only together with the other terms of its kind",
                )
            }
            _ => return SignClaim::Free("no energy or dissipation argument here fixes it"),
        };
        let stable = if (deriv.s / 2) % 2 == 0 { -1 } else { 1 };
        if sign == stable {
            SignClaim::Positive(reason)
        } else {
            SignClaim::Negative(reason)
        }
    }

    /// `c_x > 0 (reason)`.
    pub fn describe(&self, coefficient: &str) -> String {
        match self {
            SignClaim::Positive(r) => format!("{coefficient} > 0: {r}"),
            SignClaim::Negative(r) => format!("{coefficient} < 0: {r}"),
            SignClaim::Free(r) => format!("{coefficient} of either sign: {r}"),
        }
    }
}

/// `∂t²φ = Σ rhs` for one field.
#[derive(Debug, Clone)]
pub struct Equation {
    /// The field.
    pub field: Field,
    /// Right-hand side, by ascending time then space derivative.
    pub rhs: Vec<RhsTerm>,
}

/// Why the equations cannot be written.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EquationError {
    /// The order is out of range.
    #[error(transparent)]
    Order(#[from] OrderError),
    /// No standard kinetic term survives, so there is no `∂t²φ` to solve for.
    #[error("field {field}: no kinetic term (∂t {field})² survives at order {order}, so there is no ∂t²{field} to solve for")]
    NoKinetic {
        /// Field id.
        field: String,
        /// The order asked for.
        order: u32,
    },
    /// A surviving term is not quadratic: its equation would not be linear.
    #[error("field {field}: surviving term {term} is not quadratic; only linear equations of motion are derived")]
    NotQuadratic {
        /// Field id.
        field: String,
        /// The term.
        term: String,
    },
}

/// A linear combination `Σ value·parameter·∂^D φ`, keyed by (derivative, parameter).
pub type Linear = BTreeMap<(Deriv, Option<String>), Rational64>;

fn add(into: &mut Linear, deriv: Deriv, param: &Option<String>, value: Rational64) {
    let e = into
        .entry((deriv, param.clone()))
        .or_insert_with(Rational64::zero);
    *e += value;
    if e.is_zero() {
        into.remove(&(deriv, param.clone()));
    }
}

fn parity(d: Deriv) -> Rational64 {
    Rational64::from_integer(if d.order() % 2 == 0 { 1 } else { -1 })
}

/// The two derivatives of a quadratic single-field term (equal for a square), or `None`.
pub fn quadratic_parts(term: &Term) -> Option<(Deriv, Deriv)> {
    match term.factors() {
        [f] if f.power == 2 => Some((f.deriv, f.deriv)),
        [f, g] if f.power == 1 && g.power == 1 && f.field == g.field => Some((f.deriv, g.deriv)),
        _ => None,
    }
}

fn plus(a: Deriv, b: Deriv) -> Deriv {
    Deriv::new(a.t + b.t, a.s + b.s)
}

/// δL/δφ of `C·term` (Lagrangian) or δR/δv of it (Rayleigh), added to `into`.
/// `C = sign·prefactor·parameter`.
pub fn variational_derivative(density: Density, dt: &DensityTerm, into: &mut Linear) -> bool {
    let Some((a, b)) = quadratic_parts(&dt.term) else {
        return false;
    };
    let c = dt.prefactor * Rational64::from_integer(dt.sign);
    for (x, y) in [(a, b), (b, a)] {
        match density {
            // ∂F/∂(∂^x φ) = C·∂^y φ; then (−1)^|x| ∂^x of it.
            Density::Lagrangian => add(into, plus(x, y), &dt.parameter, c * parity(x)),
            // Only factors holding ∂t depend on v: ∂^x φ = ∂^{x−t} v.
            Density::Rayleigh if x.t >= 1 => {
                let xv = Deriv::new(x.t - 1, x.s);
                add(into, plus(xv, y), &dt.parameter, c * parity(xv))
            }
            Density::Rayleigh => {}
        }
    }
    true
}

fn field_equation(
    l: &Analysis,
    r: &Analysis,
    index: usize,
    order: u32,
) -> Result<Equation, EquationError> {
    let field = l.fields[index].field.clone();
    // δL/δφ − δR/δv = 0, as one linear combination.
    let mut total = Linear::new();
    for (analysis, sign) in [(l, 1), (r, -1)] {
        let mut part = Linear::new();
        for dt in &analysis.fields[index].density {
            if !variational_derivative(analysis.density, dt, &mut part) {
                return Err(EquationError::NotQuadratic {
                    field: field.id.clone(),
                    term: dt.term.render(&|_| field.symbol.clone()),
                });
            }
        }
        for ((d, p), v) in part {
            add(&mut total, d, &p, v * Rational64::from_integer(sign));
        }
    }
    let tt = (Deriv::new(2, 0), None);
    let lead = total.remove(&tt).unwrap_or_else(Rational64::zero);
    if lead.is_zero() {
        return Err(EquationError::NoKinetic {
            field: field.symbol.clone(),
            order,
        });
    }
    let mut rhs: Vec<RhsTerm> = total
        .into_iter()
        .map(|((deriv, param), v)| {
            let value = -v / lead;
            RhsTerm {
                deriv,
                sign: if value.is_negative() { -1 } else { 1 },
                prefactor: value.abs(),
                coefficient: param.unwrap_or_else(|| "1".to_string()),
                claim: SignClaim::Free(""),
            }
        })
        .collect();
    rhs.sort_by_key(|t| (t.deriv.t, t.deriv.s));
    // The lowest and highest even space order among the terms of each time order.
    let extremes = |t: u32| {
        let even = rhs
            .iter()
            .filter(|r| r.deriv.t == t && r.deriv.s % 2 == 0)
            .map(|r| r.deriv.s);
        (even.clone().min(), even.max())
    };
    let bounds: Vec<(Option<u32>, Option<u32>)> = (0..=2).map(extremes).collect();
    for r in &mut rhs {
        let (lo, hi) = bounds
            .get(r.deriv.t as usize)
            .copied()
            .unwrap_or((None, None));
        let extreme = Some(r.deriv.s) == lo || Some(r.deriv.s) == hi;
        r.claim = SignClaim::of(r.deriv, r.sign, extreme);
    }
    Ok(Equation { field, rhs })
}

/// The equations of motion of every field of `model` at `order`, plus the analyses' notes.
pub fn derive(model: &Model, order: u32) -> Result<(Vec<Equation>, Vec<String>), EquationError> {
    derive_basis(model, order, Basis::Powers)
}

/// The equations of motion when the candidates are `basis`.
pub fn derive_basis(
    model: &Model,
    order: u32,
    basis: Basis,
) -> Result<(Vec<Equation>, Vec<String>), EquationError> {
    let (l, r, notes) = analyses(model, order, basis)?;
    let equations = (0..model.fields.len())
        .map(|i| field_equation(&l, &r, i, order))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((equations, notes))
}

/// Both densities' analyses and what they say is missing.
fn analyses(
    model: &Model,
    order: u32,
    basis: Basis,
) -> Result<(Analysis, Analysis, Vec<String>), EquationError> {
    crate::reduce::check_work(
        model,
        &[Density::Lagrangian, Density::Rayleigh],
        order,
        basis,
    )?;
    let l = analyse_basis(model, Density::Lagrangian, order, basis)?;
    let r = analyse_basis(model, Density::Rayleigh, order, basis)?;
    let notes = l
        .fields
        .iter()
        .chain(&r.fields)
        .flat_map(|f| f.missing.clone())
        .collect();
    Ok((l, r, notes))
}

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

impl Equation {
    /// `∂t² x = c_x ∂s² x + c'_x ∂t∂s² x`.
    pub fn text(&self) -> String {
        let sym = &self.field.symbol;
        equation_text(
            sym,
            self.rhs.iter().map(|t| {
                let body = format!("{} {}", t.coefficient, derivative_text(t.deriv, sym));
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
            out += &format!("{base}_{{{sym}}} {}", latex_derivative(t.deriv, &sym));
        }
        out
    }

    /// What each folded coefficient absorbed, e.g. `c'_x absorbs 2`.
    pub fn folds(&self) -> Vec<String> {
        self.rhs
            .iter()
            .filter(|t| !t.prefactor.is_one())
            .map(|t| format!("{} absorbs the exact factor {}", t.coefficient, t.prefactor))
            .collect()
    }
}

/// The JSON contract: `{"order": N, "equations": [{"field", "rhs": [{"t","s","sign","coefficient"}]}]}`.
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
            })).collect::<Vec<_>>(),
            "text": e.text(),
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

/// The heading line and one indented line per equation.
fn heading(model: &str, order: u32, how: &str, lines: impl Iterator<Item = String>) -> String {
    let mut out = format!("Equations of motion of the {model} model at order {order} ({how}):\n");
    for l in lines {
        out += &format!("  {l}\n");
    }
    out
}

/// An equation that can be shown as text and LaTeX.
pub trait Shown {
    /// One line of text.
    fn line(&self) -> String;
    /// One LaTeX `align` row.
    fn latex_row(&self) -> String;
}

impl Shown for Equation {
    fn line(&self) -> String {
        self.text()
    }
    fn latex_row(&self) -> String {
        self.latex()
    }
}

impl Shown for NonlinearEquation {
    fn line(&self) -> String {
        self.text()
    }
    fn latex_row(&self) -> String {
        self.latex()
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
            self.equations.iter().map(|e| e.line()),
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
        let folds: Vec<String> = self.equations.iter().flat_map(|e| e.folds()).collect();
        if !folds.is_empty() {
            out += &format!("Exact factors: {}.\n", folds.join(", "));
        }
        for n in &self.notes {
            out += &format!("note: {n}\n");
        }
        out
    }

    fn json(&self) -> Value {
        json(self.order, &self.equations, &self.notes)
    }
}

/// One term `value · coefficient · Π ∂^α φ` of a nonlinear right-hand side.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PolyTerm {
    /// The product of field derivatives (sorted, with powers); empty is the constant 1.
    pub monomial: crate::parts::Mono,
    /// Exact signed rational factor.
    pub value: Rational64,
    /// The free parameter (`c_x`), or `1`.
    pub coefficient: String,
}

/// `∂t²φ = Σ rhs` for one field, any polynomial density: the exact Euler–Lagrange equation.
#[derive(Debug, Clone)]
pub struct NonlinearEquation {
    /// The field.
    pub field: Field,
    /// Right-hand side, by parameter then monomial.
    pub rhs: Vec<PolyTerm>,
}

/// `c·(∂s y)²·∂ss y` with the field's symbol.
fn monomial_text(m: &crate::parts::Mono, symbol: &str) -> String {
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
            })).collect::<Vec<_>>(),
            "text": self.text(),
        })
    }
}

/// The exact equations of motion of any surviving densities, quadratic or not:
/// ∂t²φ = E(L − ½(∂tφ)²) − δR/δv, with E the full Euler–Lagrange operator
/// ([`crate::parts::euler_lagrange`]) and δR/δv the Euler operator in s of the velocity
/// v = ∂tφ ([`crate::parts::space_euler`]). A term whose contribution vanishes (a total
/// derivative, as a linear ∂ssφ) is dropped with a note.
pub fn derive_nonlinear(
    model: &Model,
    order: u32,
    basis: Basis,
) -> Result<(Vec<NonlinearEquation>, Vec<String>), EquationError> {
    use crate::parts::{euler_lagrange, mono_of, space_euler, JetPoly};
    let (l, r, mut notes) = analyses(model, order, basis)?;
    let mut equations = Vec::new();
    for (i, field) in model.fields.iter().enumerate() {
        // Σ over parameters of the E(L) − δR/δv polynomials.
        let mut total: BTreeMap<Option<String>, JetPoly> = BTreeMap::new();
        for (analysis, sign) in [(&l, 1), (&r, -1)] {
            for dt in &analysis.fields[i].density {
                let c = dt.prefactor * Rational64::from_integer(dt.sign * sign);
                let p: JetPoly = [(mono_of(&dt.term), c)].into_iter().collect();
                let e = match analysis.density {
                    Density::Lagrangian => euler_lagrange(&p),
                    Density::Rayleigh => {
                        let parts = space_euler(&p);
                        if parts.keys().any(|&a| a != 1) {
                            notes.push(format!(
                                "R_{}: {} depends on more than the velocity jet; only its dependence on ∂t{} enters",
                                field.symbol,
                                dt.term.render(&|_| field.symbol.clone()),
                                field.symbol
                            ));
                        }
                        parts.get(&1).cloned().unwrap_or_default()
                    }
                };
                if e.is_empty() {
                    notes.push(format!(
                        "{}_{}: {} contributes nothing to the equation (a total derivative) and is dropped",
                        analysis.density.letter(),
                        field.symbol,
                        dt.term.render(&|_| field.symbol.clone())
                    ));
                }
                let into = total.entry(dt.parameter.clone()).or_default();
                for (m, v) in e {
                    let entry = into.entry(m.clone()).or_insert_with(Rational64::zero);
                    *entry += v;
                    if entry.is_zero() {
                        into.remove(&m);
                    }
                }
            }
        }
        let acceleration: crate::parts::Mono = vec![(Deriv::new(2, 0), 1)];
        let lead = total
            .get_mut(&None)
            .and_then(|p| p.remove(&acceleration))
            .unwrap_or_else(Rational64::zero);
        if lead.is_zero() {
            return Err(EquationError::NoKinetic {
                field: field.symbol.clone(),
                order,
            });
        }
        let rhs: Vec<PolyTerm> = total
            .into_iter()
            .flat_map(|(param, p)| {
                let coefficient = param.unwrap_or_else(|| "1".into());
                p.into_iter().map(move |(monomial, v)| PolyTerm {
                    monomial,
                    value: -v / lead,
                    coefficient: coefficient.clone(),
                })
            })
            .collect();
        let mut rhs: Vec<PolyTerm> = rhs;
        rhs.sort_by_key(|t| {
            let degree: u32 = t.monomial.iter().map(|(_, n)| n).sum();
            (degree, t.monomial.clone(), t.coefficient.clone())
        });
        equations.push(NonlinearEquation {
            field: field.clone(),
            rhs,
        });
    }
    Ok((equations, notes))
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
            if !v.is_one() {
                out += &if v.is_integer() {
                    format!("{v} ")
                } else {
                    format!("\\tfrac{{{}}}{{{}}} ", v.numer(), v.denom())
                };
            }
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
}
