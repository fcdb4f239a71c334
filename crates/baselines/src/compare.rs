//! The paper's Table 3: every model fitted on one table and scored on another.

use crate::{BaselineError, Progress, Regressor};
use hxai_eval::Metrics;
use hxai_table::Table;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// One line of a comparison: a model's test scores and its fitting time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    /// The model's [`Regressor::name`].
    pub name: String,
    /// R^2, RMSE and MAE on the test rows (RMSE and MAE in the target's unit); JSON keys
    /// `r2`, `rmse`, `mae` beside `name` and `seconds` (`hxai compare --json`'s `models`).
    #[serde(flatten)]
    pub metrics: Metrics,
    /// Wall time of `fit`, s (depends on the machine; never part of a committed result).
    pub seconds: f64,
}

/// Fits each of `models` on `(x_train, y_train)`, predicts `x_test` and scores the
/// prediction against `y_test` with [`hxai_eval::score`], in the order given; `progress`
/// hears after each model. `x_test` must have the training table's columns in its order.
///
/// # Errors
/// [`BaselineError::Model`] naming the first model that fails to fit, predict or score.
pub fn compare(
    models: Vec<Box<dyn Regressor>>,
    x_train: &Table,
    y_train: &[f64],
    x_test: &Table,
    y_test: &[f64],
    progress: &mut dyn FnMut(Progress),
) -> Result<Vec<Comparison>, BaselineError> {
    let total = models.len();
    let mut rows = Vec::with_capacity(total);
    for (k, mut m) in models.into_iter().enumerate() {
        let name = m.name().to_string();
        let in_model = |e: BaselineError| BaselineError::Model {
            model: name.clone(),
            source: Box::new(e),
        };
        let t0 = Instant::now();
        let fitted = m.fit(x_train, y_train);
        let seconds = t0.elapsed().as_secs_f64();
        fitted.map_err(in_model)?;
        let metrics = m
            .predict(x_test)
            .and_then(|pred| Ok(hxai_eval::score(y_test, &pred)?))
            .map_err(in_model)?;
        rows.push(Comparison {
            name,
            metrics,
            seconds,
        });
        progress(Progress { done: k + 1, total });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `hxai compare --json` prints the rows as they serialise: the scores beside the name.
    #[test]
    fn a_row_serialises_flat() -> Result<(), serde_json::Error> {
        let row = Comparison {
            name: "linear".into(),
            metrics: Metrics {
                r2: 0.5,
                rmse: 2.0,
                mae: 1.5,
            },
            seconds: 0.25,
        };
        let text = serde_json::to_string(&row)?;
        assert_eq!(
            text,
            r#"{"name":"linear","r2":0.5,"rmse":2.0,"mae":1.5,"seconds":0.25}"#
        );
        let back: Comparison = serde_json::from_str(&text)?;
        assert_eq!(back, row);
        Ok(())
    }
}
