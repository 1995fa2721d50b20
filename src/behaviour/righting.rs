//! Self-righting (seed §3.3.1, App. H): the two-stage model of Fig. 3.
//!
//! The torsion field θ (free ends, operator D2,f) starts inverted and at rest: every segment at
//! θ₀ (π by default), which is the zero mode alone. Arc length runs from the tail (point 0) to
//! the head (point N − 1).
//! 1. **Twist.** A constant generalised force Q = −ω₁²θ₀/a on the first torsional mode, with
//!    a = v₁(head), moves that mode's equilibrium to Θ₁* = −θ₀/a, where the head is upright. The
//!    head obeys the seed's Eq. 20, θ̈_h + 2ζ₁ω₁θ̇_h + ω₁²θ_h = 0. No force acts on the zero mode,
//!    so the mean rotation stays θ₀: the head and tail twist in opposite directions.
//! 2. **Attach and release.** When |θ_h| ≤ δ the mouth hooks hold the head where it is and the
//!    force is released. As in App. H only two degrees of freedom move: Θ₁ relaxes passively
//!    (Eq. 162 with Q = 0) and the overall rotation follows so that the head stays put, so segment
//!    j sits at θ_h(t_a) + (v₁(j) − a)Θ₁(t).
//!
//! Both stages run through [`crate::dynamics::simulate`] (exact modal propagators). A segment is
//! aligned from the first instant after which it stays within δ of the attached head; stage 2
//! ends when the first mode's energy bound √(2E)/ω₁ guarantees that no segment can leave δ again
//! (E never grows without a force). Invariants: `alignment_times` is indexed tail to head, the
//! head's entry is the attachment time, and `righting_time` is their maximum.
//!
//! The seed says righting is fastest at critical damping ζ₁ = 1. What holds exactly is that the
//! slowest decay rate of the first mode, ζ₁ω₁ (ζ₁ ≤ 1) or ω₁(ζ₁ − √(ζ₁² − 1)) (ζ₁ ≥ 1), peaks at
//! ζ₁ = 1, and that among responses without overshoot (ζ₁ ≥ 1) critical damping is fastest. At a
//! finite tolerance a slightly underdamped mode rights sooner, by ringing through δ, as in the
//! classical settling-time problem.

use super::{field_index, finite, positive, BehaviourError};
use crate::dynamics::{simulate, Config, Forcing, Initial, STOP};
use crate::modal::Params;
use crate::model::Model;

/// Settings of a self-righting run.
#[derive(Debug, Clone, PartialEq)]
pub struct RightingSettings {
    /// Points along the body.
    pub points: usize,
    /// Initial orientation of every segment (π: upside down).
    pub theta0: f64,
    /// Tolerance δ (radians) for attachment and alignment.
    pub tolerance: f64,
    /// Damping ratio ζ₁ of the first torsional mode; `None` keeps the model's ζ_t.
    pub mode_damping: Option<f64>,
    /// Give up if a stage lasts longer than this many first-mode periods.
    pub max_periods: f64,
    /// Frames kept per stage for the output (every step is still checked).
    pub frames_per_stage: usize,
    /// How the body relaxes once the head is held.
    pub attachment: Attachment,
}

/// The relaxation after the mouth hooks attach.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Attachment {
    /// The seed's App. H: the free first mode relaxes, the overall rotation keeps the head put.
    Seed,
    /// The whole chain with the head held fixed (D2,f without the head's row and column).
    Pinned,
}

impl Default for RightingSettings {
    fn default() -> Self {
        RightingSettings {
            points: 12,
            theta0: std::f64::consts::PI,
            tolerance: 0.01,
            mode_damping: Some(1.0),
            max_periods: 1e4,
            frames_per_stage: 200,
            attachment: Attachment::Seed,
        }
    }
}

/// One instant of a self-righting run.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RightingFrame {
    /// Time.
    pub t: f64,
    /// The force on the first torsional mode.
    pub torque: f64,
    /// The first torsional modal coordinate Θ₁.
    pub mode: f64,
    /// Mean rotation of the segments relative to the substrate.
    pub mean_rotation: f64,
    /// Rotation of each segment, tail to head.
    pub angles: Vec<f64>,
}

