//! The numbers behind the pictures of `hxai explain`: how a symbolic correction responds to
//! each feature it uses, how its predictions compare with the truth, and the Pareto front
//! it was chosen from. Drawing them is another crate's work (`hxai-plot`); this module
//! only computes.
//!
//! # Design decision: the data comes with the call, the front with the model
//! The response curves and the predicted-vs-true picture need the rows the correction was
//! fitted on (the points, and the medians the other features are held at). A model file of
//! the tool case would grow by twelve features times every window if it stored them, so it
//! does not: the caller passes them ([`ExplainData`], in the command line the samples table
//! `hxai fit --samples` writes). The Pareto front is small (one line per complexity), so
//! the model file stores it ([`ParetoMember`], key `correction.pareto`).
//!
//! # Design decision: the band comes from the model file's interval method
//! The prediction intervals drawn are those `predict` and `evaluate` give: the caller passes
//! a [`Band`], the intervals of the correction by the chosen method (conformal by default,
//! split or the delta method), so the pictures show the band a user is promised elsewhere.

use crate::{HybridError, IntervalMethod};
use hxai_symreg::Model;
use hxai_table::Table;
use serde::{Deserialize, Serialize};

/// The prediction intervals `(lo, hi)` of the correction at a level for every row of a table
/// of the features (the response grid, or the data's rows), by one interval method. A row
/// where the method gives no finite interval (outside the equation's domain) is `(NaN,
/// NaN)`.
pub type Band<'a> = dyn Fn(&Table, f64) -> Result<Vec<(f64, f64)>, HybridError> + 'a;

/// Points of each response curve spread evenly over the feature's range in the data (the
/// median is added to them).
pub const RESPONSE_POINTS: usize = 101;

/// One member of the Pareto front of a search, as stored in a model file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParetoMember {
    /// Complexity (the search's measure).
    pub complexity: usize,
    /// Mean squared error on the training rows.
    pub loss: f64,
    /// Plain-text equation.
    pub equation: String,
}

impl ParetoMember {
    /// The stored form of a search's front (`hxai_symreg::SearchResult::pareto`); members
    /// without a finite loss are left out.
    pub fn front(models: &[Model]) -> Vec<Self> {
        models
            .iter()
            .filter(|m| m.train_mse.is_finite())
            .map(|m| Self {
                complexity: m.complexity(),
                loss: m.train_mse,
                equation: m.equation(),
            })
            .collect()
    }
}

/// The rows an explanation draws: feature columns (every feature the model reads), the
/// correction's target, and which rows were held out.
#[derive(Debug, Clone, Copy)]
pub struct ExplainData<'a> {
    /// Feature columns (extra columns are ignored).
    pub features: &'a Table,
    /// The true target of each row (`delta`).
    pub target: &'a [f64],
    /// Whether each row is on the test side (all `false` when unknown).
    pub is_test: &'a [bool],
}

/// The response of the correction to one feature, the others held at their median.
#[derive(Debug, Clone, PartialEq)]
pub struct Response {
    /// The feature varied.
    pub feature: String,
    /// Its median on the training rows (one of the [`Response::grid`] values).
    pub median: f64,
    /// Feature values, increasing, spanning the data's range.
    pub grid: Vec<f64>,
    /// The correction at each grid value.
    pub curve: Vec<f64>,
    /// Its prediction interval `(lo, hi)` at each grid value (NaN where the equation or its
    /// gradient is undefined), when the model stores the uncertainty of its constants.
    pub band: Option<Vec<(f64, f64)>>,
    /// `(feature value, target)` of the training rows.
    pub train: Vec<(f64, f64)>,
    /// `(feature value, target)` of the test rows.
    pub test: Vec<(f64, f64)>,
}

/// Predicted vs true target.
#[derive(Debug, Clone, PartialEq)]
pub struct Parity {
    /// `(true, predicted)` of the training rows.
    pub train: Vec<(f64, f64)>,
    /// `(true, predicted)` of the test rows.
    pub test: Vec<(f64, f64)>,
    /// `(true, lo, hi)`: the prediction interval of the test rows (of every row when none is
    /// held out), when the model stores the uncertainty of its constants.
    pub intervals: Option<Vec<(f64, f64, f64)>>,
}

