//! SVG figures drawn with plotters into strings (the caller decides where they go): the
//! figures of `cargo xtask reproduce` and the pictures of `hxai explain` ([`explain`]).
//!
//! A figure is a grid of [`Panel`]s; each panel has labelled axes (with units) and a few
//! [`Series`], drawn as lines, points, bands or interval bars. Axis ranges are computed from
//! the data with a 5 % margin so every figure is readable without hand tuning.
#![deny(missing_docs)]

pub mod explain;
pub mod report;

use plotters::prelude::*;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// A polyline through the points in order.
    Line,
    /// One filled circle per point.
    Points,
    /// A dashed polyline (the reference `y = x` line of a parity plot, say).
    Dashed,
    /// A filled, translucent polygon through the points in order (a band: its lower edge
    /// left to right, then its upper edge right to left; see [`Series::band`]).
    Band,
    /// Consecutive pairs of points joined by a segment (interval bars; see
    /// [`Series::bars`]).
    Bars,
    /// One large filled circle per point (a point singled out, such as the selected model).
    Marker,
}

/// One named set of points.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// (x, y) points; non-finite points are skipped.
    pub points: Vec<(f64, f64)>,
    /// How to draw them.
    pub mark: Mark,
}

impl Series {
    /// A line series.
    pub fn line(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            name: name.into(),
            points,
            mark: Mark::Line,
        }
    }
    /// A scatter series.
    pub fn points(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            name: name.into(),
            points,
            mark: Mark::Points,
        }
    }
    /// A dashed line series.
    pub fn dashed(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            name: name.into(),
            points,
            mark: Mark::Dashed,
        }
    }
    /// A series of large markers.
    pub fn marker(name: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            name: name.into(),
            points,
            mark: Mark::Marker,
        }
    }
    /// A band between `lower` and `upper`, `(x, lo, hi)` per point in increasing `x`.
    pub fn band(name: impl Into<String>, points: &[(f64, f64, f64)]) -> Self {
        let lower = points.iter().map(|p| (p.0, p.1));
        let upper = points.iter().rev().map(|p| (p.0, p.2));
        Self {
            name: name.into(),
            points: lower.chain(upper).collect(),
            mark: Mark::Band,
        }
    }
    /// Vertical interval bars, `(x, lo, hi)` each.
    pub fn bars(name: impl Into<String>, bars: &[(f64, f64, f64)]) -> Self {
        Self {
            name: name.into(),
            points: bars.iter().flat_map(|b| [(b.0, b.1), (b.0, b.2)]).collect(),
            mark: Mark::Bars,
        }
    }
}

/// One chart of a figure.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Title above the chart.
    pub title: String,
    /// X axis label, with its unit.
    pub x_label: String,
    /// Y axis label, with its unit.
    pub y_label: String,
    /// The data.
    pub series: Vec<Series>,
}

impl Panel {
    /// A predicted-vs-true panel: `series`, then the dashed `y = x` line across the range
    /// of their scatter points ([`explain::diagonal`]).
    pub fn parity(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
        mut series: Vec<Series>,
    ) -> Self {
        let scattered: Vec<(f64, f64)> = series
            .iter()
            .filter(|s| s.mark == Mark::Points)
            .flat_map(|s| s.points.iter().copied())
            .collect();
        series.push(Series::dashed("y = x", explain::diagonal(&scattered)));
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series,
        }
    }
}

/// Errors while drawing.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    /// plotters reported a drawing failure.
    #[error("cannot draw figure {name}: {reason}")]
    Draw {
        /// Figure name.
        name: String,
        /// What plotters said.
        reason: String,
    },
}

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(90, 90, 90),
];

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let span = hi - lo;
    let pad = if span > 0.0 {
        0.05 * span
    } else {
        lo.abs().max(1.0) * 0.05
    };
    (lo - pad, hi + pad)
}

/// Draws `panels` on a grid of `cols` columns and returns the SVG text.
pub fn draw(name: &str, panels: &[Panel], cols: usize) -> Result<String, FigureError> {
    let err = |e: &dyn std::fmt::Display| FigureError::Draw {
        name: name.to_string(),
        reason: e.to_string(),
    };
    let cols = cols.clamp(1, panels.len().max(1));
    let rows = panels.len().div_ceil(cols).max(1);
    let (w, h) = (520 * cols as u32, 380 * rows as u32);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let areas = root.split_evenly((rows, cols));
        for (panel, area) in panels.iter().zip(areas.iter()) {
            let (x0, x1) = range(
                panel
                    .series
                    .iter()
                    .flat_map(|s| s.points.iter().map(|p| p.0)),
            );
            let (y0, y1) = range(
                panel
                    .series
                    .iter()
                    .flat_map(|s| s.points.iter().map(|p| p.1)),
            );
            let mut chart = ChartBuilder::on(area)
                .caption(&panel.title, ("sans-serif", 16))
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(60)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|e| err(&e))?;
            chart
                .configure_mesh()
                .x_desc(panel.x_label.as_str())
                .y_desc(panel.y_label.as_str())
                .light_line_style(WHITE.mix(0.0))
                .draw()
                .map_err(|e| err(&e))?;
            for (i, s) in panel.series.iter().enumerate() {
                let color = PALETTE[i % PALETTE.len()];
                let pts: Vec<(f64, f64)> = s
                    .points
                    .iter()
                    .copied()
                    .filter(|p| p.0.is_finite() && p.1.is_finite())
                    .collect();
                let anno = match s.mark {
                    Mark::Band => chart
                        .draw_series(std::iter::once(Polygon::new(pts, color.mix(0.2).filled()))),
                    Mark::Marker => chart
                        .draw_series(pts.into_iter().map(|p| Circle::new(p, 5, color.filled()))),
                    Mark::Bars => chart.draw_series(
                        s.points
                            .chunks_exact(2)
                            .filter(|b| b.iter().all(|p| p.0.is_finite() && p.1.is_finite()))
                            .map(|b| PathElement::new(vec![b[0], b[1]], color.mix(0.6))),
                    ),
                    Mark::Line => chart.draw_series(LineSeries::new(pts, color.stroke_width(1))),
                    Mark::Dashed => {
                        chart.draw_series(DashedLineSeries::new(pts, 6, 4, color.stroke_width(1)))
                    }
                    Mark::Points => chart
                        .draw_series(pts.into_iter().map(|p| Circle::new(p, 2, color.filled()))),
                }
                .map_err(|e| err(&e))?;
                anno.label(s.name.as_str()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2))
                });
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK.mix(0.3))
                .draw()
                .map_err(|e| err(&e))?;
        }
        root.present().map_err(|e| err(&e))?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_labels_and_series() -> Result<(), FigureError> {
        let p = Panel {
            title: "t".into(),
            x_label: "frequency (Hz)".into(),
            y_label: "amplitude (um)".into(),
            series: vec![
                Series::line("a", vec![(0.0, 1.0), (1.0, 2.0)]),
                Series::points("b", vec![(0.5, 1.5), (f64::NAN, 1.0)]),
            ],
        };
        let svg = draw("test", &[p.clone(), p], 2)?;
        assert!(svg.starts_with("<svg"));
        assert!(svg.contains("frequency (Hz)"));
        assert!(svg.contains("amplitude (um)"));
        Ok(())
    }
}
