//! A gyroscopic force does no work at the ends (issue 52 item 3): the crawler with stiffness
//! and damping 0 and only g∂t∂s φ on both fields keeps E = ½|v|² to 1e-12 per step on free,
//! clamped, pinned and mixed ends, and injects nothing; the continuum's end work g/2[v²] is
//! cancelled by the grid's skew closure (`active::closes_skew`), not left to `injected`.
//! Through `simulate`, the issue's run keeps its energy and reports no injected work.

use std::collections::BTreeMap;
use std::process::Command;

use theory_search::dynamics::nonlinear::{coefficient_names, NonlinearBody};
use theory_search::model::Model;

const CRAWLER: &str = include_str!("../tables/models/crawler.toml");

/// The crawler with both fields' ends `ends` (a TOML value), every coefficient 0 but g_x, g_y.
fn gyroscopic_only(ends: &str, points: usize) -> NonlinearBody {
    let text = CRAWLER.replace("boundary = \"free\"", &format!("boundary = {ends}"));
    let model = Model::from_toml(&text).unwrap();
    let mut values: BTreeMap<String, f64> = coefficient_names(&model, 4)
        .unwrap()
        .into_iter()
        .map(|n| (n, 0.0))
        .collect();
    assert!(values.contains_key("g_x") && values.contains_key("g_y"));
    values.insert("g_x".into(), 0.3);
    values.insert("g_y".into(), -0.45);
    NonlinearBody::new(&model, 4, points, &values).unwrap()
}

#[test]
fn a_gyroscopic_only_body_keeps_its_energy_at_every_end() {
    for ends in [
        "\"free\"",
        "\"clamped\"",
        "\"pinned\"",
        "{ head = \"clamped\", tail = \"free\" }",
    ] {
        for points in [9, 16] {
            let body = gyroscopic_only(ends, points);
            // Moving ends: the velocity is largest at the tail and head.
            let mut state: Vec<(Vec<f64>, Vec<f64>)> = body
                .fields
                .iter()
                .map(|f| {
                    let n = f.unknowns;
                    let u = (0..n).map(|j| 0.1 * (0.7 * j as f64).sin()).collect();
                    let v = (0..n)
                        .map(|j| 0.2 + 0.3 * (j as f64 / (n - 1) as f64 - 0.4).powi(2))
                        .collect();
                    (u, v)
                })
                .collect();
            let h = 0.05;
            let mut integrator = body.integrator(h);
            let start = body.energy(&state);
            let (mut worst, mut moved) = (0.0f64, 0.0f64);
            for step in 0..400 {
                let e0 = body.energy(&state);
                let before = state.clone();
                integrator.step(&mut state, step as f64 * h).unwrap();
                let e1 = body.energy(&state);
                worst = worst.max((e1 - e0).abs() / e0);
                moved += before
                    .iter()
                    .zip(&state)
                    .map(|(a, b)| {
                        a.1.iter()
                            .zip(&b.1)
                            .map(|(x, y)| (x - y).abs())
                            .sum::<f64>()
                    })
                    .sum::<f64>();
            }
            let (dissipated, injected) = integrator.work();
            assert!(
                moved > 1.0,
                "{ends}, N = {points}: the force turns the velocities"
            );
            assert!(
                worst < 1e-12,
                "{ends}, N = {points}: energy moved by {worst:e} of E in a step"
            );
            assert!(
                dissipated == 0.0 && injected.abs() < 1e-12 * start,
                "{ends}, N = {points}: injected {injected:e} of E = {start}"
            );
        }
    }
}

#[test]
fn the_issues_run_keeps_its_energy_and_injects_nothing() {
    let out = Command::new(env!("CARGO_BIN_EXE_theory-search"))
        .args([
            "simulate",
            "--model",
            concat!(env!("CARGO_MANIFEST_DIR"), "/tables/models/crawler.toml"),
            "-p",
            "9",
            "--param",
            "g_y=0.3",
            "--param",
            "cp_y=0",
            "--param",
            "cp_x=0",
            "--initial",
            "y:2=0.1",
            "--initial",
            "y:3=0,0.1",
            "--dt",
            "0.01",
            "--steps",
            "2000",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (e, w) = (column("energy"), column("injected"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 2001);
    let e0 = rows[0][e];
    for r in &rows {
        // The energy was 6.2 % up at the end, all of it injected at the free ends.
        assert!((r[e] - e0).abs() < 1e-10 * e0, "E = {} against {e0}", r[e]);
        assert!(r[w].abs() < 1e-10 * e0, "injected {}", r[w]);
    }
}
