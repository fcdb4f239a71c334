//! One window of a record's prediction as every front end shows it: `hxai predict --json`'s
//! `windows`, Python's `ToolModel.predict()["windows"]` and the rows of `predict_records`.
//! The keys are defined here once, so the command line and Python spell them alike.

use super::{RecordPrediction, WindowPrediction};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One window of a prediction (JSON keys as the field names).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WindowRow {
    /// Window index within the record.
    pub window: usize,
    /// Index of the window's first sample in the record.
    pub start: usize,
    /// Number of samples in the window.
    pub len: usize,
    /// Time of the window's first sample, s: the record's own time stamp where it has a
    /// time column (`hxai predict`), else the seconds from the record's first sample
    /// (`start / fs`).
    pub start_s: f64,
    /// Amplitude of the physics prediction, µm.
    pub a_phys_um: f64,
    /// Phase of the physics prediction, radians.
    pub phase_rad: f64,
    /// The correction `delta_hat`, µm.
    pub delta_hat_um: f64,
    /// The corrected amplitude `A_phys + delta_hat`, µm.
    pub a_corr_um: f64,
    /// The window's features by name (absent when not asked for).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub features: BTreeMap<String, f64>,
}

impl WindowRow {
    /// The row of window `w`, which starts at `start_s` seconds.
    pub fn of(w: &WindowPrediction, start_s: f64) -> Self {
        Self {
            window: w.window,
            start: w.start,
            len: w.len,
            start_s,
            a_phys_um: w.physics.amplitude,
            phase_rad: w.physics.phase,
            delta_hat_um: w.delta_hat,
            a_corr_um: w.corrected.amplitude,
            features: BTreeMap::new(),
        }
    }
}

impl RecordPrediction {
    /// One row per window. `time_s` is the record's time column (one stamp per sample);
    /// without it, or where it is too short, a window starts at `start / fs_hz` seconds.
    /// `feature_names` (the model's, in the order of the samples' features) adds each
    /// window's features to its row.
    pub fn window_rows(
        &self,
        time_s: Option<&[f64]>,
        fs_hz: f64,
        feature_names: Option<&[String]>,
    ) -> Vec<WindowRow> {
        self.windows
            .iter()
            .enumerate()
            .map(|(i, w)| {
                let start_s = time_s
                    .and_then(|t| t.get(w.start).copied())
                    .unwrap_or(w.start as f64 / fs_hz);
                let mut row = WindowRow::of(w, start_s);
                if let (Some(names), Some(sample)) = (feature_names, self.samples.get(i)) {
                    row.features = names
                        .iter()
                        .cloned()
                        .zip(sample.features.iter().copied())
                        .collect();
                }
                row
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::{Latent, WindowSample};

    fn prediction() -> RecordPrediction {
        let latent = |a: f64| Latent {
            amplitude: a,
            phase: 0.25,
            offset: 0.0,
        };
        let window = |k: usize| WindowPrediction {
            window: k,
            start: 500 + 1000 * k,
            len: 1000,
            physics: latent(5.0),
            delta_hat: 0.5,
            corrected: latent(5.5),
        };
        let sample = |k: usize| WindowSample {
            record: "r".into(),
            window: k,
            range: 500 + 1000 * k..1500 + 1000 * k,
            features: vec![20.0, 0.1 * k as f64],
            physics: latent(5.0),
            truth: None,
        };
        RecordPrediction {
            physics: Vec::new(),
            hybrid: Vec::new(),
            windows: vec![window(0), window(1)],
            samples: vec![sample(0), sample(1)],
            warnings: Vec::new(),
        }
    }

    #[test]
    fn rows_take_the_time_column_or_count_from_the_first_sample() {
        let p = prediction();
        let rows = p.window_rows(None, 2000.0, None);
        assert_eq!(rows[1].start, 1500);
        assert_eq!(rows[1].start_s, 0.75);
        assert!(rows[0].features.is_empty());
        let t: Vec<f64> = (0..3000).map(|i| 10.0 + i as f64 / 2000.0).collect();
        let rows = p.window_rows(Some(&t), 2000.0, None);
        assert_eq!(rows[1].start_s, 10.75);
        let names = vec!["f1".to_string(), "f2".to_string()];
        let rows = p.window_rows(None, 2000.0, Some(&names));
        assert_eq!(rows[1].features["f2"], 0.1);
        assert_eq!(rows[1].a_corr_um, 5.5);
        assert_eq!(rows[1].delta_hat_um, 0.5);
    }

    #[test]
    fn the_keys_are_those_both_front_ends_print() {
        let rows = prediction().window_rows(None, 2000.0, None);
        let v = serde_json::to_value(&rows[0]).unwrap_or_default();
        let keys: Vec<&str> = v
            .as_object()
            .map(|o| o.keys().map(String::as_str).collect())
            .unwrap_or_default();
        assert_eq!(
            keys,
            [
                "a_corr_um",
                "a_phys_um",
                "delta_hat_um",
                "len",
                "phase_rad",
                "start",
                "start_s",
                "window"
            ]
        );
    }
}