/// The Pareto front with the selected model marked.
#[derive(Debug, Clone, PartialEq)]
pub struct Front {
    /// The members, by increasing complexity.
    pub members: Vec<ParetoMember>,
    /// `(complexity, loss)` of the selected model (which need not lie on the front: the
    /// criterion chooses among every refitted candidate).
    pub selected: (usize, f64),
}

/// Everything the explanation pictures show.
#[derive(Debug, Clone, PartialEq)]
pub struct Explanation {
    /// Name of the target (`delta`).
    pub target: String,
    /// Level of the intervals (e.g. 0.95).
    pub level: f64,
    /// The method of the intervals drawn (absent when none are).
    pub method: Option<IntervalMethod>,
    /// The selected equation.
    pub equation: String,
    /// One response per feature the equation uses, in first-use order (empty without data).
    pub responses: Vec<Response>,
    /// Predicted vs true (absent without data).
    pub parity: Option<Parity>,
    /// The Pareto front (absent when the model file does not store it).
    pub front: Option<Front>,
    /// A factor correction's response band per column over its stability runs (the model
    /// file's `stability.bands`, issue 46): the 5-95 % spread and the median of each
    /// factor's normalised response on a grid of its column. Empty otherwise.
    pub factors: Vec<(String, hxai_symreg::factors::FactorBand)>,
    /// A factor correction's partial residuals per one-column factor, drawn on the data
    /// given: `(x, r)` for each training row, `r` the factor's normalised value there
    /// carrying the row's whole residual (a product's factor over its mean on the training
    /// rows times the row's observed over fitted ratio; a sum's term minus its mean plus
    /// the row's residual), what EBM's and feyn's shape plots draw beside the curve. Empty
    /// without data or factors.
    pub partial_residuals: PartialResiduals,
}

/// Per one-column factor, its column and the `(x, r)` points of its partial residuals
/// ([`Explanation::partial_residuals`]).
pub type PartialResiduals = Vec<(String, Vec<(f64, f64)>)>;

/// Median of finite values (mean of the middle two for an even count); `None` when empty.
/// By selection, not a sort (issue 67: `predict`'s value checks took a median of every
/// column four times, 40 % of a 10^6-row prediction); the values are those of a sort.
pub fn median(values: impl IntoIterator<Item = f64>) -> Option<f64> {
    let mut v: Vec<f64> = values.into_iter().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    let n = v.len();
    let (below, &mut mid, _) = v.select_nth_unstable_by(n / 2, f64::total_cmp);
    Some(if n % 2 == 1 {
        mid
    } else {
        // the largest of the lower half: the sorted order's element n/2 - 1
        let lower = below.iter().copied().max_by(f64::total_cmp).unwrap_or(mid);
        0.5 * (lower + mid)
    })
}

#[cfg(test)]
mod median_tests {
    /// The selection's median is the sorted list's, for odd and even counts, with ties
    /// and values that are not numbers left out.
    #[test]
    fn the_median_is_the_sorted_lists() {
        for n in 1..40usize {
            let v: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
            let mut s = v.clone();
            s.sort_by(f64::total_cmp);
            let want = if n % 2 == 1 {
                s[n / 2]
            } else {
                0.5 * (s[n / 2 - 1] + s[n / 2])
            };
            let mut with_nan = v.clone();
            with_nan.push(f64::NAN);
            assert_eq!(super::median(v), Some(want));
            assert_eq!(super::median(with_nan), Some(want));
        }
        assert_eq!(super::median(Vec::new()), None);
    }
}

fn check_data(model: &Model, data: &ExplainData<'_>) -> Result<(), HybridError> {
    let n = data.features.n_rows();
    if data.target.len() != n || data.is_test.len() != n {
        return Err(HybridError::InvalidConfig(format!(
            "{n} rows of features, {} targets and {} split flags",
            data.target.len(),
            data.is_test.len()
        )));
    }
    for name in &model.feature_names {
        data.features.require(name)?;
    }
    Ok(())
}

