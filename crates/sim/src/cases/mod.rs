//! Three more manufacturing processes as seeded table generators: finish-turning surface
//! roughness ([`roughness()`]) and the main cutting force in turning ([`cutting_force()`])
//! (issue 13), and tool life in turning ([`tool_life()`], issue 23: the case whose hidden
//! truth is one short closed form in one column), and a spindle's thermal drift
//! ([`spindle_thermal()`], issue 69: a dynamic process, one row per sample of several runs).
//!
//! Each generator starts from the law an engineer would write down (the *physics*: the
//! kinematic roughness `Ra = f^2 / (32 r)`, Kienzle's force law `Fc = kc1.1 b h^(1 - mc)`,
//! Taylor's tool-life law `T = (C / vc)^(1/n)`) and adds effects the machining literature reports, with magnitudes in their published
//! ranges, plus measurement scatter and distractor columns. The hidden truths and their
//! sources are written out in `docs/cases.md`, so a reader can judge whether a correction
//! found by symbolic regression is physically sensible. Every effect has its own switch in
//! the configuration: with all of them at zero and no scatter the target column *is* the
//! engineer's law.
//!
//! Design decision (as for the machine simulator): row `i` draws its randomness from a
//! `ChaCha8Rng` seeded by the seed on stream `i + 1` (stream 0 draws the tools), so a row
//! does not depend on how many rows are asked for, and the output is a pure function of the
//! configuration.

pub mod cutting_force;
pub mod roughness;
pub mod spindle_thermal;
pub mod tool_life;

pub use cutting_force::{CuttingForceConfig, cutting_force};
pub use roughness::{RoughnessConfig, roughness};
pub use spindle_thermal::{SpindleThermalConfig, spindle_thermal};
pub use tool_life::{ToolLifeConfig, tool_life};

use crate::SimError;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// The generators by name, as `hxai simulate --case NAME` accepts them.
pub const CASE_NAMES: [&str; 4] = ["roughness", "cutting_force", "tool_life", "spindle_thermal"];

/// Seed of every generator's default configuration.
pub const DEFAULT_SEED: u64 = 42;

/// Largest table a generator will build (rows).
pub const MAX_ROWS: usize = 10_000_000;

/// Replaces a case configuration's row count and seed (`fields`) by the ones given.
fn override_rows_and_seed(fields: (&mut usize, &mut u64), rows: Option<usize>, seed: Option<u64>) {
    if let Some(n) = rows {
        *fields.0 = n;
    }
    if let Some(s) = seed {
        *fields.1 = s;
    }
}

/// Generates the named case (one of [`CASE_NAMES`]) with its default configuration, `rows`
/// rows and the given seed.
///
/// # Errors
/// [`SimError::UnknownCase`] for another name; the generator's own errors otherwise.
pub fn generate_case(
    name: &str,
    rows: Option<usize>,
    seed: Option<u64>,
) -> Result<hxai_table::Table, SimError> {
    match name {
        "roughness" => {
            let mut c = RoughnessConfig::default();
            override_rows_and_seed((&mut c.n_rows, &mut c.seed), rows, seed);
            roughness(&c)
        }
        "cutting_force" => {
            let mut c = CuttingForceConfig::default();
            override_rows_and_seed((&mut c.n_rows, &mut c.seed), rows, seed);
            cutting_force(&c)
        }
        "tool_life" => {
            let mut c = ToolLifeConfig::default();
            override_rows_and_seed((&mut c.n_rows, &mut c.seed), rows, seed);
            tool_life(&c)
        }
        "spindle_thermal" => {
            let mut c = SpindleThermalConfig::default();
            if let Some(s) = seed {
                c.seed = s;
            }
            spindle_thermal(&c, rows)
        }
        other => Err(SimError::UnknownCase {
            name: other.to_string(),
            known: CASE_NAMES.join(", "),
        }),
    }
}

pub(crate) fn bad(name: &'static str, value: impl std::fmt::Display, reason: &str) -> SimError {
    SimError::InvalidParameter {
        name,
        value: value.to_string(),
        reason: reason.to_string(),
    }
}

/// `v` finite and `>= 0`.
pub(crate) fn non_negative(name: &'static str, v: f64) -> Result<(), SimError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(bad(name, v, "must be a finite number >= 0"))
    }
}

