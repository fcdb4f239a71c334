//! Export: a fitted program over the search's columns becomes a [`Model`] that names only
//! the features it uses.
use crate::Table;
use crate::model::Model;
use crate::program::Program;

/// The model of `prog` with `params`, its inputs renumbered so that the model names only the
/// columns of `data` it uses (in increasing column order).
pub(crate) fn to_model(
    prog: &Program,
    params: Vec<f64>,
    mse: f64,
    score: f64,
    complexity: usize,
    data: &Table,
) -> Model {
    let (names, program) = crate::model::over_used_columns(prog, data.names());
    Model {
        feature_names: names,
        program,
        params,
        complexity,
        train_mse: mse,
        score,
    }
}