/// Prediction intervals of every row of `table` by `band`, `(NaN, NaN)` where the model or
/// its gradient is not finite (a response curve can leave the equation's domain where the
/// data never go): when the whole table fails, each row is tried alone, and only when every
/// row fails is the first error returned (a model that cannot serve the method at all).
fn intervals(band: &Band<'_>, table: &Table, level: f64) -> Result<Vec<(f64, f64)>, HybridError> {
    let whole = match band(table, level) {
        Ok(v) => return Ok(v),
        Err(e) => e,
    };
    let mut out = Vec::with_capacity(table.n_rows());
    let mut any = false;
    for i in 0..table.n_rows() {
        let row = table.select_rows(&[i])?;
        match band(&row, level) {
            Ok(v) => {
                any = true;
                out.push(v.first().copied().unwrap_or((f64::NAN, f64::NAN)));
            }
            Err(_) => out.push((f64::NAN, f64::NAN)),
        }
    }
    if any { Ok(out) } else { Err(whole) }
}

/// The training rows' indices (every row when all are held out or the split is unknown).
fn fitting_rows(is_test: &[bool]) -> Vec<usize> {
    let train: Vec<usize> = (0..is_test.len()).filter(|&i| !is_test[i]).collect();
    if train.is_empty() {
        (0..is_test.len()).collect()
    } else {
        train
    }
}

/// The response of `model` to `feature`: a grid over the feature's range in `data` (plus its
/// median), every other feature the model reads at its median on the training rows, the
/// model's prediction on it and, with `band`, its prediction interval at `level`.
///
/// # Errors
/// [`HybridError::InvalidConfig`] for data of mismatched lengths or without rows,
/// [`HybridError::Table`] for a missing feature column, and the model's errors (a `level`
/// outside (0, 1) among them).
pub fn response(
    model: &Model,
    band: Option<&Band<'_>>,
    data: &ExplainData<'_>,
    feature: &str,
    level: f64,
) -> Result<Response, HybridError> {
    check_data(model, data)?;
    let fit_rows = fitting_rows(data.is_test);
    let med = |name: &str| -> Result<f64, HybridError> {
        let col = data.features.require(name)?;
        median(fit_rows.iter().map(|&i| col[i]))
            .ok_or_else(|| HybridError::NoData("no rows to explain the correction on".into()))
    };
    let x = data.features.require(feature)?;
    let (lo, hi) = x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let m = med(feature)?;
    let mut grid: Vec<f64> = if hi > lo {
        (0..RESPONSE_POINTS)
            .map(|k| lo + (hi - lo) * k as f64 / (RESPONSE_POINTS - 1) as f64)
            .collect()
    } else {
        Vec::new()
    };
    grid.push(m);
    grid.sort_by(f64::total_cmp);
    grid.dedup();
    let mut names = Vec::new();
    let mut columns = Vec::new();
    for name in &model.feature_names {
        names.push(name.clone());
        columns.push(if name == feature {
            grid.clone()
        } else {
            vec![med(name)?; grid.len()]
        });
    }
    let table = Table::new(names, columns)?;
    let curve = model.predict(&table)?;
    let band = band.map(|b| intervals(b, &table, level)).transpose()?;
    let (mut train, mut test) = (Vec::new(), Vec::new());
    for (i, (&v, &t)) in x.iter().zip(data.target).enumerate() {
        if data.is_test[i] {
            test.push((v, t));
        } else {
            train.push((v, t));
        }
    }
    Ok(Response {
        feature: feature.to_owned(),
        median: m,
        grid,
        curve,
        band,
        train,
        test,
    })
}

/// Predicted vs true target on `data`, with the prediction intervals at `level` of the test
/// rows (of every row when none is held out) when `band` is given.
///
/// # Errors
/// As [`response`].
pub fn parity(
    model: &Model,
    band: Option<&Band<'_>>,
    data: &ExplainData<'_>,
    level: f64,
) -> Result<Parity, HybridError> {
    check_data(model, data)?;
    let pred = model.predict(data.features)?;
    let (mut train, mut test) = (Vec::new(), Vec::new());
    for (i, (&t, &p)) in data.target.iter().zip(&pred).enumerate() {
        if data.is_test[i] {
            test.push((t, p));
        } else {
            train.push((t, p));
        }
    }
    let intervals = match band {
        Some(b) => {
            let any_test = data.is_test.iter().any(|&t| t);
            let iv = intervals(b, data.features, level)?;
            Some(
                iv.into_iter()
                    .zip(data.target)
                    .zip(data.is_test)
                    .filter(|(_, t)| !any_test || **t)
                    .map(|(((lo, hi), &y), _)| (y, lo, hi))
                    .collect(),
            )
        }
        None => None,
    };
    Ok(Parity {
        train,
        test,
        intervals,
    })
}

