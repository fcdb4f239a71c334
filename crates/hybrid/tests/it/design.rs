//! What to measure next (`hxai hybrid design`, issue 49, first part). A hybrid of `y = k*x`
//! with an additive correction is fitted on `x` in 1..3 (where `y = 2x + 0.5 z`); an
//! alternative correction `0.5*z + 0.3*(x - 2)^2`, which the rows could not tell apart, is
//! added to the model's selection. Over a space reaching `x = 6`, the runs that separate the
//! two must go where `(x - 2)^2` is largest (high `x`); coverage runs spread over the space;
//! every run lies inside the space, and the choice is the same on every call.
use hxai_eval::Split;
use hxai_hybrid::tables::design::{DesignGoal, candidates, design, parse_space};
use hxai_hybrid::tables::{TableConfig, fit_split};
use hxai_symreg::Table;
use hxai_symreg::report::Alternative;

fn model() -> hxai_hybrid::tables::TableModel {
    model_with(0.0, "0.5*z + 0.3*(x - 2)**2")
}

/// The hybrid of `y = 2x + 0.5z (+ noise of amplitude `noise`)` on `x` in 1..3 with the
/// one alternative `alternative` (a correction in `x` and `z`).
fn model_with(noise: f64, alternative: &str) -> hxai_hybrid::tables::TableModel {
    let n = 60;
    let x: Vec<f64> = (0..n)
        .map(|i| 1.0 + 2.0 * i as f64 / (n - 1) as f64)
        .collect();
    let z: Vec<f64> = (0..n).map(|i| ((i * 7) % 11) as f64 / 10.0).collect();
    let y: Vec<f64> = x
        .iter()
        .zip(&z)
        .enumerate()
        .map(|(i, (x, z))| 2.0 * x + 0.5 * z + noise * (((i * 13) % 17) as f64 / 8.0 - 1.0))
        .collect();
    let t = Table::new(vec!["x".into(), "z".into(), "y".into()], vec![x, z, y]).expect("table");
    let mut cfg = TableConfig::new("y", "k*x");
    cfg.calibrate = vec!["k".into()];
    cfg.search.epochs = 2;
    let split = Split {
        train: (0..n).collect(),
        test: vec![],
    };
    let mut m = fit_split(&t, &cfg, &split, &mut |_| {}).expect("fit");
    let sel = m.correction.selection.as_mut().expect("selection");
    // the search's own runners-up out: one alternative whose disagreement is known
    sel.alternatives.clear();
    sel.alternatives.push(Alternative {
        equation: alternative.into(),
        sympy: alternative.into(),
        complexity: 7,
        structure: "c*z + c*(x + c)**2".into(),
        share: None,
    });
    m
}

#[test]
fn runs_go_where_the_equations_disagree_and_stay_in_the_space() {
    let m = model();
    let space = parse_space("x=0:6,z=0:1").expect("space");
    let c = candidates(&space, 3).expect("candidates");
    let p = design(&m, &c, 4, DesignGoal::Discriminate).expect("design");
    assert_eq!(p.goal, DesignGoal::Discriminate);
    assert_eq!(p.equations.len(), 2);
    assert_eq!(p.rows.len(), 4);
    let x = c.column("x").expect("x");
    // the first run where (x - 2)^2 is largest over 0..6: x near 6
    assert!(x[p.rows[0]] > 5.5, "first run at x = {}", x[p.rows[0]]);
    assert!(p.spread[0] >= p.spread[1] * 0.5);
    for &i in &p.rows {
        assert!((0.0..=6.0).contains(&x[i]));
    }
    assert!(
        p.reason[0].contains("2 equations differ"),
        "{}",
        p.reason[0]
    );
    // deterministic
    assert_eq!(
        design(&m, &c, 4, DesignGoal::Discriminate).expect("again"),
        p
    );

    // coverage: spread over the space (the runs are not all in one corner)
    let cov = design(&m, &c, 4, DesignGoal::Coverage).expect("coverage");
    let xs: Vec<f64> = cov.rows.iter().map(|&i| x[i]).collect();
    let span = xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - xs.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(span > 1.0, "{xs:?}");

    // refused: no run, more runs than candidates, a space without a column the model reads
    assert!(design(&m, &c, 0, DesignGoal::Coverage).is_err());
    assert!(design(&m, &c, c.n_rows() + 1, DesignGoal::Coverage).is_err());
    let only_x = candidates(&parse_space("x=0:6").expect("space"), 3).expect("candidates");
    let e = design(&m, &only_x, 2, DesignGoal::Coverage)
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(e.contains('z'), "{e}");
}

/// Box and Hill's weighting (with the model's covariance): where the two equations differ
/// by the same amount everywhere (an alternative that is the selected correction plus a
/// constant), the run worth most is where an outcome is least uncertain, so the first run
/// is the candidate whose delta-method prediction interval is narrowest (within 1 %),
/// read through the model's own intervals, not the design's arithmetic. Without the
/// weighting every candidate would tie and the first one would be taken.
#[test]
fn discriminating_runs_are_weighted_by_the_uncertainty_of_an_outcome() {
    // the alternative is set below, once the selected correction is known
    let mut m = model_with(0.05, "0");
    let equation = m.correction.forms.equation.clone();
    let alt = format!("{} + 0.3", m.correction.forms.sympy);
    let a = &mut m
        .correction
        .selection
        .as_mut()
        .expect("selection")
        .alternatives[0];
    a.equation = alt.clone();
    a.sympy = alt;
    assert!(
        m.hybrid
            .uncertainty
            .as_ref()
            .is_some_and(|u| !u.covariance.is_empty() && u.residual_variance > 0.0),
        "the noisy fit has a covariance ({equation})"
    );
    let space = parse_space("x=0:6,z=0:1").expect("space");
    let c = candidates(&space, 5).expect("candidates");
    let p = design(&m, &c, 3, DesignGoal::Discriminate).expect("design");
    assert_eq!(p.goal, DesignGoal::Discriminate);
    assert!(p.reason[0].contains("Box and Hill"), "{}", p.reason[0]);
    // the spread is the constant 0.3 wherever the correction is finite
    assert!((p.spread[0] - 0.3).abs() < 1e-9, "{}", p.spread[0]);
    let widths: Vec<f64> = m
        .intervals_with(&c, 0.95, hxai_eval::IntervalMethod::Delta)
        .expect("intervals")
        .iter()
        .map(|(lo, hi)| hi - lo)
        .collect();
    let narrowest = widths.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(
        widths[p.rows[0]] <= 1.01 * narrowest,
        "first run's interval {} against the narrowest {narrowest}",
        widths[p.rows[0]]
    );
    assert_ne!(p.rows[0], 0, "not the first candidate by a tie");
}
