//! The pictures of `hxai explain` (and of the reproduction's explanation figures), drawn
//! from an [`Explanation`] computed by `hxai-hybrid`.

use crate::{FigureError, Panel, Series, draw};
use hxai_hybrid::explain::Explanation;

/// File of the response curves: one panel per feature the equation uses.
pub const RESPONSE_FILE: &str = "response.svg";
/// File of predicted vs true.
pub const PARITY_FILE: &str = "predicted_vs_true.svg";
/// File of the Pareto front.
pub const PARETO_FILE: &str = "pareto.svg";

/// File name of the factor correction's response bands (one panel per factor; drawn only
/// when the model's stability runs stored them).
pub const FACTORS_FILE: &str = "factors.svg";

/// Axis label of the tool case's correction.
pub const DELTA_AXIS: &str = "δ = A_true - A_phys (µm)";

/// The pictures drawn, and those that could not be, each with its reason.
#[derive(Debug, Clone, PartialEq)]
pub struct Pictures {
    /// `(file name, SVG)` of each picture drawn.
    pub files: Vec<(String, String)>,
    /// `(file name, reason)` of each picture the explanation has no data for.
    pub skipped: Vec<(String, String)>,
}

/// The `y = x` line across the range of `points` (both coordinates): the reference line of
/// a predicted-vs-true picture.
pub fn diagonal(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let lo = points
        .iter()
        .map(|p| p.0.min(p.1))
        .fold(f64::INFINITY, f64::min);
    let hi = points
        .iter()
        .map(|p| p.0.max(p.1))
        .fold(f64::NEG_INFINITY, f64::max);
    vec![(lo, lo), (hi, hi)]
}

fn percent(level: f64) -> String {
    format!("{} %", (level * 1000.0).round() / 10.0)
}

/// `95 % prediction interval (conformal)`: the level and, when known, the method.
fn interval_name(e: &Explanation) -> String {
    match e.method {
        Some(m) => format!("{} prediction interval ({})", percent(e.level), m.name()),
        None => format!("{} prediction interval", percent(e.level)),
    }
}

fn response_panels(e: &Explanation, target: &str) -> Vec<Panel> {
    let band_name = interval_name(e);
    e.responses
        .iter()
        .map(|r| {
            let mut series = Vec::new();
            if let Some(b) = &r.band {
                let pts: Vec<(f64, f64, f64)> = r
                    .grid
                    .iter()
                    .zip(b)
                    .map(|(&x, &(l, h))| (x, l, h))
                    .collect();
                series.push(Series::band(band_name.clone(), &pts));
            }
            series.push(Series::line(
                "correction, others at their median",
                r.grid
                    .iter()
                    .copied()
                    .zip(r.curve.iter().copied())
                    .collect(),
            ));
            series.push(Series::points("train", r.train.clone()));
            if !r.test.is_empty() {
                series.push(Series::points("test", r.test.clone()));
            }
            Panel {
                title: format!("response to {} (median {:.4})", r.feature, r.median),
                x_label: r.feature.clone(),
                y_label: target.to_owned(),
                series,
            }
        })
        .collect()
}

/// One panel per factor of a factor correction: its response band over the stability
/// runs (5-95 %) and the median response, on a grid of its column, with the training
/// rows' partial residuals where the data was given.
fn factor_panels(e: &Explanation) -> Vec<Panel> {
    e.factors
        .iter()
        .map(|(column, b)| {
            let partial = e
                .partial_residuals
                .iter()
                .find(|(c, _)| c == column)
                .map(|(_, p)| p.clone());
            let band: Vec<(f64, f64, f64)> = b
                .grid
                .iter()
                .zip(b.lo.iter().zip(&b.hi))
                .map(|(&x, (&l, &h))| (x, l, h))
                .collect();
            Panel {
                title: format!("factor of {column} ({} runs kept it)", b.runs),
                x_label: column.clone(),
                y_label: "factor (normalised response)".into(),
                series: [
                    Some(Series::band("5-95 % over the stability runs", &band)),
                    partial.map(|p| Series::points("partial residuals (training rows)", p)),
                    Some(Series::line(
                        "median over the runs",
                        b.grid
                            .iter()
                            .copied()
                            .zip(b.median.iter().copied())
                            .collect(),
                    )),
                ]
                .into_iter()
                .flatten()
                .collect(),
            }
        })
        .collect()
}

