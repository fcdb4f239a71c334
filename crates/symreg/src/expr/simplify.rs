//! Value-preserving simplification of an [`Expr`], and the recognition of the constants it
//! and the printers name: multiples of pi/2 and small fractions.

use super::Expr;
use crate::ops::Op;
use crate::vmath;

fn add_num(e: Expr, x: f64) -> Expr {
    if x < 0.0 {
        Expr::Bin(Op::Sub, Box::new(e), Box::new(Expr::Num(-x)))
    } else {
        Expr::Bin(Op::Add, Box::new(e), Box::new(Expr::Num(x)))
    }
}

/// The largest multiple of pi/2 (in absolute value) that is recognised as one: phases up to
/// four half-turns either way.
pub(crate) const MAX_HALF_PI_MULTIPLE: f64 = 8.0;

/// `k` when `v` is `k * pi/2` for a whole `k` with `0 < |k| <= 8`, within `ulps` units in
/// the last place of `v`.
fn half_pi_within(v: f64, ulps: f64) -> Option<i64> {
    let k = (v / std::f64::consts::FRAC_PI_2).round();
    let exact = k * std::f64::consts::FRAC_PI_2;
    (k != 0.0
        && k.abs() <= MAX_HALF_PI_MULTIPLE
        && (exact - v).abs() <= ulps * f64::EPSILON * v.abs())
    .then_some(k as i64)
}

/// `k` when `v` is exactly (to the last bit) `k * pi/2` for a whole `k` with
/// `0 < |k| <= 8`. Such values come from snapping (see `snap_candidates`) or from a fit
/// that converged to the double nearest a phase; any other value is `None`.
pub(crate) fn half_pi_multiple(v: f64) -> Option<i64> {
    half_pi_within(v, 0.0)
}

/// The largest denominator [`small_fraction`] recognises.
const MAX_FRACTION_DENOMINATOR: i64 = 12;

/// `(p, q)` when `v` is exactly (to the last bit) the double nearest `p/q` for a whole `p`
/// and a denominator `2 <= q <= 12` (the smallest such `q`), with `|v| < 1e6`; integers and
/// every other value give `None`.
///
/// Such values come from exact arithmetic on snapped constants (a half, the inverse of a
/// snapped 3); a fitted constant lands on one by chance with probability about 1e-15. The
/// sympy text writes them as fractions (`1/3`, which sympy reads as a rational), so that a
/// law written with exact constants reads back as one: `0.3333333333333333` rounded to
/// `0.333` would not.
pub(super) fn small_fraction(v: f64) -> Option<(i64, i64)> {
    if !v.is_finite() || v == v.round() || v.abs() >= 1e6 {
        return None;
    }
    (2..=MAX_FRACTION_DENOMINATOR).find_map(|q| {
        let p = (v * q as f64).round();
        (p / q as f64 == v).then_some((p as i64, q))
    })
}

