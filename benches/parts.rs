//! Monomial basis with reduction by parts: one shift-symmetric field to order 12, the four larva
//! fields to order 8 (Lagrangian). Run with `cargo bench --bench parts`.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use theory_search::model::{Density, Model};
use theory_search::parts::reduce_model;

const ONE_FIELD: &str = r#"
name = "one"
description = "one shift-symmetric field"
[[fields]]
id = "u"
symbol = "u"
meaning = "a field"
boundary = "free"
[lagrangian]
bound = "tau-plus-sigma"
columns = ["TRAN"]
[lagrangian.requirements]
u = ["TRAN"]
[rayleigh]
bound = "tau-and-sigma"
columns = ["DIS"]
[rayleigh.requirements]
u = ["DIS"]
"#;

fn parts(c: &mut Criterion) {
    let one = Model::from_toml(ONE_FIELD).unwrap();
    let larva = Model::larva();
    let mut group = c.benchmark_group("monomials+reduction");
    group.sample_size(10);
    group.bench_function("one field, order 12", |b| {
        b.iter(|| reduce_model(black_box(&one), Density::Lagrangian, 12).unwrap())
    });
    group.bench_function("four larva fields, order 8", |b| {
        b.iter(|| reduce_model(black_box(&larva), Density::Lagrangian, 8).unwrap())
    });
    group.finish();
}

criterion_group!(benches, parts);
criterion_main!(benches);
