//! Applying a tool-position hybrid model: prediction of a record, prediction intervals of
//! the corrected amplitude and of the displacement, and the explanation of the correction.

use super::RecordModel;
use crate::HybridError;
use crate::explain::{ExplainData, Explanation};
use crate::records::composer::RecordPrediction;
use crate::records::sample::{RecordInput, WindowSample};
use crate::records::warnings::input_warnings;
use hxai_eval::IntervalMethod;

impl RecordModel {
    /// Physics and hybrid prediction of one record, with warnings about implausible input
    /// ([`input_warnings`]) in [`RecordPrediction::warnings`].
    ///
    /// # Errors
    /// [`HybridError::FrequencyOutOfBand`] when the record's frequency lies outside the
    /// physics model's band, and the composer's errors.
    pub fn predict(&self, record: &RecordInput<'_>) -> Result<RecordPrediction, HybridError> {
        self.check_band(record)?;
        let mut p = self.hybrid().predict(record, self.correction()?)?;
        p.warnings = input_warnings(record, &self.window);
        Ok(p)
    }

    /// The interval method used at `level` when none is asked for: conformal (CV+) when the
    /// file stores its calibration and it has enough scores for `level`
    /// ([`crate::conformal::ConformalInfo::serves`]: 19 at 95 %), else the delta method when it stores the correction's
    /// uncertainty, else none (the zero correction).
    pub fn default_interval_method(&self, level: f64) -> Option<IntervalMethod> {
        crate::intervals::default_method(
            self.conformal.as_ref(),
            self.correction.uncertainty.is_some(),
            level,
        )
    }

    /// Prediction intervals at `level` of the corrected amplitude by the model's default
    /// method ([`RecordModel::default_interval_method`]).
    ///
    /// # Errors
    /// As [`RecordModel::amplitude_intervals_with`].
    pub fn amplitude_intervals(
        &self,
        samples: &[WindowSample],
        level: f64,
    ) -> Result<Vec<(f64, f64)>, HybridError> {
        let method = self
            .default_interval_method(level)
            .unwrap_or(IntervalMethod::Delta);
        self.amplitude_intervals_with(samples, level, method)
    }

