//! The input checks shared by the metrics, the splits and the statistics.

use crate::EvalError;

/// Checks that `values` has at least `need` (and at least one) values, all finite.
pub(crate) fn check_finite(
    what: &'static str,
    values: &[f64],
    need: usize,
) -> Result<(), EvalError> {
    if values.len() < need.max(1) {
        return Err(EvalError::Empty {
            what,
            need: need.max(1),
        });
    }
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(EvalError::NonFinite {
            what,
            index,
            value: values[index],
        }),
        None => Ok(()),
    }
}

/// Checks two paired samples, each given with its name: equal lengths (`what` names the
/// pair), then each as [`check_finite`] with `need` values.
pub(crate) fn check_paired(
    what: &'static str,
    (left_name, left): (&'static str, &[f64]),
    (right_name, right): (&'static str, &[f64]),
    need: usize,
) -> Result<(), EvalError> {
    if left.len() != right.len() {
        return Err(EvalError::LengthMismatch {
            what,
            left: left.len(),
            right: right.len(),
        });
    }
    check_finite(left_name, left, need)?;
    check_finite(right_name, right, need)
}

/// Checks that `value` (named `what`) is a fraction strictly between 0 and 1.
pub(crate) fn check_open_fraction(what: &'static str, value: f64) -> Result<(), EvalError> {
    if value.is_finite() && value > 0.0 && value < 1.0 {
        Ok(())
    } else {
        Err(EvalError::FractionOutOfRange { what, value })
    }
}
