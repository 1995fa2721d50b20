//! Behaviour models of the paper built on the modes, one file each:
//!
//! * [`asymmetry`]: forward/backward waves of the self-interacting axial pair (App. C);
//! * [`mathieu`]: axial–transverse parametric resonance, the Floquet chart (App. D);
//! * [`pair`]: statistics of a degenerate pair at fixed momentum (App. J);
//! * [`orbit`]: peristalsis and rolling, minimum-energy orbits of a degenerate pair (App. I);
//! * [`step`]: rearing and hunching, a constant force on one mode (§3.3.2);
//! * [`explore`]: unbiased exploration, Gaussian postures and the 3-point bend (§3.3.4);
//! * [`equipartition`]: a Langevin run's PCA beside the modes (App. B);
//! * [`righting`]: self-righting (§3.3.1, App. H).
//!
//! A behaviour finds its fields by role ([`ROLE_NEEDS`] says which), never by id, and borrows
//! the modes of one [`Theory`](crate::theory::Theory).

pub mod asymmetry;
pub mod equipartition;
pub mod explore;
pub mod forward_backward;
pub mod mathieu;
mod numerics;
pub mod orbit;
pub mod pair;
mod righting;
pub mod step;

pub use asymmetry::{asymmetry, asymmetry_roots, simulate_pair, Asymmetry};
pub use equipartition::{equipartition_from_dynamics, EquipartitionCheck, EQUIPARTITION_BUDGET};
pub use explore::{explore, fit_beta, Exploration};
pub use forward_backward::{forward_backward, ForwardBackward, Split, PAPER_COUPLING};
pub use mathieu::{
    chart, floquet, mathieu_monodromy, stability_chart, FloquetPoint, StabilityChart,
};
pub use numerics::{principal_components, rk4_step, PcaError, PhaseUnwrap};
pub use orbit::{pair_orbit, PairKind, PairOrbit};
pub use pair::{
    given_pair_frequency, integrate, pair_amplitude_weight, pair_frequency, pair_statistics,
    sample_pair, scaled_bessel_k1, PairReport, PairSamples, PairStatistics,
};
pub use righting::{
    decay_rate, righting_sweep, self_righting, Attachment, Righting, RightingFrame, RightingReport,
    RightingSettings, SweepPoint, MAX_SWEEP,
};
pub use step::{analytic_step, step_response, StepResponse};

use crate::model::{Model, Role, RoleError};

/// Why a behaviour cannot run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BehaviourError {
    /// A parameter out of range, or a run that cannot be done.
    #[error("{0}")]
    Invalid(String),
    /// The model lacks a field role the behaviour needs.
    #[error(transparent)]
    Role(#[from] RoleError),
    /// The body has the role but not the structure the behaviour needs (a degenerate pair, a
    /// free torsion field).
    #[error("{0}")]
    Body(String),
    /// A spectrum the behaviour needs could not be computed.
    #[error(transparent)]
    Modal(#[from] crate::modal::ModalError),
    /// The principal components could not be computed.
    #[error(transparent)]
    Pca(#[from] numerics::PcaError),
    /// The modes or the dynamics failed.
    #[error(transparent)]
    Dynamics(#[from] crate::dynamics::DynamicsError),
    /// The model's `[active]` section cannot be enumerated at this order.
    #[error(transparent)]
    Active(#[from] crate::active::ActiveError),
}

impl BehaviourError {
    /// The kind of failure.
    pub fn failure(&self) -> crate::failure::Failure {
        match self {
            BehaviourError::Dynamics(e) => e.failure(),
            BehaviourError::Modal(e) if e.is_numerical() => crate::failure::Failure::Numerical,
            BehaviourError::Pca(_) => crate::failure::Failure::Numerical,
            _ => crate::failure::Failure::Usage,
        }
    }

    /// Whether the body lacks what the behaviour needs (a role or a structure), rather than
    /// a setting being out of range or a run failing.
    pub fn is_missing_structure(&self) -> bool {
        matches!(self, BehaviourError::Role(_) | BehaviourError::Body(_))
    }

    fn new(why: impl Into<String>) -> BehaviourError {
        BehaviourError::Invalid(why.into())
    }
}

/// The field roles each behaviour needs, in the order it uses them: data, so a model that
/// lacks one is told which role and which command, and `--help` can list them.
pub const ROLE_NEEDS: &[(&str, &[Role])] = &[
    ("asymmetry", &[Role::Axial]),
    ("behave peristalsis", &[Role::Axial]),
    ("stats pair", &[Role::Axial]),
    ("behave rolling", &[Role::Lateral, Role::Dorsoventral]),
    ("behave rearing", &[Role::Dorsoventral]),
    ("behave hunching", &[Role::Axial]),
    ("behave self-righting", &[Role::Torsion]),
    ("stats explore", &[Role::Lateral]),
    ("stats equipartition", &[Role::Lateral]),
    ("fit (midlines)", &[Role::Lateral]),
    ("fit (lengths)", &[Role::Axial]),
];

/// The field indices `behaviour` needs in `model`, in [`ROLE_NEEDS`] order.
pub fn role_fields(model: &Model, behaviour: &str) -> Result<Vec<usize>, RoleError> {
    let roles = ROLE_NEEDS
        .iter()
        .find(|(name, _)| *name == behaviour)
        .map(|(_, roles)| *roles)
        .unwrap_or(&[]);
    roles
        .iter()
        .map(|&r| model.role_index(r, behaviour))
        .collect()
}

fn finite(name: &str, v: f64) -> Result<f64, BehaviourError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(BehaviourError::new(format!(
            "{name} must be a finite number, not {v}"
        )))
    }
}

fn positive(name: &str, v: f64) -> Result<f64, BehaviourError> {
    if finite(name, v)? > 0.0 {
        Ok(v)
    } else {
        Err(BehaviourError::new(format!(
            "{name} must be positive, not {}",
            crate::report::number(v)
        )))
    }
}
