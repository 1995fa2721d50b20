//! Scenario: the seed's forward/backward asymmetry (App. C) and axial–transverse resonance
//! (App. D), against their analytic results.

use theory_search::behaviour::{asymmetry, floquet, stability_chart};

#[test]
fn the_larva_ratio_from_the_seeds_coupling() {
    // c = −√2/2, A = ω = 1: frequencies √2 and −√2/2, ratio 1:2.
    let a = asymmetry(-std::f64::consts::FRAC_1_SQRT_2, 1.0, 1.0).unwrap();
    assert!((a.forward - 2f64.sqrt()).abs() < 1e-14);
    assert!((a.backward + std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-14);
    assert!((a.ratio - 0.5).abs() < 1e-14);
    assert!(
        (a.simulated_forward - a.forward).abs() < 1e-6,
        "{}",
        a.simulated_forward
    );
    assert!(
        (a.simulated_backward - a.backward).abs() < 1e-6,
        "{}",
        a.simulated_backward
    );
}

#[test]
fn the_amplitude_enters_squared_not_linearly() {
    // With A = 2 the simulated pair follows ω_s² + cA²ω_s − ω² = 0 (roots 1 ± √2 for c = −½),
    // not the seed's printed ω_s² + cAω_s − ω² = 0 (roots (1 ± √5)/2).
    let a = asymmetry(-0.5, 2.0, 1.0).unwrap();
    assert!((a.forward - (1.0 + 2f64.sqrt())).abs() < 1e-12);
    assert!((a.backward - (1.0 - 2f64.sqrt())).abs() < 1e-12);
    assert!(
        (a.simulated_forward - a.forward).abs() < 1e-5,
        "{}",
        a.simulated_forward
    );
    assert!(
        (a.simulated_backward - a.backward).abs() < 1e-5,
        "{}",
        a.simulated_backward
    );
    assert!((a.simulated_forward - (1.0 + 5f64.sqrt()) / 2.0).abs() > 0.5);
}

#[test]
fn no_coupling_no_asymmetry_and_bad_input_is_refused() {
    let a = asymmetry(0.0, 0.7, 1.3).unwrap();
    assert!((a.forward - 1.3).abs() < 1e-14 && (a.backward + 1.3).abs() < 1e-14);
    assert!(asymmetry(f64::NAN, 1.0, 1.0).is_err());
    assert!(asymmetry(0.1, -1.0, 1.0).is_err());
    assert!(asymmetry(0.1, 1.0, 0.0).is_err());
}

#[test]
fn without_forcing_the_monodromy_is_a_rotation() {
    for ratio in [0.7, 1.3, 2.0, 3.1] {
        let p = floquet(1.0, 0.0, ratio).unwrap();
        let want = 2.0 * (2.0 * std::f64::consts::PI / ratio).cos();
        assert!(
            (p.trace - want).abs() < 1e-8,
            "ω/λ = {ratio}: {} vs {want}",
            p.trace
        );
        assert!(p.stable);
    }
}

#[test]
fn the_first_tongue_sits_at_twice_the_natural_frequency() {
    let eps = 0.05;
    let stable = |r: f64| floquet(1.0, eps, r).unwrap().stable;
    assert!(!stable(2.0));
    assert!(stable(1.9) && stable(2.1));
    // Edges at 2√(1 ∓ ε) + O(ε²): bisect each.
    let edge = |mut inside: f64, mut outside: f64| {
        for _ in 0..50 {
            let mid = 0.5 * (inside + outside);
            if stable(mid) {
                outside = mid
            } else {
                inside = mid
            }
        }
        0.5 * (inside + outside)
    };
    let (lo, hi) = (edge(2.0, 1.9), edge(2.0, 2.1));
    assert!(
        (lo - 2.0 * (1.0 - eps).sqrt()).abs() < 2.0 * eps * eps,
        "{lo}"
    );
    assert!(
        (hi - 2.0 * (1.0 + eps).sqrt()).abs() < 2.0 * eps * eps,
        "{hi}"
    );
    // The chart has the tongue: unstable near 2, stable far from it, at every ε > 0 row.
    let chart = stability_chart(1.0, (1.5, 2.5), 0.2, (41, 5)).unwrap();
    for row in chart.chunks(41).skip(1) {
        assert!(!row[20].stable, "ε = {}", row[20].epsilon);
        assert!(row[0].stable && row[40].stable);
    }
}

use theory_search::behaviour::{integrate, pair_statistics, sample_pair};

#[test]
fn partition_function_matches_quadrature_and_the_kink() {
    for (omega, beta, m) in [
        (1.0, 1.0, 0.0),
        (1.3, 2.0, 0.7),
        (0.5, 10.0, -2.0),
        (2.0, 0.3, 0.05),
    ] {
        let s = pair_statistics(omega, beta, m).unwrap();
        let rel =
            (s.partition_function - s.partition_function_quadrature).abs() / s.partition_function;
        assert!(rel < 1e-9, "Z at ({omega}, {beta}, {m}): {rel}");
        // ⟨A⟩ against the quadrature of A·p(A).
        let w = |a: f64| {
            if a <= 0.0 {
                0.0
            } else {
                (-0.5 * beta * (m * m / (a * a) + omega * omega * a * a) + beta * m.abs() * omega)
                    .exp()
            }
        };
        let upper = (m.abs() / omega).sqrt() + 14.0 / (omega * beta.sqrt());
        let mean = integrate(&|a| a * w(a), 0.0, upper, 1e-15) / integrate(&w, 0.0, upper, 1e-15);
        assert!(
            (s.mean_amplitude - mean).abs() < 1e-8 * mean,
            "⟨A⟩ {} vs {mean}",
            s.mean_amplitude
        );
        // F(M) − F(0) = |M|ω: a kink at M = 0 with slopes ∓ω.
        let f0 = pair_statistics(omega, beta, 0.0).unwrap().free_energy;
        assert!((s.free_energy - f0 - m.abs() * omega).abs() < 1e-12 * (1.0 + s.free_energy.abs()));
    }
    assert_eq!(
        pair_statistics(1.0, 1.0, 0.5).unwrap().free_energy_slope,
        1.0
    );
    assert_eq!(
        pair_statistics(1.0, 1.0, -0.5).unwrap().free_energy_slope,
        -1.0
    );
    assert!(pair_statistics(1.0, -1.0, 0.0).is_err());
    assert!(pair_statistics(f64::NAN, 1.0, 0.0).is_err());
}

/// Kolmogorov–Smirnov statistic of `xs` against the CDF `cdf`.
fn ks(mut xs: Vec<f64>, cdf: impl Fn(f64) -> f64) -> f64 {
    xs.sort_by(f64::total_cmp);
    let n = xs.len() as f64;
    xs.iter().enumerate().fold(0.0f64, |d, (i, &x)| {
        let c = cdf(x);
        d.max((c - i as f64 / n).abs())
            .max(((i + 1) as f64 / n - c).abs())
    })
}

fn thinned(xs: &[f64], ess: f64) -> Vec<f64> {
    let k = ((xs.len() as f64 / ess).ceil() as usize).max(1);
    xs.iter().step_by(k).copied().collect()
}

#[test]
fn metropolis_marginals_match_the_analytic_densities() {
    let (omega, beta, m) = (1.3, 2.0, 0.7);
    let s = sample_pair(omega, beta, m, 400_000, 7).unwrap();
    assert!(
        s.acceptance_rate > 0.1 && s.acceptance_rate < 0.9,
        "{}",
        s.acceptance_rate
    );
    assert!(
        s.effective_sample_size > 2000.0,
        "{}",
        s.effective_sample_size
    );
    // KS at the 0.1 % level on thinned (about independent) draws: D < 1.95/√n.
    let w = |a: f64| {
        if a <= 0.0 {
            0.0
        } else {
            (-0.5 * beta * (m * m / (a * a) + omega * omega * a * a) + beta * m * omega).exp()
        }
    };
    let upper = (m / omega).sqrt() + 14.0 / (omega * beta.sqrt());
    let norm = integrate(&w, 0.0, upper, 1e-14);
    let a = thinned(&s.amplitude, s.effective_sample_size);
    let crit = 1.95 / (a.len() as f64).sqrt();
    let d = ks(a.clone(), |x| {
        integrate(&w, 0.0, x.min(upper), 1e-11) / norm
    });
    assert!(d < crit, "A: D = {d}, critical {crit}");
    let phi = thinned(&s.phase, s.effective_sample_size);
    let d = ks(phi.clone(), |x| x / (2.0 * std::f64::consts::PI));
    assert!(d < 1.95 / (phi.len() as f64).sqrt(), "φ: D = {d}");
    let p = thinned(&s.momentum, s.effective_sample_size);
    let d = ks(p.clone(), |x| {
        0.5 * (1.0 + libm::erf(x * (beta / 2.0).sqrt()))
    });
    assert!(d < 1.95 / (p.len() as f64).sqrt(), "p_A: D = {d}");
    let analytic = pair_statistics(omega, beta, m).unwrap().mean_amplitude;
    assert!(
        (s.mean_amplitude - analytic).abs()
            < 5.0 * 0.5 / (omega * beta.sqrt() * s.effective_sample_size.sqrt()),
        "{} vs {analytic}",
        s.mean_amplitude
    );
}

#[test]
fn at_zero_momentum_the_modal_coordinates_follow_the_conditioned_density() {
    // On the slice M = 0 the amplitude density is exp(−βω²A²/2) (canonical coordinates: no
    // polar Jacobian), so A is half-normal and X₁ = A cos φ is *not* the Gaussian of the
    // unconstrained ensemble: P(X₁ ≤ x) = (1/2π)∫ P(A cos φ ≤ x) dφ.
    let (omega, beta) = (0.8, 3.0);
    let s = sample_pair(omega, beta, 0.0, 400_000, 11).unwrap();
    let x1: Vec<f64> = s
        .amplitude
        .iter()
        .zip(&s.phase)
        .map(|(a, f)| a * f.cos())
        .collect();
    let x1 = thinned(&x1, s.effective_sample_size);
    let k = omega * (beta / 2.0).sqrt();
    let f_a = |a: f64| if a <= 0.0 { 0.0 } else { libm::erf(a * k) };
    let cdf = |x: f64| {
        let at = |phi: f64| {
            let c = phi.cos();
            if c > 0.0 {
                f_a(x / c)
            } else if c < 0.0 {
                1.0 - f_a(x / c)
            } else if x >= 0.0 {
                1.0
            } else {
                0.0
            }
        };
        integrate(&at, 0.0, 2.0 * std::f64::consts::PI, 1e-9) / (2.0 * std::f64::consts::PI)
    };
    let d = ks(x1.clone(), cdf);
    assert!(d < 1.95 / (x1.len() as f64).sqrt(), "X₁: D = {d}");
    // Reproducible.
    let again = sample_pair(omega, beta, 0.0, 1000, 11).unwrap();
    let once = sample_pair(omega, beta, 0.0, 1000, 11).unwrap();
    assert_eq!(again.amplitude, once.amplitude);
}

use theory_search::behaviour::{pair_orbit, PairKind};
use theory_search::modal::{field_modes, Params};
use theory_search::model::Model;
use theory_search::theory::Theory;

/// The embedded larva on `points` points with `params`.
fn larva(points: usize, params: &Params) -> Theory {
    Theory::new(Model::larva(), 4, points, params.clone()).unwrap()
}

#[test]
fn peristalsis_is_a_travelling_wave_with_conserved_momentum() {
    let model = Model::larva();
    let params = Params::default();
    let _ = model;
    let theory = larva(12, &params);
    for m in [0.3f64, -0.3] {
        let o = pair_orbit(&theory, PairKind::Peristalsis, m, 200.0).unwrap();
        assert!(o.momentum_drift < 1e-10, "M drift {}", o.momentum_drift);
        assert!((o.amplitude - (0.3 / o.omega).sqrt()).abs() < 1e-15);
        assert!(
            (o.angular_velocity - o.omega * m.signum()).abs() < 1e-9 * o.omega,
            "{}",
            o.angular_velocity
        );
        // The crest goes once round the (periodic) body per period, forwards or backwards.
        let per_period = o.body_rate * 2.0 * std::f64::consts::PI / o.omega;
        assert!((per_period.abs() - 1.0).abs() < 1e-9, "{per_period}");
    }
}

#[test]
fn rolling_turns_at_the_first_bending_frequency() {
    let model = Model::larva();
    let params = Params::default();
    let theory = larva(12, &params);
    let o = pair_orbit(&theory, PairKind::Rolling, 0.05, 50.0).unwrap();
    let modes = field_modes(&model, 4, 12, &params, None, false).unwrap();
    let first_bending = modes[2].modes[2].frequency;
    assert!((o.omega - first_bending).abs() < 1e-15);
    assert!(o.momentum_drift < 1e-10);
    // The C-bend's direction at the head turns at the first bending frequency.
    assert!(
        (o.body_rate - first_bending).abs() < 1e-9 * first_bending,
        "{} vs {first_bending}",
        o.body_rate
    );
    assert!(pair_orbit(&theory, PairKind::Rolling, 0.0, 5.0).is_err());
}

use theory_search::behaviour::{analytic_step, step_response};

#[test]
fn rearing_and_hunching_settle_on_the_shifted_equilibrium() {
    let model = Model::larva();
    // The first bending mode decays at ζ₁ω₁ = ζ_b·ω_b·λ₁ ≈ 0.0024 per unit time at ζ_b = 0.1:
    // run for 20 000 units (about 50 decay times).
    for (field, zeta) in [("z", 0.1), ("z", 0.3), ("x", 0.1)] {
        let mut params = Params::default();
        let scale = if field == "x" { "s" } else { "b" };
        params.set(&format!("zeta_{scale}"), zeta).unwrap();
        let theory = Theory::new(model.clone(), 4, 12, params).unwrap();
        let index = model.fields.iter().position(|f| f.id == field).unwrap();
        let r = step_response(&theory, "step", index, 0.02, 20_000.0).unwrap();
        // The exact propagator reproduces the analytic step response.
        let scale_q = r.equilibrium.abs();
        assert!(
            r.max_error < 1e-10 * scale_q.max(1e-300),
            "{field}: {}",
            r.max_error
        );
        // After many damping times it sits at Q* = F/ω², in the mode's shape.
        let last = r.transient.last().unwrap().1;
        assert!(
            (last - r.equilibrium).abs() < 1e-3 * scale_q,
            "{field}: {last} vs {}",
            r.equilibrium
        );
    }
    // The three regimes of the analytic form meet continuously at critical damping.
    let (w, f, t) = (0.7, 0.3, 2.5);
    let crit = analytic_step(w, 1.0, f, t);
    assert!((analytic_step(w, 1.0 - 1e-7, f, t) - crit).abs() < 1e-6);
    assert!((analytic_step(w, 1.0 + 1e-7, f, t) - crit).abs() < 1e-6);
}

use theory_search::behaviour::{explore, fit_beta};

#[test]
fn unbiased_exploration_matches_equipartition_and_the_linear_bend() {
    let model = Model::larva();
    let params = Params::default();
    // Small amplitude (large β): the 3-point bend is Gaussian with the linearised variance.
    let _ = model;
    let theory = larva(12, &params);
    let e = explore(&theory, 1e5, 200_000, 9).unwrap();
    assert!(
        (e.bend_sd / e.bend_sd_linear - 1.0).abs() < 0.01,
        "{} vs {}",
        e.bend_sd,
        e.bend_sd_linear
    );
    let d = ks(e.bend.clone(), |x| {
        0.5 * (1.0 + libm::erf(x / (e.bend_sd_linear * 2f64.sqrt())))
    });
    assert!(d < 1.95 / (e.bend.len() as f64).sqrt(), "bend KS D = {d}");
    for (v, t) in e.modal_variance.iter().zip(&e.theory_variance) {
        assert!((v / t - 1.0).abs() < 0.02, "{v} vs {t}");
    }
    assert!(
        (e.fitted_beta / 1e5 - 1.0).abs() < 0.02,
        "{}",
        e.fitted_beta
    );
    // At large amplitude the bend saturates below the linear prediction.
    let hot = explore(&theory, 1.0, 50_000, 9).unwrap();
    assert!(hot.bend_sd < hot.bend_sd_linear);
}

#[test]
fn beta_is_recovered_exactly_from_exact_variances() {
    let c = [3.0, 1.0, 0.25, 0.1];
    let v: Vec<f64> = c.iter().map(|ci| ci / 7.5).collect();
    assert!((fit_beta(&v, &c).unwrap() - 7.5).abs() < 1e-12);
    assert!(fit_beta(&[1.0], &[1.0, 2.0]).is_err());
    assert!(fit_beta(&[-1.0], &[1.0]).is_err());
}
