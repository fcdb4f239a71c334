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
    let mut m = fitted(noise);
    let sel = m.correction.selection.as_mut().expect("selection");
    // the search's own runners-up out: one alternative whose disagreement is known
    sel.alternatives.clear();
    sel.alternatives.push(Alternative {
        equation: alternative.into(),
        sympy: alternative.into(),
        complexity: 7,
        structure: "c*z + c*(x + c)**2".into(),
        share: None,
        uncertainty: None,
        codelength: None,
    });
    m
}

/// The fixture's table: `y = 2x + 0.5z (+ noise of amplitude `noise`)` on `x` in 1..3.
fn table_with(noise: f64) -> Table {
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
    Table::new(vec!["x".into(), "z".into(), "y".into()], vec![x, z, y]).expect("table")
}

/// The hybrid `k*x` with its searched correction on [`table_with`]`(noise)`, every row a
/// training row, its selection as the search left it.
fn fitted(noise: f64) -> hxai_hybrid::tables::TableModel {
    fitted_with(noise, "k*x")
}

/// [`fitted`] with the physics `physics` (its one parameter `k` calibrated).
fn fitted_with(noise: f64, physics: &str) -> hxai_hybrid::tables::TableModel {
    let t = table_with(noise);
    let n = t.n_rows();
    let mut cfg = TableConfig::new("y", physics);
    cfg.calibrate = vec!["k".into()];
    cfg.search.epochs = 2;
    let split = Split {
        train: (0..n).collect(),
        test: vec![],
    };
    fit_split(&t, &cfg, &split, &mut |_| {}).expect("fit")
}

#[test]
fn runs_go_where_the_equations_disagree_and_stay_in_the_space() {
    let m = model();
    let space = parse_space("x=0:6,z=0:1").expect("space");
    let c = candidates(&space, 3).expect("candidates").table;
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
    let only_x = candidates(&parse_space("x=0:6").expect("space"), 3)
        .expect("candidates")
        .table;
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
    let c = candidates(&space, 5).expect("candidates").table;
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

/// The inverse of the small invertible `a` (Gauss-Jordan with partial pivoting), written
/// here apart from the design's own code.
fn inverse(a: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let k = a.len();
    let mut m: Vec<Vec<f64>> = a
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let mut row = r.clone();
            row.extend((0..k).map(|j| if i == j { 1.0 } else { 0.0 }));
            row
        })
        .collect();
    for c in 0..k {
        let p = (c..k)
            .max_by(|&x, &y| m[x][c].abs().total_cmp(&m[y][c].abs()))
            .expect("a pivot row");
        m.swap(c, p);
        let d = m[c][c];
        assert!(d.abs() > 0.0, "singular");
        for v in &mut m[c] {
            *v /= d;
        }
        for r in 0..k {
            if r != c {
                let f = m[r][c];
                let pivot = m[c].clone();
                for (v, pv) in m[r].iter_mut().zip(&pivot) {
                    *v -= f * pv;
                }
            }
        }
    }
    m.into_iter().map(|r| r[k..].to_vec()).collect()
}

/// The determinant of the small `a` (elimination with partial pivoting).
fn determinant(a: &[Vec<f64>]) -> f64 {
    let k = a.len();
    let mut m = a.to_vec();
    let mut det = 1.0;
    for c in 0..k {
        let p = (c..k)
            .max_by(|&x, &y| m[x][c].abs().total_cmp(&m[y][c].abs()))
            .expect("a pivot row");
        if p != c {
            m.swap(c, p);
            det = -det;
        }
        det *= m[c][c];
        for r in c + 1..k {
            let f = m[r][c] / m[c][c];
            let pivot = m[c].clone();
            for (v, pv) in m[r].iter_mut().zip(&pivot) {
                *v -= f * pv;
            }
        }
    }
    det
}

