//! Property tests and bad-input tests of hxai-baselines.

use hxai_baselines::*;
use proptest::prelude::*;

type R = Result<(), Box<dyn std::error::Error>>;

/// A feature table of `rows`, columns named `x0`, `x1`, ...
fn table(rows: &[Vec<f64>]) -> Result<Table, TableError> {
    let p = rows.first().map_or(1, Vec::len);
    Table::from_rows((0..p).map(|j| format!("x{j}")).collect(), rows)
}

/// The rows of `t`, copied out.
fn rows_of(t: &Table) -> impl Iterator<Item = Vec<f64>> + '_ {
    (0..t.n_rows()).map(|i| t.row(i))
}

fn fail(e: impl std::fmt::Display) -> TestCaseError {
    TestCaseError::fail(e.to_string())
}

/// Rows of `p` features in [-10, 10].
fn rows(n: std::ops::Range<usize>, p: usize) -> impl Strategy<Value = Vec<Vec<f64>>> {
    prop::collection::vec(prop::collection::vec(-10.0f64..10.0, p), n)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    // Linear regression is exact on noiseless linear data (with more rows than features,
    // and a well-conditioned design since the columns are continuous random draws).
    #[test]
    fn linear_regression_is_exact_on_noiseless_linear_data(
        x in rows(8..40, 3), coef in prop::collection::vec(-5.0f64..5.0, 3), b in -5.0f64..5.0
    ) {
        let m = table(&x).map_err(fail)?;
        let y: Vec<f64> = rows_of(&m).map(|r| b + r.iter().zip(&coef).map(|(a, c)| a * c).sum::<f64>()).collect();
        let mut lr = LinearRegression::new();
        lr.fit(&m, &y).map_err(fail)?;
        let pred = lr.predict(&m).map_err(fail)?;
        // Tolerance 1e-8 absolute on targets of size <= ~160.
        for (p, t) in pred.iter().zip(&y) {
            prop_assert!((p - t).abs() < 1e-8, "{} vs {}", p, t);
        }
    }

    // A tree with at most k leaves has at most k leaves and at most k distinct predictions,
    // and every prediction lies within the range of the training targets.
    #[test]
    fn tree_with_k_leaves_has_at_most_k_distinct_predictions(
        x in rows(2..60, 3), y in prop::collection::vec(-100.0f64..100.0, 60), k in 2usize..10
    ) {
        let m = table(&x).map_err(fail)?;
        let y = &y[..m.n_rows()];
        let mut t = DecisionTree::with_max_leaf_nodes(k);
        t.fit(&m, y).map_err(fail)?;
        prop_assert!(t.n_leaves() <= k);
        let mut pred = t.predict(&m).map_err(fail)?;
        pred.sort_by(f64::total_cmp);
        pred.dedup();
        prop_assert!(pred.len() <= k);
        let (lo, hi) = y.iter().fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
        prop_assert!(pred.iter().all(|p| *p >= lo - 1e-9 && *p <= hi + 1e-9));
    }

    // The Lasso's chosen alpha lies on its own path and predictions are finite.
    #[test]
    fn lasso_cv_picks_an_alpha_from_its_path(x in rows(9..40, 4), noise in prop::collection::vec(-1.0f64..1.0, 40)) {
        let m = table(&x).map_err(fail)?;
        let y: Vec<f64> = rows_of(&m).zip(&noise).map(|(r, e)| 2.0 * r[0] - r[2] + e).collect();
        let mut l = LassoCv::new();
        l.fit(&m, &y).map_err(fail)?;
        prop_assert!(l.alphas().contains(&l.alpha()));
        prop_assert!(l.predict(&m).map_err(fail)?.iter().all(|v| v.is_finite()));
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8))]

    // The forest is the same for 1 and 2 threads (each tree seeded from (seed, tree index)).
    #[test]
    fn forest_is_identical_across_thread_counts(x in rows(10..60, 3), seed in any::<u64>()) {
        let m = table(&x).map_err(fail)?;
        let y: Vec<f64> = rows_of(&m).map(|r| r[0] * r[1] - r[2]).collect();
        let fit_with = |threads: usize| -> Result<Vec<f64>, TestCaseError> {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(fail)?;
            pool.install(|| {
                let mut f = RandomForest::with_seed(seed);
                f.n_trees = 20;
                f.fit(&m, &y).map_err(fail)?;
                f.predict(&m).map_err(fail)
            })
        };
        let one = fit_with(1)?;
        let two = fit_with(2)?;
        prop_assert_eq!(one, two);
    }
}

