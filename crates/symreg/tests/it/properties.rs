//! Property tests of the expression machinery.
#![allow(clippy::unwrap_used, clippy::needless_range_loop)]
use hxai_symreg::eval::Evaluator;
use hxai_symreg::fit::{InputScales, LmSettings, Unknowns, initial_params, levenberg_marquardt};
use hxai_symreg::search::generate::Tables;
use hxai_symreg::{
    ComplexityMeasure, Model, Node, Op, Program, SearchConfig, Table, fit_structure,
};
use proptest::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::common::affine_program;

fn tables(affine: bool) -> Tables {
    Tables {
        ops: Op::ALL.to_vec(),
        op_w: vec![1.0; Op::ALL.len()],
        in_w: vec![1.0; 3],
        affine,
        measure: ComplexityMeasure::FeaturesPlusOperators,
        max_complexity: 12,
        op_costs: hxai_symreg::ops::OpCosts::default(),
    }
}

fn columns(n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..3)
        .map(|_| (0..n).map(|_| rng.gen_range(0.3..2.5)).collect())
        .collect()
}

use rand::Rng;

/// Naive recursive evaluation of a postfix program at one row.
fn naive(prog: &Program, params: &[f64], row: &[f64]) -> f64 {
    naive_with_trig_argument(prog, params, row).0
}

/// Naive recursive evaluation of a postfix program at one row, with the largest magnitude of
/// any `sin` or `cos` argument met on the way (0 when there is none). A trigonometric
/// function of an argument near 1e10 turns the argument's last-bit rounding into an absolute
/// error near 1e-6 in its value, so two exact rewritings of one program can differ there by
/// far more than their rounding; a value comparison has to know it.
fn naive_with_trig_argument(prog: &Program, params: &[f64], row: &[f64]) -> (f64, f64) {
    let offs = prog.param_offsets();
    fn rec(
        prog: &Program,
        params: &[f64],
        offs: &[usize],
        row: &[f64],
        end: usize,
        trig: &mut f64,
    ) -> (f64, usize) {
        match prog.nodes[end] {
            Node::Var(j) => {
                let x = row[j as usize];
                let v = if prog.affine {
                    params[offs[end]] * x + params[offs[end] + 1]
                } else {
                    x
                };
                (v, end)
            }
            Node::Const => (params[offs[end]], end),
            Node::Op(op) => {
                if op.arity() == 1 {
                    let (a, s) = rec(prog, params, offs, row, end - 1, trig);
                    if matches!(op, Op::Sin | Op::Cos) {
                        *trig = trig.max(a.abs());
                    }
                    (op.apply1(a), s)
                } else {
                    let (b, sb) = rec(prog, params, offs, row, end - 1, trig);
                    let (a, sa) = rec(prog, params, offs, row, sb - 1, trig);
                    (op.apply2(a, b), sa)
                }
            }
        }
    }
    let mut trig = 0.0_f64;
    let (v, _) = rec(prog, params, &offs, row, prog.nodes.len() - 1, &mut trig);
    (params[0] * v + params[1], trig)
}

