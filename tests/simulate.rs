//! Scenario: the dynamics. Exact modal propagators conserve energy without damping, lose it
//! monotonically with damping, agree with an independent RK4 integration of the discretised
//! equations, and under noise reach the equipartition variances.

use theory_search::discretise::operator_matrix;
use theory_search::dynamics::{simulate, Config, Forcing, Initial, Sample};
use theory_search::modal::{field_modes, Params};
use theory_search::model::{Boundary, Model};

fn config(points: usize, dt: f64, steps: u64, every: u64) -> Config {
    Config {
        points,
        order: 4,
        dt,
        steps,
        every,
        temperature: 0.0,
        seed: 1,
        initial: Vec::new(),
        forcing: Vec::new(),
    }
}

fn initial(field: &str, mode: usize, q: f64, v: f64) -> Initial {
    Initial {
        field: field.into(),
        mode,
        displacement: q,
        velocity: v,
    }
}

fn run(params: &Params, c: &Config) -> Vec<Sample> {
    let mut out = Vec::new();
    simulate(&Model::larva(), params, c, |s| {
        out.push(s.clone());
        Ok(())
    })
    .unwrap();
    out
}

fn undamped() -> Params {
    let mut p = Params::default();
    for s in ["s", "b", "t"] {
        p.set(&format!("zeta_{s}"), 0.0).unwrap();
        p.set(&format!("omega_{s}"), 1.3).unwrap();
    }
    p
}

#[test]
fn energy_is_conserved_without_damping_over_a_million_steps() {
    let mut c = config(12, 0.01, 1_000_000, 50_000);
    c.initial = vec![
        initial("x", 1, 0.3, 0.1),
        initial("x", 6, -0.2, 0.0),
        initial("theta", 3, 0.5, -0.4),
        initial("y", 2, 1.0, 0.0),
        initial("z", 7, 0.1, 0.2),
    ];
    let samples = run(&undamped(), &c);
    assert_eq!(samples.len(), 21);
    let e0 = samples[0].energy;
    assert!(e0 > 0.0);
    for s in &samples {
        assert!(
            (s.energy - e0).abs() <= 1e-12 * e0,
            "t = {}: {} vs {e0}",
            s.t,
            s.energy
        );
    }
}

#[test]
fn energy_decays_monotonically_with_damping() {
    let mut c = config(12, 0.05, 4000, 1);
    c.initial = vec![
        initial("x", 2, 1.0, 0.0),
        initial("theta", 1, 0.7, 0.3),
        initial("y", 3, 0.5, -1.0),
    ];
    let samples = run(&Params::default(), &c);
    for w in samples.windows(2) {
        assert!(
            w[1].energy <= w[0].energy * (1.0 + 1e-14),
            "energy rose at t = {}",
            w[1].t
        );
    }
    assert!(samples.last().unwrap().energy < 0.05 * samples[0].energy);
}

/// q̈ = −ω²Dq − 2ζωDq̇ + f(t), integrated by classical RK4 on the full discretised system.
fn rk4(
    (d, omega, zeta): (&[Vec<i64>], f64, f64),
    q0: Vec<f64>,
    v0: Vec<f64>,
    force: &dyn Fn(f64) -> Vec<f64>,
    t_end: f64,
    h: f64,
) -> Vec<f64> {
    let n = q0.len();
    let dmul = |x: &[f64]| -> Vec<f64> {
        (0..n)
            .map(|i| (0..n).map(|j| d[i][j] as f64 * x[j]).sum())
            .collect()
    };
    let rhs = |t: f64, q: &[f64], v: &[f64]| -> (Vec<f64>, Vec<f64>) {
        let (dq, dv) = (dmul(q), dmul(v));
        let f = force(t);
        let a = (0..n)
            .map(|i| -omega * omega * dq[i] - 2.0 * zeta * omega * dv[i] + f[i])
            .collect();
        (v.to_vec(), a)
    };
    let (mut q, mut v, mut t) = (q0, v0, 0.0);
    let steps = (t_end / h).round() as usize;
    let axpy = |x: &[f64], a: f64, y: &[f64]| -> Vec<f64> {
        x.iter().zip(y).map(|(p, r)| p + a * r).collect()
    };
    for _ in 0..steps {
        let (k1q, k1v) = rhs(t, &q, &v);
        let (k2q, k2v) = rhs(
            t + h / 2.0,
            &axpy(&q, h / 2.0, &k1q),
            &axpy(&v, h / 2.0, &k1v),
        );
        let (k3q, k3v) = rhs(
            t + h / 2.0,
            &axpy(&q, h / 2.0, &k2q),
            &axpy(&v, h / 2.0, &k2v),
        );
        let (k4q, k4v) = rhs(t + h, &axpy(&q, h, &k3q), &axpy(&v, h, &k3v));
        for i in 0..n {
            q[i] += h / 6.0 * (k1q[i] + 2.0 * k2q[i] + 2.0 * k3q[i] + k4q[i]);
            v[i] += h / 6.0 * (k1v[i] + 2.0 * k2v[i] + 2.0 * k3v[i] + k4v[i]);
        }
        t += h;
    }
    q
}

