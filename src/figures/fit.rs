//! Figures of a fit: principal components against mode shapes, and the summary panels.

use super::plot::*;
use super::FigureError;

/// The fit's principal components against the mode shapes (Fig. 2A style).
fn fit_shapes(r: &crate::fit::FitReport, width: u32) -> Result<String, FigureError> {
    let shown = r.modes.len().min(4);
    let mut shape_panels = Vec::new();
    let titles: Vec<String> = (0..shown)
        .map(|k| {
            format!(
                "PC {} against mode {} (overlap {:.4})",
                k + 1,
                r.modes[k].index,
                r.mode_overlap[k]
            )
        })
        .collect();
    for (k, title) in titles.iter().enumerate() {
        let mode: Vec<f64> = r.shapes[k].clone();
        // The PC on the model's points, signed to agree with the mode.
        let mut pc: Vec<f64> = (0..mode.len())
            .map(|p| {
                (0..r.shapes.len())
                    .map(|j| r.components[k][j] * r.shapes[j][p])
                    .sum()
            })
            .collect();
        if pc.iter().zip(&mode).map(|(a, b)| a * b).sum::<f64>() < 0.0 {
            pc.iter_mut().for_each(|v| *v = -*v);
        }
        let pts = |v: &[f64]| v.iter().enumerate().map(|(p, x)| (p as f64, *x)).collect();
        shape_panels.push(panel(
            title,
            "point j (0 = tail)",
            "unit-norm shape",
            vec![
                series("mode shape", pts(&mode), Mark::Line),
                series("principal component", pts(&pc), Mark::Dashed),
            ],
        ));
    }
    render(
        width,
        &format!(
            "Principal components of {} frames against the theory's modes",
            r.frames
        ),
        380,
        (2, 2),
        &shape_panels,
    )
}

/// The verdict: each mode's fitted Ωᵢ (95 % error bars) against √λᵢ with the theory's line
/// ω√λ, and its variance against λᵢ on log–log axes with the white floor and the slope −1
/// through the voting modes; voting modes and the others apart.
/// "`what` per `unit`", in the recording's time unit when it was given (`--time-unit`).
fn per(r: &crate::fit::FitReport, what: &str) -> String {
    format!(
        "{what} per {}",
        r.units.time.as_deref().unwrap_or("time unit")
    )
}