/// `precision` against a brute-force reference computed from the model file alone: for
/// each set of runs, the physics parameters' block of the constants' covariance after the
/// runs, `C - C G^T (G C G^T + s^2 I)^-1 G C` (all runs at once, not the design's rank-one
/// updates one run at a time), and its determinant (the volume of their joint confidence region). One run:
/// the design's pick is the set with the smallest determinant. Three runs out of 12
/// candidates (220 sets): the greedy choice, each pick with the earlier ones fixed, reaches
/// at least 95 % of the best set's D-efficiency (`(det_best / det_greedy)^(1/p)`, `p` the
/// physics parameters). Greedy is not optimal in general; 95 % is the bar set here (below
/// it, the design would waste more than one run in twenty against the best set), and the
/// efficiency measured on this model is in docs/benchmarks.md.
#[test]
fn precision_agrees_with_a_brute_force_search_over_every_set_of_runs() {
    let m = model_with(0.05, "0");
    let u = m.hybrid.uncertainty.as_ref().expect("uncertainty");
    assert!(!u.covariance.is_empty() && u.residual_variance > 0.0);
    // 12 candidates, not on a symmetric grid (no ties)
    let xs: Vec<f64> = (0..12).map(|i| 0.3 + 0.47 * i as f64).collect();
    let zs: Vec<f64> = (0..12).map(|i| ((i * 5) % 12) as f64 / 11.0).collect();
    let c = Table::new(vec!["x".into(), "z".into()], vec![xs, zs]).expect("candidates");
    // the gradient of the hybrid in each constant at each candidate (central differences)
    let (_, grads) = prediction_and_gradient(u, &c);
    let physics: Vec<usize> = u
        .params
        .iter()
        .enumerate()
        .filter(|(_, (n, _))| m.physics.calibrated.contains(n))
        .map(|(j, _)| j)
        .collect();
    assert!(!physics.is_empty(), "k is calibrated");
    let k = u.params.len();
    let cov = &u.covariance;
    let s2 = u.residual_variance;
    // the covariance after the runs: C - C G^T (G C G^T + s^2 I)^-1 G C, the runs' gradients
    // G (one row a run) taken together (the file's C may be singular where constants are
    // confounded, so the information form (C^-1 + G^T G / s^2)^-1 is not used)
    let det_after = |runs: &[usize]| -> f64 {
        let cg: Vec<Vec<f64>> = runs
            .iter()
            .map(|&i| {
                (0..k)
                    .map(|a| (0..k).map(|b| cov[a][b] * grads[b][i]).sum())
                    .collect()
            })
            .collect();
        let mut gcg: Vec<Vec<f64>> = runs
            .iter()
            .map(|&i| {
                cg.iter()
                    .map(|col| (0..k).map(|a| grads[a][i] * col[a]).sum())
                    .collect()
            })
            .collect();
        for (r, row) in gcg.iter_mut().enumerate() {
            row[r] += s2;
        }
        let inv = inverse(&gcg);
        let post = |a: usize, b: usize| -> f64 {
            let mut v = cov[a][b];
            for (r, cr) in cg.iter().enumerate() {
                for (q, cq) in cg.iter().enumerate() {
                    v -= cr[a] * inv[r][q] * cq[b];
                }
            }
            v
        };
        let block: Vec<Vec<f64>> = physics
            .iter()
            .map(|&a| physics.iter().map(|&b| post(a, b)).collect())
            .collect();
        determinant(&block)
    };
    let one = design(&m, &c, 1, DesignGoal::Precision).expect("design");
    let best_one = (0..12)
        .min_by(|&a, &b| det_after(&[a]).total_cmp(&det_after(&[b])))
        .expect("a candidate");
    assert_eq!(one.rows, vec![best_one]);
    let three = design(&m, &c, 3, DesignGoal::Precision).expect("design");
    let mut best = f64::INFINITY;
    for a in 0..12 {
        for b in a + 1..12 {
            for d in b + 1..12 {
                best = best.min(det_after(&[a, b, d]));
            }
        }
    }
    let greedy = det_after(&three.rows);
    let efficiency = (best / greedy).powf(1.0 / physics.len() as f64);
    assert!(
        (0.95..=1.0 + 1e-9).contains(&efficiency),
        "greedy {:?}: D-efficiency {efficiency}",
        three.rows
    );
    // the greedy runs are the design's first picks in order: the first is the one-run best
    assert_eq!(three.rows[0], best_one);
}

