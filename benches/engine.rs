//! Enumerate, decide and reduce both densities of the larva model at several orders.
//! Run with `cargo bench --bench engine`; figures are in `docs/benchmarks.md`.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use std::hint::black_box;
use theory_search::enumerate::Basis;
use theory_search::model::{Density, Model};
use theory_search::reduce::{analyse, analyse_basis};
use theory_search::table::{write, Format};

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

/// The monomial basis (products of factors), decided and reduced, then written as text: the
/// Python peer of `benches/peer_monomials.py` does the same work.
fn monomials(c: &mut Criterion) {
    let model = Model::larva();
    let mut group = c.benchmark_group("monomials-both-densities");
    group.sample_size(10);
    for order in [6u32, 8] {
        group.bench_with_input(BenchmarkId::new("text", order), &order, |b, &order| {
            b.iter(|| {
                let analyses: Vec<_> = Density::ALL
                    .iter()
                    .map(|&d| analyse_basis(&model, d, order, Basis::Monomials).unwrap())
                    .collect();
                let mut sink = std::io::sink();
                write(&model, &analyses, Format::Text, &mut sink).unwrap();
            })
        });
    }
    group.finish();
}

criterion_group!(benches, engine, monomials);
criterion_main!(benches);
