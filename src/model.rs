//! The physical model: which fields live on the midline, their boundary conditions, and which
//! requirements each field imposes on each density. All of it is data (TOML), so another animal
//! or another set of symmetries is another file, not other code.
//!
//! The embedded default is the Drosophila larva of the paper ([`Model::larva`]), read from
//! `tables/models/larva.toml`.

use crate::markup::{identifier, text};
pub use crate::markup::{is_invisible, TextError};
use std::collections::BTreeMap;
use std::fmt;

use serde::{Deserialize, Serialize};

pub use crate::boundary::{Boundary, End};
pub use crate::enumerate::BoundShape;
pub use crate::markup::one_line;
use crate::rules::{self, Rule};

/// What a field is on the body: behaviours ask the model for roles, never for field ids.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Role {
    /// Stretch and compression along the midline.
    Axial,
    /// Twist about the midline.
    Torsion,
    /// Bending in the plane of the substrate (left–right; what a camera above sees).
    Lateral,
    /// Bending out of that plane (up–down).
    Dorsoventral,
}

impl Role {
    /// Every role.
    pub const ALL: [Role; 4] = [
        Role::Axial,
        Role::Torsion,
        Role::Lateral,
        Role::Dorsoventral,
    ];

    /// Lower-case name, as in model files.
    pub fn name(self) -> &'static str {
        match self {
            Role::Axial => "axial",
            Role::Torsion => "torsion",
            Role::Lateral => "lateral",
            Role::Dorsoventral => "dorsoventral",
        }
    }
}

impl fmt::Display for Role {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A command asked the model for a role it does not have.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{command} needs a {role} field, and model {model:?} has none (give one field role = \"{role}\")")]
pub struct RoleError {
    /// The command or behaviour.
    pub command: String,
    /// The missing role.
    pub role: Role,
    /// The model's name.
    pub model: String,
}

/// One scalar field on the midline.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Field {
    /// ASCII identifier, used in JSON and on the command line (`theta`).
    pub id: String,
    /// Symbol used in formulas and table headers (`θ`).
    pub symbol: String,
    /// What the field measures.
    pub meaning: String,
    /// Boundary condition at head and tail.
    pub boundary: Boundary,
    /// What the field is (axial, torsion, lateral, dorsoventral); behaviours find fields by it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub role: Option<Role>,
    /// Which frequency and damping scale the field uses (`s` → ω_s, ζ_s). Defaults to the id.
    #[serde(default)]
    pub scale: Option<String>,
    /// Names of the operator's zero modes, in order (constant first, then linear ramp, …).
    #[serde(default)]
    pub zero_modes: Vec<String>,
}

impl Field {
    /// The scale suffix of this field's ω and ζ.
    pub fn scale(&self) -> &str {
        self.scale.as_deref().unwrap_or(&self.id)
    }
}

/// The two densities of a dissipative Lagrangian field theory.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Density {
    /// The Lagrangian density L (conservative physics).
    Lagrangian,
    /// The Rayleigh dissipation density R.
    Rayleigh,
}

impl Density {
    /// Both densities, Lagrangian first.
    pub const ALL: [Density; 2] = [Density::Lagrangian, Density::Rayleigh];

    /// Lower-case name, as in JSON keys.
    pub fn key(self) -> &'static str {
        match self {
            Density::Lagrangian => "lagrangian",
            Density::Rayleigh => "rayleigh",
        }
    }

    /// The letter of the density in formulas: L or R.
    pub fn letter(self) -> &'static str {
        match self {
            Density::Lagrangian => "L",
            Density::Rayleigh => "R",
        }
    }
}

impl fmt::Display for Density {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Density::Lagrangian => "Lagrangian",
            Density::Rayleigh => "Rayleigh",
        })
    }
}

/// What a model says about one density.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DensitySpec {
    /// How the order bounds the candidates.
    pub bound: BoundShape,
    /// Rule codes shown as table columns, in order.
    pub columns: Vec<String>,
    /// Structural rules an interaction term must satisfy as a whole (symmetries come from each
    /// participating field's own requirements).
    #[serde(default)]
    pub interaction: Vec<String>,
    /// For each field id, the rule codes its terms must satisfy.
    pub requirements: BTreeMap<String, Vec<String>>,
    /// Which admitted terms compete for "lowest order" (default: all together, as the paper).
    #[serde(default, skip_serializing_if = "Dominance::is_joint")]
    pub dominance: Dominance,
    /// Orders kept beyond the leading one: 0 keeps the lowest-order terms (the paper), K keeps
    /// the first 1 + K layers of the admitted terms, each the lowest order of what the layers
    /// before it left (the effective theory at next-to-leading order for K = 1).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub beyond_leading: u32,
    /// `[active]` only: whether the covariant variational and Rayleigh forces that no admitted
    /// density gives enter the equations (`"enter"`, as `b_φ`) or are only listed (`"list"`).
    #[serde(default, skip_serializing_if = "Uncarried::is_list")]
    pub uncarried: Uncarried,
}

