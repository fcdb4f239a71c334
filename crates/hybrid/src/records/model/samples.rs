//! The samples table: one row per window sample of a fit (`record`, `window`, `split`, the
//! features, `A_phys`, `A_true`, `delta`). `hxai fit --samples` writes it (CSV or Parquet),
//! the reproduction writes it as `samples.csv` ([`SamplesTable::to_csv`]), and
//! `hxai explain --data` reads it back ([`SamplesTable::read_back`]): its format is known
//! here only.

use crate::HybridError;
use crate::records::sample::WindowSample;
use hxai_table::Table;
use std::fmt::Write;

/// The samples of a fit as columns, one row per sample in record then window order: the
/// table `hxai fit --samples` and the reproduction's `samples.csv` write.
#[derive(Debug, Clone, PartialEq)]
pub struct SamplesTable {
    /// Record id of each sample (column `record`).
    pub record: Vec<String>,
    /// Window index within the record (column `window`).
    pub window: Vec<usize>,
    /// `train` or `test` (column `split`).
    pub split: Vec<&'static str>,
    /// The features (named by the feature map, `f1`..`f12`), then `A_phys`, `A_true` and
    /// `delta = A_true - A_phys`, in micrometres.
    pub values: Table,
}

impl SamplesTable {
    /// Every column name in file order: `record`, `window`, `split`, then the values'.
    pub fn names(&self) -> Vec<String> {
        let mut names = vec!["record".to_string(), "window".into(), "split".into()];
        names.extend(self.values.names().iter().cloned());
        names
    }
}

/// The samples table of `samples` (each with its truth) split by `is_test`, feature columns
/// named `feature_names`.
///
/// # Errors
/// [`HybridError::NoTruth`] for a sample without truth, [`HybridError::InvalidConfig`] when
/// `is_test` or a sample's features do not match in length, [`HybridError::Table`] for a
/// non-finite value.
pub fn samples_table(
    samples: &[WindowSample],
    is_test: &[bool],
    feature_names: &[String],
) -> Result<SamplesTable, HybridError> {
    if is_test.len() != samples.len() {
        return Err(HybridError::InvalidConfig(format!(
            "{} split flags for {} samples",
            is_test.len(),
            samples.len()
        )));
    }
    let mut values = crate::records::composer::feature_table(feature_names.to_vec(), samples)?;
    let truth = |w: &WindowSample| {
        w.a_true()
            .zip(w.delta())
            .ok_or_else(|| HybridError::NoTruth {
                record: w.record.clone(),
            })
    };
    let (a_true, delta): (Vec<f64>, Vec<f64>) = samples
        .iter()
        .map(truth)
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .unzip();
    values.push_column(
        "A_phys".into(),
        samples.iter().map(|w| w.a_phys()).collect(),
    )?;
    values.push_column("A_true".into(), a_true)?;
    values.push_column("delta".into(), delta)?;
    Ok(SamplesTable {
        record: samples.iter().map(|w| w.record.clone()).collect(),
        window: samples.iter().map(|w| w.window).collect(),
        split: is_test
            .iter()
            .map(|&t| if t { "test" } else { "train" })
            .collect(),
        values,
    })
}

impl SamplesTable {
    /// The table as CSV text with a header, numbers in Rust's shortest round-trip form (what
    /// the reproduction commits as `samples.csv`).
    pub fn to_csv(&self) -> String {
        let mut s = self.names().join(",");
        s.push('\n');
        let columns = self.values.columns();
        for (i, ((record, window), split)) in self
            .record
            .iter()
            .zip(&self.window)
            .zip(&self.split)
            .enumerate()
        {
            let _ = write!(s, "{record},{window},{split}");
            for column in columns {
                let _ = write!(s, ",{}", column[i]);
            }
            s.push('\n');
        }
        s
    }

    /// What `explain` draws from a samples table read back: every numeric column (the
    /// features among them), the column `delta`, and per row whether it is a test row
    /// (from the text column `split`, `train` or `test`; every row is a training row
    /// without it).
    ///
    /// # Errors
    /// [`HybridError::NoData`]: no numeric column `delta`, a numeric `split`, or a `split`
    /// cell other than `train`/`test` (named by its row, counted from 1).
    pub fn read_back(
        numbers: Table,
        split: Option<&[String]>,
    ) -> Result<(Table, Vec<f64>, Vec<bool>), HybridError> {
        let delta = numbers
            .column("delta")
            .ok_or_else(|| {
                HybridError::NoData(
                    "no numeric column `delta`; pass the table `hxai fit --samples` wrote".into(),
                )
            })?
            .to_vec();
        if numbers.column("split").is_some() {
            return Err(HybridError::NoData(
                "`split` must be text (train or test), found numbers".into(),
            ));
        }
        let is_test = match split {
            None => vec![false; delta.len()],
            Some(cells) => cells
                .iter()
                .enumerate()
                .map(|(row, s)| match s.as_str() {
                    "train" => Ok(false),
                    "test" => Ok(true),
                    other => Err(HybridError::NoData(format!(
                        "row {}: `split` must be train or test, got `{}`",
                        row + 1,
                        other.chars().take(20).collect::<String>()
                    ))),
                })
                .collect::<Result<Vec<bool>, _>>()?,
        };
        Ok((numbers, delta, is_test))
    }
}

impl super::RecordModel {
    /// The samples table of `records` (each with its truth) labelled by this model's split:
    /// a window is `train` when the fit used it (its record among the training records,
    /// and, with a window split, the window not among the test windows), `test` otherwise
    /// (a record the fit never saw is `test`). What a report draws the correction on.
    ///
    /// # Errors
    /// [`HybridError::NoTruth`] for a record without truth,
    /// [`HybridError::FrequencyOutOfBand`] and the composer's errors.
    pub fn samples_of(
        &self,
        records: &[crate::records::RecordInput<'_>],
    ) -> Result<SamplesTable, HybridError> {
        let hybrid = self.hybrid();
        let mut samples = Vec::new();
        for r in records {
            if r.truth.is_none() {
                return Err(HybridError::NoTruth {
                    record: r.id.to_owned(),
                });
            }
            super::check_band(&self.physics, r)?;
            samples.extend(hybrid.samples(r)?.windows);
        }
        let test_windows = self.split.test_windows.as_deref().unwrap_or(&[]);
        let is_test: Vec<bool> = samples
            .iter()
            .map(|s| {
                let trained = self.split.train.contains(&s.record)
                    && !(self.split.kind == super::SplitKind::Window
                        && test_windows
                            .iter()
                            .any(|w| w.record == s.record && w.window == s.window));
                !trained
            })
            .collect();
        samples_table(&samples, &is_test, &self.features.names)
    }
}