fn random_case(seed: u64, affine: bool) -> (Program, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let t = tables(affine);
    let prog = t.random_program(&mut rng);
    let params: Vec<f64> = (0..prog.n_params())
        .map(|_| rng.gen_range(-1.5..1.5))
        .collect();
    (prog, params)
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a.is_nan() && b.is_nan()) || a == b || (a - b).abs() <= rel * a.abs().max(b.abs()).max(1.0)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    // Invariant: the batched evaluator gives the same value as a naive recursive evaluator on
    // every row (up to 1e-12 relative, for operation-order differences), NaN where it is NaN,
    // for random programs over all operators, with and without affine inputs, and for row
    // counts that are not multiples of the batch size.
    #[test]
    fn batched_equals_naive(seed in any::<u64>(), affine in any::<bool>(), n in 1usize..300) {
        let (prog, params) = random_case(seed, affine);
        prop_assert!(prog.is_valid());
        let cols = columns(n, seed ^ 1);
        let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
        let mut out = Vec::new();
        Evaluator::new(&prog).predict(&prog, &params, &refs, n, &mut out);
        for r in 0..n {
            let row = [cols[0][r], cols[1][r], cols[2][r]];
            let want = naive(&prog, &params, &row);
            prop_assert!(close(out[r], want, 1e-12), "row {r}: {} vs {want}", out[r]);
        }
    }

    // Invariant: the AVX2 code path (when the CPU has it) and the portable one give the same
    // bits: both use only IEEE add, sub, mul, div and sqrt, never fused multiply-add.
    #[test]
    fn simd_and_portable_paths_agree_bitwise(seed in any::<u64>(), affine in any::<bool>(), n in 1usize..300) {
        let (prog, params) = random_case(seed, affine);
        let cols = columns(n, seed ^ 5);
        let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        Evaluator::new(&prog).predict(&prog, &params, &refs, n, &mut a);
        Evaluator::new(&prog).portable().predict(&prog, &params, &refs, n, &mut b);
        for (x, y) in a.iter().zip(&b) {
            prop_assert!(x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()), "{x} vs {y}");
        }
    }

    // Invariant: the normal equations of Levenberg-Marquardt (J^T J, J^T r and the loss)
    // have the same bits on the AVX2 code path (four dot products per load) and the
    // portable one, for row counts that are and are not multiples of the batch and of 8.
    #[test]
    fn normal_equations_paths_agree_bitwise(seed in any::<u64>(), affine in any::<bool>(), n in 1usize..600) {
        let (prog, params) = random_case(seed, affine);
        let cols = columns(n, seed ^ 7);
        let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
        let y: Vec<f64> = cols[0].iter().zip(&cols[1]).map(|(a, b)| a * b - a).collect();
        let free: Vec<usize> = (0..params.len()).collect();
        let m = free.len();
        let (mut jtj_a, mut jtr_a) = (vec![0.0; m * m], vec![0.0; m]);
        let (mut jtj_b, mut jtr_b) = (vec![0.0; m * m], vec![0.0; m]);
        let mse_a = Evaluator::new(&prog)
            .normal_equations(hxai_symreg::eval::Inputs { prog: &prog, params: &params, cols: &refs }, &free, &y, &mut jtj_a, &mut jtr_a);
        let mse_b = Evaluator::new(&prog)
            .portable()
            .normal_equations(hxai_symreg::eval::Inputs { prog: &prog, params: &params, cols: &refs }, &free, &y, &mut jtj_b, &mut jtr_b);
        prop_assert_eq!(mse_a.to_bits(), mse_b.to_bits());
        let same = |x: &f64, y: &f64| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan());
        for (x, y) in jtj_a.iter().zip(&jtj_b).chain(jtr_a.iter().zip(&jtr_b)) {
            prop_assert!(same(x, y), "{x} vs {y}");
        }
    }

    // Invariant: the simplified reporting expression has the same value as the program
    // wherever the program is finite and every sin or cos argument is below 1e4 in magnitude
    // (1e-9 relative: folding reassociates products).
    #[test]
    fn simplification_preserves_values(seed in any::<u64>(), affine in any::<bool>()) {
        let (prog, params) = random_case(seed, affine);
        let names: Vec<String> = vec!["a".into(), "b".into(), "c".into()];
        let e = hxai_symreg::expr::Expr::from_program(&prog, &params, &names);
        let cols = columns(20, seed ^ 2);
        for r in 0..20 {
            let row = [cols[0][r], cols[1][r], cols[2][r]];
            let (want, trig) = naive_with_trig_argument(&prog, &params, &row);
            if !want.is_finite() || want.abs() > 1e100 { continue; }
            // Beyond |argument| 1e4 a sin or cos is not defined to 1e-9 by its argument's
            // rounding (the argument's own error is about 1e4 * 1e-16 * the folds' few
            // roundings), so such rows say nothing about the simplification.
            if trig > 1e4 { continue; }
            let got = e.eval(&|n: &str| match n { "a" => row[0], "b" => row[1], _ => row[2] });
            prop_assert!(close(got, want, 1e-9), "{} : {got} vs {want}", e.to_text(None, false));
        }
    }

    // Invariant: a model saved to JSON and loaded back is equal to the original and predicts
    // exactly the same values.
    #[test]
    fn save_load_round_trip(seed in any::<u64>(), affine in any::<bool>()) {
        let (prog, params) = random_case(seed, affine);
        let m = Model::new(vec!["a".into(), "b".into(), "c".into()], prog, params).unwrap();
        let back = Model::from_json(&m.to_json()).unwrap();
        // NaN fields compare unequal, so compare the JSON text and the predictions
        prop_assert_eq!(back.to_json(), m.to_json());
        let cols = columns(50, seed ^ 3);
        let data = Table::new(vec!["a".into(), "b".into(), "c".into()], cols).unwrap();
        let p1 = m.predict(&data).unwrap();
        let p2 = back.predict(&data).unwrap();
        for (x, y) in p1.iter().zip(&p2) {
            prop_assert!(x.to_bits() == y.to_bits());
        }
    }

    // Invariant: Levenberg-Marquardt never increases the mean squared error of its start.
    #[test]
    fn lm_does_not_increase_loss(seed in any::<u64>(), affine in any::<bool>()) {
        let (prog, _) = random_case(seed, affine);
        let (truth, tparams) = random_case(seed.wrapping_add(7), affine);
        let cols = columns(200, seed ^ 4);
        let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
        let mut y = Vec::new();
        Evaluator::new(&truth).predict(&truth, &tparams, &refs, 200, &mut y);
        prop_assume!(y.iter().all(|v| v.is_finite() && v.abs() < 1e6));
        let mut ev = Evaluator::new(&prog);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut p = initial_params(&prog, &InputScales::new(&refs), Some(&mut rng), &refs, &y, &mut ev);
        let before = ev.mse(&prog, &p, &refs, &y);
        let free: Vec<usize> = (0..p.len()).collect();
        let after = levenberg_marquardt(
            &prog,
            &mut p,
            Unknowns::Free(&free),
            &refs,
            &y,
            &LmSettings::new(20, 1e-12),
            &mut ev,
        );
        prop_assert!(after <= before || !before.is_finite(), "{before} -> {after}");
    }
}