/// What `[active]` does with a force that is variational or of Rayleigh form yet carried by
/// no density the model admits (`active::carried`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Uncarried {
    /// Listed by `active` with the rules that strike its densities; not in the equations.
    #[default]
    List,
    /// Also entered into the equations with a coefficient `b_φ`.
    Enter,
}

impl Uncarried {
    fn is_list(&self) -> bool {
        *self == Uncarried::List
    }
}

/// The most orders kept beyond the leading one.
pub const MAX_BEYOND_LEADING: u32 = 8;

fn is_zero(k: &u32) -> bool {
    *k == 0
}

/// Which admitted terms compete when the lowest-order ones are kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Dominance {
    /// Every admitted term against every other (the paper): a term survives when no admitted
    /// term has τ′ ≤ τ and σ′ ≤ σ with one strict.
    #[default]
    Joint,
    /// The kinetic terms (with a time derivative) and the potential terms (without) each among
    /// themselves. Needed by a body without translation symmetry, whose potential φ, φ², φ³ …
    /// has τ = σ = 0 and would otherwise outrank the kinetic term (∂t φ)² and leave no dynamics.
    ByPart,
}

impl Dominance {
    fn is_joint(&self) -> bool {
        *self == Dominance::Joint
    }
}

/// A model: fields and, per density, their requirements.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// Short name.
    pub name: String,
    /// One line about the model.
    pub description: String,
    /// The fields, in table order.
    pub fields: Vec<Field>,
    /// Requirements on the Lagrangian density.
    pub lagrangian: DensitySpec,
    /// Requirements on the Rayleigh density.
    pub rayleigh: DensitySpec,
    /// Requirements on active forces (`[active]`; absent: none are enumerated).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub active: Option<DensitySpec>,
}

/// Why a model file cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The TOML does not parse or does not have the model's shape.
    #[error("model file: {0}")]
    Syntax(String),
    /// It parses but says something inconsistent.
    #[error("model {model:?}: {why}")]
    Invalid {
        /// The model's name.
        model: String,
        /// What is inconsistent.
        why: String,
    },
}

const LARVA: &str = include_str!("../tables/models/larva.toml");

/// The default order of the expansion: the paper's Table 1 (N = 4).
pub const DEFAULT_ORDER: u32 = 4;

impl Model {
    /// Keep `k` orders beyond the leading one in every density and force section (the
    /// `--beyond-leading` of the command line, `beyond_leading=` in Python).
    pub fn set_beyond_leading(&mut self, k: u32) {
        self.lagrangian.beyond_leading = k;
        self.rayleigh.beyond_leading = k;
        if let Some(a) = self.active.as_mut() {
            a.beyond_leading = k;
        }
    }

    /// The embedded Drosophila larva model.
    pub fn larva() -> Model {
        Model::from_toml(LARVA).expect("the embedded larva model is valid (tested)")
    }

