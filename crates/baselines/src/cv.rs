//! Cross-validation of any [`Regressor`].

use crate::{BaselineError, Progress, Regressor};
use hxai_eval::{Metrics, Split};
use hxai_table::Table;

/// Fits a fresh model from `make` on each split's train rows and scores it on its test rows;
/// `progress` hears after each fold.
///
/// Folds run one after the other (models may parallelise internally), so the result is
/// the same for any thread count.
///
/// # Errors
/// Any fitting, prediction or scoring error, or a split index out of range.
pub fn cross_validate(
    make: &dyn Fn() -> Box<dyn Regressor>,
    x: &Table,
    y: &[f64],
    splits: &[Split],
    progress: &mut dyn FnMut(Progress),
) -> Result<Vec<Metrics>, BaselineError> {
    if y.len() != x.n_rows() {
        return Err(BaselineError::LengthMismatch {
            rows: x.n_rows(),
            targets: y.len(),
        });
    }
    let pick = |idx: &[usize]| -> Result<Vec<f64>, BaselineError> {
        idx.iter()
            .map(|&i| {
                y.get(i).copied().ok_or(BaselineError::RowIndex {
                    index: i,
                    nrows: y.len(),
                })
            })
            .collect()
    };
    let mut scores = Vec::with_capacity(splits.len());
    for (k, s) in splits.iter().enumerate() {
        let mut model = make();
        model.fit(&x.select_rows(&s.train)?, &pick(&s.train)?)?;
        let pred = model.predict(&x.select_rows(&s.test)?)?;
        scores.push(hxai_eval::score(&pick(&s.test)?, &pred)?);
        progress(Progress {
            done: k + 1,
            total: splits.len(),
        });
    }
    Ok(scores)
}
