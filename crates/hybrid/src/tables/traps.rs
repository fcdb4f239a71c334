//! Warnings for the traps of a table fit: input that is legal and gives numbers, but numbers
//! that do not mean what they seem to (issue 27 item 4). They are stored with the model
//! (`TableModel::warnings`, JSON `warnings`) and printed by the command line on stderr;
//! nothing here refuses anything.
//!
//! - a feature column that nearly copies the target (the correction can then reproduce the
//!   target without any physics, and the scores say nothing about the process);
//! - test rows that repeat training rows (the test scores then measure recall, not
//!   prediction);
//! - a physics that changes sign on the training rows under a multiplicative correction
//!   (`y / f_p - 1` has a pole where `f_p` crosses zero);
//! - an extrapolation column with few distinct values (the split's "high end" is then one
//!   or two settings, not a range);
//! - a test split of one row (no test scores are given: R² needs two);
//! - a target that is constant on the training rows (the correction can then only cancel
//!   the physics, and a hybrid R² of 1 means nothing);
//! - calibrated parameters without a standard error, or with one a hundred times their
//!   value (the data cannot tell them apart, as `a` and `b` in `a*b*x`: only their product
//!   is fitted);
//! - at prediction, rows outside the training ranges ([`range_warnings`]).

use super::{CorrectionForm, TableConfig};
use crate::error::num;
use hxai_eval::Split;
use hxai_symreg::Table;
use std::collections::HashSet;

/// A feature whose correlation with the target is at least this (in absolute value) on the
/// training rows is taken for a copy of it.
pub const COPY_CORRELATION: f64 = 0.9999;

/// An extrapolation column with fewer distinct values than this gets a warning.
pub const MIN_EXTRAPOLATION_VALUES: usize = 5;

/// The warnings of a fit on `split` of `table` (see the module docs): `features` are the
/// correction's candidate columns, `physics` the physics' prediction on every row.
pub(crate) fn fit_warnings(
    table: &Table,
    cfg: &TableConfig,
    features: &[String],
    split: &Split,
    y: &[f64],
    physics: &[f64],
) -> Vec<String> {
    let mut out = Vec::new();
    if split.test.len() == 1 {
        out.push(
            "the test split has 1 row: R² needs at least 2, so the model has no test scores; \
             raise --test-fraction"
                .to_string(),
        );
    }
    let train_y: Vec<f64> = split.train.iter().map(|&i| y[i]).collect();
    if let Some(&first) = train_y.first()
        && train_y.iter().all(|&v| v == first)
    {
        out.push(format!(
            "the target `{}` is constant on the training rows ({}): the correction can only \
             cancel the physics, and the hybrid's scores say nothing about the process",
            cfg.target,
            num(first)
        ));
    }
    for name in features {
        let Some(col) = table.column(name) else {
            continue;
        };
        let x: Vec<f64> = split.train.iter().map(|&i| col[i]).collect();
        if let Some(r) = correlation(&x, &train_y)
            && r.abs() >= COPY_CORRELATION
        {
            out.push(format!(
                "column `{name}` nearly copies the target `{}` (correlation {} on the training \
                 rows): the correction can reproduce the target from it alone; leave it out with \
                 --exclude {name} unless it is a measurement of the process",
                cfg.target,
                num(r)
            ));
        }
    }
    if !split.test.is_empty() {
        let mut used: Vec<&[f64]> = features.iter().filter_map(|n| table.column(n)).collect();
        used.push(y);
        let pick = |rows: &[usize]| -> Vec<Vec<f64>> {
            used.iter()
                .map(|c| rows.iter().map(|&i| c[i]).collect())
                .collect()
        };
        let (train, test) = (pick(&split.train), pick(&split.test));
        let train: Vec<&[f64]> = train.iter().map(Vec::as_slice).collect();
        let test: Vec<&[f64]> = test.iter().map(Vec::as_slice).collect();
        let shared = hxai_eval::shared_rows(&train, &test);
        if shared > 0 {
            out.push(format!(
                "{shared} of the {} test rows repeat a training row (every feature and the \
                 target equal): the test scores overstate how well the model predicts new rows",
                split.test.len()
            ));
        }
    }
    if cfg.correction == CorrectionForm::Multiplicative {
        let (neg, pos) = split.train.iter().fold((0, 0), |(n, p), &i| {
            (
                n + usize::from(physics[i] < 0.0),
                p + usize::from(physics[i] > 0.0),
            )
        });
        if neg > 0 && pos > 0 {
            out.push(format!(
                "the physics changes sign on the training rows ({neg} negative, {pos} positive): \
                 the multiplicative correction y / f_p - 1 has a pole where f_p crosses zero; \
                 use --correction additive"
            ));
        }
    }
    if let Some(e) = &cfg.extrapolate
        && let Some(col) = table.column(e)
    {
        let distinct: HashSet<u64> = col.iter().map(|v| (v + 0.0).to_bits()).collect();
        if distinct.len() < MIN_EXTRAPOLATION_VALUES {
            out.push(format!(
                "the extrapolation column `{e}` has {} distinct values: its test side is one or \
                 a few settings, not a range beyond the training rows",
                distinct.len()
            ));
        }
    }
    out
}

