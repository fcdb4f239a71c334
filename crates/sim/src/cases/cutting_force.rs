//! Main cutting force in turning: Kienzle's law plus the correction factors of the handbooks.
//!
//! The engineer's physics is Kienzle's law `Fc = kc1.1 b h^(1 - mc)` (`b` width of cut and
//! `h` uncut chip thickness in mm; for a 90° entering angle `b` is the depth of cut and `h`
//! the feed) with handbook values of `kc1.1` (N/mm²) and `mc`. The workpiece of the
//! generator is a C45 whose own `kc1.1` and `mc` differ from the handbook's (handbooks
//! disagree by tens of per cent for one steel), and the measured force carries the
//! multiplicative correction factors the handbooks list beside the law (all documented in
//! `docs/cases.md`):
//!
//! 1. **rake angle**: `K_gamma = 1 - c_gamma (gamma - gamma_ref)`, about 1-1.5 % less force
//!    per degree of positive rake;
//! 2. **cutting speed**: `K_v = (vc / vc_ref)^(-s_v)`, the thermal softening of the shear zone;
//! 3. **tool wear**: `K_VB = 1 + k_VB VB`, flank wear growing with the square root of cutting
//!    time, faster at higher speed (the same wear law as the roughness case);
//! 4. **measurement scatter**, multiplicative (log-normal), as a dynamometer's and the
//!    material's spread.
//!
//! Columns: `chip_thickness_mm` (`h`), `width_of_cut_mm` (`b`), `rake_angle_deg`,
//! `cutting_speed_m_min`, `cutting_time_min`, a distractor with no effect (`coolant_temp_C`),
//! `tool` (insert number, 1-based, a group column) and the target `Fc_N`.

use super::{
    noise_rel, non_negative, normal, positive, range, rng_for, rows_and_tools, table_of_rows,
    uniform, wear,
};
use crate::SimError;
use hxai_table::Table;
use serde::{Deserialize, Serialize};

/// Settings of the cutting-force generator: the workpiece's true Kienzle values, ranges of
/// the cutting conditions and the size of each correction (0 switches one off). Defaults and
/// their reasons: `docs/cases.md`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CuttingForceConfig {
    /// Rows to generate.
    pub n_rows: usize,
    /// Seed of every random draw.
    pub seed: u64,
    /// Number of inserts (the `tool` column); each has one rake angle.
    pub n_tools: usize,
    /// The workpiece's true specific cutting force at h = b = 1 mm (N/mm²).
    pub kc11_n_mm2: f64,
    /// The workpiece's true Kienzle exponent (-).
    pub mc: f64,
    /// Uncut chip thickness range, uniform (mm).
    pub chip_thickness_mm: [f64; 2],
    /// Width of cut range, uniform (mm).
    pub width_of_cut_mm: [f64; 2],
    /// Rake angles of the inserts, from low to high, spread evenly over the inserts (degrees).
    pub rake_angle_deg: [f64; 2],
    /// Cutting speed range, uniform (m/min).
    pub cutting_speed_m_min: [f64; 2],
    /// Cutting time range, uniform (min).
    pub cutting_time_min: [f64; 2],
    /// Relative force change per degree of rake (1/degree); 0 switches it off.
    pub rake_per_deg: f64,
    /// Rake angle at which the Kienzle values hold (degrees).
    pub rake_ref_deg: f64,
    /// Exponent `s_v` of the speed factor; 0 switches it off.
    pub speed_exponent: f64,
    /// Speed at which the Kienzle values hold (m/min).
    pub speed_ref_m_min: f64,
    /// Flank-wear rate: `VB` after 1 min at the wear reference speed (mm / sqrt(min)).
    pub wear_rate_mm: f64,
    /// Exponent of the cutting speed in the wear rate (-).
    pub wear_speed_exponent: f64,
    /// Reference cutting speed of the wear rate (m/min).
    pub wear_ref_speed_m_min: f64,
    /// Relative force increase per mm of flank wear (1/mm); 0 switches wear off.
    pub wear_force_per_mm: f64,
    /// Measurement scatter: standard deviation of the log of the measured/true ratio (-).
    pub noise_rel: f64,
}

/// Handbook `kc1.1` of C45 (Ck45) after Kienzle and Victor (N/mm²): the engineer's value.
pub const HANDBOOK_KC11: f64 = 2220.0;
/// Handbook `mc` of C45 (Ck45) after Kienzle and Victor (`1 - mc = 0.86`): the engineer's value.
pub const HANDBOOK_MC: f64 = 0.14;

impl Default for CuttingForceConfig {
    fn default() -> Self {
        Self {
            n_rows: 400,
            seed: super::DEFAULT_SEED,
            n_tools: 10,
            kc11_n_mm2: 1850.0,
            mc: 0.22,
            chip_thickness_mm: [0.05, 0.5],
            width_of_cut_mm: [0.5, 4.0],
            rake_angle_deg: [-6.0, 18.0],
            cutting_speed_m_min: [80.0, 300.0],
            cutting_time_min: [0.0, 30.0],
            rake_per_deg: 0.015,
            rake_ref_deg: 6.0,
            speed_exponent: 0.1,
            speed_ref_m_min: 100.0,
            wear_rate_mm: 0.03,
            wear_speed_exponent: 1.5,
            wear_ref_speed_m_min: 200.0,
            wear_force_per_mm: 1.0,
            noise_rel: 0.03,
        }
    }
}

