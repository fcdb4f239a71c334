//! SVG figures drawn with plotters into strings: the drawing code lives in `hxai-plot`
//! (shared with `hxai explain`); these are its names as this crate has always exported them.

pub use hxai_plot::{FigureError, Mark, Panel, Series, draw};
