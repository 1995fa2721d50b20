//! Animals that differ: the between-animal heterogeneity of the continuum constant, the pooled
//! interval that holds the population's constant, and the laws decided within animals.
//!
//! **Heterogeneity.** Each animal fitted alone gives its constant κᵢ (κ of a beam, c of a
//! string) and a standard error sᵢ (its 95 % interval's half-width over 1.96). With wᵢ = 1/sᵢ²
//! and the common mean κ̄ = Σwᵢκᵢ/Σwᵢ, Cochran's Q = Σwᵢ(κᵢ − κ̄)² is χ² on k − 1 degrees of
//! freedom when the k animals share one constant; they differ when its p < [`DIFFER_P`].
//! I² = max(0, (Q − (k − 1))/Q) is the share of the spread the errors do not explain, and
//! DerSimonian–Laird's between-animal variance τ² = max(0, (Q − (k − 1))/(Σw − Σw²/Σw)).
//!
//! **The pooled interval.** The pooled spectrum's interval (its modes' errors) describes the
//! pooled frames, not the population the animals come from: ten animals with κ spread 10 % put
//! it around a mean it covers by chance only. When the animals differ it is replaced by the
//! random-effects interval: weights wᵢ* = 1/(sᵢ² + τ²), mean μ = Σwᵢ*κᵢ/Σwᵢ*, the
//! Hartung–Knapp–Sidik–Jonkman variance V = Σwᵢ*(κᵢ − μ)²/((k − 1)Σwᵢ*), held no smaller than
//! 1/Σwᵢ* (the usual modification: animals agreeing by chance make V too small), and μ ± t·V^½
//! with t the 97.5 % point of Student's t on k − 1 degrees of freedom. A bootstrap's interval,
//! drawn over whole animals, already holds the spread and stands where it was given.
//!
//! **The laws.** Summing the spectra of animals whose frequencies differ by 10 % broadens every
//! line by 10 % of its Ω, a larger share of a narrow low mode's width than of a broad high one's:
//! the pooled ζᵢ ∝ λᵢ^c flattens, and a damping law every animal obeys is rejected. So when the
//! animals differ the laws are decided within animals, from each animal's own weighted slope
//! aᵢ ± sᵢ with its χ²ᵢ on nᵢ − 2 degrees of freedom: one common slope, one intercept per animal
//! (the weighted least squares of all their modes), â = Σ(aᵢ/sᵢ²)/Σ(1/sᵢ²) with standard error
//! (Σ1/sᵢ²)^−½ and goodness of fit χ² = Σχ²ᵢ + Σ(aᵢ − â)²/sᵢ² on Σ(nᵢ − 2) + k − 1 degrees of
//! freedom. It is rejected at p < [`GOODNESS_OF_FIT`], as one animal's is, and otherwise judged
//! as one animal's (`verdict`): undetermined with fewer than three distinct voting modes or an
//! interval wider than the expectation, else consistent when â's interval holds it. A
//! dispersion the pooled spectrum rejects as a driven wave stays rejected.

use super::note::TestNote;
use super::verdict::{TheoryTest, TheoryTests, Verdict, GOODNESS_OF_FIT};
use super::{AnimalFit, FitReport};
use crate::report::fixed;
use statrs::distribution::{ChiSquared, ContinuousCDF, StudentsT};

/// Q's p-value under which the animals differ.
pub const DIFFER_P: f64 = 0.05;

/// The normal distribution's 97.5 % point.
const NORMAL_975: f64 = 1.959_963_984_540_054;

/// What the continuum's interval is when the animals differ.
const BETWEEN: &str = "between animals";

/// How much the animals' constants differ, and what the pool makes of it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Spread {
    /// The animals with a constant and an interval of their own, k.
    pub animals: usize,
    /// Cochran's Q.
    pub q: f64,
    /// Its degrees of freedom, k − 1.
    pub dof: usize,
    /// Its p-value.
    pub p: f64,
    /// I²: the share of the spread the animals' errors do not explain.
    pub i2: f64,
    /// τ², the between-animal variance (DerSimonian–Laird).
    pub tau2: f64,
    /// τ over the random-effects mean.
    pub tau_share: f64,
    /// Whether the animals differ (p < [`DIFFER_P`]).
    pub differ: bool,
    /// The random-effects mean μ.
    pub mean: f64,
    /// Its 95 % interval (Hartung–Knapp–Sidik–Jonkman).
    pub interval: Option<[f64; 2]>,
    /// `within animals` (they differ) or `pooled spectrum`.
    pub tests_from: &'static str,
    /// The pooled spectrum's own tests, where the reported ones are decided within animals.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pooled_tests: Option<TheoryTests>,
}

