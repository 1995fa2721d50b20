//! Property: the JSON contract of `theory-search --format json` holds at every order from 1 to
//! the maximum, and agrees with the rows it reports.

use serde_json::Value;
use theory_search::enumerate::MAX_ORDER;
use theory_search::model::{Density, Model};
use theory_search::reduce::analyse;
use theory_search::table::json_report;
use theory_search::term::Term;

#[test]
fn contract_holds_at_every_order() {
    let model = Model::larva();
    for order in 1..=MAX_ORDER {
        let analyses: Vec<_> = Density::ALL
            .iter()
            .map(|&d| analyse(&model, d, order).unwrap())
            .collect();
        let v = json_report(&model, &analyses);
        assert_eq!(v["order"], order);
        for (key, reqs) in [
            ("lagrangian", ["OST", "TRAN", "REF", "KIN", "ROT"]),
            ("rayleigh", ["DIS", "TRAN", "GAL", "REF", "SPIN"]),
        ] {
            let d = &v[key];
            assert!(d["bound"]
                .as_str()
                .unwrap()
                .starts_with(&format!("δ ≤ {order}, ε ≤ {order}")));
            assert_eq!(d["requirements"], serde_json::json!(reqs));
            assert_eq!(d["fields"], serde_json::json!(["x", "theta", "y", "z"]));
            let rows = d["rows"].as_array().unwrap();
            assert!(!rows.is_empty());
            for row in rows {
                let term: Term = row["term"].as_str().unwrap().parse().unwrap();
                let factors = row["factors"].as_array().unwrap();
                assert_eq!(factors.len(), term.factors().len());
                for (j, f) in term.factors().iter().zip(factors) {
                    assert_eq!(
                        (f["t"].as_u64(), f["s"].as_u64(), f["power"].as_u64()),
                        (
                            Some(j.deriv.t as u64),
                            Some(j.deriv.s as u64),
                            Some(j.power as u64)
                        )
                    );
                }
                let o = term.orders();
                for (k, want) in [
                    ("delta", o.delta),
                    ("epsilon", o.epsilon),
                    ("tau", o.tau),
                    ("sigma", o.sigma),
                ] {
                    assert_eq!(row[k], want, "{k} of {term}");
                }
                for r in reqs {
                    assert!(row["satisfies"][r].is_boolean());
                    // A failed requirement carries its reason.
                    assert_eq!(
                        row["satisfies"][r] == false,
                        row["rejected"].get(r).is_some()
                    );
                }
                for f in ["x", "theta", "y", "z"] {
                    assert!(row["included"][f].is_boolean());
                    let included = row["included"][f] == true;
                    let listed = d["survivors"][f].as_array().unwrap().contains(&row["term"]);
                    assert_eq!(included, listed);
                }
            }
            assert!(d["survivors"].as_object().unwrap().len() == 4);
        }
    }
}

#[test]
fn bare_powers_have_zero_derivative_factors() {
    let model = Model::larva();
    let a = analyse(&model, Density::Lagrangian, 4).unwrap();
    let v: Value = json_report(&model, &[a]);
    assert!(v.get("rayleigh").is_none());
    let rows = v["lagrangian"]["rows"].as_array().unwrap();
    let cube = rows.iter().find(|r| r["term"] == "φ³").unwrap();
    assert_eq!(
        cube["factors"],
        serde_json::json!([{"t": 0, "s": 0, "power": 3}])
    );
    assert_eq!(
        v["lagrangian"]["survivors"]["x"],
        serde_json::json!(["(∂t φ)²", "(∂s φ)²"])
    );
}
