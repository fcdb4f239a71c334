//! Per-class constants of the correction (`--correction-per COL`, issue 48): the same
//! correction structure for every level of a text column, its constants refitted on each
//! level's training rows ("the same law, its constants per batch of material"), as PySR's
//! parametric expressions let a template's constants differ per class.
//!
//! How: the search finds one correction on every training row, as without the option; then,
//! for each level, all its constants (those the search snapped to whole or half numbers
//! too: a batch's slope may be another simple number) are refitted to that level's `delta`
//! by the Levenberg-Marquardt refit the conformal folds use ([`crate::conformal::refit_these`]),
//! starting from the shared values. A level with
//! fewer training rows than its constants plus two keeps the shared constants (a warning
//! names it). The levels are read from indicator columns (`COL=level`, 1 on the level's rows),
//! built as `--calibrate-per` builds them ([`super::per_class`]), so the library sees only
//! numbers; they are never features of the correction.
//!
//! The model file's `correction_per` holds the column, the levels, each level's constants,
//! equation and training rows; `predict` and `evaluate` use the row's level's constants and
//! refuse a level the fit never saw. The model's `correction` and `hybrid` equations are
//! the shared ones. Prediction intervals are not built for per-level constants yet (the
//! conformal calibration and the delta method both assume one set of constants): asking for
//! them is refused, naming the reason.

use crate::HybridError;
use hxai_symreg::{Model, Table};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The column whose levels get their own correction constants, and its levels (a fit's
/// setting: [`super::TableConfig::correction_per`]).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CorrectionPer {
    /// The text column.
    pub column: String,
    /// Its levels, sorted.
    pub levels: Vec<String>,
}

impl CorrectionPer {
    /// The indicator column of `level` (`COL=level`, as [`super::PerClassInfo::indicator`]).
    pub fn indicator(&self, level: &str) -> String {
        super::per_class::indicator_name(&self.column, level)
    }

    /// The level of each row of `table`, as an index into `levels`, from the indicator
    /// columns.
    ///
    /// # Errors
    /// [`HybridError::MissingColumn`] for an indicator the table lacks;
    /// [`HybridError::InvalidConfig`] for a row in no level.
    pub fn rows_levels(&self, table: &Table) -> Result<Vec<usize>, HybridError> {
        let mut out = vec![usize::MAX; table.n_rows()];
        for (l, level) in self.levels.iter().enumerate() {
            let name = self.indicator(level);
            let col = table
                .column(&name)
                .ok_or_else(|| HybridError::MissingColumn {
                    what: "level indicator of --correction-per",
                    name: name.clone(),
                    columns: table.names().join(", "),
                })?;
            for (i, &v) in col.iter().enumerate() {
                if v == 1.0 {
                    out[i] = l;
                }
            }
        }
        if let Some(i) = out.iter().position(|&l| l == usize::MAX) {
            return Err(HybridError::InvalidConfig(format!(
                "row {} has no level of `{}` the model knows ({})",
                i + 1,
                self.column,
                self.levels.join(", ")
            )));
        }
        Ok(out)
    }
}

/// A fitted correction's constants per level (the model file's `correction_per`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CorrectionPerInfo {
    /// The text column.
    pub column: String,
    /// Its levels, sorted.
    pub levels: Vec<String>,
    /// Each level's parameters of the correction's program (output scale and offset, then
    /// each node's), in the order of the shared model's `params`.
    pub params: BTreeMap<String, Vec<f64>>,
    /// Each level's correction, as text (4 significant digits).
    pub equations: BTreeMap<String, String>,
    /// Training rows of each level.
    pub rows: BTreeMap<String, usize>,
    /// Levels that kept the shared constants (too few training rows to refit them).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub shared: Vec<String>,
}

impl CorrectionPerInfo {
    /// The setting these constants were fitted under.
    pub fn setting(&self) -> CorrectionPer {
        CorrectionPer {
            column: self.column.clone(),
            levels: self.levels.clone(),
        }
    }

