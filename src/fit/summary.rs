//! From accumulated moments to a report: PCA, overlaps, shares, spectral peaks, and the ω and
//! β fits.

use super::project::Projector;
use super::stats;
use crate::report::number;

use super::{
    Continuum, Estimator, FitError, FitReport, FitSettings, ModeFit, Recording, Subspace, Units,
};

/// A fitted mode whose measured frequency sits within 3 frequency bins of zero cannot be told
/// from its neighbours by a window this short: ω and κ then move with `--window`. Said, never
/// silent.
fn resolution_warnings(fitted: &[ModeFit], frequencies: &[f64], window: usize) -> Vec<String> {
    let df = frequencies.get(1).copied().unwrap_or(0.0);
    let low: Vec<String> = fitted
        .iter()
        .filter(|m| df > 0.0 && m.angular_frequency / (2.0 * std::f64::consts::PI) < 3.0 * df)
        .map(|m| m.index.to_string())
        .collect();
    if low.is_empty() {
        return Vec::new();
    }
    vec![format!(
        "mode(s) {} peak within 3 frequency bins of zero (a bin is {} per time unit with a {window}-frame window): the window cannot resolve them, so ω and κ move with --window; use a longer --window",
        low.join(", "),
        crate::report::fixed(df, 6)
    )]
}

/// The continuum root βᵢL (body length 1) of the `i`-th non-zero mode (i = 1, 2, …) of the
/// projector's field: the beam's or string's roots for its ends, 2π⌈i/2⌉ around a ring.
fn continuum_root(proj: &Projector, i: usize) -> Option<f64> {
    match proj.boundary {
        crate::boundary::Boundary::Periodic if proj.stencil == 1 => {
            Some(2.0 * std::f64::consts::PI * i.div_ceil(2) as f64)
        }
        _ => crate::modal::continuum_beta(proj.stencil, proj.boundary, i),
    }
}

/// The theory's constant in body units from the fitted modes' measured frequencies: the least
/// squares C of mᵢ = C·(βᵢL)ᵏ over the same modes as ω (k = 2: κ of a beam; k = 1: the wave
/// speed c), so that the number does not depend on the model points N (ω, the N-point
/// constant, scales as (N − 1)ᵏ). `None` for a field without continuum roots.
fn continuum(proj: &Projector, fitted: &[ModeFit]) -> Option<Continuum> {
    let roots: Vec<f64> = fitted
        .iter()
        .map(|m| continuum_root(proj, m.index - proj.first_mode + 1))
        .collect::<Option<_>>()?;
    let k = proj.stencil as i32;
    let (num, den) = fitted
        .iter()
        .zip(&roots)
        .fold((0.0, 0.0), |(n, d), (m, b)| {
            (n + m.angular_frequency * b.powi(k), d + b.powi(2 * k))
        });
    let constant = num / den;
    constant.is_finite().then(|| Continuum {
        name: if k == 2 { "kappa" } else { "c" },
        constant,
        interval: None,
        unit: String::new(),
        roots,
        body_length: 0.0,
        in_data_units: 0.0,
    })
}

/// Peak (with parabolic refinement) and centroid of a one-sided spectrum, above zero frequency.
pub fn spectral_peak_and_centroid(freqs: &[f64], psd: &[f64]) -> (f64, f64) {
    let df = if freqs.len() > 1 {
        freqs[1] - freqs[0]
    } else {
        0.0
    };
    let k = (1..psd.len())
        .max_by(|&a, &b| psd[a].total_cmp(&psd[b]))
        .unwrap_or(0);
    let mut peak = freqs.get(k).copied().unwrap_or(0.0);
    if k >= 1 && k + 1 < psd.len() {
        // The vertex of the parabola through the log powers: a Hann-windowed peak is close to a
        // Gaussian there, so this is nearly unbiased where the plain parabola is off by up to a
        // tenth of a bin.
        let (a, b, c) = (psd[k - 1].ln(), psd[k].ln(), psd[k + 1].ln());
        let den = a - 2.0 * b + c;
        // Refine only a true local maximum; the vertex then lies within half a bin.
        if b >= a && b >= c && den < 0.0 && den.is_finite() {
            peak += (0.5 * (a - c) / den).clamp(-0.5, 0.5) * df;
        }
    }
    let (num, den) = freqs
        .iter()
        .zip(psd)
        .skip(1)
        .fold((0.0, 0.0), |(n, d), (f, p)| (n + f * p, d + p));
    (peak, if den > 0.0 { num / den } else { 0.0 })
}

