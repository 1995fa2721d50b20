//! A self-righting run (and its damping sweep) as text, JSON and CSV.

use super::{Righting, SweepPoint};
use crate::report::{check_finite, csv_numbers, to_json, NonFinite, Report};

/// `behave self-righting`: one run and an optional sweep over ζ₁.
#[derive(Debug, Clone)]
pub struct RightingReport {
    /// The run.
    pub righting: Righting,
    /// The sweep (empty when none was asked).
    pub sweep: Vec<SweepPoint>,
}

impl Report for RightingReport {
    fn check(&self) -> Result<(), NonFinite> {
        check_finite(&self.righting)?;
        check_finite(&self.sweep)
    }

    fn text(&self) -> String {
        let r = &self.righting;
        let regime = if (r.damping_ratio - 1.0).abs() <= 1e-9 {
            "critical"
        } else if r.damping_ratio < 1.0 {
            "underdamped"
        } else {
            "overdamped"
        };
        let mut t = format!(
            "Self-righting on N = {}: first torsional mode ω₁ = {:.9} rad/time unit, ζ₁ = {:.6} ({regime})\n\
             \x20 a = v₁(head) = {:.9} (the first mode at the head)\n\
             \x20 stage 1: constant torque Q = −ω₁²θ₀/a = {:.9} rad/time unit² on Θ₁ from θ₀ = {:.6} rad\n\
             \x20   the head follows Eq. 20 to {:.1e}; the mean rotation moves by {:.1e}\n\
             \x20   mouth hooks attach at t = {:.4} time units (head within δ = {} rad)\n\
             \x20 stage 2 ({:?}): torque released; slowest relaxing mode ω = {:.6} rad/time unit, ζ = {:.4}; overshoot {:.4}\n\
             \x20   body aligned within δ at t = {:.4} time units\n\
             \x20 alignment time per segment, time units (0 = tail … {} = head):\n",
            r.points,
            r.frequency,
            r.damping_ratio,
            r.head_coefficient,
            r.torque,
            r.theta0,
            r.head_error,
            r.rotation_before_attachment,
            r.attachment_time,
            r.tolerance,
            r.attachment,
            r.relaxation.0,
            r.relaxation.1,
            r.overshoot,
            r.righting_time,
            r.points - 1,
        );
        for (j, a) in r.alignment_times.iter().enumerate() {
            t += &format!("  {j:>6}  {a:.4}\n");
        }
        if !self.sweep.is_empty() {
            t += "  sweep of ζ₁ (attach and righted in time units, decay rate per time unit):\n      ζ₁   attach   righted  overshoot  decay rate\n";
            for p in &self.sweep {
                t += &format!(
                    "  {:>6.3}  {:>7.3}  {:>8.3}  {:>9.4}  {:>10.6}\n",
                    p.mode_damping, p.attachment_time, p.righting_time, p.overshoot, p.decay_rate,
                );
            }
        }
        t
    }

    fn json(&self) -> serde_json::Value {
        let mut v = to_json(&self.righting);
        if !self.sweep.is_empty() {
            v["sweep"] = to_json(&self.sweep);
        }
        v
    }

    fn csv(&self) -> Option<String> {
        let r = &self.righting;
        let mut header: Vec<String> = ["t", "torque", "mode", "mean_rotation"]
            .iter()
            .map(|h| h.to_string())
            .collect();
        header.extend((0..r.points).map(|j| format!("theta_{j}")));
        Some(csv_numbers(
            &header,
            r.frames.iter().map(|f| {
                let mut row = vec![f.t, f.torque, f.mode, f.mean_rotation];
                row.extend(&f.angles);
                row
            }),
        ))
    }
}