#[test]
fn different_forest_seeds_give_different_forests() -> R {
    let x = table(
        &(0..40)
            .map(|i| vec![(i as f64 * 0.37).sin(), (i as f64 * 0.11).cos()])
            .collect::<Vec<_>>(),
    )?;
    let y: Vec<f64> = rows_of(&x).map(|r| r[0] + r[1] * r[1]).collect();
    let mut a = RandomForest::with_seed(1);
    let mut b = RandomForest::with_seed(2);
    a.n_trees = 10;
    b.n_trees = 10;
    a.fit(&x, &y)?;
    b.fit(&x, &y)?;
    assert_ne!(a.predict(&x)?, b.predict(&x)?);
    Ok(())
}

#[test]
fn bad_input_gives_typed_errors() -> R {
    let x = table(&[vec![1.0, 2.0], vec![3.0, 4.0], vec![5.0, 7.0]])?;
    let empty = Table::new(vec!["x0".into(), "x1".into()], vec![vec![], vec![]])?;
    // A NaN feature cannot reach a model: the table refuses it, naming row 0 of `x1`.
    assert!(matches!(
        table(&[vec![1.0, f64::NAN], vec![3.0, 4.0]]),
        Err(TableError::NonFinite { row: 0, ref name, .. }) if name == "x1"
    ));
    for mut m in table3_models(42) {
        assert!(
            matches!(m.predict(&x), Err(BaselineError::NotFitted { .. })),
            "{}",
            m.name()
        );
        assert!(
            matches!(m.fit(&empty, &[]), Err(BaselineError::Empty { .. })),
            "{}",
            m.name()
        );
        assert!(
            matches!(m.fit(&x, &[1.0]), Err(BaselineError::LengthMismatch { .. })),
            "{}",
            m.name()
        );
        assert!(
            matches!(
                m.fit(&x, &[1.0, f64::INFINITY, 2.0]),
                Err(BaselineError::NonFinite { .. })
            ),
            "{}",
            m.name()
        );
    }
    let mut lr = LinearRegression::new();
    lr.fit(&x, &[1.0, 2.0, 3.0])?;
    let one_col = table(&[vec![1.0]])?;
    assert!(matches!(
        lr.predict(&one_col),
        Err(BaselineError::FeatureCount { fitted: 2, got: 1 })
    ));
    // LassoCV with 3 folds on 2 rows: more folds than samples.
    let two = table(&[vec![1.0], vec![2.0]])?;
    assert!(matches!(
        LassoCv::new().fit(&two, &[1.0, 2.0]),
        Err(BaselineError::Eval(_))
    ));
    assert!(matches!(
        DecisionTree::with_max_leaf_nodes(1).fit(&x, &[1.0, 2.0, 3.0]),
        Err(BaselineError::InvalidParameter { .. })
    ));
    assert!(matches!(
        Table::new(
            vec!["a".into(), "b".into()],
            vec![vec![1.0, 2.0], vec![1.0]]
        ),
        Err(TableError::RaggedColumns { .. })
    ));
    assert!(matches!(
        table(&[vec![1.0], vec![1.0, 2.0]]),
        Err(TableError::RaggedColumns { .. })
    ));
    assert!(matches!(
        x.select_rows(&[5]),
        Err(TableError::RowOutOfRange { .. })
    ));
    Ok(())
}

