//! A sound interval enclosure of a program over a box of inputs.
//!
//! A candidate (a correction, a factor, a slot, any `hxai sr` model) that is undefined,
//! infinite or has a pole somewhere in the region it will be used in must not be accepted,
//! and checking it at the training rows is not enough: `c/(x - 0.5)` is finite at
//! `x = 0, 0.25, 0.75, 1` and has a pole between them. This module decides the question for
//! a whole box at once with interval arithmetic: every node of the postfix program gets an
//! interval that holds all its values over the box, computed from its children's intervals
//! ([`enclose`]). Where a node's interval reaches outside its operator's domain (a divisor
//! interval holding 0, a logarithm's argument reaching 0, a tangent's argument reaching a
//! pole, a bound overflowing), the answer is [`Enclosure::Undefined`] with the reason; else
//! it is [`Enclosure::Bounded`] with an interval that holds every value of the program over
//! the box, which is also the bound of the correction over the box that reports quote.
//!
//! Interval arithmetic over-estimates when a variable appears more than once: `x^2 - x + 1`
//! over `[0, 2]` gets `[0, 4] - [0, 2] + 1 = [-1, 5]` though its true range is
//! `[0.75, 3]`, so `1/(x^2 - x + 1)` looks like a division by something that can be 0. The
//! over-estimate shrinks in proportion to the width of the box, so [`enclose_refined`]
//! bisects: it splits an undefined box along its widest input (widths measured relative to
//! the original box, so the units of the columns do not matter) and encloses both halves,
//! until every box is defined or the budget of boxes is spent; then, with the budget left,
//! it splits the boxes that set the lower or the upper bound until the bound is within
//! [`BOUND_TOLERANCE`] of the range seen at the boxes' centres (Moore and Skelboe's
//! scheme). A pole that is really there keeps some box undefined at any size, so the answer
//! stays [`Enclosure::Undefined`].
//!
//! Soundness. Every bound is rounded outward. Sums, products, quotients and square roots
//! are rounded in the right direction exactly (the rounding error of the nearest result is
//! recovered with an error-free transformation, so an exact result such as `-1 * 2` stays
//! a single number, and an inexact one moves one step outward). The transcendental
//! functions are not correctly rounded (the evaluator's own [`crate::vmath`] is within 2 ulp
//! of the C library, which is itself within about 1 ulp of the exact value), so their
//! bounds are widened by [`TRANSCENDENTAL_ULPS`] more, and `sin`/`cos` also by
//! [`TRIG_ABS_SLACK`] for their absolute error near their zeros. Monotone functions are
//! evaluated at the ends of the interval; `sin` and `cos` add the extremum `+-1` when the
//! interval may hold a multiple of `pi/2` where it is attained (decided with a tolerance
//! [`PERIOD_SLACK`] that errs towards including it). The resulting interval holds every
//! exact value over the box and every value the crate's [`crate::eval::Evaluator`] computes
//! in `f64` at a point of the box, so a program that evaluates to NaN or an infinity at
//! some point of the box is never [`Enclosure::Bounded`]. That last guarantee rests on the
//! error bounds of `vmath` (tested against the C library in `tests/it/vmath.rs`) and of the
//! C library's `tan` and `pow` (documented by glibc and musl, not proven here).
//!
//! Where the enclosure is deliberately cautious: a power `a^b` is defined for a base that
//! can be `<= 0` only when the exponent is a single whole number (a constant such as `3` or
//! `-2`; an exponent computed from several constants is a single number only when every
//! step was exact) or when the base reaches 0 but not below and the exponent is `> 0`;
//! otherwise a base reaching 0 or below is undefined, even where `f64::powf` happens to
//! give a number. A tangent within [`PERIOD_SLACK`] (relative) of a pole is undefined. An
//! intermediate bound beyond `f64::MAX` is undefined even where the evaluator would recover
//! (`exp(-x^2)` for `|x| > 1e154`).
use crate::ops::Op;
use crate::program::{Node, Program};
use crate::vmath;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Ulps by which a transcendental bound is widened beyond its computed value. The
/// evaluator's `exp`, `ln` and `tanh` are within 2 ulp of the C library, and the C library's
/// `exp`, `ln`, `sin`, `cos`, `tan` and `pow` within about 1 ulp of the exact value: at most
/// 3 ulp between the computed bound and the exact one, and 3 more between the exact value
/// at a point inside and what the evaluator computes there; doubled because the value
/// inside may sit in the next binade (twice the ulp), and doubled again as margin.
pub const TRANSCENDENTAL_ULPS: u32 = 16;

/// Absolute widening of `sin` and `cos` bounds on top of [`TRANSCENDENTAL_ULPS`]: near
/// their zeros the evaluator's kernels are within `2e-16` absolute of the C library
/// (`vmath`'s documented bound), not within a few ulp of a tiny value; `2e-15` covers that
/// error at the bound and at a point inside, with margin.
pub const TRIG_ABS_SLACK: f64 = 2e-15;

/// Tolerance, in periods, of the question "does this interval hold a point `x0 + k P`"
/// (an extremum of `sin`/`cos`, a pole of `tan`): `PERIOD_SLACK * (1 + |k|)`. Computing
/// `(x - x0)/P` in `f64` with `x0` and `P` rounded errs by a few times `1e-16 (1 + |k|)`;
/// `1e-12` is far above that, and answering "yes" when unsure only widens a `sin` bound to
/// `+-1` or rejects a tangent within about `3e-12` relative of a pole.
pub const PERIOD_SLACK: f64 = 1e-12;