/// PCA, overlaps, shares, frequencies and the ω and β fits from the accumulated moments.
pub(super) fn summarise(
    proj: &Projector,
    settings: &FitSettings,
    cov: Vec<Vec<f64>>,
    interval: f64,
    spectra: stats::Spectra,
) -> Result<FitReport, FitError> {
    let invalid = |s: String| FitError::Invalid(s);
    // No eigen-solve or SVD on non-finite moments (nalgebra's SVD panics on NaN).
    if cov
        .iter()
        .flatten()
        .chain(spectra.psd.iter().flatten())
        .any(|v| !v.is_finite())
    {
        return Err(invalid(
            "the modal coordinates' moments overflow: rescale the data".into(),
        ));
    }
    let stats::Spectra {
        window: used_window,
        segments,
        frequencies,
        psd,
    } = spectra;
    let lambdas = &proj.eigenvalues;
    let (m, first_mode) = (lambdas.len(), proj.first_mode);

    // PCA in the body metric: eigen of cov(Q), descending.
    let (pca_share, components) = descending_eigen(&cov);
    let (angle_share, _) = descending_eigen(&angle_covariance(&proj.design, &cov));
    let inv: f64 = lambdas.iter().map(|l| 1.0 / l).sum();
    let theory_share: Vec<f64> = lambdas.iter().map(|l| 1.0 / l / inv).collect();
    let overlap: Vec<Vec<f64>> = components
        .iter()
        .map(|c| c.iter().map(|x| x.abs()).collect())
        .collect();
    let mode_overlap = pair_overlaps(lambdas, &components);
    let subspace = subspaces(&cov, &pca_share, &components);
    let mut modes: Vec<ModeFit> = (0..m)
        .map(|j| {
            let (peak, centroid) = spectral_peak_and_centroid(&frequencies, &psd[j]);
            let f = match settings.estimator {
                Estimator::Peak => peak,
                Estimator::Centroid => centroid,
            };
            ModeFit {
                index: first_mode + j,
                eigenvalue: lambdas[j],
                variance: cov[j][j],
                peak_frequency: peak,
                centroid_frequency: centroid,
                angular_frequency: 2.0 * std::f64::consts::PI * f,
                theory_angular_frequency: 0.0,
            }
        })
        .collect();
    let used = settings.fit_modes.min(m);
    let fitted = &modes[..used];
    let omega = settings.omega.unwrap_or_else(|| {
        fitted
            .iter()
            .map(|x| x.angular_frequency * x.eigenvalue.sqrt())
            .sum::<f64>()
            / fitted.iter().map(|x| x.eigenvalue).sum::<f64>()
    });
    if !(omega.is_finite() && omega > 0.0) {
        return Err(invalid(
            "no frequency could be measured (flat spectra): give --omega".into(),
        ));
    }
    let spread: f64 = fitted
        .iter()
        .map(|x| omega * omega * x.eigenvalue * x.variance)
        .sum();
    if spread <= 0.0 {
        return Err(invalid(
            "the postures do not vary: no temperature can be fitted".into(),
        ));
    }
    let beta = used as f64 / spread;
    // ω·dt and β·ω² are what the data measure; outside the floats they cannot be reported.
    if !(beta.is_finite() && beta > 0.0 && spread.is_finite() && (omega * omega).is_finite()) {
        return Err(invalid(format!(
            "the fitted scales are out of range (ω = {}, β = {}): rescale the time column or --fps",
            number(omega),
            number(beta)
        )));
    }
    for x in &mut modes {
        x.theory_angular_frequency = omega * x.eigenvalue.sqrt();
    }
    let continuum = continuum(proj, &modes[..used]);
    let warnings = resolution_warnings(&modes[..used], &frequencies, used_window);
    Ok(FitReport {
        continuum,
        frames: 0,
        recording: Recording::default(),
        warnings,
        animals: Vec::new(),
        units: Units::default(),
        spacing: 0.0,
        subspace,
        intervals: None,
        onward: Vec::new(),
        points: proj.input_points,
        pca_variance_share: pca_share,
        theory_variance_share: theory_share,
        overlap,
        omega,
        beta,
        kind: settings.kind,
        field: proj.field.clone(),
        scale: proj.scale.clone(),
        model_points: proj.points,
        sample_interval: interval,
        welch: (used_window, segments),
        mode_overlap,
        angle_pca_variance_share: angle_share,
        modes,
        fitted_modes: used,
        frequencies,
        psd,
        components,
        shapes: proj.shapes.clone(),
    })
}

