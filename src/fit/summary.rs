//! From accumulated moments to a report: PCA, overlaps, shares, spectral peaks, and the ω and
//! β fits.

use super::alias::{mark_aliases, unfold, UNFOLDED};
use super::stats::Spectra;
use super::timedomain::{refit, Exact, Span};
use super::verdict::{self, FittedBy, ModeSpectralFit, TheoryTests};
use super::window::{
    choose_window, fit_modes_spectra, lowest_frequency, spectral_peak_and_centroid,
};
use super::{Continuum, Estimator, FitError, FitReport, FitSettings, ModeFit, Recording, Subspace};
use crate::recording::{Projector, Units};
use crate::report::fixed;

/// How much of a fit to make: everything, or only the constants (ω, β, κ from the first
/// `fit_modes` modes) for an animal alone or a bootstrap resample, warm-started from the
/// pooled fit's window and per-mode parameters when there is one. Either way the modes
/// `timedomain` names are fitted again on the series given (the animals' or the resample's):
/// one estimator in every scope.
#[derive(Clone, Copy)]
pub(super) enum Scope<'a> {
    /// Every mode fitted, every test made.
    Full(&'a [Span<'a>]),
    /// Only the constants.
    Constants(Option<&'a FitReport>, Exact<'a>),
}

/// What the report says of where its moments came from.
pub(super) struct Origin {
    /// Usable frames.
    pub frames: usize,
    /// Mean spacing of the tracked points, in the data's length unit.
    pub spacing: f64,
    /// The recording's counts (empty for a resample).
    pub recording: Recording,
    /// The data's units (none for a resample).
    pub units: Units,
}

impl Origin {
    /// The continuum constant in the data's units: κ in body length² per time unit, c in
    /// body lengths per time unit.
    fn in_units(&self, mut c: Continuum, model_points: usize) -> Continuum {
        let time = self.units.time.as_deref().unwrap_or("time unit");
        c.body_length = self.spacing * (model_points - 1) as f64;
        let (power, unit) = if c.name == "kappa" {
            (2, format!("body length²/{time}"))
        } else {
            (1, format!("body lengths/{time}"))
        };
        c.in_data_units = c.constant * c.body_length.powi(power);
        c.unit = unit;
        c
    }