    /// The correction with `level`'s constants.
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] for a corrupt file (a level without constants, or
    /// constants of another length).
    pub fn model_at(&self, shared: &Model, level: &str) -> Result<Model, HybridError> {
        let params = self.params.get(level).ok_or_else(|| {
            HybridError::InvalidConfig(format!(
                "the model file's correction_per has no constants for level {level:?}"
            ))
        })?;
        if params.len() != shared.params.len() {
            return Err(HybridError::InvalidConfig(format!(
                "the model file's correction_per holds {} constants for level {level:?}, the \
                 correction has {}",
                params.len(),
                shared.params.len()
            )));
        }
        let mut m = shared.clone();
        m.params.clone_from(params);
        Ok(m)
    }

    /// The correction on every row of `table`, each row with its level's constants.
    ///
    /// # Errors
    /// As [`CorrectionPer::rows_levels`] and [`Self::model_at`], and the model's own.
    pub fn predict(&self, shared: &Model, table: &Table) -> Result<Vec<f64>, HybridError> {
        let levels = self.setting().rows_levels(table)?;
        let mut out = vec![f64::NAN; table.n_rows()];
        for (l, level) in self.levels.iter().enumerate() {
            let rows: Vec<usize> = (0..levels.len()).filter(|&i| levels[i] == l).collect();
            if rows.is_empty() {
                continue;
            }
            let m = self.model_at(shared, level)?;
            let part = m.predict(&table.select_rows(&rows)?)?;
            for (&i, v) in rows.iter().zip(part) {
                out[i] = v;
            }
        }
        Ok(out)
    }

    /// One line per level for the terminal: its rows and its correction.
    pub fn lines(&self) -> Vec<String> {
        self.levels
            .iter()
            .map(|l| {
                format!(
                    "  {}={l} ({} training rows{}): {}",
                    self.column,
                    self.rows.get(l).copied().unwrap_or(0),
                    if self.shared.contains(l) {
                        ", shared constants"
                    } else {
                        ""
                    },
                    self.equations.get(l).map_or("", String::as_str)
                )
            })
            .collect()
    }
}

/// Adds the indicator columns of `column`'s levels (from its `cells`, one per row of
/// `table`) where the table lacks them, leaves them (and the column, where the table holds
/// it as numbers) out of the correction's features, and sets `cfg.correction_per`.
///
/// # Errors
/// [`HybridError::InvalidConfig`]: cells of another length, an empty level name (naming the
/// row), or a single level.
pub fn expand(
    cfg: &mut super::TableConfig,
    table: &mut Table,
    column: &str,
    cells: &[String],
) -> Result<CorrectionPer, HybridError> {
    let cells: Vec<String> = cells.iter().map(|c| c.trim().to_string()).collect();
    let levels = super::per_class::levels_for_fit(
        "--correction-per",
        column,
        &cells,
        table.n_rows(),
        "constants are the shared ones; leave the option out",
    )?;
    super::per_class::push_missing_indicators(column, &levels, table, &cells)?;
    let setting = CorrectionPer {
        column: column.to_string(),
        levels,
    };
    for level in &setting.levels {
        let name = setting.indicator(level);
        if !cfg.exclude.contains(&name) {
            cfg.exclude.push(name.clone());
        }
        if let Some(f) = cfg.features.as_mut() {
            f.retain(|x| x != &name);
        }
    }
    // a column of numbers read as level names is in the table: never a feature either
    if cfg.features.is_none()
        && table.column(column).is_some()
        && !cfg.exclude.iter().any(|e| e == column)
    {
        cfg.exclude.push(column.to_string());
    }
    cfg.strata
        .extend(setting.levels.iter().map(|l| setting.indicator(l)));
    cfg.correction_per = Some(setting.clone());
    Ok(setting)
}

/// Appends the indicator columns of a model's `correction_per` to a table read for it, from
/// the text column's `cells` (one per row); refuses a level the fit never saw, naming the
/// row and the levels known.
///
/// # Errors
/// [`HybridError::InvalidConfig`] as described, or for cells of another length.
pub fn add_indicators(
    info: &CorrectionPerInfo,
    table: &mut Table,
    cells: &[String],
) -> Result<(), HybridError> {
    let cells: Vec<String> = cells.iter().map(|c| c.trim().to_string()).collect();
    super::per_class::add_level_indicators(&info.column, &info.levels, "correction", table, &cells)
}

