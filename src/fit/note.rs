//! Why a mode is not resolved or does not vote, and what a test's verdict rests on: values,
//! written in words only when printed (JSON carries the same words).

use std::fmt;

use crate::report::fixed;

use super::verdict::{FittedBy, ModeSpectralFit, EXACT_NYQUIST};

// The thresholds the notes name (the verdict module applies them and re-exports them).

/// Half-widths ζΩ of a line that must stay under Nyquist for the mode to be resolved.
pub const NYQUIST_HALF_WIDTHS: f64 = 3.0;

/// Bins above zero a mode's frequency must reach to count as resolved.
pub const RESOLVED_BINS: f64 = 1.0;

/// Bins above zero a mode's frequency must reach for its variance and damping to vote: nearer
/// zero they share the window's low-frequency leakage, and their errors run short.
pub const WIDTH_BINS: f64 = 4.0;

/// The ratio of a line's peak to the white level under it above which a mode is resolved
/// however large the white level's variance (see [`line_over_floor`]).
pub const LINE_OVER_FLOOR: f64 = 30.0;

/// How far the line stands out of the white level: its peak density σ²/(π·max(γ, df)) (γ =
/// ζΩ/2π its half-width in Hz, no narrower than a bin) over the white noise's 2ν/f_s. A sharp
/// mode under noise of ten times its variance (a clamped body's first mode at 5 % tracking
/// noise) rises 120× above it: such a line is resolved, though ν > 3σ². Below 30× the rule
/// stays ν ≤ 3σ²: at 3× a free beam's modes 8 and 10 at N = 48, which hold nothing but the
/// lower modes' leakage, were taken for lines and voted against every law.
pub(super) fn line_over_floor(s: &super::spectrum::ModeSpectrum, df: f64, fs: f64) -> f64 {
    let half_width = (s.zeta * s.omega / (2.0 * std::f64::consts::PI)).max(df);
    let peak = s.variance / (std::f64::consts::PI * half_width);
    peak * fs / (2.0 * s.noise)
}

/// Why a mode is not resolved, or does not vote.
#[derive(Debug, Clone, PartialEq)]
pub enum ModeNote {
    /// The spectral fit did not converge.
    NotConverged,
    /// ζ ≥ 1.
    OverDamped {
        /// The fitted ζ.
        zeta: f64,
    },
    /// Under [`RESOLVED_BINS`] bins above zero.
    TooFewBins {
        /// Its frequency in bins.
        bins: f64,
    },
    /// Above 0.9 × Nyquist.
    AboveNyquist,
    /// Its line reaches past Nyquist.
    LinePastNyquist,
    /// White level above 3σ².
    MostlyFlat,
    /// Ω known to worse than 25 %.
    OmegaUncertain,
    /// Its variance under the white floor.
    UnderFloor {
        /// σ².
        variance: f64,
        /// The floor.
        floor: f64,
    },
    /// The grid does not resolve it.
    GridOff {
        /// λ/λ₁ against the continuum's, in per cent.
        percent: f64,
    },
    /// Neighbouring continuum modes the tracked points cannot separate from it put this share
    /// of its variance in its coordinate (at equipartition).
    Mixed {
        /// That share, in per cent.
        percent: f64,
    },
    /// A lower mode showing through.
    Leak {
        /// That mode.
        from: usize,
    },
    /// Its frequency lies below a lower mode's, in the upper half of the band: the alias of a
    /// mode above Nyquist.
    Alias {
        /// The lower mode.
        below: usize,
    },
    /// A time-domain fit above 0.8 × Nyquist, where it cannot be told from an alias.
    NearAlias,
    /// Unfolded above Nyquist by the λ law, but broad (ζ ≥ 0.4): its σ²'s error is too small
    /// there.
    BroadAlias {
        /// Its damping ratio.
        zeta: f64,
    },
    /// A time-domain fit of a line near Nyquist that may be broad (ζ + 2 se ≥ 0.4): its
    /// likelihood is flat toward the alias, and the fits that come out narrow come out low.
    BroadNearNyquist {
        /// Its damping ratio.
        zeta: f64,
        /// ζ + 2 se.
        upper: f64,
    },
    /// Too few frequency bins or no variance to fit.
    Unfittable,
    /// Only the constants were asked for.
    NotFitted,
}

