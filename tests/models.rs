//! Scenario: the shipped example models (larva, worm with a free axial field, planar x–y body)
//! run through every stage: table, equations, operators, modes, emit.

use theory_search::artifacts::generated_files_for;
use theory_search::discretise::operators;
use theory_search::equations::derive;
use theory_search::modal::{field_modes, Params};
use theory_search::model::{Boundary, Density, Model};
use theory_search::reduce::analyse;

fn load(name: &str) -> Model {
    let path = format!("{}/tables/models/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    Model::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn the_shipped_larva_is_the_embedded_one() {
    assert_eq!(load("larva"), Model::larva());
}

#[test]
fn every_example_runs_through_every_stage() {
    for name in ["larva", "worm", "planar", "crawler"] {
        let model = load(name);
        for density in Density::ALL {
            let a = analyse(&model, density, 4).unwrap();
            assert!(
                a.fields.iter().all(|f| f.missing.is_empty()),
                "{name} {density}"
            );
        }
        let (eqs, _) = derive(&model, 4).unwrap();
        assert_eq!(eqs.len(), model.fields.len());
        let ops = operators(&model, 4, 12).unwrap();
        assert_eq!(ops.len(), 2 * model.fields.len());
        let modes = field_modes(&model, 4, 12, &Params::default(), None, false).unwrap();
        for f in &modes {
            let total: f64 = f.modes.iter().map(|m| m.variance_share).sum();
            assert!((total - 1.0).abs() < 1e-12);
        }
        let files = generated_files_for(&model, 4).unwrap();
        assert!(files
            .iter()
            .any(|(p, src)| p.ends_with("operators.rs") && src.contains("OPERATORS")));
    }
}

#[test]
fn the_worm_has_a_free_axial_field() {
    let worm = load("worm");
    assert_eq!(worm.field("x").unwrap().boundary, Boundary::FREE);
    let ops = operators(&worm, 4, 12).unwrap();
    let x = &ops[0];
    assert_eq!(
        (x.field.as_str(), x.boundary.as_str(), x.size),
        ("x", "free", 12)
    );
    assert_eq!(x.seed_name, Some("D2,f, paper Eq. 4"));
    let modes = field_modes(&worm, 4, 12, &Params::default(), None, false).unwrap();
    // Free ends: no cos/sin pairs any more.
    assert!(modes[0].degenerate_pairs.is_empty());
}

#[test]
fn the_planar_model_has_two_fields() {
    let planar = load("planar");
    let (eqs, _) = derive(&planar, 4).unwrap();
    let text: Vec<String> = eqs.iter().map(|e| e.text()).collect();
    assert_eq!(
        text,
        [
            "∂t² x = c_x ∂s² x + 2 c'_x ∂t∂s² x",
            "∂t² y = −c_y ∂s⁴ y − 2 c'_y ∂t∂s⁴ y"
        ]
    );
    let modes = field_modes(&planar, 4, 12, &Params::default(), Some(3), false).unwrap();
    assert_eq!(
        modes[1].modes[1].zero_mode.as_deref(),
        Some("in-plane rotation")
    );
}

#[test]
fn malformed_models_name_the_line() {
    let text = Model::larva_toml().replace("boundary = \"free\"", "boundary = \"floppy\"");
    let err = Model::from_toml(&text).unwrap_err().to_string();
    assert!(err.contains("line") && err.contains("floppy"), "{err}");
    let text = Model::larva_toml().replace(
        "[rayleigh.requirements]\nx = ",
        "[rayleigh.requirements]\nw = ",
    );
    let err = Model::from_toml(&text).unwrap_err().to_string();
    assert!(
        err.contains("unknown field \"w\"") || err.contains("do not mention field \"x\""),
        "{err}"
    );
}

#[test]
fn a_part_that_never_appears_is_reported_without_searching_forever() {
    let never = Model::from_toml(
        r#"
name = "never"
description = "a field that never admits a potential term"
[[fields]]
id = "u"
symbol = "u"
meaning = "a field"
boundary = "free"
[lagrangian]
bound = "tau-plus-sigma"
columns = ["OST", "DIS"]
[lagrangian.requirements]
u = ["OST", "DIS"]
[rayleigh]
bound = "tau-and-sigma"
columns = ["DIS"]
[rayleigh.requirements]
u = ["DIS"]
"#,
    )
    .unwrap();
    use theory_search::enumerate::Basis;
    let a = theory_search::reduce::analyse_basis(&never, Density::Lagrangian, 3, Basis::Monomials)
        .unwrap();
    // ∂t u is admitted and of lowest order but a total derivative: passed over, and said so.
    assert_eq!(
        a.fields[0].missing,
        [
            "L_u: ∂t u changes no equation (a total derivative: the Euler–Lagrange expression vanishes) and takes no part in the lowest-order selection",
            "L_u: no potential term is admitted at any order up to 7 (monomials are searched at most 4 orders ahead, within the 1000000-candidate limit)"
        ]
    );
    let a = analyse(&never, Density::Lagrangian, 3).unwrap();
    assert_eq!(
        a.fields[0].missing,
        [
            "L_u: ∂t u changes no equation (a total derivative: the Euler–Lagrange expression vanishes) and takes no part in the lowest-order selection",
            "L_u: no potential term is admitted at any order up to 32"
        ]
    );
    // Its admitted ∂t u is no square of a derivative: no operator, and the error says so.
    let err = field_modes(&never, 3, 12, &Params::default(), None, false)
        .unwrap_err()
        .to_string();
    assert!(err.contains("cannot discretise"), "{err}");
}
