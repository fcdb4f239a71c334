//! Recovery, determinism, the paper's eq. 12-13, and bad input.
#![allow(clippy::unwrap_used)]
use hxai_symreg::{
    Criterion, Op, Par, SearchConfig, SearchResult, SrError, Table, TableError, fit_structure,
    search,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::common::affine_program;

fn uniform(n: usize, lo: f64, hi: f64, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n).map(|_| rng.gen_range(lo..hi)).collect()
}

fn r2(pred: &[f64], y: &[f64]) -> f64 {
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let sst: f64 = y.iter().map(|v| (v - mean).powi(2)).sum();
    let sse: f64 = y.iter().zip(pred).map(|(a, b)| (a - b).powi(2)).sum();
    1.0 - sse / sst
}

fn quick() -> SearchConfig {
    SearchConfig {
        epochs: 4,
        candidates_per_epoch: 400,
        ..SearchConfig::default()
    }
}

/// `rows` rows of `n_in` inputs, each uniform on [1, 5) (input `i` seeded `seed + i`),
/// and the law `f` on each row.
fn sample_law(
    f: &impl Fn(&[f64]) -> f64,
    n_in: usize,
    rows: usize,
    seed: u64,
) -> (Vec<Vec<f64>>, Vec<f64>) {
    let cols: Vec<Vec<f64>> = (0..n_in)
        .map(|i| uniform(rows, 1.0, 5.0, seed + i as u64))
        .collect();
    let y: Vec<f64> = (0..rows)
        .map(|r| f(&cols.iter().map(|c| c[r]).collect::<Vec<_>>()))
        .collect();
    (cols, y)
}

fn run_law(f: impl Fn(&[f64]) -> f64, n_in: usize, cfg: &SearchConfig) -> (SearchResult, f64) {
    let names: Vec<String> = (0..n_in).map(|i| format!("x{i}")).collect();
    let (cols, y) = sample_law(&f, n_in, 300, 10);
    let data = Table::new(names.clone(), cols).unwrap();
    let res = search(&data, &y, cfg, &mut |_| {}).unwrap();
    // held-out rows from the same law
    let (test_cols, ty) = sample_law(&f, n_in, 200, 100);
    let test = Table::new(names, test_cols).unwrap();
    let score = r2(&res.best.predict(&test).unwrap(), &ty);
    (res, score)
}

// Recovery at noise 0: held-out R^2 above 1 - 1e-9 (an exact structure; approximations of
// these laws within complexity 10 do not get that close).
#[test]
fn recovers_newton_gravity() {
    // AI-Feynman style operator set (with `square`)
    let ops = [
        "add", "sub", "mul", "div", "square", "exp", "log", "sin", "cos",
    ];
    let cfg = SearchConfig {
        operators: ops.iter().map(|s| s.to_string()).collect(),
        ..quick()
    };
    let (res, score) = run_law(|x| x[0] * x[1] / (x[2] * x[2]), 3, &cfg);
    assert!(score > 1.0 - 1e-9, "R2 {score}: {}", res.best.equation());
}

#[test]
fn recovers_sine_product() {
    let (res, score) = run_law(|x| x[0] * (x[1]).sin(), 2, &quick());
    assert!(score > 1.0 - 1e-9, "R2 {score}: {}", res.best.equation());
}

#[test]
fn recovers_exponential_decay() {
    let (res, score) = run_law(|x| 2.0 * (-0.5 * x[0]).exp() + x[1], 2, &quick());
    assert!(score > 1.0 - 1e-9, "R2 {score}: {}", res.best.equation());
}

#[test]
fn identical_for_1_2_4_threads() {
    let cfg = SearchConfig {
        epochs: 3,
        candidates_per_epoch: 200,
        ..SearchConfig::default()
    };
    let mut outs = Vec::new();
    for threads in [1, 2, 4] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let (res, _) = pool.install(|| run_law(|x| x[0] * x[0] + (x[1]).cos(), 2, &cfg));
        let mut v = serde_json::to_value(&res).unwrap();
        v["seconds"] = serde_json::Value::Null;
        outs.push(serde_json::to_string(&v).unwrap());
    }
    assert_eq!(outs[0], outs[1]);
    assert_eq!(outs[0], outs[2]);
}

