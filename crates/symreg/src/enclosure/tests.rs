//! Tests of the enclosure: poles between samples, domains, bisection, each operator, and
//! a property test against the evaluator.
#![allow(clippy::unwrap_used, clippy::wildcard_imports)]
use super::arith::*;
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
fn defined_over_stops_once_every_box_is_defined() {
    let c = compiled("c/(x - 0.5)", &[("c", 2.0)]);
    assert_eq!(
        defined_over(&c.program, &c.params, &[(0.0, 1.0)], 64),
        Err(WHY_DIV)
    );
    assert_eq!(
        defined_over(&c.program, &c.params, &[(0.6, 1.0)], 64),
        Ok(())
    );
    let d = compiled("1/(x^2 - x + 1)", &[]);
    assert_eq!(
        defined_over(&d.program, &d.params, &[(0.0, 2.0)], 64),
        Ok(())
    );
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
    // all > 0 and the margin reaching 0: the lower end moves on the log scale instead,
    // 1 * (1/11)^0.1, so a power law of the column keeps a value there
    assert!(
        (bx[4].0 - (1.0f64 / 11.0).powf(0.1)).abs() < 1e-15,
        "{:?}",
        bx[4]
    );
    assert!(bx[4].0 > 0.0 && bx[4].0 < 1.0 && bx[4].1 == 12.0);
    // further from 0 the linear margin applies in full
    let bx = widened_box(&[&[2.0, 12.0][..]], 0.1);
    assert_eq!(bx[0], (1.0, 13.0));
    assert_eq!(widened_box(&[&[2.0, 12.0][..]], -1.0)[0], (2.0, 12.0));
}

/// Every operator, the search's ([`Op::ALL`]) and the equations' ones.
fn all_ops() -> Vec<Op> {
    Op::ALL.iter().copied().chain([Op::Pow, Op::Tan]).collect()
}

/// A random expression tree of at most `depth` levels over `n_vars` inputs, written in
/// postfix, its shape drawn from `choices`.
fn build(choices: &mut std::slice::Iter<'_, u32>, depth: usize, n_vars: u16, out: &mut Vec<Node>) {
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
    let ops = all_ops();
    let op = ops[(c / 3) as usize % ops.len()];
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
