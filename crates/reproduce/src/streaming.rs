//! The tool position in real time: the fitted model applied to every test record sample by
//! sample by the causal streaming estimator (`hxai_hybrid::records::stream`, what `hxai stream`
//! runs), against the offline prediction (`hxai predict`) on the same samples.

use crate::ReproduceError;
use crate::figures::{Panel, Series};
use hxai_hybrid::records::stream::Estimator;
use hxai_hybrid::records::{RecordInput, RecordModel};
use hxai_sim::SimRecord;
use serde::Serialize;

/// Streaming against offline on one record, after the warm-up, against the probe minus its
/// mean over the compared samples.
#[derive(Debug, Clone, Serialize)]
pub struct StreamRecord {
    /// Record id.
    pub record: String,
    /// Commanded frequency, Hz.
    pub frequency_hz: f64,
    /// Commanded amplitude, um.
    pub amplitude_um: f64,
    /// Samples compared (every sample after the warm-up).
    pub samples: usize,
    /// RMSE of the streaming hybrid, um.
    pub stream_hybrid_rmse_um: f64,
    /// RMSE of the offline hybrid (`hxai predict`), um.
    pub offline_hybrid_rmse_um: f64,
    /// RMSE of the streaming physics (the physics model at the command frequency), um.
    pub stream_physics_rmse_um: f64,
    /// RMSE of the offline physics (the whole double-integrated signal), um.
    pub offline_physics_rmse_um: f64,
}

/// Pooled over the test records of one frequency.
#[derive(Debug, Clone, Serialize)]
pub struct StreamFrequency {
    /// Commanded frequency, Hz.
    pub frequency_hz: f64,
    /// Test records at it.
    pub records: usize,
    /// Pooled RMSE of the streaming hybrid, um.
    pub stream_hybrid_rmse_um: f64,
    /// Pooled RMSE of the offline hybrid, um.
    pub offline_hybrid_rmse_um: f64,
    /// Streaming over offline hybrid RMSE (the goal: at most 1.1).
    pub ratio: f64,
    /// Pooled RMSE of the streaming physics, um.
    pub stream_physics_rmse_um: f64,
    /// Pooled RMSE of the offline physics, um.
    pub offline_physics_rmse_um: f64,
    /// One period of the command, ms (the delay goal's bound).
    pub period_ms: f64,
}

/// The streaming section of the results.
#[derive(Debug, Clone, Serialize)]
pub struct StreamingSummary {
    /// The delay `D`, samples.
    pub delay_samples: usize,
    /// The delay at the records' sampling rate, ms.
    pub delay_ms: f64,
    /// Rows without values at the start, samples.
    pub warmup_samples: usize,
    /// The warm-up, ms.
    pub warmup_ms: f64,
    /// Samples between two updates of the correction.
    pub update_step_samples: usize,
    /// Per test record.
    pub records: Vec<StreamRecord>,
    /// Per frequency, pooled.
    pub by_frequency: Vec<StreamFrequency>,
}

/// The record as the offline prediction takes it, without its truth.
fn input(r: &SimRecord) -> RecordInput<'_> {
    RecordInput {
        id: &r.id,
        fs_hz: r.fs_hz,
        frequency_hz: r.frequency_hz,
        signal: &r.accel_ms2,
        truth: None,
    }
}

/// The streaming and offline predictions of one record: `(stream physics, stream hybrid,
/// offline physics, offline hybrid)`, the streaming ones `None` during the warm-up.
#[allow(clippy::type_complexity)]
fn predictions(
    model: &RecordModel,
    r: &SimRecord,
) -> Result<
    (
        Vec<Option<f64>>,
        Vec<Option<f64>>,
        Vec<f64>,
        Vec<f64>,
        Estimator,
    ),
    ReproduceError,
> {
    let offline = model.predict(&input(r))?;
    let mut est = Estimator::new(model, r.frequency_hz, r.fs_hz)?;
    let rows = est.push(&r.accel_ms2)?;
    Ok((
        rows.iter().map(|x| x.physics_um).collect(),
        rows.iter().map(|x| x.hybrid_um).collect(),
        offline.physics,
        offline.hybrid,
        est,
    ))
}

