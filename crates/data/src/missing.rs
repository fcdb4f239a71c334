//! Empty cells, by the user's choice (`--missing refuse|drop|impute`, issue 48).
//!
//! An engineer's table has gaps: a sensor that was off, a batch whose hardness was not
//! measured. hxai refuses them by default, because any choice changes the data; the user
//! may instead drop the rows that have an empty cell, or fill a feature's empty cells with
//! its median on the training rows. The target is never filled (a row without the value to
//! learn is dropped under `impute`, and counted), and columns the caller names as
//! protected (a hybrid's physics columns) are never filled either: their gaps are refused,
//! naming the column, since a median fed to a physical law is a made-up measurement.
//!
//! [`read_gappy_table`] reads a table whose numeric columns may have empty cells;
//! [`GappyTable::resolve`] applies the policy and returns the [`MixedTable`] the rest of
//! hxai reads, with a [`MissingReport`] (the rows dropped, the cells filled, the medians used)
//! for the output and the model file. `predict` passes the medians stored at fit time, so a
//! new row is filled exactly as the training rows were.
use crate::DataError;
use crate::Format;
use crate::cells::{RawColumn, parse_number};
use crate::raw;
use crate::table::{Column, MixedTable};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What to do with empty cells.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MissingPolicy {
    /// Refuse the table, naming the column, its count of empty cells and the other choices
    /// (the default).
    #[default]
    Refuse,
    /// Drop every row with an empty cell in a numeric column.
    Drop,
    /// Fill a feature column's empty cells with its training median; drop rows whose target
    /// is empty.
    Impute,
}

impl MissingPolicy {
    /// Parses `refuse`, `drop` or `impute`.
    ///
    /// # Errors
    /// A message naming the three choices.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "refuse" => Ok(Self::Refuse),
            "drop" => Ok(Self::Drop),
            "impute" => Ok(Self::Impute),
            other => Err(format!(
                "unknown --missing choice `{other}`: use refuse, drop or impute"
            )),
        }
    }

    /// `refuse`, `drop` or `impute`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Refuse => "refuse",
            Self::Drop => "drop",
            Self::Impute => "impute",
        }
    }
}

/// What [`GappyTable::resolve`] did, for the output and the model file (`missing`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MissingReport {
    /// The policy applied.
    pub policy: MissingPolicy,
    /// The median each imputed column was filled with (under `impute`: every numeric
    /// feature column's training median, whether or not it had a gap, so that `predict`
    /// can fill a gap the training rows did not have).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub medians: BTreeMap<String, f64>,
    /// Rows dropped.
    #[serde(default)]
    pub dropped_rows: usize,
    /// Cells filled, by column.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub filled: BTreeMap<String, usize>,
}

impl MissingReport {
    /// One line per thing done, for the command's warnings (empty when nothing was done).
    pub fn lines(&self) -> Vec<String> {
        let mut out = Vec::new();
        if self.dropped_rows > 0 {
            out.push(format!(
                "--missing {}: dropped {} row(s) with an empty cell",
                self.policy.name(),
                self.dropped_rows
            ));
        }
        for (col, n) in &self.filled {
            let m = self.medians.get(col).copied().unwrap_or(f64::NAN);
            out.push(format!(
                "--missing impute: filled {n} empty cell(s) of `{col}` with its training median {}",
                crate::format_number(m)
            ));
        }
        out
    }
}

/// One column of a [`GappyTable`].
#[derive(Clone, Debug, PartialEq)]
pub enum GappyColumn {
    /// Every non-empty cell a finite number; `None` an empty cell.
    Number(Vec<Option<f64>>),
    /// Text (some non-empty cell is not a number).
    Text(Vec<String>),
}

/// A table whose numeric columns may have empty cells ([`read_gappy_table`]).
#[derive(Clone, Debug, PartialEq)]
pub struct GappyTable {
    /// The file, for messages.
    pub path: PathBuf,
    /// Column names.
    pub names: Vec<String>,
    /// Columns, in the order of `names`.
    pub columns: Vec<GappyColumn>,
    /// Blank lines and all-empty rows of the CSV that were skipped (0 for Parquet).
    pub skipped_rows: usize,
}

