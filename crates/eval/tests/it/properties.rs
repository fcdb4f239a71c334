//! Property tests and bad-input tests of hxai-eval.

use hxai_eval::*;
use proptest::prelude::*;

type R = Result<(), Box<dyn std::error::Error>>;

fn finite_vec(min: usize, max: usize) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(-1e3f64..1e3, min..max)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    // A perfect prediction has R^2 = 1 and zero RMSE and MAE.
    #[test]
    fn perfect_prediction_scores_perfectly(y in finite_vec(1, 50)) {
        let m = score(&y, &y).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(m.r2, 1.0);
        prop_assert_eq!(m.rmse, 0.0);
        prop_assert_eq!(m.mae, 0.0);
    }

    // MAE <= RMSE always (Jensen), and both are non-negative.
    #[test]
    fn mae_never_exceeds_rmse(y in finite_vec(1, 40), shift in -5.0f64..5.0) {
        let p: Vec<f64> = y.iter().enumerate().map(|(i, v)| v + shift * (i as f64).sin()).collect();
        let m = score(&y, &p).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert!(m.mae >= 0.0 && m.mae <= m.rmse * (1.0 + 1e-12));
    }

    // A train/test split covers every index exactly once, both sides non-empty, and the
    // test side has ceil(fraction * n) samples.
    #[test]
    fn split_covers_every_index_once(n in 2usize..300, frac in 0.01f64..0.99, seed in any::<u64>()) {
        let expected = (frac * n as f64).ceil() as usize;
        match train_test_split(n, frac, seed) {
            Ok(s) => {
                prop_assert_eq!(s.test.len(), expected);
                let mut all: Vec<usize> = s.train.iter().chain(&s.test).copied().collect();
                all.sort_unstable();
                prop_assert_eq!(all, (0..n).collect::<Vec<_>>());
            }
            Err(e) => {
                // Only allowed when a side would be empty.
                prop_assert!(expected == 0 || expected >= n, "unexpected error {}", e);
            }
        }
    }

    // The k test folds partition 0..n, sizes differ by at most one, and each train side is
    // the complement of its test side.
    #[test]
    fn kfold_folds_partition(n in 2usize..200, k in 2usize..10, seed in any::<u64>()) {
        prop_assume!(k <= n);
        let folds = kfold(n, k, seed).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(folds.len(), k);
        let mut all: Vec<usize> = folds.iter().flat_map(|f| f.test.iter().copied()).collect();
        all.sort_unstable();
        prop_assert_eq!(all, (0..n).collect::<Vec<_>>());
        let sizes: Vec<usize> = folds.iter().map(|f| f.test.len()).collect();
        prop_assert!(sizes.iter().max().unwrap_or(&0) - sizes.iter().min().unwrap_or(&0) <= 1);
        for f in &folds {
            prop_assert_eq!(f.train.len() + f.test.len(), n);
            prop_assert!(f.test.iter().all(|i| f.train.binary_search(i).is_err()));
        }
    }

    // A grouped split never puts one group on both sides.
    #[test]
    fn grouped_split_never_splits_a_group(groups in prop::collection::vec(0u8..12, 2..120),
                                          frac in 0.05f64..0.95, seed in any::<u64>()) {
        if let Ok(s) = grouped_train_test_split(&groups, frac, seed) {
            prop_assert_eq!(s.train.len() + s.test.len(), groups.len());
            for &i in &s.test {
                prop_assert!(s.train.iter().all(|&j| groups[j] != groups[i]));
            }
        }
    }

    // Grouped k-fold: folds partition the samples, every fold is non-empty, and each group
    // sits in exactly one test fold.
    #[test]
    fn grouped_kfold_keeps_groups_whole(groups in prop::collection::vec(0u8..15, 2..150),
                                        k in 2usize..6, seed in any::<u64>()) {
        if let Ok(folds) = grouped_kfold(&groups, k, seed) {
            let mut all: Vec<usize> = folds.iter().flat_map(|f| f.test.iter().copied()).collect();
            all.sort_unstable();
            prop_assert_eq!(all, (0..groups.len()).collect::<Vec<_>>());
            for f in &folds {
                prop_assert!(!f.test.is_empty());
                for &i in &f.test {
                    prop_assert!(f.train.iter().all(|&j| groups[j] != groups[i]));
                }
            }
        }
    }

    // The t interval is never narrower than the normal one, and both contain the mean.
    #[test]
    fn t_interval_contains_normal_interval(v in finite_vec(2, 30)) {
        let s = summarize(&v).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert!(s.ci_t.lower <= s.ci_normal.lower + 1e-9 * s.mean.abs().max(1.0));
        prop_assert!(s.ci_normal.lower <= s.mean && s.mean <= s.ci_normal.upper);
        prop_assert!(s.ci_normal.upper <= s.ci_t.upper + 1e-9 * s.mean.abs().max(1.0));
    }

    // Swapping the two samples flips the statistic's sign and keeps the p-value; p lies in [0, 1].
    #[test]
    fn t_test_is_antisymmetric(a in finite_vec(2, 40), noise in 0.1f64..3.0) {
        let b: Vec<f64> = a.iter().enumerate().map(|(i, v)| v + noise * ((i * 7 % 5) as f64 - 1.7)).collect();
        let ab = paired_t_test(&a, &b).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let ba = paired_t_test(&b, &a).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(ab.statistic, -ba.statistic);
        prop_assert_eq!(ab.p_value, ba.p_value);
        prop_assert!((0.0..=1.0).contains(&ab.p_value));
    }
}

