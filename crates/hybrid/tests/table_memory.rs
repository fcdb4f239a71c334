//! A large table's fit keeps its memory near the data's own size (issue 67; its own test
//! binary: the counting allocator sees every thread, so nothing else may run beside it).
//!
//! The bound is measured by the test itself: the peak of the bytes allocated during a fit,
//! above what was live before it, at 2x10^4 and at 10^5 rows. Their difference over the
//! 8x10^4 extra rows is what each row costs the fit; the data itself is 9 columns of 8
//! bytes, 72 bytes a row. Before the search worked on a sample, a row cost the fit about
//! 8.5 kB (8.3 GB at 10^6 rows).
// Implementing `GlobalAlloc` needs `unsafe impl`, allowed in this test binary only.
#![allow(unsafe_code)]

use hxai_hybrid::tables::{self, CorrectionForm, Form, TableConfig};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicIsize, Ordering};

struct Counting;

static LIVE: AtomicIsize = AtomicIsize::new(0);
static PEAK: AtomicIsize = AtomicIsize::new(0);

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
    let (small, large) = (fit_peak(20_000), fit_peak(100_000));
    let per_row = (large - small) / 80_000;
    assert!(
        per_row <= BYTES_PER_ROW,
        "the fit's peak grew by {per_row} bytes a row (peaks {small} and {large} bytes at \
         2x10^4 and 10^5 rows)"
    );
}
