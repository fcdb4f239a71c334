//! The vectorisable elementary functions agree with the C library (`std`), which is the
//! reference: correctly rounded or within 1 ulp on glibc.
//!
//! Tolerances: `exp`, `ln`, `tanh` within 2 ulp of the reference; `sin`, `cos` within 2 ulp
//! or 2.5e-16 absolute (the reduction by pi/2 loses relative accuracy only next to the zeros,
//! where the absolute error stays at the rounding of the reduced argument). Special values
//! (0, +-inf, NaN, the overflow and underflow edges) must match exactly.
#![allow(clippy::unwrap_used)]
use hxai_symreg::vmath;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Special arguments at which exp, ln and tanh must agree with the reference (NaN has checks
/// of its own), each function then adding its own edges.
const ZEROS_AND_INFINITIES: [f64; 4] = [0.0, -0.0, f64::INFINITY, f64::NEG_INFINITY];

fn ulps(a: f64, b: f64) -> f64 {
    if a == b || (a.is_nan() && b.is_nan()) {
        return 0.0;
    }
    let ulp = if b == 0.0 {
        f64::MIN_POSITIVE * f64::EPSILON
    } else {
        (b.abs() * f64::EPSILON).max(5e-324)
    };
    (a - b).abs() / ulp
}

fn samples(lo: f64, hi: f64, n: usize, log: bool, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            if log {
                let e = rng.gen_range(lo..hi);
                let s = if rng.gen_bool(0.5) { 1.0 } else { -1.0 };
                s * 10f64.powf(e)
            } else {
                rng.gen_range(lo..hi)
            }
        })
        .collect()
}

/// Max ulp error of `f` against `g` over `xs`, with the worst argument.
fn worst(xs: &[f64], f: fn(f64) -> f64, g: fn(f64) -> f64, abs_ok: f64) -> (f64, f64) {
    let mut w = (0.0, 0.0);
    for &x in xs {
        let (a, b) = (f(x), g(x));
        if (a - b).abs() <= abs_ok {
            continue;
        }
        let u = ulps(a, b);
        if u > w.0 {
            w = (u, x);
        }
    }
    w
}

/// Asserts that `f` is within 2 ulp of the reference `g` at every one of `xs` where the two
/// differ by more than `abs_ok`; the message names `name` and the worst argument.
fn assert_within_2_ulp(name: &str, xs: &[f64], f: fn(f64) -> f64, g: fn(f64) -> f64, abs_ok: f64) {
    let (u, x) = worst(xs, f, g, abs_ok);
    assert!(u <= 2.0, "{name}: {u} ulp at {x:e}");
}

/// Asserts that `f` equals the reference `g` at each of the special arguments `xs` to
/// `max_ulp` (0: the same value, NaN matching NaN); the message names `name` and the argument.
fn assert_special(name: &str, xs: &[f64], f: fn(f64) -> f64, g: fn(f64) -> f64, max_ulp: f64) {
    for &x in xs {
        let (a, b) = (f(x), g(x));
        assert!(ulps(a, b) <= max_ulp, "{name}({x:e}) = {a:e}, want {b:e}");
    }
}

#[test]
fn exp_within_2_ulp() {
    for (lo, hi) in [
        (-1.0, 1.0),
        (-30.0, 30.0),
        (-745.0, 709.7),
        (-708.0, -700.0),
        (700.0, 709.78),
    ] {
        let xs = samples(lo, hi, 200_000, false, 1);
        assert_within_2_ulp("exp", &xs, vmath::exp, f64::exp, 0.0);
    }
    let xs = samples(-20.0, 2.8, 200_000, true, 2);
    assert_within_2_ulp("exp", &xs, vmath::exp, f64::exp, 0.0);
}

