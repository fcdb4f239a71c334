//! Equivalents of the paper's Figures 4, 5, 8, 9, 10, 11 and 12, and the pictures of
//! `hxai explain` for the paper's case.

use crate::ReproduceError;
use crate::figures::{Panel, Series, draw};
use crate::pipeline::{Computed, input};
use hxai_sim::SimRecord;
use std::collections::BTreeMap;

/// File name and caption of every figure, in the order they are listed in the report.
pub const CAPTIONS: [(&str, &str); 11] = [
    (
        "fig04_command_encoder_probe.svg",
        "Fig. 4: command, encoder and probe at 10 and 40 Hz; mean fitted amplitudes vs frequency and vs amplitude",
    ),
    (
        "fig05_physics_vs_true.svg",
        "Fig. 5: physics-model vs true displacement at 10 and 25 Hz; δ vs frequency and vs amplitude",
    ),
    (
        "fig08_delta_predicted.svg",
        "Fig. 8: predicted vs true δ (train and test)",
    ),
    (
        "fig09_amplitude_predictions.svg",
        "Fig. 9: physics and hybrid amplitudes vs the true amplitude (test windows)",
    ),
    (
        "fig10_amplitudes.svg",
        "Fig. 10: physics, hybrid and true amplitudes across frequencies, amplitudes and test samples",
    ),
    (
        "fig11_position_signals.svg",
        "Fig. 11: physics, hybrid and true position at 10 and 25 Hz (test records)",
    ),
    (
        "fig12_errors.svg",
        "Fig. 12: physics and hybrid position errors at 10 and 25 Hz (test records)",
    ),
    (
        "fig_explain_response.svg",
        "`hxai explain --model MODEL --data samples.csv --out DIR` on the paper's fit: the selected correction's response to each feature it uses, the other features at their median over the training windows, with its 95 % prediction interval as a band and the windows (train, test) as points",
    ),
    (
        "fig_explain_predicted_vs_true.svg",
        "`hxai explain`: predicted vs true δ of every window, with the 95 % prediction intervals of the test windows",
    ),
    (
        "fig_explain_pareto.svg",
        "`hxai explain`: the search's Pareto front (complexity vs training mean squared error), the selected equation (the one above) marked",
    ),
    (
        STREAM_FIGURE,
        "`hxai stream` on a test record at 25 Hz: the probe, the offline hybrid of `hxai predict` and the causal streaming hybrid around the end of the warm-up (dashed), where the streaming rows begin; the streaming estimate of each sample uses that sample and the ones before it only",
    ),
];

/// File name of the streaming figure.
const STREAM_FIGURE: &str = "fig_stream_position.svg";

/// Prefix of the explanation pictures' file names (`hxai explain` writes them unprefixed).
const EXPLAIN_PREFIX: &str = "fig_explain_";

const T_LABEL: &str = "time (ms)";
const X_LABEL: &str = "position (µm)";

/// The record at frequency `f` with the amplitude closest to 8 µm, preferring test records.
fn pick(c: &Computed, f: f64) -> Option<&SimRecord> {
    let test = &c.fit.model.split.test;
    let score = |r: &SimRecord| {
        let not_test = u8::from(!test.contains(&r.id));
        (
            not_test,
            ((r.amplitude_um - 8.0).abs() * 1e6) as u64,
            r.repeat,
        )
    };
    c.records
        .iter()
        .filter(|r| (r.frequency_hz - f).abs() < 1e-9)
        .min_by_key(|r| score(r))
}

/// `(first sample, count)` of three periods starting at the first window.
fn span(c: &Computed, r: &SimRecord) -> (usize, usize) {
    let start = (c.fit.model.window.discard_s * r.fs_hz).round() as usize;
    let n = (3.0 * r.fs_hz / r.frequency_hz).round() as usize;
    let end = (start + n).min(r.time_s.len());
    (start.min(end), end - start.min(end))
}

fn trace(r: &SimRecord, x: &[f64], start: usize, n: usize, offset: f64) -> Vec<(f64, f64)> {
    (start..start + n)
        .filter_map(|i| Some((r.time_s.get(i)? * 1e3, x.get(i)? - offset)))
        .collect()
}

fn fig4(c: &Computed) -> Vec<Panel> {
    let mut panels = Vec::new();
    for f in [10.0, 40.0] {
        if let Some(r) = pick(c, f) {
            let (s, n) = span(c, r);
            panels.push(Panel {
                title: format!("{} µm, {f} Hz", r.amplitude_um),
                x_label: T_LABEL.into(),
                y_label: X_LABEL.into(),
                series: vec![
                    Series::line("command", trace(r, &r.command_um, s, n, 0.0)),
                    Series::line("encoder", trace(r, &r.encoder_um, s, n, 0.0)),
                    Series::line("probe", trace(r, &r.probe_um, s, n, 0.0)),
                ],
            });
        }
    }
    let a = &c.results.amplitudes;
    let by = |key: fn(&crate::results::AmplitudeRow) -> f64,
              val: fn(&crate::results::AmplitudeRow) -> f64| {
        hxai_eval::means_by_key(a.iter().map(|x| (key(x), val(x))))
    };
    for (title, x_label, key) in [
        (
            "mean fitted amplitude vs frequency",
            "frequency (Hz)",
            (|x: &crate::results::AmplitudeRow| x.frequency_hz) as fn(&_) -> f64,
        ),
        (
            "mean fitted amplitude vs amplitude",
            "commanded amplitude (µm)",
            |x: &crate::results::AmplitudeRow| x.amplitude_um,
        ),
    ] {
        panels.push(Panel {
            title: title.into(),
            x_label: x_label.into(),
            y_label: "amplitude (µm)".into(),
            series: vec![
                Series::line("command", by(key, |x| x.command_um)),
                Series::line("encoder", by(key, |x| x.encoder_um)),
                Series::line("probe", by(key, |x| x.probe_um)),
            ],
        });
    }
    panels
}