#[test]
fn gradient_matches_finite_differences() {
    // The Jacobian from the adjoint sweep matches central differences (1e-5 relative).
    let prog = affine_program("x0 x1 mul x2 gaussian2 sin");
    let params = vec![1.3, -0.2, 0.7, 0.1, -0.4, 0.3, 0.5, -0.6];
    let cols = columns(37, 9);
    let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
    let y: Vec<f64> = (0..37).map(|i| (i as f64 * 0.1).cos()).collect();
    let mut ev = Evaluator::new(&prog);
    let m = params.len();
    let free: Vec<usize> = (0..m).collect();
    let mut jtj = vec![0.0; m * m];
    let mut jtr = vec![0.0; m];
    ev.normal_equations(
        hxai_symreg::eval::Inputs {
            prog: &prog,
            params: &params,
            cols: &refs,
        },
        &free,
        &y,
        &mut jtj,
        &mut jtr,
    );
    // d(mse)/dp = 2/n * J^T r
    for p in 0..m {
        let h = 1e-6;
        let mut a = params.clone();
        a[p] += h;
        let mut b = params.clone();
        b[p] -= h;
        let fd = (ev.mse(&prog, &a, &refs, &y) - ev.mse(&prog, &b, &refs, &y)) / (2.0 * h);
        let an = 2.0 / 37.0 * jtr[p];
        assert!(
            (fd - an).abs() <= 1e-5 * an.abs().max(1e-3),
            "param {p}: fd {fd} analytic {an}"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    // Invariant: snapping constants never makes the model's BIC worse than the unsnapped
    // refit's, beyond the slack the snap rule allows (0.1 % of the loss plus 1e-14 of the
    // target's variance, for snaps to 1-3 significant digits). Snaps to exact values must
    // pay for themselves: the loss they add is at most what BIC stops charging for the
    // constant. Random programs with affine inputs, the target made by the program itself
    // plus 1 % noise, the structure refitted with and without snapping.
    #[test]
    fn snapping_never_worsens_the_criterion(seed in any::<u64>()) {
        let (prog, params) = random_case(seed, true);
        let n = 200;
        let cols = columns(n, seed ^ 7);
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 11);
        let clean: Vec<f64> = (0..n)
            .map(|r| naive(&prog, &params, &[cols[0][r], cols[1][r], cols[2][r]]))
            .collect();
        prop_assume!(clean.iter().all(|v| v.is_finite()));
        let mean = clean.iter().sum::<f64>() / n as f64;
        let var = clean.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64;
        prop_assume!(var > 1e-12 && var < 1e12);
        let y: Vec<f64> = clean
            .iter()
            .map(|v| v + 0.01 * var.sqrt() * rng.gen_range(-1.7..1.7))
            .collect();
        let data = Table::new(vec!["a".into(), "b".into(), "c".into()], cols).unwrap();
        let plain = SearchConfig { snap_constants: false, ..SearchConfig::default() };
        let (Ok(a), Ok(b)) = (
            fit_structure(&data, &y, &prog, &plain),
            fit_structure(&data, &y, &prog, &SearchConfig::default()),
        ) else {
            return Err(TestCaseError::reject("not fittable"));
        };
        let mean_y = y.iter().sum::<f64>() / n as f64;
        let var_y = y.iter().map(|v| (v - mean_y).powi(2)).sum::<f64>() / n as f64;
        let m = a.train_mse / var_y;
        let slack = n as f64 * ((m * (1.0 + 1e-3) + 1e-14 + 1e-12) / (m + 1e-12)).ln();
        prop_assert!(
            b.score <= a.score + slack + 1e-9 * a.score.abs().max(1.0),
            "snapped {} ({}) vs unsnapped {} ({}), slack {slack}",
            b.score, b.equation(), a.score, a.equation()
        );
    }
}
