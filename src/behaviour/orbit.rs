//! Peristalsis and rolling (paper App. I): the minimum-energy orbit of a degenerate pair at
//! fixed momentum M, run undamped with the exact propagators.

use super::{finite, positive, role_fields, BehaviourError, PhaseUnwrap};
use crate::report::{check_finite, csv_numbers, number, to_json, NonFinite, Report};
use crate::theory::Theory;

/// Which degenerate pair to set in motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PairKind {
    /// The first axial cos/sin pair: a travelling compression wave (peristalsis).
    Peristalsis,
    /// The first mediolateral and dorsoventral bending modes: a C-bend rotating about the axis.
    Rolling,
}

/// The minimum-energy orbit of a degenerate pair at momentum M, run with the exact propagators.
#[derive(Debug, Clone, serde::Serialize)]
pub struct PairOrbit {
    /// Which pair.
    pub kind: PairKind,
    /// Points along the body.
    pub points: usize,
    /// Periods run.
    pub periods: f64,
    /// The pair's frequency ω (natural frequency of its modes).
    pub omega: f64,
    /// The momentum M = Q_a·Q̇_b − Q_b·Q̇_a.
    pub momentum: f64,
    /// The orbit's amplitude A* = √(|M|/ω).
    pub amplitude: f64,
    /// Largest relative change of M over the run.
    pub momentum_drift: f64,
    /// Mean rate of the pair's polar angle, measured (equals ω·sign M).
    pub angular_velocity: f64,
    /// Mean rate at which the wave crest (peristalsis) or the bend direction at the head
    /// (rolling) moves, in body lengths or radians per unit time.
    pub body_rate: f64,
    /// (t, Q_a, Q_b) over the first period.
    pub trajectory: Vec<(f64, f64, f64)>,
    /// The body at eight instants of the first period: (t, field a, field b) at each point.
    pub postures: Vec<(f64, Vec<f64>, Vec<f64>)>,
}

/// (field index, mode) of the two members of the pair.
type Member = (usize, usize);

fn members(
    theory: &Theory,
    modes: &[crate::modal::FieldModes],
    kind: PairKind,
) -> Result<(Member, Member), BehaviourError> {
    let model = &theory.model;
    Ok(match kind {
        PairKind::Peristalsis => {
            let x = role_fields(model, "behave peristalsis")?[0];
            let (i, j) = *modes[x].degenerate_pairs.first().ok_or_else(|| {
                BehaviourError::Body(format!(
                    "the axial field {} has no degenerate pair (peristalsis needs a periodic axial field)",
                    model.fields[x].id
                ))
            })?;
            ((x, i), (x, j))
        }
        PairKind::Rolling => {
            let f = role_fields(model, "behave rolling")?;
            let (y, z) = (f[0], f[1]);
            (
                (y, modes[y].spectrum.nullity),
                (z, modes[z].spectrum.nullity),
            )
        }
    })
}

/// Where the bend direction is read: where mode `mode` moves most, from the head down (the
/// head of a free body, the tail of one held at the head).
fn watch_point(field: &crate::modal::FieldModes, mode: usize) -> usize {
    match field.spectrum.shapes.as_ref() {
        Some(v) => (0..v.nrows()).rev().fold(v.nrows() - 1, |best, r| {
            if v[(r, mode)].abs() > v[(best, mode)].abs() * (1.0 + 1e-9) {
                r
            } else {
                best
            }
        }),
        None => 0,
    }
}