/// The prediction of `template` (its constants `params`) on `c`, and its gradient in each
/// constant by central differences: the test's own evaluation of a model file's covariance.
fn prediction_and_gradient(u: &hxai_symreg::Uncertainty, c: &Table) -> (Vec<f64>, Vec<Vec<f64>>) {
    let values: std::collections::BTreeMap<String, f64> =
        u.params.iter().map(|(n, p)| (n.clone(), p.value)).collect();
    let at = |name: Option<&str>, dv: f64| {
        let mut v = values.clone();
        if let Some(name) = name {
            *v.get_mut(name).expect("a constant") += dv;
        }
        let compiled =
            hxai_symreg::infix::compile_text(&u.template, &v).expect("the template compiles");
        let cols: Vec<&[f64]> = compiled
            .inputs
            .iter()
            .map(|n| c.column(n).expect("a column"))
            .collect();
        compiled.eval_columns(&cols, c.n_rows())
    };
    let grads = u
        .params
        .iter()
        .map(|(name, p)| {
            let h = 1e-6 * p.value.abs().max(1e-3);
            let (hi, lo) = (at(Some(name), h), at(Some(name), -h));
            hi.iter()
                .zip(&lo)
                .map(|(a, b)| (a - b) / (2.0 * h))
                .collect()
        })
        .collect();
    (at(None, 0.0), grads)
}

