//! Scenario: the command line as a user runs it, including every error path.

use std::process::Command;

mod common;

use common::binary as run;

fn assert_clean_error(args: &[&str], needle: &str) {
    let (code, stdout, stderr) = run(args);
    assert_ne!(code, 0, "{args:?} succeeded");
    assert!(stdout.is_empty(), "{args:?} printed {stdout}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(stderr.contains(needle), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

#[test]
fn default_run_prints_both_tables_and_the_densities() {
    let (code, out, err) = run(&["--order", "4"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("Lagrangian density: 27 candidate terms with δ ≤ 4, ε ≤ 4, τ+σ ≤ 4"));
    assert!(out.contains("Rayleigh density: 32 candidate terms with δ ≤ 4, ε ≤ 4, τ ≤ 4, σ ≤ 4"));
    assert!(out.contains("L_x = ½(∂t x)² − ½ c_x (∂s x)²"));
    assert!(out.contains("L_y = ½(∂t y)² − ½ c_y (∂ss y)²"));
    assert!(out.contains("R_y = c'_y (∂tss y)²"));
    let (_, bare, _) = run(&[]);
    assert_eq!(bare, out, "order 4 is the default");
    let (_, sub, _) = run(&["table", "--order", "4"]);
    assert_eq!(sub, out);
}

#[test]
fn every_format_runs() {
    for (format, needle) in [
        ("text", "OST"),
        ("markdown", "| term | δ |"),
        ("csv", "density,term,delta,epsilon,tau,sigma,OST"),
        ("json", "\"lagrangian\""),
        ("latex", "\\begin{tabular}"),
    ] {
        let (code, out, err) = run(&["--order", "5", "--format", format]);
        assert_eq!(code, 0, "{format}: {err}");
        assert!(out.contains(needle), "{format}");
    }
    let (_, json, _) = run(&["--format", "json", "--density", "rayleigh"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!(v.get("lagrangian").is_none());
    assert_eq!(
        v["rayleigh"]["survivors"]["y"],
        serde_json::json!(["(∂tss φ)²"])
    );
}

#[test]
fn order_three_says_the_beam_has_no_potential() {
    let (code, out, _) = run(&["--order", "3", "--density", "lagrangian"]);
    assert_eq!(code, 0);
    assert!(
        out.contains("note: L_y: no potential term survives at order 3"),
        "{out}"
    );
}

#[test]
fn bad_input_is_one_line_and_non_zero() {
    assert_clean_error(&["--order", "0"], "0 is not in 1..=32");
    assert_clean_error(&["--order", "33"], "33 is not in 1..=32");
    assert_clean_error(&["--order", "-2"], "-2");
    assert_clean_error(&["--order", "four"], "four");
    assert_clean_error(&["--format", "pdf"], "pdf");
    assert_clean_error(&["--density", "hamiltonian"], "hamiltonian");
    assert_clean_error(&["--frobnicate"], "frobnicate");
    assert_clean_error(
        &["--model", "/no/such/model.toml"],
        "cannot read /no/such/model.toml",
    );
}

#[test]
fn malformed_model_files_name_the_problem() {
    let dir_held = common::scratch("cli");
    let dir = dir_held.path();
    let broken = dir.join("broken.toml");
    std::fs::write(&broken, "name = \"w\"\nfields = [\n").unwrap();
    assert_clean_error(&["--model", broken.to_str().unwrap()], "line");
    let unknown = dir.join("unknown.toml");
    let text = theory_search::model::Model::larva_toml().replace("\"SPIN\"]\n", "\"SPINX\"]\n");
    std::fs::write(&unknown, text).unwrap();
    assert_clean_error(&["--model", unknown.to_str().unwrap()], "SPINX");
    // The embedded model written out and read back gives the same output.
    let same = dir.join("larva.toml");
    std::fs::write(&same, theory_search::model::Model::larva_toml()).unwrap();
    assert_eq!(run(&["--model", same.to_str().unwrap()]).1, run(&[]).1);
}

#[test]
fn help_explains_every_option() {
    let (code, out, _) = run(&["--help"]);
    assert_eq!(code, 0);
    for opt in [
        "--order",
        "--density",
        "--format",
        "--model",
        "From 1 to 32",
        "emit",
        "rules",
    ] {
        assert!(out.contains(opt), "--help lacks {opt}");
    }
}

#[test]
fn equations_command_prints_every_format() {
    let (code, out, err) = run(&["equations"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("∂t² x = c_x ∂s² x + 2 c'_x ∂t∂s² x"), "{out}");
    assert!(out.contains("∂t² y = −c_y ∂s⁴ y − 2 c'_y ∂t∂s⁴ y"), "{out}");
    let (_, latex, _) = run(&["equations", "--format", "latex"]);
    assert!(
        latex.contains("\\partial_t^{2} y &= -c_{y} \\partial_s^{4} y"),
        "{latex}"
    );
    let (_, json, _) = run(&["equations", "--format", "json", "--order", "6"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["equations"][3]["field"], "z");
    assert_clean_error(&["equations", "--order", "1"], "no kinetic term");
    assert_clean_error(&["equations", "--format", "html"], "html");
}

#[test]
fn operators_command_prints_the_seeds_operators() {
    let (code, out, err) = run(&["operators", "--points", "12"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("x · lagrangian · (∂s x)² · periodic boundary · 11×11 · D = Σ (Δ¹x)² = D2,c, paper Eq. 3"), "{out}");
    assert!(out.contains("= D2,f, paper Eq. 4"));
    assert!(out.contains(
        "y · lagrangian · (∂ss y)² · free boundary · 12×12 · D = Σ (Δ²y)² = D4, paper Eq. 5"
    ));
    assert!(out.contains("  -2  5 -4  1  0  0  0  0  0  0  0  0\n"));

    let (_, json, _) = run(&["operators", "--points", "5", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["points"], 5);
    let x = &v["operators"][0];
    assert_eq!(
        (
            x["field"].as_str(),
            x["density"].as_str(),
            x["term"].as_str(),
            x["boundary"].as_str()
        ),
        (
            Some("x"),
            Some("lagrangian"),
            Some("(∂s φ)²"),
            Some("periodic")
        )
    );
    assert_eq!(x["size"], 4);
    assert_eq!(
        x["matrix"],
        serde_json::json!([
            [2, -1, 0, -1],
            [-1, 2, -1, 0],
            [0, -1, 2, -1],
            [-1, 0, -1, 2]
        ])
    );
    assert_eq!(v["operators"].as_array().unwrap().len(), 8);

    assert_clean_error(&["operators", "--points", "1"], "too few");
    assert_clean_error(&["operators", "--points", "2"], "need at least 3");
    assert_clean_error(&["operators", "--points", "0"], "0 is not in 1..=2000");
    assert_clean_error(&["operators", "--points", "5000"], "5000");
    assert_clean_error(&["operators"], "--points");
}

#[test]
fn modes_command() {
    let (code, out, err) = run(&["modes", "--points", "12"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("zero mode: axial translation"));
    assert!(out.contains("80.10 %"), "{out}");
    assert!(out.contains("98.33 %"), "{out}");
    assert!(out.contains("degenerate pairs: (1, 2) (3, 4)"));

    let (_, json, _) = run(&[
        "modes", "--points", "12", "--format", "json", "--shapes", "--modes", "5",
    ]);
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["points"], 12);
    let x = &v["fields"][0];
    assert_eq!(x["field"], "x");
    for key in [
        "eigenvalues",
        "frequencies",
        "damping_ratios",
        "variance_share",
    ] {
        assert_eq!(x[key].as_array().unwrap().len(), 5, "{key}");
    }
    assert_eq!(x["zero_modes"], serde_json::json!([0]));
    assert_eq!(x["variance_share"][0], 0.0);
    assert_eq!(x["degenerate_pairs"], serde_json::json!([[1, 2], [3, 4]]));
    assert_eq!(x["shapes"].as_array().unwrap().len(), 5);
    assert_eq!(x["shapes"][0].as_array().unwrap().len(), 11);
    assert_eq!(v["fields"][2]["zero_modes"], serde_json::json!([0, 1]));
    let (_, plain, _) = run(&["modes", "--points", "12", "--format", "json"]);
    assert!(!plain.contains("\"shapes\""));

    let (_, csv, _) = run(&["modes", "--points", "6", "--format", "csv"]);
    assert!(csv.starts_with("field,index,eigenvalue,frequency"));
    assert_eq!(csv.lines().count(), 1 + 5 + 6 + 6 + 6);

    let (code, _, err) = run(&["modes", "--points", "100000", "--modes", "20"]);
    assert_eq!(code, 0, "{err}");

    assert_clean_error(&["modes", "--points", "2"], "too few");
    assert_clean_error(&["modes", "--points", "0"], "0 is not in");
    assert_clean_error(
        &["modes", "--points", "12", "--param", "omega_b=nan"],
        "finite",
    );
    assert_clean_error(
        &["modes", "--points", "12", "--param", "omega_b=-2"],
        "positive",
    );
    assert_clean_error(
        &["modes", "--points", "12", "--param", "zeta_q=0.2"],
        "no field",
    );
    assert_clean_error(
        &["modes", "--points", "12", "--param", "omega_b"],
        "name=value",
    );
    assert_clean_error(
        &["modes", "--points", "12", "--params", "/no/file.toml"],
        "cannot read",
    );
    assert_clean_error(&["modes", "--points", "12", "--modes", "0"], "--modes");
    assert_clean_error(&["modes", "--points", "200000", "--shapes"], "--modes K");
    assert_clean_error(
        &["modes", "--points", "12", "--order", "3"],
        "no potential term survives at order 3",
    );
}

#[test]
fn simulate_command_writes_csv() {
    let (code, out, err) = run(&[
        "simulate",
        "--points",
        "6",
        "--steps",
        "4",
        "--initial",
        "y:2=1,0.5",
        "--force",
        "theta:1=0.2",
        "--drive",
        "x:1=0.1,2.0",
    ]);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 1 + 5);
    assert!(lines[0].starts_with("t,energy,x_0,x_1,x_2,x_3,x_4,theta_0"));
    assert!(lines[0].ends_with("q_z_5"));
    let cols = lines[0].split(',').count();
    assert!(lines.iter().all(|l| l.split(',').count() == cols));
    let dir_held = common::scratch("sim");
    let dir = dir_held.path();
    let file = dir.join("run.csv");
    let (code, out, _) = run(&[
        "simulate",
        "--points",
        "6",
        "--steps",
        "4",
        "--every",
        "2",
        "--temperature",
        "0.5",
        "--seed",
        "3",
        "--out",
        file.to_str().unwrap(),
    ]);
    assert_eq!(code, 0);
    assert!(out.is_empty());
    assert_eq!(
        std::fs::read_to_string(&file).unwrap().lines().count(),
        1 + 3
    );

    assert_clean_error(&["simulate", "--points", "6", "--dt", "0"], "time step");
    assert_clean_error(
        &["simulate", "--points", "6", "--temperature", "nan"],
        "temperature",
    );
    assert_clean_error(&["simulate", "--points", "6", "--every", "0"], "--every");
    assert_clean_error(
        &["simulate", "--points", "6", "--initial", "w:1=1"],
        "unknown field",
    );
    assert_clean_error(
        &["simulate", "--points", "6", "--initial", "y:1"],
        "FIELD:MODE=VALUE",
    );
    assert_clean_error(
        &["simulate", "--points", "6", "--initial", "y:one=1"],
        "whole number",
    );
    assert_clean_error(
        &["simulate", "--points", "6", "--drive", "y:2=1"],
        "F0,OMEGA",
    );
    assert_clean_error(
        &["simulate", "--points", "6", "--force", "y:2=inf"],
        "finite",
    );
    assert_clean_error(&["simulate", "--points", "5000"], "5000");
    assert_clean_error(&["simulate", "--points", "2"], "too few");
}

#[test]
fn absurd_monomial_orders_are_refused_quickly() {
    assert_clean_error(&["--basis", "monomials", "--order", "32"], "more than");
    assert_clean_error(&["interactions", "--order", "32"], "more than");
    assert_clean_error(&["parts", "--order", "30"], "more than");
}

#[test]
fn asymmetry_and_mathieu_commands() {
    let (code, out, err) = run(&[
        "asymmetry",
        "--coupling",
        "-0.7071067811865476",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for key in [
        "forward",
        "backward",
        "ratio",
        "simulated_forward",
        "simulated_backward",
    ] {
        assert!(v[key].is_number(), "{key}");
    }
    assert!((v["ratio"].as_f64().unwrap() - 0.5).abs() < 1e-12);
    assert_clean_error(&["asymmetry", "--coupling", "nan"], "finite");
    assert_clean_error(
        &["asymmetry", "--coupling", "1", "--amplitude", "0"],
        "positive",
    );
    assert_clean_error(&["asymmetry"], "--coupling");

    let (code, out, _) = run(&[
        "mathieu",
        "--rows",
        "3",
        "--columns",
        "5",
        "--format",
        "csv",
    ]);
    assert_eq!(code, 0);
    assert_eq!(out.lines().count(), 1 + 15);
    let (_, chart, _) = run(&[
        "mathieu",
        "--rows",
        "5",
        "--columns",
        "41",
        "--ratio-min",
        "1.5",
        "--ratio-max",
        "2.5",
    ]);
    let top = chart.lines().nth(1).unwrap();
    assert!(top.contains('#') && top.contains('.'), "{chart}");
    assert_clean_error(
        &["mathieu", "--ratio-min", "3", "--ratio-max", "2"],
        "empty",
    );
    assert_clean_error(&["mathieu", "--columns", "1"], "grid");
    assert_clean_error(&["mathieu", "--lambda", "-1"], "positive");
}

#[test]
fn stats_pair_command() {
    let args = [
        "stats",
        "pair",
        "--omega",
        "1.3",
        "--beta",
        "2",
        "--momentum",
        "0.7",
        "--format",
        "json",
        "--samples",
        "20000",
        "--seed",
        "5",
    ];
    let (code, out, err) = run(&args);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    for key in [
        "partition_function",
        "free_energy",
        "amplitude_at_minimum",
        "mean_amplitude",
    ] {
        assert!(v[key].is_number(), "{key}");
    }
    let z = 2.0 * std::f64::consts::PI.powi(2) / (2.0 * 1.3) * (-2.0f64 * 0.7 * 1.3).exp();
    assert!((v["partition_function"].as_f64().unwrap() - z).abs() < 1e-12 * z);
    assert!(
        v["samples"]["mean_amplitude"].is_number() && v["samples"]["acceptance_rate"].is_number()
    );
    let (_, again, _) = run(&args);
    assert_eq!(out, again, "seeded runs repeat");
    assert_clean_error(&["stats", "pair", "--beta", "-1"], "positive");
    assert_clean_error(&["stats", "pair", "--omega", "nan"], "finite");
    assert_clean_error(&["stats", "pair", "--samples", "0"], "samples");
}

#[test]
fn stats_equipartition_command() {
    let (code, out, err) = run(&[
        "stats",
        "equipartition",
        "--points",
        "6",
        "--steps",
        "20000",
        "--format",
        "json",
        "--param",
        "zeta_b=1",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["pca_variance_share"].as_array().unwrap().len(), 4);
    assert!(v["overlap"][0].as_f64().unwrap() > 0.99);
    assert_clean_error(&["stats", "equipartition", "--field", "w"], "no field");
    assert_clean_error(
        &["stats", "equipartition", "--temperature", "0"],
        "positive",
    );
    assert_clean_error(&["stats", "equipartition", "--points", "2000"], "budget");
}

#[test]
fn behave_command() {
    let (code, out, err) = run(&[
        "behave",
        "rolling",
        "--momentum",
        "0.1",
        "--periods",
        "20",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["kind"], "rolling");
    assert!((v["body_rate"].as_f64().unwrap() - v["omega"].as_f64().unwrap()).abs() < 1e-9);
    assert_clean_error(&["behave", "peristalsis", "--momentum", "0"], "M = 0");
    assert_clean_error(&["behave", "swimming"], "swimming");
}

#[test]
fn behave_rearing_and_hunching() {
    let (code, out, err) = run(&[
        "behave",
        "rearing",
        "--duration",
        "20000",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["field"], "z");
    assert!(v["max_error"].as_f64().unwrap() < 1e-12);
    let (code, out, _) = run(&["behave", "hunching"]);
    assert_eq!(code, 0);
    assert!(out.starts_with("Hunching: force 0.02 on mode 1 of x"));
    assert_clean_error(&["behave", "rearing", "--force", "nan"], "finite");
    assert_clean_error(&["behave", "rearing", "--duration", "0"], "positive");
}

#[test]
fn behave_self_righting() {
    let (code, out, err) = run(&[
        "behave",
        "self-righting",
        "--sweep",
        "1,2",
        "--format",
        "json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["damping_ratio"], 1.0);
    let times = v["alignment_times"].as_array().unwrap();
    assert_eq!(times.len(), 12);
    assert_eq!(times[11], v["attachment_time"]);
    let sweep = v["sweep"].as_array().unwrap();
    assert!(sweep[0]["righting_time"].as_f64() < sweep[1]["righting_time"].as_f64());
    // The model's own ζ_t when it is given explicitly.
    let (_, out, _) = run(&[
        "behave",
        "self-righting",
        "--param",
        "zeta_t=2",
        "--format",
        "json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let lambda1 = 2.0 - 2.0 * (std::f64::consts::PI / 12.0).cos();
    assert!((v["damping_ratio"].as_f64().unwrap() - 2.0 * lambda1.sqrt()).abs() < 1e-12);
    let (code, out, _) = run(&["behave", "self-righting", "--format", "csv"]);
    assert_eq!(code, 0);
    let header = out.lines().next().unwrap();
    assert!(header.starts_with("t,torque,mode,mean_rotation,theta_0,"));
    assert_eq!(header.split(',').count(), 16);
    assert_clean_error(&["behave", "self-righting", "--tolerance", "0"], "positive");
    assert_clean_error(
        &["behave", "self-righting", "--mode-damping", "nan"],
        "finite",
    );
    assert_clean_error(&["behave", "self-righting", "--points", "1"], "points");
}

#[test]
fn stats_explore_command() {
    let (code, out, err) = run(&["stats", "explore", "--samples", "20000", "--format", "json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let (sd, lin) = (
        v["bend_sd"].as_f64().unwrap(),
        v["bend_sd_linear"].as_f64().unwrap(),
    );
    assert!((sd / lin - 1.0).abs() < 0.05, "{sd} vs {lin}");
    let (_, csv, _) = run(&["stats", "explore", "--samples", "10", "--format", "csv"]);
    assert_eq!(csv.lines().count(), 11);
    assert_clean_error(&["stats", "explore", "--beta", "0"], "positive");
    assert_clean_error(&["stats", "explore", "--samples", "0"], "samples");
}

/// Every behaviour and statistics command has a CSV form with a header and numeric rows.
#[test]
fn behaviour_commands_write_csv() {
    let pair = "stats pair --omega 1 --beta 2 --momentum 0.3";
    let cases = [
        (
            "asymmetry --coupling -0.5".to_string(),
            "forward,backward,ratio",
            1,
        ),
        (pair.to_string(), "partition_function,", 1),
        (
            format!("{pair} --samples 200"),
            "amplitude,phase,momentum_a",
            200,
        ),
        (
            "stats equipartition --steps 2000".into(),
            "k,pca_variance_share",
            10,
        ),
        ("behave hunching --duration 100".into(), "t,q", 401),
        ("behave rolling --periods 2".into(), "t,q_a,q_b", 201),
        (
            "behave self-righting".into(),
            "t,torque,mode,mean_rotation,theta_0",
            0,
        ),
    ];
    for (args, header, rows) in cases {
        let mut all: Vec<&str> = args.split_whitespace().collect();
        all.extend(["--format", "csv"]);
        let (code, out, err) = run(&all);
        assert_eq!(code, 0, "{all:?}: {err}");
        let mut lines = out.lines();
        assert!(lines.next().unwrap().starts_with(header), "{all:?}");
        let body: Vec<&str> = lines.collect();
        if rows > 0 {
            assert_eq!(body.len(), rows, "{all:?}");
        }
        for l in body {
            for cell in l.split(',') {
                let v: f64 = cell.parse().unwrap_or_else(|_| panic!("{all:?}: {l}"));
                assert!(v.is_finite(), "{all:?}: {l}");
            }
        }
    }
}

#[test]
fn fit_command() {
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/tables/examples/midlines.csv");
    let (code, out, err) = run(&["fit", example, "--window", "512", "--format", "json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let keys: Vec<&str> = v.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    assert_eq!(
        &keys[..7],
        [
            "frames",
            "points",
            "pca_variance_share",
            "theory_variance_share",
            "overlap",
            "omega",
            "beta"
        ]
    );
    assert_eq!(v["frames"], 3000);
    assert_eq!(v["points"], 12);
    assert_eq!(v["overlap"].as_array().unwrap().len(), 10);
    assert!(v["overlap"][0][0].as_f64().unwrap() > 0.99);
    let (code, out, _) = run(&["fit", example, "--format", "csv"]);
    assert_eq!(code, 0);
    assert_eq!(out.lines().count(), 11);
    assert!(out.starts_with("mode,eigenvalue,pca_share,theory_share,overlap"));
    let (code, out, _) = run(&["fit", example]);
    assert_eq!(code, 0);
    // The verdict in words first, with the next command; then how it was found.
    assert!(
        out.starts_with("In short: the theory holds here: equipartition, dispersion and damping consistent over modes 2, 3, 4.\n  κ = "),
        "{out}"
    );
    assert!(out.contains("\n  next: theory-search simulate --points 12 --param omega_b="));
    assert!(out.contains("\n\nFit of 3000 frames of 12-point midlines"));
    // Standard input.
    let child = Command::new(env!("CARGO_BIN_EXE_theory-search"))
        .args(["fit", "-", "--format", "json"])
        .stdin(std::fs::File::open(example).unwrap())
        .output()
        .unwrap();
    assert!(child.status.success());
    // Figures.
    let dir_held = common::scratch("fit");
    let dir = dir_held.path();
    let (code, _, err) = run(&["fit", example, "--figures", dir.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    for name in ["fit_shapes.svg", "fit_summary.svg"] {
        let svg = std::fs::read_to_string(dir.join(name)).unwrap();
        assert!(svg.contains("<polyline"), "{name}");
    }
    // The modal series, streamed.
    let series = dir.join("series.csv");
    let (code, _, err) = run(&["fit", example, "--series", series.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&series).unwrap();
    assert!(text.starts_with("t,q_2,q_3,"));
    assert_eq!(text.lines().count(), 3001);
    std::fs::remove_file(&series).unwrap();
    assert_clean_error(
        &["fit", example, "--series", "/nonexistent/dir/s.csv"],
        "cannot write",
    );
    // Errors: files exit 1 naming the line, settings exit 2.
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, "0 0 0 1 0 2 0 3 0 4 0\n1 0 0 1 0 2 x 3 0 4 0\n").unwrap();
    let (code, _, err) = run(&["fit", bad.to_str().unwrap(), "--points", "5"]);
    assert_eq!(code, 1);
    assert!(err.contains("line 2: column 7"), "{err}");
    std::fs::remove_file(&bad).unwrap();
    assert_clean_error(&["fit", "/nonexistent/m.csv"], "cannot open");
    assert_clean_error(&["fit", example, "--window", "4"], "window");
    assert_clean_error(&["fit", example, "--window", "1000000000"], "at most");
    assert_clean_error(&["fit", example, "--points", "100000"], "at most 500");
    assert_clean_error(
        &["fit", example, "--points", "2"],
        "at least 3 model points",
    );
    assert_clean_error(&["fit", example, "--fit-modes", "0"], "at least one mode");
    assert_clean_error(&["fit", example, "--omega", "nan"], "ω");
    assert_clean_error(
        &["fit", example, "--kind", "lengths"],
        "segment lengths must be positive",
    );
    assert_clean_error(&["fit", example, "--ring", "20"], "--kind lengths only");
}
