//! Axial–transverse resonance (App. D): the Mathieu equation `Φ̈ + λ²[1 − 2ε cos ωt]Φ = 0`.
//! The monodromy matrix M over one period 2π/ω (RK4 on the two fundamental solutions) has
//! det M = 1; the motion is stable when |tr M| ≤ 2. The first instability tongue sits at
//! ω = 2λ, between ω/λ = 2√(1 − ε) and 2√(1 + ε) for small ε.

use super::{finite, positive, rk4_step, BehaviourError};
use crate::report::{check_finite, csv_table, number, to_json, NonFinite, Report};

/// The monodromy matrix of `Φ̈ + λ²[1 − 2ε cos ωt]Φ = 0` over one period 2π/ω.
pub fn mathieu_monodromy(lambda: f64, epsilon: f64, omega: f64) -> [[f64; 2]; 2] {
    let period = 2.0 * std::f64::consts::PI / omega;
    // 400 RK4 steps per half oscillation of the unforced motion keep tr M to ~1e-10.
    let steps = 400 * (2.0 * lambda / omega).ceil().max(1.0) as usize;
    let h = period / steps as f64;
    let f = |t: f64, y: [f64; 2]| {
        [
            y[1],
            -lambda * lambda * (1.0 - 2.0 * epsilon * (omega * t).cos()) * y[0],
        ]
    };
    let mut cols = [[1.0, 0.0], [0.0, 1.0]];
    for col in &mut cols {
        let mut y = *col;
        for n in 0..steps {
            y = rk4_step(f, n as f64 * h, y, h);
        }
        *col = y;
    }
    // Columns are the images of (1, 0) and (0, 1): M = [[a, b], [c, d]] row-major.
    [[cols[0][0], cols[1][0]], [cols[0][1], cols[1][1]]]
}

/// One point of the stability chart.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FloquetPoint {
    /// ω/λ.
    pub frequency_ratio: f64,
    /// ε.
    pub epsilon: f64,
    /// tr M.
    pub trace: f64,
    /// The larger Floquet multiplier modulus.
    pub multiplier: f64,
    /// |tr M| ≤ 2.
    pub stable: bool,
}

/// Floquet analysis at one point.
pub fn floquet(lambda: f64, epsilon: f64, omega: f64) -> Result<FloquetPoint, BehaviourError> {
    let lambda = positive("λ", lambda)?;
    let epsilon = finite("ε", epsilon)?;
    let omega = positive("ω", omega)?;
    let m = mathieu_monodromy(lambda, epsilon, omega);
    let trace = m[0][0] + m[1][1];
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let disc = trace * trace / 4.0 - det;
    let multiplier = if disc > 0.0 {
        (trace.abs() / 2.0 + disc.sqrt()).max((trace.abs() / 2.0 - disc.sqrt()).abs())
    } else {
        det.abs().sqrt()
    };
    Ok(FloquetPoint {
        frequency_ratio: omega / lambda,
        epsilon,
        trace,
        multiplier,
        stable: trace.abs() <= 2.0 + 1e-9,
    })
}

/// A stability chart: the grid and its points, ε-major (row j holds ε_j at every ω/λ).
#[derive(Debug, Clone, PartialEq)]
pub struct StabilityChart {
    /// λ.
    pub lambda: f64,
    /// Lowest and highest ω/λ.
    pub ratio: (f64, f64),
    /// Grid points along ω/λ.
    pub columns: usize,
    /// The points.
    pub points: Vec<FloquetPoint>,
}

impl Report for StabilityChart {
    fn check(&self) -> Result<(), NonFinite> {
        check_finite(&self.points)
    }

    fn text(&self) -> String {
        let mut t = format!(
            "Mathieu stability chart, λ = {}: '#' unstable (|tr M| > 2), '.' stable; ε up, ω/λ across\n",
            self.lambda
        );
        for row in self.points.chunks(self.columns).rev() {
            let cells: String = row
                .iter()
                .map(|p| if p.stable { '.' } else { '#' })
                .collect();
            t += &format!("ε = {:<6.3} {cells}\n", row[0].epsilon);
        }
        t += &format!(
            "           ω/λ from {} to {}; the first tongue is at ω/λ = 2\n",
            self.ratio.0, self.ratio.1
        );
        t
    }