/// `v` finite and `> 0`.
pub(crate) fn positive(name: &'static str, v: f64) -> Result<(), SimError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(bad(name, v, "must be a finite number > 0"))
    }
}

/// `[lo, hi]` finite with `lo <= hi`, and `lo > 0` when `strict`, else `lo >= 0`.
pub(crate) fn range(name: &'static str, r: [f64; 2], strict: bool) -> Result<(), SimError> {
    let [lo, hi] = r;
    let lo_ok = if strict { lo > 0.0 } else { lo >= 0.0 };
    if lo.is_finite() && hi.is_finite() && lo_ok && lo <= hi {
        Ok(())
    } else {
        Err(bad(
            name,
            format!("[{lo}, {hi}]"),
            if strict {
                "must be [low, high] with 0 < low <= high"
            } else {
                "must be [low, high] with 0 <= low <= high"
            },
        ))
    }
}

/// Row count in `1..=MAX_ROWS`.
pub(crate) fn rows(n: usize) -> Result<(), SimError> {
    if (1..=MAX_ROWS).contains(&n) {
        Ok(())
    } else {
        Err(bad("n_rows", n, &format!("must be in 1..={MAX_ROWS}")))
    }
}

/// Row count in `1..=MAX_ROWS` and at least one tool.
pub(crate) fn rows_and_tools(n_rows: usize, n_tools: usize) -> Result<(), SimError> {
    rows(n_rows)?;
    if n_tools == 0 {
        return Err(bad("n_tools", 0, "must be at least 1"));
    }
    Ok(())
}

/// The settings of [`flank_wear_mm`]: rate and speed exponent `>= 0`, reference speed `> 0`.
pub(crate) fn wear(
    rate_mm: f64,
    speed_exponent: f64,
    ref_speed_m_min: f64,
) -> Result<(), SimError> {
    non_negative("wear_rate_mm", rate_mm)?;
    non_negative("wear_speed_exponent", speed_exponent)?;
    positive("wear_ref_speed_m_min", ref_speed_m_min)
}

/// The relative measurement scatter in `[0, 1]`.
pub(crate) fn noise_rel(v: f64) -> Result<(), SimError> {
    if v.is_finite() && (0.0..=1.0).contains(&v) {
        Ok(())
    } else {
        Err(bad("noise_rel", v, "must be in [0, 1]"))
    }
}

/// The table with columns `names` and `n_rows` rows, row `i` made by `row(i, rng)` from the
/// random source of row `i` ([`rng_for`]).
pub(crate) fn table_of_rows<const N: usize>(
    names: &[&str; N],
    seed: u64,
    n_rows: usize,
    mut row: impl FnMut(usize, &mut ChaCha8Rng) -> [f64; N],
) -> Result<hxai_table::Table, SimError> {
    let mut cols: Vec<Vec<f64>> = vec![Vec::with_capacity(n_rows); N];
    for i in 0..n_rows {
        let mut rng = rng_for(seed, Some(i));
        for (col, v) in cols.iter_mut().zip(row(i, &mut rng)) {
            col.push(v);
        }
    }
    Ok(hxai_table::Table::new(
        names.iter().map(|s| s.to_string()).collect(),
        cols,
    )?)
}

/// The random source of row `row` (stream `row + 1`) or of the tools (`None`, stream 0).
pub(crate) fn rng_for(seed: u64, row: Option<usize>) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(row.map_or(0, |r| r as u64 + 1));
    rng
}

/// Uniform on `[lo, hi]` (exactly `lo` when the range is a point).
pub(crate) fn uniform(rng: &mut ChaCha8Rng, [lo, hi]: [f64; 2]) -> f64 {
    lo + (hi - lo) * rng.r#gen::<f64>()
}

/// A standard normal draw.
pub(crate) fn normal(rng: &mut ChaCha8Rng) -> f64 {
    StandardNormal.sample(rng)
}

/// Flank-wear land width `VB` (mm) after `t_min` minutes at `vc` m/min: a square-root growth
/// with time whose rate rises with cutting speed, `VB = rate (vc / vc_ref)^speed_exp sqrt(t)`.
pub(crate) fn flank_wear_mm(rate: f64, speed_exp: f64, vc_ref: f64, vc: f64, t_min: f64) -> f64 {
    rate * (vc / vc_ref).powf(speed_exp) * t_min.sqrt()
}
