//! The sampling clock of a time column: its interval (the first step, within range), and the
//! frames missing where a later step spans several intervals. A reader that sees the next rows
//! ahead seeds the interval first: when frames were lost right after the first one, the first
//! step spans several intervals, and taking it for the interval would refuse every later
//! (shorter) step as uneven.

use crate::report::number;

/// The shortest sampling interval a time column may have: below it the squares of the
/// frequencies it samples overflow (so does Nyquist's π/Δt itself near 10⁻³⁰⁸, where the
/// spectra came out flat). Between it and about 10⁻¹⁵⁴ the fit says its ω is out of range.
pub const MIN_TIME_STEP: f64 = 1e-300;

/// A time column that is not a uniform clock.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ClockError {
    /// Time went backwards or stood still.
    #[error("time {} does not increase (previous {})", number(*.t), number(*.last))]
    NotIncreasing {
        /// This frame's time.
        t: f64,
        /// The previous frame's time.
        last: f64,
    },
    /// A step that is not a whole number of sampling intervals.
    #[error("time step {} after t = {} is not a whole number of sampling intervals {}", number(*.gap), number(*.last), number(*.dt))]
    Uneven {
        /// The step.
        gap: f64,
        /// The previous frame's time.
        last: f64,
        /// The sampling interval (the first step).
        dt: f64,
    },
    /// A sampling interval below [`MIN_TIME_STEP`].
    #[error("time step {} is out of range (below {MIN_TIME_STEP:e}): the squares of the frequencies it samples (up to π/Δt) overflow f64; rescale the time column", number(*.dt))]
    TooFine {
        /// The sampling interval (the first step).
        dt: f64,
    },
}

/// The sampling clock: the first time step is the interval; later steps must be whole numbers
/// of it (within 1 %), the surplus being frames missing from the file.
#[derive(Debug, Default)]
pub(crate) struct Clock {
    last_t: Option<f64>,
    pub(crate) dt: Option<f64>,
}

/// How many rows ahead a reader looks for the interval.
pub(crate) const LOOK_AHEAD: usize = 64;

impl Clock {
    /// Before the first step: when the first step (to the first of `ahead`, the next rows'
    /// times after the last one stepped to, or between the first two of them) is a whole number
    /// m ≥ 2 of the shortest positive step among them, frames were lost right after the first
    /// and the shortest step is the interval. Otherwise the first step stays the interval, as
    /// [`Clock::step`] takes it.
    pub(crate) fn seed(&mut self, ahead: impl IntoIterator<Item = f64>) {
        if self.dt.is_some() {
            return;
        }
        let mut last = self.last_t;
        let (mut first, mut shortest) = (None, f64::INFINITY);
        for t in ahead.into_iter().take(LOOK_AHEAD) {
            if let Some(l) = last {
                let gap = t - l;
                first.get_or_insert(gap);
                if gap > 0.0 && gap < shortest {
                    shortest = gap;
                }
            }
            last = Some(t);
        }
        let Some(first) = first else {
            return;
        };
        let m = (first / shortest).round();
        if shortest >= MIN_TIME_STEP
            && m >= 2.0
            && (first - m * shortest).abs() <= 0.01 * shortest * m
        {
            self.dt = Some(shortest);
        }
    }

    /// Check the step to `t`; returns how many frames are missing before it.
    pub(crate) fn step(&mut self, t: f64) -> Result<usize, ClockError> {
        let Some(last) = self.last_t.replace(t) else {
            return Ok(0);
        };
        let gap = t - last;
        if gap <= 0.0 {
            return Err(ClockError::NotIncreasing { t, last });
        }
        if self.dt.is_none() && gap < MIN_TIME_STEP {
            return Err(ClockError::TooFine { dt: gap });
        }
        let dt = *self.dt.get_or_insert(gap);
        // The common step, one interval: what the rule below gives, without its division.
        if (gap - dt).abs() <= 0.01 * dt {
            return Ok(0);
        }
        let steps = (gap / dt).round();
        if steps >= 1.0 && (gap - steps * dt).abs() <= 0.01 * dt * steps.max(1.0) {
            // Frames missing before this one; a step of absurd length is one long gap.
            Ok((steps as usize).saturating_sub(1))
        } else {
            Err(ClockError::Uneven { gap, last, dt })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Clock;

    /// Frames lost right after the first: the first step spans three intervals.
    #[test]
    fn a_first_step_over_lost_frames_is_not_the_interval() {
        let times = [0.0, 0.6, 0.8, 1.0, 1.6, 1.8];
        let mut seeded = Clock::default();
        seeded.seed(times);
        let missing: Vec<usize> = times.iter().map(|&t| seeded.step(t).unwrap()).collect();
        assert_eq!(missing, [0, 2, 0, 0, 2, 0]);
        // Unseeded, the first step is the interval and the next one is refused.
        let mut plain = Clock::default();
        plain.step(0.0).unwrap();
        plain.step(0.6).unwrap();
        assert!(plain.step(0.8).is_err());
        // A clock whose steps wobble within 1 % keeps its first step.
        let mut wobbly = Clock::default();
        wobbly.seed([0.0, 0.1, 0.2005, 0.2999, 0.4]);
        assert_eq!(wobbly.dt, None);
    }
}
