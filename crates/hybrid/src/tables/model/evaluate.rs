//! Evaluating a table hybrid on a table: physics against hybrid on the target column,
//! with the coverage and width of its prediction intervals, on any table or on the test
//! rows of the model's own split.

use super::{TableEvaluation, TableModel, columns_of};
use crate::HybridError;
use crate::intervals::{DEFAULT_INTERVAL, IntervalReport};
use hxai_eval::{IntervalMethod, TTest};
use hxai_symreg::Table;

impl TableModel {
    /// Physics vs hybrid against the target column of `table`.
    ///
    /// # Errors
    /// A missing column (the target included), a bad physics value, or fewer than two rows
    /// or non-finite predictions (from the statistics).
    pub fn evaluate(&self, table: &Table) -> Result<TableEvaluation, HybridError> {
        self.evaluate_at(table, DEFAULT_INTERVAL)
    }

    /// [`TableModel::evaluate`] with the coverage and median width of the hybrid's
    /// prediction intervals at `level` ([`TableEvaluation::interval`]) by the model's
    /// default method ([`TableModel::default_interval_method`]), when it has one.
    ///
    /// # Errors
    /// As [`TableModel::evaluate`], and a `level` outside (0, 1).
    pub fn evaluate_at(&self, table: &Table, level: f64) -> Result<TableEvaluation, HybridError> {
        match self.default_interval_method(level) {
            Some(method) => self.evaluate_with(table, level, method),
            None => {
                let y = columns_of(table, std::slice::from_ref(&self.target), "target")?[0];
                let p = self.predict(table)?;
                let mut ev = evaluation(y, &p.physics, &p.hybrid)?;
                ev.warnings = self.range_warnings(table);
                Ok(ev)
            }
        }
    }

    /// [`TableModel::evaluate_at`] with the intervals made by `method`.
    ///
    /// # Errors
    /// As [`TableModel::evaluate_at`], and those of [`TableModel::intervals_with`] (a
    /// method the model file cannot serve among them).
    pub fn evaluate_with(
        &self,
        table: &Table,
        level: f64,
        method: IntervalMethod,
    ) -> Result<TableEvaluation, HybridError> {
        let y = columns_of(table, std::slice::from_ref(&self.target), "target")?[0];
        let p = self.predict(table)?;
        let mut ev = evaluation(y, &p.physics, &p.hybrid)?;
        let iv = self.intervals_with(table, level, method)?;
        let report = IntervalReport::of(method, level, y, &iv);
        ev.interval = Some(report);
        ev.warnings = self.range_warnings(table);
        ev.warnings
            .extend(crate::intervals::undefined_warning(&report, "row(s)"));
        Ok(ev)
    }

    /// The coverage and median width of the intervals by `method` at `level` on the test
    /// rows of the model's own split of `table` (the table it was fitted on); `None` when
    /// the split has no test rows.
    ///
    /// # Errors
    /// A table with fewer rows than the split names, and those of
    /// [`TableModel::intervals_with`].
    pub fn test_interval(
        &self,
        table: &Table,
        level: f64,
        method: IntervalMethod,
    ) -> Result<Option<IntervalReport>, HybridError> {
        if self.split.test.is_empty() {
            return Ok(None);
        }
        if let Some(&i) = self.split.test.iter().find(|&&i| i >= table.n_rows()) {
            return Err(HybridError::InvalidConfig(format!(
                "the model's split names row {} but the table has {} rows: pass the table the model was fitted on",
                i + 1,
                table.n_rows()
            )));
        }
        let test = table.select_rows(&self.split.test)?;
        let y = columns_of(&test, std::slice::from_ref(&self.target), "target")?[0];
        let iv = self.intervals_with(&test, level, method)?;
        Ok(Some(IntervalReport::of(method, level, y, &iv)))
    }
}

pub(crate) fn evaluation(
    y: &[f64],
    physics: &[f64],
    hybrid: &[f64],
) -> Result<TableEvaluation, HybridError> {
    if y.len() < 2 {
        return Err(HybridError::InvalidConfig(format!(
            "{} row(s) to evaluate on: R² and the paired t-test need at least 2",
            y.len()
        )));
    }
    let ps = hxai_eval::score(y, physics)?;
    let hs = hxai_eval::score(y, hybrid)?;
    let se_p = hxai_eval::squared_errors(y, physics)?;
    let se_h = hxai_eval::squared_errors(y, hybrid)?;
    let (t_test, t_test_reason) = defined_t_test(&se_p, &se_h, "the physics and the hybrid")?;
    Ok(TableEvaluation {
        improvement_pct: hxai_eval::improvement_pct(ps.rmse, hs.rmse)?,
        t_test,
        t_test_reason,
        physics: ps,
        hybrid: hs,
        n_samples: y.len(),
        interval: None,
        warnings: Vec::new(),
    })
}

/// A paired t-test of `a` against `b`, or `None` with the reason where it is undefined
/// (`what` predict the same on every row: the statistic is 0/0). An undefined test is a
/// result, not a failure (issue 63): the other numbers are still reported.
///
/// # Errors
/// What [`hxai_eval::paired_t_test`] refuses besides identical samples.
pub(crate) fn defined_t_test(
    a: &[f64],
    b: &[f64],
    what: &str,
) -> Result<(Option<TTest>, Option<String>), HybridError> {
    match hxai_eval::paired_t_test(a, b) {
        Ok(t) => Ok((Some(t), None)),
        Err(hxai_eval::EvalError::IdenticalSamples) => Ok((
            None,
            Some(format!(
                "{what} have the same error on every row (the correction changes nothing \
                 there): the paired t-test is undefined (0/0)"
            )),
        )),
        Err(e) => Err(e.into()),
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::evaluation;

    /// A hybrid that predicts its physics on every row (the correction kept nothing) is
    /// evaluated: the t-test is `None` with the reason, every other number is given
    /// (issue 63: it aborted the whole evaluation).
    #[test]
    fn a_hybrid_equal_to_its_physics_is_evaluated_without_a_t_test() {
        let y = [1.0, 2.5, 2.9, 4.2];
        let p = [1.1, 2.4, 3.0, 4.0];
        let e = evaluation(&y, &p, &p).unwrap();
        assert!(e.t_test.is_none());
        assert!(e.t_test_reason.unwrap().contains("undefined"));
        assert_eq!(e.physics, e.hybrid);
        assert_eq!(e.improvement_pct, 0.0);
        let json = serde_json::to_value(evaluation(&y, &p, &p).unwrap()).unwrap();
        assert!(json["t_test"].is_null(), "{json}");
        // a defined test is still given
        let h = [1.0, 2.5, 2.95, 4.1];
        assert!(evaluation(&y, &p, &h).unwrap().t_test.is_some());
    }
}