/// Streams every test record of `model` among `all` and compares.
///
/// # Errors
/// The estimator's and the offline prediction's errors.
pub fn compute(all: &[SimRecord], model: &RecordModel) -> Result<StreamingSummary, ReproduceError> {
    let test = &model.split.test;
    let mut records = Vec::new();
    // (frequency, [se stream hybrid, se offline hybrid, se stream physics, se offline physics], n, records)
    let mut pooled: Vec<(f64, [f64; 4], usize, usize)> = Vec::new();
    let mut settings = None;
    for r in all.iter().filter(|r| test.contains(&r.id)) {
        let (sp, sh, op, oh, est) = predictions(model, r)?;
        let idx: Vec<usize> = (0..sh.len()).filter(|&i| sh[i].is_some()).collect();
        if idx.is_empty() {
            continue;
        }
        let mean = idx.iter().map(|&i| r.probe_um[i]).sum::<f64>() / idx.len() as f64;
        let mut se = [0.0; 4];
        for &i in &idx {
            let truth = r.probe_um[i] - mean;
            let vals = [
                sh[i].unwrap_or(f64::NAN),
                oh[i],
                sp[i].unwrap_or(f64::NAN),
                op[i],
            ];
            for (s, v) in se.iter_mut().zip(vals) {
                *s += (v - truth).powi(2);
            }
        }
        let n = idx.len();
        let rmse = |k: usize| (se[k] / n as f64).sqrt();
        records.push(StreamRecord {
            record: r.id.clone(),
            frequency_hz: r.frequency_hz,
            amplitude_um: r.amplitude_um,
            samples: n,
            stream_hybrid_rmse_um: rmse(0),
            offline_hybrid_rmse_um: rmse(1),
            stream_physics_rmse_um: rmse(2),
            offline_physics_rmse_um: rmse(3),
        });
        match pooled.iter_mut().find(|p| p.0 == r.frequency_hz) {
            Some(p) => {
                for (a, b) in p.1.iter_mut().zip(se) {
                    *a += b;
                }
                p.2 += n;
                p.3 += 1;
            }
            None => pooled.push((r.frequency_hz, se, n, 1)),
        }
        settings.get_or_insert((
            est.delay_samples(),
            est.warmup_samples(),
            est.update_step(),
            r.fs_hz,
        ));
    }
    let Some((delay, warmup, step, fs)) = settings else {
        return Err(ReproduceError::Pipeline("no test record to stream".into()));
    };
    pooled.sort_by(|a, b| a.0.total_cmp(&b.0));
    let by_frequency = pooled
        .into_iter()
        .map(|(f, se, n, k)| {
            let rmse = |i: usize| (se[i] / n as f64).sqrt();
            StreamFrequency {
                frequency_hz: f,
                records: k,
                stream_hybrid_rmse_um: rmse(0),
                offline_hybrid_rmse_um: rmse(1),
                ratio: rmse(0) / rmse(1),
                stream_physics_rmse_um: rmse(2),
                offline_physics_rmse_um: rmse(3),
                period_ms: 1e3 / f,
            }
        })
        .collect();
    Ok(StreamingSummary {
        delay_samples: delay,
        delay_ms: delay as f64 / fs * 1e3,
        warmup_samples: warmup,
        warmup_ms: warmup as f64 / fs * 1e3,
        update_step_samples: step,
        records,
        by_frequency,
    })
}

/// The figure: the probe, the offline and the streaming hybrid of `model` over one test
/// record (at 25 Hz) around the end of the warm-up (marked), where the streaming rows begin.
///
/// # Errors
/// The estimator's and the offline prediction's errors.
pub fn figure(model: &RecordModel, r: &SimRecord) -> Result<Vec<Panel>, ReproduceError> {
    let (_, sh, _, oh, est) = predictions(model, r)?;
    let w = est.warmup_samples();
    let period = (r.fs_hz / r.frequency_hz).round() as usize;
    let from = w.saturating_sub(2 * period);
    let to = (w + 4 * period).min(sh.len());
    let mean = (from..to).map(|i| r.probe_um[i]).sum::<f64>() / (to - from).max(1) as f64;
    let t = |i: usize| r.time_s[i] * 1e3;
    let truth: Vec<(f64, f64)> = (from..to).map(|i| (t(i), r.probe_um[i] - mean)).collect();
    let offline: Vec<(f64, f64)> = (from..to).map(|i| (t(i), oh[i])).collect();
    let stream: Vec<(f64, f64)> = (from..to).filter_map(|i| Some((t(i), sh[i]?))).collect();
    let (lo, hi) = truth
        .iter()
        .chain(&offline)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.1), hi.max(p.1))
        });
    Ok(vec![Panel {
        title: format!(
            "{} µm, {} Hz ({}): delay {} samples, warm-up {} ms (dashed)",
            r.amplitude_um,
            r.frequency_hz,
            r.id,
            est.delay_samples(),
            (w as f64 / r.fs_hz * 1e3).round()
        ),
        x_label: "time (ms)".into(),
        y_label: "position (µm)".into(),
        series: vec![
            Series::line("true (probe)", truth),
            Series::line("offline hybrid (hxai predict)", offline),
            Series::line("streaming hybrid (hxai stream)", stream),
            Series::dashed("end of the warm-up", vec![(t(w), lo), (t(w), hi)]),
        ],
    }])
}
