//! The shared CSV reader on a 1,000,000-row, 20-column file (issue 52's goal: no slower than
//! the `hybrid` reader it replaced).
//!
//! The reader of every command (`read_mixed_table`, as `hxai hybrid` calls it) reads the
//! file's text once more than the reader it replaced did: a first pass finds the separator
//! and checks for blank lines, Excel's empty rows and lone `\r` line ends
//! (`normalise`); a regular comma-separated file is then handed to polars as it is, as
//! before. So the cost of the change is that pass, measured here beside the whole read in
//! the same run: `first pass` over `read_mixed_table` is the fraction the one reader adds
//! (docs/benchmarks.md). `read_table` (numbers only, `hxai sr`) is measured too.
//!
//! The file (about 180 MB) is generated deterministically into a temporary folder, never
//! committed. Run: `cargo bench -p hxai-data --bench reader`.
use criterion::{Criterion, criterion_group, criterion_main};
use std::fmt::Write as _;
use std::hint::black_box;

const ROWS: usize = 1_000_000;
const COLS: usize = 20;

/// A deterministic table of numbers with 6 to 8 significant digits.
fn csv_text() -> String {
    let mut s = String::with_capacity(ROWS * COLS * 10);
    let names: Vec<String> = (0..COLS).map(|j| format!("x{j}")).collect();
    s.push_str(&names.join(","));
    s.push('\n');
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    for _ in 0..ROWS {
        for j in 0..COLS {
            // xorshift: deterministic, no dependency
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let u = (state >> 11) as f64 / (1u64 << 53) as f64;
            if j > 0 {
                s.push(',');
            }
            let _ = write!(s, "{:.6}", 10.0 * u - 3.0);
        }
        s.push('\n');
    }
    s
}

fn bench(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("hxai-reader-bench-{}", std::process::id()));
    if std::fs::create_dir_all(&dir).is_err() {
        return;
    }
    let path = dir.join("million.csv");
    let text = csv_text();
    if std::fs::write(&path, &text).is_err() {
        return;
    }
    let mut g = c.benchmark_group("reader_1m_rows_20_cols");
    g.sample_size(10);
    g.bench_function("read_mixed_table", |b| {
        b.iter(|| black_box(hxai_data::read_mixed_table(&path).map(|t| t.names.len())))
    });
    g.bench_function("read_table", |b| {
        b.iter(|| black_box(hxai_data::read_table(&path).map(|t| t.n_rows())))
    });
    g.bench_function("first_pass", |b| {
        b.iter(|| black_box(hxai_data::bench_support::needs_rewrite(black_box(&text))))
    });
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
