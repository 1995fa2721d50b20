//! Active forces (`theory-search active`): the classification against an oracle that searches
//! for a density instead of using the homotopy formula, the requirement verdicts against the
//! transformations applied by hand, and the command on the shipped crawler.

mod common;

use std::collections::BTreeMap;

use rand::RngExt;

use num_rational::Rational64;
use theory_search::active::{allows, classify, ForceClass};
use theory_search::enumerate::{monomials, BoundShape, Bounds};
use theory_search::jet::{
    euler_lagrange, mono_of, poly_of, space_euler, term_of, JetMono, JetPoly,
};
use theory_search::rules::rule;
use theory_search::term::{Deriv, Term};

/// Does some combination of `basis` map to `target` under `op`? Exact Gaussian elimination on
/// the coefficients of the jet monomials.
fn reaches(basis: &[JetPoly], op: &dyn Fn(&JetPoly) -> JetPoly, target: &JetPoly) -> bool {
    let images: Vec<JetPoly> = basis.iter().map(op).collect();
    let mut rows: Vec<JetMono> = images.iter().flat_map(|p| p.keys().cloned()).collect();
    rows.extend(target.keys().cloned());
    rows.sort();
    rows.dedup();
    let zero = Rational64::from_integer(0);
    // Augmented matrix: one row per monomial, one column per basis image, then the target.
    let mut m: Vec<Vec<Rational64>> = rows
        .iter()
        .map(|r| {
            images
                .iter()
                .chain(std::iter::once(target))
                .map(|p| p.get(r).copied().unwrap_or(zero))
                .collect()
        })
        .collect();
    let cols = images.len();
    let mut pivot_row = 0;
    for c in 0..cols {
        let Some(p) = (pivot_row..m.len()).find(|&r| m[r][c] != zero) else {
            continue;
        };
        m.swap(pivot_row, p);
        for r in 0..m.len() {
            if r != pivot_row && m[r][c] != zero {
                let f = m[r][c] / m[pivot_row][c];
                let pivot = m[pivot_row].clone();
                for (x, v) in m[r].iter_mut().zip(&pivot).skip(c) {
                    *x -= f * v;
                }
            }
        }
        pivot_row += 1;
    }
    // Consistent exactly when no row is 0 = non-zero.
    m.iter()
        .all(|row| row[..cols].iter().any(|v| *v != zero) || row[cols] == zero)
}

/// The single-field monomials of degree `degree` with `tau` time and `sigma` space derivatives
/// in all, as polynomials (a velocity jet only when `velocity`).
fn densities(degree: u32, tau: u32, sigma: u32, velocity: bool) -> Vec<JetPoly> {
    let n = degree.max(tau + sigma).max(1);
    monomials(&Bounds::for_order(BoundShape::TauAndSigma, n))
        .into_iter()
        .filter(|t| {
            let o = t.orders();
            o.epsilon == degree && o.tau == tau && o.sigma == sigma
        })
        .filter(|t| !velocity || t.factors().iter().all(|f| f.deriv.t == 1))
        .map(|t| poly_of(&t))
        .collect()
}

/// The oracle: variational when some density of one degree more with the same derivative
/// counts has f as its Euler–Lagrange expression; of Rayleigh form when some density of the
/// velocity jet has f as δ/δv over s; active otherwise.
fn oracle(t: &Term) -> ForceClass {
    let o = t.orders();
    let f = poly_of(t);
    if reaches(
        &densities(o.epsilon + 1, o.tau, o.sigma, false),
        &euler_lagrange,
        &f,
    ) {
        let odd = t.factors().iter().map(|x| x.deriv.t * x.power).sum::<u32>() % 2 == 1;
        return if odd {
            ForceClass::Gyroscopic
        } else {
            ForceClass::Conservative
        };
    }
    let velocity = t.factors().iter().all(|x| x.deriv.t == 1);
    let e1 = |p: &JetPoly| space_euler(p).remove(&1).unwrap_or_default();
    if velocity && reaches(&densities(o.epsilon + 1, o.tau + 1, o.sigma, true), &e1, &f) {
        return ForceClass::Dissipative;
    }
    ForceClass::Active
}