impl Spread {
    /// Q's p-value as `= 0.23` or `< 1e-16` (it underflows past 1e-300 for animals far apart).
    pub fn p_words(&self) -> String {
        if self.p < 1e-16 {
            "< 1e-16".into()
        } else {
            format!("= {}", super::note::p_value(self.p))
        }
    }
}

/// The heterogeneity of the animals' constants: `None` with fewer than two that have one.
pub(super) fn between(animals: &[AnimalFit]) -> Option<Spread> {
    let each: Vec<(f64, [f64; 2])> = (animals.iter())
        .filter(|a| a.note.is_none())
        .filter_map(|a| Some((a.continuum?, a.continuum_interval?)))
        .collect();
    spread_of(&each)
}

/// The heterogeneity of estimates, each with its 95 % interval (its standard error the
/// half-width over 1.96): `None` with fewer than two usable ones. `discover` uses it for each
/// pooled coefficient over the animals.
pub(crate) fn spread_of(estimates: &[(f64, [f64; 2])]) -> Option<Spread> {
    let each: Vec<(f64, f64)> = (estimates.iter())
        .filter_map(|&(x, [lo, hi])| {
            let s = (hi - lo) / (2.0 * NORMAL_975);
            (s > 0.0 && s.is_finite() && x.is_finite()).then_some((x, s * s))
        })
        .collect();
    let k = each.len();
    if k < 2 {
        return None;
    }
    let mean = |w: &dyn Fn(f64) -> f64| {
        let sw: f64 = each.iter().map(|&(_, v)| w(v)).sum();
        (each.iter().map(|&(x, v)| w(v) * x).sum::<f64>() / sw, sw)
    };
    let (common, sw) = mean(&|v| 1.0 / v);
    let q: f64 = each.iter().map(|&(x, v)| (x - common).powi(2) / v).sum();
    let dof = k - 1;
    let p = ChiSquared::new(dof as f64).map_or(f64::NAN, |d| d.sf(q));
    let sw2: f64 = each.iter().map(|&(_, v)| 1.0 / (v * v)).sum();
    let excess = (q - dof as f64).max(0.0);
    let tau2 = excess / (sw - sw2 / sw);
    let (mu, sw_star) = mean(&|v| 1.0 / (v + tau2));
    let spread: f64 = each
        .iter()
        .map(|&(x, v)| (x - mu).powi(2) / (v + tau2))
        .sum();
    let var = (spread / (dof as f64 * sw_star)).max(1.0 / sw_star);
    let t = StudentsT::new(0.0, 1.0, dof as f64).map_or(f64::NAN, |d| d.inverse_cdf(0.975));
    let half = t * var.sqrt();
    Some(Spread {
        animals: k,
        q,
        dof,
        p,
        i2: if q > 0.0 { excess / q } else { 0.0 },
        tau2,
        tau_share: tau2.sqrt() / mu,
        differ: p < DIFFER_P,
        mean: mu,
        interval: half.is_finite().then_some([mu - half, mu + half]),
        tests_from: "pooled spectrum",
        pooled_tests: None,
    })
}

