//! Agreement with scikit-learn and scipy on vectors stored by `scripts/ref_eval.py`.
//! Tolerance everywhere: 1e-10 relative (plus 1e-300 absolute so exact zeros compare).

use approx::assert_relative_eq;
use serde::Deserialize;

type R = Result<(), Box<dyn std::error::Error>>;

#[derive(Deserialize)]
struct MetricCase {
    y_true: Vec<f64>,
    y_pred: Vec<f64>,
    r2: f64,
    rmse: f64,
    mae: f64,
}
#[derive(Deserialize)]
struct TTestCase {
    a: Vec<f64>,
    b: Vec<f64>,
    statistic: f64,
    df: f64,
    p_value: f64,
}
#[derive(Deserialize)]
struct PCase {
    t: f64,
    df: f64,
    p_value: f64,
}
#[derive(Deserialize)]
struct IntervalCase {
    values: Vec<f64>,
    level: f64,
    mean: f64,
    std: f64,
    t: [f64; 2],
    normal: [f64; 2],
}
#[derive(Deserialize)]
struct Reference {
    metrics: Vec<MetricCase>,
    ttests: Vec<TTestCase>,
    t_pvalues: Vec<PCase>,
    intervals: Vec<IntervalCase>,
}

fn load() -> Result<Reference, Box<dyn std::error::Error>> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/eval/reference.json"
    );
    Ok(serde_json::from_str(&std::fs::read_to_string(path)?)?)
}

const REL: f64 = 1e-10;

#[test]
fn metrics_match_sklearn() -> R {
    for c in load()?.metrics {
        assert_relative_eq!(
            hxai_eval::r2(&c.y_true, &c.y_pred)?,
            c.r2,
            max_relative = REL
        );
        assert_relative_eq!(
            hxai_eval::rmse(&c.y_true, &c.y_pred)?,
            c.rmse,
            max_relative = REL
        );
        assert_relative_eq!(
            hxai_eval::mae(&c.y_true, &c.y_pred)?,
            c.mae,
            max_relative = REL
        );
    }
    Ok(())
}

#[test]
fn paired_t_test_matches_scipy_ttest_rel() -> R {
    let cases = load()?.ttests;
    // The stored cases must reach p-values below 1e-12, otherwise this test proves little.
    assert!(cases.iter().any(|c| c.p_value < 1e-12));
    for c in cases {
        let t = hxai_eval::paired_t_test(&c.a, &c.b)?;
        assert_relative_eq!(t.statistic, c.statistic, max_relative = REL);
        assert_eq!(t.df, c.df);
        assert_relative_eq!(t.p_value, c.p_value, max_relative = REL, epsilon = 1e-300);
    }
    Ok(())
}

#[test]
fn two_tailed_p_values_match_scipy_down_to_tiny_values() -> R {
    for c in load()?.t_pvalues {
        let p = hxai_eval::t_two_tailed_p(c.t, c.df);
        assert_relative_eq!(p, c.p_value, max_relative = REL, epsilon = 1e-300);
    }
    Ok(())
}

#[test]
fn intervals_match_scipy_t_and_norm_interval() -> R {
    for c in load()?.intervals {
        let s = hxai_eval::summarize_at(&c.values, c.level)?;
        assert_relative_eq!(s.mean, c.mean, max_relative = REL);
        assert_relative_eq!(s.std, c.std, max_relative = REL);
        assert_relative_eq!(s.ci_t.lower, c.t[0], max_relative = REL);
        assert_relative_eq!(s.ci_t.upper, c.t[1], max_relative = REL);
        assert_relative_eq!(s.ci_normal.lower, c.normal[0], max_relative = REL);
        assert_relative_eq!(s.ci_normal.upper, c.normal[1], max_relative = REL);
    }
    Ok(())
}
