//! A field's physical modes: eigenvalues turned into frequencies, damping ratios, regimes and
//! variance shares with the model's scales.

use super::{continuum_beta, degenerate_pairs, seed_eq17, spectrum, ModalError, Spectrum};
use crate::model::Boundary;
use crate::params::Params;

/// How a damped mode moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Regime {
    /// A zero mode: free motion.
    Free,
    /// ζᵢ < 1: oscillates at the damped frequency.
    Underdamped,
    /// ζᵢ = 1 (to 1e-12).
    Critical,
    /// ζᵢ > 1: creeps back without oscillation.
    Overdamped,
}

impl Regime {
    /// Name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Regime::Free => "zero-mode",
            Regime::Underdamped => "underdamped",
            Regime::Critical => "critical",
            Regime::Overdamped => "overdamped",
        }
    }
}

/// One mode with its physics.
#[derive(Debug, Clone)]
pub struct Mode {
    /// Index in ascending order.
    pub index: usize,
    /// Eigenvalue λᵢ.
    pub eigenvalue: f64,
    /// ωᵢ = ω√λᵢ.
    pub frequency: f64,
    /// ζᵢ = ζ√λᵢ.
    pub damping_ratio: f64,
    /// ωᵢ√(1 − ζᵢ²) when underdamped.
    pub damped_frequency: Option<f64>,
    /// Regime.
    pub regime: Regime,
    /// λᵢ⁻¹ / Σⱼ λⱼ⁻¹ over all non-zero modes; 0 for zero modes.
    pub variance_share: f64,
    /// Running sum of the shares.
    pub cumulative_share: f64,
    /// The zero mode's name, for zero modes.
    pub zero_mode: Option<String>,
}

/// A beam's i-th non-zero eigenvalue beside its continuum limit (and, free–free, the paper's
/// Eq. 17).
#[derive(Debug, Clone)]
pub struct BeamComparison {
    /// Mode index (ascending, zero modes included).
    pub index: usize,
    /// The numerical eigenvalue.
    pub eigenvalue: f64,
    /// 16 sin⁴(πi/(2(N−1))): the paper's Eq. 17, for the free–free beam only.
    pub seed_eq17: Option<f64>,
    /// (βᵢL)⁴/(N−1)⁴.
    pub continuum: f64,
}

/// All the modes of one field.
#[derive(Debug, Clone)]
pub struct FieldModes {
    /// The field.
    pub field: crate::model::Field,
    /// Stencil order of its operator.
    pub k: u32,
    /// The spectrum.
    pub spectrum: Spectrum,
    /// ω of the field.
    pub omega: f64,
    /// ζ of the field.
    pub zeta: f64,
    /// The lowest modes.
    pub modes: Vec<Mode>,
    /// Consecutive degenerate pairs (i, j).
    pub degenerate_pairs: Vec<(usize, usize)>,
    /// An earlier field with the same operator and scales, hence the same frequencies.
    pub same_frequencies_as: Option<String>,
    /// Beams (k = 2, any ends): numerics beside the continuum limit (and Eq. 17 when free).
    pub beam: Vec<BeamComparison>,
}

/// Why the model's modes cannot be computed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ModesError {
    /// The modal solver failed.
    #[error("field {field}: {source}")]
    Modal {
        /// Field id.
        field: String,
        /// The error.
        source: ModalError,
    },
    /// The operators could not be derived.
    #[error(transparent)]
    Discretise(#[from] crate::discretise::DiscretiseError),
    /// A field lacks a potential or damping operator, or they differ.
    #[error("field {field}: {why}")]
    Operator {
        /// Field id.
        field: String,
        /// What is wrong.
        why: OperatorIssue,
    },
}

/// Why a field's operators do not make the modal theory.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum OperatorIssue {
    /// No potential term survives.
    #[error("no potential term survives at order {order}, so there is no stiffness operator (see the notes of `theory-search --order {order}`; raise --order)")]
    NoPotential {
        /// The order asked for.
        order: u32,
    },
    /// More than one potential term survives.
    #[error("{count} potential terms survive at order {order}; modes need exactly one potential operator")]
    ManyPotentials {
        /// How many.
        count: usize,
        /// The order asked for.
        order: u32,
    },
    /// The damping operator is not the stiffness operator.
    #[error("the damping operator (Δ^{damping}) differs from the stiffness one (Δ^{stiffness}): damping is not modal")]
    NotModal {
        /// Power of Δ in the damping.
        damping: u32,
        /// Power of Δ in the stiffness.
        stiffness: u32,
    },
}

impl ModesError {
    /// The kind of failure: an eigensolver that fails on valid input is numerical; everything
    /// else is a body or a size the solver does not take.
    pub fn failure(&self) -> crate::failure::Failure {
        match self {
            ModesError::Modal { source, .. } if source.is_numerical() => {
                crate::failure::Failure::Numerical
            }
            _ => crate::failure::Failure::Usage,
        }
    }
}

