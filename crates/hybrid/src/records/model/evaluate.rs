//! Evaluating a tool-position hybrid model on records: physics against hybrid on the
//! model's test data (or every window), with the coverage of its prediction intervals.

use super::{RecordModel, SplitKind};
use crate::HybridError;
use crate::intervals::{DEFAULT_INTERVAL, IntervalReport};
use crate::records::evaluation::{EvalInput, Evaluation, evaluate};
use crate::records::sample::RecordInput;
use crate::records::warnings::input_warnings;
use hxai_eval::IntervalMethod;
use std::collections::BTreeMap;

impl RecordModel {
    /// Evaluates the model on records. With `all` false, only this model's test data is
    /// used: the test records (record split) or the test windows (window split) among
    /// `records`; records not in the test set are skipped. With `all` true, every window
    /// of every record.
    ///
    /// # Errors
    /// [`HybridError::NoData`] when none of the records is a test record.
    pub fn evaluate(
        &self,
        records: &[RecordInput<'_>],
        all: bool,
    ) -> Result<Evaluation, HybridError> {
        self.evaluate_at(records, all, DEFAULT_INTERVAL)
    }

    /// [`RecordModel::evaluate`] with the coverage of prediction intervals at `level` by the
    /// model's default method ([`RecordModel::default_interval_method`])
    /// ([`Evaluation::interval`]: the share of evaluated windows whose true amplitude lies
    /// inside the interval of the corrected amplitude), when the model stores the
    /// uncertainty of its correction.
    ///
    /// # Errors
    /// As [`RecordModel::evaluate`], and a `level` outside (0, 1).
    pub fn evaluate_at(
        &self,
        records: &[RecordInput<'_>],
        all: bool,
        level: f64,
    ) -> Result<Evaluation, HybridError> {
        let method = self
            .default_interval_method(level)
            .unwrap_or(IntervalMethod::Delta);
        self.evaluate_with(records, all, level, method)
    }

    /// [`RecordModel::evaluate_at`] with the intervals made by `method`
    /// ([`RecordModel::amplitude_intervals_with`]).
    ///
    /// # Errors
    /// As [`RecordModel::evaluate_at`], and a method the model file cannot serve.
    pub fn evaluate_with(
        &self,
        records: &[RecordInput<'_>],
        all: bool,
        level: f64,
        method: IntervalMethod,
    ) -> Result<Evaluation, HybridError> {
        let mut by_record: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
        for w in self.split.test_windows.iter().flatten() {
            by_record
                .entry(w.record.as_str())
                .or_default()
                .push(w.window);
        }
        let mut inputs = Vec::new();
        for r in records {
            if all {
                inputs.push(EvalInput {
                    record: *r,
                    windows: None,
                });
                continue;
            }
            match self.split.kind {
                SplitKind::Record => {
                    if self.split.test.iter().any(|t| t == r.id) {
                        inputs.push(EvalInput {
                            record: *r,
                            windows: None,
                        });
                    }
                }
                SplitKind::Window => {
                    if let Some(ws) = by_record.get(r.id) {
                        inputs.push(EvalInput {
                            record: *r,
                            windows: Some(ws.as_slice()),
                        });
                    }
                }
            }
        }
        if inputs.is_empty() {
            return Err(HybridError::NoData(format!(
                "none of the {} records given is a test record of this model (test records: {}); \
                 evaluate on the data folder the model was fitted on, or evaluate every record",
                records.len(),
                self.split.test.join(", ")
            )));
        }
        for i in &inputs {
            self.check_band(&i.record)?;
        }
        let mut ev = evaluate(&self.hybrid(), self.correction()?, &inputs)?;
        if self.correction.uncertainty.is_some() {
            let hybrid = self.hybrid();
            let mut samples = Vec::new();
            for i in &inputs {
                let rs = hybrid.samples(&i.record)?;
                samples.extend(
                    rs.windows
                        .into_iter()
                        .filter(|s| i.windows.is_none_or(|w| w.contains(&s.window))),
                );
            }
            let iv = self.amplitude_intervals_with(&samples, level, method)?;
            let truth: Vec<f64> = samples
                .iter()
                .map(|s| s.a_true().unwrap_or(f64::NAN))
                .collect();
            ev.interval = Some(IntervalReport::of(method, level, &truth, &iv));
        }
        ev.warnings = inputs
            .iter()
            .flat_map(|i| input_warnings(&i.record, &self.window))
            .map(|w| w.to_string())
            .collect();
        Ok(ev)
    }
}