/// Plain angle-space covariance (S V) cov(Q) (S V)ᵀ over the observations, `design[i]` = S vᵢ.
fn angle_covariance(design: &[Vec<f64>], cov: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let m = design.len();
    let obs = design[0].len();
    // Bᵀ(C·B) by faer's matrix products: O(N³) once, not the O(N⁴) of the entry-wise sum.
    let b = faer::Mat::<f64>::from_fn(m, obs, |i, a| design[i][a]);
    let c = faer::Mat::<f64>::from_fn(m, m, |i, j| cov[i][j]);
    let cb = &c * &b;
    let out = b.transpose() * &cb;
    (0..obs)
        .map(|a| (0..obs).map(|b| out[(a, b)]).collect())
        .collect()
}

/// The first k principal components against the first k modes, for k up to 6: the smallest
/// singular value of the k × k block of components over modes is the cosine of the largest
/// principal angle; the captured variances are the modes' variances and the components'
/// shares, summed.
fn subspaces(cov: &[Vec<f64>], pca_share: &[f64], components: &[Vec<f64>]) -> Vec<Subspace> {
    let m = cov.len();
    let trace: f64 = (0..m).map(|j| cov[j][j]).sum();
    (1..=m.min(6))
        .map(|k| {
            let block = nalgebra::DMatrix::from_fn(k, k, |i, j| components[i][j]);
            let cosine = block
                .singular_values()
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min)
                .clamp(0.0, 1.0);
            let modes: f64 = (0..k).map(|j| cov[j][j]).sum();
            Subspace {
                k,
                cosine,
                modes_capture: if trace > 0.0 { modes / trace } else { 0.0 },
                components_capture: pca_share[..k].iter().sum(),
            }
        })
        .collect()
}

/// Each principal component's overlap with its mode, or with the plane of its degenerate pair.
fn pair_overlaps(lambdas: &[f64], components: &[Vec<f64>]) -> Vec<f64> {
    let m = lambdas.len();
    let degenerate = |i: usize, j: usize| (lambdas[i] - lambdas[j]).abs() <= 1e-9 * lambdas[i];
    components
        .iter()
        .enumerate()
        .map(|(k, c)| {
            (0..m)
                .filter(|&j| degenerate(k, j))
                .map(|j| c[j] * c[j])
                .sum::<f64>()
                .sqrt()
        })
        .collect()
}

/// Eigenvalue shares (descending) and eigenvectors (rows, same order) of a symmetric matrix.
fn descending_eigen(a: &[Vec<f64>]) -> (Vec<f64>, Vec<Vec<f64>>) {
    let (values, vectors) = crate::behaviour::principal_components(a)
        .unwrap_or_else(|_| (vec![0.0; a.len()], vec![vec![0.0; a.len()]; a.len()]));
    let total: f64 = values.iter().map(|v| v.max(0.0)).sum();
    let shares = values
        .iter()
        .map(|v| if total > 0.0 { v.max(0.0) / total } else { 0.0 })
        .collect();
    (shares, vectors)
}
