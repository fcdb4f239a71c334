//! Interval arithmetic with directed rounding: the basic operations rounded outward
//! exactly (error-free transformations), the transcendental functions widened by
//! [`super::TRANSCENDENTAL_ULPS`], and each operator of [`crate::ops::Op`] over intervals.
#![allow(clippy::wildcard_imports)]
use super::*;

// ---- directed rounding of the basic operations -------------------------------------------

/// `a + b` and the exact error `(a + b) - s` (Knuth's TwoSum; exact barring overflow, where
/// the error is NaN and the caller's finiteness check rejects the result).
pub(super) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

pub(super) fn add_dn(a: f64, b: f64) -> f64 {
    let (s, e) = two_sum(a, b);
    if e < 0.0 { s.next_down() } else { s }
}

pub(super) fn add_up(a: f64, b: f64) -> f64 {
    let (s, e) = two_sum(a, b);
    if e > 0.0 { s.next_up() } else { s }
}

/// The sign of `exact - rounded` as -1, 0 or 1, or `None` where it cannot be told.
pub(super) fn sign_of(e: f64) -> Option<i8> {
    if e > 0.0 {
        Some(1)
    } else if e < 0.0 {
        Some(-1)
    } else if e == 0.0 {
        Some(0)
    } else {
        None
    }
}

/// Sign of `a * b - fl(a * b)`.
pub(super) fn mul_err(a: f64, b: f64, p: f64) -> Option<i8> {
    if a == 0.0 || b == 0.0 {
        Some(0)
    } else if p.is_finite() && p.abs() >= EFT_MIN {
        sign_of(a.mul_add(b, -p))
    } else {
        None
    }
}

/// Sign of `a / b - fl(a / b)`: the remainder `a - q b` is exact, and the quotient's error
/// is the remainder over `b`.
pub(super) fn div_err(a: f64, b: f64, q: f64) -> Option<i8> {
    if a == 0.0 {
        Some(0)
    } else if q.is_finite() && q.abs() >= EFT_MIN && a.abs() >= EFT_MIN {
        let r = sign_of((-q).mul_add(b, a))?;
        Some(if b > 0.0 { r } else { -r })
    } else {
        None
    }
}

pub(super) fn round_dn(v: f64, err: Option<i8>) -> f64 {
    match err {
        Some(e) if e >= 0 => v,
        _ => v.next_down(),
    }
}

pub(super) fn round_up(v: f64, err: Option<i8>) -> f64 {
    match err {
        Some(e) if e <= 0 => v,
        _ => v.next_up(),
    }
}

pub(super) fn mul_dn(a: f64, b: f64) -> f64 {
    let p = a * b;
    round_dn(p, mul_err(a, b, p))
}

pub(super) fn mul_up(a: f64, b: f64) -> f64 {
    let p = a * b;
    round_up(p, mul_err(a, b, p))
}

pub(super) fn div_dn(a: f64, b: f64) -> f64 {
    let q = a / b;
    round_dn(q, div_err(a, b, q))
}

pub(super) fn div_up(a: f64, b: f64) -> f64 {
    let q = a / b;
    round_up(q, div_err(a, b, q))
}

/// Sign of `sqrt(x) - fl(sqrt(x))`, from the exact `x - s^2`.
pub(super) fn sqrt_err(x: f64, s: f64) -> Option<i8> {
    if x == 0.0 {
        Some(0)
    } else if x >= EFT_MIN {
        sign_of((-s).mul_add(s, x))
    } else {
        None
    }
}

/// `n` steps down (towards -inf).
pub(super) fn steps_dn(mut v: f64, n: u32) -> f64 {
    for _ in 0..n {
        v = v.next_down();
    }
    v
}

/// `n` steps up (towards +inf).
pub(super) fn steps_up(mut v: f64, n: u32) -> f64 {
    for _ in 0..n {
        v = v.next_up();
    }
    v
}

/// `[lo, hi]` computed by a transcendental function, widened for its error.
pub(super) fn widen_transcendental(lo: f64, hi: f64) -> Interval {
    Interval::new(
        steps_dn(lo, TRANSCENDENTAL_ULPS),
        steps_up(hi, TRANSCENDENTAL_ULPS),
    )
}

pub(super) fn finite(iv: Interval) -> Iv {
    if iv.is_finite() {
        Ok(iv)
    } else {
        Err(WHY_OVERFLOW)
    }
}

// ---- interval operations -----------------------------------------------------------------

