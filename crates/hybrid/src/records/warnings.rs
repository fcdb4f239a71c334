//! Warnings: input that is legal but implausible, reported with the result instead of
//! refused (the caller decides whether to show them; this crate prints nothing).

use crate::records::sample::{RecordInput, WindowSample};
use crate::records::window::WindowConfig;
use serde::{Deserialize, Serialize};

/// Sampling rates outside this range, Hz, are legal but suggest `time_s` is not in seconds
/// (milliseconds give 1000 times less, microseconds a million times less).
pub const PLAUSIBLE_FS_HZ: (f64, f64) = (100.0, 1e6);

/// Fewer periods of the commanded frequency per window than this make the per-window sine
/// fit (amplitude and phase) unreliable.
pub const MIN_PERIODS_PER_WINDOW: f64 = 5.0;

/// A ratio between two amplitudes that should agree (probe vs commanded, probe vs
/// physics) beyond which a warning is given: a factor of 3 either way. Unit slips are a
/// factor of 9.81 (g vs m/s^2) or 1000 (mm vs um), real disagreements far less.
pub const AMPLITUDE_RATIO_LIMIT: f64 = 3.0;

/// One warning about one record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Warning {
    /// Record id.
    pub record: String,
    /// What looks wrong, and what to check.
    pub message: String,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "record `{}`: {}", self.record, self.message)
    }
}

fn num(v: f64) -> String {
    crate::error::num(v)
}

/// Warnings about one record's settings: a sampling rate outside [`PLAUSIBLE_FS_HZ`], a
/// commanded frequency at or above the Nyquist frequency (half the sampling rate), and
/// fewer than [`MIN_PERIODS_PER_WINDOW`] periods of the commanded frequency per window.
pub fn input_warnings(r: &RecordInput<'_>, window: &WindowConfig) -> Vec<Warning> {
    let mut out = Vec::new();
    let w = |message: String| Warning {
        record: r.id.to_owned(),
        message,
    };
    let (lo, hi) = PLAUSIBLE_FS_HZ;
    if r.fs_hz.is_finite() && !(lo..=hi).contains(&r.fs_hz) {
        out.push(w(format!(
            "sampling rate {} Hz is outside the usual {} Hz to {} Hz; is `time_s` in seconds?",
            num(r.fs_hz),
            num(lo),
            num(hi)
        )));
    }
    let nyquist = 0.5 * r.fs_hz;
    if r.fs_hz.is_finite() && r.frequency_hz.is_finite() && r.frequency_hz >= nyquist {
        out.push(w(format!(
            "the commanded frequency {} Hz is at or above the Nyquist frequency {} Hz of a \
             record sampled at {} Hz: the samples cannot hold it (it aliases to a lower \
             frequency); is the frequency in Hz and `time_s` in seconds?",
            num(r.frequency_hz),
            num(nyquist),
            num(r.fs_hz)
        )));
    }
    let periods = window.length_s * r.frequency_hz;
    if periods.is_finite() && periods < MIN_PERIODS_PER_WINDOW {
        out.push(w(format!(
            "a {} s window holds {} periods of {} Hz (fewer than {}); the per-window sine fit is unreliable, use a longer --window-s",
            num(window.length_s),
            num(periods),
            num(r.frequency_hz),
            num(MIN_PERIODS_PER_WINDOW)
        )));
    }
    out
}

/// Warnings about a whole record used without windows (`hxai displacement`, `hxai
/// features`): a sampling rate outside [`PLAUSIBLE_FS_HZ`], fewer than
/// [`MIN_PERIODS_PER_WINDOW`] periods of `frequency_hz` in its `n` samples.
pub fn record_warnings(record: &str, fs: f64, frequency_hz: f64, n: usize) -> Vec<Warning> {
    let input = RecordInput {
        id: record,
        fs_hz: fs,
        frequency_hz,
        signal: &[],
        truth: None,
    };
    let mut out = input_warnings(
        &input,
        &WindowConfig {
            length_s: f64::INFINITY,
            discard_s: 0.0,
        },
    );
    let periods = n as f64 / fs * frequency_hz;
    if periods.is_finite() && periods < MIN_PERIODS_PER_WINDOW {
        out.push(Warning {
            record: record.to_owned(),
            message: format!(
                "the record holds {} periods of {} Hz (fewer than {}); amplitude and spectral estimates are unreliable",
                num(periods),
                num(frequency_hz),
                num(MIN_PERIODS_PER_WINDOW)
            ),
        });
    }
    out
}

