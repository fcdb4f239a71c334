//! Step 5, validation against the ground truth: physics vs hybrid on chosen windows.

use crate::HybridError;
use crate::IntervalReport;
use crate::correction::CorrectionInfo;
use crate::records::composer::RecordHybrid;
use crate::records::sample::RecordInput;
use hxai_eval::Metrics;
use serde::{Deserialize, Serialize};

/// The serde form of a [`Metrics`] in the truth's unit (micrometres in the tool-position
/// case): keys `rmse_um`, `r2`, `mae_um`, in that order, as the model file and
/// `hxai evaluate --json` have always written them. Keys `rmse` and `mae` are read too.
pub(crate) mod metrics_um {
    use hxai_eval::Metrics;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Serialize, Deserialize)]
    struct Um {
        #[serde(alias = "rmse")]
        rmse_um: f64,
        r2: f64,
        #[serde(alias = "mae")]
        mae_um: f64,
    }

    impl From<&Metrics> for Um {
        fn from(m: &Metrics) -> Self {
            Um {
                rmse_um: m.rmse,
                r2: m.r2,
                mae_um: m.mae,
            }
        }
    }

    impl From<Um> for Metrics {
        fn from(u: Um) -> Self {
            Metrics {
                r2: u.r2,
                rmse: u.rmse_um,
                mae: u.mae_um,
            }
        }
    }

    pub(crate) fn serialize<S: Serializer>(m: &Metrics, s: S) -> Result<S::Ok, S::Error> {
        Um::from(m).serialize(s)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Metrics, D::Error> {
        Um::deserialize(d).map(Metrics::from)
    }

    /// The same for an optional [`Metrics`] (`null` when absent).
    pub(crate) mod option {
        use super::Um;
        use hxai_eval::Metrics;
        use serde::{Deserialize, Deserializer, Serialize, Serializer};

        pub(crate) fn serialize<S: Serializer>(
            m: &Option<Metrics>,
            s: S,
        ) -> Result<S::Ok, S::Error> {
            m.as_ref().map(Um::from).serialize(s)
        }

        pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
            d: D,
        ) -> Result<Option<Metrics>, D::Error> {
            Ok(Option::<Um>::deserialize(d)?.map(Metrics::from))
        }
    }
}

/// The result of [`evaluate`].
///
/// Definition: for every evaluated window the truth is the ground truth minus its window
/// mean; the physics prediction is the physics signal as it is; the hybrid prediction is
/// `x_hat = A_corr sin(omega t + phi_phys)`; the physics sine is `A_phys sin(omega t +
/// phi_phys)`, the hybrid with a zero correction, reported so the gain of the correction
/// alone is visible. RMSE, R^2 and MAE pool every sample of every window. The t-test pairs
/// the per-window mean squared errors of physics and hybrid.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Evaluation {
    /// Number of pooled samples (time points).
    pub n_samples: usize,
    /// Number of windows.
    pub n_windows: usize,
    /// Number of records.
    pub n_records: usize,
    /// The records evaluated.
    pub records: Vec<String>,
    /// The physics signal (RMSE and MAE in the truth's unit; JSON keys `rmse_um`, `r2`,
    /// `mae_um`).
    #[serde(with = "metrics_um")]
    pub physics: Metrics,
    /// The physics model's sine representation (zero correction).
    #[serde(with = "metrics_um")]
    pub physics_sine: Metrics,
    /// The hybrid model.
    #[serde(with = "metrics_um")]
    pub hybrid: Metrics,
    /// `(RMSE_phys - RMSE_hybrid) / RMSE_phys * 100`.
    pub improvement_pct: f64,
    /// The same against the physics sine: what the correction alone buys.
    pub improvement_vs_sine_pct: f64,
    /// `(R^2_hybrid - R^2_phys) / R^2_phys * 100`, as the paper quotes it.
    pub r2_change_pct: f64,
    /// Paired t-test; `None` with fewer than two windows (or identical errors).
    pub t_test: Option<hxai_eval::TTest>,
    /// How well `delta_hat` matches `delta = A_true - A_phys` over the windows (`None`
    /// when it cannot be scored, e.g. a single window).
    #[serde(default, with = "metrics_um::option")]
    pub delta: Option<Metrics>,
    /// Implausible but legal input, one line each (filled by
    /// [`crate::records::RecordModel::evaluate`]; empty from [`evaluate`]). Left out of the JSON
    /// when empty, so stored results do not change; `hxai evaluate --json` always has it.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// Coverage of the prediction intervals of the corrected amplitude (filled by
    /// [`crate::records::RecordModel::evaluate`] when the model stores the uncertainty of its
    /// correction; absent otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interval: Option<IntervalReport>,
}

