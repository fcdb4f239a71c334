//! Cross-validation of any [`Regressor`].

use crate::{BaselineError, Matrix, Regressor};
use hxai_eval::{Metrics, Split};

/// Fits a fresh model from `make` on each split's train rows and scores it on its test rows.
///
/// Folds run one after the other (models may parallelise internally), so the result is
/// the same for any thread count.
///
/// # Errors
/// Any fitting, prediction or scoring error, or a split index out of range.
pub fn cross_validate(
    make: &dyn Fn() -> Box<dyn Regressor>,
    x: &Matrix,
    y: &[f64],
    splits: &[Split],
) -> Result<Vec<Metrics>, BaselineError> {
    if y.len() != x.nrows() {
        return Err(BaselineError::LengthMismatch {
            rows: x.nrows(),
            targets: y.len(),
        });
    }
    splits
        .iter()
        .map(|s| {
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
            let mut model = make();
            model.fit(&x.select_rows(&s.train)?, &pick(&s.train)?)?;
            let pred = model.predict(&x.select_rows(&s.test)?)?;
            Ok(hxai_eval::score(&pick(&s.test)?, &pred)?)
        })
        .collect()
}