/// The whole explanation of a symbolic correction: a [`response`] for each feature the
/// equation uses and the [`parity`] when `data` is given, and the front when `pareto` is.
/// `band` gives the intervals drawn and names their method. `target` names the
/// correction's target in the pictures.
///
/// # Errors
/// As [`response`].
pub fn explain(
    model: &Model,
    band: Option<(&Band<'_>, IntervalMethod)>,
    pareto: Option<&[ParetoMember]>,
    data: Option<&ExplainData<'_>>,
    target: &str,
    level: f64,
) -> Result<Explanation, HybridError> {
    if !(level > 0.0 && level < 1.0) {
        return Err(HybridError::InvalidConfig(format!(
            "the interval level must lie strictly between 0 and 1, got {level}"
        )));
    }
    let b = band.map(|(b, _)| b);
    let (responses, parity) = match data {
        Some(d) => (
            model
                .features()
                .iter()
                .map(|f| response(model, b, d, f, level))
                .collect::<Result<Vec<_>, _>>()?,
            Some(parity(model, b, d, level)?),
        ),
        None => (Vec::new(), None),
    };
    Ok(Explanation {
        target: target.to_owned(),
        level,
        method: band.map(|(_, m)| m),
        equation: model.equation(),
        responses,
        parity,
        front: pareto.map(|members| Front {
            members: members.to_vec(),
            selected: (model.complexity(), model.train_mse),
        }),
        factors: Vec::new(),
        partial_residuals: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use hxai_symreg::{SearchConfig, Uncertainty, search};

    /// The delta method's band of `m` with `u`, as the tool case's model file gives it.
    fn delta_band<'a>(
        m: &'a Model,
        u: &'a Uncertainty,
    ) -> impl Fn(&Table, f64) -> Result<Vec<(f64, f64)>, HybridError> + 'a {
        move |t: &Table, level: f64| Ok(m.prediction_intervals(u, t, level)?)
    }

    /// `y = 2 x0 + 0.5 x1^2`-like data with a little deterministic noise; x2 is unused.
    fn case() -> (Table, Vec<f64>, Vec<bool>) {
        let n = 60;
        let x0: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin() * 3.0).collect();
        let x1: Vec<f64> = (0..n)
            .map(|i| (i as f64 * 0.11).cos() * 2.0 + 1.0)
            .collect();
        let x2: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let y: Vec<f64> = (0..n)
            .map(|i| 2.0 * x0[i] + 0.5 * x1[i] + 0.05 * ((i * 7 % 11) as f64 - 5.0))
            .collect();
        let is_test = (0..n).map(|i| i % 5 == 0).collect();
        let t = Table::new(
            vec!["x0".into(), "x1".into(), "x2".into()],
            vec![x0, x1, x2],
        )
        .unwrap();
        (t, y, is_test)
    }

    fn fitted() -> (Model, Uncertainty, Table, Vec<f64>, Vec<bool>) {
        let (t, y, is_test) = case();
        let cfg = SearchConfig {
            epochs: 2,
            seed: 3,
            ..SearchConfig::paper()
        };
        let r = search(&t, &y, &cfg, &mut |_| {}).unwrap();
        let u = r.best.uncertainty(&t, &y).unwrap();
        (r.best, u, t, y, is_test)
    }

    #[test]
    fn the_curve_at_the_median_is_the_model_at_the_medians_and_the_band_holds_it() {
        let (m, u, t, y, is_test) = fitted();
        let data = ExplainData {
            features: &t,
            target: &y,
            is_test: &is_test,
        };
        let b = delta_band(&m, &u);
        let e = explain(
            &m,
            Some((&b, IntervalMethod::Delta)),
            None,
            Some(&data),
            "y",
            0.95,
        )
        .unwrap();
        assert_eq!(e.method, Some(IntervalMethod::Delta));
        assert_eq!(e.responses.len(), m.features().len());
        assert!(!e.responses.is_empty());
        let train: Vec<usize> = (0..y.len()).filter(|&i| !is_test[i]).collect();
        let med = |name: &str| median(train.iter().map(|&i| t.column(name).unwrap()[i])).unwrap();
        for r in &e.responses {
            assert!(r.grid.windows(2).all(|w| w[0] < w[1]));
            let k = r.grid.iter().position(|&g| g == r.median).unwrap();
            let row = Table::new(
                m.feature_names.clone(),
                m.feature_names.iter().map(|n| vec![med(n)]).collect(),
            )
            .unwrap();
            let at_medians = m.predict(&row).unwrap()[0];
            // the same expression on the same inputs: equal to rounding
            assert!(
                (r.curve[k] - at_medians).abs() <= 1e-12 * at_medians.abs().max(1.0),
                "{} vs {at_medians}",
                r.curve[k]
            );
            let band = r.band.as_ref().unwrap();
            assert_eq!(band.len(), r.grid.len());
            for (c, (lo, hi)) in r.curve.iter().zip(band) {
                assert!(lo < c && c < hi, "{lo} < {c} < {hi}");
            }
            assert_eq!(r.train.len() + r.test.len(), y.len());
            assert_eq!(r.test.len(), 12);
        }
        let p = e.parity.unwrap();
        assert_eq!((p.train.len(), p.test.len()), (48, 12));
        let iv = p.intervals.unwrap();
        assert_eq!(iv.len(), 12);
        // a 95 % interval of a model this good holds most of its test rows
        let inside = iv.iter().filter(|(y, lo, hi)| lo <= y && y <= hi).count();
        assert!(inside >= 9, "{inside} of 12 inside");
    }

    #[test]
    fn without_data_only_the_front_is_explained() {
        let (m, _, _, _, _) = fitted();
        let front = vec![ParetoMember {
            complexity: 1,
            loss: 2.0,
            equation: "x0".into(),
        }];
        let e = explain(&m, None, Some(&front), None, "y", 0.9).unwrap();
        assert!(e.responses.is_empty() && e.parity.is_none());
        let f = e.front.unwrap();
        assert_eq!(f.members, front);
        assert_eq!(f.selected, (m.complexity(), m.train_mse));
        assert!(explain(&m, None, None, None, "y", 1.0).is_err());
    }

    #[test]
    fn mismatched_or_incomplete_data_is_an_error() {
        let (m, u, t, y, is_test) = fitted();
        let short = ExplainData {
            features: &t,
            target: &y[1..],
            is_test: &is_test,
        };
        let b = delta_band(&m, &u);
        assert!(
            explain(
                &m,
                Some((&b, IntervalMethod::Delta)),
                None,
                Some(&short),
                "y",
                0.95
            )
            .is_err()
        );
        let other = Table::new(vec!["z".into()], vec![vec![0.0; y.len()]]).unwrap();
        let missing = ExplainData {
            features: &other,
            target: &y,
            is_test: &is_test,
        };
        assert!(matches!(
            parity(&m, None, &missing, 0.95),
            Err(HybridError::Table(_))
        ));
    }

    // A band that fails on some rows (outside the equation's domain) draws NaN there and the
    // interval elsewhere; one that fails everywhere (a model that cannot serve the method)
    // is an error, not an empty band.
    #[test]
    fn a_band_is_nan_where_undefined_and_an_error_where_impossible() {
        let t = Table::new(vec!["x".into()], vec![vec![1.0, -1.0, 4.0]]).unwrap();
        let sqrt_band = |t: &Table, _: f64| -> Result<Vec<(f64, f64)>, HybridError> {
            let x = t.require("x")?;
            if x.iter().any(|&v| v < 0.0) {
                return Err(HybridError::InvalidConfig("negative".into()));
            }
            Ok(x.iter().map(|v| (v.sqrt() - 0.1, v.sqrt() + 0.1)).collect())
        };
        let iv = intervals(&sqrt_band, &t, 0.95).unwrap();
        assert_eq!(iv[0], (0.9, 1.1));
        assert!(iv[1].0.is_nan() && iv[1].1.is_nan());
        assert_eq!(iv[2], (1.9, 2.1));
        let never = |_: &Table, _: f64| -> Result<Vec<(f64, f64)>, HybridError> {
            Err(HybridError::InvalidConfig("no calibration".into()))
        };
        let e = intervals(&never, &t, 0.95).unwrap_err();
        assert!(e.to_string().contains("no calibration"), "{e}");
    }

    #[test]
    fn median_of_odd_even_and_empty() {
        assert_eq!(median([3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median([4.0, 1.0, 2.0, 3.0]), Some(2.5));
        assert_eq!(median([f64::NAN]), None);
    }
}