fn fig5(c: &Computed) -> Result<Vec<Panel>, ReproduceError> {
    let mut panels = Vec::new();
    for f in [10.0, 25.0] {
        if let Some(r) = pick(c, f) {
            let pred = c.fit.model.predict(&input(r))?;
            let (s, n) = span(c, r);
            let offset = hxai_eval::extent(&r.probe_um[s..s + n])?.mean;
            panels.push(Panel {
                title: format!("{} µm, {f} Hz", r.amplitude_um),
                x_label: T_LABEL.into(),
                y_label: X_LABEL.into(),
                series: vec![
                    Series::line("true (probe)", trace(r, &r.probe_um, s, n, offset)),
                    Series::line("physics model", trace(r, &pred.physics, s, n, 0.0)),
                ],
            });
        }
    }
    let samples = &c.fit.samples;
    let amp_of: BTreeMap<&str, (f64, f64)> = c
        .records
        .iter()
        .map(|r| (r.id.as_str(), (r.amplitude_um, r.frequency_hz)))
        .collect();
    let pts = |use_freq: bool| -> Vec<(f64, f64)> {
        samples
            .iter()
            .filter_map(|w| {
                let (a, f) = amp_of.get(w.record.as_str())?;
                Some((if use_freq { *f } else { *a }, w.delta()?))
            })
            .collect()
    };
    for (use_freq, title, x_label) in [
        (true, "δ vs frequency", "frequency (Hz)"),
        (false, "δ vs amplitude", "commanded amplitude (µm)"),
    ] {
        let p = pts(use_freq);
        panels.push(Panel {
            title: title.into(),
            x_label: x_label.into(),
            y_label: "δ = A_true - A_phys (µm)".into(),
            series: vec![
                Series::points("windows", p.clone()),
                Series::line("mean", hxai_eval::means_by_key(p.into_iter())),
            ],
        });
    }
    Ok(panels)
}

fn fig8(c: &Computed) -> Vec<Panel> {
    let (mut train, mut test) = (Vec::new(), Vec::new());
    for (i, w) in c.fit.samples.iter().enumerate() {
        if let Some(d) = w.delta() {
            let p = (d, c.delta_hat[i]);
            if c.fit.is_test[i] {
                test.push(p)
            } else {
                train.push(p)
            }
        }
    }
    vec![Panel::parity(
        "symbolic model of δ",
        "true δ (µm)",
        "predicted δ (µm)",
        vec![Series::points("train", train), Series::points("test", test)],
    )]
}

/// `(true, physics, hybrid)` amplitudes of the test windows, with record amplitude and frequency.
fn test_amplitudes(c: &Computed) -> Vec<(f64, f64, f64, f64, f64)> {
    let conds: BTreeMap<&str, (f64, f64)> = c
        .records
        .iter()
        .map(|r| (r.id.as_str(), (r.amplitude_um, r.frequency_hz)))
        .collect();
    c.fit
        .samples
        .iter()
        .enumerate()
        .filter(|(i, _)| c.fit.is_test[*i])
        .filter_map(|(i, w)| {
            let (a, f) = conds.get(w.record.as_str())?;
            let a_corr =
                hxai_hybrid::records::corrected_latent(&w.physics, c.delta_hat[i]).amplitude;
            Some((w.a_true()?, w.a_phys(), a_corr, *a, *f))
        })
        .collect()
}

fn fig9(c: &Computed) -> Vec<Panel> {
    let t = test_amplitudes(c);
    let phys: Vec<_> = t.iter().map(|x| (x.0, x.1)).collect();
    let hyb: Vec<_> = t.iter().map(|x| (x.0, x.2)).collect();
    vec![Panel::parity(
        "amplitude predictions, test windows",
        "true amplitude A_true (µm)",
        "predicted amplitude (µm)",
        vec![
            Series::points("physics A_phys", phys),
            Series::points("hybrid A_corr", hyb),
        ],
    )]
}