impl CuttingForceConfig {
    /// The defaults with every correction and the scatter switched off: `Fc_N` is then
    /// exactly Kienzle's law with the configuration's `kc11_n_mm2` and `mc`.
    pub fn physics_only() -> Self {
        Self {
            rake_per_deg: 0.0,
            speed_exponent: 0.0,
            wear_force_per_mm: 0.0,
            noise_rel: 0.0,
            ..Self::default()
        }
    }

    /// Checks every setting.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] naming the first bad setting.
    pub fn check(&self) -> Result<(), SimError> {
        rows_and_tools(self.n_rows, self.n_tools)?;
        positive("kc11_n_mm2", self.kc11_n_mm2)?;
        if !(self.mc.is_finite() && (0.0..1.0).contains(&self.mc)) {
            return Err(super::bad("mc", self.mc, "must be in [0, 1)"));
        }
        range("chip_thickness_mm", self.chip_thickness_mm, true)?;
        range("width_of_cut_mm", self.width_of_cut_mm, true)?;
        let [g_lo, g_hi] = self.rake_angle_deg;
        if !(g_lo.is_finite() && g_hi.is_finite() && g_lo <= g_hi && g_lo > -45.0 && g_hi < 45.0) {
            return Err(super::bad(
                "rake_angle_deg",
                format!("[{g_lo}, {g_hi}]"),
                "must be [low, high] with -45 < low <= high < 45",
            ));
        }
        range("cutting_speed_m_min", self.cutting_speed_m_min, true)?;
        range("cutting_time_min", self.cutting_time_min, false)?;
        non_negative("rake_per_deg", self.rake_per_deg)?;
        if !self.rake_ref_deg.is_finite() {
            return Err(super::bad(
                "rake_ref_deg",
                self.rake_ref_deg,
                "must be finite",
            ));
        }
        // The rake factor must stay positive over the whole range of rake angles.
        let k_min = 1.0 - self.rake_per_deg * (g_hi - self.rake_ref_deg);
        if k_min <= 0.1 {
            return Err(super::bad(
                "rake_per_deg",
                self.rake_per_deg,
                "makes the rake factor 1 - c (gamma - gamma_ref) fall below 0.1 at the largest rake angle",
            ));
        }
        non_negative("speed_exponent", self.speed_exponent)?;
        positive("speed_ref_m_min", self.speed_ref_m_min)?;
        wear(
            self.wear_rate_mm,
            self.wear_speed_exponent,
            self.wear_ref_speed_m_min,
        )?;
        non_negative("wear_force_per_mm", self.wear_force_per_mm)?;
        noise_rel(self.noise_rel)
    }

    /// The rake angle of insert `tool` (0-based): evenly spread over the range.
    fn rake_of(&self, tool: usize) -> f64 {
        let [lo, hi] = self.rake_angle_deg;
        if self.n_tools == 1 {
            return 0.5 * (lo + hi);
        }
        lo + (hi - lo) * tool as f64 / (self.n_tools - 1) as f64
    }
}

/// Column names of the cutting-force table, in order; the target is last.
pub const COLUMNS: [&str; 8] = [
    "chip_thickness_mm",
    "width_of_cut_mm",
    "rake_angle_deg",
    "cutting_speed_m_min",
    "cutting_time_min",
    "coolant_temp_C",
    "tool",
    "Fc_N",
];

/// Kienzle's law in the syntax of `hxai hybrid --physics`, parameters `kc` and `mc`.
pub const PHYSICS: &str = "kc*width_of_cut_mm*chip_thickness_mm^(1-mc)";

/// Generates the cutting-force table (columns [`COLUMNS`]).
///
/// # Errors
/// A bad configuration ([`CuttingForceConfig::check`]).
pub fn cutting_force(c: &CuttingForceConfig) -> Result<Table, SimError> {
    c.check()?;
    // Tools are assigned in a shuffled order so that the rake angle does not follow the row.
    let mut tools_rng = rng_for(c.seed, None);
    let mut order: Vec<usize> = (0..c.n_tools).collect();
    rand::seq::SliceRandom::shuffle(order.as_mut_slice(), &mut tools_rng);
    table_of_rows(&COLUMNS, c.seed, c.n_rows, |i, rng| {
        let tool = order[i % c.n_tools];
        let gamma = c.rake_of(tool);
        let h = uniform(rng, c.chip_thickness_mm);
        let b = uniform(rng, c.width_of_cut_mm);
        let vc = uniform(rng, c.cutting_speed_m_min);
        let t = uniform(rng, c.cutting_time_min);
        let coolant = uniform(rng, [18.0, 28.0]);
        let scatter = (c.noise_rel * normal(rng)).exp();
        let kienzle = c.kc11_n_mm2 * b * h.powf(1.0 - c.mc);
        let k_gamma = 1.0 - c.rake_per_deg * (gamma - c.rake_ref_deg);
        let k_v = (vc / c.speed_ref_m_min).powf(-c.speed_exponent);
        let vb = super::flank_wear_mm(
            c.wear_rate_mm,
            c.wear_speed_exponent,
            c.wear_ref_speed_m_min,
            vc,
            t,
        );
        let k_vb = 1.0 + c.wear_force_per_mm * vb;
        let fc = kienzle * k_gamma * k_v * k_vb * scatter;
        [h, b, gamma, vc, t, coolant, (tool + 1) as f64, fc]
    })
}
