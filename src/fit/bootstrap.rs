//! Uncertainty by the bootstrap: whole animals (or, for one animal, whole runs between gaps)
//! are drawn with replacement, their statistics pooled as the fit pools them, and the fit made
//! again; the 2.5 % and 97.5 % quantiles of B replicates bound each number. Drawing whole
//! animals keeps what varies between animals, and whole runs keeps the correlation in time
//! inside a run.

use rand::{RngExt, SeedableRng};

use super::pool::Animal;
use super::stats::Stats;
use super::{FitReport, FitSettings};

/// The most replicates.
pub const MAX_REPLICATES: usize = 100_000;

/// Replicates × units pooled, at most: each pooling costs about m² + m·W/2 operations.
const MAX_DRAWS: usize = 20_000_000;

/// 95 % bootstrap intervals, `[low, high]`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Intervals {
    /// What was resampled: `animals` or `runs`.
    pub resampled: &'static str,
    /// How many there were.
    pub units: usize,
    /// Replicates drawn.
    pub replicates: usize,
    /// Replicates that gave a fit (a draw without a spectrum or with flat spectra gives none).
    pub fitted: usize,
    /// ω.
    pub omega: [f64; 2],
    /// β.
    pub beta: [f64; 2],
    /// Each principal component's variance share.
    pub pca_variance_share: Vec<[f64; 2]>,
    /// Each principal component's overlap with its mode (or pair).
    pub mode_overlap: Vec<[f64; 2]>,
    /// The smallest cosine of the principal angles between the first k components and the
    /// first k modes, k = 1, 2, ….
    pub subspace_cosine: Vec<[f64; 2]>,
}

/// The units a bootstrap draws: the animals, or the one animal's runs.
pub(super) fn units(animals: &[Animal]) -> (Vec<&Stats>, &'static str) {
    let with_frames: Vec<&Animal> = animals.iter().filter(|a| a.stats.count > 0.0).collect();
    if with_frames.len() > 1 {
        (with_frames.iter().map(|a| &a.stats).collect(), "animals")
    } else {
        let runs = with_frames
            .first()
            .map(|a| a.pieces.iter().filter(|p| p.count > 0.0).collect())
            .unwrap_or_default();
        (runs, "runs")
    }
}

/// The quantiles at 2.5 % and 97.5 % (linear between order statistics).
fn interval(mut v: Vec<f64>) -> [f64; 2] {
    v.sort_by(f64::total_cmp);
    let q = |p: f64| {
        let x = p * (v.len() - 1) as f64;
        let (i, f) = (x.floor() as usize, x - x.floor());
        v[i] + f * (v[(i + 1).min(v.len() - 1)] - v[i])
    };
    [q(0.025), q(0.975)]
}

/// Per-coordinate intervals of vectors of replicates.
fn intervals_of(rows: &[Vec<f64>]) -> Vec<[f64; 2]> {
    let len = rows.iter().map(Vec::len).min().unwrap_or(0);
    (0..len)
        .map(|k| interval(rows.iter().map(|r| r[k]).collect()))
        .collect()
}

/// B replicates (`settings.bootstrap`, seeded by `settings.seed`) of `fit` on resampled
/// `units`; an explanation instead when they cannot be drawn.
pub(super) fn intervals(
    (units, resampled): &(Vec<&Stats>, &'static str),
    settings: &FitSettings,
    fit: impl Fn(&Stats) -> Option<FitReport>,
) -> Result<Intervals, String> {
    let n = units.len();
    if n < 2 {
        return Err(format!(
            "no bootstrap: it draws whole animals or whole runs, and there is {n} {}",
            if *resampled == "runs" {
                "run"
            } else {
                "animal"
            }
        ));
    }
    let replicates = settings.bootstrap.min(MAX_DRAWS / n);
    if replicates < 20 {
        return Err(format!(
            "no bootstrap: {n} {resampled} are too many to resample within the budget"
        ));
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(settings.seed);
    let (m, window) = (units[0].mean.len(), settings.window);
    let mut reports = Vec::with_capacity(replicates);
    let mut times = vec![0usize; n];
    for _ in 0..replicates {
        times.iter_mut().for_each(|c| *c = 0);
        for _ in 0..n {
            times[rng.random_range(0..n)] += 1;
        }
        let mut pooled = Stats::new(m, window);
        for (s, &c) in units.iter().zip(&times) {
            pooled.absorb(s, c as f64);
        }
        if let Some(r) = fit(&pooled) {
            reports.push(r);
        }
    }
    if reports.len() < replicates / 2 {
        return Err(format!(
            "no bootstrap: only {} of {replicates} resamples could be fitted (too few frames per {})",
            reports.len(),
            &resampled[..resampled.len() - 1]
        ));
    }
    let column =
        |f: &dyn Fn(&FitReport) -> Vec<f64>| -> Vec<Vec<f64>> { reports.iter().map(f).collect() };
    Ok(Intervals {
        resampled,
        units: n,
        replicates,
        fitted: reports.len(),
        omega: interval(reports.iter().map(|r| r.omega).collect()),
        beta: interval(reports.iter().map(|r| r.beta).collect()),
        pca_variance_share: intervals_of(&column(&|r| r.pca_variance_share.clone())),
        mode_overlap: intervals_of(&column(&|r| r.mode_overlap.clone())),
        subspace_cosine: intervals_of(&column(&|r| r.subspace.iter().map(|s| s.cosine).collect())),
    })
}