#[test]
fn same_seed_same_split_other_seed_other_split() -> R {
    assert_eq!(
        train_test_split(100, 0.2, 7)?,
        train_test_split(100, 0.2, 7)?
    );
    assert_ne!(
        train_test_split(100, 0.2, 7)?,
        train_test_split(100, 0.2, 8)?
    );
    Ok(())
}

#[test]
fn contiguous_kfold_matches_sklearn_kfold_blocks() -> R {
    // KFold(3) on 10 samples tests [0..4), [4..7), [7..10).
    let f = kfold_contiguous(10, 3)?;
    assert_eq!(f[0].test, vec![0, 1, 2, 3]);
    assert_eq!(f[1].test, vec![4, 5, 6]);
    assert_eq!(f[2].test, vec![7, 8, 9]);
    Ok(())
}

#[test]
fn improvement_matches_the_paper_definition() -> R {
    // The paper: physics RMSE 2.87, hybrid 0.6529 -> 77.25 % (the paper prints 77.27).
    let pct = improvement_pct(2.87, 0.6529)?;
    assert!((pct - 77.2508).abs() < 1e-3, "{pct}");
    Ok(())
}

#[test]
fn bad_input_gives_typed_errors() {
    assert!(matches!(r2(&[], &[]), Err(EvalError::Empty { .. })));
    assert!(matches!(
        rmse(&[1.0, 2.0], &[1.0]),
        Err(EvalError::LengthMismatch { .. })
    ));
    assert!(matches!(
        mae(&[1.0, f64::NAN], &[1.0, 2.0]),
        Err(EvalError::NonFinite { index: 1, .. })
    ));
    for fraction in [0.0, 1.0, f64::NAN] {
        assert!(
            matches!(
                train_test_split(10, fraction, 1),
                Err(EvalError::FractionOutOfRange { .. })
            ),
            "fraction {fraction}"
        );
    }
    for n in [1, 0] {
        assert!(
            matches!(
                train_test_split(n, 0.5, 1),
                Err(EvalError::EmptySide { .. })
            ),
            "{n} rows"
        );
    }
    assert!(matches!(
        kfold(4, 5, 1),
        Err(EvalError::TooManyFolds { .. })
    ));
    assert!(matches!(kfold(4, 1, 1), Err(EvalError::TooFewFolds { .. })));
    assert!(matches!(
        grouped_kfold(&[1, 1, 2, 2], 3, 1),
        Err(EvalError::TooManyFolds { .. })
    ));
    assert!(matches!(
        grouped_train_test_split(&[1, 1, 1], 0.5, 1),
        Err(EvalError::EmptySide { .. })
    ));
    assert!(matches!(summarize(&[1.0]), Err(EvalError::Empty { .. })));
    assert!(matches!(
        summarize_at(&[1.0, 2.0], 1.5),
        Err(EvalError::FractionOutOfRange { .. })
    ));
    assert!(matches!(
        paired_t_test(&[1.0, 2.0], &[1.0, 2.0]),
        Err(EvalError::IdenticalSamples)
    ));
    assert!(matches!(
        paired_t_test(&[1.0, 2.0], &[1.0]),
        Err(EvalError::LengthMismatch { .. })
    ));
    assert!(matches!(
        improvement_pct(0.0, 1.0),
        Err(EvalError::NonPositive { .. })
    ));
}

