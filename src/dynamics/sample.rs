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
}

/// `s` if its time, energy and every position are finite numbers: no sample that is not is
/// ever handed to a sink.
pub fn checked(s: Sample) -> Result<Sample, DynamicsError> {
    let finite = s.t.is_finite()
        && s.energy.is_finite()
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

/// The CSV header matching [`sample_row`]: t, energy, each field at each point (`x_0` …),
/// then the modal coordinates (`q_x_0` …). `ids` are the model's field ids in order.
pub fn sample_header(ids: &[&str], s: &Sample) -> Vec<String> {
    let mut cols = vec!["t".to_string(), "energy".to_string()];
    for (id, field) in ids.iter().zip(&s.positions) {
        cols.extend((0..field.len()).map(|j| format!("{id}_{j}")));
    }
    for (id, field) in ids.iter().zip(&s.modal) {
        cols.extend((0..field.len()).map(|j| format!("q_{id}_{j}")));
    }
    cols
}

/// One CSV record of a sample.
pub fn sample_row(s: &Sample) -> Vec<String> {
    // Exact (shortest round trip), in exponent form where plain would print dozens of digits.
    let number = crate::report::number;
    let mut cells = vec![number(s.t), number(s.energy)];
    for field in s.positions.iter().chain(&s.modal) {
        cells.extend(field.iter().map(|&v| number(v)));
    }
    cells
}
