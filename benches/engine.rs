//! Enumerate, decide and reduce both densities of the larva model at several orders.
//! Run with `cargo bench --bench engine`; figures are recorded in the README.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use std::hint::black_box;
use theory_search::model::{Density, Model};
use theory_search::reduce::analyse;

fn engine(c: &mut Criterion) {
    let model = Model::larva();
    let mut group = c.benchmark_group("enumerate-decide-reduce");
    for order in [4u32, 8, 12, 16] {
        for density in Density::ALL {
            group.bench_with_input(
                BenchmarkId::new(density.key(), order),
                &order,
                |b, &order| b.iter(|| analyse(black_box(&model), density, order).unwrap()),
            );
        }
    }
    group.finish();
}

criterion_group!(benches, engine);
criterion_main!(benches);