/// Reads a table whose numeric columns may have empty cells; CSV or Parquet by extension.
/// A column is numeric when every non-empty cell parses as a number (a column with every
/// cell empty too); a non-finite number is an error naming row and column.
///
/// # Errors
/// [`DataError`] for an unreadable file, a file without rows, or a NaN or infinite cell.
pub fn read_gappy_table(path: &Path) -> Result<GappyTable, DataError> {
    let format = Format::from_path(path)?;
    let raw = raw::read(path, format)?;
    crate::cells::require_rows(path, &raw)?;
    let mut columns = Vec::with_capacity(raw.names.len());
    for (name, col) in raw.names.iter().zip(&raw.columns) {
        let cells: Vec<Option<String>> = match col {
            RawColumn::Num(v) => v.iter().map(|c| c.map(|x| x.to_string())).collect(),
            RawColumn::Text(v) => v.clone(),
        };
        let trimmed: Vec<Option<&str>> = cells
            .iter()
            .map(|c| c.as_deref().map(str::trim).filter(|s| !s.is_empty()))
            .collect();
        // a column with every cell empty counts as numbers with gaps, so that it is named
        // (and refused unless left out) rather than silently dropped as text
        let numeric = trimmed.iter().flatten().all(|s| parse_number(s).is_some());
        if numeric {
            let mut v = Vec::with_capacity(trimmed.len());
            for (i, c) in trimmed.iter().enumerate() {
                v.push(match c.and_then(parse_number) {
                    Some(x) if !x.is_finite() => {
                        return Err(DataError::NonFinite {
                            path: path.to_path_buf(),
                            row: i + 1,
                            column: name.clone(),
                            value: x,
                        });
                    }
                    other => other,
                });
            }
            columns.push(GappyColumn::Number(v));
        } else {
            columns.push(GappyColumn::Text(
                cells.into_iter().map(Option::unwrap_or_default).collect(),
            ));
        }
    }
    Ok(GappyTable {
        path: path.to_path_buf(),
        names: raw.names,
        columns,
        skipped_rows: raw.skipped,
    })
}

/// The median of the present values (`None` when there are none).
fn median(v: &[Option<f64>]) -> Option<f64> {
    let mut x: Vec<f64> = v.iter().flatten().copied().collect();
    if x.is_empty() {
        return None;
    }
    x.sort_by(f64::total_cmp);
    let n = x.len();
    Some(if n % 2 == 1 {
        x[n / 2]
    } else {
        0.5 * (x[n / 2 - 1] + x[n / 2])
    })
}

/// A refusal naming the table, the column and what to do.
fn refusal(path: &Path, message: String) -> DataError {
    DataError::Invalid {
        path: path.to_path_buf(),
        message,
    }
}

impl GappyTable {
    /// Empty cells per numeric column, in column order (columns without one left out).
    pub fn gaps(&self) -> Vec<(&str, usize)> {
        self.names
            .iter()
            .zip(&self.columns)
            .filter_map(|(n, c)| match c {
                GappyColumn::Number(v) => {
                    let k = v.iter().filter(|x| x.is_none()).count();
                    (k > 0).then_some((n.as_str(), k))
                }
                GappyColumn::Text(_) => None,
            })
            .collect()
    }

