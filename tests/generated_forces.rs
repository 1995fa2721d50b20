//! The generated forces (`templates/forces.rs.tera`, emitted by `theory-search emit`): the
//! checked-in larva's against the generated linear operators (another template), and the source
//! emitted for nonlinear bodies, compiled here by rustc on its own, against the integrator's
//! potential (central differences of its energy), dissipation and active forces, its Jacobians
//! against differences of the integrator's force.

mod common;

use std::collections::BTreeMap;
use std::process::Command;

use theory_search::dynamics::nonlinear::NonlinearBody;
use theory_search::generated::forces::FORCES;
use theory_search::generated::operators::OPERATORS;
use theory_search::model::Model;

/// A reproducible number in [−½, ½).
fn draws(seed: u64, n: usize) -> Vec<f64> {
    let mut s = seed | 1;
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s % 10_000) as f64 / 10_000.0 - 0.5
        })
        .collect()
}

#[test]
fn the_larvas_forces_are_its_linear_operators() {
    // F = −c·D u − 2c′·D v for each field, D from the generated operators.
    for (k, f) in FORCES.iter().enumerate() {
        for points in [5, 9, 12] {
            let n = f.unknowns(points).unwrap();
            let c = draws(7 + k as u64, f.coefficients.len())
                .iter()
                .map(|x| x + 1.0)
                .collect::<Vec<_>>();
            let (u, v) = (draws(11 + points as u64, n), draws(13 + points as u64, n));
            let mut out = vec![0.0; n];
            f.force(points, &c, &u, &v, &mut out).unwrap();
            let mut want = vec![0.0; n];
            for (density, x, scale) in [("lagrangian", &u, 1.0), ("rayleigh", &v, 2.0)] {
                let op = OPERATORS
                    .iter()
                    .find(|o| o.field == f.field && o.density == density)
                    .unwrap();
                let mut dx = vec![0.0; n];
                (op.apply)(points, x, &mut dx).unwrap();
                // The field's one coefficient of this density (the larva's squares).
                let slot = f
                    .coefficients
                    .iter()
                    .position(|name| name.starts_with("c'") == (density == "rayleigh"))
                    .unwrap();
                for (w, d) in want.iter_mut().zip(&dx) {
                    *w -= scale * c[slot] * d;
                }
            }
            for (a, b) in out.iter().zip(&want) {
                assert!(
                    (a - b).abs() < 1e-12,
                    "{} at N = {points}: {a} against {b}",
                    f.field
                );
            }
            // And the Jacobians are those constant matrices.
            let (mut du, mut dv) = (vec![vec![0.0; n]; n], vec![vec![0.0; n]; n]);
            f.jacobian(
                points,
                &c,
                &u,
                &v,
                &mut |i, j, x| du[i][j] += x,
                &mut |i, j, x| dv[i][j] += x,
            )
            .unwrap();
            let mut e = vec![0.0; n];
            e[n / 2] = 1.0;
            let mut col = vec![0.0; n];
            f.force(points, &c, &e, &vec![0.0; n], &mut col).unwrap();
            for i in 0..n {
                assert!((du[i][n / 2] - col[i]).abs() < 1e-12, "{}: ∂F/∂u", f.field);
            }
        }
    }
    assert!(matches!(
        FORCES[0].unknowns(2),
        Err(theory_search::generated::forces::ForceError::TooFewPoints { .. })
    ));
    let err = FORCES[0]
        .force(12, &[1.0], &[0.0; 11], &[0.0; 11], &mut [0.0; 11])
        .unwrap_err();
    assert!(err.to_string().contains("length 1"), "{err}");
}

