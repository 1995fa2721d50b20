//! The fit's target: 10⁶ frames of 12-point midlines streamed in about a second, in memory that
//! does not grow with the number of frames. Criterion times 10⁵ frames held in memory (parse,
//! angles, projection, covariance, Welch); the README gives the CLI figures for a 10⁶-frame
//! file measured with `/usr/bin/time`.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use theory_search::fit::{fit, FitSettings};
use theory_search::modal::Params;
use theory_search::model::Model;
use theory_search::recording::InputKind;

fn frames(n: usize) -> String {
    let mut s = String::new();
    for k in 0..n {
        let t = k as f64;
        s += &format!("{t}");
        for j in 0..12 {
            let y = 0.01 * (0.3 * t + j as f64).sin() + 0.005 * (0.11 * t * (j as f64 + 1.0)).cos();
            s += &format!(" {j} {y:.6}");
        }
        s.push('\n');
    }
    s
}

fn bench(c: &mut Criterion) {
    let text = frames(100_000);
    let model = Model::larva();
    let settings = FitSettings::new(InputKind::Midline);
    let mut group = c.benchmark_group("fit");
    group.sample_size(10);
    group.bench_function("100000 frames, N = 12", |b| {
        b.iter(|| {
            fit(
                std::io::Cursor::new(black_box(text.as_bytes())),
                &model,
                &Params::default(),
                &settings,
            )
            .unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