#[test]
fn agrees_with_an_independent_rk4_integration() {
    let points = 9;
    let mut params = Params::default();
    params.set("omega_b", 1.7).unwrap();
    params.set("zeta_b", 0.2).unwrap();
    params.set("omega_s", 0.9).unwrap();
    params.set("zeta_s", 0.05).unwrap();
    let t_end = 6.0;
    let mut c = config(points, 0.5, 12, 12);
    c.initial = vec![
        initial("y", 2, 0.8, 0.0),
        initial("y", 4, 0.0, 0.5),
        initial("y", 1, 0.2, 0.1),
        initial("x", 3, 0.4, 0.0),
    ];
    c.forcing = vec![
        Forcing {
            field: "y".into(),
            mode: 3,
            constant: 0.3,
            amplitude: 0.5,
            frequency: 2.1,
            phase: 0.4,
        },
        Forcing {
            field: "y".into(),
            mode: 0,
            constant: 0.1,
            amplitude: 0.2,
            frequency: 0.7,
            phase: 0.0,
        },
        Forcing {
            field: "x".into(),
            mode: 2,
            constant: 0.0,
            amplitude: 0.25,
            frequency: 1.3,
            phase: 1.0,
        },
    ];
    let ours = run(&params, &c).pop().unwrap();
    assert!((ours.t - t_end).abs() < 1e-12);
    let modes = field_modes(&Model::larva(), 4, points, &params, None, true).unwrap();
    for (f, field, boundary, k, omega, zeta) in [
        (2, "y", Boundary::FREE, 2, 1.7, 0.2),
        (0, "x", Boundary::Periodic, 1, 0.9, 0.05),
    ] {
        let shapes = modes[f].spectrum.shapes.as_ref().unwrap();
        let n = shapes.nrows();
        let to_field = |coefs: &[(usize, f64)]| -> Vec<f64> {
            (0..n)
                .map(|j| coefs.iter().map(|&(i, a)| a * shapes[(j, i)]).sum())
                .collect()
        };
        let q0 = to_field(
            &c.initial
                .iter()
                .filter(|i| i.field == field)
                .map(|i| (i.mode, i.displacement))
                .collect::<Vec<_>>(),
        );
        let v0 = to_field(
            &c.initial
                .iter()
                .filter(|i| i.field == field)
                .map(|i| (i.mode, i.velocity))
                .collect::<Vec<_>>(),
        );
        let forces: Vec<Forcing> = c
            .forcing
            .iter()
            .filter(|g| g.field == field)
            .cloned()
            .collect();
        let force = |t: f64| {
            to_field(
                &forces
                    .iter()
                    .map(|g| {
                        (
                            g.mode,
                            g.constant + g.amplitude * (g.frequency * t + g.phase).cos(),
                        )
                    })
                    .collect::<Vec<_>>(),
            )
        };
        let d = operator_matrix(k, boundary, points).unwrap();
        let reference = rk4((&d, omega, zeta), q0, v0, &force, t_end, 1e-3);
        for (j, (a, b)) in ours.positions[f].iter().zip(&reference).enumerate() {
            assert!((a - b).abs() < 1e-9, "{field}[{j}]: {a} vs RK4 {b}");
        }
    }
}

