//! Fit + predict time of `GradientBoosting` at scikit-learn's defaults on the stored
//! Friedman #1 table (testdata/boosting/friedman1_*.csv: fit on its 800 training rows,
//! predict its 200 test rows).
//!
//! `python3 scripts/ref_boosting.py --time` times scikit-learn's
//! `HistGradientBoostingRegressor()` on the same rows (median of 5, on its default
//! threads); quote the ratio of the two medians measured in the same session, not the
//! absolute times. `threads/2` matches scikit-learn's default of every core on a 2-core
//! machine; `threads/1` is the sequential time.
#![allow(missing_docs)]

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use hxai_baselines::*;
use std::hint::black_box;

/// Features and target of a stored CSV (header, then rows; `y` last).
fn read_csv(name: &str) -> (Table, Vec<f64>) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../testdata/boosting")
        .join(name);
    let text = std::fs::read_to_string(&path).expect("run scripts/ref_boosting.py first");
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .expect("a header")
        .split(',')
        .map(String::from)
        .collect();
    let p = header.len() - 1;
    let (mut cols, mut y) = (vec![Vec::new(); p], Vec::new());
    for line in lines {
        let row: Vec<f64> = line
            .split(',')
            .map(|v| v.parse().expect("a number"))
            .collect();
        for (c, v) in cols.iter_mut().zip(&row) {
            c.push(*v);
        }
        y.push(row[p]);
    }
    (
        Table::new(header[..p].to_vec(), cols).expect("finite columns"),
        y,
    )
}

fn bench(c: &mut Criterion) {
    let (x_train, y_train) = read_csv("friedman1_train.csv");
    let (x_test, _) = read_csv("friedman1_test.csv");
    let mut g = c.benchmark_group("boosting");
    for threads in [1usize, 2] {
        // pools built once, outside the timing; the model runs in the caller's pool
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool");
        let id = BenchmarkId::new("fit_predict_800x5", format!("threads/{threads}"));
        g.bench_function(id, |b| {
            b.iter(|| {
                pool.install(|| {
                    let mut m = GradientBoosting::new();
                    m.fit(black_box(&x_train), black_box(&y_train))
                        .expect("valid data");
                    black_box(m.predict(&x_test).expect("fitted"));
                })
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
