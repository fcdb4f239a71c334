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

mod arith;
use arith::{add, apply1, apply2, finite, mul};
#[cfg(test)]
mod tests;
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
    Enclosure::from_result(refine(program, params, bounds, max_boxes, true))
}

/// Whether `program` is proven defined and finite over the box `bounds`: the bisection of
/// [`enclose_refined`], stopped as soon as every box is defined (no budget spent on
/// tightening the bound). `Err(why)` where it is not proven within `max_boxes` boxes: the
/// search's test of a candidate ("no pole beside the data"), run once per fitted candidate.
///
/// # Errors
/// The reason of the box left undefined, as [`Enclosure::Undefined`] says it.
pub fn defined_over(
    program: &Program,
    params: &[f64],
    bounds: &[(f64, f64)],
    max_boxes: usize,
) -> Result<(), &'static str> {
    match Enclosure::from_result(refine(program, params, bounds, max_boxes, false)) {
        Enclosure::Bounded(_) => Ok(()),
        Enclosure::Undefined { why } => Err(why),
    }
}

fn refine(
    program: &Program,
    params: &[f64],
    bounds: &[(f64, f64)],
    max_boxes: usize,
    tighten: bool,
) -> Iv {
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
            None if !tighten => break,
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

/// The default [`SearchConfig::defined_margin`](crate::SearchConfig::defined_margin): 10 %
/// of each column's range (issue 64), the `margin` of [`widened_box`] that the search and
/// the factor fits check candidates over.
pub const DEFINED_MARGIN: f64 = 0.1;

/// Boxes [`defined_over`] may bisect a candidate's input box into before a candidate not
/// yet proven defined is rejected (by the search and the factor fits): 64 halvings settle
/// the dependency over-estimates of short programs (`1/(x^2 - x + 1)` needs a handful) at a
/// cost of about a millisecond per rejected candidate, a fraction of its fit.
pub const DEFINED_BOXES: usize = 64;

/// The box of `columns` widened by `margin` (for example 0.1) of each column's range on each
/// side, but not below 0 for a column whose values are all `>= 0` (a length, a speed, a
/// count stays one), and not to 0 for a column whose values are all `> 0`: where the linear
/// margin would reach 0 there, the lower end moves down by `margin` of the column's range
/// on the log scale instead (`lo (lo/hi)^margin`), so a power law or a logarithm of a
/// positive quantity, which an engineer writes and which has no value at 0, is not
/// rejected for a point no row comes near (`b` in [0.5, 8]: down to 0.379, not 0).
/// Values that are not finite are ignored; a column without a finite
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
            let wide_lo = if lo > 0.0 && wide_lo <= 0.0 {
                lo * (lo / hi).powf(margin)
            } else if lo >= 0.0 {
                wide_lo.max(0.0)
            } else {
                wide_lo
            };
            (wide_lo, hi + pad)
        })
        .collect()
}