/// Which windows of a record to evaluate.
#[derive(Debug, Clone, Copy)]
pub struct EvalInput<'a> {
    /// The record (must carry the truth).
    pub record: RecordInput<'a>,
    /// Window indices to use; `None` for all.
    pub windows: Option<&'a [usize]>,
}

fn mse(truth: &[f64], pred: &[f64]) -> f64 {
    truth
        .iter()
        .zip(pred)
        .map(|(t, p)| (t - p) * (t - p))
        .sum::<f64>()
        / truth.len() as f64
}

/// Evaluates physics and hybrid predictions on the given records and windows.
///
/// # Errors
/// [`HybridError::NoTruth`] for a record without truth, [`HybridError::NoData`] when no
/// window is selected, and the errors of [`RecordHybrid::predict`].
pub fn evaluate<K>(
    hybrid: &RecordHybrid,
    correction: &CorrectionInfo<K>,
    inputs: &[EvalInput<'_>],
) -> Result<Evaluation, HybridError> {
    let (mut truth, mut phys, mut sine, mut hyb) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut mse_p, mut mse_h) = (Vec::new(), Vec::new());
    let (mut delta, mut delta_hat) = (Vec::new(), Vec::new());
    let mut records = Vec::new();
    for inp in inputs {
        let rec = &inp.record;
        let t = rec.truth.ok_or_else(|| HybridError::NoTruth {
            record: rec.id.to_owned(),
        })?;
        let pred = hybrid.predict(rec, correction)?;
        let mut used = false;
        for (s, w) in pred.samples.iter().zip(&pred.windows) {
            if let Some(sel) = inp.windows
                && !sel.contains(&s.window)
            {
                continue;
            }
            used = true;
            let r = s.range.clone();
            let tw = &t[r.clone()];
            let m = tw.iter().sum::<f64>() / tw.len() as f64;
            let tw: Vec<f64> = tw.iter().map(|v| v - m).collect();
            let pw = &pred.physics[r.clone()];
            let hw = &pred.hybrid[r.clone()];
            let sw = crate::records::composer::corrected_latent(&s.physics, 0.0).sine(
                rec.fs_hz,
                rec.frequency_hz,
                0,
                r.len(),
            );
            mse_p.push(mse(&tw, pw));
            mse_h.push(mse(&tw, hw));
            truth.extend_from_slice(&tw);
            phys.extend_from_slice(pw);
            hyb.extend_from_slice(hw);
            sine.extend_from_slice(&sw);
            if let Some(d) = s.delta() {
                delta.push(d);
                delta_hat.push(w.delta_hat);
            }
        }
        if used {
            records.push(rec.id.to_owned());
        }
    }
    if truth.is_empty() {
        return Err(HybridError::NoData(
            "no window to evaluate: the selection is empty".into(),
        ));
    }
    let physics = hxai_eval::score(&truth, &phys)?;
    let physics_sine = hxai_eval::score(&truth, &sine)?;
    let hybrid_s = hxai_eval::score(&truth, &hyb)?;
    let t_test = if mse_p.len() >= 2 {
        hxai_eval::paired_t_test(&mse_p, &mse_h).ok()
    } else {
        None
    };
    let improvement =
        |a: f64, b: f64| -> f64 { hxai_eval::improvement_pct(a, b).unwrap_or(f64::NAN) };
    Ok(Evaluation {
        n_samples: truth.len(),
        n_windows: mse_p.len(),
        n_records: records.len(),
        records,
        improvement_pct: improvement(physics.rmse, hybrid_s.rmse),
        improvement_vs_sine_pct: improvement(physics_sine.rmse, hybrid_s.rmse),
        r2_change_pct: (hybrid_s.r2 - physics.r2) / physics.r2.abs() * 100.0,
        physics,
        physics_sine,
        hybrid: hybrid_s,
        t_test,
        delta: hxai_eval::score(&delta, &delta_hat).ok(),
        warnings: Vec::new(),
        interval: None,
    })
}