/// Default budget of boxes for [`enclose_refined`]. 256 boxes cost about 1000 evaluations of
/// the program over a box or a point, about what fitting a candidate's constants costs on
/// a few hundred rows; they reach 1/128 of the box's width along a curve of poles in two
/// inputs, and far finer around an isolated pole in one, where the over-estimate of a
/// repeated variable (which shrinks in proportion to the width) no longer hides the sign of
/// a denominator bounded away from 0.
pub const DEFAULT_MAX_BOXES: usize = 256;

/// [`enclose_refined`] stops tightening the bound once it exceeds the range of the values
/// at the boxes' centres (a range the program certainly reaches) by at most this fraction
/// of that range: a bound quoted to two significant digits no longer moves.
pub const BOUND_TOLERANCE: f64 = 0.01;

/// An enclosure narrower than this fraction of its largest magnitude is a constant up to
/// rounding (`c`, `x - x` at a point); splitting cannot narrow it further.
const NEGLIGIBLE_WIDTH: f64 = 1e-12;

/// Products, quotients and square roots whose results are at least this large in magnitude
/// (2^-900, about 1.2e-271: biased exponent 1023 - 900) have a representable rounding error, so the error-free transformations below are
/// exact; below it (near underflow) a bound is simply moved one step outward.
const EFT_MIN: f64 = f64::from_bits((1023 - 900) << 52);

const WHY_DIV: &str = "a division by a value that can be 0";
const WHY_LOG: &str = "the logarithm of a value that can be <= 0";
const WHY_SQRT: &str = "the square root of a value that can be < 0";
const WHY_POW_NEG: &str =
    "a power of a value that can be < 0 to an exponent that is not a single whole number";
const WHY_POW_ZERO: &str = "a power of a value that can be 0 to an exponent that can be <= 0";
const WHY_TAN: &str = "the tangent of a value that can reach a pole (an odd multiple of pi/2)";
const WHY_OVERFLOW: &str = "an overflow to infinity";
const WHY_BOX: &str = "an input range that is empty or not finite";
const WHY_COLUMN: &str = "an input column the box does not cover";
const WHY_PARAMS: &str = "fewer parameters than the program has, or one that is not finite";
const WHY_MALFORMED: &str = "a malformed program (not a single postfix expression)";

/// A closed interval `[lo, hi]` (`lo <= hi`), possibly unbounded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
}

impl Interval {
    /// The interval `[lo, hi]`.
    pub fn new(lo: f64, hi: f64) -> Self {
        Self { lo, hi }
    }

    /// The single number `x`.
    pub fn point(x: f64) -> Self {
        Self { lo: x, hi: x }
    }

    /// Whether `x` lies in the interval (false for NaN).
    pub fn contains(&self, x: f64) -> bool {
        self.lo <= x && x <= self.hi
    }

    /// `hi - lo`.
    pub fn width(&self) -> f64 {
        self.hi - self.lo
    }

    fn is_finite(&self) -> bool {
        self.lo.is_finite() && self.hi.is_finite()
    }

    /// Whether the interval holds 0, an end touching it included.
    fn holds_zero(&self) -> bool {
        self.lo <= 0.0 && self.hi >= 0.0
    }
}

/// What the enclosure says of a program over a box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Enclosure {
    /// Defined and finite everywhere in the box; the values lie in this interval
    /// (outward-rounded, so it holds every exact value and every `f64` evaluation by the
    /// crate's evaluator, up to the error bounds of the elementary functions stated in the
    /// module documentation). Both ends are finite.
    Bounded(Interval),
    /// Not proven defined and finite over the box: a division by an interval holding 0, a
    /// logarithm, square root or power of an interval reaching outside its domain, a
    /// tangent over a pole, an overflow to infinity. `why` says which (for example "a
    /// division by a value that can be 0", "the logarithm of a value that can be <= 0").
    Undefined {
        /// The first operation found not defined over the box, in words.
        why: &'static str,
    },
}

impl Enclosure {
    /// The interval of a [`Enclosure::Bounded`] enclosure.
    pub fn bound(&self) -> Option<Interval> {
        match self {
            Enclosure::Bounded(iv) => Some(*iv),
            Enclosure::Undefined { .. } => None,
        }
    }

    fn from_result(r: Result<Interval, &'static str>) -> Self {
        match r {
            Ok(iv) => Enclosure::Bounded(iv),
            Err(why) => Enclosure::Undefined { why },
        }
    }
}

type Iv = Result<Interval, &'static str>;

// ---- directed rounding of the basic operations -------------------------------------------

/// `a + b` and the exact error `(a + b) - s` (Knuth's TwoSum; exact barring overflow, where
/// the error is NaN and the caller's finiteness check rejects the result).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

fn add_dn(a: f64, b: f64) -> f64 {
    let (s, e) = two_sum(a, b);
    if e < 0.0 { s.next_down() } else { s }
}

fn add_up(a: f64, b: f64) -> f64 {
    let (s, e) = two_sum(a, b);
    if e > 0.0 { s.next_up() } else { s }
}

