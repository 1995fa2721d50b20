//! Reports about the engine rather than one theory: the rule registry, what a model requires
//! of each field with how many candidates each rule strikes out, and how many candidates each
//! density has at every order. They sit above the engine (`rules`, `enumerate`, `reduce`) so
//! that the engine never imports its own reports.

use crate::enumerate::{candidates, count_products, Basis, Bounds};
use crate::model::{Density, Model};
use crate::reduce::{analyse, OrderError};
use crate::rules::REGISTRY;

/// The rule registry as a Markdown page (without the generated-file header).
pub fn rules_markdown() -> String {
    let mut out = String::new();
    out +=
        "\n# Rules\n\nEvery requirement the engine knows. A model names, per field and density, \
            which of these its terms must satisfy.\n\n";
    out += "| code | name | meaning | decided by |\n|---|---|---|---|\n";
    for r in REGISTRY {
        out += &format!(
            "| {} | `{}` | {} | {} |\n",
            r.code,
            r.name,
            r.meaning,
            r.decided_by()
        );
    }
    out
}

/// What `model` requires of each field in each density, with the field's role, and how many
/// of the field's candidates at `order` each required rule strikes out (a candidate can fail
/// several).
pub fn requirements_markdown(model: &Model, order: u32) -> Result<String, OrderError> {
    let mut out = format!(
        "\n# Requirements of the {} model at order {order}\n",
        model.name
    );
    for density in Density::ALL {
        let a = analyse(model, density, order)?;
        let codes: Vec<&str> = a.columns.iter().map(|r| r.code).collect();
        out += &format!(
            "\n## {density} ({} candidates)\n\n| field | role | requires | {} |\n|---|---|---|{}\n",
            a.rows.len(),
            codes.join(" | "),
            "---|".repeat(codes.len())
        );
        for f in &model.fields {
            let required = model.requirements(density, &f.id);
            let struck: Vec<String> = a
                .columns
                .iter()
                .enumerate()
                .map(|(c, rule)| {
                    if required.iter().any(|r| r.code == rule.code) {
                        a.rows
                            .iter()
                            .filter(|row| !row.passed[c])
                            .count()
                            .to_string()
                    } else {
                        "·".into()
                    }
                })
                .collect();
            out += &format!(
                "| {} | {} | {} | {} |\n",
                f.id,
                f.role.map(|r| r.name()).unwrap_or("—"),
                required
                    .iter()
                    .map(|r| r.code)
                    .collect::<Vec<_>>()
                    .join(" "),
                struck.join(" | ")
            );
        }
    }
    out += "\nA number is how many candidates the rule strikes out for that field; · means the field does not require it.\n";
    Ok(out)
}

/// `count`: the candidate terms of each density at orders 1 … N.
pub struct CountReport {
    /// The model's name.
    pub model: String,
    /// The basis counted.
    pub basis: Basis,
    /// (order, Lagrangian, Rayleigh) counts.
    pub rows: Vec<(u32, u128, u128)>,
}

impl CountReport {
    /// Count the candidates of `model` in `basis` at orders 1 … `max_order`: monomials by the
    /// generating function (no enumeration, so order 32 is instant), pure powers (few) by
    /// listing them.
    pub fn new(model: &Model, basis: Basis, max_order: u32) -> CountReport {
        let count = |d: Density, order: u32| {
            let bounds = Bounds::for_order(model.density(d).bound, order);
            match basis {
                Basis::Monomials => count_products(&bounds, 1),
                Basis::Powers => candidates(basis, &bounds).len() as u128,
            }
        };
        CountReport {
            model: model.name.clone(),
            basis,
            rows: (1..=max_order)
                .map(|o| {
                    (
                        o,
                        count(Density::Lagrangian, o),
                        count(Density::Rayleigh, o),
                    )
                })
                .collect(),
        }
    }
}

impl crate::report::Report for CountReport {
    fn text(&self) -> String {
        let name = match self.basis {
            Basis::Powers => "powers",
            Basis::Monomials => "monomials",
        };
        let mut text = format!(
            "order  lagrangian  rayleigh   ({name} basis, model {})\n",
            self.model
        );
        for (order, l, r) in &self.rows {
            text += &format!("{order:>5}  {l:>10}  {r:>8}\n");
        }
        text
    }

    fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "model": self.model,
            "rows": self.rows.iter().map(|(o, l, r)| serde_json::json!({"order": o, "lagrangian": l, "rayleigh": r})).collect::<Vec<_>>(),
        })
    }
}