/// A warning when the median ratio of the truth's amplitude to the physics amplitude over a
/// record's windows is beyond [`AMPLITUDE_RATIO_LIMIT`]: the channels are probably in other
/// units than `um` and `m/s^2` (a probe in mm reads 1000 times smaller, an accelerometer in
/// g 9.81 times smaller).
pub fn units_warning(record: &str, windows: &[WindowSample]) -> Option<Warning> {
    let mut ratios: Vec<f64> = windows
        .iter()
        .filter_map(|s| Some(s.a_true()? / s.a_phys()))
        .filter(|r| r.is_finite() && *r > 0.0)
        .collect();
    if ratios.is_empty() {
        return None;
    }
    ratios.sort_by(f64::total_cmp);
    let r = ratios[ratios.len() / 2];
    let lim = AMPLITUDE_RATIO_LIMIT;
    (!(1.0 / lim..=lim).contains(&r)).then(|| Warning {
        record: record.to_owned(),
        message: format!(
            "the probe amplitude is {} times the physics model's; check the units \
             (`probe_um` in micrometres, `accel_ms2` in m/s^2, not mm or g)",
            num(r)
        ),
    })
}

/// A warning when the probe's amplitude at the commanded frequency (least-squares sine
/// fit over the whole record) is beyond [`AMPLITUDE_RATIO_LIMIT`] of the commanded
/// amplitude, for example a probe recorded in mm. `None` without truth or when the fit fails.
pub fn amplitude_warning(r: &RecordInput<'_>, commanded_um: f64) -> Option<Warning> {
    let truth = r.truth?;
    let fit = hxai_signal::fit_sine(truth, r.fs_hz, r.frequency_hz).ok()?;
    if !(commanded_um.is_finite() && commanded_um > 0.0 && fit.amplitude.is_finite()) {
        return None;
    }
    let ratio = fit.amplitude / commanded_um;
    let lim = AMPLITUDE_RATIO_LIMIT;
    (!(1.0 / lim..=lim).contains(&ratio)).then(|| Warning {
        record: r.id.to_owned(),
        message: format!(
            "the probe amplitude {} um is {} times the commanded {} um; is `probe_um` in micrometres?",
            num(fit.amplitude),
            num(ratio),
            num(commanded_um)
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input<'a>(fs: f64, f: f64, truth: Option<&'a [f64]>, sig: &'a [f64]) -> RecordInput<'a> {
        RecordInput {
            id: "r",
            fs_hz: fs,
            frequency_hz: f,
            signal: sig,
            truth,
        }
    }

    #[test]
    fn sampling_rate_and_periods() {
        let w = WindowConfig::default();
        assert!(input_warnings(&input(10_000.0, 20.0, None, &[]), &w).is_empty());
        // (20 Hz sampled at 10 Hz is also above the Nyquist frequency)
        let ms = input_warnings(&input(10.0, 20.0, None, &[]), &w);
        assert_eq!(ms.len(), 2, "{ms:?}");
        assert!(ms[0].message.contains("10 Hz"), "{}", ms[0]);
        let short = input_warnings(&input(10_000.0, 6.0, None, &[]), &w);
        assert_eq!(short.len(), 1);
        assert!(short[0].message.contains("3 periods"), "{}", short[0]);
    }

    /// `--frequency-hz` at or above half the sampling rate is named (issue 52): the samples
    /// cannot hold it; just below it is not.
    #[test]
    fn a_frequency_above_nyquist_is_named() {
        let w = WindowConfig::default();
        let above = input_warnings(&input(1000.0, 600.0, None, &[]), &w);
        assert_eq!(above.len(), 1, "{above:?}");
        assert!(
            above[0].message.contains("Nyquist frequency 500 Hz"),
            "{}",
            above[0]
        );
        assert_eq!(
            input_warnings(&input(1000.0, 500.0, None, &[]), &w).len(),
            1
        );
        assert!(input_warnings(&input(1000.0, 499.0, None, &[]), &w).is_empty());
        let whole = record_warnings("r", 1000.0, 2000.0, 10_000);
        assert!(
            whole.iter().any(|x| x.message.contains("Nyquist")),
            "{whole:?}"
        );
    }

    #[test]
    fn probe_in_mm_is_flagged() {
        let fs = 1000.0;
        let probe_um: Vec<f64> = (0..2000)
            .map(|i| 5.0 * (2.0 * std::f64::consts::PI * 20.0 * i as f64 / fs).sin())
            .collect();
        let probe_mm: Vec<f64> = probe_um.iter().map(|v| v / 1000.0).collect();
        assert!(amplitude_warning(&input(fs, 20.0, Some(&probe_um), &[]), 5.0).is_none());
        let w = amplitude_warning(&input(fs, 20.0, Some(&probe_mm), &[]), 5.0);
        assert!(w.is_some_and(|w| w.message.contains("0.001 times")));
    }
}
