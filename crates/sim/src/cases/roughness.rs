//! Finish-turning surface roughness: the kinematic law plus the effects the literature reports.
//!
//! The engineer's physics is the kinematic roughness of a round-nosed tool, the peak-to-valley
//! height `Rt = f^2 / (8 r)` of the feed marks and, for that parabolic profile, `Ra = Rt / 4 =
//! f^2 / (32 r)` (`f` feed in mm/rev, `r` nose radius in mm; times 1000 for µm). The
//! generator's measured roughness adds, in this order (all documented in `docs/cases.md`):
//!
//! 1. **minimum chip thickness (ploughing)**, Brammertz's form of the peak-to-valley height,
//!    `Rt = f^2 / (8 r) + h_min / 2 (1 + r h_min / f^2)`, with `h_min` per tool (edge
//!    preparation scatters from insert to insert), converted with the same `Ra = Rt / 4`;
//! 2. **flank wear** growing with the square root of cutting time, faster at higher cutting
//!    speed, multiplying the roughness by `1 + k_VB VB`;
//! 3. **built-up edge** at low cutting speed: an additive term that fades out above a
//!    transition speed (logistic in `vc`);
//! 4. **relative vibration** of tool and workpiece, growing with the depth of cut (force);
//! 5. **measurement scatter**, multiplicative (log-normal), as a profilometer's repeatability.
//!
//! Columns: `feed_mm` (mm/rev), `nose_radius_mm`, `cutting_speed_m_min`, `cutting_time_min`,
//! `depth_of_cut_mm`, two distractors with no effect (`coolant_temp_C`,
//! `workpiece_diameter_mm`), `tool` (insert number, 1-based: a group column for grouped
//! splits; the nose radius and `h_min` belong to the insert), and the target `Ra_um`.

use super::{
    noise_rel, non_negative, normal, positive, range, rng_for, rows_and_tools, table_of_rows,
    uniform, wear,
};
use crate::SimError;
use hxai_table::Table;
use serde::{Deserialize, Serialize};

/// Settings of the roughness generator: ranges of the cutting conditions and the size of
/// each effect (0 switches an effect off). Defaults and their reasons: `docs/cases.md`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct RoughnessConfig {
    /// Rows to generate.
    pub n_rows: usize,
    /// Seed of every random draw.
    pub seed: u64,
    /// Number of inserts (the `tool` column); each has its nose radius and `h_min`.
    pub n_tools: usize,
    /// Nose radii the inserts are chosen from, in turn (mm).
    pub nose_radii_mm: Vec<f64>,
    /// Feed range, uniform (mm/rev).
    pub feed_mm: [f64; 2],
    /// Cutting speed range, uniform (m/min).
    pub cutting_speed_m_min: [f64; 2],
    /// Cutting time range, uniform: how long the insert has cut when the surface is made (min).
    pub cutting_time_min: [f64; 2],
    /// Depth of cut range, uniform (mm).
    pub depth_of_cut_mm: [f64; 2],
    /// Mean minimum chip thickness of Brammertz's form (mm); 0 switches ploughing off.
    pub h_min_mm: f64,
    /// Relative standard deviation of `h_min` from insert to insert (-).
    pub h_min_tool_sd: f64,
    /// Flank-wear rate: `VB` after 1 min at the reference speed (mm / sqrt(min)).
    pub wear_rate_mm: f64,
    /// Exponent of the cutting speed in the wear rate (-).
    pub wear_speed_exponent: f64,
    /// Reference cutting speed of the wear rate (m/min).
    pub wear_ref_speed_m_min: f64,
    /// Relative roughness increase per mm of flank wear (1/mm); 0 switches wear off.
    pub wear_ra_per_mm: f64,
    /// Built-up-edge roughness well below the transition speed (µm); 0 switches it off.
    pub bue_um: f64,
    /// Cutting speed at which the built-up edge's contribution is halved (m/min).
    pub bue_speed_m_min: f64,
    /// Width of the built-up edge's fade-out in speed (m/min).
    pub bue_width_m_min: f64,
    /// Roughness from relative vibration per mm of depth of cut (µm/mm); 0 switches it off.
    pub vibration_um_per_mm: f64,
    /// Measurement scatter: standard deviation of the log of the measured/true ratio (-).
    pub noise_rel: f64,
}

impl Default for RoughnessConfig {
    fn default() -> Self {
        Self {
            n_rows: 400,
            seed: super::DEFAULT_SEED,
            n_tools: 12,
            nose_radii_mm: vec![0.4, 0.8, 1.2],
            feed_mm: [0.04, 0.3],
            cutting_speed_m_min: [50.0, 300.0],
            cutting_time_min: [0.0, 40.0],
            depth_of_cut_mm: [0.2, 1.5],
            h_min_mm: 0.002,
            h_min_tool_sd: 0.15,
            wear_rate_mm: 0.03,
            wear_speed_exponent: 1.5,
            wear_ref_speed_m_min: 200.0,
            wear_ra_per_mm: 2.0,
            bue_um: 0.8,
            bue_speed_m_min: 90.0,
            bue_width_m_min: 12.0,
            vibration_um_per_mm: 0.12,
            noise_rel: 0.06,
        }
    }
}