#[test]
fn the_classes_agree_with_a_search_for_densities_at_orders_4_and_6() {
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    for order in [4, 6] {
        let shape = if order == 4 {
            BoundShape::TauAndSigma
        } else {
            BoundShape::TauPlusSigma
        };
        for t in monomials(&Bounds::for_order(shape, order)) {
            // Inertia and above are not forces (OST); degrees beyond 3 only grow the search.
            if t.max_time_order() > 1 || t.orders().epsilon > 3 {
                continue;
            }
            let engine = classify(&t, &|_| "φ".into()).kind;
            assert_eq!(engine, oracle(&t), "order {order}: {:?}", mono_of(&t));
            *seen.entry(format!("{engine:?}")).or_default() += 1;
        }
    }
    println!("{seen:?}");
    for class in ["Conservative", "Gyroscopic", "Dissipative", "Active"] {
        assert!(
            seen.get(class).copied().unwrap_or(0) > 3,
            "{class}: {seen:?}"
        );
    }
}

/// A force from its text, on placeholder field 0.
fn force(text: &str) -> Term {
    text.parse().expect("a term")
}

#[test]
fn a_force_transforms_as_its_field() {
    // (rule, allowed, struck): φ → −φ wants odd forces; s → −s even ones; a translation and a
    // rotation leave a force unchanged; a boost too (so no bare velocity); no inertia.
    let cases: [(&str, &[&str], &[&str]); 6] = [
        ("REF", &["φ", "∂s φ", "(∂s φ)^3"], &["φ^2", "∂s φ·∂ss φ"]),
        (
            "PAR",
            &["φ", "∂ss φ", "(∂s φ)^2"],
            &["∂s φ", "∂sss φ", "∂ts φ"],
        ),
        ("TRAN", &["∂s φ", "∂t φ"], &["φ", "φ·∂s φ"]),
        ("ROT", &["∂ss φ", "∂t φ"], &["∂s φ", "φ"]),
        ("GAL", &["∂ts φ", "∂ss φ"], &["∂t φ", "φ"]),
        ("OST", &["∂t φ", "∂ts φ"], &["∂tt φ"]),
    ];
    for (code, allowed, struck) in cases {
        let r = rule(code).expect("a rule");
        for t in allowed {
            assert!(allows(r, &force(t)), "{code} should allow {t}");
        }
        for t in struck {
            assert!(!allows(r, &force(t)), "{code} should strike {t}");
        }
    }
}

