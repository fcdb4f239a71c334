//! Selection by k-fold cross-validated loss (`Criterion::CrossValidation`).
#![allow(clippy::unwrap_used)]
use hxai_symreg::{Criterion, SearchConfig, SearchResult, SrError, Table, search};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const ROWS: usize = 400;
const NOISE_SD: f64 = 0.5;

/// `y = 3 x0 + 1 + e`, `e ~ N(0, NOISE_SD^2)` (Box-Muller), with `x1` a distractor that
/// does not enter `y`.
fn noisy_line() -> (Table, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let x0: Vec<f64> = (0..ROWS).map(|_| rng.gen_range(0.0..4.0)).collect();
    let x1: Vec<f64> = (0..ROWS).map(|_| rng.gen_range(0.0..4.0)).collect();
    let y = x0
        .iter()
        .map(|x| {
            let (u1, u2): (f64, f64) = (rng.gen_range(f64::EPSILON..1.0), rng.r#gen());
            let e = (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
            3.0 * x + 1.0 + NOISE_SD * e
        })
        .collect();
    (
        Table::new(vec!["x0".into(), "x1".into()], vec![x0, x1]).unwrap(),
        y,
    )
}

fn cv_config() -> SearchConfig {
    SearchConfig {
        epochs: 3,
        candidates_per_epoch: 300,
        criterion: Criterion::CrossValidation,
        ..SearchConfig::default()
    }
}

fn run(threads: usize) -> SearchResult {
    let (data, y) = noisy_line();
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| search(&data, &y, &cv_config(), &mut |_| {}).unwrap())
}

// The reported score is the held-out error, so for the true structure it estimates the noise
// variance: 0.25 here. Its sampling error over 400 held-out rows is about
// sigma^2 sqrt(2/400) = 7 % of it; the band below is +-25 %, over 3.5 of those.
#[test]
fn cv_score_is_the_held_out_error_and_the_pick_ignores_the_distractor() {
    let res = run(2);
    let best = &res.best;
    assert_eq!(
        best.features(),
        vec!["x0".to_string()],
        "{}",
        best.equation()
    );
    let var = NOISE_SD * NOISE_SD;
    assert!(
        (0.75 * var..1.25 * var).contains(&best.score),
        "held-out MSE {} vs noise variance {var}",
        best.score
    );
    // on average a held-out error exceeds the training error of the same structure (the
    // training fit absorbs some of its own noise); with this seed it does
    assert!(best.score > best.train_mse, "{best:?}");
}

#[test]
fn cv_selection_does_not_depend_on_the_thread_count() {
    let (a, b) = (run(1), run(2));
    assert_eq!(a.best.equation(), b.best.equation());
    assert_eq!(a.best.score.to_bits(), b.best.score.to_bits());
    assert_eq!(a.pareto.len(), b.pareto.len());
}

#[test]
fn fewer_than_two_folds_are_refused() {
    let (data, y) = noisy_line();
    let cfg = SearchConfig {
        cv_folds: 1,
        ..cv_config()
    };
    let err = search(&data, &y, &cfg, &mut |_| {}).unwrap_err();
    assert!(
        matches!(err, SrError::InvalidConfig(ref m) if m.contains("cv_folds")),
        "{err}"
    );
}
