//! Agreement of the conformal quantile and CV+ with numpy on vectors stored by
//! `scripts/ref_conformal.py` (the `k`-th smallest score as `np.quantile(..., method="higher")`
//! picks it). Both are order statistics of the inputs, so the tolerance is exact equality.

use hxai_eval::{EvalError, conformal_quantile, conformal_rank, cv_plus};
use serde::Deserialize;

type R = Result<(), Box<dyn std::error::Error>>;

#[derive(Deserialize)]
struct QuantileCase {
    scores: Vec<f64>,
    level: f64,
    rank: Option<usize>,
    quantile: Option<f64>,
}

#[derive(Deserialize)]
struct CvPlusCase {
    centre: Vec<f64>,
    radius: Vec<f64>,
    level: f64,
    lower: f64,
    upper: f64,
}

#[derive(Deserialize)]
struct Reference {
    quantiles: Vec<QuantileCase>,
    cv_plus: Vec<CvPlusCase>,
}

fn reference() -> Result<Reference, Box<dyn std::error::Error>> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/eval/conformal.json"
    );
    Ok(serde_json::from_str(&std::fs::read_to_string(path)?)?)
}

#[test]
fn conformal_quantile_matches_numpy_higher() -> R {
    let r = reference()?;
    assert!(r.quantiles.len() > 50);
    let mut finite = 0;
    for c in &r.quantiles {
        let n = c.scores.len();
        match (c.rank, c.quantile) {
            (Some(k), Some(q)) => {
                finite += 1;
                assert_eq!(conformal_rank(n, c.level)?, k, "n {n} level {}", c.level);
                assert_eq!(conformal_quantile(&c.scores, c.level)?, q);
            }
            _ => assert!(matches!(
                conformal_quantile(&c.scores, c.level),
                Err(EvalError::TooFewScores { .. })
            )),
        }
    }
    // both kinds of case are present
    assert!(finite > 0 && finite < r.quantiles.len());
    Ok(())
}

#[test]
fn cv_plus_matches_numpy() -> R {
    let r = reference()?;
    assert!(!r.cv_plus.is_empty());
    for c in &r.cv_plus {
        let (lo, hi) = cv_plus(&c.centre, &c.radius, c.level)?;
        assert_eq!(
            (lo, hi),
            (c.lower, c.upper),
            "n {} level {}",
            c.centre.len(),
            c.level
        );
    }
    Ok(())
}
