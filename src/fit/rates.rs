//! Recordings sampled at different rates: each rate group fitted as its own pool (spectra in
//! frames of different lengths cannot be summed), and the continuum constant combined across
//! the groups, which is possible because κ (or c) is a constant of the body in physical units:
//! every group's time unit is the recordings' one unit (files that state different units are
//! refused before this).
//!
//! **Across the rates.** Each group gives κ_g with a standard error s_g (its 95 % interval's
//! half-width over 1.96). Cochran's Q = Σw_g(κ_g − κ̄)², w_g = 1/s_g², κ̄ = Σw_gκ_g/Σw_g, is χ²
//! on G − 1 degrees of freedom when the groups share one constant. When they do (p ≥
//! [`DIFFER_P`](super::spread::DIFFER_P)) the combined constant is the fixed-effect κ̄ ± 1.96
//! (Σw_g)^−½; when they differ it is the random-effects mean with the Hartung–Knapp interval
//! of [`spread`](super::spread), and the report says the rates disagree (a rate-dependent
//! bias: too few frames per period in one group, or different animals).

use super::{AnimalFit, FitError, FitReport};
use crate::markup::bound_line;
use crate::report::{fixed, number};

/// The normal distribution's 97.5 % point.
const NORMAL_975: f64 = 1.959_963_984_540_054;

/// One rate group: its sampling interval and its pool's fit, summarised.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RateGroup {
    /// The sampling interval (time units per frame).
    pub interval: f64,
    /// Its animals' names.
    pub animals: Vec<String>,
    /// Its pooled fit's constants and tests (`recording` names the group), or why it has none.
    pub fit: AnimalFit,
}

impl RateGroup {
    /// The group sampled every `interval`, its animals `names`, fitted as `report` (or not).
    pub(super) fn of(
        interval: f64,
        names: Vec<String>,
        report: Result<&FitReport, &FitError>,
    ) -> RateGroup {
        let label = format!("sampled every {}", number(interval));
        let fit = match report {
            Ok(r) => AnimalFit::of(&label, &r.recording, r),
            Err(e) => AnimalFit::unfitted(&label, &bound_line(&e.to_string())),
        };
        RateGroup {
            interval,
            animals: names,
            fit,
        }
    }
}

/// The rate groups into `report`, the fit of the first group (sampled every `interval`, its
/// animals `names`): each other group's (interval, animals, fit) summarised, its animals listed
/// beside the pool's with their group, and κ combined across the groups.
pub(super) fn attach(
    report: &mut FitReport,
    (interval, names): (f64, Vec<String>),
    others: Vec<(f64, Vec<String>, Result<FitReport, FitError>)>,
) {
    let mut groups = vec![RateGroup::of(interval, names, Ok(report))];
    for (rate, names, fitted) in others {
        let group = RateGroup::of(rate, names, fitted.as_ref());
        let note = format!(
            "rate group {}, sampled every {}",
            groups.len() + 1,
            number(rate)
        );
        let own = match fitted {
            Ok(r) if !r.animals.is_empty() => r.animals,
            _ => vec![AnimalFit {
                recording: group.animals.join(", "),
                ..group.fit.clone()
            }],
        };
        report.animals.extend(own.into_iter().map(|mut a| {
            a.note = Some(a.note.map_or(note.clone(), |n| format!("{note}; {n}")));
            a
        }));
        groups.push(group);
    }
    report.across_rates = across(&groups);
    report.rate_groups = groups;
}

/// The continuum constant across the rate groups.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct AcrossRates {
    /// The groups with a constant and an interval, G.
    pub groups: usize,
    /// Cochran's Q.
    pub q: f64,
    /// Its p-value on G − 1 degrees of freedom.
    pub p: f64,
    /// Whether the groups differ.
    pub differ: bool,
    /// The combined constant (fixed effect, or random effects when they differ).
    pub constant: f64,
    /// Its 95 % interval.
    pub interval: Option<[f64; 2]>,
}