fn fig10(c: &Computed) -> Vec<Panel> {
    let t = test_amplitudes(c);
    let mut panels = Vec::new();
    for (title, x_label, key) in [
        ("vs frequency (test mean)", "frequency (Hz)", 4usize),
        ("vs amplitude (test mean)", "commanded amplitude (µm)", 3),
    ] {
        let k = |x: &(f64, f64, f64, f64, f64)| if key == 4 { x.4 } else { x.3 };
        panels.push(Panel {
            title: title.into(),
            x_label: x_label.into(),
            y_label: "amplitude (µm)".into(),
            series: vec![
                Series::line(
                    "true",
                    hxai_eval::means_by_key(t.iter().map(|x| (k(x), x.0))),
                ),
                Series::line(
                    "physics",
                    hxai_eval::means_by_key(t.iter().map(|x| (k(x), x.1))),
                ),
                Series::line(
                    "hybrid",
                    hxai_eval::means_by_key(t.iter().map(|x| (k(x), x.2))),
                ),
            ],
        });
    }
    let idx = |v: fn(&(f64, f64, f64, f64, f64)) -> f64| -> Vec<(f64, f64)> {
        t.iter()
            .enumerate()
            .map(|(i, x)| (i as f64 + 1.0, v(x)))
            .collect()
    };
    panels.push(Panel {
        title: "by test sample".into(),
        x_label: "test sample number".into(),
        y_label: "amplitude (µm)".into(),
        series: vec![
            Series::points("true", idx(|x| x.0)),
            Series::points("physics", idx(|x| x.1)),
            Series::points("hybrid", idx(|x| x.2)),
        ],
    });
    panels
}

fn fig11_12(c: &Computed) -> Result<(Vec<Panel>, Vec<Panel>), ReproduceError> {
    let (mut sig, mut err) = (Vec::new(), Vec::new());
    for f in [10.0, 25.0] {
        let Some(r) = pick(c, f) else { continue };
        let pred = c.fit.model.predict(&input(r))?;
        let (s, n) = span(c, r);
        let offset = hxai_eval::extent(&r.probe_um[s..s + n])?.mean;
        let truth = trace(r, &r.probe_um, s, n, offset);
        let phys = trace(r, &pred.physics, s, n, 0.0);
        let hyb = trace(r, &pred.hybrid, s, n, 0.0);
        let truth_um: Vec<f64> = truth.iter().map(|p| p.1).collect();
        let diff = |p: &[(f64, f64)]| -> Result<Vec<(f64, f64)>, ReproduceError> {
            let pred_um: Vec<f64> = p.iter().map(|p| p.1).collect();
            let err = hxai_eval::residuals(&truth_um, &pred_um)?;
            Ok(p.iter().zip(err).map(|(a, e)| (a.0, e)).collect())
        };
        let title = format!("{} µm, {f} Hz ({})", r.amplitude_um, r.id);
        err.push(Panel {
            title: title.clone(),
            x_label: T_LABEL.into(),
            y_label: "error, prediction - true (µm)".into(),
            series: vec![
                Series::line("physics", diff(&phys)?),
                Series::line("hybrid", diff(&hyb)?),
            ],
        });
        sig.push(Panel {
            title,
            x_label: T_LABEL.into(),
            y_label: X_LABEL.into(),
            series: vec![
                Series::line("true (probe)", truth),
                Series::line("physics", phys),
                Series::line("hybrid", hyb),
            ],
        });
    }
    Ok((sig, err))
}

/// Every figure as `(file name, SVG)`.
pub fn all(c: &Computed) -> Result<Vec<(String, String)>, ReproduceError> {
    let (f11, f12) = fig11_12(c)?;
    let figs: [(Vec<Panel>, usize); 7] = [
        (fig4(c), 2),
        (fig5(c)?, 2),
        (fig8(c), 1),
        (fig9(c), 1),
        (fig10(c), 3),
        (f11, 2),
        (f12, 2),
    ];
    let mut files = CAPTIONS
        .iter()
        .zip(figs)
        .map(|((name, _), (panels, cols))| Ok((name.to_string(), draw(name, &panels, cols)?)))
        .collect::<Result<Vec<_>, ReproduceError>>()?;
    files.extend(explain(c)?);
    if let Some(r) = pick(c, 25.0) {
        let panels = crate::streaming::figure(&c.fit.model, r)?;
        files.push((STREAM_FIGURE.to_string(), draw(STREAM_FIGURE, &panels, 1)?));
    }
    Ok(files)
}

/// The pictures of `hxai explain --data samples.csv` for the paper's fit.
fn explain(c: &Computed) -> Result<Vec<(String, String)>, ReproduceError> {
    let t = c.fit.samples_table()?;
    let delta = t.values.require("delta")?.to_vec();
    let data = hxai_hybrid::explain::ExplainData {
        features: &t.values,
        target: &delta,
        is_test: &c.fit.is_test,
    };
    let e = c
        .fit
        .model
        .explain(Some(&data), hxai_hybrid::DEFAULT_INTERVAL, None)?;
    let p = hxai_plot::explain::pictures(&e, hxai_plot::explain::DELTA_AXIS, EXPLAIN_PREFIX)?;
    if let Some((file, why)) = p.skipped.first() {
        return Err(ReproduceError::Pipeline(format!("{file}: {why}")));
    }
    Ok(p.files)
}