/// The sign of `exact - rounded` as -1, 0 or 1, or `None` where it cannot be told.
fn sign_of(e: f64) -> Option<i8> {
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
fn mul_err(a: f64, b: f64, p: f64) -> Option<i8> {
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
fn div_err(a: f64, b: f64, q: f64) -> Option<i8> {
    if a == 0.0 {
        Some(0)
    } else if q.is_finite() && q.abs() >= EFT_MIN && a.abs() >= EFT_MIN {
        let r = sign_of((-q).mul_add(b, a))?;
        Some(if b > 0.0 { r } else { -r })
    } else {
        None
    }
}

fn round_dn(v: f64, err: Option<i8>) -> f64 {
    match err {
        Some(e) if e >= 0 => v,
        _ => v.next_down(),
    }
}

fn round_up(v: f64, err: Option<i8>) -> f64 {
    match err {
        Some(e) if e <= 0 => v,
        _ => v.next_up(),
    }
}

fn mul_dn(a: f64, b: f64) -> f64 {
    let p = a * b;
    round_dn(p, mul_err(a, b, p))
}

fn mul_up(a: f64, b: f64) -> f64 {
    let p = a * b;
    round_up(p, mul_err(a, b, p))
}

fn div_dn(a: f64, b: f64) -> f64 {
    let q = a / b;
    round_dn(q, div_err(a, b, q))
}

fn div_up(a: f64, b: f64) -> f64 {
    let q = a / b;
    round_up(q, div_err(a, b, q))
}

/// Sign of `sqrt(x) - fl(sqrt(x))`, from the exact `x - s^2`.
fn sqrt_err(x: f64, s: f64) -> Option<i8> {
    if x == 0.0 {
        Some(0)
    } else if x >= EFT_MIN {
        sign_of((-s).mul_add(s, x))
    } else {
        None
    }
}

/// `n` steps down (towards -inf).
fn steps_dn(mut v: f64, n: u32) -> f64 {
    for _ in 0..n {
        v = v.next_down();
    }
    v
}

/// `n` steps up (towards +inf).
fn steps_up(mut v: f64, n: u32) -> f64 {
    for _ in 0..n {
        v = v.next_up();
    }
    v
}

/// `[lo, hi]` computed by a transcendental function, widened for its error.
fn widen_transcendental(lo: f64, hi: f64) -> Interval {
    Interval::new(
        steps_dn(lo, TRANSCENDENTAL_ULPS),
        steps_up(hi, TRANSCENDENTAL_ULPS),
    )
}

fn finite(iv: Interval) -> Iv {
    if iv.is_finite() {
        Ok(iv)
    } else {
        Err(WHY_OVERFLOW)
    }
}

// ---- interval operations -----------------------------------------------------------------

fn add(a: Interval, b: Interval) -> Iv {
    finite(Interval::new(add_dn(a.lo, b.lo), add_up(a.hi, b.hi)))
}

fn sub(a: Interval, b: Interval) -> Iv {
    finite(Interval::new(add_dn(a.lo, -b.hi), add_up(a.hi, -b.lo)))
}

fn neg(a: Interval) -> Interval {
    Interval::new(-a.hi, -a.lo)
}

/// Min and max of `f` over the four corners.
fn corners(a: Interval, b: Interval, f: impl Fn(f64, f64) -> f64) -> (f64, f64) {
    let v = [f(a.lo, b.lo), f(a.lo, b.hi), f(a.hi, b.lo), f(a.hi, b.hi)];
    // NaN never arises from finite corners of a product or of a quotient by a nonzero value
    v.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        })
}

fn mul(a: Interval, b: Interval) -> Iv {
    let (lo, _) = corners(a, b, mul_dn);
    let (_, hi) = corners(a, b, mul_up);
    finite(Interval::new(lo, hi))
}

fn div(a: Interval, b: Interval) -> Iv {
    if b.holds_zero() {
        return Err(WHY_DIV);
    }
    let (lo, _) = corners(a, b, div_dn);
    let (_, hi) = corners(a, b, div_up);
    finite(Interval::new(lo, hi))
}

