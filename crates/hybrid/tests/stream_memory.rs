//! The streaming estimator's memory does not grow with the stream (its own test binary: the
//! counting allocator sees every thread, so nothing else may run beside it).
// Implementing `GlobalAlloc` needs `unsafe impl`, allowed in this test binary only.
#![allow(unsafe_code)]

use hxai_hybrid::records::RecordModel;
use hxai_hybrid::records::stream::Estimator;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicIsize, Ordering};

struct Counting;

static LIVE: AtomicIsize = AtomicIsize::new(0);

// SAFETY: forwards to the system allocator unchanged; only counts the bytes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LIVE.fetch_add(layout.size() as isize, Ordering::Relaxed);
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
