//! Applying a table hybrid to a table: physics, correction and hybrid per row, the
//! prediction intervals by each method, the rows outside the training ranges, and the
//! explanation of the correction.

use super::{TableModel, TablePrediction, columns_of, combine, combine_values};
use super::{compile_physics, finite_physics};
use crate::HybridError;
use hxai_eval::IntervalMethod;
use hxai_symreg::infix::Compiled;
use hxai_symreg::{Table, expr::Expr};

impl TableModel {
    /// The physics equation compiled with the model's parameter values.
    ///
    /// # Errors
    /// A corrupt model file (the equation does not parse or names an unknown symbol).
    pub fn physics_program(&self) -> Result<Compiled, HybridError> {
        compile_physics(
            &self.physics.equation,
            &self.physics.columns,
            &self.physics.parameters,
        )
    }

    /// Appends to `table` the indicator columns of the levels the model has constants for
    /// (of its physics, `per_class`, or its correction, `correction_per`), from the cells
    /// of each such column in `text` (trimmed), or of a numeric column of `table` (its
    /// numbers as written). Nothing to do for a model without per-level constants.
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] for a level column the rows lack, or a level the
    /// model was not fitted on (naming the row, the level and the levels known).
    pub fn add_levels(
        &self,
        table: &mut Table,
        text: &[(String, Vec<String>)],
    ) -> Result<(), HybridError> {
        let cells_of = |table: &Table, column: &str, what: &str| {
            crate::tables::per_class::level_cells(table, text, column).map_err(|columns| {
                HybridError::InvalidConfig(format!(
                    "the model's {what} has constants per level of `{column}`, which the rows \
                     do not give (their columns: {columns})"
                ))
            })
        };
        if let Some(cp) = &self.correction_per {
            let cells = cells_of(table, &cp.column, "correction")?;
            crate::tables::correction_per::add_indicators(cp, table, &cells)?;
        }
        if let Some(pc) = &self.per_class {
            let cells = cells_of(table, &pc.column, "physics")?;
            crate::tables::per_class::add_indicators(pc, table, &cells)?;
        }
        Ok(())
    }

    /// Physics, correction and hybrid for every row of `table` (the target is not needed;
    /// extra columns are ignored).
    ///
    /// # Errors
    /// [`HybridError::MissingColumn`] for a column the model needs;
    /// [`HybridError::BadPhysics`] naming the first row where the physics is not finite.
    pub fn predict(&self, table: &Table) -> Result<TablePrediction, HybridError> {
        let phys = self.physics_program()?;
        let physics = finite_physics(table, &phys, &phys.inputs)?;
        let model = self.correction.fitted()?;
        columns_of(table, &model.feature_names, "correction feature")?;
        let correction = match &self.correction_per {
            Some(cp) => cp.predict(model, table)?,
            None => model.predict(table)?,
        };
        if let Some((row, v)) = correction.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(HybridError::BadCorrection { row, value: *v });
        }
        let hybrid = physics
            .iter()
            .zip(&correction)
            .map(|(p, d)| combine_values(self.correction.kind, *p, *d))
            .collect();
        Ok(TablePrediction {
            physics,
            correction,
            hybrid,
        })
    }

    /// Whether the model has a value at each row of `table` (its physics and correction
    /// both finite there): the rows [`TableModel::predict`] accepts, from one evaluation.
    ///
    /// # Errors
    /// Those of [`TableModel::predict`] other than a row without a value.
    pub fn defined_rows(&self, table: &Table) -> Result<Vec<bool>, HybridError> {
        let phys = self.physics_program()?;
        let cols = columns_of(table, &phys.inputs, "physics column")?;
        let physics = phys.eval_columns(&cols, table.n_rows());
        let model = self.correction.fitted()?;
        columns_of(table, &model.feature_names, "correction feature")?;
        let correction = match &self.correction_per {
            Some(cp) => cp.predict(model, table)?,
            None => model.predict(table)?,
        };
        Ok(physics
            .iter()
            .zip(&correction)
            .map(|(p, d)| p.is_finite() && d.is_finite())
            .collect())
    }

    /// Warnings for rows of `table` outside the ranges of the training rows, per input
    /// column of the hybrid ([`crate::tables::traps::range_warnings`]; the ranges are those the
    /// conformal calibration stores, so a file fitted without it gives none).
    pub fn range_warnings(&self, table: &Table) -> Vec<String> {
        let Some(w) = self.conformal.as_ref().and_then(|c| c.widening.as_ref()) else {
            return Vec::new();
        };
        let ranges: Vec<(String, f64, f64)> = w
            .columns
            .iter()
            .zip(w.lo.iter().zip(&w.hi))
            .map(|(n, (lo, hi))| (n.clone(), *lo, *hi))
            .collect();
        crate::tables::traps::range_warnings(table, &ranges)
    }

    /// For each row of `table`, whether it lies beside the data: any column the hybrid
    /// reads outside its training range by more than 10 % of the range's width
    /// ([`super::TrainingRanges::outside`]; the column `outside_training` of `predict`).
    /// A file written before the ranges were stored uses those of its conformal
    /// calibration, and without either every row is `false`.
    pub fn outside_training(&self, table: &Table) -> Vec<bool> {
        if let Some(t) = &self.training {
            return t.outside(table);
        }
        match self.conformal.as_ref().and_then(|c| c.widening.as_ref()) {
            Some(w) => super::TrainingRanges {
                columns: w
                    .columns
                    .iter()
                    .zip(w.lo.iter().zip(&w.hi))
                    .map(|(n, (lo, hi))| (n.clone(), [*lo, *hi]))
                    .collect(),
                target: [f64::NAN, f64::NAN],
            }
            .outside(table),
            None => vec![false; table.n_rows()],
        }
    }

    /// The warnings for `predictions` of `table`'s rows: how many rows lie beside the data
    /// ([`TableModel::outside_training`]), and the rows predicted with a sign the training
    /// target never had.
    pub fn prediction_warnings(&self, table: &Table, predictions: &[f64]) -> Vec<String> {
        let mut out = Vec::new();
        let outside = self.outside_training(table).iter().filter(|o| **o).count();
        if outside > 0 {
            out.push(format!(
                "{outside} of {} rows lie beside the data (a column outside its training range \
                 by more than 10 % of its width; column `outside_training` = 1): their \
                 predictions are extrapolations",
                table.n_rows()
            ));
        }
        if let Some(t) = &self.training {
            out.extend(t.sign_warning(predictions, "row(s)"));
        }
        out
    }

    /// Warnings for values of `table` in the columns the model reads that look like a
    /// missing-value code or are gross outliers among the table's rows
    /// ([`crate::tables::traps::value_warnings`]).
    pub fn value_warnings(&self, table: &Table) -> Vec<String> {
        let used = super::model_columns(self, false);
        crate::tables::traps::value_warnings(table, &used)
    }

    /// The interval method used at `level` when none is asked for: conformal (CV+) when the
    /// file stores its calibration and it has enough scores for `level`
    /// ([`crate::conformal::ConformalInfo::serves`]: 19 at 95 %), else the delta method when it stores the hybrid's
    /// uncertainty, else none (and none for constants per level, `correction_per`).
    pub fn default_interval_method(&self, level: f64) -> Option<IntervalMethod> {
        if self.correction_per.is_some() {
            // one set of constants is what both methods assume (intervals_with says so)
            return None;
        }
        crate::intervals::default_method(
            self.conformal.as_ref(),
            self.hybrid.uncertainty.is_some(),
            level,
        )
    }

    /// Prediction intervals `(lo, hi)` of the hybrid at `level` for every row of `table`, by
    /// the model's default method ([`TableModel::default_interval_method`]).
    ///
    /// # Errors
    /// As [`TableModel::intervals_with`]; [`HybridError::InvalidConfig`] when the file
    /// stores neither conformal calibration nor uncertainty.
    pub fn intervals(&self, table: &Table, level: f64) -> Result<Vec<(f64, f64)>, HybridError> {
        let method = self
            .default_interval_method(level)
            .unwrap_or(IntervalMethod::Delta);
        self.intervals_with(table, level, method)
    }

    /// Prediction intervals `(lo, hi)` of the hybrid at `level` for every row of `table` by
    /// `method`:
    ///
    /// - [`IntervalMethod::Conformal`]: CV+ over the folds of the fit with scores
    ///   normalised by the local scale ([`ConformalInfo`](crate::conformal::ConformalInfo));
    ///   coverage at least `2 level - 1` (in practice near `level`) for rows exchangeable
    ///   with the training rows.
    /// - [`IntervalMethod::Split`]: split conformal with the first fold's model, calibrated
    ///   on that fold's rows alone; coverage at least `level` for such rows.
    /// - [`IntervalMethod::Delta`]: the delta method through the whole hybrid equation
    ///   (calibrated physics parameters and the correction's free constants, with their
    ///   covariance on the training rows) plus the residual variance of the hybrid on the
    ///   training rows. Assumes independent residuals of constant variance and the structure
    ///   fixed; the physics parameters and the correction were fitted one after the other,
    ///   and their covariance is taken as if they had been fitted together (the joint fit's;
    ///   see `hxai_symreg::uncertainty`).
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] when the model file cannot serve `method` (no
    /// conformal calibration, or no uncertainty: a file written before they existed, or
    /// fitted without conformal folds: refit), too few calibration scores for `level`, a
    /// `level` outside (0, 1), a missing column, a non-finite value.
    pub fn intervals_with(
        &self,
        table: &Table,
        level: f64,
        method: IntervalMethod,
    ) -> Result<Vec<(f64, f64)>, HybridError> {
        crate::intervals::check_level(level)?;
        if let Some(cp) = &self.correction_per {
            return Err(HybridError::InvalidConfig(format!(
                "prediction intervals are not built for a correction with constants per level \
                 of `{}` (--correction-per): the conformal calibration and the delta method \
                 both assume one set of constants; predict without --interval, or refit \
                 without --correction-per",
                cp.column
            )));
        }
        let phys = self.physics_program()?;
        let c = combine(&phys, self.correction.fitted()?, self.correction.kind);
        if method != IntervalMethod::Delta {
            let Some(conf) = &self.conformal else {
                return Err(crate::intervals::no_conformal(method, "hxai hybrid fit"));
            };
            return conformal_intervals(conf, &c, table, level, method);
        }
        let Some(unc) = &self.hybrid.uncertainty else {
            return Err(HybridError::InvalidConfig(
                "this model file stores no uncertainty (written before prediction intervals \
                 existed): refit it with `hxai hybrid fit`"
                    .into(),
            ));
        };
        let cols = columns_of(table, &c.names, "column")?;
        Ok(unc.intervals(&c.program, &c.params, &cols, table.n_rows(), level)?)
    }

    /// The explanation of the correction ([`crate::explain::explain`]): with `table` (the
    /// table the model was fitted on, every row of its split present) the correction's
    /// response to each feature it uses and predicted vs true `delta` (`y - f_p`,
    /// `y / f_p - 1` for a multiplicative correction, `ln(y / f_p)` for the log form) on the
    /// split's rows, with prediction intervals of the correction at `level` by `method`
    /// (default: the file's,
    /// [`TableModel::default_interval_method`]; none when the file stores no way to make
    /// them); the Pareto front when the file stores it; a factor correction's response
    /// bands when its stability runs stored them.
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] when `table` has fewer rows than the split names, and
    /// those of [`TableModel::predict`] and [`crate::explain::explain`].
    pub fn explain(
        &self,
        table: Option<&Table>,
        level: f64,
        method: Option<IntervalMethod>,
    ) -> Result<crate::explain::Explanation, HybridError> {
        let mut e = self.explain_correction(table, level, method)?;
        if let Some(bands) = self.stability.as_ref().and_then(|s| s.bands.as_ref()) {
            e.factors = bands.iter().map(|(c, b)| (c.clone(), b.clone())).collect();
        }
        if let Some(table) = table {
            e.partial_residuals = self.partial_residuals(table)?;
        }
        Ok(e)
    }

    /// Each one-column factor's partial residuals on the training rows of `table` (the
    /// table of the fit): see [`crate::explain::Explanation::partial_residuals`]. Empty for
    /// a correction that is not in the factor form; rows where the residual is not a
    /// number (a fitted product at or below zero) are left out.
    ///
    /// # Errors
    /// A factor's equation that does not compile, or a column missing from `table`.
    pub fn partial_residuals(
        &self,
        table: &Table,
    ) -> Result<crate::explain::PartialResiduals, HybridError> {
        let Some(factors) = &self.correction.factors else {
            return Ok(Vec::new());
        };
        let rows = &self.split.train;
        let y = table.require(&self.target)?;
        let prediction = self.predict(table)?;
        let delta = super::deltas(self.correction.kind, y, &prediction.physics, rows)?;
        let fitted: Vec<f64> = rows.iter().map(|&i| prediction.correction[i]).collect();
        let link = self.correction.kind.link();
        // the row's whole residual, on the scale the factors combine on
        let residual: Vec<f64> = delta
            .iter()
            .zip(&fitted)
            .map(|(&d, &f)| match link {
                hxai_symreg::factors::Link::Additive => d - f,
                hxai_symreg::factors::Link::Multiplicative => (1.0 + d) / (1.0 + f),
                hxai_symreg::factors::Link::Log => (d - f).exp(),
            })
            .collect();
        let mut out = Vec::new();
        for f in factors {
            let Some(column) = &f.column else { continue };
            let g =
                hxai_symreg::infix::compile_text(&f.equation, &std::collections::BTreeMap::new())
                    .map_err(|e| {
                    HybridError::InvalidConfig(format!(
                        "the factor `{}` of {column} does not compile: {e}",
                        f.equation
                    ))
                })?;
            let x = table.require(column)?;
            let xs: Vec<f64> = rows.iter().map(|&i| x[i]).collect();
            let cols: Vec<&[f64]> = g.inputs.iter().map(|_| xs.as_slice()).collect();
            let values = g.eval_columns(&cols, xs.len());
            let finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
            if finite.is_empty() {
                continue;
            }
            let mean = finite.iter().sum::<f64>() / finite.len() as f64;
            let points: Vec<(f64, f64)> = xs
                .iter()
                .zip(&values)
                .zip(&residual)
                .map(|((&x, &v), &r)| {
                    let r = match link {
                        hxai_symreg::factors::Link::Additive => v - mean + r,
                        _ => v / mean * r,
                    };
                    (x, r)
                })
                .filter(|(x, r)| x.is_finite() && r.is_finite())
                .collect();
            out.push((column.clone(), points));
        }
        Ok(out)
    }

    /// [`TableModel::explain`] without the factor bands.
    fn explain_correction(
        &self,
        table: Option<&Table>,
        level: f64,
        method: Option<IntervalMethod>,
    ) -> Result<crate::explain::Explanation, HybridError> {
        let Some(table) = table else {
            return self.correction.explain(None, None, level);
        };
        let rows: Vec<usize> = self
            .split
            .train
            .iter()
            .chain(&self.split.test)
            .copied()
            .collect();
        if let Some(&i) = rows.iter().find(|&&i| i >= table.n_rows()) {
            return Err(HybridError::InvalidConfig(format!(
                "the model was fitted on a table with at least {} rows, this one has {}: pass the table the model was fitted on",
                i + 1,
                table.n_rows()
            )));
        }
        let y = columns_of(table, std::slice::from_ref(&self.target), "target")?[0];
        let prediction = self.predict(table)?;
        // The split's row numbers mean something only on the table of the fit: another
        // table of the same length would be drawn without a word. The hybrid's training
        // RMSE on these rows must be the one the model file stores.
        let train_y: Vec<f64> = self.split.train.iter().map(|&i| y[i]).collect();
        let train_hybrid: Vec<f64> = self
            .split
            .train
            .iter()
            .map(|&i| prediction.hybrid[i])
            .collect();
        let rmse = hxai_eval::rmse(&train_y, &train_hybrid)?;
        let stored = self.scores.train.hybrid.rmse;
        // 1 %: a copy of the table with its numbers rounded (to 6 digits, or through
        // another tool) is still the table; another table of the same length is not.
        if (rmse - stored).abs() > 0.01 * stored.abs() + 1e-12 {
            return Err(HybridError::InvalidConfig(format!(
                "this is not the table the model was fitted on: the hybrid's RMSE on its \
                 training rows is {} here and {} in the model file; pass the table given to \
                 `hxai hybrid fit`",
                crate::error::num(rmse),
                crate::error::num(stored)
            )));
        }
        let physics = prediction.physics;
        let delta = super::deltas(self.correction.kind, y, &physics, &rows)?;
        let features = table.select_rows(&rows)?;
        let is_test: Vec<bool> = (0..rows.len())
            .map(|k| k >= self.split.train.len())
            .collect();
        let data = crate::explain::ExplainData {
            features: &features,
            target: &delta,
            is_test: &is_test,
        };
        // the columns a response grid lacks (the physics' own) are held at their median
        // on the training rows, as the grid holds the correction's other features
        let phys = self.physics_program()?;
        let c = combine(&phys, self.correction.fitted()?, self.correction.kind);
        let mut fill = Vec::new();
        for name in &c.names {
            let col = table.require(name)?;
            let m = crate::explain::median(self.split.train.iter().map(|&i| col[i]))
                .ok_or_else(|| HybridError::NoData("no training rows to explain on".into()))?;
            fill.push((name.clone(), m));
        }
        let band = method
            .or_else(|| self.default_interval_method(level))
            .map(|m| {
                (m, move |t: &Table, l: f64| {
                    self.correction_intervals(t, l, m, &fill)
                })
            });
        let band = band
            .as_ref()
            .map(|(m, b)| (b as &crate::explain::Band<'_>, *m));
        self.correction.explain(band, Some(&data), level)
    }

    /// Prediction intervals of the correction `delta` at `level` by `method` for the rows of
    /// `features`: the hybrid's intervals ([`TableModel::intervals_with`]; a column
    /// `features` lacks is held at its value in `fill`) taken back to `delta` through the
    /// physics' prediction
    /// ([`CorrectionForm::delta_interval`](crate::tables::CorrectionForm::delta_interval)).
    fn correction_intervals(
        &self,
        features: &Table,
        level: f64,
        method: IntervalMethod,
        fill: &[(String, f64)],
    ) -> Result<Vec<(f64, f64)>, HybridError> {
        let mut names = features.names().to_vec();
        let mut cols: Vec<Vec<f64>> = names
            .iter()
            .map(|n| features.require(n).map(<[f64]>::to_vec))
            .collect::<Result<_, _>>()?;
        for (name, v) in fill {
            if !names.contains(name) {
                names.push(name.clone());
                cols.push(vec![*v; features.n_rows()]);
            }
        }
        let full = Table::new(names, cols)?;
        let iv = self.intervals_with(&full, level, method)?;
        let phys = self.physics_program()?;
        let physics = finite_physics(&full, &phys, &phys.inputs)?;
        Ok(iv
            .into_iter()
            .zip(physics)
            .map(|((lo, hi), p)| self.correction.kind.delta_interval(lo, hi, p))
            .collect())
    }

    /// The whole hybrid as one expression over the columns.
    ///
    /// # Errors
    /// A corrupt model file.
    pub fn hybrid_expr(&self) -> Result<Expr, HybridError> {
        let phys = self.physics_program()?;
        let c = combine(&phys, self.correction.fitted()?, self.correction.kind);
        Ok(Expr::from_program(&c.program, &c.params, &c.names))
    }
}

/// The table hybrid's intervals at `level` by `method` for every row of `table` from the
/// calibration `conf` (`c`: the model's one-program hybrid).
///
/// # Errors
/// Those of [`ConformalInfo::intervals_from`] and a missing column.
fn conformal_intervals(
    conf: &crate::conformal::ConformalInfo,
    c: &super::Combined,
    table: &Table,
    level: f64,
    method: IntervalMethod,
) -> Result<Vec<(f64, f64)>, HybridError> {
    let distance = match &conf.widening {
        Some(w) => Some(w.distances(table)?),
        None => None,
    };
    let iv = conf.intervals_by(
        |p| c.predict_with(p, table),
        distance.as_deref(),
        level,
        method,
    )?;
    Ok(crate::intervals::holding_points(
        iv,
        &c.predict_with(&c.params, table)?,
    ))
}