/// A harness around generated source: evaluates F and the Jacobians of every field at given
/// points, coefficients, u and v, printing `F k i x`, `U k i j x`, `V k i j x`, `M k i j x` lines.
fn harness(source: &str, points: usize, inputs: &[(Vec<f64>, Vec<f64>, Vec<f64>)]) -> String {
    let list = |x: &[f64]| {
        let cells: Vec<String> = x.iter().map(|v| format!("{v:?}")).collect();
        format!("&[{}]", cells.join(", "))
    };
    let mut main = String::from("\nfn main() {\n");
    for (k, (c, u, v)) in inputs.iter().enumerate() {
        main += &format!(
            "    {{ let f = &FORCES[{k}]; let (c, u, v): (&[f64], &[f64], &[f64]) = ({}, {}, {});\n      let mut out = vec![0.0; u.len()]; f.force({points}, c, u, v, &mut out).unwrap();\n      for (i, x) in out.iter().enumerate() {{ println!(\"F {k} {{i}} {{x:?}}\"); }}\n      f.jacobian({points}, c, u, v, &mut |i, j, x| println!(\"U {k} {{i}} {{j}} {{x:?}}\"), &mut |i, j, x| println!(\"V {k} {{i}} {{j}} {{x:?}}\")).unwrap();\n      f.mass({points}, c, v, &mut |i, j, x| println!(\"M {k} {{i}} {{j}} {{x:?}}\")).unwrap(); }}\n",
            list(c),
            list(u),
            list(v)
        );
    }
    main += "}\n";
    // One directory per harness: the tests run in parallel.
    static RUNS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let _run = RUNS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir_held = common::scratch("forces");
    let dir = dir_held.path();
    let file = dir.join("forces.rs");
    std::fs::write(&file, format!("{source}{main}")).unwrap();
    let exe = dir.join("forces");
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let built = Command::new(rustc)
        .args(["--edition", "2021", "-O", "-o"])
        .arg(&exe)
        .arg(&file)
        .output()
        .unwrap();
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    let run = Command::new(&exe).output().unwrap();
    assert!(run.status.success());
    String::from_utf8(run.stdout).unwrap()
}

fn check_emitted(model: &Model, points: usize) {
    let source = theory_search::codegen::forces_source(model, 4).unwrap();
    // The coefficient names, in the generated order, from the source itself.
    let names = theory_search::dynamics::nonlinear::coefficient_names(model, 4).unwrap();
    let values: BTreeMap<String, f64> = names
        .iter()
        .zip(draws(99, names.len()))
        .map(|(n, x)| (n.clone(), 0.5 + x))
        .collect();
    let body = NonlinearBody::new(model, 4, points, &values).unwrap();
    // Each field's c in the order its `coefficients` list gives: read from the source.
    let mut inputs = Vec::new();
    let lists: Vec<&str> = source
        .split("coefficients: &[")
        .skip(1)
        .map(|s| s.split(']').next().unwrap())
        .collect();
    assert_eq!(lists.len(), body.fields.len());
    for (k, f) in body.fields.iter().enumerate() {
        let c: Vec<f64> = lists[k]
            .split(',')
            .map(|s| s.trim().trim_matches('"'))
            .filter(|s| !s.is_empty())
            .map(|name| values[name])
            .collect();
        let u: Vec<f64> = draws(5 + k as u64, f.unknowns);
        let v: Vec<f64> = draws(17 + k as u64, f.unknowns);
        inputs.push((c, u, v));
    }
    let printed = harness(&source, points, &inputs);
    let mut force: BTreeMap<(usize, usize), f64> = BTreeMap::new();
    let mut du: BTreeMap<(usize, usize, usize), f64> = BTreeMap::new();
    let mut dv: BTreeMap<(usize, usize, usize), f64> = BTreeMap::new();
    let mut mass: BTreeMap<(usize, usize, usize), f64> = BTreeMap::new();
    for line in printed.lines() {
        let w: Vec<&str> = line.split(' ').collect();
        let at = |i: usize| w[i].parse::<usize>().unwrap();
        match w[0] {
            "F" => {
                force.insert((at(1), at(2)), w[3].parse().unwrap());
            }
            "U" => *du.entry((at(1), at(2), at(3))).or_default() += w[4].parse::<f64>().unwrap(),
            "V" => *dv.entry((at(1), at(2), at(3))).or_default() += w[4].parse::<f64>().unwrap(),
            "M" => *mass.entry((at(1), at(2), at(3))).or_default() += w[4].parse::<f64>().unwrap(),
            _ => {}
        }
    }
    for (k, f) in body.fields.iter().enumerate() {
        let (_, u, v) = &inputs[k];
        // −∂V/∂u_i by central differences of the integrator's energy at rest (v = 0).
        let potential = |x: &[f64]| {
            let mut state: Vec<(Vec<f64>, Vec<f64>)> = body
                .fields
                .iter()
                .map(|g| (vec![0.0; g.unknowns], vec![0.0; g.unknowns]))
                .collect();
            state[k].0 = x.to_vec();
            body.energy(&state)
        };
        let friction = f.dissipation_gradient(v);
        // The mass ∇²T(v) is the integrator's.
        let m = f.mass(v);
        for i in 0..f.unknowns {
            for j in 0..f.unknowns {
                let got = mass.get(&(k, i, j)).copied().unwrap_or(0.0);
                assert!(
                    (got - m[(i, j)]).abs() < 1e-12,
                    "{} field {}: M[{i}][{j}] = {got} against {}",
                    model.name,
                    f.id,
                    m[(i, j)]
                );
            }
        }
        for i in 0..f.unknowns {
            let h = 1e-5;
            let (mut up, mut down) = (u.clone(), u.clone());
            up[i] += h;
            down[i] -= h;
            let want = -(potential(&up) - potential(&down)) / (2.0 * h) - friction[i]
                + f.active_force(u, v)[i];
            let got = force[&(k, i)];
            assert!(
                (got - want).abs() < 1e-7 * (1.0 + want.abs()),
                "{} field {}: F[{i}] = {got} against {want}",
                model.name,
                f.id
            );
        }
        // ∂F/∂u by differences of the potential's gradient, column by column: the second
        // differences of the energy.
        for j in 0..f.unknowns {
            for i in 0..f.unknowns {
                let h = 1e-4;
                let at = |di: f64, dj: f64| {
                    let mut x = u.clone();
                    x[i] += di;
                    x[j] += dj;
                    potential(&x)
                };
                // The active forces' part, by central differences of the integrator's.
                let pushed = |d: f64| {
                    let mut x = u.clone();
                    x[j] += d;
                    f.active_force(&x, v)[i]
                };
                let want = -(at(h, h) - at(h, -h) - at(-h, h) + at(-h, -h)) / (4.0 * h * h)
                    + (pushed(h) - pushed(-h)) / (2.0 * h);
                let got = du.get(&(k, i, j)).copied().unwrap_or(0.0);
                assert!(
                    (got - want).abs() < 1e-5 * (1.0 + want.abs()),
                    "{} field {}: ∂F/∂u[{i}][{j}] = {got} against {want}",
                    model.name,
                    f.id
                );
            }
        }
        // ∂F/∂v = −∇²R(v) + ∂f/∂v, by central differences of the integrator's.
        for j in 0..f.unknowns {
            let h = 1e-5;
            let at = |d: f64| {
                let mut x = v.clone();
                x[j] += d;
                let r = f.dissipation_gradient(&x);
                let a = f.active_force(u, &x);
                r.iter().zip(a).map(|(r, a)| a - r).collect::<Vec<f64>>()
            };
            let (up, down) = (at(h), at(-h));
            for i in 0..f.unknowns {
                let want = (up[i] - down[i]) / (2.0 * h);
                let got = dv.get(&(k, i, j)).copied().unwrap_or(0.0);
                assert!(
                    (got - want).abs() < 1e-6 * (1.0 + want.abs()),
                    "{} field {}: ∂F/∂v[{i}][{j}] = {got} against {want}",
                    model.name,
                    f.id
                );
            }
        }
    }
}