/// Each level's constants of the `shared` correction (its feature columns `features`, every
/// row of `table`), refitted to `delta` (the correction's target on the training rows
/// `train`, in their order) on that level's training rows; a level with fewer rows than the
/// correction's constants plus two keeps the shared ones.
///
/// # Errors
/// As [`CorrectionPer::rows_levels`].
pub(crate) fn fit_levels(
    setting: &CorrectionPer,
    (shared, features): (&Model, &[&[f64]]),
    table: &Table,
    train: &[usize],
    delta: &[f64],
) -> Result<CorrectionPerInfo, HybridError> {
    let levels = setting.rows_levels(table)?;
    // every constant, the snapped ones too: a batch's slope may be another simple number
    let free: Vec<usize> = (0..shared.params.len()).collect();
    let mut info = CorrectionPerInfo {
        column: setting.column.clone(),
        levels: setting.levels.clone(),
        params: BTreeMap::new(),
        equations: BTreeMap::new(),
        rows: BTreeMap::new(),
        shared: Vec::new(),
    };
    for (l, level) in setting.levels.iter().enumerate() {
        let pos: Vec<usize> = (0..train.len())
            .filter(|&k| levels[train[k]] == l)
            .collect();
        let rows: Vec<usize> = pos.iter().map(|&k| train[k]).collect();
        let m = if rows.len() >= free.len() + 2 {
            let d: Vec<f64> = pos.iter().map(|&k| delta[k]).collect();
            let cols: Vec<Vec<f64>> = features
                .iter()
                .map(|c| rows.iter().map(|&i| c[i]).collect())
                .collect();
            let cols: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
            crate::conformal::refit_these(shared, &free, &cols, &d, features)
        } else {
            info.shared.push(level.clone());
            shared.clone()
        };
        info.equations.insert(level.clone(), m.equation());
        info.params.insert(level.clone(), m.params.clone());
        info.rows.insert(level.clone(), rows.len());
    }
    Ok(info)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_are_read_from_the_indicators_and_a_row_without_one_is_named()
    -> Result<(), HybridError> {
        let setting = CorrectionPer {
            column: "m".into(),
            levels: vec!["A".into(), "B".into()],
        };
        let t = Table::new(
            vec!["m=A".into(), "m=B".into()],
            vec![vec![1.0, 0.0, 1.0], vec![0.0, 1.0, 0.0]],
        )?;
        assert_eq!(setting.rows_levels(&t)?, vec![0, 1, 0]);
        let bad = Table::new(
            vec!["m=A".into(), "m=B".into()],
            vec![vec![1.0, 0.0], vec![0.0, 0.0]],
        )?;
        let e = setting.rows_levels(&bad).err().map(|e| e.to_string());
        assert!(e.is_some_and(|e| e.contains("row 2")));
        Ok(())
    }

    #[test]
    fn expand_refuses_one_level_and_empty_names() {
        let mut cfg = super::super::TableConfig::new("y", "x");
        let t = || Table::new(vec!["x".into()], vec![vec![1.0, 2.0]]);
        let Ok(mut t1) = t() else { return };
        let e = expand(&mut cfg, &mut t1, "m", &["a".into(), "a".into()]).err();
        assert!(e.is_some_and(|e| e.to_string().contains("one level")));
        let Ok(mut t2) = t() else { return };
        let e = expand(&mut cfg, &mut t2, "m", &["a".into(), " ".into()]).err();
        assert!(e.is_some_and(|e| e.to_string().contains("row 2")));
        let Ok(mut t1) = t() else { return };
        let e = expand(&mut cfg, &mut t1, "m", &["b".into(), "a".into()]).err();
        assert!(e.is_some_and(|e| e.to_string().contains("\"a\" (1 row), \"b\" (1 row)")));
        let Ok(mut t3) = Table::new(vec!["x".into()], vec![vec![1.0, 2.0, 3.0, 4.0]]) else {
            return;
        };
        let cells = ["b".into(), "a".into(), "b".into(), "a".into()];
        let ok = expand(&mut cfg, &mut t3, "m", &cells);
        assert!(ok.is_ok_and(|s| s.levels == vec!["a".to_string(), "b".to_string()]));
        assert_eq!(t3.column("m=b"), Some(&[1.0, 0.0, 1.0, 0.0][..]));
        assert!(cfg.exclude.contains(&"m=a".to_string()));
        assert!(cfg.strata.contains(&"m=b".to_string()));
    }
}