impl fmt::Display for ModeNote {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ModeNote::NotConverged => f.write_str("the spectral fit did not converge"),
            ModeNote::OverDamped { zeta } => write!(f, "over-damped (ζ = {})", fixed(*zeta, 3)),
            ModeNote::TooFewBins { bins } => write!(
                f,
                "its frequency is {} bins above zero, fewer than {RESOLVED_BINS}: the window cannot resolve it",
                fixed(*bins, 2)
            ),
            ModeNote::AboveNyquist => f.write_str("its frequency is above 0.9 × Nyquist"),
            ModeNote::LinePastNyquist => write!(
                f,
                "its line reaches past Nyquist (Ω(1 + {NYQUIST_HALF_WIDTHS}ζ) above it): Ω and ζ are biased by its own aliasing"
            ),
            ModeNote::MostlyFlat => {
                f.write_str("its spectrum is mostly flat (white level ν above 3σ², its line's peak under 30 × the white level)")
            }
            ModeNote::OmegaUncertain => f.write_str("Ω is known to worse than 25 %"),
            ModeNote::UnderFloor { variance, floor } => write!(
                f,
                "its variance {} is under the white floor {}",
                fixed(*variance, 4),
                fixed(*floor, 4)
            ),
            ModeNote::GridOff { percent } => write!(
                f,
                "λ/λ₁ of the model's points differs from the continuum's by {} %: the grid does not resolve it",
                fixed(*percent, 1)
            ),
            ModeNote::Mixed { percent } => write!(
                f,
                "neighbouring modes the tracked points cannot separate from it put {} % of its variance in its coordinate",
                fixed(*percent, 1)
            ),
            ModeNote::Leak { from } => write!(
                f,
                "its coordinate follows mode {from}'s at a small fraction of its variance: mode {from} showing through"
            ),
            ModeNote::Alias { below } => write!(
                f,
                "its frequency lies below mode {below}'s: the alias of a mode above Nyquist, identifiable only up to it"
            ),
            ModeNote::BroadAlias { zeta } => write!(
                f,
                "unfolded above Nyquist by the λ law, its line is broad (ζ = {}), where the leakage of the modes above it is not white: it does not vote",
                crate::report::fixed(*zeta, 2)
            ),
            ModeNote::BroadNearNyquist { zeta, upper } => write!(
                f,
                "its line near Nyquist may be broad (ζ = {}, up to {} within two errors), where its likelihood is flat toward the alias and the fits that come out narrow come out low: it does not vote",
                crate::report::fixed(*zeta, 2),
                crate::report::fixed(*upper, 2)
            ),
            ModeNote::NearAlias => f.write_str(
                "its frequency is above 0.8 × Nyquist, where its time-domain fit cannot be told from the alias of a mode above Nyquist",
            ),
            ModeNote::Unfittable => f.write_str("too few frequency bins or no variance to fit"),
            ModeNote::NotFitted => f.write_str("not fitted (only the constants were asked for)"),
        }
    }
}

impl serde::Serialize for ModeNote {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// What a test's verdict rests on, when it needs saying.
#[derive(Debug, Clone, PartialEq)]
pub enum TestNote {
    /// Fewer than three voting modes.
    TooFew {
        /// How many voted.
        n: usize,
    },
    /// The voting modes share one eigenvalue.
    SharedEigenvalue,
    /// The modes scatter about the law beyond their errors.
    LawDoesNotFit {
        /// χ².
        chi2: f64,
        /// Degrees of freedom.
        dof: usize,
        /// Its p-value.
        p: f64,
    },
    /// Notable scatter, within chance.
    WithinChance {
        /// χ².
        chi2: f64,
        /// Degrees of freedom.
        dof: usize,
        /// Its p-value.
        p: f64,
    },
    /// The interval cannot tell the expected exponent from zero.
    TooWide,
    /// Modes phase-locked at one frequency with a lag between them (`wave`).
    DrivenWave {
        /// Those modes.
        modes: Vec<usize>,
        /// The shared frequency (cycles per time unit).
        frequency: f64,
    },
    /// Modes that vote on the dispersion only, after what else there is to say.
    DispersionOnly {
        /// Those modes.
        modes: Vec<usize>,
        /// The note before.
        after: Option<Box<TestNote>>,
    },
}

/// A p-value as a reader wants it: three decimals, or two significant digits when small.
pub(super) fn p_value(p: f64) -> String {
    if p >= 0.001 {
        fixed(p, 3)
    } else {
        format!("{p:.1e}")
    }
}

impl fmt::Display for TestNote {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TestNote::TooFew { n } if *n < 2 => {
                write!(f, "{n} voting mode(s); at least 3 are needed")
            }
            TestNote::TooFew { n } => write!(f, "{n} voting modes; at least 3 are needed"),
            TestNote::SharedEigenvalue => f.write_str("the voting modes share one eigenvalue"),
            TestNote::LawDoesNotFit { chi2, dof, p } => write!(
                f,
                "the modes scatter about the power law beyond their errors (χ² = {}, ν = {dof}, p = {}): the law does not fit",
                fixed(*chi2, 1),
                p_value(*p)
            ),
            TestNote::WithinChance { chi2, dof, p } => write!(
                f,
                "scatter {}× the errors, within chance (χ² = {}, ν = {dof}, p = {})",
                fixed((chi2 / *dof as f64).sqrt(), 2),
                fixed(*chi2, 1),
                p_value(*p)
            ),
            TestNote::TooWide => f.write_str(
                "the interval's half-width exceeds the expected exponent's size: it could not tell that exponent from zero",
            ),
            TestNote::DrivenWave { modes, frequency } => {
                let list: Vec<String> = modes.iter().map(|m| m.to_string()).collect();
                write!(
                    f,
                    "modes {} are phase-locked at f = {} per time unit with a lag between them: a driven travelling wave, not a passive body",
                    list.join(", "),
                    crate::report::number(*frequency)
                )
            }
            TestNote::DispersionOnly { modes, after } => {
                if let Some(a) = after {
                    write!(f, "{a}; ")?;
                }
                let (who, verb) = match modes.len() {
                    1 => ("mode", "votes"),
                    _ => ("modes", "vote"),
                };
                let list: Vec<String> = modes.iter().map(|m| m.to_string()).collect();
                write!(
                    f,
                    "{who} {} {verb} on the dispersion only (under {WIDTH_BINS} bins above zero their σ² and ζ errors run short; a longer --window resolves them)",
                    list.join(", ")
                )
            }
        }
    }
}