    /// The TOML text of the embedded larva model.
    pub fn larva_toml() -> &'static str {
        LARVA
    }

    /// Read and check a model from TOML text.
    pub fn from_toml(text: &str) -> Result<Model, ModelError> {
        let model: Model =
            toml::from_str(text).map_err(|e| ModelError::Syntax(one_line(&e.to_string())))?;
        model.validate()?;
        // A key a section cannot use is refused even at its default value (`dominance =
        // "joint"`, `interaction = []`): a reader would think it was read.
        let table: toml::Table = toml::from_str(text).unwrap_or_default();
        for (section, key, why) in UNUSED_KEYS {
            if table
                .get(section)
                .and_then(|t| t.as_table())
                .is_some_and(|t| t.contains_key(key))
            {
                return Err(model.invalid(why.to_string()));
            }
        }
        Ok(model)
    }

    /// What the model says about `density`.
    pub fn density(&self, density: Density) -> &DensitySpec {
        match density {
            Density::Lagrangian => &self.lagrangian,
            Density::Rayleigh => &self.rayleigh,
        }
    }

    /// The field with this id.
    pub fn field(&self, id: &str) -> Option<&Field> {
        self.fields.iter().find(|f| f.id == id)
    }

    /// The index of the field with `role`, or an error naming the role and the `command` that
    /// needs it.
    pub fn role_index(&self, role: Role, command: &str) -> Result<usize, RoleError> {
        self.fields
            .iter()
            .position(|f| f.role == Some(role))
            .ok_or_else(|| RoleError {
                command: command.to_string(),
                role,
                model: self.name.clone(),
            })
    }

    /// The model reduced to field `index` alone (its requirements kept): what one field's
    /// operator and modes need, without the other fields' limits.
    pub fn only(&self, index: usize) -> Model {
        let mut m = self.clone();
        let id = m.fields[index].id.clone();
        m.fields = vec![m.fields[index].clone()];
        for spec in [&mut m.lagrangian, &mut m.rayleigh]
            .into_iter()
            .chain(m.active.as_mut())
        {
            spec.requirements.retain(|k, _| *k == id);
        }
        m
    }

    /// The symbol of the field with this id (empty if there is none).
    pub fn symbol(&self, id: &str) -> String {
        self.field(id).map(|f| f.symbol.clone()).unwrap_or_default()
    }

    /// The rules `field` must satisfy in `density`.
    pub fn requirements(&self, density: Density, field: &str) -> Vec<&'static Rule> {
        self.density(density)
            .requirements
            .get(field)
            .into_iter()
            .flatten()
            .filter_map(|code| rules::rule(code))
            .collect()
    }

    /// The table columns of `density`, as rules.
    pub fn columns(&self, density: Density) -> Vec<&'static Rule> {
        self.density(density)
            .columns
            .iter()
            .filter_map(|code| rules::rule(code))
            .collect()
    }

    /// A model error naming this model (its name clipped, control characters dropped).
    fn invalid(&self, why: String) -> ModelError {
        ModelError::Invalid {
            model: self
                .name
                .chars()
                .filter(|c| !c.is_control())
                .take(64)
                .collect(),
            why,
        }
    }

    fn validate(&self) -> Result<(), ModelError> {
        let invalid = |why: String| self.invalid(why);
        if self.rayleigh.dominance != Dominance::Joint {
            return Err(invalid(UNUSED_KEYS[0].2.into()));
        }
        for (spec, key) in [(&self.lagrangian, 3), (&self.rayleigh, 4)] {
            if spec.uncarried != Uncarried::List {
                return Err(invalid(UNUSED_KEYS[key].2.into()));
            }
        }
        // Forces are not densities: no parts compete and no interaction table is built for
        // them, so these keys would be read and ignored.
        if let Some(active) = &self.active {
            if active.dominance != Dominance::Joint {
                return Err(invalid(UNUSED_KEYS[1].2.into()));
            }
            if !active.interaction.is_empty() {
                return Err(invalid(UNUSED_KEYS[2].2.into()));
            }
        }
        for (name, spec) in [
            ("lagrangian", &self.lagrangian),
            ("rayleigh", &self.rayleigh),
        ]
        .into_iter()
        .chain(self.active.iter().map(|a| ("active", a)))
        {
            if spec.beyond_leading > MAX_BEYOND_LEADING {
                return Err(invalid(format!(
                    "[{name}] beyond_leading = {}: at most {MAX_BEYOND_LEADING}",
                    spec.beyond_leading
                )));
            }
        }
        if self.fields.is_empty() {
            return Err(invalid("declares no fields".into()));
        }
        if self.fields.len() > MAX_FIELDS {
            return Err(invalid(format!(
                "declares {} fields; at most {MAX_FIELDS} (interactions grow as 2^fields)",
                self.fields.len()
            )));
        }
        text("name", &self.name, 64).map_err(|e| invalid(e.to_string()))?;
        text("description", &self.description, 500).map_err(|e| invalid(e.to_string()))?;
        for (i, f) in self.fields.iter().enumerate() {
            identifier("field id", &f.id).map_err(|e| invalid(e.to_string()))?;
            let key = |k: &str| format!("field {:?} {k}", f.id);
            text(&key("symbol"), &f.symbol, 16).map_err(|e| invalid(e.to_string()))?;
            if f.symbol.trim().is_empty() || f.symbol.chars().any(char::is_whitespace) {
                return Err(invalid(format!(
                    "{} must be non-empty, without spaces",
                    key("symbol")
                )));
            }
            text(&key("meaning"), &f.meaning, 200).map_err(|e| invalid(e.to_string()))?;
            if let Some(scale) = &f.scale {
                identifier(&key("scale"), scale).map_err(|e| invalid(e.to_string()))?;
            }
            for z in &f.zero_modes {
                text(&key("zero mode name"), z, 100).map_err(|e| invalid(e.to_string()))?;
            }
            if self.fields[..i].iter().any(|g| g.id == f.id) {
                return Err(invalid(format!("field id {:?} is declared twice", f.id)));
            }
            if let Some(role) = f.role {
                if let Some(g) = self.fields[..i].iter().find(|g| g.role == Some(role)) {
                    return Err(invalid(format!(
                        "fields {:?} and {:?} both have role {role}: a role names one field",
                        g.id, f.id
                    )));
                }
            }
        }
        // (name, spec, whether its terms are forces rather than density terms)
        let sections = Density::ALL
            .iter()
            .map(|d| (d.to_string(), self.density(*d), false))
            .chain(
                self.active
                    .iter()
                    .map(|a| ("active forces".to_string(), a, true)),
            );
        for (density, spec, forces) in sections {
            let known = rules::REGISTRY.iter().map(|r| r.code).collect::<Vec<_>>();
            for code in &spec.columns {
                if rules::rule(code).is_none() {
                    return Err(invalid(format!(
                        "{density} column {code:?} is not a rule (known: {})",
                        known.join(", ")
                    )));
                }
            }
            for code in &spec.interaction {
                match rules::rule(code) {
                    Some(r) if matches!(r.check, rules::Check::Structural(_)) => {}
                    Some(_) => {
                        return Err(invalid(format!(
                            "{density} interaction rule {code:?} is a symmetry: symmetries come from each field's requirements"
                        )))
                    }
                    None => return Err(invalid(format!("{density} interaction rule {code:?} is not a rule"))),
                }
            }
            for field in &self.fields {
                if !spec.requirements.contains_key(&field.id) {
                    return Err(invalid(format!(
                        "{density} requirements do not mention field {:?}",
                        field.id
                    )));
                }
            }
            for (id, codes) in &spec.requirements {
                // A force is not a density: no kinetic-term or velocity-function rule.
                if let Some(code) = codes
                    .iter()
                    .find(|c| forces && matches!(c.as_str(), "KIN" | "DIS"))
                {
                    return Err(invalid(format!(
                        "[active] requirement {code:?} of field {id:?} is a rule about densities; forces take OST and the symmetry rules"
                    )));
                }
                if self.field(id).is_none() {
                    return Err(invalid(format!(
                        "{density} requirements name unknown field {id:?}"
                    )));
                }
                for code in codes {
                    if !spec.columns.contains(code) {
                        return Err(invalid(format!(
                            "{density} requirement {code:?} of field {id:?} is not among the columns {:?}",
                            spec.columns
                        )));
                    }
                }
            }
        }
        Ok(())
    }
}

