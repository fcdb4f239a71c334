//! Fit times of the Table 3 baselines and a 5-fold CV of each on a 1,000 x 12 table.
//!
//! The table comes from a splitmix64 stream that `scripts/bench_baselines.py` reproduces
//! bit for bit, so scikit-learn is timed on exactly the same numbers. Every model except the
//! forest runs on one thread (scikit-learn's defaults are single-threaded); the forest uses
//! the global rayon pool, so run with `RAYON_NUM_THREADS=2` and compare with `n_jobs=2`.
#![allow(missing_docs)]

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use hxai_baselines::*;
use std::hint::black_box;

struct SplitMix(u64);
impl SplitMix {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// Friedman-1-like target on 12 uniform features (7 of them pure noise).
fn table(n: usize, p: usize) -> (Table, Vec<f64>) {
    let mut g = SplitMix(2026);
    let mut data = Vec::with_capacity(n);
    let mut y = Vec::with_capacity(n);
    for _ in 0..n {
        let row: Vec<f64> = (0..p).map(|_| g.uniform()).collect();
        let noise = g.uniform() - 0.5;
        y.push(
            10.0 * (std::f64::consts::PI * row[0] * row[1]).sin()
                + 20.0 * (row[2] - 0.5).powi(2)
                + 10.0 * row[3]
                + 5.0 * row[4]
                + noise,
        );
        data.push(row);
    }
    let names = (0..p).map(|j| format!("x{j}")).collect();
    (
        Table::from_rows(names, &data).expect("finite n x p rows by construction"),
        y,
    )
}

fn model(name: &str) -> Box<dyn Regressor> {
    match name {
        "linear" => Box::new(LinearRegression::new()),
        "lasso_cv" => Box::new(LassoCv::new()),
        "tree_5" => Box::new(DecisionTree::with_max_leaf_nodes(5)),
        "tree_8" => Box::new(DecisionTree::with_max_leaf_nodes(8)),
        _ => Box::new(RandomForest::new()),
    }
}

fn bench(c: &mut Criterion) {
    let (x, y) = table(1000, 12);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("thread pool");
    let folds = hxai_eval::kfold(x.n_rows(), 5, 42).expect("1000 rows, 5 folds");
    for name in ["linear", "lasso_cv", "tree_5", "tree_8", "forest"] {
        let mut g = c.benchmark_group(name);
        if name == "forest" {
            g.sample_size(10);
        }
        let run = |f: &(dyn Fn() + Sync)| {
            if name == "forest" {
                f()
            } else {
                one.install(f)
            }
        };
        g.bench_function(BenchmarkId::new("fit", "1000x12"), |b| {
            b.iter(|| {
                run(&|| {
                    let mut m = model(name);
                    m.fit(black_box(&x), black_box(&y)).expect("valid data");
                    black_box(m.predict(&x).expect("fitted"));
                })
            })
        });
        g.bench_function(BenchmarkId::new("cv5", "1000x12"), |b| {
            b.iter(|| {
                run(&|| {
                    black_box(
                        cross_validate(&|| model(name), &x, &y, &folds, &mut |_| {})
                            .expect("valid data"),
                    );
                })
            })
        });
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