/// The outcome of a self-righting run.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Righting {
    /// Points along the body.
    pub points: usize,
    /// Initial orientation.
    pub theta0: f64,
    /// Tolerance δ.
    pub tolerance: f64,
    /// The relaxation model after attachment.
    pub attachment: Attachment,
    /// (ω, ζ) of the slowest relaxing mode after attachment.
    pub relaxation: (f64, f64),
    /// ω₁ of the first torsional mode.
    pub frequency: f64,
    /// ζ₁ of the first torsional mode.
    pub damping_ratio: f64,
    /// a = v₁(head).
    pub head_coefficient: f64,
    /// Q = −ω₁²θ₀/a.
    pub torque: f64,
    /// When the head came within δ and the hooks attached.
    pub attachment_time: f64,
    /// When the last segment aligned.
    pub righting_time: f64,
    /// When each segment aligned, tail to head.
    pub alignment_times: Vec<f64>,
    /// Largest |mean rotation − θ₀| before attachment.
    pub rotation_before_attachment: f64,
    /// Largest excursion of Θ₁ past its equilibrium after release, as a fraction of Θ₁(t_a).
    pub overshoot: f64,
    /// The first mode's slowest decay rate.
    pub decay_rate: f64,
    /// Largest |θ_h − analytic Eq. 20| during stage 1.
    pub head_error: f64,
    /// Sampled frames of both stages.
    pub frames: Vec<RightingFrame>,
}

/// The slowest decay rate of `Q̈ + 2ζωQ̇ + ω²Q = 0`.
pub fn decay_rate(omega: f64, zeta: f64) -> f64 {
    if zeta <= 1.0 {
        zeta * omega
    } else {
        omega * (zeta - (zeta * zeta - 1.0).sqrt())
    }
}