#[test]
fn the_crawler_has_active_forces_and_the_larva_none() {
    let out = common::binary(&[
        "active",
        "--model",
        "tables/models/crawler.toml",
        "--format",
        "json",
    ]);
    assert_eq!(out.0, 0, "{}", out.2);
    let v: serde_json::Value = serde_json::from_str(&out.1).unwrap();
    let fields = v["fields"].as_array().unwrap();
    // The lowest active force on the axial field is the gradient ∂s x: odd under s → −s, so
    // only a body with a head has it.
    assert_eq!(fields[0]["active"][0]["term"], "∂s x");
    assert_eq!(fields[0]["active"][0]["space_parity"], -1);
    // The bending field's gyroscopic force ∂ts y: the KIN-struck Lagrangian ∂t y ∂s y.
    assert_eq!(fields[1]["gyroscopic"][0]["term"], "∂ts y");
    assert_eq!(fields[1]["gyroscopic"][0]["kind"], "gyroscopic");
    let (code, _, err) = common::binary(&["active"]);
    assert_eq!(code, 2);
    assert!(err.contains("no [active] section"), "{err}");
    // An order whose candidates would not fit the budget is refused at once, from counts.
    let (code, _, err) = common::binary(&[
        "active",
        "--model",
        "tables/models/crawler.toml",
        "--order",
        "32",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("candidate forces"), "{err}");
}

/// `active --format csv` (offered by `--help`) gives one row per listed force, the JSON's
/// forces in order; the reasons hold commas and colons, so the cells must be quoted to read back.
#[test]
fn the_active_report_has_a_csv_form_with_the_jsons_rows() {
    let run = |format: &str| {
        let (code, out, err) = common::binary(&[
            "active",
            "--model",
            "tables/models/crawler.toml",
            "--format",
            format,
        ]);
        assert_eq!(code, 0, "{err}");
        out
    };
    let v: serde_json::Value = serde_json::from_str(&run("json")).unwrap();
    let mut expected = Vec::new();
    for f in v["fields"].as_array().unwrap() {
        for class in ["active", "gyroscopic", "uncarried"] {
            for x in f[class].as_array().unwrap() {
                expected.push(vec![
                    f["field"].as_str().unwrap().to_string(),
                    class.to_string(),
                    x["term"].as_str().unwrap().to_string(),
                    x["coefficient"].as_str().unwrap_or("").to_string(),
                    x["time_parity"].to_string(),
                    x["space_parity"].to_string(),
                    x["why"].as_str().unwrap().to_string(),
                ]);
            }
        }
    }
    assert!(!expected.is_empty());
    let csv = run("csv");
    let mut reader = csv::Reader::from_reader(csv.as_bytes());
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(
        header,
        [
            "field",
            "class",
            "term",
            "coefficient",
            "delta",
            "epsilon",
            "tau",
            "sigma",
            "time_parity",
            "space_parity",
            "why"
        ]
    );
    let rows: Vec<Vec<String>> = reader
        .records()
        .map(|r| {
            let r = r.unwrap();
            [0, 1, 2, 3, 8, 9, 10]
                .iter()
                .map(|&i| r[i].to_string())
                .collect()
        })
        .collect();
    assert_eq!(rows, expected);
    assert!(
        expected.iter().any(|r| r[6].contains(',')),
        "no reason to quote"
    );
    // The help offers exactly the formats the command gives.
    let (_, help, _) = common::binary(&["active", "--help"]);
    assert!(help.contains("csv"), "{help}");
}

/// One axial field whose `[active]` section lacks OST: `∂ttt x` enters its equation.
const ROD_WITHOUT_OST: &str = r#"
name = "rod"
description = "one axial field, forces without OST"

[[fields]]
id = "x"
symbol = "x"
meaning = "axial displacement"
boundary = "free"

[lagrangian]
bound = "tau-plus-sigma"
columns = ["OST", "TRAN", "REF"]

[lagrangian.requirements]
x = ["OST", "TRAN", "REF"]

[rayleigh]
bound = "tau-and-sigma"
columns = ["DIS", "TRAN", "GAL", "REF"]

[rayleigh.requirements]
x = ["DIS", "TRAN", "GAL", "REF"]

[active]
bound = "tau-and-sigma"
columns = ["TRAN", "REF", "GAL"]

[active.requirements]
x = ["TRAN", "REF", "GAL"]
"#;

/// Issue 52 item 6: without OST, `equations` prints ∂t³x with its coefficient but says under
/// the equation, and in its JSON, that it is inertia and not a force (the integrator refuses
/// it); with OST nothing is said. The coefficient it names is the one `simulate` refuses.
#[test]
fn equations_say_which_terms_are_inertia_and_not_forces() {
    let file = common::scratch_file("noost", ".toml");
    std::fs::write(file.path(), ROD_WITHOUT_OST).unwrap();
    let m = file.path().to_str().unwrap();
    let (code, text, err) = common::binary(&["equations", "--model", m]);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<&str> = text.lines().collect();
    let at = lines
        .iter()
        .position(|l| l.trim_start().starts_with("∂t² x ="))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(lines[at].contains("∂t³ x"), "{text}");
    let note = lines[at + 1];
    assert!(
        note.trim_start().starts_with("not forces: ") && note.contains("∂ttt x"),
        "{text}"
    );
    assert!(note.contains("inertia, not a force") && note.contains("order in time"));
    // Only the ∂t³ term is named, with the coefficient it has in the equation.
    let coefficient = note
        .trim_start()
        .strip_prefix("not forces: ")
        .and_then(|r| r.split_whitespace().next())
        .unwrap()
        .to_string();
    assert!(
        lines[at].contains(&format!("{coefficient} ∂t³ x")),
        "{text}"
    );
    assert!(!note.contains("∂s"), "{note}");
    let (code, json, _) = common::binary(&["equations", "--model", m, "--format", "json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let listed = v["equations"][0]["not_forces"].as_array().unwrap();
    assert_eq!(listed.len(), 1, "{json}");
    assert_eq!(listed[0]["coefficient"], coefficient.as_str());
    assert_eq!(listed[0]["term"], "∂ttt x");
    assert!(listed[0]["why"].as_str().unwrap().contains("inertia"));
    // simulate refuses that term while it is on, and runs once it is off.
    let run = |value: &str| {
        let set = format!("{coefficient}={value}");
        common::binary(&[
            "simulate", "-p", "8", "--steps", "2", "--model", m, "--param", &set,
        ])
    };
    let (code, _, err) = run("0.5");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("∂ttt x") && err.contains("inertia"), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    let (code, _, err) = run("0");
    assert_eq!(code, 0, "{err}");
    // With OST in the section there is no such term and no such note.
    let with_ost = ROD_WITHOUT_OST
        .replace(
            "[active.requirements]\nx = [\"TRAN\"",
            "[active.requirements]\nx = [\"OST\", \"TRAN\"",
        )
        .replace("columns = [\"TRAN\"", "columns = [\"OST\", \"TRAN\"");
    assert_ne!(with_ost, ROD_WITHOUT_OST);
    std::fs::write(file.path(), with_ost).unwrap();
    let (code, text, err) = common::binary(&["equations", "--model", m]);
    assert_eq!(code, 0, "{err}");
    assert!(
        !text.contains("not forces") && !text.contains("∂t³"),
        "{text}"
    );
    let (_, json, _) = common::binary(&["equations", "--model", m, "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["equations"][0]["not_forces"], serde_json::json!([]));
}

/// A random periodic profile: its value and first derivatives in s at `m` stations, as
/// trigonometric polynomials of degree 4 (so the quadrature below is exact).
fn profile(rng: &mut impl rand::Rng, m: usize, derivatives: u32) -> Vec<Vec<f64>> {
    let (a, b): (Vec<f64>, Vec<f64>) = (0..5)
        .map(|_| (rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)))
        .unzip();
    (0..=derivatives)
        .map(|d| {
            (0..m)
                .map(|j| {
                    let s = std::f64::consts::TAU * j as f64 / m as f64;
                    let mut v = if d == 0 { a[0] } else { 0.0 };
                    for k in 1..5 {
                        // ∂s^d of a cos ks + b sin ks: rotate the phase by d quarter turns.
                        let (c, sn) = ((k as f64 * s).cos(), (k as f64 * s).sin());
                        let kd = (k as f64).powi(d as i32);
                        let (p, q) = match d % 4 {
                            0 => (c, sn),
                            1 => (-sn, c),
                            2 => (-c, -sn),
                            _ => (sn, -c),
                        };
                        v += kd * (a[k] * p + b[k] * q);
                    }
                    v
                })
                .collect()
        })
        .collect()
}

/// The power ∫ v·f ds of force `t` at one instant with random periodic φ and v = ∂tφ (the two
/// are independent at an instant).
fn power(t: &Term, rng: &mut impl rand::Rng) -> f64 {
    let m = 96;
    let top = t.factors().iter().map(|f| f.deriv.s).max().unwrap_or(0);
    let (phi, v) = (profile(rng, m, top), profile(rng, m, top));
    (0..m)
        .map(|j| {
            let f: f64 = t
                .factors()
                .iter()
                .map(|x| {
                    let jet = if x.deriv.t == 0 { &phi } else { &v };
                    jet[x.deriv.s as usize][j].powi(x.power as i32)
                })
                .product();
            v[0][j] * f
        })
        .sum::<f64>()
        / m as f64
}

#[test]
fn each_forces_power_text_agrees_with_random_motions() {
    // The `why` of a gyroscopic or Rayleigh force says what its power is; random periodic
    // motions check it (no ends, so terms that only do work at the ends do none here).
    use rand::SeedableRng;
    let mut rng = rand::rngs::StdRng::seed_from_u64(52);
    let mut checked: BTreeMap<&str, usize> = BTreeMap::new();
    for t in monomials(&Bounds::for_order(BoundShape::TauPlusSigma, 6)) {
        if t.max_time_order() > 1 || t.orders().epsilon > 3 {
            continue;
        }
        let force = classify(&t, &|_| "φ".into());
        let powers: Vec<f64> = (0..200).map(|_| power(&t, &mut rng)).collect();
        let scale = powers.iter().map(|p| p.abs()).fold(0.0, f64::max);
        let (low, high) = (
            powers.iter().copied().fold(f64::INFINITY, f64::min),
            powers.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        );
        let what = mono_of(&t);
        let claim = match force.kind {
            ForceClass::Gyroscopic if force.why.contains("does no work") => {
                assert!(scale < 1e-9, "{what:?}: {}: power up to {scale}", force.why);
                "no work"
            }
            ForceClass::Gyroscopic => {
                assert!(scale > 1e-6, "{what:?}: {}: no power seen", force.why);
                "some power"
            }
            ForceClass::Dissipative if force.why.contains("opposite of the coefficient's sign") => {
                assert!(
                    high < 1e-9 * scale.max(1.0) && low < 0.0,
                    "{what:?}: {}: {low}..{high}",
                    force.why
                );
                "opposite sign"
            }
            ForceClass::Dissipative if force.why.contains("the coefficient's sign") => {
                assert!(
                    low > -1e-9 * scale.max(1.0) && high > 0.0,
                    "{what:?}: {}: {low}..{high}",
                    force.why
                );
                "coefficient's sign"
            }
            ForceClass::Dissipative if force.why.contains("only at the ends") => {
                assert!(scale < 1e-9, "{what:?}: {}: power up to {scale}", force.why);
                "ends only"
            }
            ForceClass::Dissipative => {
                assert!(
                    low < 0.0 && high > 0.0,
                    "{what:?}: {}: {low}..{high}",
                    force.why
                );
                "no sign"
            }
            _ => continue,
        };
        *checked.entry(claim).or_default() += 1;
    }
    println!("{checked:?}");
    for claim in ["no work", "coefficient's sign", "opposite sign", "no sign"] {
        assert!(
            checked.get(claim).copied().unwrap_or(0) > 0,
            "{claim}: {checked:?}"
        );
    }
}

/// Every monomial of `degree` factors ∂tᵃ∂sᵇφ with Σa = `tau`, Σb = `sigma` (only a = 1 factors
/// when `velocity`): a multiset walk, independent of the engine's enumerators.
fn block_monomials(degree: u32, tau: u32, sigma: u32, velocity: bool) -> Vec<JetPoly> {
    let factors: Vec<Deriv> = (0..=tau)
        .flat_map(|a| (0..=sigma).map(move |b| Deriv::new(a, b)))
        .filter(|d| !velocity || d.t == 1)
        .collect();
    let mut out = Vec::new();
    // Non-decreasing factor indices make each multiset once.
    let mut stack: Vec<usize> = Vec::new();
    fn walk(
        f: &[Deriv],
        from: usize,
        left: (u32, u32, u32),
        st: &mut Vec<usize>,
        out: &mut Vec<JetPoly>,
    ) {
        if left.0 == 0 {
            if left.1 == 0 && left.2 == 0 {
                let mut m: JetMono = Vec::new();
                for &i in st.iter() {
                    match m.last_mut() {
                        Some((d, n)) if *d == f[i] => *n += 1,
                        _ => m.push((f[i], 1)),
                    }
                }
                m.sort();
                out.push(JetPoly::from([(m, Rational64::from_integer(1))]));
            }
            return;
        }
        for i in from..f.len() {
            if f[i].t <= left.1 && f[i].s <= left.2 {
                st.push(i);
                walk(
                    f,
                    i,
                    (left.0 - 1, left.1 - f[i].t, left.2 - f[i].s),
                    st,
                    out,
                );
                st.pop();
            }
        }
    }
    walk(&factors, 0, (degree, tau, sigma), &mut stack, &mut out);
    out
}

/// The images of the Euler operator and of the Rayleigh map in the block of force `t`.
fn images_of_block(t: &Term) -> Vec<JetPoly> {
    let o = t.orders();
    let mut out: Vec<JetPoly> = block_monomials(o.epsilon + 1, o.tau, o.sigma, false)
        .iter()
        .map(euler_lagrange)
        .collect();
    out.extend(
        block_monomials(o.epsilon + 1, o.tau + 1, o.sigma, true)
            .iter()
            .map(|p| space_euler(p).remove(&1).unwrap_or_default()),
    );
    out
}

#[test]
fn the_listed_active_forces_are_a_basis_modulo_variational_and_rayleigh_forces() {
    // Random [active] requirements (OST always) on the crawler at order 4, the lowest layer and
    // the next, and the issue's lateral field without REF at order 6 to the eighth layer: within
    // each listed block, no listed force is reached by the densities' images and the other
    // listed forces, and every covariant candidate is.
    use rand::SeedableRng;
    let mut rng = rand::rngs::StdRng::seed_from_u64(1);
    let optional = ["TRAN", "REF", "ROT", "GAL", "PAR", "TREV"];
    let mut pick = || {
        let mut r = vec!["\"OST\"".to_string()];
        r.extend(
            optional
                .iter()
                .filter(|_| rng.random_range(0..2) == 1)
                .map(|c| format!("\"{c}\"")),
        );
        format!("[{}]", r.join(", "))
    };
    let mut cases: Vec<(String, String, u32, u32)> =
        (0..8).map(|_| (pick(), pick(), 4, 1)).collect();
    let bare = "[\"OST\", \"TRAN\"]".to_string();
    cases.push((bare.clone(), bare, 6, 8));
    let crawler = include_str!("../tables/models/crawler.toml");
    let (mut blocks, mut named) = (0, Vec::new());
    for (case, (x, y, order, beyond)) in cases.iter().enumerate() {
        let text = crawler
            .replace(
                "x = [\"OST\", \"TRAN\", \"REF\", \"GAL\"]",
                &format!("x = {x}"),
            )
            .replace(
                "y = [\"OST\", \"TRAN\", \"REF\", \"ROT\", \"GAL\"]",
                &format!("y = {y}"),
            )
            .replace(
                "[active]\n",
                &format!("[active]\nbeyond_leading = {beyond}\n"),
            );
        let model = theory_search::model::Model::from_toml(&text).expect("model");
        let fields = theory_search::active::active_forces(&model, *order)
            .expect("forces")
            .expect("an [active] section");
        for (field, req) in fields.iter().zip([x, y]) {
            let rules: Vec<_> = req
                .trim_matches(['[', ']'])
                .split(", ")
                .filter_map(|c| rule(c.trim_matches('"')))
                .collect();
            let mut by_block: BTreeMap<(u32, u32, u32), Vec<JetPoly>> = BTreeMap::new();
            for f in &field.active {
                let o = f.orders;
                by_block
                    .entry((o.epsilon, o.tau, o.sigma))
                    .or_default()
                    .push(poly_of(&f.shape));
            }
            for (&(e, ta, si), listed) in &by_block {
                blocks += 1;
                let some = field
                    .active
                    .iter()
                    .find(|f| (f.orders.epsilon, f.orders.tau, f.orders.sigma) == (e, ta, si))
                    .expect("listed");
                let images = images_of_block(&some.shape);
                for (i, f) in listed.iter().enumerate() {
                    let mut others = images.clone();
                    others.extend(
                        listed
                            .iter()
                            .enumerate()
                            .filter(|(j, _)| *j != i)
                            .map(|(_, p)| p.clone()),
                    );
                    assert!(
                        !reaches(&others, &|p| p.clone(), f),
                        "case {case}, {}: {f:?} depends on the others",
                        field.field
                    );
                }
                let mut all = images.clone();
                all.extend(listed.iter().cloned());
                for p in block_monomials(e, ta, si, false) {
                    let t = term_of(p.keys().next().expect("a monomial")).expect("a term");
                    if rules.iter().all(|r| allows(r, &t)) {
                        assert!(
                            reaches(&all, &|p| p.clone(), &p),
                            "case {case}, {}: {:?} not spanned",
                            field.field,
                            mono_of(&t)
                        );
                    }
                }
            }
            named.extend(field.dependent.iter().map(|d| d.term.clone()));
        }
    }
    println!("{blocks} listed blocks checked, dependent: {named:?}");
    assert!(blocks > 20, "{blocks} blocks");
    // The issue's pair: (∂s³y)² and ∂s²y·∂s⁴y add up to E((∂s²y)³)/6, one direction.
    assert!(named.iter().any(|t| t == "∂ss y·∂ssss y"), "{named:?}");
}

/// The images of the densities of the block of force `t` that every rule of `lagrangian` (for
/// L) or `rayleigh` (for R) admits, by the test's own enumerator.
fn admitted_images(t: &Term, lagrangian: &[&str], rayleigh: &[&str]) -> Vec<JetPoly> {
    let o = t.orders();
    let admits = |codes: &[&str], p: &JetPoly| {
        let m = term_of(p.keys().next().expect("a monomial")).expect("a term");
        codes
            .iter()
            .all(|c| rule(c).expect("a rule").passes_by_expansion(&m))
    };
    let mut out: Vec<JetPoly> = block_monomials(o.epsilon + 1, o.tau, o.sigma, false)
        .iter()
        .filter(|p| admits(lagrangian, p))
        .map(euler_lagrange)
        .collect();
    out.extend(
        block_monomials(o.epsilon + 1, o.tau + 1, o.sigma, false)
            .iter()
            .filter(|p| admits(rayleigh, p))
            .map(|p| space_euler(p).remove(&1).unwrap_or_default()),
    );
    out
}

#[test]
fn covariant_forces_no_admitted_density_gives_are_listed_with_the_rules_that_strike_them() {
    // Random [lagrangian], [rayleigh] and [active] requirements of the crawler's lateral field
    // at order 4, every layer kept: the forces listed as carried by no density are exactly the
    // covariant variational or Rayleigh forces (by the oracle's search for a density) that no
    // admitted density's image reaches (the test's own enumerator and elimination).
    use rand::SeedableRng;
    let mut rng = rand::rngs::StdRng::seed_from_u64(5);
    let mut pick = |always: &'static str, optional: &[&'static str]| -> Vec<&'static str> {
        let mut r = vec![always];
        r.extend(optional.iter().filter(|_| rng.random_range(0..2) == 1));
        r
    };
    let crawler = include_str!("../tables/models/crawler.toml");
    let (mut listed, mut seen_rot) = (0, false);
    for case in 0..10 {
        let l = pick("OST", &["TRAN", "REF", "ROT"]);
        let r = pick("DIS", &["TRAN", "GAL", "REF", "SPIN"]);
        let a = pick("OST", &["TRAN", "REF", "ROT", "GAL"]);
        let list = |v: &[&str]| {
            format!(
                "[{}]",
                v.iter()
                    .map(|c| format!("\"{c}\""))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        };
        let text = crawler
            .replace(
                "y = [\"OST\", \"TRAN\", \"REF\", \"KIN\", \"ROT\"]",
                &format!("y = {}", list(&[&l[..], &["KIN"]].concat())),
            )
            .replace(
                "y = [\"DIS\", \"TRAN\", \"GAL\", \"REF\", \"SPIN\"]",
                &format!("y = {}", list(&r)),
            )
            .replace(
                "y = [\"OST\", \"TRAN\", \"REF\", \"ROT\", \"GAL\"]",
                &format!("y = {}", list(&a)),
            )
            .replace("[active]\n", "[active]\nbeyond_leading = 8\n");
        let model = theory_search::model::Model::from_toml(&text).expect("model");
        let fields = theory_search::active::active_forces(&model, 4)
            .expect("forces")
            .expect("an [active] section");
        let y = &fields[1];
        let reported: Vec<&Term> = y.uncarried.iter().map(|f| &f.shape).collect();
        let lagrangian = [&l[..], &["KIN"]].concat();
        let rules: Vec<_> = a.iter().filter_map(|c| rule(c)).collect();
        let mut expected: Vec<Term> = Vec::new();
        for t in monomials(&Bounds::for_order(BoundShape::TauAndSigma, 4)) {
            if !rules.iter().all(|r| allows(r, &t)) {
                continue;
            }
            if !matches!(
                oracle(&t),
                ForceClass::Conservative | ForceClass::Dissipative
            ) {
                continue;
            }
            let images = admitted_images(&t, &lagrangian, &r);
            if !reaches(&images, &|p| p.clone(), &poly_of(&t)) {
                expected.push(t);
            }
        }
        let mut got: Vec<Term> = reported.into_iter().cloned().collect();
        got.sort();
        expected.sort();
        assert_eq!(got, expected, "case {case}: L {l:?}, R {r:?}, active {a:?}");
        for f in &y.uncarried {
            assert!(
                f.why.contains("[lagrangian]") || f.why.contains("[rayleigh]"),
                "{}",
                f.why
            );
            assert!(f.coefficient.is_none(), "listed only by default: {f:?}");
        }
        seen_rot |= y
            .uncarried
            .iter()
            .any(|f| f.term == "∂ss y" && f.why.contains("ROT"));
        listed += y.uncarried.len();
    }
    println!("{listed} forces carried by no density");
    assert!(listed > 5 && seen_rot, "{listed}");
}

#[test]
fn the_crawlers_tension_force_is_listed_and_enters_when_the_model_says_so() {
    // ROT strikes (∂s y)², the only density whose variation ∂s²y is: `active` lists it, the
    // equations leave it out, and `uncarried = "enter"` puts it in with a sign from its square.
    let listed = common::cli(&["active", "--model", "tables/models/crawler.toml"]).expect("active");
    assert!(listed.contains("carried by no density:"), "{listed}");
    assert!(
        listed.contains("∂ss y") && listed.contains("ROT in [lagrangian] strikes every density"),
        "{listed}"
    );
    let crawler = include_str!("../tables/models/crawler.toml");
    let file = common::scratch_file("uncarried", ".toml");
    let path = file.path();
    let text = crawler.replace(
        "[active.requirements]",
        "uncarried = \"enter\"\n\n[active.requirements]",
    );
    std::fs::write(path, text).expect("write");
    let p = path.to_str().expect("utf-8");
    let eqs = common::cli(&["equations", "--model", p]).expect("equations");
    assert!(eqs.contains("∂t² y = b_y ∂s² y +"), "{eqs}");
    assert!(
        eqs.contains("b_y > 0: the energy must be bounded below"),
        "{eqs}"
    );
    let plain =
        common::cli(&["equations", "--model", "tables/models/crawler.toml"]).expect("plain");
    assert!(!plain.contains("b_y"), "{plain}");
    // A key only [active] takes.
    let bad = crawler.replace("[rayleigh]\n", "[rayleigh]\nuncarried = \"enter\"\n");
    std::fs::write(path, bad).expect("write");
    let (code, _, err) = common::binary(&["active", "--model", p]);
    assert_ne!(code, 0);
    assert!(
        err.contains("[rayleigh] uncarried") && err.lines().count() == 1,
        "{err}"
    );
}