fn square(a: Interval) -> Iv {
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

fn abs(a: Interval) -> Interval {
    if a.lo >= 0.0 {
        a
    } else if a.hi <= 0.0 {
        neg(a)
    } else {
        Interval::new(0.0, (-a.lo).max(a.hi))
    }
}

fn sqrt(a: Interval) -> Iv {
    if a.lo < 0.0 {
        return Err(WHY_SQRT);
    }
    let (s, t) = (a.lo.sqrt(), a.hi.sqrt());
    let lo = round_dn(s, sqrt_err(a.lo, s)).max(0.0);
    finite(Interval::new(lo, round_up(t, sqrt_err(a.hi, t))))
}

/// `exp` over `a`; `exp` (exact or the evaluator's) is never below 0.
fn exp(a: Interval) -> Iv {
    let iv = widen_transcendental(vmath::exp(a.lo), vmath::exp(a.hi));
    finite(Interval::new(iv.lo.max(0.0), iv.hi))
}

fn ln(a: Interval) -> Iv {
    if a.lo <= 0.0 {
        return Err(WHY_LOG);
    }
    finite(widen_transcendental(vmath::ln(a.lo), vmath::ln(a.hi)))
}

fn tanh(a: Interval) -> Iv {
    // |tanh| <= 1 exactly, and the evaluator's `1 - 2/(e + 1)` and `x + x z P/Q` forms never
    // leave [-1, 1] either
    let iv = widen_transcendental(vmath::tanh(a.lo), vmath::tanh(a.hi));
    finite(Interval::new(iv.lo.max(-1.0), iv.hi.min(1.0)))
}

/// Whether `[a.lo, a.hi]` may hold a point `x0 + k period` for an integer `k` (true when
/// unsure; see [`PERIOD_SLACK`]). The slack grows with the larger `|k|` of the two ends, so a
/// sub-interval never answers "yes" where its interval answers "no".
fn may_hold_periodic_point(a: Interval, x0: f64, period: f64) -> bool {
    let t_lo = (a.lo - x0) / period;
    let t_hi = (a.hi - x0) / period;
    let eps = PERIOD_SLACK * (1.0 + t_lo.abs().max(t_hi.abs()));
    (t_lo - eps).ceil() <= (t_hi + eps).floor()
}

/// `sin` or `cos` over `a`: `f` the function, maxima at `max_at + 2 k pi`, minima at
/// `min_at + 2 k pi`.
fn periodic(a: Interval, f: fn(f64) -> f64, max_at: f64, min_at: f64) -> Iv {
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

fn tan(a: Interval) -> Iv {
    if a.width() >= PI || may_hold_periodic_point(a, FRAC_PI_2, PI) {
        return Err(WHY_TAN);
    }
    finite(widen_transcendental(a.lo.tan(), a.hi.tan()))
}

/// `a^b` (`f64::powf`) over the boxes `a` and `b`.
fn pow(a: Interval, b: Interval) -> Iv {
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
fn pow_whole(a: Interval, n: f64) -> Iv {
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

fn apply1(op: Op, a: Interval) -> Iv {
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

fn apply2(op: Op, a: Interval, b: Interval) -> Iv {
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

/// The checks that no subdivision can change: enough finite parameters, and a finite,
/// non-empty range for every column the program reads.
fn check_inputs(
    program: &Program,
    params: &[f64],
    bounds: &[(f64, f64)],
) -> Result<(), &'static str> {
    if params.len() < program.n_params() || params.iter().any(|p| !p.is_finite()) {
        return Err(WHY_PARAMS);
    }
    for j in program.vars() {
        let &(lo, hi) = bounds.get(usize::from(j)).ok_or(WHY_COLUMN)?;
        if !(lo <= hi && lo.is_finite() && hi.is_finite()) {
            return Err(WHY_BOX);
        }
    }
    Ok(())
}

/// The enclosure of the program's output over `bounds`, once [`check_inputs`] passed.
fn interval_of(program: &Program, params: &[f64], bounds: &[(f64, f64)]) -> Iv {
    let offsets = program.param_offsets();
    let mut stack: Vec<Interval> = Vec::with_capacity(program.nodes.len());
    for (node, &off) in program.nodes.iter().zip(&offsets) {
        let v = match *node {
            Node::Var(j) => {
                let &(lo, hi) = bounds.get(usize::from(j)).ok_or(WHY_COLUMN)?;
                let x = finite(Interval::new(lo, hi))?;
                if program.affine {
                    let w = Interval::point(params[off]);
                    add(mul(w, x)?, Interval::point(params[off + 1]))?
                } else {
                    x
                }
            }
            Node::Const => Interval::point(params[off]),
            Node::Op(op) => {
                if op.arity() == 2 {
                    let b = stack.pop().ok_or(WHY_MALFORMED)?;
                    let a = stack.pop().ok_or(WHY_MALFORMED)?;
                    apply2(op, a, b)?
                } else {
                    let a = stack.pop().ok_or(WHY_MALFORMED)?;
                    apply1(op, a)?
                }
            }
        };
        stack.push(v);
    }
    let root = match (stack.pop(), stack.is_empty()) {
        (Some(r), true) => r,
        _ => return Err(WHY_MALFORMED),
    };
    // the output map, `scale * root + offset`, as the evaluator applies it
    add(
        mul(Interval::point(params[0]), root)?,
        Interval::point(params[1]),
    )
}

/// One evaluation over the box `bounds` (one `(lo, hi)` per input column, indexed as
/// [`Node::Var`]): the program's output `params[0] * root + params[1]` enclosed by interval
/// arithmetic. [`Enclosure::Undefined`] also when a column the program reads is missing
/// from `bounds` or its range is empty or not finite, when `params` is too short or holds a
/// value that is not finite, or when the program is not a single postfix expression.
pub fn enclose(program: &Program, params: &[f64], bounds: &[(f64, f64)]) -> Enclosure {
    Enclosure::from_result(
        check_inputs(program, params, bounds).and_then(|()| interval_of(program, params, bounds)),
    )
}

// ---- bisection ---------------------------------------------------------------------------

/// One box of the subdivision and what is known of it.
struct Leaf {
    bounds: Vec<(f64, f64)>,
    enclosure: Iv,
    /// Middle of the enclosure at the box's centre: a value the program takes (up to
    /// rounding), the inner estimate of the range.
    centre: f64,
}

/// Encloses the box and its centre; `Err` when the centre itself is undefined (then every
/// box holding it is, both halves of a split through it included).
fn leaf(program: &Program, params: &[f64], bounds: Vec<(f64, f64)>) -> Result<Leaf, &'static str> {
    let centre_box: Vec<(f64, f64)> = bounds
        .iter()
        .map(|&(lo, hi)| {
            let c = lo.midpoint(hi);
            (c, c)
        })
        .collect();
    let at_centre = interval_of(program, params, &centre_box)?;
    Ok(Leaf {
        enclosure: interval_of(program, params, &bounds),
        centre: at_centre.lo + (at_centre.hi - at_centre.lo) / 2.0,
        bounds,
    })
}

/// The column to split a leaf along: the widest of `columns` relative to `widths` (the
/// original box's), among those whose midpoint still falls strictly inside.
fn split_column(leaf: &Leaf, columns: &[usize], widths: &[f64]) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for &j in columns {
        let (lo, hi) = leaf.bounds[j];
        let mid = lo.midpoint(hi);
        if !(lo < mid && mid < hi) {
            continue;
        }
        let rel = (hi - lo) / widths[j];
        if best.is_none_or(|(_, r)| rel > r) {
            best = Some((j, rel));
        }
    }
    best.map(|(j, _)| j)
}

/// The largest relative width of a leaf along `columns` (0 when it cannot be split).
fn relative_size(leaf: &Leaf, columns: &[usize], widths: &[f64]) -> f64 {
    split_column(leaf, columns, widths).map_or(0.0, |j| {
        let (lo, hi) = leaf.bounds[j];
        (hi - lo) / widths[j]
    })
}

/// `enclose` refined by bisection. Where the plain enclosure is undefined, the box is split
/// in two along its widest input column (relative to the original box's widths; only
/// columns the program reads are split) and each half enclosed, the largest undefined box
/// first, up to `max_boxes` boxes in all ([`DEFAULT_MAX_BOXES`] is a sensible budget).
/// Once every box is defined, the remaining budget tightens the bound: the box that sets
/// the lower (or upper) bound is split, whichever bound exceeds the values seen at the
/// boxes' centres by more, until the excess is within [`BOUND_TOLERANCE`] of their range.
///
/// Returns [`Enclosure::Undefined`] only if some box is still undefined when the budget is
/// spent or cannot be split further, or if the centre of a box is already undefined as a
/// single point (then every box holding it is, at any size), or for the reasons of
/// [`enclose`] that no subdivision changes (a missing or non-finite input range or
/// parameter). So a dependency over-estimate, such as `1/(x^2 - x + 1)` over `[0, 2]`
/// whose denominator encloses to `[-1, 5]`, is proven defined; else the result is the
/// union of the boxes' bounds.
pub fn enclose_refined(
    program: &Program,
    params: &[f64],
    bounds: &[(f64, f64)],
    max_boxes: usize,
) -> Enclosure {
    Enclosure::from_result(refine(program, params, bounds, max_boxes))
}

fn refine(program: &Program, params: &[f64], bounds: &[(f64, f64)], max_boxes: usize) -> Iv {
    check_inputs(program, params, bounds)?;
    let widths: Vec<f64> = bounds.iter().map(|&(lo, hi)| hi - lo).collect();
    // columns the program reads whose range has a width to split
    let columns: Vec<usize> = program
        .vars()
        .into_iter()
        .map(usize::from)
        .filter(|&j| widths[j] > 0.0 && widths[j].is_finite())
        .collect();
    let mut leaves = vec![leaf(program, params, bounds.to_vec())?];
    loop {
        // the largest undefined box, else the box setting the bound that is furthest off
        let undefined = leaves
            .iter()
            .enumerate()
            .filter(|(_, l)| l.enclosure.is_err())
            .map(|(i, l)| (i, relative_size(l, &columns, &widths)))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let pick = match undefined {
            Some((i, _)) => i,
            None => match widest_bound(&leaves) {
                Some(i) => i,
                None => break,
            },
        };
        let col = split_column(&leaves[pick], &columns, &widths);
        let (Some(j), true) = (col, leaves.len() < max_boxes) else {
            // the budget is spent or the box cannot be split
            leaves[pick].enclosure?;
            break;
        };
        let parent = leaves.swap_remove(pick);
        let (lo, hi) = parent.bounds[j];
        let mid = lo.midpoint(hi);
        let mut left = parent.bounds.clone();
        left[j] = (lo, mid);
        let mut right = parent.bounds;
        right[j] = (mid, hi);
        leaves.push(leaf(program, params, left)?);
        leaves.push(leaf(program, params, right)?);
    }
    union(&leaves)
}

/// Among defined leaves, the one to split to tighten the bound, or `None` when the bound is
/// tight enough ([`BOUND_TOLERANCE`], [`NEGLIGIBLE_WIDTH`]).
fn widest_bound(leaves: &[Leaf]) -> Option<usize> {
    let outer = union(leaves).ok()?;
    let (c_lo, c_hi) = leaves
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), l| {
            (lo.min(l.centre), hi.max(l.centre))
        });
    let (below, above) = (c_lo - outer.lo, outer.hi - c_hi);
    let magnitude = outer.lo.abs().max(outer.hi.abs());
    if below + above <= BOUND_TOLERANCE * (c_hi - c_lo)
        || outer.width() <= NEGLIGIBLE_WIDTH * magnitude
    {
        return None;
    }
    let ends = leaves
        .iter()
        .enumerate()
        .filter_map(|(i, l)| l.enclosure.ok().map(|e| (i, e)));
    if below >= above {
        ends.min_by(|a, b| a.1.lo.total_cmp(&b.1.lo))
            .map(|(i, _)| i)
    } else {
        ends.max_by(|a, b| a.1.hi.total_cmp(&b.1.hi))
            .map(|(i, _)| i)
    }
}

/// The union of the leaves' bounds, or the first leaf's reason to be undefined.
fn union(leaves: &[Leaf]) -> Iv {
    let mut out = Interval::new(f64::INFINITY, f64::NEG_INFINITY);
    for l in leaves {
        let e = l.enclosure?;
        out = Interval::new(out.lo.min(e.lo), out.hi.max(e.hi));
    }
    finite(out)
}

// ---- the box -----------------------------------------------------------------------------

/// The box of `columns` widened by `margin` (for example 0.1) of each column's range on each
/// side, but not below 0 for a column whose values are all `>= 0` (a length, a speed, a
/// count stays one). Values that are not finite are ignored; a column without a finite
/// value gets `(NaN, NaN)`, which [`enclose`] reports as undefined if the program reads
/// that column. A `margin` that is negative or NaN counts as 0.
pub fn widened_box(columns: &[&[f64]], margin: f64) -> Vec<(f64, f64)> {
    let margin = if margin > 0.0 { margin } else { 0.0 };
    columns
        .iter()
        .map(|col| {
            let (lo, hi) = col
                .iter()
                .filter(|v| v.is_finite())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                    (lo.min(v), hi.max(v))
                });
            if lo > hi {
                return (f64::NAN, f64::NAN);
            }
            let pad = margin * (hi - lo);
            let wide_lo = lo - pad;
            let wide_lo = if lo >= 0.0 { wide_lo.max(0.0) } else { wide_lo };
            (wide_lo, hi + pad)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::eval::Evaluator;
    use crate::infix::{Compiled, compile_text};
    use proptest::prelude::*;
    use std::collections::BTreeMap;

    fn compiled(text: &str, constants: &[(&str, f64)]) -> Compiled {
        let consts: BTreeMap<String, f64> =
            constants.iter().map(|&(n, v)| (n.to_string(), v)).collect();
        compile_text(text, &consts).unwrap()
    }

    fn bounded(e: Enclosure) -> Interval {
        match e {
            Enclosure::Bounded(iv) => iv,
            Enclosure::Undefined { why } => panic!("expected a bound, got undefined: {why}"),
        }
    }

    fn why(e: Enclosure) -> &'static str {
        match e {
            Enclosure::Undefined { why } => why,
            Enclosure::Bounded(iv) => panic!("expected undefined, got {iv:?}"),
        }
    }

    #[test]
    fn a_pole_between_sample_points_is_caught() {
        let c = compiled("c/(x - 0.5)", &[("c", 2.0)]);
        assert_eq!(c.inputs, vec!["x".to_string()]);
        // the samples alone see nothing wrong
        for x in [0.0, 0.25, 0.75, 1.0] {
            assert!(c.eval_row(&[x]).is_finite());
        }
        assert_eq!(why(enclose(&c.program, &c.params, &[(0.0, 1.0)])), WHY_DIV);
        assert_eq!(
            why(enclose_refined(
                &c.program,
                &c.params,
                &[(0.0, 1.0)],
                DEFAULT_MAX_BOXES
            )),
            WHY_DIV
        );
        // away from the pole: 2/(x - 0.5) over [0.6, 1] is [4, 20]
        let iv = bounded(enclose(&c.program, &c.params, &[(0.6, 1.0)]));
        assert!(iv.lo <= 4.0 && iv.hi >= 20.0 - 1e-12, "{iv:?}");
        assert!(iv.lo > 3.99 && iv.hi < 20.01, "{iv:?}");
        let refined = bounded(enclose_refined(&c.program, &c.params, &[(0.6, 1.0)], 64));
        assert!(
            refined.contains(4.0) && refined.hi >= 20.0 - 1e-12,
            "{refined:?}"
        );
    }

    #[test]
    fn a_pole_off_the_centres_is_caught_by_refinement() {
        // the pole at 1/3 is never the centre of a bisected box of [0, 1]
        let c = compiled("1/(x - 1/3)", &[]);
        let e = enclose_refined(&c.program, &c.params, &[(0.0, 1.0)], DEFAULT_MAX_BOXES);
        assert_eq!(why(e), WHY_DIV);
    }

    #[test]
    fn log_is_undefined_where_its_argument_can_be_at_most_zero() {
        let c = compiled("log(x + c)", &[("c", 1.0)]);
        assert_eq!(why(enclose(&c.program, &c.params, &[(-2.0, 1.0)])), WHY_LOG);
        // touching 0 at the end is undefined too
        assert_eq!(why(enclose(&c.program, &c.params, &[(-1.0, 1.0)])), WHY_LOG);
        assert_eq!(
            why(enclose_refined(
                &c.program,
                &c.params,
                &[(-2.0, 1.0)],
                DEFAULT_MAX_BOXES
            )),
            WHY_LOG
        );
        let iv = bounded(enclose(&c.program, &c.params, &[(-0.5, 1.0)]));
        assert!(iv.lo <= 0.5f64.ln() && iv.hi >= 2.0f64.ln(), "{iv:?}");
        assert!(
            iv.lo > 0.5f64.ln() - 1e-12 && iv.hi < 2.0f64.ln() + 1e-12,
            "{iv:?}"
        );
    }

    #[test]
    fn bisection_removes_the_dependency_overestimate() {
        let c = compiled("1/(x^2 - x + 1)", &[]);
        // naive: x^2 - x + 1 over [0, 2] encloses to [-1, 5], which holds 0
        assert_eq!(why(enclose(&c.program, &c.params, &[(0.0, 2.0)])), WHY_DIV);
        let iv = bounded(enclose_refined(
            &c.program,
            &c.params,
            &[(0.0, 2.0)],
            DEFAULT_MAX_BOXES,
        ));
        // true range [1/3, 4/3] (at x = 2 and x = 1/2)
        assert!(iv.lo <= 1.0 / 3.0 && iv.hi >= 4.0 / 3.0, "{iv:?}");
        assert!(iv.lo > 0.32 && iv.hi < 1.35, "{iv:?}");
    }

    #[test]
    fn a_budget_of_one_box_is_the_plain_enclosure() {
        let c = compiled("1/(x^2 - x + 1)", &[]);
        assert_eq!(
            why(enclose_refined(&c.program, &c.params, &[(0.0, 2.0)], 1)),
            WHY_DIV
        );
    }

    #[test]
    fn operators_on_known_intervals() {
        assert_eq!(EFT_MIN, 2f64.powi(-900));
        let iv = Interval::new;
        assert_eq!(square(iv(-2.0, 1.0)).unwrap(), iv(0.0, 4.0));
        assert_eq!(square(iv(-2.0, -1.0)).unwrap(), iv(1.0, 4.0));
        assert_eq!(abs(iv(-3.0, 1.0)), iv(0.0, 3.0));
        // exact operations stay exact
        assert_eq!(mul(iv(-1.0, -1.0), iv(2.0, 2.0)).unwrap(), iv(-2.0, -2.0));
        assert_eq!(add(iv(0.5, 0.5), iv(0.25, 0.25)).unwrap(), iv(0.75, 0.75));
        // inexact ones bracket the exact value
        let third = div(iv(1.0, 1.0), iv(3.0, 3.0)).unwrap();
        assert!(third.lo < third.hi && third.hi == third.lo.next_up());
        let s = add(iv(0.1, 0.1), iv(0.2, 0.2)).unwrap();
        assert!(s.lo < s.hi && s.contains(0.1 + 0.2));
        assert_eq!(div(iv(1.0, 1.0), iv(0.0, 1.0)), Err(WHY_DIV));
        assert_eq!(div(iv(1.0, 1.0), iv(-1.0, -0.0)), Err(WHY_DIV));
        assert_eq!(sqrt(iv(-1e-300, 4.0)), Err(WHY_SQRT));
        assert_eq!(sqrt(iv(0.0, 4.0)).unwrap(), iv(0.0, 2.0));
        // sin over [0, pi] reaches its maximum inside; cos over [0.5, 3] is monotone
        let s = apply1(Op::Sin, iv(0.0, PI)).unwrap();
        assert!(s.contains(1.0) && s.contains(0.0) && s.lo > -1e-14 && s.hi < 1.0 + 1e-14);
        let c = apply1(Op::Cos, iv(0.5, 3.0)).unwrap();
        assert!(c.contains(0.5f64.cos()) && c.contains(3.0f64.cos()));
        assert!(c.lo > -1.0 + 1e-3 && c.hi < 0.5f64.cos() + 1e-14);
        let wide = apply1(Op::Sin, iv(-10.0, 10.0)).unwrap();
        assert!(wide.contains(-1.0) && wide.contains(1.0) && wide.hi < 1.0 + 1e-14);
        // tan over a pole, and next to one
        assert_eq!(apply1(Op::Tan, iv(1.0, 2.0)), Err(WHY_TAN));
        assert_eq!(apply1(Op::Tan, iv(-1.0, 5.0)), Err(WHY_TAN));
        assert!(
            apply1(Op::Tan, iv(-1.0, 1.5))
                .unwrap()
                .contains(1.5f64.tan())
        );
        // gaussian of an interval holding 0 peaks at 1
        let g = apply1(Op::Gaussian, iv(-1.0, 2.0)).unwrap();
        assert!(g.contains(1.0) && g.contains((-4.0f64).exp()) && g.lo >= 0.0);
        // powers: whole exponents take negative bases, others do not
        assert_eq!(
            pow(iv(-2.0, 1.0), iv(2.0, 2.0)).map(|p| p.contains(4.0) && p.lo == 0.0),
            Ok(true)
        );
        let cube = pow(iv(-2.0, 1.0), iv(3.0, 3.0)).unwrap();
        assert!(cube.contains(-8.0) && cube.contains(1.0) && cube.lo > -8.0 - 1e-12);
        assert_eq!(pow(iv(-2.0, 1.0), iv(-1.0, -1.0)), Err(WHY_POW_ZERO));
        let inv = pow(iv(-2.0, -1.0), iv(-1.0, -1.0)).unwrap();
        assert!(inv.contains(-1.0) && inv.contains(-0.5));
        assert_eq!(pow(iv(-2.0, 1.0), iv(0.5, 0.5)), Err(WHY_POW_NEG));
        assert_eq!(pow(iv(0.0, 4.0), iv(-0.5, -0.5)), Err(WHY_POW_ZERO));
        let root = pow(iv(0.0, 4.0), iv(0.5, 0.5)).unwrap();
        assert!(root.lo == 0.0 && root.contains(2.0) && root.hi < 2.0 + 1e-12);
        let p = pow(iv(1.0, 2.0), iv(-1.5, 0.5)).unwrap();
        assert!(p.contains(2.0f64.powf(-1.5)) && p.contains(2.0f64.sqrt()));
        // overflow
        assert_eq!(exp(iv(0.0, 800.0)), Err(WHY_OVERFLOW));
        assert_eq!(mul(iv(1e200, 1e200), iv(1e200, 1e200)), Err(WHY_OVERFLOW));
    }

    #[test]
    fn affine_inputs_and_the_output_map() {
        // 2 * (3 x - 1) + 5 over x in [0, 1]: the input enters as 3 x - 1, range [-1, 2]
        let p = Program {
            nodes: vec![Node::Var(0)],
            affine: true,
        };
        let iv = bounded(enclose(&p, &[2.0, 5.0, 3.0, -1.0], &[(0.0, 1.0)]));
        assert_eq!(iv, Interval::new(3.0, 9.0));
        // the reasons no subdivision changes
        assert_eq!(
            why(enclose(&p, &[2.0, 5.0, 3.0], &[(0.0, 1.0)])),
            WHY_PARAMS
        );
        assert_eq!(
            why(enclose(&p, &[2.0, 5.0, 3.0, f64::NAN], &[(0.0, 1.0)])),
            WHY_PARAMS
        );
        assert_eq!(why(enclose(&p, &[2.0, 5.0, 3.0, -1.0], &[])), WHY_COLUMN);
        assert_eq!(
            why(enclose(&p, &[2.0, 5.0, 3.0, -1.0], &[(1.0, 0.0)])),
            WHY_BOX
        );
        assert_eq!(
            why(enclose_refined(
                &p,
                &[2.0, 5.0, 3.0, -1.0],
                &[(f64::NAN, 1.0)],
                64
            )),
            WHY_BOX
        );
        // a box as wide as f64 allows: its centre and its halves do not overflow
        let x = Program {
            nodes: vec![Node::Var(0)],
            affine: false,
        };
        let iv = bounded(enclose_refined(&x, &[1.0, 0.0], &[(-1e308, 1e308)], 8));
        assert_eq!(iv, Interval::new(-1e308, 1e308));
        let bad = Program {
            nodes: vec![Node::Var(0), Node::Var(0)],
            affine: false,
        };
        assert_eq!(
            why(enclose(&bad, &[1.0, 0.0], &[(0.0, 1.0)])),
            WHY_MALFORMED
        );
    }

    #[test]
    fn refinement_tightens_the_bound() {
        // x (1 - x) has range [0, 1/4] over [0, 1], and encloses naively to [0, 1] (x appears
        // twice)
        let c = compiled("x*(1 - x)", &[]);
        let plain = bounded(enclose(&c.program, &c.params, &[(0.0, 1.0)]));
        assert!(plain.hi >= 0.99);
        let iv = bounded(enclose_refined(
            &c.program,
            &c.params,
            &[(0.0, 1.0)],
            DEFAULT_MAX_BOXES,
        ));
        assert!(iv.lo <= 0.0 && iv.hi >= 0.25, "{iv:?}");
        assert!(iv.lo > -0.01 && iv.hi < 0.255, "{iv:?}");
    }

    #[test]
    fn widened_box_pads_each_column_and_keeps_non_negative_columns_non_negative() {
        let a = [0.0, 1.0, 2.0, f64::NAN];
        let b = [-1.0, 3.0, f64::INFINITY];
        let c = [5.0, 5.0];
        let d = [f64::NAN];
        let e = [1.0, 11.0];
        let cols: Vec<&[f64]> = vec![&a, &b, &c, &d, &e];
        let bx = widened_box(&cols, 0.1);
        assert_eq!(bx[0], (0.0, 2.2));
        assert!((bx[1].0 + 1.4).abs() < 1e-12 && (bx[1].1 - 3.4).abs() < 1e-12);
        assert_eq!(bx[2], (5.0, 5.0));
        assert!(bx[3].0.is_nan() && bx[3].1.is_nan());
        // all >= 0, the margin reaching exactly 0; further from 0 it applies in full
        assert_eq!(bx[4], (0.0, 12.0));
        let bx = widened_box(&[&[2.0, 12.0][..]], 0.1);
        assert_eq!(bx[0], (1.0, 13.0));
        assert_eq!(widened_box(&[&[2.0, 12.0][..]], -1.0)[0], (2.0, 12.0));
    }

    /// Every operator, the search's and the equations' ones.
    const OPS: [Op; 17] = [
        Op::Add,
        Op::Sub,
        Op::Mul,
        Op::Div,
        Op::Exp,
        Op::Log,
        Op::Sqrt,
        Op::Square,
        Op::Inverse,
        Op::Sin,
        Op::Cos,
        Op::Tanh,
        Op::Abs,
        Op::Gaussian,
        Op::Gaussian2,
        Op::Pow,
        Op::Tan,
    ];

    /// A random expression tree of at most `depth` levels over `n_vars` inputs, written in
    /// postfix, its shape drawn from `choices`.
    fn build(
        choices: &mut std::slice::Iter<'_, u32>,
        depth: usize,
        n_vars: u16,
        out: &mut Vec<Node>,
    ) {
        let c = choices.next().copied().unwrap_or(0);
        if depth == 0 || c % 3 == 0 {
            let leaf = (c / 3) % (u32::from(n_vars) + 1);
            out.push(if leaf == 0 {
                Node::Const
            } else {
                Node::Var((leaf - 1) as u16)
            });
            return;
        }
        let op = OPS[(c / 3) as usize % OPS.len()];
        for _ in 0..op.arity() {
            build(choices, depth - 1, n_vars, out);
        }
        out.push(Node::Op(op));
    }

    fn param() -> impl Strategy<Value = f64> {
        prop_oneof![-3.0..3.0, (-3i32..=3).prop_map(f64::from)]
    }

    fn fraction() -> impl Strategy<Value = f64> {
        prop_oneof![1 => Just(0.0), 1 => Just(1.0), 8 => 0.0..=1.0]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        /// Soundness against the evaluator: for a random program (every operator, one or
        /// two inputs, plain or affine, constants in [-3, 3] and some whole) over a random
        /// box, evaluated in `f64` by the crate's `Evaluator` at 50 points of the box (its
        /// corners among them): if the enclosure (plain or refined) is `Bounded`, every
        /// value at those points is finite and lies within it; so if any value is NaN or
        /// infinite, the enclosure is not `Bounded`.
        #[test]
        fn the_enclosure_holds_every_evaluated_value(
            choices in prop::collection::vec(any::<u32>(), 40),
            n_vars in 1u16..=2,
            affine in any::<bool>(),
            params in prop::collection::vec(param(), 64),
            corner in prop::collection::vec((-3.0f64..3.0, prop_oneof![Just(0.0), 0.0f64..3.0]), 2),
            points in prop::collection::vec((fraction(), fraction()), 50),
        ) {
            let mut nodes = Vec::new();
            build(&mut choices.iter(), 4, n_vars, &mut nodes);
            let program = Program { nodes, affine };
            prop_assert!(program.is_valid());
            let params = &params[..program.n_params().min(params.len())];
            prop_assume!(params.len() == program.n_params());
            let bounds: Vec<(f64, f64)> = corner.iter().map(|&(lo, w)| (lo, lo + w)).collect();
            let at = |f: f64, (lo, hi): (f64, f64)| (lo + f * (hi - lo)).min(hi);
            let cols: Vec<Vec<f64>> = (0..2)
                .map(|j| points.iter().map(|p| at(if j == 0 { p.0 } else { p.1 }, bounds[j])).collect())
                .collect();
            let col_refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
            let mut values = Vec::new();
            Evaluator::new(&program).predict(&program, params, &col_refs, points.len(), &mut values);
            for e in [enclose(&program, params, &bounds), enclose_refined(&program, params, &bounds, 16)] {
                if let Enclosure::Bounded(iv) = e {
                    prop_assert!(iv.lo.is_finite() && iv.hi.is_finite() && iv.lo <= iv.hi);
                    for (i, v) in values.iter().enumerate() {
                        prop_assert!(
                            iv.contains(*v),
                            "{:?} {:?} over {:?}: {} at ({}, {}) outside {:?}",
                            program, params, bounds, v, cols[0][i], cols[1][i], iv
                        );
                    }
                }
            }
        }
    }
}
