//! Forward/backward asymmetry (App. C): a degenerate axial pair with the cubic dissipative
//! self-interaction `Ẍᵢ + ω²Xᵢ = c·φ̇·Xᵢ`, `φ̇ = X₁Ẋ₂ − X₂Ẋ₁`. The travelling wave
//! `X₁ = A cos ω_s t, X₂ = A sin ω_s t` has `φ̇ = A²ω_s`, hence `ω_s² + cA²ω_s − ω² = 0`. The paper
//! prints `cAω_s` (Eq. 94–96), which agrees only at A = 1; we solve the correct equation and
//! confirm both roots by integrating the nonlinear pair (RK4) and measuring the phase advance.

use super::{finite, positive, rk4_step, BehaviourError, PhaseUnwrap};
use crate::report::{check_finite, csv_numbers, number, to_json, NonFinite, Report};

/// Forward and backward frequencies of the self-interacting axial pair.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Asymmetry {
    /// The coupling c.
    pub coupling: f64,
    /// The wave amplitude A.
    pub amplitude: f64,
    /// The free-field frequency ω.
    pub omega: f64,
    /// The positive root of ω_s² + cA²ω_s − ω² = 0.
    pub forward: f64,
    /// The negative root.
    pub backward: f64,
    /// |backward / forward|.
    pub ratio: f64,
    /// The forward frequency measured by integrating the nonlinear pair.
    pub simulated_forward: f64,
    /// The backward frequency measured likewise.
    pub simulated_backward: f64,
}

/// Integrate `Ẍᵢ + ω²Xᵢ = c·φ̇·Xᵢ` from the travelling-wave state of frequency `ws` and return
/// the mean phase velocity of (X₁, X₂) over `periods` periods.
pub fn simulate_pair(c: f64, a: f64, omega: f64, ws: f64, periods: f64) -> f64 {
    let rhs = |x: [f64; 4]| {
        let (x1, x2, v1, v2) = (x[0], x[1], x[2], x[3]);
        let phi_dot = x1 * v2 - x2 * v1;
        [
            v1,
            v2,
            -omega * omega * x1 + c * phi_dot * x1,
            -omega * omega * x2 + c * phi_dot * x2,
        ]
    };
    let t_end = periods * 2.0 * std::f64::consts::PI / ws.abs();
    // 2000 steps per period of the fastest motion: the wave, the free oscillator, or the
    // coupling rate cA²ω_s. Beyond 2·10⁷ steps the pair is too stiff to check: NaN.
    let fast = (omega.max((c * a * a * ws).abs()) / ws.abs()).max(1.0);
    let steps = (periods * 2000.0 * fast).ceil();
    if steps.is_nan() || steps > 2e7 {
        return f64::NAN;
    }
    let steps = steps as usize;
    let h = t_end / steps as f64;
    let mut x = [a, 0.0, 0.0, a * ws];
    // The polar angle of (X₁, X₂), unwrapped.
    let mut angle = PhaseUnwrap::default();
    angle.push(x[1].atan2(x[0]));
    for n in 0..steps {
        x = rk4_step(|_, x| rhs(x), n as f64 * h, x, h);
        angle.push(x[1].atan2(x[0]));
    }
    angle.total() / t_end
}

/// The forward (positive) and backward (negative) roots of ω_s² + cA²ω_s − ω² = 0, computed
/// stably (their product is −ω²). `omega` must be positive.
pub fn asymmetry_roots(c: f64, a: f64, omega: f64) -> (f64, f64) {
    let b = c * a * a;
    let root = (b * b + 4.0 * omega * omega).sqrt();
    let big = if b >= 0.0 {
        -(b + root) / 2.0
    } else {
        (root - b) / 2.0
    };
    let small = -omega * omega / big;
    if big > 0.0 {
        (big, small)
    } else {
        (small, big)
    }
}

/// The asymmetry for coupling `c`, amplitude `a` and free frequency `omega`.
pub fn asymmetry(c: f64, a: f64, omega: f64) -> Result<Asymmetry, BehaviourError> {
    let c = finite("the coupling", c)?;
    let a = positive("the amplitude", a)?;
    let omega = positive("the frequency", omega)?;
    let (forward, backward) = asymmetry_roots(c, a, omega);
    let (simulated_forward, simulated_backward) = (
        simulate_pair(c, a, omega, forward, 20.0),
        simulate_pair(c, a, omega, backward, 20.0),
    );
    if !(simulated_forward.is_finite() && simulated_backward.is_finite()) {
        return Err(BehaviourError::new(format!(
            "cA² = {} against ω = {}: the roots differ by {:.1e}×, too stiff to confirm by integrating the pair",
            number(c * a * a),
            number(omega),
            (backward / forward).abs()
        )));
    }
    Ok(Asymmetry {
        coupling: c,
        amplitude: a,
        omega,
        forward,
        backward,
        ratio: (backward / forward).abs(),
        simulated_forward,
        simulated_backward,
    })
}

impl Report for Asymmetry {
    fn check(&self) -> Result<(), NonFinite> {
        check_finite(self)
    }

    fn text(&self) -> String {
        format!(
            "ω_s² + cA²ω_s − ω² = 0 with c = {}, A = {}, ω = {}\n  forward  ω₊ = {:.12}  (simulated {:.12})\n  backward ω₋ = {:.12}  (simulated {:.12})\n  |ω₋/ω₊| = {:.12}\n",
            number(self.coupling),
            number(self.amplitude),
            number(self.omega),
            self.forward,
            self.simulated_forward,
            self.backward,
            self.simulated_backward,
            self.ratio
        )
    }

    fn json(&self) -> serde_json::Value {
        to_json(self)
    }

    fn csv(&self) -> Option<String> {
        Some(csv_numbers(
            &[
                "forward",
                "backward",
                "ratio",
                "simulated_forward",
                "simulated_backward",
            ],
            [vec![
                self.forward,
                self.backward,
                self.ratio,
                self.simulated_forward,
                self.simulated_backward,
            ]],
        ))
    }
}
