//! Figures of a fit: principal components against mode shapes, the summary panels, and the
//! verdict. The frequencies are two estimates, each named where drawn: the summary's measured
//! ωᵢ are 2π × each spectrum's peak (or centroid), the verdict's Ωᵢ each spectrum's fitted line.
//! Units: times in the recording's unit, ω in rad per it, β in it squared, amplitudes in point
//! spacings.

use super::plot::*;
use super::script::sup;
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

/// "`what` per `unit`", in the recording's time unit when it was given (`--time-unit`).
fn per(r: &crate::fit::FitReport, what: &str) -> String {
    format!("{what} per {}", time(r))
}

/// The recording's time unit, or "time unit" when it was not given.
fn time(r: &crate::fit::FitReport) -> &str {
    r.units.time.as_deref().unwrap_or("time unit")
}

/// The palette places of the verdict's marks, the same in both panels (one meaning, one
/// colour): the modes that vote on the panel's test, their intervals, the others, the theory.
const VOTING: usize = 0;
const OTHER: usize = 7;
const THEORY: usize = 3;
const FLOOR: usize = 4;

/// A test's fitted exponent typeset as a power of λ (`λ` with `0.079` raised), or `a` when
/// there is none to show.
fn power(t: &crate::fit::TheoryTest) -> String {
    let a = (t.exponent)
        .map(|a| format!("{a:.3}").replace('-', "\u{2212}"))
        .unwrap_or_else(|| "a".into());
    format!("λ{}", sup(&a))
}

/// The verdict: each mode's Ωᵢ (its spectrum's fitted line, with 95 % error bars) against √λᵢ
/// with the theory's line ω√λ, and its variance against λᵢ on log–log axes with the white
/// floor and the slope −1 through the modes voting on equipartition; in each panel the modes
/// that vote on its test apart from the others, and a point far off the rest marked off scale.
fn fit_verdict(r: &crate::fit::FitReport, width: u32) -> Result<String, FigureError> {
    use crate::fit::ModeSpectralFit;
    // Fitted: each spectrum's line, not the summary's 2π × its peak.
    let rad_per = format!("fitted Ωᵢ ({})", per(r, "rad"));
    let fitted: Vec<&ModeSpectralFit> = r.modes_fit.iter().filter(|m| m.omega > 0.0).collect();
    let (d, e) = (&r.tests.dispersion, &r.tests.equipartition);
    // The modes voting on a test, or the others, through `f`.
    let split = |voters: &[usize], votes: bool, f: &dyn Fn(&ModeSpectralFit) -> (f64, f64)| {
        (fitted.iter())
            .filter(|m| voters.contains(&m.mode) == votes)
            .map(|m| f(m))
            .collect::<Vec<_>>()
    };
    let titles = [
        format!("dispersion Ω ∝ {} (expected ½): {}", power(d), d.verdict),
        format!(
            "equipartition σ² ∝ {} (expected −1): {}",
            power(e),
            e.verdict
        ),
    ];
    let sq = |m: &ModeSpectralFit| m.lambda.sqrt();
    let bars: Vec<(f64, f64)> = (fitted.iter())
        .filter(|m| d.modes.contains(&m.mode))
        .filter_map(|m| {
            let e = 1.96 * m.omega_error?;
            Some([(sq(m), m.omega - e), (sq(m), m.omega + e)])
        })
        .flatten()
        .collect();
    let top = fitted.iter().map(|m| sq(m)).fold(0.0, f64::max);
    let omega = |m: &ModeSpectralFit| (sq(m), m.omega);
    let mut dispersion = panel(
        &titles[0],
        "√λᵢ (model's operator)",
        &rad_per,
        vec![
            series("voting modes", split(&d.modes, true, &omega), Mark::Dots).hue(VOTING),
            series("95 % intervals", bars, Mark::Errors).hue(VOTING),
            series("other modes", split(&d.modes, false, &omega), Mark::Dots).hue(OTHER),
            series(
                // ω in the axis' unit (√λ has none); the figure's title is the summary's.
                format!("theory ω√λ, ω = {:.4}", r.omega),
                curve(0.0, top, 40, |x| r.omega * x),
                Mark::Line,
            )
            .hue(THEORY),
        ],
    );
    dispersion.zero = true;
    dispersion.outliers = true;
    let log = |m: &ModeSpectralFit| (m.lambda.log10(), m.variance.max(1e-300).log10());
    let voting: Vec<(f64, f64)> = split(&e.modes, true, &log);
    let mut lines = vec![
        series("voting modes", voting.clone(), Mark::Dots).hue(VOTING),
        series("other modes", split(&e.modes, false, &log), Mark::Dots).hue(OTHER),
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
        lines.push(
            series(
                "equipartition, slope −1",
                curve(lo, hi, 2, |x| my - (x - mx)),
                Mark::Line,
            )
            .hue(THEORY),
        );
    }
    if let (Some(f), true) = (r.noise_floor.filter(|f| *f > 0.0), lo < hi) {
        lines.push(
            series(
                "white floor ν",
                vec![(lo, f.log10()), (hi, f.log10())],
                Mark::Dashed,
            )
            .hue(FLOOR),
        );
    }
    let mut variance = panel(
        &titles[1],
        "log₁₀ λᵢ",
        "log₁₀ σᵢ², noise removed (point spacings²)",
        lines,
    );
    variance.outliers = true;
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

/// Which spectral estimate the measured ωᵢ are (2π × each spectrum's peak or its centroid):
/// `fit --estimator` chose it.
fn estimate(r: &crate::fit::FitReport) -> &'static str {
    r.estimator.name()
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
    // The measured ωᵢ are not the verdict's Ωᵢ (each spectrum's fitted line): the title says
    // which estimate they are.
    let freq_title = format!("modal frequencies: 2π × each spectrum's {}", estimate(r));
    let mut freq = panel(
        &freq_title,
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
                // ω's unit is the axis' and the title's.
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
    // A density in frequency: the amplitude (in point spacings) squared per cycle per time unit.
    let psd_unit = format!("log₁₀ PSD (point spacings²·{})", time(r));
    let summary = render(
        width,
        &format!(
            "Fit of {} frames: ω = {:.4} {}, β = {:.4} {}² (paper Fig. 2)",
            r.frames,
            r.omega,
            per(r, "rad"),
            r.beta,
            time(r)
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