/// A calibrated parameter whose standard error exceeds its value this many times is taken
/// as not determined by the data.
pub const UNDETERMINED_RELATIVE_SE: f64 = 100.0;

/// A warning naming the calibrated parameters the data do not determine: no standard error
/// (a singular Jacobian) or one above [`UNDETERMINED_RELATIVE_SE`] times the value (nearly
/// singular: the data fix a combination of them, as the product in `a*b*x`, not each).
pub(crate) fn parameter_warnings(
    standard_errors: &std::collections::BTreeMap<String, Option<f64>>,
    values: &std::collections::BTreeMap<String, f64>,
) -> Vec<String> {
    let undetermined: Vec<&str> = standard_errors
        .iter()
        .filter(|(n, se)| match se {
            None => true,
            Some(se) => {
                let v = values.get(*n).copied().unwrap_or(0.0).abs();
                *se > UNDETERMINED_RELATIVE_SE * v
            }
        })
        .map(|(n, _)| n.as_str())
        .collect();
    if undetermined.is_empty() {
        return Vec::new();
    }
    let why = format!(
        "no standard error, or one over {} times the value",
        num(UNDETERMINED_RELATIVE_SE)
    );
    if standard_errors.len() == 1 {
        return vec![format!(
            "the data do not determine the calibrated parameter {} ({why}): check that the \
             physics depends on it over the training rows",
            undetermined.join(", ")
        )];
    }
    vec![format!(
        "the data cannot tell the calibrated parameter(s) {} apart from the others ({why}: \
         only a combination of them is determined, e.g. the product in a*b*x); calibrate fewer \
         and --set the rest",
        undetermined.join(", ")
    )]
}

/// Rows below which the residuals' shape is not judged: a spread or a tail needs some.
const ASSUMPTION_ROWS: usize = 20;

/// Spearman correlation of the residuals' size with the prediction above which the scatter
/// is said to grow (with its t statistic above [`ASSUMPTION_T`]).
const SCATTER_RHO: f64 = 0.3;

/// t statistic of that correlation above which it is not chance (two-sided p about 0.01).
const ASSUMPTION_T: f64 = 2.6;

/// Excess kurtosis of the residuals above which their tails are called heavy (a normal
/// sample of 20 rows passes 3 in about 1 % of draws; a t with 5 degrees of freedom has 6).
const HEAVY_TAILS: f64 = 3.0;

/// Where the intervals' assumptions fail (issue 64), from the hybrid's residuals on the
/// training rows (`y`, `pred`) and whether the split extrapolates: a scatter that grows
/// with the prediction and heavy tails break the delta method's constant normal scatter
/// (`--interval-method delta`; the conformal default scales its scores by the prediction
/// and assumes no shape); an extrapolation split breaks the exchangeability every method
/// assumes (the test rows are not like the training rows).
/// `additive`: the correction is additive, so a relative one is worth suggesting.
pub(crate) fn interval_warnings(
    y: &[f64],
    pred: &[f64],
    extrapolate: bool,
    additive: bool,
) -> Vec<String> {
    let mut out = Vec::new();
    if extrapolate {
        out.push(
            "the test rows lie outside the training rows' range (--extrapolate): every \
             interval method assumes new rows like the training rows, so the intervals' \
             coverage there is not guaranteed (the evaluation's `interval` measures it)"
                .to_string(),
        );
    }
    let r: Vec<f64> = y.iter().zip(pred).map(|(a, b)| a - b).collect();
    if r.len() < ASSUMPTION_ROWS || r.iter().any(|v| !v.is_finite()) {
        return out;
    }
    let n = r.len() as f64;
    let size: Vec<f64> = r.iter().map(|v| v.abs()).collect();
    if let Some(rho) = correlation(&ranks(&size), &ranks(pred)) {
        let t = rho * ((n - 2.0) / (1.0 - rho * rho).max(1e-12)).sqrt();
        if rho > SCATTER_RHO && t > ASSUMPTION_T {
            out.push(format!(
                "the residuals grow with the prediction (Spearman {:.2} between their size and \
                 the prediction on the training rows): intervals of --interval-method delta \
                 assume a constant scatter and are too narrow at large values; the conformal \
                 default scales with the prediction{}",
                rho,
                if additive {
                    ", or try --correction multiplicative"
                } else {
                    ""
                }
            ));
        }
    }
    let mean = r.iter().sum::<f64>() / n;
    let m2 = r.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    let m4 = r.iter().map(|v| (v - mean).powi(4)).sum::<f64>() / n;
    let kurtosis = m4 / (m2 * m2) - 3.0;
    if m2 > 0.0 && kurtosis > HEAVY_TAILS {
        out.push(format!(
            "the residuals have heavy tails (excess kurtosis {kurtosis:.1} on the training \
             rows, 0 for normal errors): intervals of --interval-method delta assume normal \
             errors and miss the outlying rows; the conformal default does not assume a shape"
        ));
    }
    out
}