impl serde::Serialize for TestNote {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl ModeSpectralFit {
    /// Whether it votes on dispersion only: a Whittle fit under [`WIDTH_BINS`] bins (the exact
    /// likelihood's errors hold at any frequency).
    pub fn dispersion_only(&self) -> bool {
        self.bins < WIDTH_BINS && self.exact.is_none()
    }

    /// Classify the fit `s` of mode `mode` (eigenvalue `lambda`) at frequency bin `df` and
    /// sampling rate `fs`, made `by` one likelihood: the time-domain one has aliasing in it and
    /// errors that hold for a line of any width, so only a line near or above Nyquist (an
    /// alias, identifiable only up to it) is then taken from the vote for its frequency — unless
    /// the λ law chose its branch (`alias`).
    pub(super) fn of(
        mode: usize,
        lambda: f64,
        s: &super::spectrum::ModeSpectrum,
        (df, fs): (f64, f64),
        by: FittedBy,
    ) -> ModeSpectralFit {
        let exact = by != FittedBy::Whittle;
        let known = |e: f64| e.is_finite().then_some(e);
        let f = s.omega / (2.0 * std::f64::consts::PI);
        let why = if !s.converged {
            Some(ModeNote::NotConverged)
        } else if s.zeta >= 1.0 {
            Some(ModeNote::OverDamped { zeta: s.zeta })
        } else if !exact && f < RESOLVED_BINS * df {
            Some(ModeNote::TooFewBins { bins: f / df })
        } else if by == FittedBy::Unfolded && s.zeta >= super::timedomain::BROAD {
            // As a broad line near Nyquist keeps its Whittle fit (`timedomain`): a clamped–free
            // beam's third mode (ζ = 0.53) voting unfolded rejected a true equipartition in 6
            // of 20.
            Some(ModeNote::BroadAlias { zeta: s.zeta })
        } else if by == FittedBy::Exact && f > 0.5 * EXACT_NYQUIST * fs {
            Some(ModeNote::NearAlias)
        } else if by == FittedBy::Exact
            && f * (1.0 + NYQUIST_HALF_WIDTHS * s.zeta) > super::timedomain::NEAR_NYQUIST * 0.5 * fs
            // An unknown width (NaN) counts as broad.
            && (s.zeta + 2.0 * s.zeta_error >= super::timedomain::BROAD || s.zeta_error.is_nan())
        {
            // A clamped–free beam's third mode (Ω = 0.79 × Nyquist, ζ = 0.53) fitted this way
            // came out within its error in most recordings, but the 7 of 40 that voted were
            // 1.7–6 errors low: narrow, low fits look resolved.
            Some(ModeNote::BroadNearNyquist {
                zeta: s.zeta,
                upper: s.zeta + 2.0 * s.zeta_error,
            })
        } else if by != FittedBy::Unfolded && f > 0.45 * fs {
            Some(ModeNote::AboveNyquist)
        } else if !exact && f + NYQUIST_HALF_WIDTHS * s.zeta * f > 0.5 * fs {
            // Its line folds back on itself: the fitted Ω and ζ of such lines run low by
            // several of their standard errors in simulations (tests/coverage.rs).
            Some(ModeNote::LinePastNyquist)
        } else if s.noise > 3.0 * s.variance
            && super::note::line_over_floor(s, df, fs) < LINE_OVER_FLOOR
        {
            Some(ModeNote::MostlyFlat)
        } else if s.omega_error > 0.25 * s.omega {
            Some(ModeNote::OmegaUncertain)
        } else {
            None
        };
        ModeSpectralFit {
            mode,
            lambda,
            omega: s.omega,
            omega_error: known(s.omega_error),
            zeta: s.zeta,
            // A line narrower than half a bin: its width is the window's, not the mode's.
            zeta_error: known(s.zeta_error)
                .filter(|_| exact || s.zeta * s.omega / (2.0 * std::f64::consts::PI) >= 0.5 * df),
            variance: s.variance,
            variance_error: known(s.variance_error),
            noise: s.noise,
            relaxation_rate: (s.converged && s.zeta >= 1.0)
                .then(|| s.omega * (s.zeta - (s.zeta * s.zeta - 1.0).sqrt())),
            resolved: why.is_none(),
            votes: why.is_none(),
            bins: f / df,
            note: why,
            exact: None,
        }
    }
}
