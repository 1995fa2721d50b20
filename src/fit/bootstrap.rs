//! Uncertainty by the bootstrap: whole animals are drawn with replacement, their statistics
//! pooled as the fit pools them, and the fit made again; drawing whole animals keeps what varies
//! between animals. One animal is resampled in time by the moving-block bootstrap (Künsch
//! 1989): its frames, kept in consecutive blocks, are drawn as runs of L consecutive blocks
//! starting anywhere, L blocks spanning at least five of the slowest voting mode's correlation
//! times 1/(ζΩ) and the Welch window, so the correlation in time stays inside a draw.
//!
//! The interval is Hesterberg's *expanded percentile* interval (The American Statistician 69,
//! 2015): with n units the plain percentile interval is too narrow (the bootstrap variance is
//! (n − 1)/n of the plug-in one, and z replaces Student's t), so the quantiles taken are at
//! α′/2 = Φ(−√(n/(n − 1))·t₀.₉₇₅,ₙ₋₁) instead of 2.5 %; for large n this is the plain 95 %
//! percentile interval. Over whole animals, ω, β and κ's quantiles are bias-corrected (Efron's
//! BC, z₀ from the share of replicates below the pooled estimate): the time-domain refits of
//! sharp lines left the replicates skewed about it. Moving blocks keep the plain quantiles.

use rand::{RngExt, SeedableRng};

use super::stats::Stats;
use super::welch::Ladder;
use super::{FitReport, FitSettings};

/// The most replicates.
pub const MAX_REPLICATES: usize = 100_000;

/// Replicates × units pooled, at most: each pooling costs about m² + m·W/2 operations.
const MAX_DRAWS: usize = 20_000_000;

/// 95 % bootstrap intervals, `[low, high]`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Intervals {
    /// What was resampled: `animals` or `blocks`.
    pub resampled: &'static str,
    /// How many there were.
    pub units: usize,
    /// Consecutive blocks per draw (moving blocks of one animal), with their length in frames.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub moving: Option<(usize, usize)>,
    /// Replicates drawn.
    pub replicates: usize,
    /// Replicates that gave a fit (a draw without a spectrum or with flat spectra gives none).
    pub fitted: usize,
    /// ω.
    pub omega: [f64; 2],
    /// β.
    pub beta: [f64; 2],
    /// The continuum constant (κ or c), when every replicate has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub continuum: Option<[f64; 2]>,
    /// Each principal component's variance share.
    pub pca_variance_share: Vec<[f64; 2]>,
    /// Each principal component's overlap with its mode (or pair).
    pub mode_overlap: Vec<[f64; 2]>,
    /// The smallest cosine of the principal angles between the first k components and the
    /// first k modes, k = 1, 2, ….
    pub subspace_cosine: Vec<[f64; 2]>,
}