#[test]
fn exp_special_values() {
    assert_special("exp", &ZEROS_AND_INFINITIES, vmath::exp, f64::exp, 0.0);
    // the overflow and underflow edges
    let edges = [709.79, 710.0, 1e300, -746.0, -1e300, 709.782_712_893_384];
    assert_special("exp", &edges, vmath::exp, f64::exp, 0.0);
    assert!(vmath::exp(f64::NAN).is_nan());
    // subnormal results: absolute error of the subnormal spacing
    for x in samples(-745.1, -708.4, 20_000, false, 3) {
        let (a, b) = (vmath::exp(x), x.exp());
        assert!(
            (a - b).abs() <= 2.0 * 5e-324 + 2.0 * b * f64::EPSILON,
            "exp({x}) = {a:e} want {b:e}"
        );
    }
}

#[test]
fn ln_within_2_ulp() {
    let mut xs = samples(-310.0, 308.0, 300_000, true, 4);
    xs.extend(samples(0.5, 2.0, 200_000, false, 5));
    xs.extend(samples(0.99, 1.01, 100_000, false, 6));
    let xs: Vec<f64> = xs.into_iter().map(f64::abs).collect();
    assert_within_2_ulp("ln", &xs, vmath::ln, f64::ln, 0.0);
    // subnormal inputs
    let sub: Vec<f64> = (1..2000u64)
        .map(|k| f64::from_bits(k * 1_234_567_891))
        .collect();
    assert_within_2_ulp("ln", &sub, vmath::ln, f64::ln, 0.0);
}

#[test]
fn ln_special_values() {
    // ln(-inf) is NaN for both
    assert_special("ln", &ZEROS_AND_INFINITIES, vmath::ln, f64::ln, 1.0);
    let edges = [1.0, f64::MIN_POSITIVE, f64::MAX, 5e-324];
    assert_special("ln", &edges, vmath::ln, f64::ln, 1.0);
    for x in [-1.0, -0.5, f64::NEG_INFINITY, f64::NAN, -5e-324] {
        assert!(vmath::ln(x).is_nan(), "ln({x}) should be NaN");
    }
}

#[test]
fn sin_cos_within_2_ulp_or_tiny_absolute() {
    let mut xs = samples(-4.0, 4.0, 200_000, false, 7);
    xs.extend(samples(-60.0, 60.0, 200_000, false, 8));
    xs.extend(samples(-12.0, 6.3, 200_000, true, 9));
    assert_within_2_ulp("sin", &xs, vmath::sin, f64::sin, 2.5e-16);
    assert_within_2_ulp("cos", &xs, vmath::cos, f64::cos, 2.5e-16);
    // beyond the kernel's range the C library's answer is used
    for x in [1e6 + 1.0, -3e7, 1e300, f64::MAX] {
        assert_eq!(vmath::sin(x), x.sin());
        assert_eq!(vmath::cos(x), x.cos());
    }
    for x in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
        assert!(vmath::sin(x).is_nan() && vmath::cos(x).is_nan());
    }
    assert_eq!(vmath::sin(0.0), 0.0);
    assert_eq!(vmath::cos(0.0), 1.0);
}

#[test]
fn tanh_within_2_ulp() {
    let mut xs = samples(-3.0, 3.0, 200_000, false, 10);
    xs.extend(samples(-20.0, 2.0, 200_000, true, 11));
    xs.extend(samples(-0.7, 0.7, 200_000, false, 12));
    assert_within_2_ulp("tanh", &xs, vmath::tanh, f64::tanh, 0.0);
    assert_special("tanh", &ZEROS_AND_INFINITIES, vmath::tanh, f64::tanh, 0.0);
    assert_special("tanh", &[30.0, -30.0], vmath::tanh, f64::tanh, 0.0);
    assert!(vmath::tanh(f64::NAN).is_nan());
}

#[test]
fn batch_kernels_with_fixup_equal_scalar_functions() {
    let mut xs = samples(-8.0, 8.0, 1000, true, 13);
    xs.extend([f64::NAN, f64::INFINITY, 2e6, -1e6, 1e6]);
    let mut dst: Vec<f64> = xs.iter().map(|&x| vmath::sin_kernel(x)).collect();
    vmath::trig_fixup(&mut dst, &xs, |_, x| vmath::sin(x));
    for (d, &x) in dst.iter().zip(&xs) {
        assert!(d.to_bits() == vmath::sin(x).to_bits() || (d.is_nan() && x.sin().is_nan()));
    }
}