/// Invariant: the thread count chosen per call (`SearchConfig::par`) changes nothing: the
/// same search with `Par` of 1 and of 2 threads gives bit-identical models (the best and
/// the whole Pareto front, constants compared by their bits through the JSON form), with
/// BIC and with cross-validation (whose fold refits also run in the pool).
#[test]
fn identical_for_par_of_1_and_2_threads() {
    for criterion in [Criterion::Bic, Criterion::CrossValidation] {
        let outs: Vec<(String, Vec<String>)> = [1, 2]
            .into_iter()
            .map(|threads| {
                let cfg = SearchConfig {
                    epochs: 2,
                    candidates_per_epoch: 200,
                    criterion,
                    par: Par::threads(threads),
                    ..SearchConfig::default()
                };
                let (res, _) = run_law(|x| x[0] * x[0] + (x[1]).cos(), 2, &cfg);
                let front = res.pareto.iter().map(|m| m.to_json()).collect();
                (res.best.to_json(), front)
            })
            .collect();
        assert_eq!(outs[0], outs[1], "{criterion:?}");
    }
}

fn eq12_data(n: usize, seed: u64) -> (Table, Vec<f64>) {
    // The paper's eq. 12-13 with f1 (frequency), f2 and f6 in plausible ranges and three
    // unrelated distractor features.
    let f1 = uniform(n, 10.0, 40.0, seed);
    let f2 = uniform(n, 5.0, 40.0, seed + 1);
    let f6 = uniform(n, 1.5, 3.5, seed + 2);
    let d1 = uniform(n, 0.0, 1.0, seed + 3);
    let d2 = uniform(n, -2.0, 2.0, seed + 4);
    let y: Vec<f64> = (0..n)
        .map(|i| {
            let a2 = 3980.0 * (1.0 - 0.018 * f1[i]).powi(2) * (f6[i] - 0.02).powi(2) / 1000.0;
            let b2 = (0.044 * f2[i] - 1.0).powi(2);
            29.4 * (-(a2 + b2)).exp() - 9.71
        })
        .collect();
    let names = ["f1", "f2", "f6", "d1", "d2"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    (Table::new(names, vec![f1, f2, f6, d1, d2]).unwrap(), y)
}

// The structure of eq. 12-13, gaussian2(mul(f1, f6), f2), has complexity 5 and, fitted to data
// generated from it, reaches R^2 > 0.99 on held-out rows.
#[test]
fn paper_eq12_is_complexity_5_and_fits() {
    let (data, y) = eq12_data(400, 1);
    let prog = affine_program("x0 x2 mul x1 gaussian2");
    let m = fit_structure(&data, &y, &prog, &SearchConfig::default()).unwrap();
    assert_eq!(m.complexity(), 5);
    // (in any order: the model comes back in its canonical form, whose operand order is
    // the canonical one)
    let mut features = m.features();
    features.sort();
    assert_eq!(features, vec!["f1", "f2", "f6"]);
    let (test, ty) = eq12_data(300, 50);
    let score = r2(&m.predict(&test).unwrap(), &ty);
    assert!(score > 0.99, "R2 {score}: {}", m.equation());
}

// And the search (paper settings: 10 epochs, complexity <= 10, default operators, 600
// candidates an epoch to keep the test short) finds a model with held-out R^2 > 0.99.
#[test]
fn search_fits_paper_eq12_data() {
    let (data, y) = eq12_data(400, 1);
    let cfg = SearchConfig {
        candidates_per_epoch: 600,
        ..SearchConfig::default()
    };
    let res = search(&data, &y, &cfg, &mut |_| {}).unwrap();
    let (test, ty) = eq12_data(300, 50);
    let score = r2(&res.best.predict(&test).unwrap(), &ty);
    assert!(score > 0.99, "R2 {score}: {}", res.best.equation());
    assert!(res.best.complexity() <= 10);
}

#[test]
fn progress_is_reported_every_epoch() {
    let x = uniform(50, 1.0, 2.0, 3);
    let y: Vec<f64> = x.iter().map(|v| v * 2.0).collect();
    let data = Table::new(vec!["x".into()], vec![x]).unwrap();
    let cfg = SearchConfig {
        epochs: 3,
        candidates_per_epoch: 50,
        ..SearchConfig::default()
    };
    let mut seen = Vec::new();
    search(&data, &y, &cfg, &mut |p| {
        seen.push((p.epoch, p.epochs, p.evaluations))
    })
    .unwrap();
    assert_eq!(seen.len(), 3);
    assert_eq!(seen[2].0, 3);
    assert!(seen.windows(2).all(|w| w[0].2 <= w[1].2));
}

#[test]
fn bad_input_gives_typed_errors() {
    let x = vec![1.0, 2.0, 3.0];
    assert!(matches!(
        Table::new(vec!["x".into()], vec![vec![1.0, f64::NAN]]),
        Err(TableError::NonFinite { row: 1, .. })
    ));
    assert!(matches!(
        Table::new(
            vec!["a".into(), "b".into()],
            vec![vec![1.0], vec![1.0, 2.0]]
        ),
        Err(TableError::RaggedColumns { .. })
    ));
    assert!(matches!(
        Table::new(vec!["a".into()], vec![]),
        Err(TableError::NoColumns)
    ));
    assert!(matches!(
        Table::new(vec!["a".into(), "a".into()], vec![vec![1.0], vec![2.0]]),
        Err(TableError::DuplicateName(_))
    ));
    let data = Table::new(vec!["x".into()], vec![x.clone()]).unwrap();
    let cfg = SearchConfig::default();
    assert!(matches!(
        search(&data, &[1.0, 2.0], &cfg, &mut |_| {}),
        Err(SrError::TargetLength { .. })
    ));
    assert!(matches!(
        search(&data, &[1.0, f64::INFINITY, 2.0], &cfg, &mut |_| {}),
        Err(SrError::NonFinite { .. })
    ));
    assert!(matches!(
        search(&data, &[1.0, 2.0, 3.0], &cfg, &mut |_| {}),
        Err(SrError::TooFewRows { .. })
    ));
    let xs: Vec<f64> = (0..20).map(|i| i as f64).collect();
    let data = Table::new(vec!["x".into()], vec![xs]).unwrap();
    assert!(matches!(
        search(&data, &[4.0; 20], &cfg, &mut |_| {}),
        Err(SrError::ConstantTarget(_))
    ));
    let bad_ops = SearchConfig {
        operators: vec!["add".into(), "frobnicate".into()],
        ..SearchConfig::default()
    };
    let y: Vec<f64> = (0..20).map(|i| i as f64 * 2.0).collect();
    assert!(
        matches!(search(&data, &y, &bad_ops, &mut |_| {}), Err(SrError::UnknownOperator(o)) if o == "frobnicate")
    );
    let zero = SearchConfig {
        max_complexity: 0,
        ..SearchConfig::default()
    };
    assert!(matches!(
        search(&data, &y, &zero, &mut |_| {}),
        Err(SrError::InvalidConfig(_))
    ));
    let no_budget = SearchConfig {
        max_evaluations: Some(0),
        ..SearchConfig::default()
    };
    assert!(matches!(
        search(&data, &y, &no_budget, &mut |_| {}),
        Err(SrError::InvalidConfig(m)) if m.contains("max_evaluations")
    ));
    // unknown column when predicting
    let small = SearchConfig {
        epochs: 1,
        candidates_per_epoch: 20,
        ..SearchConfig::default()
    };
    let res = search(&data, &y, &small, &mut |_| {}).unwrap();
    let other = Table::new(vec!["z".into()], vec![vec![1.0]]).unwrap();
    assert!(matches!(res.best.predict(&other), Err(SrError::UnknownColumn(c)) if c == "x"));
    assert!(matches!(
        hxai_symreg::Model::from_json("{\"nope\": 1}"),
        Err(SrError::MalformedModel(_))
    ));
}

// Exported text: sympy text of a snapped exact model uses plain integers where the fit
// allows, and LaTeX is produced without panicking.
#[test]
fn snapped_constants_are_simple() {
    let x = uniform(200, 1.0, 3.0, 8);
    let y: Vec<f64> = x.iter().map(|v| 3.0 * v * v + 2.0).collect();
    let data = Table::new(vec!["x".into()], vec![x]).unwrap();
    let prog = affine_program("x0 x0 mul");
    let m = fit_structure(&data, &y, &prog, &SearchConfig::default()).unwrap();
    // x*x with two affine leaves is returned as its shorter form, one leaf squared
    assert_eq!(m.sympy(), "3*x**2 + 2", "{}", m.sympy());
    assert_eq!(m.equation(), "3*x**2 + 2");
    assert!(!m.latex().is_empty());
}

// A weight snapped to 0 kills its input's term: the reported model no longer lists that
// feature nor counts it (or the operator that joined it) in its complexity, and still
// predicts the law (issue 14's snapping fix).
#[test]
fn a_weight_snapped_to_zero_drops_its_feature_and_complexity() {
    let x0 = uniform(200, 1.0, 3.0, 31);
    let x1 = uniform(200, -2.0, 2.0, 32);
    let y: Vec<f64> = x0.iter().map(|v| 3.0 * v + 2.0).collect();
    let data = Table::new(vec!["x0".into(), "x1".into()], vec![x0, x1]).unwrap();
    // add(x0, x1): x1's weight fits to 0 and is snapped there
    let prog = affine_program("x0 x1 add");
    let m = fit_structure(&data, &y, &prog, &SearchConfig::default()).unwrap();
    assert_eq!(m.features(), vec!["x0".to_string()], "{}", m.equation());
    assert_eq!(m.complexity(), 1, "{}", m.equation());
    assert_eq!(
        m.program
            .complexity(hxai_symreg::ComplexityMeasure::default()),
        1
    );
    // still the law: exact to 1e-9 relative on the training rows
    let pred = m.predict(&data).unwrap();
    for (p, t) in pred.iter().zip(&y) {
        assert!((p - t).abs() <= 1e-9 * t.abs(), "{p} vs {t}");
    }
}

/// `1.5 x0 x1` plus Gaussian noise of 1 % of the target's standard deviation, 1,000 rows.
fn noisy_product() -> (Table, Vec<f64>) {
    let x0 = uniform(1000, 1.0, 5.0, 21);
    let x1 = uniform(1000, 1.0, 5.0, 22);
    let clean: Vec<f64> = x0.iter().zip(&x1).map(|(a, b)| 1.5 * a * b).collect();
    let mean = clean.iter().sum::<f64>() / 1000.0;
    let sd = (clean.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 1000.0).sqrt();
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let y: Vec<f64> = clean
        .iter()
        .map(|v| {
            // Box-Muller
            let (u1, u2): (f64, f64) = (rng.gen_range(1e-12..1.0), rng.gen_range(0.0..1.0));
            v + 0.01 * sd * (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
        })
        .collect();
    let data = Table::new(vec!["x0".into(), "x1".into()], vec![x0, x1]).unwrap();
    (data, y)
}

// On noisy data the fitted input offsets and the output offset only fit the noise: snapping
// them to 0 costs less than BIC charges for a parameter, so they go.
#[test]
fn noise_only_offsets_are_snapped_away() {
    let (data, y) = noisy_product();
    let prog = affine_program("x0 x1 mul");
    let m = fit_structure(&data, &y, &prog, &SearchConfig::default()).unwrap();
    // params: scale, offset, (w0, b0), (w1, b1)
    assert_eq!(m.params[1], 0.0, "{}", m.equation());
    assert_eq!(m.params[3], 0.0, "{}", m.equation());
    assert_eq!(m.params[5], 0.0, "{}", m.equation());
    assert!(!m.sympy().contains(['+', '-']), "{}", m.sympy());
}

// The search on the same data picks the product law itself, not a more complex model that
// fits the noise a little better.
#[test]
fn search_on_noisy_data_picks_the_law() {
    let (data, y) = noisy_product();
    let res = search(&data, &y, &quick(), &mut |_| {}).unwrap();
    assert_eq!(res.best.complexity, 3, "{}", res.best.equation());
    assert!(
        !res.best.sympy().contains(['+', '-']),
        "{}",
        res.best.sympy()
    );
}

#[test]
fn strategy_serde_names_match_the_flag_values() {
    use hxai_symreg::Strategy;
    assert_eq!(
        serde_json::to_string(&Strategy::QLattice).unwrap(),
        "\"qlattice\""
    );
    for name in ["\"qlattice\"", "\"q_lattice\""] {
        assert_eq!(
            serde_json::from_str::<Strategy>(name).unwrap(),
            Strategy::QLattice
        );
    }
    assert_eq!(
        serde_json::to_string(&Strategy::Genetic).unwrap(),
        "\"genetic\""
    );
}

// Operator complexities set in the configuration are what the reported complexities count,
// and no reported model exceeds the cap for its number of inputs.
#[test]
fn operator_complexity_is_counted_and_capped() {
    use hxai_symreg::ComplexityMeasure;
    use hxai_symreg::ops::OpCosts;
    let mut cfg = quick();
    cfg.complexity_per_input = 2;
    cfg.operator_complexity = [("mul".to_string(), 3), ("square".to_string(), 2)]
        .into_iter()
        .collect();
    let costs = cfg.op_costs().unwrap();
    assert_eq!(costs.of(Op::Mul), 3);
    assert_eq!(costs.of(Op::Add), 1);
    let (res, score) = run_law(|x| x[0] * x[1] + x[2], 3, &cfg);
    assert!(score > 0.99, "{score}: {}", res.best.equation());
    for m in res.pareto.iter().chain([&res.best]) {
        let c = m
            .program
            .complexity_with(ComplexityMeasure::FeaturesPlusOperators, &costs);
        assert_eq!(m.complexity, c, "{}", m.equation());
        assert!(c <= cfg.complexity_cap(3), "{}", m.equation());
    }
    // the cap: 10 for one input, 2 more per further input, at most 60
    assert_eq!(cfg.complexity_cap(1), 10);
    assert_eq!(cfg.complexity_cap(9), 26);
    assert_eq!(cfg.complexity_cap(100), 60);
    // a bad entry is a typed error
    let mut bad = SearchConfig::default();
    bad.operator_complexity.insert("cube".into(), 2);
    assert!(matches!(bad.check(), Err(SrError::UnknownOperator(_))));
    bad.operator_complexity.clear();
    bad.operator_complexity.insert("sqrt".into(), 0);
    assert!(matches!(bad.check(), Err(SrError::InvalidConfig(_))));
    let _ = OpCosts::default();
}

// A phase of a quarter turn, fitted on noisy data, snaps to pi/2 and the reported equation
// is the shifted function: 3 x1 sin(x0 - pi/2) reads as -3 x1 cos(x0), with no 1.571 left.
#[test]
fn quarter_turn_phase_snaps_and_reads_as_cos() {
    let n = 300;
    let x0 = uniform(n, -3.0, 3.0, 7);
    let x1 = uniform(n, 1.0, 5.0, 8);
    let noise = uniform(n, -0.01, 0.01, 9);
    let y: Vec<f64> = (0..n)
        .map(|r| 3.0 * x1[r] * (x0[r] - std::f64::consts::FRAC_PI_2).sin() + noise[r])
        .collect();
    let data = Table::new(vec!["x0".into(), "x1".into()], vec![x0, x1]).unwrap();
    let res = search(&data, &y, &quick(), &mut |_| {}).unwrap();
    let text = res.best.sympy();
    assert!(text.contains("cos(x0)"), "{text}");
    assert!(!text.contains("1.57") && !text.contains("pi"), "{text}");
}

// The normal density's constants are snapped to the values a physicist writes and printed
// by name in the sympy text: the fitted 0.39894228... of `exp(-x**2/2)/sqrt(2 pi)` becomes
// `1/sqrt(2*pi)`, and the weights +-0.70710678... of `exp(-(x0 - x1)**2/2)` become
// `sqrt(2)/2`, so SRBench's rule (floats rounded to 3 decimals) no longer breaks the law.
#[test]
fn normal_density_constants_snap_to_their_names() {
    let x0 = uniform(300, -3.0, 3.0, 21);
    let x1 = uniform(300, -3.0, 3.0, 22);
    let sympy_of = |cols: Vec<Vec<f64>>, y: Vec<f64>, postfix: &str| {
        let names = (0..cols.len()).map(|i| format!("x{i}")).collect();
        let data = Table::new(names, cols).unwrap();
        let cfg = SearchConfig::default();
        fit_structure(&data, &y, &affine_program(postfix), &cfg)
            .unwrap()
            .sympy()
    };
    let norm = 1.0 / (2.0 * std::f64::consts::PI).sqrt();
    let y = x0.iter().map(|v| norm * (-v * v / 2.0).exp()).collect();
    let text = sympy_of(vec![x0.clone()], y, "x0 gaussian");
    assert!(text.contains("1/sqrt(2*pi)"), "{text}");

    let y = x0
        .iter()
        .zip(&x1)
        .map(|(a, b)| (-(a - b) * (a - b) / 2.0).exp())
        .collect();
    let text = sympy_of(vec![x0, x1], y, "x0 x1 add gaussian");
    assert_eq!(text.matches("sqrt(2)/2").count(), 2, "{text}");
    assert!(!text.contains("0.707"), "{text}");
}

// A configuration checked once and searched with `search_checked` gives what `search` gives
// (which checks it itself), and what depends on the rows (more CV folds than rows) is still
// refused there.
#[test]
fn search_checked_is_search_without_the_second_check() {
    let x = uniform(40, 1.0, 5.0, 3);
    let y: Vec<f64> = x.iter().map(|v| 2.0 * v * v + 1.0).collect();
    let data = Table::new(vec!["x".into()], vec![x]).unwrap();
    let cfg = quick();
    let a = search(&data, &y, &cfg, &mut |_| {}).unwrap();
    let b = hxai_symreg::search_checked(&data, &y, &cfg.check().unwrap(), &mut |_| {}).unwrap();
    assert_eq!(a.best.equation(), b.best.equation());
    assert_eq!(a.evaluations, b.evaluations);
    let cv = SearchConfig {
        criterion: hxai_symreg::Criterion::CrossValidation,
        cv_folds: 41,
        ..quick()
    };
    let e = hxai_symreg::search_checked(&data, &y, &cv.check().unwrap(), &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("cv-folds"), "{e}");
}