fn fit_verdict(r: &crate::fit::FitReport, width: u32) -> Result<String, FigureError> {
    let rad_per = format!("Ωᵢ ({})", per(r, "rad"));
    let fits = &r.modes_fit;
    let fitted: Vec<&crate::fit::ModeSpectralFit> = fits.iter().filter(|m| m.omega > 0.0).collect();
    let split = |votes: bool, f: &dyn Fn(&crate::fit::ModeSpectralFit) -> (f64, f64)| {
        fitted
            .iter()
            .filter(|m| m.votes == votes)
            .map(|m| f(m))
            .collect::<Vec<_>>()
    };
    let d = &r.tests.dispersion;
    let e = &r.tests.equipartition;
    // The fitted exponent, or its symbol when there is none to show.
    let said = |t: &crate::fit::TheoryTest| {
        t.exponent
            .map(|a| format!("{a:.3}").replace('-', "\u{2212}"))
            .unwrap_or_else(|| "a".into())
    };
    let titles = [
        format!("dispersion Ω ∝ λ^{} (expected ½): {}", said(d), d.verdict),
        format!(
            "equipartition σ² ∝ λ^{} (expected −1): {}",
            said(e),
            e.verdict
        ),
    ];
    let sq = |m: &crate::fit::ModeSpectralFit| m.lambda.sqrt();
    let bars: Vec<(f64, f64)> = fitted
        .iter()
        .filter(|m| m.votes)
        .filter_map(|m| {
            let e = 1.96 * m.omega_error?;
            Some([(sq(m), m.omega - e), (sq(m), m.omega + e)])
        })
        .flatten()
        .collect();
    let top = fitted.iter().map(|m| sq(m)).fold(0.0, f64::max);
    let mut dispersion = panel(
        &titles[0],
        "√λᵢ (model's operator)",
        &rad_per,
        vec![
            series(
                "voting modes",
                split(true, &|m| (sq(m), m.omega)),
                Mark::Dots,
            ),
            series("95 % intervals", bars, Mark::Errors),
            series(
                "other modes",
                split(false, &|m| (sq(m), m.omega)),
                Mark::Dots,
            ),
            series(
                format!("theory ω√λ, ω = {:.4}", r.omega),
                curve(0.0, top, 40, |x| r.omega * x),
                Mark::Line,
            ),
        ],
    );
    dispersion.zero = true;
    let log = |m: &crate::fit::ModeSpectralFit| (m.lambda.log10(), m.variance.max(1e-300).log10());
    let voting: Vec<(f64, f64)> = split(true, &log);
    let mut lines = vec![
        series("voting modes", voting.clone(), Mark::Dots),
        series("other modes", split(false, &log), Mark::Dots),
    ];
    let xs: Vec<f64> = fitted.iter().map(|m| m.lambda.log10()).collect();
    let (lo, hi) = (
        xs.iter().copied().fold(f64::INFINITY, f64::min),
        xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    if !voting.is_empty() && lo < hi {
        // Slope −1 through the voting modes' mean.
        let (mx, my) = voting
            .iter()
            .fold((0.0, 0.0), |(a, b), p| (a + p.0, b + p.1));
        let (mx, my) = (mx / voting.len() as f64, my / voting.len() as f64);
        lines.push(series(
            "equipartition, slope −1",
            curve(lo, hi, 2, |x| my - (x - mx)),
            Mark::Line,
        ));
    }
    if let (Some(f), true) = (r.noise_floor.filter(|f| *f > 0.0), lo < hi) {
        lines.push(series(
            "white floor ν",
            vec![(lo, f.log10()), (hi, f.log10())],
            Mark::Dashed,
        ));
    }
    let variance = panel(
        &titles[1],
        "log₁₀ λᵢ",
        "log₁₀ σᵢ² (tracking noise removed)",
        lines,
    );
    render(
        width,
        &format!(
            "Does the theory hold? {} frames; modes voting on the dispersion {}, on equipartition {}",
            r.frames,
            d.modes.len(),
            e.modes.len()
        ),
        440,
        (1, 2),
        &[dispersion, variance],
    )
}

/// The fit's figures (Fig. 2 style): principal components against mode shapes, variance shares,
/// spectra, and measured against fitted modal frequencies.
/// Laid out for `page` (its width; the format is for the writer).
pub fn fit_figures(
    r: &crate::fit::FitReport,
    page: &super::Page,
) -> Result<Vec<(&'static str, String)>, FigureError> {
    let width = page.canvas_width();
    let shown = r.modes.len().min(4);
    let shapes = fit_shapes(r, width)?;
    let (angular, cycles_per) = (
        format!("angular frequency ({})", per(r, "rad")),
        format!("frequency ({})", per(r, "cycles")),
    );
    let idx = |k: usize| r.modes[k].index as f64;
    let share = |v: &[f64]| -> Vec<(f64, f64)> {
        v.iter()
            .enumerate()
            .map(|(k, s)| (idx(k), 100.0 * s))
            .collect()
    };
    let mut shares = panel(
        "variance share of each principal component",
        "mode index i",
        "share (%)",
        vec![
            series("PCA of the data", share(&r.pca_variance_share), Mark::Dots),
            series(
                "equipartition λᵢ⁻¹/Σλⱼ⁻¹",
                share(&r.theory_variance_share),
                Mark::Line,
            ),
        ],
    );
    shares.zero = true;
    let mut freq = panel(
        "modal frequencies",
        "mode index i",
        &angular,
        vec![
            series(
                "measured",
                (0..r.modes.len())
                    .map(|k| (idx(k), r.modes[k].angular_frequency))
                    .collect(),
                Mark::Dots,
            ),
            series(
                format!("ω√λᵢ, ω = {:.4}", r.omega),
                (0..r.modes.len())
                    .map(|k| (idx(k), r.modes[k].theory_angular_frequency))
                    .collect(),
                Mark::Line,
            ),
        ],
    );
    freq.zero = true;
    let ratio = |f: &dyn Fn(&crate::fit::ModeFit) -> f64| -> Vec<(f64, f64)> {
        let first = f(&r.modes[0]);
        (0..r.modes.len())
            .map(|k| (idx(k), f(&r.modes[k]) / first))
            .collect()
    };
    let mut ratios = panel(
        "frequency ratios ωᵢ/ω₁ (independent of ω)",
        "mode index i",
        "ωᵢ / ω of the first mode",
        vec![
            series("measured", ratio(&|m| m.angular_frequency), Mark::Dots),
            series(
                "theory √(λᵢ/λ₁)",
                ratio(&|m| m.eigenvalue.sqrt()),
                Mark::Line,
            ),
        ],
    );
    ratios.zero = true;
    let spectra: Vec<Series> = (0..shown)
        .map(|k| {
            let pts = log_spectrum(&r.frequencies, &r.psd[k]);
            series(format!("mode {}", r.modes[k].index), pts, Mark::Line)
        })
        .collect();
    // A density in frequency: Q² (Q is dimensionless) per cycle per time unit.
    let psd_unit = format!(
        "log₁₀ PSD (Q²·{})",
        r.units.time.as_deref().unwrap_or("time unit")
    );
    let summary = render(
        width,
        &format!(
            "Fit of {} frames: ω = {:.4}, β = {:.4} (paper Fig. 2)",
            r.frames, r.omega, r.beta
        ),
        390,
        (2, 2),
        &[
            shares,
            panel(
                "Welch spectra of the modal coordinates",
                &cycles_per,
                &psd_unit,
                spectra,
            ),
            freq,
            ratios,
        ],
    )?;
    Ok(vec![
        ("fit_shapes.svg", shapes),
        ("fit_summary.svg", summary),
        ("fit_verdict.svg", fit_verdict(r, width)?),
    ])
}
