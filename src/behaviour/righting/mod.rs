//! Self-righting (paper §3.3.1, App. H): the two-stage model of Fig. 3.
//!
//! The torsion field θ (the model's `torsion` role, free ends) starts inverted and at rest: every segment at
//! θ₀ (π by default), which is the zero mode alone. Arc length runs from the tail (point 0) to
//! the head (point N − 1).
//! 1. **Twist.** A constant generalised force Q = −ω₁²θ₀/a on the first torsional mode, with
//!    a = v₁(head), moves that mode's equilibrium to Θ₁* = −θ₀/a, where the head is upright. The
//!    head obeys the paper's Eq. 20, θ̈_h + 2ζ₁ω₁θ̇_h + ω₁²θ_h = 0. No force acts on the zero mode,
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
//! The paper says righting is fastest at critical damping ζ₁ = 1. What holds exactly is that the
//! slowest decay rate of the first mode, ζ₁ω₁ (ζ₁ ≤ 1) or ω₁(ζ₁ − √(ζ₁² − 1)) (ζ₁ ≥ 1), peaks at
//! ζ₁ = 1, and that among responses without overshoot (ζ₁ ≥ 1) critical damping is fastest. At a
//! finite tolerance a slightly underdamped mode rights sooner, by ringing through δ, as in the
//! classical settling-time problem.

mod pinned;
mod report;
use pinned::{pinned_modes, RelaxMode};
pub use report::RightingReport;

use super::{finite, positive, role_fields, BehaviourError};
use crate::dynamics::{run, Config, Forcing, Halt, Initial};
use crate::theory::Theory;

/// Settings of a self-righting run.
#[derive(Debug, Clone, PartialEq)]
pub struct RightingSettings {
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
    /// The paper's App. H: the free first mode relaxes, the overall rotation keeps the head put.
    Paper,
    /// The whole chain with the head held fixed (D2,f without the head's row and column).
    Pinned,
}

impl Default for RightingSettings {
    fn default() -> Self {
        RightingSettings {
            theta0: std::f64::consts::PI,
            tolerance: 0.01,
            mode_damping: Some(1.0),
            max_periods: 1e4,
            frames_per_stage: 200,
            attachment: Attachment::Paper,
        }
    }
}

impl RightingSettings {
    /// ζ₁ of a run: `given`, else the model's own ζ when the user set it (`file_given`, or the
    /// body's parameters name the torsion field's ζ), else critical damping (ζ₁ = 1).
    pub fn mode_damping_for(
        theory: &Theory,
        given: Option<f64>,
        file_given: bool,
    ) -> Result<Option<f64>, BehaviourError> {
        let torsion = super::role_fields(&theory.model, "behave self-righting")?[0];
        let zeta = crate::params::Params::zeta_name(theory.model.fields[torsion].scale());
        let explicit = file_given || theory.params.get(&zeta).is_some();
        Ok(given.or((!explicit).then_some(1.0)))
    }
}

impl std::str::FromStr for Attachment {
    type Err = BehaviourError;

