//! Frequency and damping scales (`omega_X`, `zeta_X` for each scale suffix X of the model's
//! fields), read from `--param NAME=VALUE` and TOML files, each checked as it is set.

use crate::report::number;

/// Frequency and damping scales: `omega_X`, `zeta_X` for each scale suffix X (`s`, `b`, `t`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Params {
    values: std::collections::BTreeMap<String, f64>,
}

/// The documented defaults: ω = 1 (it sets the unit of time) and ζ = 0.1 for every scale.
pub const DEFAULT_OMEGA: f64 = 1.0;
/// Default damping scale.
pub const DEFAULT_ZETA: f64 = 0.1;

/// A bad parameter.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("parameter {name}: {why}")]
pub struct ParamError {
    /// The parameter.
    pub name: String,
    /// What is wrong.
    pub why: String,
}

impl Params {
    /// Set `name` (`omega_s`, `zeta_b`, …) after checking it: finite, ω > 0, ζ ≥ 0.
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), ParamError> {
        let err = |why: &str| ParamError {
            name: name.to_string(),
            why: why.to_string(),
        };
        let Some((kind, scale)) = name.split_once('_') else {
            return Err(err("expected omega_<scale> or zeta_<scale>, e.g. omega_b"));
        };
        if scale.is_empty() || !matches!(kind, "omega" | "zeta") {
            return Err(err("expected omega_<scale> or zeta_<scale>, e.g. omega_b"));
        }
        if !value.is_finite() {
            return Err(err(&format!("{value} is not a finite number")));
        }
        if kind == "omega" && value <= 0.0 {
            return Err(err(&format!(
                "a frequency scale must be positive, not {}",
                number(value)
            )));
        }
        if kind == "zeta" && value < 0.0 {
            return Err(err(&format!(
                "a damping scale cannot be negative ({})",
                number(value)
            )));
        }
        self.values.insert(name.to_string(), value);
        Ok(())
    }

    /// Parse `name=value`.
    pub fn set_assignment(&mut self, text: &str) -> Result<(), ParamError> {
        let (name, value) = text.split_once('=').ok_or_else(|| ParamError {
            name: text.to_string(),
            why: "expected name=value, e.g. omega_b=2.5".into(),
        })?;
        let value: f64 = value.trim().parse().map_err(|_| ParamError {
            name: name.trim().to_string(),
            why: format!("{:?} is not a number", value.trim()),
        })?;
        self.set(name.trim(), value)
    }

    /// Read `name = value` lines from a TOML table of numbers.
    pub fn set_from_toml(&mut self, text: &str) -> Result<(), ParamError> {
        let table: toml::Table = toml::from_str(text).map_err(|e| ParamError {
            name: "file".into(),
            why: crate::markup::one_line(&e.to_string()),
        })?;
        for (name, value) in table {
            let v = value.as_float().or(value.as_integer().map(|i| i as f64));
            let v = v.ok_or_else(|| ParamError {
                name: name.clone(),
                why: "must be a number".into(),
            })?;
            self.set(&name, v)?;
        }
        Ok(())
    }

    /// The value set for `name` (`omega_s`, `zeta_b`, …), if any.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.values.get(name).copied()
    }

    /// The name of the frequency scale of suffix `scale` (`omega_b`): the one place it is spelled.
    pub fn omega_name(scale: &str) -> String {
        format!("omega_{scale}")
    }

    /// The name of the damping scale of suffix `scale` (`zeta_b`).
    pub fn zeta_name(scale: &str) -> String {
        format!("zeta_{scale}")
    }

    /// ω for a scale suffix.
    pub fn omega(&self, scale: &str) -> f64 {
        *self
            .values
            .get(&Self::omega_name(scale))
            .unwrap_or(&DEFAULT_OMEGA)
    }

    /// ζ for a scale suffix.
    pub fn zeta(&self, scale: &str) -> f64 {
        *self
            .values
            .get(&Self::zeta_name(scale))
            .unwrap_or(&DEFAULT_ZETA)
    }

    /// Names set that no field of `scales` uses (probably typos).
    pub fn unused(&self, scales: &[&str]) -> Vec<String> {
        self.values
            .keys()
            .filter(|k| !scales.iter().any(|s| k.ends_with(&format!("_{s}"))))
            .cloned()
            .collect()
    }
}