pub(super) fn add(a: Interval, b: Interval) -> Iv {
    finite(Interval::new(add_dn(a.lo, b.lo), add_up(a.hi, b.hi)))
}

pub(super) fn sub(a: Interval, b: Interval) -> Iv {
    finite(Interval::new(add_dn(a.lo, -b.hi), add_up(a.hi, -b.lo)))
}

pub(super) fn neg(a: Interval) -> Interval {
    Interval::new(-a.hi, -a.lo)
}

/// Min and max of `f` over the four corners.
pub(super) fn corners(a: Interval, b: Interval, f: impl Fn(f64, f64) -> f64) -> (f64, f64) {
    let v = [f(a.lo, b.lo), f(a.lo, b.hi), f(a.hi, b.lo), f(a.hi, b.hi)];
    // NaN never arises from finite corners of a product or of a quotient by a nonzero value
    v.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        })
}

pub(super) fn mul(a: Interval, b: Interval) -> Iv {
    let (lo, _) = corners(a, b, mul_dn);
    let (_, hi) = corners(a, b, mul_up);
    finite(Interval::new(lo, hi))
}

pub(super) fn div(a: Interval, b: Interval) -> Iv {
    if b.holds_zero() {
        return Err(WHY_DIV);
    }
    let (lo, _) = corners(a, b, div_dn);
    let (_, hi) = corners(a, b, div_up);
    finite(Interval::new(lo, hi))
}

pub(super) fn square(a: Interval) -> Iv {
    let (lo, hi) = if a.lo >= 0.0 {
        (mul_dn(a.lo, a.lo), mul_up(a.hi, a.hi))
    } else if a.hi <= 0.0 {
        (mul_dn(a.hi, a.hi), mul_up(a.lo, a.lo))
    } else {
        (0.0, mul_up(a.lo, a.lo).max(mul_up(a.hi, a.hi)))
    };
    // a square (exact or rounded) is never below 0
    finite(Interval::new(lo.max(0.0), hi))
}

pub(super) fn abs(a: Interval) -> Interval {
    if a.lo >= 0.0 {
        a
    } else if a.hi <= 0.0 {
        neg(a)
    } else {
        Interval::new(0.0, (-a.lo).max(a.hi))
    }
}

pub(super) fn sqrt(a: Interval) -> Iv {
    if a.lo < 0.0 {
        return Err(WHY_SQRT);
    }
    let (s, t) = (a.lo.sqrt(), a.hi.sqrt());
    let lo = round_dn(s, sqrt_err(a.lo, s)).max(0.0);
    finite(Interval::new(lo, round_up(t, sqrt_err(a.hi, t))))
}

/// `exp` over `a`; `exp` (exact or the evaluator's) is never below 0.
pub(super) fn exp(a: Interval) -> Iv {
    let iv = widen_transcendental(vmath::exp(a.lo), vmath::exp(a.hi));
    finite(Interval::new(iv.lo.max(0.0), iv.hi))
}

pub(super) fn ln(a: Interval) -> Iv {
    if a.lo <= 0.0 {
        return Err(WHY_LOG);
    }
    finite(widen_transcendental(vmath::ln(a.lo), vmath::ln(a.hi)))
}

pub(super) fn tanh(a: Interval) -> Iv {
    // |tanh| <= 1 exactly, and the evaluator's `1 - 2/(e + 1)` and `x + x z P/Q` forms never
    // leave [-1, 1] either
    let iv = widen_transcendental(vmath::tanh(a.lo), vmath::tanh(a.hi));
    finite(Interval::new(iv.lo.max(-1.0), iv.hi.min(1.0)))
}

/// Whether `[a.lo, a.hi]` may hold a point `x0 + k period` for an integer `k` (true when
/// unsure; see [`PERIOD_SLACK`]). The slack grows with the larger `|k|` of the two ends, so a
/// sub-interval never answers "yes" where its interval answers "no".
pub(super) fn may_hold_periodic_point(a: Interval, x0: f64, period: f64) -> bool {
    let t_lo = (a.lo - x0) / period;
    let t_hi = (a.hi - x0) / period;
    let eps = PERIOD_SLACK * (1.0 + t_lo.abs().max(t_hi.abs()));
    (t_lo - eps).ceil() <= (t_hi + eps).floor()
}