/// Draws the pictures of `e`: [`RESPONSE_FILE`], [`PARITY_FILE`] and [`PARETO_FILE`], and
/// [`FACTORS_FILE`] for a factor correction whose stability runs stored bands, each
/// named with `prefix` before it (empty for `hxai explain`). `target` labels the
/// correction's axis (with its unit, e.g. `δ (µm)`).
///
/// # Errors
/// [`FigureError`] when plotters cannot draw.
pub fn pictures(e: &Explanation, target: &str, prefix: &str) -> Result<Pictures, FigureError> {
    let mut files = Vec::new();
    let mut skipped = Vec::new();
    let no_data = "needs the rows the correction was fitted on (--data)";
    let name = |f: &str| format!("{prefix}{f}");
    if e.responses.is_empty() {
        let why = if e.parity.is_some() {
            "the equation uses no feature (a constant correction)"
        } else {
            no_data
        };
        skipped.push((name(RESPONSE_FILE), why.to_owned()));
    } else {
        let panels = response_panels(e, target);
        let cols = panels.len().min(3);
        files.push((
            name(RESPONSE_FILE),
            draw(&name(RESPONSE_FILE), &panels, cols)?,
        ));
    }
    match &e.parity {
        None => skipped.push((name(PARITY_FILE), no_data.to_owned())),
        Some(p) => {
            // the bars first, so the points stay visible on them
            let mut series = Vec::new();
            if let Some(iv) = &p.intervals {
                let side = if p.test.is_empty() { "" } else { " (test)" };
                series.push(Series::bars(format!("{}{side}", interval_name(e)), iv));
            }
            series.push(Series::points("train", p.train.clone()));
            if !p.test.is_empty() {
                series.push(Series::points("test", p.test.clone()));
            }
            let panel = Panel::parity(
                "predicted vs true",
                format!("true {target}"),
                format!("predicted {target}"),
                series,
            );
            files.push((name(PARITY_FILE), draw(&name(PARITY_FILE), &[panel], 1)?));
        }
    }
    match &e.front {
        None => skipped.push((
            name(PARETO_FILE),
            "the model file stores no Pareto front (written before it was stored, or a zero \
             correction): refit to draw it"
                .to_owned(),
        )),
        Some(f) => {
            let pts: Vec<(f64, f64)> = f
                .members
                .iter()
                .map(|m| (m.complexity as f64, m.loss))
                .collect();
            let panel = Panel {
                title: "Pareto front of the search".into(),
                x_label: "complexity".into(),
                y_label: "training loss (mean squared error)".into(),
                series: vec![
                    Series::line("Pareto front", pts.clone()),
                    Series::points("members", pts),
                    Series::marker(
                        format!("selected (complexity {})", f.selected.0),
                        vec![(f.selected.0 as f64, f.selected.1)],
                    ),
                ],
            };
            files.push((name(PARETO_FILE), draw(&name(PARETO_FILE), &[panel], 1)?));
        }
    }
    if !e.factors.is_empty() {
        let panels = factor_panels(e);
        let cols = panels.len().min(3);
        files.push((
            name(FACTORS_FILE),
            draw(&name(FACTORS_FILE), &panels, cols)?,
        ));
    }
    Ok(Pictures { files, skipped })
}

#[cfg(test)]
mod tests {
    use super::*;
    use hxai_hybrid::explain::{Front, ParetoMember, Parity, Response};