#[test]
fn noise_reaches_the_equipartition_variances() {
    let kt = 0.5;
    let mut params = Params::default();
    params.set("zeta_b", 0.8).unwrap();
    let points = 6;
    let mut c = config(points, 0.2, 200_000, 1);
    c.temperature = kt;
    c.seed = 42;
    let modes = field_modes(&Model::larva(), 4, points, &params, None, false).unwrap();
    let y = &modes[2];
    let (mut sum, mut sq, mut count) = (vec![0.0; points], vec![0.0; points], 0.0);
    simulate(&Model::larva(), &params, &c, |s| {
        if s.t > 200.0 {
            for i in 2..points {
                sum[i] += s.modal[2][i];
                sq[i] += s.modal[2][i] * s.modal[2][i];
            }
            count += 1.0;
        }
        Ok(())
    })
    .unwrap();
    for i in 2..points {
        let mean = sum[i] / count;
        let var = sq[i] / count - mean * mean;
        let want = kt / y.modes[i].frequency.powi(2);
        // The slowest mode decorrelates in ~1/γ ≈ 40 time units: ~5000 independent samples, so
        // a 6 % band is about four standard errors.
        assert!(
            (var / want - 1.0).abs() < 0.06,
            "mode {i}: variance {var} vs kT/ω² = {want}"
        );
    }
}

#[test]
fn the_same_seed_gives_the_same_run() {
    let mut c = config(8, 0.1, 200, 10);
    c.temperature = 1.0;
    let a: Vec<f64> = run(&Params::default(), &c)
        .iter()
        .map(|s| s.energy)
        .collect();
    let b: Vec<f64> = run(&Params::default(), &c)
        .iter()
        .map(|s| s.energy)
        .collect();
    assert_eq!(a, b);
    c.seed = 2;
    let d: Vec<f64> = run(&Params::default(), &c)
        .iter()
        .map(|s| s.energy)
        .collect();
    assert_ne!(a, d);
}

#[test]
fn bad_settings_are_errors() {
    let p = Params::default();
    let bad = |c: Config| {
        simulate(&Model::larva(), &p, &c, |_| Ok(()))
            .unwrap_err()
            .to_string()
    };
    let mut c = config(12, 0.0, 10, 1);
    assert!(bad(c.clone()).contains("time step"));
    c.dt = f64::NAN;
    assert!(bad(c.clone()).contains("time step"));
    c.dt = 0.1;
    c.temperature = -1.0;
    assert!(bad(c.clone()).contains("temperature"));
    c.temperature = 0.0;
    c.initial = vec![initial("q", 0, 1.0, 0.0)];
    assert!(bad(c.clone()).contains("unknown field"));
    c.initial = vec![initial("y", 99, 1.0, 0.0)];
    assert!(bad(c.clone()).contains("modes 0…11"));
    c.initial.clear();
    c.points = 2;
    assert!(bad(c).contains("too few"));
}

#[test]
fn overflow_is_an_error_not_garbage() {
    let mut c = config(5, 0.1, 2, 1);
    c.initial = vec![initial("y", 2, 1e300, 1e300)];
    let err = simulate(&Model::larva(), &Params::default(), &c, |_| Ok(()))
        .unwrap_err()
        .to_string();
    assert!(err.contains("overflowed"), "{err}");
}

#[test]
fn principal_components_of_simulated_postures_are_the_modes() {
    // End to end: term engine → operators → modal solver → Langevin dynamics → PCA. With
    // ζ_b = 1 the slowest bending mode decorrelates in ~1/(ζωλ₂) ≈ 11 time units, so the 150 000
    // units simulated give ~13 000 independent postures: ~1.2 % error on each variance.
    let mut params = Params::default();
    params.set("zeta_b", 1.0).unwrap();
    let theory = theory_search::theory::Theory::new(Model::larva(), 4, 8, params).unwrap();
    // The lateral field by role (y in the larva).
    let check =
        theory_search::behaviour::equipartition_from_dynamics(&theory, None, 300_000, 0.5, 3)
            .unwrap();
    assert_eq!(check.field, "y");
    for k in 0..3 {
        assert!(
            check.overlap[k] > 0.99,
            "PC {k} overlap {}",
            check.overlap[k]
        );
        let (pca, theory) = (check.pca_variance_share[k], check.theory_variance_share[k]);
        assert!(
            (pca - theory).abs() < 0.05 * theory,
            "PC {k}: share {pca} vs {theory}"
        );
    }
}
