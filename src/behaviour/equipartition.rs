//! Equipartition from dynamics (paper App. B): a Langevin run's principal components beside the
//! modes of one field.

use super::{positive, principal_components, role_fields, BehaviourError};
use crate::report::{check_finite, csv_numbers, number, to_json, NonFinite, Report};
use crate::theory::Theory;

/// Principal components of simulated postures of one field beside its modes.
#[derive(Debug, Clone, serde::Serialize)]
pub struct EquipartitionCheck {
    /// Field id.
    pub field: String,
    /// Points along the body.
    pub points: usize,
    /// Thermal energy kT of the run.
    pub temperature: f64,
    /// Postures used.
    pub frames: usize,
    /// Variance share of each principal component (descending), over the non-zero modes.
    pub pca_variance_share: Vec<f64>,
    /// Equipartition share λᵢ⁻¹/Σλⱼ⁻¹ of the non-zero modes (ascending λ).
    pub theory_variance_share: Vec<f64>,
    /// |cos| between principal component k and the k-th non-zero mode shape.
    pub overlap: Vec<f64>,
}

/// The largest steps × N(N + 50) that [`equipartition_from_dynamics`] takes, about three
/// seconds: a step costs the modes (∝ N) and their shapes' sum (∝ N²); measured 1.0 s for
/// 2·10⁶ steps at N = 12 (1.5·10⁹ units), 1.2 s for 2·10⁴ steps at N = 200 (10⁹ units).
pub const EQUIPARTITION_BUDGET: f64 = 4e9;

/// Run the Langevin dynamics of the theory at temperature `kt` and compare the PCA of the
/// postures of the field with id `field` (the lateral field by default) with its modes (paper App. B:
/// equipartition from dynamics). Only that field is simulated: the others do not couple.
pub fn equipartition_from_dynamics(
    theory: &Theory,
    field: Option<&str>,
    steps: u64,
    kt: f64,
    seed: u64,
) -> Result<EquipartitionCheck, BehaviourError> {
    use crate::dynamics::{run, Config};
    let points = theory.points;
    // Every step costs O(N) for the modes and O(N²) for the positions: refuse long runs.
    let n = points as f64;
    let work = steps as f64 * n * (n + 50.0);
    if work > EQUIPARTITION_BUDGET {
        return Err(BehaviourError::new(format!(
            "{steps} steps on {points} points is {work:.1e} units of work, over the {EQUIPARTITION_BUDGET:.0e} budget (about three seconds): use fewer points or steps"
        )));
    }
    let index = match field {
        Some(id) => theory
            .model
            .fields
            .iter()
            .position(|f| f.id == id)
            .ok_or_else(|| {
                BehaviourError::new(format!(
                    "the model has no field {}",
                    crate::markup::clip(id)
                ))
            })?,
        None => role_fields(&theory.model, "stats equipartition")?[0],
    };
    let f = &theory.modes[index];
    // Postures live on the body's points (held points stay at zero).
    let n = f
        .spectrum
        .shapes
        .as_ref()
        .map_or(f.spectrum.size, |s| s.nrows());
    let config = Config {
        points,
        order: theory.order,
        dt: 0.5,
        steps,
        every: 1,
        temperature: positive("kT", kt)?,
        seed,
        initial: Vec::new(),
        forcing: Vec::new(),
    };
    // Accumulate the covariance of the postures after a burn-in of a tenth of the run.
    if steps < 100 {
        return Err(BehaviourError::new(format!(
            "--steps {steps}: at least 100 are needed (a tenth is burn-in, the rest make the covariance)"
        )));
    }
    let burn = steps / 10;
    let (mut sum, mut outer, mut frames) = (vec![0.0; n], vec![vec![0.0; n]; n], 0usize);
    run(std::slice::from_ref(f), &config, |s| {
        if (s.t / config.dt).round() as u64 > burn {
            let q = &s.positions[0];
            for i in 0..n {
                sum[i] += q[i];
                for j in 0..n {
                    outer[i][j] += q[i] * q[j];
                }
            }
            frames += 1;
        }
        Ok(())
    })?;
    let fr = frames as f64;
    let cov: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| outer[i][j] / fr - sum[i] * sum[j] / (fr * fr))
                .collect()
        })
        .collect();
    let (variances, components) = principal_components(&cov)?;
    // Principal components by descending variance; the zero modes (and held points) carry none.
    let nonzero = f.spectrum.size - f.spectrum.nullity;
    let total: f64 = variances[..nonzero].iter().map(|v| v.max(0.0)).sum();
    let shapes = f
        .spectrum
        .shapes
        .as_ref()
        .ok_or_else(|| BehaviourError::new("no shapes"))?;
    let overlap = components[..nonzero]
        .iter()
        .enumerate()
        .map(|(rank, pc)| {
            let mode = f.spectrum.nullity + rank;
            (0..n).map(|i| pc[i] * shapes[(i, mode)]).sum::<f64>().abs()
        })
        .collect();
    Ok(EquipartitionCheck {
        field: f.field.id.clone(),
        points,
        temperature: kt,
        frames,
        pca_variance_share: variances[..nonzero]
            .iter()
            .map(|v| v.max(0.0) / total)
            .collect(),
        theory_variance_share: f.modes[f.spectrum.nullity..]
            .iter()
            .map(|m| m.variance_share)
            .collect(),
        overlap,
    })
}

impl Report for EquipartitionCheck {
    fn check(&self) -> Result<(), NonFinite> {
        check_finite(self)
    }

    fn text(&self) -> String {
        let mut t = format!(
            "PCA of {} simulated postures of {} (N = {}, kT = {}) beside its non-zero modes\n   k   PCA share   equipartition   |cos(PC, mode)|\n",
            self.frames, self.field, self.points, number(self.temperature)
        );
        for k in 0..self.overlap.len() {
            t += &format!(
                "  {:>2}   {:>8.4} %   {:>10.4} %   {:>10.5}\n",
                k + 1,
                100.0 * self.pca_variance_share[k],
                100.0 * self.theory_variance_share[k],
                self.overlap[k]
            );
        }
        t
    }

    fn json(&self) -> serde_json::Value {
        to_json(self)
    }

    fn csv(&self) -> Option<String> {
        Some(csv_numbers(
            &[
                "k",
                "pca_variance_share",
                "theory_variance_share",
                "overlap",
            ],
            (0..self.overlap.len()).map(|k| {
                vec![
                    (k + 1) as f64,
                    self.pca_variance_share[k],
                    self.theory_variance_share[k],
                    self.overlap[k],
                ]
            }),
        ))
    }
}