    /// Warnings that follow from the recording rather than from the modes.
    fn warnings(
        &self,
        welch: (usize, usize),
        proj: &Projector,
        ring: Option<usize>,
    ) -> Vec<String> {
        let mut out = Vec::new();
        if welch.1 < 4 {
            out.push(format!(
                "the spectra average {} Welch segment(s) of {} frames: the peak frequencies, and ω with them, are rough (use a shorter --window or longer runs)",
                welch.1, welch.0
            ));
        }
        if proj.kind == crate::recording::InputKind::Midline && proj.input_points < proj.points {
            out.push(format!(
                "the model's {} points are more than the {} tracked: the midlines are interpolated onto them (`--points {}` fits the tracked points alone)",
                proj.points, proj.input_points, proj.input_points
            ));
        }
        if let Some(r) = ring.filter(|&r| r > proj.input_points) {
            out.push(format!(
                "only {} of {r} ring segments were measured: under equipartition every mode carries the same strain variance, so the unresolved modes alias into the fitted ones; ω and β are reliable for a dominant rhythm, not for thermal data",
                proj.input_points
            ));
        }
        out
    }
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

/// The theory's constant in body units: the weighted least-squares C of Ωᵢ = C·(βᵢL)ᵏ over
/// the modes `used` (`(mode index, Ω, σ_Ω)`; k = 2: κ of a beam; k = 1: the wave speed c), so
/// that the number does not depend on the model points N (ω, the N-point constant, scales as
/// (N − 1)ᵏ). Its 95 % interval comes from the modes' errors, widened by the Birge ratio when
/// they scatter more than their errors say. `None` for a field without continuum roots.
fn continuum(proj: &Projector, used: &[(usize, f64, f64)]) -> Option<Continuum> {
    let roots: Vec<f64> = used
        .iter()
        .map(|&(i, _, _)| continuum_root(proj, i - proj.first_mode + 1))
        .collect::<Option<_>>()?;
    let k = proj.stencil as i32;
    let x: Vec<f64> = roots.iter().map(|b| b.powi(k)).collect();
    let (constant, interval) = super::uncertainty::weighted_scale(used, &x)?;
    Some(Continuum {
        name: if k == 2 { "kappa" } else { "c" },
        constant,
        interval,
        interval_from: interval.map(|_| "mode errors"),
        unit: String::new(),
        roots,
        body_length: 0.0,
        in_data_units: 0.0,
    })
}

/// ω, β and the continuum constant from the spectral peaks (or centroids) of `fitted`, when no
/// mode's own fit resolves it: ω = Σmᵢ√λᵢ/Σλᵢ, β = n/Σω²λᵢVar Qᵢ.
fn from_peaks(
    proj: &Projector,
    settings: &FitSettings,
    fitted: &[ModeFit],
) -> (f64, f64, Option<Continuum>) {
    let omega = settings.omega.unwrap_or_else(|| {
        fitted
            .iter()
            .map(|x| x.angular_frequency * x.eigenvalue.sqrt())
            .sum::<f64>()
            / fitted.iter().map(|x| x.eigenvalue).sum::<f64>()
    });
    let spread: f64 = fitted
        .iter()
        .map(|x| omega * omega * x.eigenvalue * x.variance)
        .sum();
    let peaks: Vec<(usize, f64, f64)> = fitted
        .iter()
        .map(|x| (x.index, x.angular_frequency, 1.0))
        .collect();
    let continuum = continuum(proj, &peaks).map(|mut c| {
        c.interval = None;
        c.interval_from = None;
        c
    });
    (omega, fitted.len() as f64 / spread, continuum)
}

/// PCA, overlaps, shares, frequencies and the ω and β fits from the accumulated moments.
pub(super) fn summarise(
    proj: &Projector,
    settings: &FitSettings,
    cov: Vec<Vec<f64>>,
    interval: f64,
    spectra: Vec<Spectra>,
    (scope, origin): (Scope<'_>, Origin),
) -> Result<FitReport, FitError> {
    check_moments(&cov, &spectra)?;
    let fs = 1.0 / interval;
    let warm = match scope {
        Scope::Constants(Some(r), _) => Some(r),
        _ => None,
    };
    let exact = match scope {
        Scope::Full(s) => Exact::Spans(s),
        Scope::Constants(_, e) => e,
    };
    // A resample keeps the pooled fit's window, when it has it.
    let spectra = match warm.map(|r| r.window.frames) {
        Some(w) if spectra.iter().any(|s| s.window == w) => {
            spectra.into_iter().filter(|s| s.window == w).collect()
        }
        _ => spectra,
    };
    let (spec, window) = choose_window(
        spectra,
        settings.window.is_some() || warm.is_some(),
        |s| lowest_frequency(proj, &cov, s, fs),
        fs,
    );
    if spec.partial {
        return Err(FitError::Pruned {
            window: spec.window,
        });
    }
    let count = match scope {
        Scope::Full(_) => cov.len(),
        Scope::Constants(..) => settings.fit_modes.min(cov.len()),
    };
    let mut modes_fit = fit_modes_spectra(
        proj,
        &cov,
        &spec,
        fs,
        (count, warm.map(|r| r.modes_fit.as_slice())),
    );
    let df = fs / spec.window as f64;
    let chosen = warm.map(|r| r.modes_fit.as_slice());
    let classify = |j: usize, s: &_, why: &str| {
        let (index, lambda) = (proj.first_mode + j, proj.eigenvalues[j]);
        let by = match why {
            UNFOLDED => FittedBy::Unfolded,
            _ => FittedBy::Exact,
        };
        ModeSpectralFit::of(index, lambda, s, (df, fs), by)
    };
    refit(&mut modes_fit, (exact, chosen), (df, fs), &classify);
    mark_aliases(&mut modes_fit, fs);
    unfold(
        &mut modes_fit,
        exact.spans(),
        (&regressor(proj), fs),
        &classify,
    );
    // A mode unfolded above the next one's resolved Ω shows that one to be an alias too.
    mark_aliases(&mut modes_fit, fs);
    let Spectra {
        window: used_window,
        segments,
        frequencies,
        psd,
        ..
    } = spec;
    let lambdas = &proj.eigenvalues;
    let m = lambdas.len();

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
    let mut modes = mode_table(proj, settings, &cov, &frequencies, &psd);
    // A driven wave (`wave`), looked for on the series in the full fit only.
    let wave = match scope {
        Scope::Full(s) => super::wave::driven_wave(s, used_window, fs, m),
        Scope::Constants(..) => None,
    };
    let locked = wave.as_ref().map_or(&[][..], |w| &w.coordinates[..]);
    let (noise_floor, mut tests) = vote(proj, &cov, &mut modes_fit, locked);
    let mut warnings = Vec::new();
    if let Some(w) = &wave {
        w.reject(&mut tests.dispersion, proj.first_mode);
        warnings.push(w.warning(proj.first_mode));
    }

    let used = settings.fit_modes.min(m);
    let (omega, beta, continuum) = scales(
        proj,
        settings,
        &cov,
        (&modes_fit, &modes),
        (used, used_window),
        &mut warnings,
    )?;
    warn_of(&modes_fit, &cov, &tests, &mut warnings);
    warnings.extend(origin.warnings((used_window, segments), proj, settings.recording.ring));
    for x in &mut modes {
        x.theory_angular_frequency = omega * x.eigenvalue.sqrt();
    }
    let continuum = continuum.map(|c| origin.in_units(c, proj.points));
    Ok(FitReport {
        estimator: settings.estimator,
        continuum,
        modes_fit,
        tests,
        noise_floor,
        tracking_noise: None,
        held_movement: None,
        window,
        frames: origin.frames,
        recording: origin.recording,
        warnings,
        animals: Vec::new(),
        units: origin.units,
        spacing: origin.spacing,
        subspace,
        intervals: None,
        spread: None,
        rate_groups: Vec::new(),
        across_rates: None,
        advice: None,
        onward: Vec::new(),
        inputs: Vec::new(),
        active_allowed: false,
        model_argument: None,
        points: proj.input_points,
        pca_variance_share: pca_share,
        theory_variance_share: theory_share,
        overlap,
        omega,
        omega_given: settings.omega.is_some(),
        beta,
        kind: settings.recording.kind,
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

/// No eigen-solve or SVD on non-finite moments (nalgebra's SVD panics on NaN), and spectra
/// to fit.
fn check_moments(cov: &[Vec<f64>], spectra: &[Spectra]) -> Result<(), FitError> {
    if cov
        .iter()
        .flatten()
        .chain(spectra.iter().flat_map(|s| s.psd.iter().flatten()))
        .any(|v| !v.is_finite())
    {
        return Err(FitError::Invalid(
            "the modal coordinates' moments overflow: rescale the data".into(),
        ));
    }
    if spectra.is_empty() {
        return Err(FitError::Invalid("no spectra to fit".into()));
    }
    Ok(())
}

/// Each mode's eigenvalue, variance and spectral peak and centroid.
fn mode_table(
    proj: &Projector,
    settings: &FitSettings,
    cov: &[Vec<f64>],
    frequencies: &[f64],
    psd: &[Vec<f64>],
) -> Vec<ModeFit> {
    (0..proj.eigenvalues.len())
        .map(|j| {
            let (peak, centroid) = spectral_peak_and_centroid(frequencies, &psd[j]);
            let f = match settings.estimator {
                Estimator::Peak => peak,
                Estimator::Centroid => centroid,
            };
            ModeFit {
                index: proj.first_mode + j,
                eigenvalue: proj.eigenvalues[j],
                variance: cov[j][j],
                peak_frequency: peak,
                centroid_frequency: centroid,
                angular_frequency: 2.0 * std::f64::consts::PI * f,
                theory_angular_frequency: 0.0,
            }
        })
        .collect()
}

/// Which modes vote (above the white floor, resolved, not leaking), and the three tests over
/// them against the continuum eigenvalues.
fn vote(
    proj: &Projector,
    cov: &[Vec<f64>],
    modes_fit: &mut [ModeSpectralFit],
    locked: &[usize],
) -> (Option<f64>, TheoryTests) {
    let noise_floor = verdict::noise_floor(modes_fit);
    verdict::disqualify(
        modes_fit,
        noise_floor,
        (&continuum_lambda(proj), proj.mixed_shares()),
        proj.continuum_modes,
    );
    verdict::drop_leaks(modes_fit, cov, locked);
    let tests = verdict::tests(modes_fit, &regressor(proj), &proj.continuum_gains());
    (noise_floor, tests)
}

/// Each mode's continuum eigenvalue, where the body has one.
fn continuum_lambda(proj: &Projector) -> Vec<Option<f64>> {
    let k = proj.stencil as i32;
    (0..proj.eigenvalues.len())
        .map(|j| continuum_root(proj, j + 1).map(|b| b.powi(2 * k)))
        .collect()
}

/// The λ each mode is regressed on: the continuum's, else the grid's.
fn regressor(proj: &Projector) -> Vec<f64> {
    (continuum_lambda(proj).iter().zip(&proj.eigenvalues))
        .map(|(c, l)| c.unwrap_or(*l))
        .collect()
}

/// ω, β and the continuum constant from the voting modes (from the spectral peaks when none
/// votes, said in `warnings`), checked to be measurable and representable.
fn scales(
    proj: &Projector,
    settings: &FitSettings,
    cov: &[Vec<f64>],
    (modes_fit, modes): (&[ModeSpectralFit], &[ModeFit]),
    (used, window): (usize, usize),
    warnings: &mut Vec<String>,
) -> Result<(f64, f64, Option<Continuum>), FitError> {
    let invalid = |s: String| FitError::Invalid(s);
    let lambdas = &proj.eigenvalues;
    let (m, first_mode) = (lambdas.len(), proj.first_mode);
    let voting: Vec<(usize, f64, f64)> = modes_fit[..used]
        .iter()
        .filter(|f| f.votes)
        .filter_map(|f| Some((f.mode, f.omega, f.omega_error?)))
        .collect();
    let unresolved: Vec<String> = modes_fit[..used]
        .iter()
        .filter(|f| !f.resolved)
        .map(|f| f.mode.to_string())
        .collect();
    if !unresolved.is_empty() {
        warnings.push(format!(
            "the spectral fits cannot resolve mode(s) {} at this window ({window} frames) and frame rate (see the per-mode notes): left out of ω, β and κ",
            unresolved.join(", ")
        ));
    }
    let (omega, beta, continuum) = if voting.is_empty() {
        warnings.push(format!(
            "no mode among {}–{} is resolved and above the white floor: ω, β and κ come from the spectral {}s, which move with --window (use a longer --window or recording)",
            first_mode,
            first_mode + used - 1,
            settings.estimator.name()
        ));
        from_peaks(proj, settings, &modes[..used])
    } else {
        let sqrt: Vec<f64> = voting
            .iter()
            .map(|&(i, _, _)| lambdas[i - first_mode].sqrt())
            .collect();
        let omega = settings
            .omega
            .or_else(|| super::uncertainty::weighted_scale(&voting, &sqrt).map(|(w, _)| w))
            .unwrap_or(f64::NAN);
        let spread: f64 = voting
            .iter()
            .map(|&(i, _, _)| {
                omega * omega * lambdas[i - first_mode] * modes_fit[i - first_mode].variance
            })
            .sum();
        (
            omega,
            voting.len() as f64 / spread,
            continuum(proj, &voting),
        )
    };
    if !(omega.is_finite() && omega > 0.0) {
        return Err(invalid(
            "no frequency could be measured (flat spectra): give --omega".into(),
        ));
    }
    // β = modes/Σω²λσ² is 0 when ω² alone overflows (a time unit of 10⁻²⁰⁰ s): that is a
    // scale out of range (below), not postures at rest.
    let overflow = !(omega * omega).is_finite();
    if (!overflow && (beta.is_nan() || beta <= 0.0)) || (0..m).all(|j| cov[j][j] <= 0.0) {
        return Err(invalid(
            "the postures do not vary: no temperature can be fitted".into(),
        ));
    }
    // ω·dt and β·ω² are what the data measure; outside the floats they cannot be reported.
    if !(beta.is_finite() && (beta * omega * omega).is_finite() && (omega * omega).is_finite()) {
        return Err(invalid(format!(
            "the fitted scales are out of range (ω = {}, β = {}): rescale the time column or --fps",
            fixed(omega, 4),
            fixed(beta, 4)
        )));
    }
    Ok((omega, beta, continuum))
}

/// Warnings on what the voting modes show: pairs that move together, a rejected dispersion.
fn warn_of(
    modes_fit: &[ModeSpectralFit],
    cov: &[Vec<f64>],
    tests: &TheoryTests,
    warnings: &mut Vec<String>,
) {
    let pairs = verdict::correlated(modes_fit, cov);
    if !pairs.is_empty() {
        let shown: Vec<String> = pairs
            .iter()
            .take(6)
            .map(|(i, j, r2)| format!("{i}–{j} (r² = {})", fixed(*r2, 2)))
            .collect();
        warnings.push(format!(
            "{} pair(s) of voting modes move together: {}{}; a passive body's modes are independent, so this is a driven rhythm or one mode leaking into another",
            pairs.len(),
            shown.join(", "),
            if pairs.len() > 6 { ", …" } else { "" }
        ));
    }
    if tests.dispersion.verdict == verdict::Verdict::Rejected {
        warnings.push(
            "the dispersion Ωᵢ ∝ √λᵢ is rejected: the modes do not oscillate as a passive body's would, so ω and κ are not constants of the body: `discover FILE --model M --active` says which terms the recording needs (an active force, a driven rhythm)".into(),
        );
    }
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
