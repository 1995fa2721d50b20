//! Reports about the engine rather than one theory: the rule registry, what a model requires
//! of each field with how many candidates each rule strikes out, and how many candidates each
//! density has at every order. They sit above the engine (`rules`, `enumerate`, `reduce`) so
//! that the engine never imports its own reports.

use crate::enumerate::{candidates, count_products, Basis, Bounds};
use crate::markup::markdown_cell;
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

/// What a model requires of one field in one density.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FieldRequirement {
    /// Field id.
    pub field: String,
    /// Its role, if any.
    pub role: Option<&'static str>,
    /// The rule codes it requires.
    pub requires: Vec<&'static str>,
    /// Per table column: how many candidates that rule strikes out for the field (None: the
    /// field does not require it).
    pub struck: Vec<Option<usize>>,
}

/// What a model requires in one density.
#[derive(Debug, Clone, serde::Serialize)]
pub struct DensityRequirements {
    /// `lagrangian` or `rayleigh`.
    pub density: &'static str,
    /// Candidates at the order.
    pub candidates: usize,
    /// The rule codes of the table's columns.
    pub columns: Vec<&'static str>,
    /// Each field's requirements.
    pub fields: Vec<FieldRequirement>,
}

/// What `model` requires of each field in each density at `order`, with how many of the
/// field's candidates each required rule strikes out (a candidate can fail several).
#[derive(Debug, Clone, serde::Serialize)]
pub struct Requirements {
    /// The model's name.
    pub model: String,
    /// The order.
    pub order: u32,
    /// Lagrangian, then Rayleigh.
    pub densities: Vec<DensityRequirements>,
}

impl Requirements {
    /// Decide every candidate of both densities.
    pub fn new(model: &Model, order: u32) -> Result<Requirements, OrderError> {
        let mut densities = Vec::new();
        for density in Density::ALL {
            let a = analyse(model, density, order)?;
            let fields = model
                .fields
                .iter()
                .map(|f| {
                    let required = model.requirements(density, &f.id);
                    let struck = a
                        .columns
                        .iter()
                        .enumerate()
                        .map(|(c, rule)| {
                            required
                                .iter()
                                .any(|r| r.code == rule.code)
                                .then(|| a.rows.iter().filter(|row| !row.passed[c]).count())
                        })
                        .collect();
                    FieldRequirement {
                        field: f.id.clone(),
                        role: f.role.map(|r| r.name()),
                        requires: required.iter().map(|r| r.code).collect(),
                        struck,
                    }
                })
                .collect();
            densities.push(DensityRequirements {
                density: density.key(),
                candidates: a.rows.len(),
                columns: a.columns.iter().map(|r| r.code).collect(),
                fields,
            });
        }
        Ok(Requirements {
            model: model.name.clone(),
            order,
            densities,
        })
    }

    /// As Markdown: one table per density.
    pub fn markdown(&self) -> String {
        let mut out = format!(
            "\n# Requirements of the {} model at order {}\n",
            markdown_cell(&self.model),
            self.order
        );
        for (d, density) in self.densities.iter().zip(Density::ALL) {
            out += &format!(
                "\n## {density} ({} candidates)\n\n| field | role | requires | {} |\n|---|---|---|{}\n",
                d.candidates,
                d.columns.join(" | "),
                "---|".repeat(d.columns.len())
            );
            for f in &d.fields {
                let struck: Vec<String> = f
                    .struck
                    .iter()
                    .map(|s| s.map_or("·".to_string(), |n| n.to_string()))
                    .collect();
                out += &format!(
                    "| {} | {} | {} | {} |\n",
                    f.field,
                    f.role.unwrap_or("—"),
                    f.requires.join(" "),
                    struck.join(" | ")
                );
            }
        }
        out += "\nA number is how many candidates the rule strikes out for that field; · means the field does not require it.\n";
        out
    }
}

/// `rules`: the registry, and with a model what it requires.
pub struct RulesReport {
    /// The header generated files carry, if any (the Markdown page is also `tables/rules.md`).
    pub header: String,
    /// A model's requirements, when asked.
    pub requirements: Option<Requirements>,
}

impl RulesReport {
    /// The registry (and the requirements) as Markdown, the form `emit` keeps in `tables/`.
    pub fn markdown(&self) -> String {
        let mut text = self.header.clone() + &rules_markdown();
        if let Some(r) = &self.requirements {
            text += &r.markdown();
        }
        text
    }
}

impl crate::report::Report for RulesReport {
    fn text(&self) -> String {
        let mut text = rules_markdown();
        if let Some(r) = &self.requirements {
            text += &r.markdown();
        }
        crate::markup::plain_from_markdown(text.trim_start())
    }

    fn json(&self) -> serde_json::Value {
        let rules: Vec<_> = REGISTRY
            .iter()
            .map(|r| {
                serde_json::json!({
                    "code": r.code,
                    "name": r.name,
                    "meaning": r.meaning,
                    "decided_by": r.decided_by(),
                })
            })
            .collect();
        serde_json::json!({"rules": rules, "requirements": self.requirements})
    }

    fn csv(&self) -> Option<String> {
        Some(crate::report::csv_table(
            &["code", "name", "meaning", "decided_by"],
            REGISTRY.iter().map(|r| {
                vec![
                    r.code.to_string(),
                    r.name.to_string(),
                    r.meaning.to_string(),
                    r.decided_by(),
                ]
            }),
        ))
    }
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
    /// A `max_order` outside 1 … [`MAX_ORDER`](crate::enumerate::MAX_ORDER) is refused.
    pub fn new(
        model: &Model,
        basis: Basis,
        max_order: u32,
    ) -> Result<CountReport, crate::reduce::OrderError> {
        if max_order == 0 || max_order > crate::enumerate::MAX_ORDER {
            return Err(crate::reduce::OrderError::OutOfRange(max_order));
        }
        let count = |d: Density, order: u32| {
            let bounds = Bounds::for_order(model.density(d).bound, order);
            match basis {
                Basis::Monomials => count_products(&bounds, 1),
                Basis::Powers => candidates(basis, &bounds).len() as u128,
            }
        };
        Ok(CountReport {
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
        })
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

    fn csv(&self) -> Option<String> {
        Some(crate::report::csv_table(
            &["order", "lagrangian", "rayleigh"],
            self.rows
                .iter()
                .map(|(o, l, r)| vec![o.to_string(), l.to_string(), r.to_string()]),
        ))
    }

    fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "model": self.model,
            "rows": self.rows.iter().map(|(o, l, r)| serde_json::json!({"order": o, "lagrangian": l, "rayleigh": r})).collect::<Vec<_>>(),
        })
    }
}