    fn explanation() -> Explanation {
        Explanation {
            target: "delta".into(),
            level: 0.95,
            method: Some(hxai_hybrid::IntervalMethod::Conformal),
            equation: "2*x".into(),
            responses: vec![Response {
                feature: "x".into(),
                median: 0.5,
                grid: vec![0.0, 0.5, 1.0],
                curve: vec![0.0, 1.0, 2.0],
                band: Some(vec![(-0.1, 0.1), (0.9, 1.1), (1.9, 2.1)]),
                train: vec![(0.0, 0.05), (1.0, 1.9)],
                test: vec![(0.5, 1.02)],
            }],
            parity: Some(Parity {
                train: vec![(0.05, 0.0), (1.9, 2.0)],
                test: vec![(1.02, 1.0)],
                intervals: Some(vec![(1.02, 0.9, 1.1)]),
            }),
            front: Some(Front {
                members: vec![ParetoMember {
                    complexity: 3,
                    loss: 0.01,
                    equation: "2*x".into(),
                }],
                selected: (3, 0.01),
            }),
            factors: Vec::new(),
            partial_residuals: Vec::new(),
        }
    }

    #[test]
    fn every_picture_is_drawn_with_its_series() -> Result<(), FigureError> {
        let p = pictures(&explanation(), "δ (µm)", "fig_")?;
        assert!(p.skipped.is_empty());
        let names: Vec<&str> = p.files.iter().map(|f| f.0.as_str()).collect();
        assert_eq!(
            names,
            [
                "fig_response.svg",
                "fig_predicted_vs_true.svg",
                "fig_pareto.svg"
            ]
        );
        for (_, svg) in &p.files {
            assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        }
        assert!(
            p.files[0]
                .1
                .contains("95 % prediction interval (conformal)")
        );
        assert!(p.files[0].1.contains("<polygon"));
        assert!(p.files[1].1.contains("true δ (µm)"));
        assert!(p.files[2].1.contains("selected (complexity 3)"));
        Ok(())
    }

    #[test]
    fn a_factor_correction_draws_one_band_per_factor() -> Result<(), FigureError> {
        let band = hxai_symreg::factors::FactorBand {
            runs: 18,
            grid: vec![1.0, 2.0, 3.0],
            lo: vec![0.8, 0.9, 1.0],
            median: vec![0.9, 1.0, 1.1],
            hi: vec![1.0, 1.1, 1.2],
        };
        let e = Explanation {
            factors: vec![("feed".into(), band.clone()), ("speed".into(), band)],
            partial_residuals: vec![("feed".into(), vec![(1.5, 0.95), (2.5, 1.2)])],
            ..explanation()
        };
        let p = pictures(&e, "y", "")?;
        let last = p.files.last();
        assert_eq!(last.map(|f| f.0.as_str()), Some(FACTORS_FILE));
        let svg = last.map(|f| f.1.as_str()).unwrap_or_default();
        assert!(svg.contains("factor of feed (18 runs kept it)"), "{svg}");
        assert!(svg.contains("factor of speed"));
        assert!(svg.contains("<polygon"));
        // the partial residuals of feed, in its panel only
        assert_eq!(svg.matches("partial residuals (training rows)").count(), 1);
        // without bands there is no such picture
        let p = pictures(&explanation(), "y", "")?;
        assert!(p.files.iter().all(|(n, _)| n != FACTORS_FILE));
        Ok(())
    }

    #[test]
    fn missing_parts_are_skipped_with_a_reason() -> Result<(), FigureError> {
        let e = Explanation {
            responses: Vec::new(),
            parity: None,
            front: None,
            ..explanation()
        };
        let p = pictures(&e, "y", "")?;
        assert!(p.files.is_empty());
        assert_eq!(p.skipped.len(), 3);
        assert!(p.skipped[2].1.contains("Pareto front"));
        Ok(())
    }

    #[test]
    fn the_diagonal_spans_both_coordinates() {
        assert_eq!(
            diagonal(&[(1.0, -2.0), (3.0, 0.5)]),
            vec![(-2.0, -2.0), (3.0, 3.0)]
        );
    }
}
