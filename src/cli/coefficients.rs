//! Coefficients by the names `equations` prints (`c_y`, `c'1_x`, ASCII `cp1_x`): every one of a
//! nonlinear body, and on the linear (modal) path the leading squares as the scales they are
//! (c = ω², c′ = ζω for the field's scale).

use super::{check_list, load_params, CliError, ParamArgs};
use crate::model::{Density, Model};
use crate::params::Params;

/// A coefficient's name as `--param` takes it: as `equations` prints it (`c'1_θ`), or in ASCII
/// with `p` for the prime and the field's id for its symbol (`cp1_theta`).
pub(super) fn coefficient_of(
    name: &str,
    names: &[String],
    model: &crate::model::Model,
) -> Option<String> {
    names
        .iter()
        .find(|n| {
            *n == name
                || n.rsplit_once('_').is_some_and(|(letter, symbol)| {
                    model.fields.iter().any(|f| {
                        f.symbol == symbol
                            && format!("{}_{}", letter.replace('\'', "p"), f.id) == name
                    })
                })
        })
        .cloned()
}

/// `--param` split into the coefficients it sets (canonical name, value) and the scale
/// assignments left for [`load_params`] (with the `--params` file).
fn split(
    args: &ParamArgs,
    names: &[String],
    model: &Model,
) -> Result<(Vec<(String, f64)>, ParamArgs), CliError> {
    check_list("--param", args.params.len())?;
    let mut coefficients = Vec::new();
    let mut scales = Vec::new();
    for text in &args.params {
        let (name, value) = text.split_once('=').unwrap_or((text.as_str(), ""));
        let name = name.trim();
        match coefficient_of(name, names, model) {
            Some(canonical) => {
                let value = value
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        CliError::Usage(format!(
                            "parameter {name}: expected {name}=a finite number"
                        ))
                    })?;
                coefficients.push((canonical, value));
            }
            None => scales.push(text.clone()),
        }
    }
    let scale_args = ParamArgs {
        params: scales,
        params_file: args.params_file.clone(),
    };
    Ok((coefficients, scale_args))
}

/// The discretised nonlinear body of `model`: coefficients from `--param` under their printed
/// (or ASCII) names, the rest by [`crate::dynamics::default_coefficients`] from the scales.
pub(super) fn nonlinear_body(
    args: &ParamArgs,
    model: &Model,
    order: u32,
    points: usize,
) -> Result<crate::dynamics::nonlinear::NonlinearBody, CliError> {
    use crate::dynamics::nonlinear::{coefficient_names, NonlinearBody};
    let names = coefficient_names(model, order).map_err(CliError::usage)?;
    let (given, scale_args) = split(args, &names, model)?;
    let params = load_params(&scale_args, model).map_err(|e| match e {
        CliError::Usage(m) => CliError::Usage(format!(
            "{m} (this body's coefficients: {})",
            names.join(", ")
        )),
        other => other,
    })?;
    let mut values =
        crate::dynamics::default_coefficients(model, order, &params).map_err(CliError::usage)?;
    values.extend(given);
    NonlinearBody::new(model, order, points, &values).map_err(CliError::usage)
}

/// The scales of a linear body from `--param`, where a coefficient the equations print stands
/// for its field's scale: c = ω² sets ω = √c, c′ = ζω sets ζ = c′/ω (ω as set, or its
/// default). Two fields sharing a scale must agree; a coefficient that is not a leading square
/// has no scale to go to.
pub(super) fn linear_params(
    args: &ParamArgs,
    model: &Model,
    order: u32,
) -> Result<Params, CliError> {
    let names =
        crate::dynamics::nonlinear::coefficient_names(model, order).map_err(CliError::usage)?;
    let (mut coefficients, scale_args) = split(args, &names, model)?;
    let mut params = load_params(&scale_args, model)?;
    if coefficients.is_empty() {
        return Ok(params);
    }
    // Which field and density each coefficient belongs to.
    let mut owner = std::collections::BTreeMap::new();
    for density in [Density::Lagrangian, Density::Rayleigh] {
        let a = crate::reduce::analyse(model, density, order).map_err(CliError::usage)?;
        for f in &a.fields {
            for d in &f.density {
                if let Some(p) = &d.parameter {
                    owner.insert(p.clone(), (density, f.field.scale().to_string()));
                }
            }
        }
    }
    // Frequencies first (a damping coefficient is ζω with ω as set), then dampings.
    coefficients.sort_by_key(|(name, _)| owner.get(name).map(|o| o.0));
    let mut set: std::collections::BTreeMap<String, (String, f64)> = Default::default();
    for (name, value) in coefficients {
        let Some((density, scale)) = owner.get(&name) else {
            continue;
        };
        let (key, scaled) = match density {
            Density::Lagrangian => {
                if value <= 0.0 {
                    return Err(CliError::Usage(format!(
                        "parameter {name}: the linear path takes {name} = ω² > 0, not {value}"
                    )));
                }
                (format!("omega_{scale}"), value.sqrt())
            }
            Density::Rayleigh => (format!("zeta_{scale}"), value / params.omega(scale)),
        };
        if let Some((other, was)) = set.get(&key) {
            if (was - scaled).abs() > 1e-12 * was.abs().max(1.0) {
                return Err(CliError::Usage(format!(
                    "parameters {other} and {name} share the scale {scale} ({key}) but set it to {was} and {scaled}: give the fields their own scales in the model file"
                )));
            }
        }
        params
            .set(&key, scaled)
            .map_err(|e| CliError::Usage(format!("parameter {name}: {e}")))?;
        set.insert(key, (name, scaled));
    }
    Ok(params)
}