    /// Applies `policy` to the numeric columns, except those in `ignore` (columns the
    /// command leaves out: their gaps do not matter). `target` is never filled (rows where
    /// it is empty are dropped under `impute`); a gap in a `protected` column is refused.
    /// `medians` (from a fitted model) replace the medians of this table under `impute`.
    ///
    /// # Errors
    /// [`DataError::Invalid`] naming the column: under `refuse` any gap (with the count and
    /// the two other choices), a column with every cell empty, a gap in a protected column,
    /// a gap in a column with no stored median, or no row left.
    pub fn resolve(
        &self,
        policy: MissingPolicy,
        target: Option<&str>,
        protected: &[&str],
        ignore: &[&str],
        medians: Option<&BTreeMap<String, f64>>,
    ) -> Result<(MixedTable, MissingReport), DataError> {
        let path = &self.path;
        let used = |n: &str| !ignore.contains(&n);
        let n_rows = self.columns.first().map_or(0, |c| match c {
            GappyColumn::Number(v) => v.len(),
            GappyColumn::Text(v) => v.len(),
        });
        let mut report = MissingReport {
            policy,
            ..MissingReport::default()
        };
        for (name, count) in self.gaps() {
            if !used(name) {
                continue;
            }
            let all = count == n_rows;
            match policy {
                MissingPolicy::Refuse => {
                    return Err(refusal(
                        path,
                        format!(
                            "column `{name}` has {count} empty cell(s) of {n_rows}; hxai \
                             refuses empty cells by default: choose --missing drop (drop \
                             the rows with an empty cell) or --missing impute (fill a \
                             feature's empty cells with its training median), or leave \
                             the column out"
                        ),
                    ));
                }
                _ if all => {
                    return Err(refusal(
                        path,
                        format!("column `{name}` is empty in every row: leave it out"),
                    ));
                }
                MissingPolicy::Impute if protected.contains(&name) => {
                    return Err(refusal(
                        path,
                        format!(
                            "column `{name}` has {count} empty cell(s) and feeds the \
                             physics, which is never given a made-up value: choose \
                             --missing drop or fill the cells"
                        ),
                    ));
                }
                MissingPolicy::Impute
                    if Some(name) != target && medians.is_some_and(|m| !m.contains_key(name)) =>
                {
                    return Err(refusal(
                        path,
                        format!(
                            "column `{name}` has {count} empty cell(s) but the model \
                                 stores no median for it (it had none at fit time or is \
                                 not one of its features)"
                        ),
                    ));
                }
                _ => {}
            }
        }
        // rows kept: under drop, no gap in a used numeric column; under impute, the target
        // present
        let keep: Vec<bool> = (0..n_rows)
            .map(|i| {
                self.names.iter().zip(&self.columns).all(|(n, c)| match c {
                    GappyColumn::Number(v) if used(n) => {
                        v[i].is_some()
                            || match policy {
                                MissingPolicy::Drop => false,
                                _ => Some(n.as_str()) != target,
                            }
                    }
                    _ => true,
                })
            })
            .collect();
        report.dropped_rows = keep.iter().filter(|k| !**k).count();
        if report.dropped_rows == n_rows {
            return Err(refusal(
                path,
                format!(
                    "--missing {}: every row has an empty cell, no row is left",
                    policy.name()
                ),
            ));
        }
        let mut out = MixedTable::default();
        for (name, col) in self.names.iter().zip(&self.columns) {
            match col {
                GappyColumn::Text(v) => out.push(
                    name,
                    Column::Text(
                        v.iter()
                            .zip(&keep)
                            .filter(|(_, k)| **k)
                            .map(|(s, _)| s.clone())
                            .collect(),
                    ),
                ),
                GappyColumn::Number(v) => {
                    let kept: Vec<Option<f64>> = v
                        .iter()
                        .zip(&keep)
                        .filter(|(_, k)| **k)
                        .map(|(x, _)| *x)
                        .collect();
                    let fill = if policy == MissingPolicy::Impute
                        && used(name)
                        && Some(name.as_str()) != target
                        && !protected.contains(&name.as_str())
                    {
                        let m = match medians {
                            Some(m) => m.get(name).copied(),
                            None => median(&kept),
                        };
                        if let Some(m) = m {
                            report.medians.insert(name.clone(), m);
                        }
                        m
                    } else {
                        None
                    };
                    let gaps = kept.iter().filter(|x| x.is_none()).count();
                    if gaps == 0 {
                        out.push(name, Column::Number(kept.into_iter().flatten().collect()));
                    } else if let Some(m) = fill {
                        report.filled.insert(name.clone(), gaps);
                        out.push(
                            name,
                            Column::Number(kept.into_iter().map(|x| x.unwrap_or(m)).collect()),
                        );
                    } else {
                        // an ignored column with gaps: text, as read_mixed_table keeps it
                        out.push(
                            name,
                            Column::Text(
                                kept.iter()
                                    .map(|x| x.map(|v| v.to_string()).unwrap_or_default())
                                    .collect(),
                            ),
                        );
                    }
                }
            }
        }
        Ok((out, report))
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)]
    use super::*;

    fn table(text: &str) -> (tempdir::Dir, GappyTable) {
        let dir = tempdir::Dir::new();
        let p = dir.0.join("t.csv");
        std::fs::write(&p, text).unwrap();
        let t = read_gappy_table(&p).unwrap();
        (dir, t)
    }

    mod tempdir {
        pub struct Dir(pub std::path::PathBuf);
        impl Dir {
            pub fn new() -> Self {
                use std::sync::atomic::{AtomicUsize, Ordering};
                static N: AtomicUsize = AtomicUsize::new(0);
                let p = std::env::temp_dir().join(format!(
                    "hxai-missing-{}-{}",
                    std::process::id(),
                    N.fetch_add(1, Ordering::Relaxed)
                ));
                std::fs::create_dir_all(&p).unwrap();
                Self(p)
            }
        }
        impl Drop for Dir {
            fn drop(&mut self) {
                let _ = std::fs::remove_dir_all(&self.0);
            }
        }
    }

    fn numbers(t: &MixedTable, name: &str) -> Vec<f64> {
        let i = t.names.iter().position(|n| n == name).unwrap();
        match &t.columns[i] {
            Column::Number(v) => v.clone(),
            Column::Text(v) => panic!("{name} is text: {v:?}"),
        }
    }

    const T: &str = "a,b,mat,y\n1,10,steel,5\n2,,steel,6\n3,30,alu,\n,40,alu,8\n5,50,steel,9\n";

    #[test]
    fn refuse_names_the_column_its_count_and_the_choices() {
        let (_d, t) = table(T);
        let err = t
            .resolve(MissingPolicy::Refuse, Some("y"), &[], &[], None)
            .unwrap_err()
            .to_string();
        assert!(err.contains("`a` has 1 empty cell"), "{err}");
        assert!(
            err.contains("--missing drop") && err.contains("--missing impute"),
            "{err}"
        );
        // a column left out does not count
        assert!(
            t.resolve(
                MissingPolicy::Refuse,
                Some("y"),
                &[],
                &["a", "b", "y"],
                None
            )
            .is_ok()
        );
    }

    #[test]
    fn drop_keeps_the_complete_rows_and_counts_the_others() {
        let (_d, t) = table(T);
        let (m, r) = t
            .resolve(MissingPolicy::Drop, Some("y"), &[], &[], None)
            .unwrap();
        assert_eq!(r.dropped_rows, 3);
        assert_eq!(numbers(&m, "a"), vec![1.0, 5.0]);
        assert_eq!(numbers(&m, "y"), vec![5.0, 9.0]);
        assert_eq!(
            m.columns[2],
            Column::Text(vec!["steel".into(), "steel".into()])
        );
    }

    #[test]
    fn impute_fills_features_with_training_medians_and_never_the_target() {
        let (_d, t) = table(T);
        let (m, r) = t
            .resolve(MissingPolicy::Impute, Some("y"), &[], &[], None)
            .unwrap();
        // the row without a target is dropped; the medians are those of the kept rows
        assert_eq!(r.dropped_rows, 1);
        assert_eq!(numbers(&m, "y"), vec![5.0, 6.0, 8.0, 9.0]);
        // a: 1, 2, _, 5 -> median 2; b: 10, _, 40, 50 -> median 40
        assert_eq!(numbers(&m, "a"), vec![1.0, 2.0, 2.0, 5.0]);
        assert_eq!(numbers(&m, "b"), vec![10.0, 40.0, 40.0, 50.0]);
        assert_eq!(r.medians.get("a"), Some(&2.0));
        assert_eq!(r.filled.get("b"), Some(&1));
        assert!(!r.medians.contains_key("y"));
        // stored medians replace the table's own (predict)
        let stored: BTreeMap<String, f64> = [("a".to_string(), 7.0), ("b".to_string(), 0.5)]
            .into_iter()
            .collect();
        let (m, _) = t
            .resolve(MissingPolicy::Impute, Some("y"), &[], &[], Some(&stored))
            .unwrap();
        assert_eq!(numbers(&m, "a"), vec![1.0, 2.0, 7.0, 5.0]);
        // a protected column's gap is refused, naming it
        let err = t
            .resolve(MissingPolicy::Impute, Some("y"), &["a"], &[], None)
            .unwrap_err()
            .to_string();
        assert!(err.contains("`a`") && err.contains("physics"), "{err}");
        // a gap in a column without a stored median is refused
        let only_a: BTreeMap<String, f64> = [("a".to_string(), 7.0)].into_iter().collect();
        let err = t
            .resolve(MissingPolicy::Impute, Some("y"), &[], &[], Some(&only_a))
            .unwrap_err()
            .to_string();
        assert!(err.contains("`b`") && err.contains("no median"), "{err}");
    }

    #[test]
    fn an_empty_column_and_a_table_with_no_complete_row_are_refused() {
        let (_d, t) = table("a,e,y\n1,,2\n2,,3\n3,,5\n");
        for p in [MissingPolicy::Drop, MissingPolicy::Impute] {
            let err = t
                .resolve(p, Some("y"), &[], &[], None)
                .unwrap_err()
                .to_string();
            assert!(err.contains("`e`") && err.contains("every row"), "{err}");
        }
        let (_d, t) = table("a,b,y\n1,,2\n,2,3\n");
        let err = t
            .resolve(MissingPolicy::Drop, Some("y"), &[], &[], None)
            .unwrap_err()
            .to_string();
        assert!(err.contains("no row is left"), "{err}");
        assert_eq!(MissingPolicy::parse("Impute"), Ok(MissingPolicy::Impute));
        assert!(
            MissingPolicy::parse("zero")
                .unwrap_err()
                .contains("refuse, drop or impute")
        );
    }
}
