//! One reported instant of a run, checked finite before any sink sees it, and its CSV form
//! (numbers exact, in exponent form where plain would print dozens of digits).

use super::DynamicsError;

/// One reported instant.
#[derive(Debug, Clone)]
pub struct Sample {
    /// Time.
    pub t: f64,
    /// H, the total mechanical energy.
    pub energy: f64,
    /// Per field (model order): the field at each point.
    pub positions: Vec<Vec<f64>>,
    /// Per field: the modal coordinates Qᵢ.
    pub modal: Vec<Vec<f64>>,
    /// Per field: the modal velocities Q̇ᵢ.
    pub velocity: Vec<Vec<f64>>,
    /// The work the active forces have injected since t = 0 (a body with active forces only):
    /// with the dissipated work it closes the energy balance.
    pub injected: Option<f64>,
}

/// `s` if its time, energy and every position are finite numbers: no sample that is not is
/// ever handed to a sink.
pub fn checked(s: Sample) -> Result<Sample, DynamicsError> {
    let finite = s.t.is_finite()
        && s.energy.is_finite()
        && s.injected.is_none_or(f64::is_finite)
        && s.positions
            .iter()
            .chain(&s.modal)
            .flatten()
            .all(|v| v.is_finite());
    if finite {
        Ok(s)
    } else {
        Err(DynamicsError::Overflow {
            t: s.t,
            energy: s.energy,
        })
    }
}

/// The CSV header matching [`sample_row`]: t, energy, the injected work (`injected`, a body
/// with active forces only), each field at each point (`x_0` …), then the modal coordinates
/// (`q_x_0` …). `ids` are the model's field ids in order.
pub fn sample_header(ids: &[&str], s: &Sample) -> Vec<String> {
    let mut cols = vec!["t".to_string(), "energy".to_string()];
    if s.injected.is_some() {
        cols.push("injected".into());
    }
    for (id, field) in ids.iter().zip(&s.positions) {
        cols.extend((0..field.len()).map(|j| format!("{id}_{j}")));
    }
    for (id, field) in ids.iter().zip(&s.modal) {
        cols.extend((0..field.len()).map(|j| format!("q_{id}_{j}")));
    }
    cols
}

/// One record of a sample, in [`sample_header`]'s order.
pub fn sample_values(s: &Sample) -> Vec<f64> {
    [s.t, s.energy]
        .into_iter()
        .chain(s.injected)
        .chain(s.positions.iter().chain(&s.modal).flatten().copied())
        .collect()
}

/// One CSV record of a sample: exact (shortest round trip), in exponent form where plain would
/// print dozens of digits.
pub fn sample_row(s: &Sample) -> Vec<String> {
    sample_values(s)
        .into_iter()
        .map(crate::report::number)
        .collect()
}