    fn json(&self) -> serde_json::Value {
        to_json(&self.points)
    }

    fn csv(&self) -> Option<String> {
        Some(csv_table(
            &[
                "frequency_ratio",
                "epsilon",
                "trace",
                "multiplier",
                "stable",
            ],
            self.points.iter().map(|p| {
                vec![
                    p.frequency_ratio.to_string(),
                    p.epsilon.to_string(),
                    p.trace.to_string(),
                    p.multiplier.to_string(),
                    p.stable.to_string(),
                ]
            }),
        ))
    }
}

/// The chart over ω/λ ∈ [lo, hi] and ε ∈ [0, ε_max] on a (columns, rows) grid.
pub fn chart(
    lambda: f64,
    ratio: (f64, f64),
    epsilon_max: f64,
    grid: (usize, usize),
) -> Result<StabilityChart, BehaviourError> {
    Ok(StabilityChart {
        lambda,
        ratio,
        columns: grid.0,
        points: stability_chart(lambda, ratio, epsilon_max, grid)?,
    })
}

/// The most RK4 steps a stability chart may take (about ten seconds).
pub const MAX_CHART_STEPS: f64 = 5e8;

/// The stability chart over ω/λ ∈ [lo, hi] (`n` points) and ε ∈ [0, ε_max] (`m` points).
pub fn stability_chart(
    lambda: f64,
    ratio: (f64, f64),
    epsilon_max: f64,
    grid: (usize, usize),
) -> Result<Vec<FloquetPoint>, BehaviourError> {
    let (lo, hi) = (
        positive("the lowest ω/λ", ratio.0)?,
        positive("the highest ω/λ", ratio.1)?,
    );
    if lo >= hi {
        return Err(BehaviourError::new(format!(
            "the ω/λ range {}…{} is empty",
            number(lo),
            number(hi)
        )));
    }
    let emax = finite("ε_max", epsilon_max)?;
    let (n, m) = grid;
    if !(2..=2000).contains(&n) || !(2..=2000).contains(&m) {
        return Err(BehaviourError::new(
            "the grid needs 2 to 2000 points each way",
        ));
    }
    // Scale-free in λ (the chart depends on ω/λ and ε), but λ² must not overflow.
    if !(1e-100..=1e100).contains(&positive("λ", lambda)?) {
        return Err(BehaviourError::new(format!(
            "λ = {lambda:e} is outside 1e-100…1e100 (the chart depends only on ω/λ and ε)"
        )));
    }
    if emax.abs() > 1e6 {
        return Err(BehaviourError::new(format!(
            "ε_max = {emax:e} is beyond 10⁶: the solutions overflow within one period"
        )));
    }
    // One monodromy costs 2·400·⌈2λ/ω⌉ RK4 steps: budget the whole chart up front.
    let steps: f64 = (0..n)
        .map(|i| {
            let r = lo + (hi - lo) * i as f64 / (n - 1) as f64;
            800.0 * (2.0 / r).ceil().max(1.0)
        })
        .sum::<f64>()
        * m as f64;
    if steps > MAX_CHART_STEPS {
        return Err(BehaviourError::new(format!(
            "the chart needs {steps:.1e} RK4 steps (ω/λ down to {lo:e}), over the budget of {MAX_CHART_STEPS:.0e}: raise --ratio-min or use fewer --columns/--rows"
        )));
    }
    let mut out = Vec::with_capacity(n * m);
    for j in 0..m {
        let eps = emax * j as f64 / (m - 1) as f64;
        for i in 0..n {
            let r = lo + (hi - lo) * i as f64 / (n - 1) as f64;
            out.push(floquet(lambda, eps, r * lambda)?);
        }
    }
    Ok(out)
}