    /// Prediction intervals at `level` of the corrected amplitude `A_corr = A_phys +
    /// delta_hat` of each sample: `A_phys` plus the interval of `delta_hat` by `method`:
    ///
    /// - [`IntervalMethod::Conformal`]: CV+ over the fit's folds of training records (the
    ///   correction's constants refitted without each fold, scores normalised by the local
    ///   scale; [`crate::conformal::ConformalInfo`]); coverage at least `2 level - 1`, in
    ///   practice near `level`, for windows exchangeable with the training windows.
    /// - [`IntervalMethod::Split`]: split conformal with the first fold's model and scores.
    /// - [`IntervalMethod::Delta`]: the delta method through the correction with the
    ///   covariance of its constants, plus the residual variance of `delta` on the training
    ///   windows (see `hxai_symreg::uncertainty` for the assumptions).
    ///
    /// The zero correction has none.
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] when the model cannot serve `method` (the zero
    /// correction, or a file from before it existed, or fitted with `--conformal-folds 0`:
    /// refit), a `level` outside (0, 1), and the correction's errors.
    pub fn amplitude_intervals_with(
        &self,
        samples: &[WindowSample],
        level: f64,
        method: IntervalMethod,
    ) -> Result<Vec<(f64, f64)>, HybridError> {
        let table = self.hybrid().feature_table(samples)?;
        let iv = self.correction_intervals(&table, level, method)?;
        Ok(samples
            .iter()
            .zip(iv)
            .map(|(s, (lo, hi))| (s.a_phys() + lo, s.a_phys() + hi))
            .collect())
    }

    /// Prediction intervals at `level` of the correction `delta_hat` by `method` for every
    /// row of a feature table (the windows' features, named as the feature map names them):
    /// the part of [`RecordModel::amplitude_intervals_with`] before the shift by `A_phys`.
    ///
    /// # Errors
    /// As [`RecordModel::amplitude_intervals_with`].
    pub fn correction_intervals(
        &self,
        table: &hxai_table::Table,
        level: f64,
        method: IntervalMethod,
    ) -> Result<Vec<(f64, f64)>, HybridError> {
        crate::intervals::check_level(level)?;
        let (Some(model), Some(unc)) = (&self.correction.model, &self.correction.uncertainty)
        else {
            return Err(HybridError::InvalidConfig(
                "this model stores no uncertainty of its correction (a zero correction, or a \
                 file written before prediction intervals existed): refit it with `hxai fit`"
                    .into(),
            ));
        };
        Ok(if method == IntervalMethod::Delta {
            model.prediction_intervals(unc, table, level)?
        } else {
            let Some(conf) = &self.conformal else {
                return Err(crate::intervals::no_conformal(method, "hxai fit"));
            };
            conf.model_intervals(model, table, level, method)?
        })
    }

    /// [`RecordModel::predict`] with pointwise bounds of the displacement: each window's
    /// sine reconstructed with the lower and the upper corrected amplitude of
    /// [`RecordModel::amplitude_intervals`] (the model's default method; the smaller and
    /// larger value at each sample). The band carries the amplitude's uncertainty only, not the phase's or the noise of
    /// the probe.
    ///
    /// # Errors
    /// As [`RecordModel::predict`] and [`RecordModel::amplitude_intervals`].
    pub fn predict_with_intervals(
        &self,
        record: &RecordInput<'_>,
        level: f64,
    ) -> Result<(RecordPrediction, Vec<f64>, Vec<f64>), HybridError> {
        let method = self
            .default_interval_method(level)
            .unwrap_or(IntervalMethod::Delta);
        self.predict_with_intervals_by(record, level, method)
    }

    /// [`RecordModel::predict_with_intervals`] with the amplitude's intervals made by
    /// `method` ([`RecordModel::amplitude_intervals_with`]).
    ///
    /// # Errors
    /// As [`RecordModel::predict`] and [`RecordModel::amplitude_intervals_with`].
    pub fn predict_with_intervals_by(
        &self,
        record: &RecordInput<'_>,
        level: f64,
        method: IntervalMethod,
    ) -> Result<(RecordPrediction, Vec<f64>, Vec<f64>), HybridError> {
        let p = self.predict(record)?;
        let iv = self.amplitude_intervals_with(&p.samples, level, method)?;
        let with = |pick: fn(&(f64, f64)) -> f64| -> Vec<f64> {
            let windows: Vec<_> = p
                .windows
                .iter()
                .zip(&iv)
                .map(|(w, b)| crate::records::composer::WindowPrediction {
                    corrected: crate::records::composer::corrected_latent(
                        &w.physics,
                        pick(b) - w.physics.amplitude,
                    ),
                    ..*w
                })
                .collect();
            crate::records::composer::reconstruct_record(
                &windows,
                record.signal.len(),
                record.fs_hz,
                record.frequency_hz,
            )
        };
        let a = with(|b| b.0);
        let b = with(|b| b.1);
        let lo = a.iter().zip(&b).map(|(x, y)| x.min(*y)).collect();
        let hi = a.iter().zip(&b).map(|(x, y)| x.max(*y)).collect();
        Ok((p, lo, hi))
    }

    /// The explanation of the correction ([`crate::explain::explain`]): with `data` (the
    /// samples of a fit: features, `delta`, split) its response to each feature it uses and
    /// predicted vs true `delta`, with prediction intervals of the correction at `level` by
    /// `method` (default: the file's, [`RecordModel::default_interval_method`]; none for a
    /// file that stores no way to make them); the Pareto front when the file stores it.
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] for the zero correction (nothing to explain), and those
    /// of [`crate::explain::explain`].
    pub fn explain(
        &self,
        data: Option<&ExplainData<'_>>,
        level: f64,
        method: Option<IntervalMethod>,
    ) -> Result<Explanation, HybridError> {
        let band = method
            .or_else(|| self.default_interval_method(level))
            .map(|m| {
                (m, move |t: &hxai_table::Table, l: f64| {
                    self.correction_intervals(t, l, m)
                })
            });
        self.correction.explain(
            band.as_ref()
                .map(|(m, b)| (b as &crate::explain::Band<'_>, *m)),
            data,
            level,
        )
    }
}