    /// `paper` (alias `seed`) or `pinned`.
    fn from_str(name: &str) -> Result<Attachment, BehaviourError> {
        match name {
            "paper" | "seed" => Ok(Attachment::Paper),
            "pinned" => Ok(Attachment::Pinned),
            other => Err(BehaviourError::Invalid(format!(
                "attachment must be \"paper\" or \"pinned\", not {}",
                crate::markup::clip(other)
            ))),
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

/// Run the two-stage self-righting model on the torsion field of `theory`.
pub fn self_righting(
    theory: &Theory,
    settings: &RightingSettings,
) -> Result<Righting, BehaviourError> {
    let theta0 = finite("the initial orientation", settings.theta0)?;
    let tol = positive("the tolerance", settings.tolerance)?;
    positive("the period limit", settings.max_periods)?;
    if theta0.abs() <= tol {
        return Err(BehaviourError::new(format!(
            "the body starts within the tolerance ({theta0} rad): nothing to right"
        )));
    }
    let n = theory.points;
    let torsion = torsion_modes(theory, settings)?;
    let modes = std::slice::from_ref(&torsion);
    let shapes = torsion
        .spectrum
        .shapes
        .clone()
        .ok_or_else(|| BehaviourError::new("no mode shapes"))?;
    let head = n - 1;
    let v1: Vec<f64> = (0..n).map(|j| shapes[(j, 1)]).collect();
    let a = v1[head];
    let m1 = &torsion.modes[1];
    let (omega, zeta) = (m1.frequency, m1.damping_ratio);
    if zeta == 0.0 {
        return Err(BehaviourError::new(
            "an undamped first mode never settles: give ζ_t > 0",
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
        return Err(BehaviourError::new(format!(
            "righting would take about {expected:.3e} time units, more than {} periods of the first mode: raise the tolerance or bring ζ₁ nearer 1",
            settings.max_periods
        )));
    }
    let stride = ((expected / dt) as u64 / settings.frames_per_stage.max(1) as u64).max(1);
    // Each stage is given ten times its expected span (within the period limit), so the work
    // budget sees the steps a run will take, not the limit.
    let max_steps = max_steps.min((10.0 * expected / dt).ceil() as u64 + 1000);
    let plan = Plan {
        order: theory.order,
        n,
        head,
        theta0,
        tol,
        omega,
        zeta,
        torque,
        dt,
        stride,
        max_steps,
        max_periods: settings.max_periods,
    };
    let mut frames = Vec::new();
    let twisted = twist(&plan, modes, &shapes, &mut frames)?;
    let (drift, head_error, ta) = (twisted.drift, twisted.head_error, twisted.time);
    let (at_attach, rates) = (twisted.angles, twisted.rates);
    let hold = at_attach[head];

    // Stage 2: the head is held, the torque released, and the body relaxes as a sum of damped
    // modes, each carried by the exact propagator.
    let relax = match settings.attachment {
        Attachment::Paper => {
            let shape: Vec<f64> = v1.iter().map(|v| v - a).collect();
            let q: f64 = v1.iter().zip(&at_attach).map(|(v, th)| v * th).sum();
            let p: f64 = v1.iter().zip(&rates).map(|(v, w)| v * w).sum();
            vec![RelaxMode::new(omega, zeta * omega, shape, q, p)]
        }
        Attachment::Pinned => pinned_modes(
            torsion.k,
            n,
            head,
            torsion.omega,
            torsion.zeta,
            &at_attach,
            &rates,
            hold,
        )?,
    };
    let (last_out, overshoot) = release(&plan, &relax, &at_attach, &v1, ta, &mut frames)?;
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

/// The torsion field's modes, checked for one zero mode, with the damping scale that gives the
/// asked first-mode ratio ζ₁ = ζ√λ₁ (without solving again).
fn torsion_modes(
    theory: &Theory,
    settings: &RightingSettings,
) -> Result<crate::modal::FieldModes, BehaviourError> {
    let f = role_fields(&theory.model, "behave self-righting")?[0];
    let torsion = &theory.modes[f];
    if torsion.spectrum.nullity != 1 || torsion.modes.len() < 2 {
        return Err(BehaviourError::Body(format!(
            "self-righting needs a torsion field with one zero mode (free at both ends); {} is {}",
            torsion.field.id, torsion.field.boundary
        )));
    }
    Ok(match settings.mode_damping {
        Some(z) => {
            let z = finite("the first mode's damping ratio", z)?;
            if z < 0.0 {
                return Err(BehaviourError::new(format!(
                    "the first mode's damping ratio must be at least 0, not {}",
                    crate::report::number(z)
                )));
            }
            torsion.with_zeta(z / torsion.modes[1].eigenvalue.sqrt())
        }
        None => torsion.clone(),
    })
}

/// What both stages share.
struct Plan {
    order: u32,
    n: usize,
    head: usize,
    theta0: f64,
    tol: f64,
    omega: f64,
    zeta: f64,
    torque: f64,
    dt: f64,
    stride: u64,
    max_steps: u64,
    max_periods: f64,
}

/// The state when the hooks attach, and what stage 1 measured.
struct Twisted {
    time: f64,
    angles: Vec<f64>,
    rates: Vec<f64>,
    drift: f64,
    head_error: f64,
}

/// Stage 1: twist under the constant torque until the head is within δ.
fn twist(
    plan: &Plan,
    modes: &[crate::modal::FieldModes],
    shapes: &faer::Mat<f64>,
    frames: &mut Vec<RightingFrame>,
) -> Result<Twisted, BehaviourError> {
    let (n, head, theta0, tol, omega, zeta, torque, dt, stride, max_steps) = (
        plan.n,
        plan.head,
        plan.theta0,
        plan.tol,
        plan.omega,
        plan.zeta,
        plan.torque,
        plan.dt,
        plan.stride,
        plan.max_steps,
    );
    let field = modes[0].field.id.clone();
    let stage1 = Config {
        points: n,
        order: plan.order,
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

    let mut drift = 0.0f64;
    let mut head_error = 0.0f64;
    let mut attached: Option<(f64, Vec<f64>, Vec<f64>)> = None;
    let mut step = 0u64;
    run(modes, &stage1, |s| {
        let angles = &s.positions[0];
        let mean = angles.iter().sum::<f64>() / n as f64;
        drift = drift.max((mean - theta0).abs());
        let expected = theta0 * (1.0 - super::analytic_step(omega, zeta, omega * omega, s.t));
        head_error = head_error.max((angles[head] - expected).abs());
        let done = angles[head].abs() <= tol;
        if step % stride == 0 || done {
            frames.push(RightingFrame {
                t: s.t,
                torque,
                mode: s.modal[0][1],
                mean_rotation: mean,
                angles: angles.clone(),
            });
        }
        step += 1;
        if done {
            // Only modes 0 and 1 ever move in stage 1.
            let rates = (0..n)
                .map(|j| {
                    s.velocity[0]
                        .iter()
                        .take(shapes.ncols())
                        .enumerate()
                        .map(|(i, p)| p * shapes[(j, i)])
                        .sum()
                })
                .collect();
            attached = Some((s.t, angles.clone(), rates));
            return Err(Halt::Stop);
        }
        Ok(())
    })?;
    let Some((ta, at_attach, rates)) = attached else {
        return Err(BehaviourError::new(format!(
            "the head did not come within {tol} rad of upright in {} periods",
            plan.max_periods
        )));
    };
    Ok(Twisted {
        time: ta,
        angles: at_attach,
        rates,
        drift,
        head_error,
    })
}

/// Stage 2: the head is held, the torque released, and the body relaxes as a sum of damped
/// modes, each carried by the exact propagator. Returns when each point last left δ, and the
/// overshoot.
fn release(
    plan: &Plan,
    relax: &[RelaxMode],
    at_attach: &[f64],
    v1: &[f64],
    ta: f64,
    frames: &mut Vec<RightingFrame>,
) -> Result<(Vec<f64>, f64), BehaviourError> {
    let (n, head, tol, dt, stride, max_steps) = (
        plan.n,
        plan.head,
        plan.tol,
        plan.dt,
        plan.stride,
        plan.max_steps,
    );
    let hold = at_attach[head];
    let start: Vec<f64> = at_attach.iter().map(|th| th - hold).collect();
    let largest = start.iter().map(|u| u.abs()).fold(0.0, f64::max);
    let mut last_out = vec![f64::NEG_INFINITY; n];
    let mut overshoot = 0.0f64;
    let mut settled = false;
    for step in 0..=max_steps {
        let t = step as f64 * dt;
        let mut u = vec![0.0; n];
        let mut bound = 0.0;
        for m in relax {
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
        return Err(BehaviourError::new(format!(
            "the body did not align within {tol} rad in {} periods after attachment",
            plan.max_periods
        )));
    }
    Ok((last_out, overshoot))
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

/// The most damping ratios one sweep runs (each is a whole self-righting run, about 0.1 s).
pub const MAX_SWEEP: usize = 50;

/// [`self_righting`] at each first-mode damping ratio of `dampings` (at most [`MAX_SWEEP`]),
/// other settings as given.
pub fn righting_sweep(
    theory: &Theory,
    settings: &RightingSettings,
    dampings: &[f64],
) -> Result<Vec<SweepPoint>, BehaviourError> {
    if dampings.len() > MAX_SWEEP {
        return Err(BehaviourError::new(format!(
            "--sweep takes at most {MAX_SWEEP} damping ratios, not {} (each is a full run)",
            dampings.len()
        )));
    }
    dampings
        .iter()
        .map(|&z| {
            let s = RightingSettings {
                mode_damping: Some(z),
                frames_per_stage: 1,
                ..settings.clone()
            };
            let r = self_righting(theory, &s)?;
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