/// The spread of `report`'s animals into it: with animals that differ, the random-effects
/// interval on the constant (unless a bootstrap's stands) and the laws decided within animals.
pub(super) fn apply(report: &mut FitReport) {
    let Some(mut spread) = between(&report.animals) else {
        return;
    };
    if spread.differ {
        let interval = spread.interval;
        if let Some(c) =
            (report.continuum.as_mut()).filter(|c| c.interval_from != Some("bootstrap"))
        {
            c.interval = interval;
            c.interval_from = interval.map(|_| BETWEEN);
        }
        let mut own: Vec<TheoryTests> = (report.animals.iter())
            .filter(|a| a.note.is_none())
            .filter_map(|a| a.tests.clone())
            .collect();
        spread.pooled_tests = Some(report.tests.clone());
        let laws: [fn(&mut TheoryTests) -> &mut TheoryTest; 3] = [
            |t| &mut t.equipartition,
            |t| &mut t.dispersion,
            |t| &mut t.damping,
        ];
        for law in laws {
            let each: Vec<&TheoryTest> = own.iter_mut().map(|t| &*law(t)).collect();
            let pooled = law(&mut report.tests);
            if !matches!(pooled.note, Some(TestNote::DrivenWave { .. })) {
                *pooled = within(&each, pooled.expected);
            }
        }
        spread.tests_from = "within animals";
    }
    report.spread = Some(spread);
}

/// One law decided within animals from each one's own test (see the module header).
pub(super) fn within(each: &[&TheoryTest], expected: f64) -> TheoryTest {
    let mut modes: Vec<usize> = each.iter().flat_map(|t| t.modes.iter().copied()).collect();
    modes.sort_unstable();
    modes.dedup();
    let fits: Vec<(f64, f64, f64, usize)> = each
        .iter()
        .filter_map(|t| {
            let (se, chi2, dof) = t.scatter?;
            (se > 0.0 && se.is_finite()).then_some((t.exponent?, se, chi2, dof))
        })
        .collect();
    let test = |exponent, interval, verdict, note| TheoryTest {
        exponent,
        interval,
        expected,
        verdict,
        modes: modes.clone(),
        note,
        scatter: None,
    };
    let few = TestNote::TooFew { n: modes.len() };
    if fits.is_empty() {
        return test(None, None, Verdict::Undetermined, Some(few));
    }
    let sw: f64 = fits.iter().map(|f| 1.0 / (f.1 * f.1)).sum();
    let slope = fits.iter().map(|f| f.0 / (f.1 * f.1)).sum::<f64>() / sw;
    let se = sw.sqrt().recip();
    let chi2: f64 = (fits.iter())
        .map(|f| f.2 + ((f.0 - slope) / f.1).powi(2))
        .sum();
    let dof = fits.iter().map(|f| f.3).sum::<usize>() + fits.len() - 1;
    let p = ChiSquared::new(dof as f64).map_or(f64::NAN, |d| d.sf(chi2));
    if dof > 0 && p < GOODNESS_OF_FIT {
        let note = TestNote::LawDoesNotFit { chi2, dof, p };
        return test(Some(slope), None, Verdict::Rejected, Some(note));
    }
    let half = NORMAL_975 * se;
    let interval = [slope - half, slope + half];
    let scatter =
        (dof > 0 && chi2 > 1.21 * dof as f64).then_some(TestNote::WithinChance { chi2, dof, p });
    let (verdict, note) = super::verdict::judged(modes.len(), (interval, half), expected, scatter);
    test(Some(slope), Some(interval), verdict, note)
}

/// The line `fit` prints about the animals' spread (nothing without one).
pub(super) fn text(r: &FitReport) -> String {
    let (Some(s), Some(c)) = (&r.spread, &r.continuum) else {
        return String::new();
    };
    let symbol = c.symbol();
    let q = format!(
        "Q = {} on {} dof, p {}; I² = {} %, τ = {} % of {symbol}",
        fixed(s.q, 1),
        s.dof,
        s.p_words(),
        fixed(100.0 * s.i2, 0),
        fixed(100.0 * s.tau_share, 1),
    );
    if !s.differ {
        return format!(
            "  between animals: the {} animals' {symbol} agree within their errors ({q}): the pooled interval stands and the laws are decided on the pooled spectrum\n",
            s.animals
        );
    }
    let interval = match (c.interval_from, s.interval) {
        (Some(BETWEEN), Some([lo, hi])) => format!(
            "{symbol} = {} [{}, {}] (95 %, random effects: DerSimonian–Laird weights, Hartung–Knapp t on {} dof) is the interval above",
            fixed(s.mean, 6),
            fixed(lo, 6),
            fixed(hi, 6),
            s.dof
        ),
        _ => format!("the {} interval above stands", c.interval_from.unwrap_or("")),
    };
    format!(
        "  between animals: the {} animals' {symbol} differ beyond their errors ({q}): {interval}; the laws are decided within animals (each one's own slopes, combined), not on the pooled spectrum, whose lines the spread broadens\n",
        s.animals
    )
}