/// Run the two-stage self-righting model on the torsion field `theta` of `model`.
pub fn self_righting(
    model: &Model,
    params: &Params,
    settings: &RightingSettings,
) -> Result<Righting, BehaviourError> {
    let theta0 = finite("the initial orientation", settings.theta0)?;
    let tol = positive("the tolerance", settings.tolerance)?;
    positive("the period limit", settings.max_periods)?;
    if theta0.abs() <= tol {
        return Err(BehaviourError(format!(
            "the body starts within the tolerance ({theta0} rad): nothing to right"
        )));
    }
    let n = settings.points;
    let mut params = params.clone();
    // Only the two lowest modes of each field are needed here (simulate computes its own).
    let lowest = |params: &Params| {
        crate::modal::field_modes(model, 4, n, params, Some(2), true)
            .map_err(|e| BehaviourError(e.to_string()))
    };
    let f = field_index(model, "theta")?;
    let modes = lowest(&params)?;
    let scale = modes[f].field.scale.clone().unwrap_or_default();
    let first = modes[f].spectrum.nullity;
    if first != 1 || modes[f].modes.len() < 2 {
        return Err(BehaviourError(
            "self-righting needs a torsion field with one zero mode (free boundary)".into(),
        ));
    }
    if let Some(z) = settings.mode_damping {
        let z = finite("the first mode's damping ratio", z)?;
        let lambda = modes[f].modes[1].eigenvalue;
        params
            .set(&format!("zeta_{scale}"), z / lambda.sqrt())
            .map_err(|e| BehaviourError(e.to_string()))?;
    }
    let modes = lowest(&params)?;
    let shapes = modes[f]
        .spectrum
        .shapes
        .clone()
        .ok_or_else(|| BehaviourError("no mode shapes".into()))?;
    let head = n - 1;
    let v1: Vec<f64> = (0..n).map(|j| shapes[(j, 1)]).collect();
    let a = v1[head];
    let m1 = &modes[f].modes[1];
    let (omega, zeta) = (m1.frequency, m1.damping_ratio);
    if zeta == 0.0 {
        return Err(BehaviourError(
            "an undamped first mode never settles: give ζ_t > 0".into(),
        ));
    }
    let torque = -omega * omega * theta0 / a;
    let rate = decay_rate(omega, zeta);
    let period = 2.0 * std::f64::consts::PI / omega;
    let dt = period / 1000.0;
    let max_steps = (settings.max_periods * 1000.0).ceil() as u64;
    // A stage lasts about ln(range/δ)/rate: sample that span into the frames.
    let expected = ((2.0 * theta0.abs() / tol).ln() + 3.0) / rate;
    if expected > settings.max_periods * period {
        return Err(BehaviourError(format!(
            "righting would take about {expected:.3e} time units, more than {} periods of the first mode: raise the tolerance or bring ζ₁ nearer 1",
            settings.max_periods
        )));
    }
    let stride = ((expected / dt) as u64 / settings.frames_per_stage.max(1) as u64).max(1);
    let field = modes[f].field.id.clone();
    let stage1 = Config {
        points: n,
        order: 4,
        dt,
        steps: max_steps,
        every: 1,
        temperature: 0.0,
        seed: 0,
        initial: vec![Initial {
            field: field.clone(),
            mode: 0,
            displacement: theta0 / shapes[(head, 0)],
            velocity: 0.0,
        }],
        forcing: vec![Forcing {
            field,
            mode: 1,
            constant: torque,
            amplitude: 0.0,
            frequency: 0.0,
            phase: 0.0,
        }],
    };

    // Stage 1: twist under the constant torque until the head is within δ.
    let mut frames = Vec::new();
    let mut drift = 0.0f64;
    let mut head_error = 0.0f64;
    let mut attached: Option<(f64, Vec<f64>, Vec<f64>)> = None;
    let mut step = 0u64;
    simulate(model, &params, &stage1, |s| {
        let angles = &s.positions[f];
        let mean = angles.iter().sum::<f64>() / n as f64;
        drift = drift.max((mean - theta0).abs());
        let expected = theta0 * (1.0 - super::analytic_step(omega, zeta, omega * omega, s.t));
        head_error = head_error.max((angles[head] - expected).abs());
        let done = angles[head].abs() <= tol;
        if step % stride == 0 || done {
            frames.push(RightingFrame {
                t: s.t,
                torque,
                mode: s.modal[f][1],
                mean_rotation: mean,
                angles: angles.clone(),
            });
        }
        step += 1;
        if done {
            // Only modes 0 and 1 ever move in stage 1.
            let rates = (0..n)
                .map(|j| {
                    s.velocity[f]
                        .iter()
                        .take(shapes.ncols())
                        .enumerate()
                        .map(|(i, p)| p * shapes[(j, i)])
                        .sum()
                })
                .collect();
            attached = Some((s.t, angles.clone(), rates));
            return Err(STOP.into());
        }
        Ok(())
    })
    .map_err(|e| BehaviourError(e.to_string()))?;
    let Some((ta, at_attach, rates)) = attached else {
        return Err(BehaviourError(format!(
            "the head did not come within {tol} rad of upright in {} periods",
            settings.max_periods
        )));
    };
    let hold = at_attach[head];

    // Stage 2: the head is held, the torque released, and the body relaxes as a sum of damped
    // modes, each carried by the exact propagator.
    let relax = match settings.attachment {
        Attachment::Seed => {
            let shape: Vec<f64> = v1.iter().map(|v| v - a).collect();
            let q: f64 = v1.iter().zip(&at_attach).map(|(v, th)| v * th).sum();
            let p: f64 = v1.iter().zip(&rates).map(|(v, w)| v * w).sum();
            vec![RelaxMode::new(omega, zeta * omega, shape, q, p)]
        }
        Attachment::Pinned => pinned_modes(
            modes[f].k,
            n,
            head,
            modes[f].omega,
            modes[f].zeta,
            &at_attach,
            &rates,
            hold,
        )?,
    };
    let start: Vec<f64> = at_attach.iter().map(|th| th - hold).collect();
    let largest = start.iter().map(|u| u.abs()).fold(0.0, f64::max);
    let mut last_out = vec![f64::NEG_INFINITY; n];
    let mut overshoot = 0.0f64;
    let mut settled = false;
    for step in 0..=max_steps {
        let t = step as f64 * dt;
        let mut u = vec![0.0; n];
        let mut bound = 0.0;
        for m in &relax {
            let (q, p) = crate::dynamics::propagate(m.omega, m.gamma, m.q, m.p, t);
            for (uj, s) in u.iter_mut().zip(&m.shape) {
                *uj += q * s;
            }
            bound += m.reach * (p * p + m.omega * m.omega * q * q).sqrt() / m.omega;
        }
        for (j, uj) in u.iter().enumerate() {
            if uj.abs() > tol {
                last_out[j] = t;
            }
            if start[j] != 0.0 && largest > 0.0 {
                overshoot = overshoot.max(-uj * start[j].signum() / largest);
            }
        }
        settled = bound <= tol;
        if step % stride == 0 || settled {
            let angles: Vec<f64> = u.iter().map(|x| hold + x).collect();
            frames.push(RightingFrame {
                t: ta + t,
                torque: 0.0,
                mode: v1.iter().zip(&u).map(|(v, x)| v * x).sum(),
                mean_rotation: angles.iter().sum::<f64>() / n as f64,
                angles,
            });
        }
        if settled {
            break;
        }
    }
    if !settled {
        return Err(BehaviourError(format!(
            "the body did not align within {tol} rad in {} periods after attachment",
            settings.max_periods
        )));
    }
    let alignment_times: Vec<f64> = last_out
        .iter()
        .map(|&t| if t.is_finite() { ta + t + dt } else { ta })
        .collect();
    Ok(Righting {
        points: n,
        theta0,
        tolerance: tol,
        attachment: settings.attachment,
        frequency: omega,
        damping_ratio: zeta,
        relaxation: relax
            .iter()
            .map(|m| (m.omega, m.gamma / m.omega))
            .next()
            .unwrap_or((0.0, 0.0)),
        head_coefficient: a,
        torque,
        attachment_time: ta,
        righting_time: alignment_times.iter().cloned().fold(ta, f64::max),
        alignment_times,
        rotation_before_attachment: drift,
        overshoot,
        decay_rate: rate,
        head_error,
        frames,
    })
}

