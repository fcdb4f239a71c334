//! One spec in, a complete model out (issue 66): the caller (the CLI, Python) builds one
//! [`TableConfig`] with every setting, the per-level ones ([`PerLevel`]) and what its
//! reader did with empty cells ([`TableConfig::missing`]) included, and hands it with the
//! table to [`prepare`]; the [`Prepared`] fit, comparison and stability then return models
//! that need nothing patched afterwards (`per_class`, `missing`, the reader's notes).

use super::per_class::{self, PerClassInfo};
use super::{Comparison, TableConfig, TableModel, TableProgress, check_text_columns};
use crate::HybridError;
use hxai_eval::Split;
use hxai_symreg::Table;
use serde::{Deserialize, Serialize};

/// `--calibrate-per COL=P1,P2`: physics parameters fitted once per level of a column.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct CalibratePer {
    /// The column whose levels get their own parameters (text, or numbers read as levels).
    pub column: String,
    /// The physics parameters fitted once per level.
    pub parameters: Vec<String>,
}

/// The per-level settings of a fit, as asked (before [`prepare`] writes them out).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct PerLevel {
    /// `--calibrate-per`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibrate: Option<CalibratePer>,
    /// `--correction-per COL`: the correction's constants refitted per level of `COL`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correction: Option<String>,
}

/// A table and its configuration ready to fit: the per-level settings written out (the
/// physics' per-level parameters, the level indicator columns), the text columns checked.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// The configuration, per-level settings written out.
    pub cfg: TableConfig,
    /// The numeric table with the level indicator columns.
    pub table: Table,
    /// `--calibrate-per`: the column, its levels and the parameters fitted per level.
    pub per_class: Option<PerClassInfo>,
    /// Warnings about the input for the user (text columns left out of the features); not
    /// written into the model file.
    pub warnings: Vec<String>,
    /// Notes about the input that the model file keeps among its warnings (what the reader
    /// did with empty cells).
    notes: Vec<String>,
}

/// Prepares `table` (numbers) and its text columns `text` (each with its cells) for a fit
/// of `cfg`: the per-level settings written out, the text columns checked against what
/// the configuration names; `notes` are what the reader did with the table (kept in the
/// model file's warnings).
///
/// # Errors
/// A per-level column the table lacks or with one level, a per-level parameter not in the
/// physics, a text column where numbers are needed (naming the row and cell).
pub fn prepare(
    cfg: &TableConfig,
    mut table: Table,
    text: &[(String, Vec<String>)],
    notes: Vec<String>,
) -> Result<Prepared, HybridError> {
    let mut cfg = cfg.clone();
    let per_class = match cfg.per_level.calibrate.clone() {
        Some(cp) => {
            let cells = level_cells(&table, text, &cp.column, "--calibrate-per")?;
            let info = per_class::expand(&mut cfg, &mut table, &cp.column, &cells, &cp.parameters)?;
            // the column's levels are in the physics now, never a feature
            if cfg.features.is_none() && !cfg.exclude.contains(&cp.column) {
                cfg.exclude.push(cp.column);
            }
            Some(info)
        }
        None => None,
    };
    if let Some(col) = cfg.per_level.correction.clone() {
        let cells = level_cells(&table, text, &col, "--correction-per")?;
        super::correction_per::expand(&mut cfg, &mut table, &col, &cells)?;
        if cfg.features.is_none() && !cfg.exclude.contains(&col) {
            cfg.exclude.push(col);
        }
    }
    let warnings = check_text_columns(&cfg, text)?;
    // a text column is never a feature: excluding it needs no word to the fit, which sees
    // the numeric columns only
    cfg.exclude.retain(|e| !text.iter().any(|(n, _)| n == e));
    Ok(Prepared {
        cfg,
        table,
        per_class,
        warnings,
        notes,
    })
}

/// The cells of `col` as level names ([`per_class::level_cells`]), the flag that asked
/// for them named where the table lacks it.
fn level_cells(
    table: &Table,
    text: &[(String, Vec<String>)],
    col: &str,
    flag: &str,
) -> Result<Vec<String>, HybridError> {
    per_class::level_cells(table, text, col).map_err(|columns| {
        HybridError::InvalidConfig(format!(
            "{flag} {col}: the table has no column `{col}` (its columns: {columns})"
        ))
    })
}

impl Prepared {
    /// What the fit itself does not know: the per-class levels, the reader's handling of
    /// empty cells and its notes.
    fn complete(&self, model: &mut TableModel) {
        model.per_class.clone_from(&self.per_class);
        model.missing.clone_from(&self.cfg.missing);
        model.warnings.extend(self.notes.iter().cloned());
    }

    /// [`super::fit`] on the split the configuration chooses: a complete model.
    ///
    /// # Errors
    /// Those of [`super::fit`].
    pub fn fit(&self, progress: &mut dyn FnMut(&TableProgress)) -> Result<TableModel, HybridError> {
        let mut model = super::fit(&self.table, &self.cfg, progress)?;
        self.complete(&mut model);
        Ok(model)
    }

    /// [`super::fit_split`] on `split`: a complete model.
    ///
    /// # Errors
    /// Those of [`super::fit_split`].
    pub fn fit_split(
        &self,
        split: &Split,
        progress: &mut dyn FnMut(&TableProgress),
    ) -> Result<TableModel, HybridError> {
        let mut model = super::fit_split(&self.table, &self.cfg, split, progress)?;
        self.complete(&mut model);
        Ok(model)
    }

    /// [`super::compare`] with `folds` folds, its hybrid a complete model.
    ///
    /// # Errors
    /// Those of [`super::compare`].
    pub fn compare(
        &self,
        folds: usize,
        progress: &mut dyn FnMut(&TableProgress),
    ) -> Result<Comparison, HybridError> {
        let mut c = super::compare(&self.table, &self.cfg, folds, progress)?;
        self.complete(&mut c.hybrid);
        Ok(c)
    }

    /// [`super::measure_stability`] of `model` (fitted from this) over `runs` resamples.
    ///
    /// # Errors
    /// Those of [`super::measure_stability`].
    pub fn measure_stability(
        &self,
        model: &mut TableModel,
        runs: usize,
        progress: &mut (dyn FnMut(usize, usize) + Send),
    ) -> Result<(), HybridError> {
        super::measure_stability(&self.table, &self.cfg, model, runs, progress)
    }
}