// A constant target whose mean does not round back to its value (ten copies of 0.1) is
// constant all the same: scikit-learn's 0.0 for an imperfect prediction, 1.0 for a perfect
// one; before, SS_tot of about 1e-33 gave R^2 of about -1e27.
#[test]
fn a_constant_target_scores_like_scikit_learn_despite_rounding() -> R {
    let y = [0.1; 10];
    let mean = y.iter().sum::<f64>() / 10.0;
    assert_ne!(mean, 0.1, "the case needs a mean that does not round back");
    assert_eq!(r2(&y, &[0.2; 10])?, 0.0);
    assert_eq!(r2(&y, &y)?, 1.0);
    // a truly varying target just above rounding is still scored as usual
    let v = [0.1, 0.1 + 1e-9, 0.1 - 1e-9, 0.1];
    let shifted: Vec<f64> = v.iter().map(|x| x + 5e-10).collect();
    let r = r2(&v, &shifted)?;
    // SS_res = 4 (5e-10)^2 = 1e-18 against SS_tot = 2e-18; the differences of 1e-9 on 0.1
    // carry about 1e-8 relative rounding
    assert!((r - 0.5).abs() < 1e-6, "{r}");
    Ok(())
}

#[test]
fn constant_shift_gives_infinite_statistic_and_zero_p() -> R {
    let t = paired_t_test(&[2.0, 3.0, 4.0], &[1.0, 2.0, 3.0])?;
    assert_eq!(t.statistic, f64::INFINITY);
    assert_eq!(t.p_value, 0.0);
    Ok(())
}

// `extent`, `residuals` and `means_by_key` on hand-checked numbers (exact: every value is a
// small dyadic fraction, so sums and means are exact in f64).
#[test]
fn extent_residuals_and_means_by_key_by_hand() -> R {
    let e = extent(&[0.5, -1.25, 2.0, 0.75])?;
    assert_eq!((e.min, e.max, e.mean), (-1.25, 2.0, 0.5));
    assert!(matches!(extent(&[]), Err(EvalError::Empty { .. })));
    assert!(matches!(
        extent(&[1.0, f64::NAN]),
        Err(EvalError::NonFinite { index: 1, .. })
    ));
    assert_eq!(residuals(&[1.0, 2.0], &[1.5, 1.0])?, [0.5, -1.0]);
    assert!(matches!(
        residuals(&[1.0], &[1.0, 2.0]),
        Err(EvalError::LengthMismatch { .. })
    ));
    // 10 Hz twice (once read with a rounding error below 1e-6), 20 Hz once; keys ascending.
    let m = means_by_key([(20.0, 4.0), (10.0, 1.0), (10.000_000_1, 2.0)]);
    assert_eq!(m, [(10.0, 1.5), (20.0, 4.0)]);
    Ok(())
}