/// The irrational constants a physicist writes that are not multiples of pi/2: square roots
/// of small integers and of pi and 2 pi, their inverses, and the inverses of pi, 2 pi and 4 pi
/// (`1/sqrt(2 pi)` of the normal density, `1/(4 pi)` of Coulomb's law), each with its sympy
/// text. The value is the double these functions compute, so a snapped constant
/// (`snap_candidates`) is recognised by its bits ([`named_constant`]).
pub(crate) fn named_constants() -> [(f64, &'static str); 13] {
    use std::f64::consts::PI;
    [
        (2f64.sqrt(), "sqrt(2)"),
        (3f64.sqrt(), "sqrt(3)"),
        (5f64.sqrt(), "sqrt(5)"),
        (1.0 / 2f64.sqrt(), "sqrt(2)/2"),
        (1.0 / 3f64.sqrt(), "sqrt(3)/3"),
        (1.0 / 5f64.sqrt(), "sqrt(5)/5"),
        (PI.sqrt(), "sqrt(pi)"),
        ((2.0 * PI).sqrt(), "sqrt(2*pi)"),
        (1.0 / PI.sqrt(), "1/sqrt(pi)"),
        (1.0 / (2.0 * PI).sqrt(), "1/sqrt(2*pi)"),
        (1.0 / PI, "1/pi"),
        (1.0 / (2.0 * PI), "1/(2*pi)"),
        (1.0 / (4.0 * PI), "1/(4*pi)"),
    ]
}

/// The sympy text of `v` when it is exactly (to the last bit) one of [`named_constants`] or
/// its negative (`-sqrt(2)`); any other value is `None`. A fitted constant lands on one by
/// chance with probability about 1e-15; snapped ones are there on purpose.
pub(super) fn named_constant(v: f64) -> Option<String> {
    if !v.is_finite() || v == 0.0 {
        return None;
    }
    named_constants()
        .into_iter()
        .find(|(c, _)| *c == v.abs())
        .map(|(_, text)| {
            if v < 0.0 {
                format!("-{text}")
            } else {
                text.to_string()
            }
        })
}

/// `(u, k)` when `e` is `u + k pi/2` (or `u - k pi/2`, or `k pi/2 + u`) for a whole `k`,
/// with the phase a number within a few units in the last place of the multiple.
fn split_phase(e: &Expr) -> Option<(&Expr, i64)> {
    let num = |c: &Expr| match c {
        Expr::Num(v) => Some(*v),
        _ => None,
    };
    let (u, phase) = match e {
        Expr::Bin(Op::Add, a, b) => match (num(a), num(b)) {
            (_, Some(v)) => (&**a, v),
            (Some(v), None) => (&**b, v),
            (None, None) => return None,
        },
        Expr::Bin(Op::Sub, a, b) => (&**a, -num(b)?),
        _ => return None,
    };
    half_pi_within(phase, 4.0).map(|k| (u, k))
}

/// `sin(u + k pi/2)` or `cos(u + k pi/2)` written without the phase: `cos(u)`, `-sin(u)`, ...
fn shift_trig(op: Op, u: Expr, k: i64) -> Expr {
    // sin(u + q pi/2) for q = 0..3 is sin, cos, -sin, -cos of u; cos(u + q pi/2) is
    // sin(u + (q + 1) pi/2)
    let q = (k + i64::from(op == Op::Cos)).rem_euclid(4);
    let f = if q % 2 == 0 { Op::Sin } else { Op::Cos };
    let e = Expr::Un(f, Box::new(u));
    if q >= 2 { Expr::Neg(Box::new(e)) } else { e }
}

/// `exp(a log(u) + b)` as the power law `e^b u^a` (`u^a` when `b` is absent, `u` when `a`
/// is 1), given the simplified argument `a log(u) + b`; `None` for any other argument. The
/// two agree wherever the exponential form is defined (`u > 0`); this is how the search
/// writes `c f^a`, and how an engineer reads it.
fn power_law(arg: &Expr) -> Option<Expr> {
    use Expr::{Bin, Num, Un};
    let (scaled_log, b) = match arg {
        Bin(Op::Add, x, c) | Bin(Op::Add, c, x) if matches!(**c, Num(_)) => {
            let Num(b) = **c else { return None };
            (&**x, b)
        }
        Bin(Op::Sub, x, c) => {
            let Num(b) = **c else { return None };
            (&**x, -b)
        }
        other => (other, 0.0),
    };
    let (a, u) = match scaled_log {
        Un(Op::Log, u) => (1.0, u),
        Bin(Op::Mul, c, l) | Bin(Op::Mul, l, c) if matches!(**c, Num(_)) => {
            let (Num(a), Un(Op::Log, u)) = (&**c, &**l) else {
                return None;
            };
            (*a, u)
        }
        _ => return None,
    };
    let base = (**u).clone();
    let power = if a == 1.0 {
        base
    } else {
        Bin(Op::Pow, Box::new(base), Box::new(Num(a)))
    };
    Some(Bin(Op::Mul, Box::new(Num(vmath::exp(b))), Box::new(power)).simplify())
}

impl Expr {
    /// Value-preserving simplification (for finite values): folds constants, drops `*1`,
    /// `+0`, `0*x`, merges nested numeric factors and offsets, turns `x + (-c)` into `x - c`.
    pub fn simplify(self) -> Expr {
        use Expr::*;
        match self {
            Neg(a) => match a.simplify() {
                Num(v) => Num(-v),
                Neg(x) => *x,
                x => Neg(Box::new(x)),
            },
            Un(op, a) => {
                let a = a.simplify();
                // a phase of a whole number of quarter turns is a shift between sin and cos:
                // sin(u - pi/2) is -cos(u)
                if let (Op::Sin | Op::Cos, Some((u, k))) = (op, split_phase(&a)) {
                    return shift_trig(op, u.clone(), k).simplify();
                }
                if op == Op::Exp
                    && let Some(power) = power_law(&a)
                {
                    return power;
                }
                match (op, a) {
                    (_, Num(v)) => Num(op.apply1(v)),
                    // log undoes exp wherever exp is finite (where it is not, neither is the
                    // model)
                    (Op::Log, Un(Op::Exp, x)) => *x,
                    (Op::Log, Un(Op::Gaussian, x)) => Neg(Box::new(Un(Op::Square, x))),
                    // even functions drop a sign
                    (Op::Square | Op::Abs | Op::Cos | Op::Gaussian, Neg(x)) => Un(op, x),
                    (_, x) => Un(op, Box::new(x)),
                }
            }
            Bin(op, a, b) => {
                let a = a.simplify();
                let b = b.simplify();
                match (op, a, b) {
                    (_, Num(x), Num(y)) => Num(op.apply2(x, y)),
                    // a snapped exponent of 1 or -1 reads as the column or its reciprocal
                    // (`powf` is exact for both)
                    (Op::Pow, e, Num(1.0)) => e,
                    (Op::Pow, e, Num(-1.0)) => {
                        Bin(Op::Div, Box::new(Num(1.0)), Box::new(e)).simplify()
                    }
                    // `-9*1/(c + 4)` (a product with an inverse) reads `-9/(c + 4)`
                    (Op::Mul, x, Un(Op::Inverse, d)) | (Op::Mul, Un(Op::Inverse, d), x) => {
                        Bin(Op::Div, Box::new(x), d).simplify()
                    }
                    // `f**2*1/r` reads `f**2/r`
                    (Op::Mul, x, Bin(Op::Div, one, d)) if matches!(*one, Num(v) if v == 1.0) => {
                        Bin(Op::Div, Box::new(x), d).simplify()
                    }
                    // gaussian2 with a constant argument c is exp(-c^2) gaussian(other)
                    (Op::Gaussian2, Num(c), y) | (Op::Gaussian2, y, Num(c)) => Bin(
                        Op::Mul,
                        Box::new(Num(vmath::exp(-c * c))),
                        Box::new(Un(Op::Gaussian, Box::new(y))),
                    )
                    .simplify(),
                    // gaussian2 squares both arguments: their signs do not matter
                    (Op::Gaussian2, Neg(x), y) => Bin(op, x, Box::new(y)).simplify(),
                    (Op::Gaussian2, x, Neg(y)) => Bin(op, Box::new(x), y),
                    (Op::Mul, Num(x), e) | (Op::Mul, e, Num(x)) => {
                        if x == 1.0 {
                            e
                        } else if x == 0.0 {
                            Num(0.0)
                        } else if x == -1.0 {
                            Neg(Box::new(e)).simplify()
                        } else {
                            match e {
                                // x * (y * e) is (x y) * e, and x * (y / d) is (x y) / d:
                                // `4.8*1/(f + 0.5)` reads `4.8/(f + 0.5)`
                                Bin(inner @ (Op::Mul | Op::Div), inner_a, inner_b) => {
                                    match *inner_a {
                                        Num(y) => {
                                            Bin(inner, Box::new(Num(x * y)), inner_b).simplify()
                                        }
                                        other => Bin(
                                            Op::Mul,
                                            Box::new(Num(x)),
                                            Box::new(Bin(inner, Box::new(other), inner_b)),
                                        ),
                                    }
                                }
                                Neg(inner) => Bin(Op::Mul, Box::new(Num(-x)), inner),
                                e => Bin(Op::Mul, Box::new(Num(x)), Box::new(e)),
                            }
                        }
                    }
                    (Op::Add, Num(x), e) | (Op::Add, e, Num(x)) => {
                        if x == 0.0 {
                            e
                        } else {
                            match e {
                                Bin(Op::Add, ia, ib) => match *ib {
                                    Num(y) => Bin(Op::Add, ia, Box::new(Num(x + y))).simplify(),
                                    other => add_num(Bin(Op::Add, ia, Box::new(other)), x),
                                },
                                Bin(Op::Sub, ia, ib) => match *ib {
                                    Num(y) => Bin(Op::Add, ia, Box::new(Num(x - y))).simplify(),
                                    other => add_num(Bin(Op::Sub, ia, Box::new(other)), x),
                                },
                                e => add_num(e, x),
                            }
                        }
                    }
                    // pull signs out of products and quotients: -a * b is -(a * b)
                    (Op::Mul | Op::Div, Neg(x), y) => {
                        Neg(Box::new(Bin(op, x, Box::new(y)).simplify())).simplify()
                    }
                    (Op::Mul | Op::Div, x, Neg(y)) => {
                        Neg(Box::new(Bin(op, Box::new(x), y).simplify())).simplify()
                    }
                    // pull numeric factors out of products and quotients
                    (Op::Mul, Bin(Op::Mul, pa, x), y) if matches!(*pa, Num(_)) => Bin(
                        Op::Mul,
                        pa,
                        Box::new(Bin(Op::Mul, x, Box::new(y)).simplify()),
                    )
                    .simplify(),
                    (Op::Mul, x, Bin(Op::Mul, pb, y)) if matches!(*pb, Num(_)) => Bin(
                        Op::Mul,
                        pb,
                        Box::new(Bin(Op::Mul, Box::new(x), y).simplify()),
                    )
                    .simplify(),
                    (Op::Div, Bin(Op::Mul, pa, x), y) if matches!(*pa, Num(_)) => Bin(
                        Op::Mul,
                        pa,
                        Box::new(Bin(Op::Div, x, Box::new(y)).simplify()),
                    )
                    .simplify(),
                    (Op::Div, x, Bin(Op::Mul, pb, y)) if matches!(*pb, Num(_)) => match *pb {
                        Num(q) => Bin(
                            Op::Mul,
                            Box::new(Num(1.0 / q)),
                            Box::new(Bin(Op::Div, Box::new(x), y).simplify()),
                        )
                        .simplify(),
                        other => Bin(
                            Op::Div,
                            Box::new(x),
                            Box::new(Bin(Op::Mul, Box::new(other), y)),
                        ),
                    },
                    (Op::Sub, e, Num(x)) => Bin(Op::Add, Box::new(e), Box::new(Num(-x))).simplify(),
                    (Op::Sub, Num(0.0), e) => Neg(Box::new(e)).simplify(),
                    (Op::Div, e, Num(1.0)) => e,
                    (Op::Add, a, Neg(b)) => Bin(Op::Sub, Box::new(a), b),
                    (Op::Sub, a, Neg(b)) => Bin(Op::Add, Box::new(a), b),
                    (op, a, b) => Bin(op, Box::new(a), Box::new(b)),
                }
            }
            e => e,
        }
    }
}