/// The ranks of `v` (1 for the smallest; ties get the mean of their ranks).
fn ranks(v: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..v.len()).collect();
    order.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
    let mut out = vec![0.0; v.len()];
    let mut i = 0;
    while i < order.len() {
        let mut j = i;
        while j + 1 < order.len() && v[order[j + 1]] == v[order[i]] {
            j += 1;
        }
        let rank = (i + j) as f64 / 2.0 + 1.0;
        for &k in &order[i..=j] {
            out[k] = rank;
        }
        i = j + 1;
    }
    out
}

/// Pearson's correlation of two equally long series (`None` when either is constant).
fn correlation(x: &[f64], y: &[f64]) -> Option<f64> {
    let n = x.len() as f64;
    if x.len() < 2 || x.len() != y.len() {
        return None;
    }
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x.iter().zip(y) {
        sxy += (a - mx) * (b - my);
        sxx += (a - mx) * (a - mx);
        syy += (b - my) * (b - my);
    }
    let r = sxy / (sxx * syy).sqrt();
    r.is_finite().then_some(r)
}

/// Warnings for rows of `table` outside the ranges the model was fitted on: per column of
/// `ranges` (name, smallest and largest training value), how many rows lie outside and how
/// far the farthest does, in widths of the training range. A prediction there is an
/// extrapolation of the correction (and a value in other units, mm for µm, looks like one).
pub fn range_warnings(table: &Table, ranges: &[(String, f64, f64)]) -> Vec<String> {
    let mut out = Vec::new();
    for (name, lo, hi) in ranges {
        let Some(col) = table.column(name) else {
            continue;
        };
        let width = hi - lo;
        let mut outside = 0;
        let mut farthest: f64 = 0.0;
        for &v in col {
            let d = (lo - v).max(v - hi);
            if d > 0.0 {
                outside += 1;
                farthest = farthest.max(d);
            }
        }
        if outside > 0 {
            let how_far = if width > 0.0 {
                format!("{} widths of the training range", num(farthest / width))
            } else {
                format!("{} from its one training value", num(farthest))
            };
            out.push(format!(
                "{outside} of {} rows have `{name}` outside its training range [{}, {}], the \
                 farthest by {how_far}: the correction is extrapolated there (are the units \
                 those of the training table?)",
                col.len(),
                num(*lo),
                num(*hi)
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn correlation_of_a_copy_a_line_and_a_constant() {
        let x = [1.0, 2.0, 3.0, 4.0];
        assert!((correlation(&x, &[2.0, 4.0, 6.0, 8.0]).unwrap() - 1.0).abs() < 1e-15);
        assert!((correlation(&x, &[-1.0, -2.0, -3.0, -4.0]).unwrap() + 1.0).abs() < 1e-15);
        assert!(correlation(&x, &[5.0; 4]).is_none());
    }

    /// Residuals of constant normal-like scatter give no warning; scatter in proportion to
    /// the prediction, heavy tails and an extrapolation split each give theirs.
    #[test]
    fn the_intervals_assumptions_are_checked_on_the_residuals() {
        let n = 200;
        let pred: Vec<f64> = (0..n).map(|i| 1.0 + f64::from(i) / 10.0).collect();
        // a deterministic sequence of spread 1 and light tails
        let wiggle: Vec<f64> = (0..n).map(|i| (f64::from(i) * 2.39).sin()).collect();
        let y: Vec<f64> = pred.iter().zip(&wiggle).map(|(p, w)| p + w).collect();
        assert!(interval_warnings(&y, &pred, false, true).is_empty());
        let growing: Vec<f64> = pred.iter().zip(&wiggle).map(|(p, w)| p + p * w).collect();
        let w = interval_warnings(&growing, &pred, false, true);
        assert!(
            w.iter().any(|w| w.contains("grow with the prediction")),
            "{w:?}"
        );
        let mut tails = y.clone();
        for i in [7, 77, 150] {
            tails[i] += 40.0;
        }
        let w = interval_warnings(&tails, &pred, false, true);
        assert!(w.iter().any(|w| w.contains("heavy tails")), "{w:?}");
        let w = interval_warnings(&y, &pred, true, true);
        assert!(w.len() == 1 && w[0].contains("--extrapolate"), "{w:?}");
        assert_eq!(ranks(&[3.0, 1.0, 3.0, 2.0]), vec![3.5, 1.0, 3.5, 2.0]);
    }

    #[test]
    fn rows_outside_the_ranges_are_counted_with_the_farthest() {
        let t = Table::new(vec!["a".into()], vec![vec![0.5, 1.0, 3.0, -1.0]]).unwrap();
        let w = range_warnings(&t, &[("a".into(), 0.0, 1.0)]);
        assert_eq!(w.len(), 1);
        assert!(w[0].starts_with("2 of 4 rows have `a` outside"), "{}", w[0]);
        assert!(w[0].contains("by 2 widths"), "{}", w[0]);
        assert!(range_warnings(&t, &[("a".into(), -1.0, 3.0)]).is_empty());
    }
}

/// Values data loggers and file formats write for "no value": `-9999`, `-999`, `9999`,
/// `99999`, `-99999`, NetCDF's fill value `9.96921e36`, and `±1e30`, `±1e20`.
pub const MISSING_CODES: [f64; 10] = [
    -9999.0, -999.0, 9999.0, 99999.0, -99999.0, 9.96921e36, 1e30, -1e30, 1e20, -1e20,
];

/// A value further than this many robust standard deviations (1.4826 median absolute
/// deviations) from its column's median is a gross outlier.
pub const OUTLIER_ROBUST_SDS: f64 = 10.0;

/// The `--missing-codes` value naming the codes found at `idx` of `col` (each once, in
/// the order met: `-9999` or `-9999,9.96921e36`; `=` so that a negative code reads as a
/// value).
fn codes_flag(col: &[f64], idx: &[usize]) -> String {
    let mut seen: Vec<String> = Vec::new();
    for &i in idx {
        let s = num(col[i]);
        if !seen.contains(&s) {
            seen.push(s);
        }
    }
    format!("--missing-codes={}", seen.join(","))
}

/// Warnings, naming row (from 1) and column, for values of `columns` that look like a
/// missing-value code ([`MISSING_CODES`], within 1e-6 relative) or are gross outliers
/// ([`OUTLIER_ROBUST_SDS`]), each only where it stands far outside the column's other
/// values (beyond [`OUTLIER_ROBUST_SDS`] robust standard deviations of the median, or, for
/// a column whose median absolute deviation is 0, anywhere off the median). In a column of
/// positive values an outlier must also be one among the logarithms (tool life and wear
/// spread over decades: a long tail is not a typo, a value 1000 times too large is). At
/// most three rows are named per column, then the count.
pub fn value_warnings(table: &Table, columns: &[String]) -> Vec<String> {
    let mut out = Vec::new();
    for name in columns {
        let Some(col) = table.column(name) else {
            continue;
        };
        let finite: Vec<f64> = col.iter().copied().filter(|v| v.is_finite()).collect();
        if finite.len() < 5 {
            continue;
        }
        let (med, sd) = robust(&finite);
        let far = |v: f64| {
            let d = (v - med).abs();
            if sd > 0.0 {
                d > OUTLIER_ROBUST_SDS * sd
            } else {
                d > 0.0
            }
        };
        // a column of positive values (tool life, wear) is often skewed: a value is a gross
        // outlier only if it is also one among the logarithms
        let positive = finite.iter().all(|&v| v > 0.0);
        let (log_med, log_sd) = if positive {
            robust(&finite.iter().map(|v| v.ln()).collect::<Vec<_>>())
        } else {
            (0.0, 0.0)
        };
        let far_in_logs = |v: f64| {
            !positive
                || v <= 0.0
                || log_sd <= 0.0
                || (v.ln() - log_med).abs() > OUTLIER_ROBUST_SDS * log_sd
        };
        let is_code = |v: f64| {
            MISSING_CODES
                .iter()
                .any(|c| (v - c).abs() <= 1e-6 * c.abs())
        };
        let (mut codes, mut outliers) = (Vec::new(), Vec::new());
        for (i, &v) in col.iter().enumerate() {
            if !v.is_finite() || !far(v) {
                continue;
            }
            if is_code(v) {
                codes.push(i);
            } else if sd > 0.0 && far_in_logs(v) {
                outliers.push(i);
            }
        }
        let rows = |idx: &[usize]| {
            let shown: Vec<String> = idx
                .iter()
                .take(3)
                .map(|&i| format!("row {} ({})", i + 1, num(col[i])))
                .collect();
            let more = idx.len().saturating_sub(3);
            if more > 0 {
                format!("{} and {more} more", shown.join(", "))
            } else {
                shown.join(", ")
            }
        };
        if !codes.is_empty() {
            out.push(format!(
                "column `{name}`: {} look(s) like a missing-value code, far outside the \
                 column's other values (median {}): if it means \"no value\", give \
                 {} (the cells are then empty) and --missing drop or impute",
                rows(&codes),
                num(med),
                codes_flag(col, &codes)
            ));
        }
        if !outliers.is_empty() {
            out.push(format!(
                "column `{name}`: {} lie(s) more than {OUTLIER_ROBUST_SDS} robust standard \
                 deviations from the column's median {} (robust sd {}): a gross outlier or a \
                 typo? check those rows",
                rows(&outliers),
                num(med),
                num(sd)
            ));
        }
    }
    out
}

/// The median of `v` (finite values, not empty) and its robust standard deviation, 1.4826
/// median absolute deviations.
fn robust(v: &[f64]) -> (f64, f64) {
    use crate::explain::median;
    let med = median(v.iter().copied()).unwrap_or(0.0);
    let sd = 1.4826 * median(v.iter().map(|x| (x - med).abs())).unwrap_or(0.0);
    (med, sd)
}

#[cfg(test)]
mod value_tests {
    use super::*;

    fn table(v: Vec<f64>) -> Table {
        Table::new(vec!["y".into()], vec![v]).expect("table")
    }

    /// A logger's `-9999` and NetCDF's fill value are named by row as missing-value codes,
    /// a typo's 1000-fold value as a gross outlier, and an ordinary spread gives no word.
    #[test]
    fn codes_and_gross_outliers_are_named_by_row() {
        let base: Vec<f64> = (0..40).map(|i| 1.0 + 0.01 * i as f64).collect();
        assert!(value_warnings(&table(base.clone()), &["y".into()]).is_empty());
        let mut v = base.clone();
        v[6] = -9999.0;
        v[20] = 9.96921e36;
        let w = value_warnings(&table(v), &["y".into()]);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("row 7 (-9999)") && w[0].contains("row 21 (9.96921e36)"),
            "{w:?}"
        );
        assert!(w[0].contains("missing-value code"), "{w:?}");
        let mut v = base;
        v[3] = 1130.0;
        let w = value_warnings(&table(v), &["y".into()]);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("row 4 (1130)") && w[0].contains("gross outlier"),
            "{w:?}"
        );
        // -9999 inside a column whose values are all near it is not a code out of place
        let near: Vec<f64> = (0..20).map(|i| -10_000.0 + i as f64).collect();
        assert!(value_warnings(&table(near), &["y".into()]).is_empty());
    }
}

#[cfg(test)]
mod skew_tests {
    use super::*;

    /// A log-normal column (tool lives spread over two decades, whose long tail lies more
    /// than 10 robust standard deviations above the median on the linear scale) gives no
    /// outlier warning; a value a million times too large in it (a unit slip) does.
    #[test]
    fn a_long_tail_is_not_an_outlier_but_a_unit_slip_is() {
        // logistic quantiles of a log-normal law with a log-scale spread of about 1
        let v: Vec<f64> = (0..60)
            .map(|i| {
                let p = (i as f64 + 0.5) / 60.0;
                (2.0 + (p / (1.0 - p)).ln() / 1.7).exp()
            })
            .collect();
        let t = Table::new(vec!["life".into()], vec![v.clone()]).expect("table");
        let (med, linear_sd) = robust(&v);
        let top = v.iter().copied().fold(0.0, f64::max);
        assert!(
            top - med > OUTLIER_ROBUST_SDS * linear_sd,
            "the tail is far on the linear scale"
        );
        assert!(value_warnings(&t, &["life".into()]).is_empty());
        let mut bad = v;
        bad[9] *= 1e6;
        let t = Table::new(vec!["life".into()], vec![bad]).expect("table");
        let w = value_warnings(&t, &["life".into()]);
        assert!(w.len() == 1 && w[0].contains("row 10"), "{w:?}");
    }
}