/// Box and Hill's criterion with each equation's own prediction variance (a fit stores each
/// alternative's covariance): the first run is where the test's own evaluation of
/// `sum over pairs (v_a - v_b)^2 / (v_a v_b) + (y_a - y_b)^2 (1/v_a + 1/v_b)` is largest,
/// `v` the scatter plus each equation's `g^T C g` from its own covariance.
#[test]
fn each_equation_is_weighted_by_its_own_prediction_variance() {
    // a search's alternatives carry their covariance on the training rows
    let searched = fitted(0.05);
    let alts = &searched
        .correction
        .selection
        .as_ref()
        .expect("selection")
        .alternatives;
    assert!(!alts.is_empty(), "the noisy fixture has alternatives");
    for a in alts {
        let u = a
            .uncertainty
            .as_ref()
            .unwrap_or_else(|| panic!("{} has a covariance", a.sympy));
        assert_eq!(u.covariance.len(), u.params.len(), "{}", a.sympy);
    }

    let alt = "0.47*z + 0.31*x - 0.13";
    let mut m = model_with(0.05, alt);
    let t = table_with(0.05);
    let k = m.physics.parameters["k"];
    let (x, z, y) = (
        t.column("x").expect("the fixture"),
        t.column("z").expect("the fixture"),
        t.column("y").expect("the fixture"),
    );
    let delta: Vec<f64> = x.iter().zip(y).map(|(x, y)| y - k * x).collect();
    let features = Table::new(vec!["x".into(), "z".into()], vec![x.to_vec(), z.to_vec()])
        .expect("the fixture");
    let c = hxai_symreg::infix::compile_text(alt, &Default::default()).expect("the fixture");
    let am = hxai_symreg::Model {
        feature_names: c.inputs,
        program: c.program,
        params: c.params,
        complexity: 5,
        train_mse: f64::NAN,
        score: f64::NAN,
    };
    let ua = am
        .uncertainty(&features, &delta)
        .expect("the alternative's covariance");
    m.correction
        .selection
        .as_mut()
        .expect("the fixture")
        .alternatives[0]
        .uncertainty = Some(ua.clone());

    let space = parse_space("x=0:6,z=0:1").expect("space");
    let cand = candidates(&space, 11).expect("candidates").table;
    let p = design(&m, &cand, 1, DesignGoal::Discriminate).expect("design");
    assert_eq!(p.goal, DesignGoal::Discriminate);

    let s2 = m
        .hybrid
        .uncertainty
        .as_ref()
        .expect("the fixture")
        .residual_variance;
    let us = m
        .correction
        .uncertainty
        .as_ref()
        .expect("the correction's covariance");
    let phys: Vec<f64> = cand
        .column("x")
        .expect("the fixture")
        .iter()
        .map(|x| k * x)
        .collect();
    let variance = |u: &hxai_symreg::Uncertainty| {
        let (_, g) = prediction_and_gradient(u, &cand);
        let v: Vec<f64> = (0..cand.n_rows())
            .map(|i| {
                let gi: Vec<f64> = g.iter().map(|g| g[i]).collect();
                let mut q = 0.0;
                for (a, row) in u.covariance.iter().enumerate() {
                    for (b, cab) in row.iter().enumerate() {
                        q += gi[a] * cab * gi[b];
                    }
                }
                s2 + q.max(0.0)
            })
            .collect();
        v
    };
    let (vs, va) = (variance(us), variance(&ua));
    // the predictions: the selected hybrid's, and the physics plus the alternative as written
    let ys = m.predict(&cand).expect("predict").hybrid;
    let written = hxai_symreg::infix::compile_text(alt, &Default::default()).expect("the fixture");
    let cols: Vec<&[f64]> = written
        .inputs
        .iter()
        .map(|n| cand.column(n).expect("the fixture"))
        .collect();
    let ya: Vec<f64> = written
        .eval_columns(&cols, cand.n_rows())
        .iter()
        .zip(&phys)
        .map(|(d, p)| p + d)
        .collect();
    // the two equations' variances differ, so their own variances are what is tested
    let differ = (0..cand.n_rows()).any(|i| (vs[i] - va[i]).abs() > 0.01 * vs[i]);
    assert!(
        differ,
        "the fixture's equations have different prediction variances"
    );
    let worth: Vec<f64> = (0..cand.n_rows())
        .map(|i| {
            (vs[i] - va[i]).powi(2) / (vs[i] * va[i])
                + (ys[i] - ya[i]).powi(2) * (1.0 / vs[i] + 1.0 / va[i])
        })
        .collect();
    let best = (0..worth.len())
        .max_by(|&a, &b| worth[a].total_cmp(&worth[b]))
        .expect("the fixture");
    assert!(
        worth[p.rows[0]] >= worth[best] * (1.0 - 1e-9),
        "first run {} worth {} against the best {} worth {}",
        p.rows[0],
        worth[p.rows[0]],
        best,
        worth[best]
    );
}

/// A candidate where the model has no value (here the physics `k*sqrt(x)` at `x < 0`) is
/// left out and counted, the others are designed over, and the rows returned index the
/// candidates as given; a space where it has none is refused with one line.
#[test]
fn candidates_outside_the_models_domain_are_left_out() {
    let m = fitted_with(0.05, "k*sqrt(x)");
    let space = parse_space("x=-2:6,z=0:1").expect("space");
    let c = candidates(&space, 3).expect("candidates").table;
    let x = c.column("x").expect("x");
    let negative = x.iter().filter(|v| **v < 0.0).count();
    assert!(negative > 0);
    for goal in [
        DesignGoal::Discriminate,
        DesignGoal::Coverage,
        DesignGoal::Precision,
    ] {
        let p = design(&m, &c, 5, goal).expect("design");
        assert_eq!(p.rows.len(), 5);
        assert!(p.left_out >= negative, "{goal:?}: {} left out", p.left_out);
        for &i in &p.rows {
            assert!(x[i] >= 0.0, "{goal:?}: run at x = {}", x[i]);
        }
    }
    let outside = candidates(&parse_space("x=-3:-1,z=0:1").expect("space"), 3)
        .expect("candidates")
        .table;
    let e = design(&m, &outside, 5, DesignGoal::Coverage).expect_err("no value anywhere");
    assert!(e.to_string().contains("no finite value"), "{e}");
}