#[cfg(test)]
mod tests {
    use super::{between, within, TestNote, TheoryTest, Verdict};
    use crate::fit::AnimalFit;

    /// An animal with constant `kappa` of standard error `se`.
    fn animal(kappa: f64, se: f64) -> AnimalFit {
        let half = super::NORMAL_975 * se;
        AnimalFit {
            recording: String::new(),
            frames: 1000,
            frames_lost: 0,
            omega: Some(1.0),
            beta: Some(1.0),
            first_share: None,
            pca_variance_share: Vec::new(),
            mode_overlap: Vec::new(),
            continuum: Some(kappa),
            continuum_interval: Some([kappa - half, kappa + half]),
            tests: None,
            note: None,
        }
    }

    #[test]
    fn three_animals_by_hand() {
        // w = 100 each, κ̄ = 2, Q = 200 on 2 dof, I² = 0.99, τ² = 198/(300 − 100) = 0.99;
        // w* = 1, μ = 2, V = 2/(2·3) = 1/3 (= 1/Σw*), t(2 dof) = 4.302653.
        let animals: Vec<AnimalFit> = [1.0, 2.0, 3.0].map(|k| animal(k, 0.1)).into();
        let s = between(&animals).expect("a spread");
        assert!(
            (s.q - 200.0).abs() < 1e-9 && s.dof == 2 && s.differ,
            "{s:?}"
        );
        assert!((s.i2 - 0.99).abs() < 1e-12 && (s.tau2 - 0.99).abs() < 1e-12);
        let half = 4.302_652_729_696_142 * (1.0_f64 / 3.0).sqrt();
        let [lo, hi] = s.interval.expect("an interval");
        assert!((lo - (2.0 - half)).abs() < 1e-6 && (hi - (2.0 + half)).abs() < 1e-6);
        // One animal, or one with a note, is no spread.
        let mut noted = animal(5.0, 0.1);
        noted.note = Some("not pooled".into());
        assert!(between(&[animal(1.0, 0.1), noted]).is_none());
    }

    /// An animal's test: slope `a` ± `se`, χ² `chi2` on one dof over modes 2, 3, 4.
    fn slope(a: f64, se: f64, chi2: f64) -> TheoryTest {
        TheoryTest {
            exponent: Some(a),
            interval: Some([a - 1.96 * se, a + 1.96 * se]),
            expected: 0.5,
            verdict: Verdict::Consistent,
            modes: vec![2, 3, 4],
            note: None,
            scatter: Some((se, chi2, 1)),
        }
    }

    #[test]
    fn laws_within_animals_combine_their_slopes() {
        let judge = |tests: &[TheoryTest]| within(&tests.iter().collect::<Vec<_>>(), 0.5);
        // Ten animals at the law: one common slope, 0.5 ± 0.1/√10.
        let kept = judge(&vec![slope(0.5, 0.1, 1.0); 10]);
        assert_eq!(kept.verdict, Verdict::Consistent, "{kept:?}");
        let [lo, hi] = kept.interval.unwrap();
        assert!(((hi - lo) / 2.0 - 1.96 * 0.1 / 10f64.sqrt()).abs() < 1e-3);
        // Each one's interval holds 0.5, their common one does not.
        let off = judge(&vec![slope(0.35, 0.1, 1.0); 10]);
        assert_eq!(off.verdict, Verdict::Rejected, "{off:?}");
        // Slopes that disagree beyond their errors: the law does not fit.
        let apart: Vec<TheoryTest> = (0..10)
            .map(|i| slope(if i % 2 == 0 { 0.1 } else { 0.9 }, 0.1, 1.0))
            .collect();
        let split = judge(&apart);
        assert!(
            matches!(split.note, Some(TestNote::LawDoesNotFit { .. })),
            "{split:?}"
        );
        assert_eq!(split.verdict, Verdict::Rejected);
    }
}