/// Run the minimum-energy orbit of `kind` for `periods` periods, undamped.
pub fn pair_orbit(
    theory: &Theory,
    kind: PairKind,
    momentum: f64,
    periods: f64,
) -> Result<PairOrbit, BehaviourError> {
    use crate::dynamics::{run, Config, Initial};
    let (model, points) = (&theory.model, theory.points);
    let m = finite("M", momentum)?;
    if m == 0.0 {
        return Err(BehaviourError::new(
            "M = 0 has no orbit: the pair is at rest",
        ));
    }
    let periods = positive("the number of periods", periods)?;
    // The undamped dynamics: the orbit is a statement about the conservative pair.
    let undamped = theory.undamped();
    let modes = &undamped.modes;
    let (a, b) = members(theory, modes, kind)?;
    let omega = modes[a.0].modes[a.1].frequency;
    if (modes[b.0].modes[b.1].frequency - omega).abs() > 1e-9 * omega {
        return Err(BehaviourError::Body(
            "the first lateral and dorsoventral modes are not degenerate, so they cannot roll"
                .into(),
        ));
    }
    let amplitude = (m.abs() / omega).sqrt();
    let id = |f: usize| model.fields[f].id.clone();
    let period = 2.0 * std::f64::consts::PI / omega;
    let steps_per_period = 200u64;
    let dt = period / steps_per_period as f64;
    let steps = (periods * steps_per_period as f64).ceil() as u64;
    let config = Config {
        points,
        order: theory.order,
        dt,
        steps,
        every: 1,
        temperature: 0.0,
        seed: 0,
        initial: vec![
            Initial {
                field: id(a.0),
                mode: a.1,
                displacement: amplitude,
                velocity: 0.0,
            },
            Initial {
                field: id(b.0),
                mode: b.1,
                displacement: 0.0,
                velocity: m / amplitude,
            },
        ],
        forcing: Vec::new(),
    };
    let n_a = modes[a.0].spectrum.size;
    let (mut drift, mut angle, mut body) = (0.0f64, PhaseUnwrap::default(), PhaseUnwrap::default());
    let mut t_end = 0.0;
    let (mut trajectory, mut postures) = (Vec::new(), Vec::new());
    let mut step = 0u64;
    let watch = watch_point(&modes[a.0], a.1);
    run(modes, &config, |s| {
        let (qa, qb) = (s.modal[a.0][a.1], s.modal[b.0][b.1]);
        if step <= steps_per_period {
            trajectory.push((s.t, qa, qb));
            // Six postures 30° apart over half a period: none is the opposite of another (which
            // would coincide with it for a rolling C-bend), and their order shows the direction.
            let stride = (steps_per_period / 12).max(1);
            if step % stride == 0 && step / stride < 6 {
                postures.push((s.t, s.positions[a.0].clone(), s.positions[b.0].clone()));
            }
        }
        step += 1;
        let (va, vb) = (s.velocity[a.0][a.1], s.velocity[b.0][b.1]);
        drift = drift.max(((qa * vb - qb * va - m) / m).abs());
        let phi = qb.atan2(qa);
        let body_angle = match kind {
            // Crest position: phase of the field's first Fourier component along the body.
            PairKind::Peristalsis => {
                let field = &s.positions[a.0];
                let (mut c, mut sn) = (0.0, 0.0);
                for (j, v) in field.iter().enumerate() {
                    let th = 2.0 * std::f64::consts::PI * j as f64 / n_a as f64;
                    c += v * th.cos();
                    sn += v * th.sin();
                }
                sn.atan2(c)
            }
            // Direction of the bend in the lateral–dorsoventral plane.
            PairKind::Rolling => s.positions[b.0][watch].atan2(s.positions[a.0][watch]),
        };
        angle.push(phi);
        body.push(body_angle);
        t_end = s.t;
        Ok(())
    })?;
    let body_rate = match kind {
        PairKind::Peristalsis => body.total() / (2.0 * std::f64::consts::PI) / t_end,
        PairKind::Rolling => body.total() / t_end,
    };
    Ok(PairOrbit {
        kind,
        points,
        periods,
        omega,
        momentum: m,
        amplitude,
        momentum_drift: drift,
        angular_velocity: angle.total() / t_end,
        body_rate,
        trajectory,
        postures,
    })
}

impl Report for PairOrbit {
    fn check(&self) -> Result<(), NonFinite> {
        check_finite(self)
    }

    fn text(&self) -> String {
        let what = match self.kind {
            PairKind::Peristalsis => format!(
                "the compression wave travels {:.9} body lengths per unit time",
                self.body_rate
            ),
            PairKind::Rolling => format!(
                "the C-bend turns at {:.9} rad per unit time",
                self.body_rate
            ),
        };
        format!(
            "{:?} on N = {}: pair frequency ω = {:.9}, M = {}\n  minimum-energy orbit A* = √(|M|/ω) = {:.9}\n  phase advances at {:.9} (ω·sign M); M conserved to {:.1e} relative over {} periods\n  {what}\n",
            self.kind,
            self.points,
            self.omega,
            number(self.momentum),
            self.amplitude,
            self.angular_velocity,
            self.momentum_drift,
            number(self.periods)
        )
    }

    fn json(&self) -> serde_json::Value {
        to_json(self)
    }

    fn csv(&self) -> Option<String> {
        Some(csv_numbers(
            &["t", "q_a", "q_b"],
            self.trajectory.iter().map(|&(t, a, b)| vec![t, a, b]),
        ))
    }
}