/// The constant across `groups`, `None` with fewer than two that have one.
pub(super) fn across(groups: &[RateGroup]) -> Option<AcrossRates> {
    let fits: Vec<AnimalFit> = groups.iter().map(|g| g.fit.clone()).collect();
    let spread = super::spread::between(&fits)?;
    let each: Vec<(f64, f64)> = fits
        .iter()
        .filter(|f| f.note.is_none())
        .filter_map(|f| {
            let [lo, hi] = f.continuum_interval?;
            let s = (hi - lo) / (2.0 * NORMAL_975);
            Some((f.continuum?, 1.0 / (s * s)))
        })
        .collect();
    let (constant, interval) = if spread.differ {
        (spread.mean, spread.interval)
    } else {
        let sw: f64 = each.iter().map(|e| e.1).sum();
        let mean = each.iter().map(|&(k, w)| k * w).sum::<f64>() / sw;
        let half = NORMAL_975 / sw.sqrt();
        (mean, Some([mean - half, mean + half]))
    };
    Some(AcrossRates {
        groups: spread.animals,
        q: spread.q,
        p: spread.p,
        differ: spread.differ,
        constant,
        interval,
    })
}

/// The lines `fit` prints about the rate groups (nothing with one rate).
pub(super) fn text(r: &FitReport) -> String {
    if r.rate_groups.is_empty() {
        return String::new();
    }
    let symbol = r.continuum.as_ref().map_or("κ", |c| c.symbol());
    let time = r.units.time.as_deref().unwrap_or("time unit");
    let mut t = format!(
        "  rate groups: the animals were sampled at {} rates, each fitted as its own pool (the fit above is the first); {symbol} in body lengths and {time}s, one unit for all:\n",
        r.rate_groups.len()
    );
    for (i, g) in r.rate_groups.iter().enumerate() {
        let value = match (g.fit.continuum, g.fit.continuum_interval, &g.fit.note) {
            (_, _, Some(why)) => format!("no {symbol}: {why}"),
            (Some(k), Some([lo, hi]), None) => {
                format!(
                    "{symbol} = {} [{}, {}]",
                    fixed(k, 6),
                    fixed(lo, 6),
                    fixed(hi, 6)
                )
            }
            (Some(k), None, None) => format!("{symbol} = {} (no interval)", fixed(k, 6)),
            (None, _, None) => format!("no {symbol}"),
        };
        t += &format!(
            "    {}. every {} {time}: {} animal(s), {} frames: {value}\n",
            i + 1,
            number(g.interval),
            g.animals.len(),
            g.fit.frames
        );
    }
    if let Some(a) = &r.across_rates {
        let interval = a.interval.map_or(String::new(), |[lo, hi]| {
            format!(" [{}, {}] (95 %)", fixed(lo, 6), fixed(hi, 6))
        });
        let how = if a.differ {
            "the rates disagree beyond their errors: random effects; a rate with too few frames per period, or different animals?"
        } else {
            "the rates agree within their errors: inverse-variance weights"
        };
        t += &format!(
            "    across the {} rates: {symbol} = {}{interval} (Q = {}, p = {}; {how})\n",
            a.groups,
            fixed(a.constant, 6),
            fixed(a.q, 2),
            super::note::p_value(a.p)
        );
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn group(interval: f64, kappa: f64, se: f64) -> RateGroup {
        let half = NORMAL_975 * se;
        let none = FitError::Invalid("none".into());
        let mut g = RateGroup::of(interval, vec!["a".into()], Err(&none));
        g.fit.note = None;
        g.fit.continuum = Some(kappa);
        g.fit.continuum_interval = Some([kappa - half, kappa + half]);
        g
    }

    #[test]
    fn groups_that_agree_give_the_inverse_variance_mean() {
        // w = 1/0.01² and 1/0.02²: κ̄ = (4·1.00 + 1·1.02)/5 = 1.004, se = 0.02/√5.
        let a = across(&[group(0.1, 1.0, 0.01), group(0.05, 1.02, 0.02)]).unwrap();
        assert!(!a.differ && a.groups == 2);
        assert!((a.constant - 1.004).abs() < 1e-12, "{a:?}");
        let [lo, hi] = a.interval.unwrap();
        let half = NORMAL_975 * 0.02 / 5f64.sqrt();
        assert!((lo - (1.004 - half)).abs() < 1e-9 && (hi - (1.004 + half)).abs() < 1e-9);
        // Q = (1.0 − 1.004)²/0.01² + (1.02 − 1.004)²/0.02² = 0.16 + 0.64 = 0.8.
        assert!((a.q - 0.8).abs() < 1e-9);
        // Groups far apart differ, and one group alone is no combination.
        assert!(
            across(&[group(0.1, 1.0, 0.01), group(0.05, 1.2, 0.01)])
                .unwrap()
                .differ
        );
        assert!(across(&[group(0.1, 1.0, 0.01)]).is_none());
    }
}