/// Keys a section parses (it shares the densities' shape) but cannot use: (section, key, the
/// one line that refuses it).
const UNUSED_KEYS: [(&str, &str, &str); 5] = [
    (
        "rayleigh",
        "dominance",
        "[rayleigh] dominance: a Rayleigh density has one part (all of it enters through δR/δ(∂tφ)), so only [lagrangian] takes dominance = \"by-part\"",
    ),
    (
        "active",
        "dominance",
        "[active] dominance: forces are not a density with parts; only [lagrangian] takes dominance",
    ),
    (
        "active",
        "interaction",
        "[active] interaction: no interaction table is built for forces; only [lagrangian] and [rayleigh] take interaction rules",
    ),
    (
        "lagrangian",
        "uncarried",
        "[lagrangian] uncarried: it says whether forces no density gives enter the equations, so only [active] takes it",
    ),
    (
        "rayleigh",
        "uncarried",
        "[rayleigh] uncarried: it says whether forces no density gives enter the equations, so only [active] takes it",
    ),
];

/// The most fields a model may declare (interactions grow as 2^fields).
pub const MAX_FIELDS: usize = 8;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn larva_is_valid_and_ordered() {
        let m = Model::larva();
        let ids: Vec<_> = m.fields.iter().map(|f| f.id.as_str()).collect();
        assert_eq!(ids, ["x", "theta", "y", "z"]);
        assert_eq!(m.field("x").unwrap().boundary, Boundary::Periodic);
        let codes = |d, f| {
            m.requirements(d, f)
                .iter()
                .map(|r| r.code)
                .collect::<Vec<_>>()
        };
        assert_eq!(
            codes(Density::Lagrangian, "y"),
            ["OST", "TRAN", "REF", "KIN", "ROT"]
        );
        assert_eq!(codes(Density::Rayleigh, "x"), ["DIS", "TRAN", "GAL", "REF"]);
    }

    #[test]
    fn bad_models_name_the_problem() {
        let bad_rule = LARVA.replacen(
            "columns = [\"OST\", \"TRAN\", \"REF\", \"KIN\", \"ROT\"]",
            "columns = [\"OST\", \"TRAN\", \"REF\", \"KIN\", \"ROTX\"]",
            1,
        );
        assert_ne!(bad_rule, LARVA);
        let err = Model::from_toml(&bad_rule).unwrap_err().to_string();
        assert!(err.contains("\"ROTX\" is not a rule"), "{err}");

        let symmetry = LARVA.replacen(
            "interaction = [\"OST\", \"KIN\"]",
            "interaction = [\"ROT\"]",
            1,
        );
        let err = Model::from_toml(&symmetry).unwrap_err().to_string();
        assert!(err.contains("is a symmetry"), "{err}");

        let err = Model::from_toml("name = 3").unwrap_err().to_string();
        assert!(err.contains("line 1"), "{err}");
    }
}