/// `sin` or `cos` over `a`: `f` the function, maxima at `max_at + 2 k pi`, minima at
/// `min_at + 2 k pi`.
pub(super) fn periodic(a: Interval, f: fn(f64) -> f64, max_at: f64, min_at: f64) -> Iv {
    let (mut lo, mut hi) = if a.width() >= TAU {
        (-1.0, 1.0)
    } else {
        let (fl, fh) = (f(a.lo), f(a.hi));
        let mut lo = fl.min(fh);
        let mut hi = fl.max(fh);
        if may_hold_periodic_point(a, max_at, TAU) {
            hi = hi.max(1.0);
        }
        if may_hold_periodic_point(a, min_at, TAU) {
            lo = lo.min(-1.0);
        }
        (lo, hi)
    };
    let iv = widen_transcendental(lo, hi);
    lo = iv.lo - TRIG_ABS_SLACK;
    hi = iv.hi + TRIG_ABS_SLACK;
    finite(Interval::new(lo.next_down(), hi.next_up()))
}

pub(super) fn tan(a: Interval) -> Iv {
    if a.width() >= PI || may_hold_periodic_point(a, FRAC_PI_2, PI) {
        return Err(WHY_TAN);
    }
    finite(widen_transcendental(a.lo.tan(), a.hi.tan()))
}

/// `a^b` (`f64::powf`) over the boxes `a` and `b`.
pub(super) fn pow(a: Interval, b: Interval) -> Iv {
    if b.lo == b.hi && b.lo.fract() == 0.0 {
        return pow_whole(a, b.lo);
    }
    if a.lo > 0.0 {
        // a^b = exp(b ln a) for a > 0; the enclosure of the composition holds the exact
        // values, and the widening covers `powf`'s own error
        let e = exp(mul(ln(a)?, b)?)?;
        return finite(widen_transcendental(e.lo, e.hi));
    }
    if a.lo < 0.0 {
        return Err(WHY_POW_NEG);
    }
    // base in [0, hi]: for b > 0, a^b rises with a from 0 (powf(0, b) = 0)
    if b.lo <= 0.0 {
        return Err(WHY_POW_ZERO);
    }
    if a.hi == 0.0 {
        return Ok(Interval::point(0.0));
    }
    let top = pow(Interval::point(a.hi), b)?;
    Ok(Interval::new(0.0, top.hi))
}

/// `a^n` for a whole number `n`: exact in sign for a negative base.
pub(super) fn pow_whole(a: Interval, n: f64) -> Iv {
    if n == 0.0 {
        // powf(x, 0) = 1 for every x
        return Ok(Interval::point(1.0));
    }
    if n < 0.0 && a.holds_zero() {
        return Err(WHY_POW_ZERO);
    }
    let even = n % 2.0 == 0.0;
    let (fl, fh) = (a.lo.powf(n), a.hi.powf(n));
    let (lo, hi) = if even && n > 0.0 && a.lo < 0.0 && a.hi > 0.0 {
        // x^n falls to 0 at x = 0 and rises on both sides
        (0.0, fl.max(fh))
    } else {
        // monotone on the interval: an odd power everywhere (off 0 when negative), an even
        // one on either side of 0
        (fl.min(fh), fl.max(fh))
    };
    let iv = widen_transcendental(lo, hi);
    let lo = if even { iv.lo.max(0.0) } else { iv.lo };
    finite(Interval::new(lo, iv.hi))
}

pub(super) fn apply1(op: Op, a: Interval) -> Iv {
    match op {
        Op::Exp => exp(a),
        Op::Log => ln(a),
        Op::Sqrt => sqrt(a),
        Op::Square => square(a),
        Op::Inverse => div(Interval::point(1.0), a),
        Op::Sin => periodic(a, vmath::sin, FRAC_PI_2, -FRAC_PI_2),
        Op::Cos => periodic(a, vmath::cos, 0.0, PI),
        Op::Tanh => tanh(a),
        Op::Abs => Ok(abs(a)),
        Op::Gaussian => exp(neg(square(a)?)),
        Op::Tan => tan(a),
        _ => Err(WHY_MALFORMED),
    }
}

pub(super) fn apply2(op: Op, a: Interval, b: Interval) -> Iv {
    match op {
        Op::Add => add(a, b),
        Op::Sub => sub(a, b),
        Op::Mul => mul(a, b),
        Op::Div => div(a, b),
        Op::Gaussian2 => exp(neg(add(square(a)?, square(b)?)?)),
        Op::Pow => pow(a, b),
        _ => Err(WHY_MALFORMED),
    }
}

// ---- one box -----------------------------------------------------------------------------
