//! Tool life in turning: Taylor's law, and the feed effect of the extended Taylor law that
//! it leaves out. The case whose hidden truth is one short closed form.
//!
//! The engineer's physics is Taylor's tool-life law `vc T^n = C`, i.e. `T = (C / vc)^(1/n)`
//! (`T` tool life in min, `vc` cutting speed in m/min) with handbook values for carbide on
//! steel. The generator's measured tool life follows the *extended* Taylor law in its
//! textbook form `vc T^n f^y = C'` at a fixed depth of cut, written here with a reference
//! feed `f_ref` so that `C` keeps its meaning (the speed for 1 min of life at `f_ref`):
//!
//! ```text
//! T = (C / vc)^(1/n) · (f / f_ref)^(-y/n) · exp(σ z)
//! ```
//!
//! so the true multiplicative correction of the (calibrated) law is the power law
//! `(f / f_ref)^(-y/n)` in one column, the feed, and nothing else (documented, with its
//! sources, in `docs/cases.md`):
//!
//! 1. **feed**: `(f / f_ref)^(-y/n)`, [`ToolLifeConfig::feed_factor`]; a larger feed heats
//!    and loads the edge more and shortens its life, less steeply than the speed does;
//! 2. **measurement scatter**, multiplicative (log-normal): tool life scatters widely from
//!    edge to edge even at fixed conditions.
//!
//! Columns: `cutting_speed_m_min`, `feed_mm` (mm/rev), two distractors with no effect
//! (`coolant_temp_C`, `workpiece_diameter_mm`: the speed, not the diameter, is what the edge
//! feels), `tool` (insert number, 1-based, a group column with no effect of its own) and the
//! target `tool_life_min`.

use super::{
    noise_rel, non_negative, normal, positive, range, rows_and_tools, table_of_rows, uniform,
};
use crate::SimError;
use hxai_table::Table;
use serde::{Deserialize, Serialize};

/// Settings of the tool-life generator: the workpiece's true Taylor constants, the feed
/// effect (0 switches it off), the ranges of the cutting conditions and the scatter.
/// Defaults and their reasons: `docs/cases.md`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ToolLifeConfig {
    /// Rows to generate (one tool-life test, one edge, per row).
    pub n_rows: usize,
    /// Seed of every random draw.
    pub seed: u64,
    /// Number of inserts (the `tool` column); an identifier, with no effect of its own.
    pub n_tools: usize,
    /// The workpiece's true Taylor constant: the cutting speed for 1 min of tool life at the
    /// reference feed (m/min).
    pub taylor_c_m_min: f64,
    /// The workpiece's true Taylor exponent `n` (-).
    pub taylor_n: f64,
    /// Feed at which `taylor_c_m_min` holds (mm/rev).
    pub feed_ref_mm: f64,
    /// Exponent `y` of the feed in the extended Taylor law `vc T^n f^y = C'` (speed form); the
    /// tool life goes as `f^(-y/n)`. 0 switches the feed effect off.
    pub feed_exponent: f64,
    /// Cutting speed range, uniform (m/min).
    pub cutting_speed_m_min: [f64; 2],
    /// Feed range, uniform (mm/rev).
    pub feed_mm: [f64; 2],
    /// Measurement scatter: standard deviation of the log of the measured/true ratio (-).
    pub noise_rel: f64,
}

/// Handbook Taylor constant of (uncoated) cemented carbide on steel, after Groover's table
/// (m/min, for f = 0.25 mm/rev and a depth of cut of 2.5 mm): the engineer's value.
pub const HANDBOOK_C: f64 = 500.0;
/// Handbook Taylor exponent of cemented carbide on steel, after Groover's table: the
/// engineer's value.
pub const HANDBOOK_N: f64 = 0.25;

impl Default for ToolLifeConfig {
    fn default() -> Self {
        Self {
            n_rows: 400,
            seed: super::DEFAULT_SEED,
            n_tools: 10,
            taylor_c_m_min: 400.0,
            taylor_n: 0.25,
            feed_ref_mm: 0.25,
            feed_exponent: 0.6,
            cutting_speed_m_min: [150.0, 350.0],
            feed_mm: [0.1, 0.4],
            noise_rel: 0.3,
        }
    }
}

impl ToolLifeConfig {
    /// The defaults with the feed effect and the scatter switched off: `tool_life_min` is
    /// then exactly Taylor's law `(taylor_c_m_min / vc)^(1 / taylor_n)`.
    pub fn physics_only() -> Self {
        Self {
            feed_exponent: 0.0,
            noise_rel: 0.0,
            ..Self::default()
        }
    }

    /// The exponent of the feed in the tool life, `y / n` (`T ∝ f^(-y/n)`).
    pub fn feed_life_exponent(&self) -> f64 {
        self.feed_exponent / self.taylor_n
    }

    /// The hidden truth's correction of Taylor's law at feed `feed_mm`:
    /// `(feed_mm / feed_ref_mm)^(-y/n)`. Measured tool life (before scatter) is Taylor's law
    /// with the configuration's constants times this factor.
    pub fn feed_factor(&self, feed_mm: f64) -> f64 {
        (feed_mm / self.feed_ref_mm).powf(-self.feed_life_exponent())
    }

    /// Checks every setting.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] naming the first bad setting.
    pub fn check(&self) -> Result<(), SimError> {
        rows_and_tools(self.n_rows, self.n_tools)?;
        positive("taylor_c_m_min", self.taylor_c_m_min)?;
        if !(self.taylor_n.is_finite() && self.taylor_n > 0.0 && self.taylor_n <= 1.0) {
            return Err(super::bad(
                "taylor_n",
                self.taylor_n,
                "must be in (0, 1] (carbide on steel: about 0.25)",
            ));
        }
        positive("feed_ref_mm", self.feed_ref_mm)?;
        non_negative("feed_exponent", self.feed_exponent)?;
        range("cutting_speed_m_min", self.cutting_speed_m_min, true)?;
        range("feed_mm", self.feed_mm, true)?;
        noise_rel(self.noise_rel)
    }
}

/// Column names of the tool-life table, in order; the target is last.
pub const COLUMNS: [&str; 6] = [
    "cutting_speed_m_min",
    "feed_mm",
    "coolant_temp_C",
    "workpiece_diameter_mm",
    "tool",
    "tool_life_min",
];

/// Taylor's law in the syntax of `hxai hybrid --physics`, parameters `C` and `n`.
pub const PHYSICS: &str = "(C/cutting_speed_m_min)^(1/n)";

/// Generates the tool-life table (columns [`COLUMNS`]).
///
/// # Errors
/// A bad configuration ([`ToolLifeConfig::check`]).
pub fn tool_life(c: &ToolLifeConfig) -> Result<Table, SimError> {
    c.check()?;
    table_of_rows(&COLUMNS, c.seed, c.n_rows, |i, rng| {
        let tool = i % c.n_tools;
        let vc = uniform(rng, c.cutting_speed_m_min);
        let f = uniform(rng, c.feed_mm);
        let coolant = uniform(rng, [18.0, 28.0]);
        let diameter = uniform(rng, [30.0, 120.0]);
        let scatter = (c.noise_rel * normal(rng)).exp();
        let taylor = (c.taylor_c_m_min / vc).powf(1.0 / c.taylor_n);
        let life = taylor * c.feed_factor(f) * scatter;
        [vc, f, coolant, diameter, (tool + 1) as f64, life]
    })
}
