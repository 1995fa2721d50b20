//! Where a run starts and what pushes it, read from the command line's texts (the same texts
//! Python passes): `FIELD:MODE=Q[,V]` (a mode), `FIELD=Q[,V]` (every point alike, a nonlinear
//! body), `FIELD:MODE=F` (a constant force), `FIELD:MODE=F0,OMEGA[,PHASE]` (a drive).

use super::BodyError;
use crate::dynamics::{Forcing, Initial};

/// Where a run starts and what pushes it: modal initial states, forces and drives, and the
/// uniform displacements of a nonlinear body, read from the command line's texts.
#[derive(Debug, Clone, Default)]
pub struct Start {
    /// Initial modal states.
    pub initial: Vec<Initial>,
    /// Constant and sinusoidal modal forces.
    pub forcing: Vec<Forcing>,
    /// `FIELD=Q[,V]`: the text, the field, Q and V.
    pub uniform: Vec<(String, String, f64, f64)>,
}

/// The most values a repeatable option takes (`--param`, `--initial`, `--force`, `--drive`).
pub const MAX_LIST: usize = 256;

impl Start {
    /// Read `initial` (`FIELD:MODE=Q[,V]` or `FIELD=Q[,V]`), `force` (`FIELD:MODE=F`) and
    /// `drive` (`FIELD:MODE=F0,OMEGA[,PHASE]`: F0·cos(OMEGA·t + PHASE)).
    pub fn parse(
        initial: &[String],
        force: &[String],
        drive: &[String],
    ) -> Result<Start, BodyError> {
        for (option, list) in [
            ("--initial", initial),
            ("--force", force),
            ("--drive", drive),
        ] {
            if list.len() > MAX_LIST {
                return Err(BodyError::Assignment {
                    option,
                    text: format!("is given {} times", list.len()),
                    why: "at most 256",
                });
            }
        }
        let mut start = Start::default();
        for text in initial {
            let uniform = text
                .split_once('=')
                .is_some_and(|(target, _)| !target.contains(':'));
            if uniform {
                let (field, values) = text.split_once('=').unwrap_or_default();
                let v = numbers("--initial", text, values, 1..=2, "give Q or Q,V")?;
                start.uniform.push((
                    text.clone(),
                    field.trim().to_string(),
                    v[0],
                    v.get(1).copied().unwrap_or(0.0),
                ));
                continue;
            }
            let (field, mode, v) = modal("--initial", text, 1..=2, "give Q or Q,V")?;
            start.initial.push(Initial {
                field,
                mode,
                displacement: v[0],
                velocity: v.get(1).copied().unwrap_or(0.0),
            });
        }
        let forcing = |field, mode, constant, amplitude, frequency, phase| Forcing {
            field,
            mode,
            constant,
            amplitude,
            frequency,
            phase,
        };
        for text in force {
            let (field, mode, v) = modal("--force", text, 1..=1, "give one value")?;
            start
                .forcing
                .push(forcing(field, mode, v[0], 0.0, 0.0, 0.0));
        }
        for text in drive {
            let (field, mode, v) =
                modal("--drive", text, 2..=3, "give F0,OMEGA or F0,OMEGA,PHASE")?;
            let phase = v.get(2).copied().unwrap_or(0.0);
            start
                .forcing
                .push(forcing(field, mode, 0.0, v[0], v[1], phase));
        }
        Ok(start)
    }

    /// Whether nothing is set: the run starts at rest and stays there without noise.
    pub fn is_empty(&self) -> bool {
        self.initial.is_empty() && self.forcing.is_empty() && self.uniform.is_empty()
    }
}

/// Comma-separated finite numbers, as many as `counts` allows.
fn numbers(
    option: &'static str,
    text: &str,
    values: &str,
    counts: std::ops::RangeInclusive<usize>,
    hint: &'static str,
) -> Result<Vec<f64>, BodyError> {
    let bad = |why| BodyError::Assignment {
        option,
        text: crate::markup::clip(text),
        why,
    };
    let values = values
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<Vec<f64>, _>>()
        .map_err(|_| bad("values must be numbers"))?;
    if values.iter().any(|v| !v.is_finite()) {
        return Err(bad("values must be finite"));
    }
    if !counts.contains(&values.len()) {
        return Err(bad(hint));
    }
    Ok(values)
}

/// `FIELD:MODE=values`: the field, the mode and the numbers.
fn modal(
    option: &'static str,
    text: &str,
    counts: std::ops::RangeInclusive<usize>,
    hint: &'static str,
) -> Result<(String, usize, Vec<f64>), BodyError> {
    let bad = |why| BodyError::Assignment {
        option,
        text: crate::markup::clip(text),
        why,
    };
    let (target, values) = text
        .split_once('=')
        .ok_or_else(|| bad("expected FIELD:MODE=VALUE"))?;
    let (field, mode) = target
        .split_once(':')
        .ok_or_else(|| bad("expected FIELD:MODE before '='"))?;
    let mode: usize = mode
        .trim()
        .parse()
        .map_err(|_| bad("the mode must be a whole number"))?;
    let values = numbers(option, text, values, counts, hint)?;
    Ok((field.trim().to_string(), mode, values))
}
