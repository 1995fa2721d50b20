//! Relaxation of the whole torsion chain with the head held: the pinned chain's modes.

use crate::behaviour::BehaviourError;

/// One damped mode of the relaxation after attachment: its shape over all points (zero at the
/// head) and its state at attachment.
pub(super) struct RelaxMode {
    pub(super) omega: f64,
    pub(super) gamma: f64,
    pub(super) shape: Vec<f64>,
    /// max |shape|: how far this mode can move any point per unit of Q.
    pub(super) reach: f64,
    pub(super) q: f64,
    pub(super) p: f64,
}

impl RelaxMode {
    pub(super) fn new(omega: f64, gamma: f64, shape: Vec<f64>, q: f64, p: f64) -> RelaxMode {
        let reach = shape.iter().map(|s| s.abs()).fold(0.0, f64::max);
        RelaxMode {
            omega,
            gamma,
            shape,
            reach,
            q,
            p,
        }
    }
}

/// The modes of the torsion chain with the head held: the model's operator (stencil order `k`)
/// with the head end held and the tail free, with the model's stiffness-proportional damping
/// (γ = ζωλ), started from the state at attachment (the head stops there).
#[allow(clippy::too_many_arguments)]
pub(super) fn pinned_modes(
    k: u32,
    n: usize,
    head: usize,
    omega: f64,
    zeta: f64,
    angles: &[f64],
    rates: &[f64],
    hold: f64,
) -> Result<Vec<RelaxMode>, BehaviourError> {
    use crate::model::{Boundary, End};
    debug_assert_eq!(head, n - 1, "arc length runs from the tail to the head");
    let held = Boundary::Ends {
        tail: End::Free,
        head: End::Clamped,
    };
    let s = crate::modal::spectrum(k, held, n, None, true)?;
    let shapes = s
        .shapes
        .ok_or_else(|| BehaviourError::new("no mode shapes"))?;
    // Unknown u is point u: the held points are at the head.
    Ok(s.eigenvalues
        .iter()
        .enumerate()
        .map(|(m, &lambda)| {
            let mut shape = vec![0.0; n];
            let (mut q, mut p) = (0.0, 0.0);
            for u in 0..s.size {
                let w = shapes[(u, m)];
                shape[u] = w;
                q += w * (angles[u] - hold);
                p += w * rates[u];
            }
            RelaxMode::new(omega * lambda.sqrt(), zeta * omega * lambda, shape, q, p)
        })
        .collect())
}