/// Student's t quantile at probability 0.975 with `nu` degrees of freedom: exact for 1 and 2,
/// the Cornish–Fisher expansion in 1/ν beyond (error below 1 % at ν = 3, 0.2 % from ν = 5).
pub(super) fn student_975(nu: f64) -> f64 {
    let z = 1.959_963_984_540_054_f64;
    if nu < 1.5 {
        return (std::f64::consts::PI * 0.475).tan();
    }
    if nu < 2.5 {
        let p = 0.975_f64;
        return (2.0 * p - 1.0) / (2.0 * p * (1.0 - p)).sqrt();
    }
    let (z3, z5, z7) = (z.powi(3), z.powi(5), z.powi(7));
    z + (z3 + z) / (4.0 * nu)
        + (5.0 * z5 + 16.0 * z3 + 3.0 * z) / (96.0 * nu * nu)
        + (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / (384.0 * nu.powi(3))
}

/// The lower tail probability α′/2 of the expanded percentile interval for `n` units.
pub(crate) fn expanded_tail(n: usize) -> f64 {
    let n = n as f64;
    let x = (n / (n - 1.0)).sqrt() * student_975(n - 1.0);
    0.5 * libm::erfc(x / std::f64::consts::SQRT_2)
}

/// The quantiles at `tail` and 1 − `tail` (linear between order statistics).
fn interval(mut v: Vec<f64>, tail: f64) -> [f64; 2] {
    v.sort_by(f64::total_cmp);
    let q = |p: f64| {
        let x = p * (v.len() - 1) as f64;
        let (i, f) = (x.floor() as usize, x - x.floor());
        v[i] + f * (v[(i + 1).min(v.len() - 1)] - v[i])
    };
    [q(tail), q(1.0 - tail)]
}

/// The bias-corrected percentile interval (Efron 1981) of replicates `v` about the estimate
/// `at`: where the replicates' median lies off the estimate (z₀ = Φ⁻¹ of the share below it),
/// the quantiles taken move to Φ(2z₀ ± z): pooled exact fits of sharp lines left the replicates
/// skewed above the estimate, and the plain percentile interval missed low truths (ω covered in
/// 89 of 100 directories of 16 animals, tests/animals.rs).
fn corrected(v: Vec<f64>, at: Option<f64>, tail: f64) -> [f64; 2] {
    use statrs::distribution::{ContinuousCDF, Normal};
    let (Some(at), Ok(normal)) = (at, Normal::new(0.0, 1.0)) else {
        return interval(v, tail);
    };
    let n = v.len() as f64;
    let below = v.iter().filter(|x| **x < at).count() as f64;
    let ties = v.iter().filter(|x| **x == at).count() as f64;
    let share = ((below + 0.5 * ties) / n).clamp(0.5 / n, 1.0 - 0.5 / n);
    let (z0, z) = (normal.inverse_cdf(share), normal.inverse_cdf(tail));
    let (lo, hi) = (normal.cdf(2.0 * z0 + z), normal.cdf(2.0 * z0 - z));
    let mut v = v;
    v.sort_by(f64::total_cmp);
    let q = |p: f64| {
        let x = p.clamp(0.0, 1.0) * (v.len() - 1) as f64;
        let (i, f) = (x.floor() as usize, x - x.floor());
        v[i] + f * (v[(i + 1).min(v.len() - 1)] - v[i])
    };
    [q(lo), q(hi)]
}

/// Per-coordinate intervals of vectors of replicates.
fn intervals_of(rows: &[Vec<f64>], tail: f64) -> Vec<[f64; 2]> {
    let len = rows.iter().map(Vec::len).min().unwrap_or(0);
    (0..len)
        .map(|k| interval(rows.iter().map(|r| r[k]).collect(), tail))
        .collect()
}

/// Why no bootstrap was drawn (a warning in the report, not an error).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NoBootstrap {
    /// Fewer than two units to resample.
    #[error("no bootstrap: it draws whole animals, and there is {n} {unit}")]
    TooFew {
        /// Units available.
        n: usize,
        /// `run` or `animal`.
        unit: &'static str,
    },
    /// So many units that fewer than 20 replicates fit the budget.
    #[error("no bootstrap: {n} {resampled} are too many to resample within the budget")]
    TooMany {
        /// Units available.
        n: usize,
        /// `runs` or `animals`.
        resampled: &'static str,
    },
    /// One animal's recording holds too few blocks as long as its correlation time needs.
    #[error("no bootstrap: a draw must span {frames} frames (five correlation times of the slowest mode, and the window) and the recording's runs hold only {n} blocks of {block} frames; record longer")]
    Short {
        /// Blocks available.
        n: usize,
        /// Frames per block.
        block: usize,
        /// Frames a draw must span.
        frames: usize,
    },
    /// Too few resamples could be fitted.
    #[error("no bootstrap: only {fitted} of {replicates} resamples could be fitted (too few frames per {unit})")]
    Unfitted {
        /// Resamples fitted.
        fitted: usize,
        /// Resamples drawn.
        replicates: usize,
        /// `run` or `animal`.
        unit: &'static str,
    },
}