/// One row of a damping sweep: [`self_righting`] at one ζ₁, without frames.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SweepPoint {
    /// ζ₁ of the first torsional mode.
    pub mode_damping: f64,
    /// When the hooks attached.
    pub attachment_time: f64,
    /// When the last segment aligned.
    pub righting_time: f64,
    /// Largest excursion past equilibrium after release (fraction).
    pub overshoot: f64,
    /// The first mode's slowest decay rate.
    pub decay_rate: f64,
}

/// [`self_righting`] at each first-mode damping ratio of `dampings`, other settings as given.
pub fn righting_sweep(
    model: &Model,
    params: &Params,
    settings: &RightingSettings,
    dampings: &[f64],
) -> Result<Vec<SweepPoint>, BehaviourError> {
    dampings
        .iter()
        .map(|&z| {
            let s = RightingSettings {
                mode_damping: Some(z),
                frames_per_stage: 1,
                ..settings.clone()
            };
            let r = self_righting(model, params, &s)?;
            Ok(SweepPoint {
                mode_damping: r.damping_ratio,
                attachment_time: r.attachment_time,
                righting_time: r.righting_time,
                overshoot: r.overshoot,
                decay_rate: r.decay_rate,
            })
        })
        .collect()
}

/// One damped mode of the relaxation after attachment: its shape over all points (zero at the
/// head) and its state at attachment.
struct RelaxMode {
    omega: f64,
    gamma: f64,
    shape: Vec<f64>,
    /// max |shape|: how far this mode can move any point per unit of Q.
    reach: f64,
    q: f64,
    p: f64,
}

impl RelaxMode {
    fn new(omega: f64, gamma: f64, shape: Vec<f64>, q: f64, p: f64) -> RelaxMode {
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
fn pinned_modes(
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
    let s = crate::modal::spectrum(k, held, n, None, true)
        .map_err(|e| BehaviourError(e.to_string()))?;
    let shapes = s
        .shapes
        .ok_or_else(|| BehaviourError("no mode shapes".into()))?;
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
