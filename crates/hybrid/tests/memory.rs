//! The memory of the hybrid's long work, in a test binary of its own: its counting allocator
//! sees every thread, so nothing else may run beside it, and its tests take [`ALONE`] so
//! they do not run beside each other either.
//!
//! - The streaming estimator's memory does not grow with the stream.
//! - A large table's fit keeps its memory near the data's own size (issue 67). The bound is
//!   measured by the test itself: the peak of the bytes allocated during a fit, above what
//!   was live before it, at 2x10^4 and at 10^5 rows. Their difference over the 8x10^4 extra
//!   rows is what each row costs the fit; the data itself is 9 columns of 8 bytes, 72 bytes
//!   a row. Before the search worked on a sample, a row cost the fit about 8.5 kB (8.3 GB
//!   at 10^6 rows).
// Implementing `GlobalAlloc` needs `unsafe impl`, allowed in this test binary only.
#![allow(unsafe_code)]

use hxai_hybrid::records::RecordModel;
use hxai_hybrid::records::stream::Estimator;
use hxai_hybrid::tables::{self, CorrectionForm, Form, TableConfig};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::Mutex;
use std::sync::atomic::{AtomicIsize, Ordering};

struct Counting;

static LIVE: AtomicIsize = AtomicIsize::new(0);
static PEAK: AtomicIsize = AtomicIsize::new(0);

/// Held by each test for its whole run: the counts are the test's alone.
static ALONE: Mutex<()> = Mutex::new(());

// SAFETY: forwards to the system allocator unchanged; only counts the bytes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let size = layout.size() as isize;
        let now = LIVE.fetch_add(size, Ordering::Relaxed) + size;
        PEAK.fetch_max(now, Ordering::Relaxed);
        // SAFETY: the caller's contract is passed on to the system allocator.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size() as isize, Ordering::Relaxed);
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

fn accel(n: usize, fs: f64, f: f64) -> Vec<f64> {
    let w = 2.0 * std::f64::consts::PI * f;
    (0..n)
        .map(|i| -6e-6 * w * w * (w * i as f64 / fs).sin() + 1e-3 * ((i * 7919) % 101) as f64)
        .collect()
}

/// Memory is constant in the stream's length: after the first windows, pushing 60 more
/// seconds at 10 kHz leaves the estimator's live memory where it was (within 64 KiB).
#[test]
fn memory_does_not_grow_with_the_stream() {
    let _alone = ALONE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let (fs, f) = (10_000.0, 30.0);
    let chunk = accel(10_000, fs, f);
    let model = RecordModel::from_json(include_str!("../../../testdata/bad/good/model.json"))
        .expect("the test model loads");
    let mut est = Estimator::new(&model, f, fs).expect("estimator");
    let mut rows = Vec::with_capacity(chunk.len());
    for _ in 0..10 {
        rows.clear();
        est.push_into(&chunk, &mut rows).expect("push");
    }
    let before = LIVE.load(Ordering::Relaxed);
    for _ in 0..60 {
        rows.clear();
        est.push_into(&chunk, &mut rows).expect("push");
    }
    let after = LIVE.load(Ordering::Relaxed);
    assert!(
        (after - before).abs() <= 64 * 1024,
        "live memory moved by {} bytes over 60 s of stream",
        after - before
    );
}

/// Bytes a training row may cost the fit above the data's own 72: the columns the fit
/// derives per row (physics, deltas, the correction's feature table, predictions, the
/// split's indices) are a few dozen numbers, not the thousand a per-row copy of the work
/// would be.
const BYTES_PER_ROW: isize = 1024;

/// The peak bytes a fit of `n` rows of the roughness case allocates above those live
/// before it (the table is generated first and counted out).
fn fit_peak(n: usize) -> isize {
    let table = hxai_sim::cases::roughness(&hxai_sim::cases::RoughnessConfig {
        n_rows: n,
        seed: 42,
        ..Default::default()
    })
    .expect("the case generates");
    let mut cfg = TableConfig::new("Ra_um", "1000*feed_mm^2/(32*nose_radius_mm) + Ra0");
    cfg.calibrate = vec!["Ra0".into()];
    cfg.init.insert("Ra0".into(), 0.0);
    cfg.exclude = vec!["tool".into()];
    cfg.correction = CorrectionForm::Multiplicative;
    cfg.form = Form::Factors;
    let before = LIVE.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let model = tables::fit(&table, &cfg, &mut |_| {}).expect("the fit runs");
    let peak = PEAK.load(Ordering::Relaxed) - before;
    // the structure was searched on the sample, the constants on every training row
    let sample = model.search_sample.as_ref().expect("a sample at this size");
    assert!(sample.rows >= cfg.search_rows && sample.rows <= cfg.search_rows + 16);
    assert_eq!(sample.training_rows, model.split.train.len());
    peak
}

#[test]
fn a_large_fit_costs_each_row_a_few_numbers() {
    let _alone = ALONE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let (small, large) = (fit_peak(20_000), fit_peak(100_000));
    let per_row = (large - small) / 80_000;
    assert!(
        per_row <= BYTES_PER_ROW,
        "the fit's peak grew by {per_row} bytes a row (peaks {small} and {large} bytes at \
         2x10^4 and 10^5 rows)"
    );
}