#[test]
fn rank_deficient_design_gives_the_minimum_norm_fit() -> R {
    // Column 1 duplicates column 0: the minimum-norm solution splits the weight evenly.
    let x = table(
        &(0..10)
            .map(|i| vec![i as f64, i as f64])
            .collect::<Vec<_>>(),
    )?;
    let y: Vec<f64> = (0..10).map(|i| 2.0 * i as f64 + 1.0).collect();
    let mut lr = LinearRegression::new();
    lr.fit(&x, &y)?;
    assert!(
        (lr.coef()[0] - 1.0).abs() < 1e-10 && (lr.coef()[1] - 1.0).abs() < 1e-10,
        "{:?}",
        lr.coef()
    );
    Ok(())
}

#[test]
fn cross_validate_scores_every_fold() -> R {
    let x = table(
        &(0..50)
            .map(|i| vec![i as f64, (i as f64).sqrt()])
            .collect::<Vec<_>>(),
    )?;
    let y: Vec<f64> = rows_of(&x).map(|r| 3.0 * r[0] - r[1]).collect();
    let folds = hxai_eval::kfold(50, 5, 42)?;
    let mut heard = Vec::new();
    let scores = cross_validate(
        &|| Box::new(LinearRegression::new()),
        &x,
        &y,
        &folds,
        &mut |p| heard.push(p.done),
    )?;
    assert_eq!(scores.len(), 5);
    assert_eq!(heard, [1, 2, 3, 4, 5]);
    assert!(scores.iter().all(|m| m.r2 > 1.0 - 1e-12));
    Ok(())
}

// `compare` fits every model in order, scores it on the test rows with `hxai_eval::score`,
// reports progress per model, and names the model that fails.
#[test]
fn compare_scores_each_model_and_names_a_failure() -> R {
    let rows: Vec<Vec<f64>> = (0..30)
        .map(|i| vec![i as f64, (i as f64 * 0.7).sin()])
        .collect();
    let x = table(&rows)?;
    let y: Vec<f64> = rows_of(&x).map(|r| 2.0 * r[0] - r[1] + 1.0).collect();
    let (train, test): (Vec<usize>, Vec<usize>) = (0..30).partition(|i| i % 5 != 0);
    let (x_train, x_test) = (x.select_rows(&train)?, x.select_rows(&test)?);
    let pick = |idx: &[usize]| idx.iter().map(|&i| y[i]).collect::<Vec<f64>>();
    let (y_train, y_test) = (pick(&train), pick(&test));
    let models: Vec<Box<dyn Regressor>> = vec![
        Box::new(LinearRegression::new()),
        Box::new(DecisionTree::with_max_leaf_nodes(5)),
    ];
    let mut heard = Vec::new();
    let rows = compare(models, &x_train, &y_train, &x_test, &y_test, &mut |p| {
        heard.push((p.done, p.total))
    })?;
    assert_eq!(heard, [(1, 2), (2, 2)]);
    let names: Vec<&str> = rows.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["linear", "tree_5"]);
    // Noiseless linear data: the linear model is exact to 1e-10 in R^2.
    assert!(rows[0].metrics.r2 > 1.0 - 1e-10, "{:?}", rows[0]);
    let mut tree = DecisionTree::with_max_leaf_nodes(5);
    tree.fit(&x_train, &y_train)?;
    assert_eq!(
        rows[1].metrics,
        hxai_eval::score(&y_test, &tree.predict(&x_test)?)?
    );
    let one_col = x_test.select_columns(&["x0"])?;
    let err = compare(
        vec![Box::new(LinearRegression::new())],
        &x_train,
        &y_train,
        &one_col,
        &y_test,
        &mut |_| {},
    )
    .err()
    .ok_or("expected an error")?;
    assert!(
        matches!(&err, BaselineError::Model { model, .. } if model == "linear"),
        "{err:?}"
    );
    Ok(())
}