/// Frequencies, damping ratios, regimes and variance shares of a spectrum at scales ω, ζ.
fn physical_modes(
    spectrum: &Spectrum,
    field: &crate::model::Field,
    omega: f64,
    zeta: f64,
) -> Vec<Mode> {
    let mut cumulative = 0.0;
    spectrum
        .eigenvalues
        .iter()
        .enumerate()
        .map(|(i, &lam)| {
            let zero = i < spectrum.nullity;
            let (frequency, ratio) = (omega * lam.sqrt(), zeta * lam.sqrt());
            let regime = if zero {
                Regime::Free
            } else if (ratio - 1.0).abs() <= 1e-12 {
                Regime::Critical
            } else if ratio < 1.0 {
                Regime::Underdamped
            } else {
                Regime::Overdamped
            };
            let share = if zero {
                0.0
            } else {
                1.0 / lam / spectrum.inverse_trace
            };
            cumulative += share;
            Mode {
                index: i,
                eigenvalue: lam,
                frequency,
                damping_ratio: ratio,
                damped_frequency: (regime == Regime::Underdamped)
                    .then(|| frequency * (1.0 - ratio * ratio).sqrt()),
                regime,
                variance_share: share,
                cumulative_share: cumulative,
                zero_mode: zero.then(|| {
                    field
                        .zero_modes
                        .get(i)
                        .cloned()
                        .unwrap_or_else(|| format!("zero mode {i}"))
                }),
            }
        })
        .collect()
}

impl FieldModes {
    /// The same modes with the damping scale ζ (ζᵢ = ζ√λᵢ), without solving again.
    pub fn with_zeta(&self, zeta: f64) -> FieldModes {
        FieldModes {
            zeta,
            modes: physical_modes(&self.spectrum, &self.field, self.omega, zeta),
            ..self.clone()
        }
    }
}

/// The modes of every field of `model` at `order` on `points` points.
pub fn field_modes(
    model: &crate::model::Model,
    order: u32,
    points: usize,
    params: &Params,
    limit: Option<usize>,
    shapes: bool,
) -> Result<Vec<FieldModes>, ModesError> {
    use crate::model::Density;
    let plan = crate::discretise::plan(model, order)?;
    let mut out: Vec<FieldModes> = Vec::new();
    for field in &model.fields {
        let op = |d: Density| {
            plan.iter()
                .filter(|p| p.field == field.id && p.density == d)
                .collect::<Vec<_>>()
        };
        let (potential, damping) = (op(Density::Lagrangian), op(Density::Rayleigh));
        let operator_error = |why: OperatorIssue| ModesError::Operator {
            field: field.id.clone(),
            why,
        };
        let [stiff] = potential.as_slice() else {
            return Err(operator_error(if potential.is_empty() {
                OperatorIssue::NoPotential { order }
            } else {
                OperatorIssue::ManyPotentials {
                    count: potential.len(),
                    order,
                }
            }));
        };
        // Modal damping ζᵢ = ζ√λᵢ needs the Rayleigh operator to be the potential one.
        if let Some(d) = damping.iter().find(|d| d.k != stiff.k) {
            return Err(operator_error(OperatorIssue::NotModal {
                damping: d.k,
                stiffness: stiff.k,
            }));
        }
        let spectrum =
            spectrum(stiff.k, stiff.boundary, points, limit, shapes).map_err(|source| {
                ModesError::Modal {
                    field: field.id.clone(),
                    source,
                }
            })?;
        let (omega, zeta) = (params.omega(field.scale()), params.zeta(field.scale()));
        let zeta = if damping.is_empty() { 0.0 } else { zeta };
        let modes = physical_modes(&spectrum, field, omega, zeta);
        let same_frequencies_as = out
            .iter()
            .find(|o| {
                o.k == stiff.k
                    && o.field.boundary == field.boundary
                    && o.omega == omega
                    && o.zeta == zeta
            })
            .map(|o| o.field.id.clone());
        let beam = match stiff.boundary {
            Boundary::Ends { .. } if stiff.k == 2 => {
                let l4 = (points as f64 - 1.0).powi(4);
                let free = stiff.boundary == Boundary::FREE;
                spectrum
                    .eigenvalues
                    .iter()
                    .enumerate()
                    .skip(spectrum.nullity)
                    .filter_map(|(i, &lam)| {
                        let order = i - spectrum.nullity + 1;
                        Some(BeamComparison {
                            index: i,
                            eigenvalue: lam,
                            seed_eq17: free.then(|| seed_eq17(order, points)),
                            continuum: continuum_beta(2, stiff.boundary, order)?.powi(4) / l4,
                        })
                    })
                    .collect()
            }
            _ => Vec::new(),
        };
        out.push(FieldModes {
            degenerate_pairs: degenerate_pairs(&spectrum.eigenvalues, spectrum.nullity, 1e-9),
            field: field.clone(),
            k: stiff.k,
            spectrum,
            omega,
            zeta,
            modes,
            same_frequencies_as,
            beam,
        });
    }
    Ok(out)
}