#[test]
fn emitted_nonlinear_forces_are_the_integrators() {
    let dir = env!("CARGO_MANIFEST_DIR");
    let tethered = Model::from_toml(
        &std::fs::read_to_string(format!("{dir}/tables/models/tethered.toml")).unwrap(),
    )
    .unwrap();
    check_emitted(&tethered, 6);
    let mut larva = Model::larva();
    larva.lagrangian.beyond_leading = 1;
    larva.rayleigh.beyond_leading = 1;
    check_emitted(&larva, 9);
    let zebrafish = Model::from_toml(
        &std::fs::read_to_string(format!("{dir}/tables/models/zebrafish.toml")).unwrap(),
    )
    .unwrap();
    check_emitted(&zebrafish, 8);
    // The worm at the next order: kinetic terms ½k2(∂ts x)² and k1(∂t x)⁴ in the mass.
    let mut worm = Model::from_toml(
        &std::fs::read_to_string(format!("{dir}/tables/models/worm.toml")).unwrap(),
    )
    .unwrap();
    worm.lagrangian.beyond_leading = 1;
    worm.rayleigh.beyond_leading = 1;
    check_emitted(&worm, 7);
}

/// The `[active]` section's forces, emitted: the crawler's linear a∂s x, a∂s³y and gyroscopic
/// g∂t∂s φ, and at the next layers its nonlinear ones ((∂s x)²·∂ts x among them), against the
/// integrator's active forces, with their Jacobians in u and v; and around a ring.
#[test]
fn emitted_active_forces_are_the_integrators() {
    let dir = env!("CARGO_MANIFEST_DIR");
    let read = |name: &str| {
        Model::from_toml(&std::fs::read_to_string(format!("{dir}/{name}")).unwrap()).unwrap()
    };
    let mut crawler = read("tables/models/crawler.toml");
    check_emitted(&crawler, 9);
    crawler.set_beyond_leading(3);
    check_emitted(&crawler, 11);
    check_emitted(&read("tables/models/peristalsis.toml"), 8);
    check_emitted(&read("tests/common/ring.toml"), 10);
}
