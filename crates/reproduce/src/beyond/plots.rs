//! The section's figures: predicted vs measured per split, error vs the extrapolated column.

use super::CaseSpec;
use crate::ReproduceError;
use crate::figures::{Panel, Series};
use hxai_hybrid::tables::TableModel;

fn span(v: impl Iterator<Item = f64>) -> [f64; 2] {
    v.fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], x| {
        [lo.min(x), hi.max(x)]
    })
}

/// Per-row values a figure needs: `(measured, physics, hybrid, extrapolated column, is_test)`.
type Rows = Vec<(f64, f64, f64, f64, bool)>;

pub(super) fn rows_of(m: &TableModel, spec: &CaseSpec) -> Result<Rows, ReproduceError> {
    let pred = m.predict(&spec.table)?;
    let col = |name: &str| {
        spec.table
            .column(name)
            .ok_or_else(|| ReproduceError::Pipeline(format!("{}: no column {name}", spec.name)))
    };
    let (y, x) = (col(spec.target)?, col(spec.extrapolate)?);
    let mut is_test = vec![false; y.len()];
    for &i in &m.split.test {
        if let Some(t) = is_test.get_mut(i) {
            *t = true;
        }
    }
    Ok((0..y.len())
        .map(|i| (y[i], pred.physics[i], pred.hybrid[i], x[i], is_test[i]))
        .collect())
}

pub(super) fn parity(rows: &Rows, title: String, unit: &str, target: &str) -> Panel {
    let test: Vec<_> = rows.iter().filter(|r| r.4).collect();
    let phys: Vec<_> = test.iter().map(|r| (r.0, r.1)).collect();
    let hyb: Vec<_> = test.iter().map(|r| (r.0, r.2)).collect();
    let [lo, hi] = span(test.iter().flat_map(|r| [r.0, r.1, r.2]));
    Panel {
        title,
        x_label: format!("measured {target} ({unit})"),
        y_label: format!("predicted ({unit})"),
        series: vec![
            Series::points("physics, calibrated", phys),
            Series::points("hybrid", hyb),
            Series::dashed("y = x", vec![(lo, lo), (hi, hi)]),
        ],
    }
}

pub(super) fn error_panel(rows: &Rows, spec: &CaseSpec) -> Panel {
    let pick = |test: bool, hybrid: bool| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| r.4 == test)
            .map(|r| (r.3, if hybrid { r.2 } else { r.1 } - r.0))
            .collect()
    };
    Panel {
        title: format!("error vs {} (extrapolation split)", spec.extrapolate),
        x_label: spec.extrapolate.to_string(),
        y_label: format!("prediction - measured ({})", spec.unit),
        series: vec![
            Series::points("physics, train", pick(false, false)),
            Series::points("hybrid, train", pick(false, true)),
            Series::points("physics, test", pick(true, false)),
            Series::points("hybrid, test", pick(true, true)),
        ],
    }
}

/// File name of a case's figure.
pub fn figure_name(case: &str) -> String {
    format!("fig_beyond_{case}.svg")
}