/// B replicates (`settings.bootstrap`, seeded by `settings.seed`) of `fit` on resampled
/// `units`; an explanation instead when they cannot be drawn.
///
/// ω, β and κ's intervals are bias-corrected about the pooled fit's (`centre`) when whole
/// animals are drawn.
/// `span` is, for the blocks of one animal, the frames a draw must span: the draws are then moving
/// blocks of consecutive units. `fit` is given the resample's pooled statistics and how many
/// times it holds each unit.
pub(super) fn intervals(
    (units, resampled): &(Vec<&Stats>, &'static str),
    settings: &FitSettings,
    (ladder, span): (&Ladder, usize),
    fit: impl Fn(&Stats, &[usize]) -> Option<FitReport>,
    centre: (f64, f64, Option<f64>),
) -> Result<Intervals, NoBootstrap> {
    let n = units.len();
    let moving = *resampled == "blocks";
    // Blocks per draw, and draws per replicate.
    let (length, draws) = if moving {
        let frames: f64 = units.iter().map(|u| u.count).sum();
        let block = (frames / n.max(1) as f64).max(1.0);
        let length = ((span as f64 / block).ceil() as usize).max(1);
        if n < 2 * length || n + 1 < length + 5 {
            return Err(NoBootstrap::Short {
                n,
                block: block.round() as usize,
                frames: span,
            });
        }
        (length, n.div_ceil(length))
    } else {
        if n < 2 {
            return Err(NoBootstrap::TooFew { n, unit: "animal" });
        }
        (1, n)
    };
    let replicates = settings.bootstrap.min(MAX_DRAWS / n);
    if replicates < 20 {
        return Err(NoBootstrap::TooMany { n, resampled });
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(settings.seed);
    let m = units[0].mean.len();
    let mut reports = Vec::with_capacity(replicates);
    let mut times = vec![0usize; n];
    for _ in 0..replicates {
        times.iter_mut().for_each(|c| *c = 0);
        for _ in 0..draws {
            let start = rng.random_range(0..=n - length);
            for c in &mut times[start..start + length] {
                *c += 1;
            }
        }
        let mut pooled = Stats::new(m, ladder);
        for (s, &c) in units.iter().zip(&times) {
            pooled.absorb(s, c as f64);
        }
        if let Some(r) = fit(&pooled, &times) {
            reports.push(r);
        }
    }
    if reports.len() < replicates / 2 {
        return Err(NoBootstrap::Unfitted {
            fitted: reports.len(),
            replicates,
            unit: if moving { "block" } else { "animal" },
        });
    }
    let column =
        |f: &dyn Fn(&FitReport) -> Vec<f64>| -> Vec<Vec<f64>> { reports.iter().map(f).collect() };
    let tail = expanded_tail(draws);
    // Bias-corrected about the estimate only over whole animals: moving blocks of one animal
    // have a bias of their own (the joins), which the correction would take for the
    // estimator's (κ covered in 77 of 100 against 87 uncorrected, tests/verdicts.rs).
    let at = |x: f64| (!moving).then_some(x);
    let block = units.iter().map(|u| u.count).sum::<f64>() / n as f64;
    Ok(Intervals {
        resampled,
        units: n,
        moving: moving.then(|| (length, block.round() as usize)),
        replicates,
        fitted: reports.len(),
        omega: corrected(
            reports.iter().map(|r| r.omega).collect(),
            at(centre.0),
            tail,
        ),
        beta: corrected(reports.iter().map(|r| r.beta).collect(), at(centre.1), tail),
        continuum: reports
            .iter()
            .map(|r| r.continuum.as_ref().map(|c| c.constant))
            .collect::<Option<Vec<f64>>>()
            .map(|v| corrected(v, centre.2.and_then(at), tail)),
        pca_variance_share: intervals_of(&column(&|r| r.pca_variance_share.clone()), tail),
        mode_overlap: intervals_of(&column(&|r| r.mode_overlap.clone()), tail),
        subspace_cosine: intervals_of(
            &column(&|r| r.subspace.iter().map(|s| s.cosine).collect()),
            tail,
        ),
    })
}

/// The frames a draw of one animal's blocks spans: five correlation times of the slowest voting
/// mode of `report` (sampled every `interval`), and its window. (A line narrower than half a bin
/// has no known width; its correlation time is at least W/π frames, which stands for it.)
pub(super) fn span(report: &FitReport, interval: f64) -> usize {
    let slowest = (report.modes_fit.iter())
        .filter(|m| m.votes)
        .map(|m| match m.zeta_error {
            Some(_) => 1.0 / (m.zeta * m.omega * interval),
            None => report.window.frames as f64 / std::f64::consts::PI,
        })
        .fold(0.0, f64::max);
    (5.0 * slowest).max(report.window.frames as f64).ceil() as usize
}

/// The bootstrap's intervals (or why there are none) into `report`.
pub(super) fn attach(report: &mut FitReport, drawn: Result<Intervals, NoBootstrap>) {
    match drawn {
        Ok(i) => {
            // The modes' errors give κ's interval when they can (their coverage is checked,
            // docs/fit.md); the bootstrap's stands in for the peaks' κ.
            if let Some(c) = report.continuum.as_mut().filter(|c| c.interval.is_none()) {
                c.interval = i.continuum;
                c.interval_from = i.continuum.map(|_| "bootstrap");
            }
            if let Some(why) = degenerate(report, &i) {
                report.warnings.push(why);
            }
            report.intervals = Some(i)
        }
        Err(why) => report.warnings.push(why.to_string()),
    }
}

/// Why ω's bootstrap interval has an end on the estimate itself (within 1 % of its width),
/// when it has: from spectral peaks (no mode resolved) the resamples' peaks fall on the same
/// few frequency bins.
pub(super) fn degenerate(report: &FitReport, i: &Intervals) -> Option<String> {
    let [lo, hi] = i.omega;
    let w = report.omega;
    let edge = (w - lo).min(hi - w) <= 0.01 * (hi - lo);
    edge.then(|| {
        let cause = if report.modes_fit.iter().any(|m| m.votes) {
            "the resamples' fits keep landing on the same value"
        } else {
            "ω comes from the spectral peaks (no mode is resolved), and the resamples' peaks fall on the same few frequency bins"
        };
        format!(
            "the bootstrap interval of ω, [{}, {}], ends on the estimate: it is degenerate, not precise ({cause}); use a longer recording or --window",
            crate::report::fixed(lo, 6),
            crate::report::fixed(hi, 6)
        )
    })
}

#[cfg(test)]
mod tests {
    use super::{expanded_tail, student_975};

    #[test]
    fn student_quantiles_and_the_expanded_tail() {
        // Tables: t₀.₉₇₅ for ν = 1, 2, 3, 5, 10, 30.
        for (nu, t) in [
            (1.0, 12.7062),
            (2.0, 4.3027),
            (3.0, 3.1824),
            (5.0, 2.5706),
            (10.0, 2.2281),
            (30.0, 2.0423),
        ] {
            let tol = if nu < 4.0 { 1e-2 } else { 2e-3 };
            assert!(
                (student_975(nu) - t).abs() < tol * t,
                "ν = {nu}: {}",
                student_975(nu)
            );
        }
        // n = 5: √(5/4)·t₀.₉₇₅,₄ = 1.1180 × 2.7764 = 3.1041, Φ(−3.1041) = 0.000954 (tables);
        // large n tends to 0.025.
        assert!(
            (expanded_tail(5) - 0.000954).abs() < 3e-5,
            "{}",
            expanded_tail(5)
        );
        assert!((expanded_tail(100_000) - 0.025).abs() < 1e-4);
        assert!(expanded_tail(2) > 0.0 && expanded_tail(2) < 1e-6);
    }
}