impl RoughnessConfig {
    /// The defaults with every effect and the scatter switched off: `Ra_um` is then exactly
    /// the kinematic law `1000 feed_mm^2 / (32 nose_radius_mm)`.
    pub fn physics_only() -> Self {
        Self {
            h_min_mm: 0.0,
            wear_ra_per_mm: 0.0,
            bue_um: 0.0,
            vibration_um_per_mm: 0.0,
            noise_rel: 0.0,
            ..Self::default()
        }
    }

    /// Checks every setting (ranges ordered and positive where a law needs it).
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] naming the first bad setting, [`SimError::EmptyList`]
    /// for an empty list of nose radii.
    pub fn check(&self) -> Result<(), SimError> {
        rows_and_tools(self.n_rows, self.n_tools)?;
        if self.nose_radii_mm.is_empty() {
            return Err(SimError::EmptyList {
                name: "nose_radii_mm",
            });
        }
        for &r in &self.nose_radii_mm {
            positive("nose_radii_mm", r)?;
        }
        range("feed_mm", self.feed_mm, true)?;
        range("cutting_speed_m_min", self.cutting_speed_m_min, true)?;
        range("cutting_time_min", self.cutting_time_min, false)?;
        range("depth_of_cut_mm", self.depth_of_cut_mm, true)?;
        non_negative("h_min_mm", self.h_min_mm)?;
        if !(self.h_min_tool_sd.is_finite() && (0.0..0.5).contains(&self.h_min_tool_sd)) {
            return Err(super::bad(
                "h_min_tool_sd",
                self.h_min_tool_sd,
                "must be in [0, 0.5) (a relative scatter)",
            ));
        }
        wear(
            self.wear_rate_mm,
            self.wear_speed_exponent,
            self.wear_ref_speed_m_min,
        )?;
        non_negative("wear_ra_per_mm", self.wear_ra_per_mm)?;
        non_negative("bue_um", self.bue_um)?;
        positive("bue_speed_m_min", self.bue_speed_m_min)?;
        positive("bue_width_m_min", self.bue_width_m_min)?;
        non_negative("vibration_um_per_mm", self.vibration_um_per_mm)?;
        noise_rel(self.noise_rel)
    }
}

/// Column names of the roughness table, in order; the target is last.
pub const COLUMNS: [&str; 9] = [
    "feed_mm",
    "nose_radius_mm",
    "cutting_speed_m_min",
    "cutting_time_min",
    "depth_of_cut_mm",
    "coolant_temp_C",
    "workpiece_diameter_mm",
    "tool",
    "Ra_um",
];

/// The engineer's law in the syntax of `hxai hybrid --physics` (µm from mm).
pub const PHYSICS: &str = "1000*feed_mm^2/(32*nose_radius_mm)";

/// The hidden truth of one row, before measurement scatter (µm). `h_min` and `wear` are in mm.
fn true_ra_um(c: &RoughnessConfig, f: f64, r: f64, vc: f64, t: f64, ap: f64, h_min: f64) -> f64 {
    let kinematic = 1000.0 * f * f / (32.0 * r);
    // Brammertz: Rt gains h_min/2 (1 + r h_min / f^2); Ra = Rt / 4, in µm.
    let ploughing = 1000.0 / 4.0 * (h_min / 2.0) * (1.0 + r * h_min / (f * f));
    let vb = super::flank_wear_mm(
        c.wear_rate_mm,
        c.wear_speed_exponent,
        c.wear_ref_speed_m_min,
        vc,
        t,
    );
    let wear = 1.0 + c.wear_ra_per_mm * vb;
    let bue = c.bue_um / (1.0 + ((vc - c.bue_speed_m_min) / c.bue_width_m_min).exp());
    let vibration = c.vibration_um_per_mm * ap;
    (kinematic + ploughing) * wear + bue + vibration
}

/// Generates the roughness table (columns [`COLUMNS`]).
///
/// # Errors
/// A bad configuration ([`RoughnessConfig::check`]).
pub fn roughness(c: &RoughnessConfig) -> Result<Table, SimError> {
    c.check()?;
    let mut tools_rng = rng_for(c.seed, None);
    let tools: Vec<(f64, f64)> = (0..c.n_tools)
        .map(|k| {
            let r = c.nose_radii_mm[k % c.nose_radii_mm.len()];
            let h = c.h_min_mm * (c.h_min_tool_sd * normal(&mut tools_rng)).exp();
            (r, h)
        })
        .collect();
    table_of_rows(&COLUMNS, c.seed, c.n_rows, |i, rng| {
        let tool = i % c.n_tools;
        let (r, h_min) = tools[tool];
        let f = uniform(rng, c.feed_mm);
        let vc = uniform(rng, c.cutting_speed_m_min);
        let t = uniform(rng, c.cutting_time_min);
        let ap = uniform(rng, c.depth_of_cut_mm);
        let coolant = uniform(rng, [18.0, 28.0]);
        let diameter = uniform(rng, [30.0, 120.0]);
        let scatter = (c.noise_rel * normal(rng)).exp();
        let ra = true_ra_um(c, f, r, vc, t, ap, h_min) * scatter;
        [f, r, vc, t, ap, coolant, diameter, (tool + 1) as f64, ra]
    })
}
