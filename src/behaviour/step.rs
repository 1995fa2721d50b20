//! Rearing and hunching (paper §3.3.2): a constant generalised force on the first non-zero mode
//! of one field, from rest, beside the analytic step response.

use super::{finite, positive, BehaviourError};
use crate::report::{check_finite, csv_numbers, number, to_json, NonFinite, Report};
use crate::theory::Theory;

/// A constant generalised force on one mode (rearing: first dorsoventral bending mode; hunching:
/// first axial mode), started from rest.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StepResponse {
    /// The behaviour's name (rearing, hunching).
    pub behaviour: String,
    /// Field id.
    pub field: String,
    /// Mode index.
    pub mode: usize,
    /// The force.
    pub force: f64,
    /// The shifted equilibrium Q* = F/ωᵢ².
    pub equilibrium: f64,
    /// The equilibrium shape Q*·vᵢ at each point.
    pub shape: Vec<f64>,
    /// (t, Qᵢ(t)) of the transient.
    pub transient: Vec<(f64, f64)>,
    /// Largest deviation of the transient from the analytic step response.
    pub max_error: f64,
}

/// The analytic response of Q̈ + 2ζωQ̇ + ω²Q = F from rest: Q*(1 − e^{−ζωt}(cos ω_d t +
/// ζω/ω_d sin ω_d t)) (underdamped; the critical and overdamped forms likewise).
pub fn analytic_step(omega: f64, zeta: f64, force: f64, t: f64) -> f64 {
    let q = force / (omega * omega);
    let g = zeta * omega;
    if zeta < 1.0 {
        let wd = omega * (1.0 - zeta * zeta).sqrt();
        q * (1.0 - (-g * t).exp() * ((wd * t).cos() + g / wd * (wd * t).sin()))
    } else if zeta == 1.0 {
        q * (1.0 - (-omega * t).exp() * (1.0 + omega * t))
    } else {
        let r = omega * (zeta * zeta - 1.0).sqrt();
        let (s1, s2) = (-g + r, -g - r);
        q * (1.0 + (s2 * (s1 * t).exp() - s1 * (s2 * t).exp()) / (s1 - s2))
    }
}

/// Apply `force` to the first non-zero mode of field `index` and follow it for `duration`.
/// Rearing is the dorsoventral field, hunching the axial one ([`super::ROLE_NEEDS`]).
pub fn step_response(
    theory: &Theory,
    behaviour: &str,
    index: usize,
    force: f64,
    duration: f64,
) -> Result<StepResponse, BehaviourError> {
    use crate::dynamics::{run, Config, Forcing};
    let force = finite("the force", force)?;
    let duration = positive("the duration", duration)?;
    let f = theory
        .modes
        .get(index)
        .ok_or_else(|| BehaviourError::new(format!("no field {index}")))?;
    let field = f.field.id.as_str();
    if f.spectrum.nullity >= f.modes.len() {
        return Err(BehaviourError::Body(format!(
            "field {field} has no non-zero mode to force"
        )));
    }
    let mode = f.spectrum.nullity;
    let m = &f.modes[mode];
    let (omega, zeta) = (m.frequency, m.damping_ratio);
    let steps = 400u64;
    let config = Config {
        points: theory.points,
        order: theory.order,
        dt: duration / steps as f64,
        steps,
        every: 1,
        temperature: 0.0,
        seed: 0,
        initial: Vec::new(),
        forcing: vec![Forcing {
            field: field.to_string(),
            mode,
            constant: force,
            amplitude: 0.0,
            frequency: 0.0,
            phase: 0.0,
        }],
    };
    let mut transient = Vec::new();
    let mut max_error = 0.0f64;
    run(std::slice::from_ref(f), &config, |s| {
        let q = s.modal[0][mode];
        max_error = max_error.max((q - analytic_step(omega, zeta, force, s.t)).abs());
        transient.push((s.t, q));
        Ok(())
    })?;
    let equilibrium = force / (omega * omega);
    let shapes = f
        .spectrum
        .shapes
        .as_ref()
        .ok_or_else(|| BehaviourError::new("no shapes"))?;
    Ok(StepResponse {
        behaviour: behaviour.to_string(),
        field: field.to_string(),
        mode,
        force,
        equilibrium,
        shape: (0..shapes.nrows())
            .map(|j| equilibrium * shapes[(j, mode)])
            .collect(),
        transient,
        max_error,
    })
}

impl Report for StepResponse {
    fn check(&self) -> Result<(), NonFinite> {
        check_finite(self)
    }

    fn text(&self) -> String {
        let shape: Vec<String> = self.shape.iter().map(|v| format!("{v:.5}")).collect();
        let mut t = format!(
            "{}: force {} on mode {} of {}; equilibrium Q* = F/ω² = {:.9}\n  shifted shape: {}\n  transient agrees with the analytic step response to {:.1e}\n  t, Q(t):\n",
            self.behaviour,
            number(self.force),
            self.mode,
            self.field,
            self.equilibrium,
            shape.join(" "),
            self.max_error
        );
        // Every sample is in the JSON and CSV; the text shows about twenty, plus the peak, so an
        // overshoot between the rows is not lost.
        let peak = self
            .transient
            .iter()
            .enumerate()
            .max_by(|a, b| (a.1 .1).total_cmp(&b.1 .1))
            .map(|(i, _)| i)
            .unwrap_or(0);
        let stride = (self.transient.len() / 20).max(1);
        for (i, (tt, q)) in self.transient.iter().enumerate() {
            if i % stride == 0 || i == peak {
                let mark = if i == peak { "  (peak)" } else { "" };
                t += &format!("  {tt:>10.2}  {q:.9}{mark}\n");
            }
        }
        if let Some(&(tp, qp)) = self.transient.get(peak) {
            if self.equilibrium != 0.0 {
                t += &format!(
                    "  peak Q = {qp:.9} at t = {tp:.2}: {:+.2} % of Q*\n",
                    100.0 * (qp / self.equilibrium - 1.0)
                );
            }
        }
        t
    }

    fn json(&self) -> serde_json::Value {
        to_json(self)
    }

    fn csv(&self) -> Option<String> {
        Some(csv_numbers(
            &["t", "q"],
            self.transient.iter().map(|&(t, q)| vec![t, q]),
        ))
    }
}
