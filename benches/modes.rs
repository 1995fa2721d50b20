//! The modal solver's targets: all modes of all four larva fields at N = 2000, and the lowest 20
//! at N = 100 000 (shares exact over all modes). Run with `cargo bench --bench modes`; compare
//! with LAPACK through `python3 benches/lapack_eigvalsh.py 2000` (needs numpy).

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use theory_search::modal::{field_modes, Params};
use theory_search::model::Model;

fn modes(c: &mut Criterion) {
    let model = Model::larva();
    let params = Params::default();
    let mut group = c.benchmark_group("modes");
    group.sample_size(20);
    group.bench_function("all modes, N = 2000", |b| {
        b.iter(|| field_modes(black_box(&model), 4, 2000, &params, None, false).unwrap())
    });
    group.bench_function("lowest 20, N = 100000", |b| {
        b.iter(|| field_modes(black_box(&model), 4, 100_000, &params, Some(20), false).unwrap())
    });
    group.bench_function("lowest 20 with shapes, N = 100000", |b| {
        b.iter(|| field_modes(black_box(&model), 4, 100_000, &params, Some(20), true).unwrap())
    });
    group.finish();
}

criterion_group!(benches, modes);
criterion_main!(benches);
