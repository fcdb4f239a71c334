//! `hxai features`: the twelve acceleration features (paper Table 2) of one record.
use anyhow::{Context, Result};
use hxai_features::{FeatureConfig, Features, PsdEstimator, Sigma};

use crate::Global;
use crate::one_record::RecordArgs;

/// Sigma of kurtosis and skewness.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum SigmaArg {
    /// 1/N deviation (scipy.stats default).
    Biased,
    /// 1/(N-1) deviation.
    Unbiased,
}

/// PSD estimator of the mean frequency and total power.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum PsdArg {
    /// Welch, scipy.signal.welch defaults.
    Welch,
    /// One-segment periodogram, scipy.signal.periodogram defaults.
    Periodogram,
}

/// Arguments of `hxai features`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The record and its commanded frequency (feature f1).
    #[command(flatten)]
    pub input: RecordArgs,
    /// Sigma of kurtosis (f6) and skewness (f7).
    #[arg(long, value_enum, default_value = "biased")]
    pub sigma: SigmaArg,
    /// PSD estimator of f11 and f12.
    #[arg(long, value_enum, default_value = "welch")]
    pub psd: PsdArg,
    /// Print one JSON document with keys `f1`..`f12` on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Runs `hxai features`.
pub fn run(args: Args, _g: &Global) -> Result<()> {
    let rec = hxai_data::read_record(&args.input.record)
        .with_context(|| format!("reading record {}", args.input.record.display()))?;
    anyhow::ensure!(
        args.input.frequency_hz.is_finite() && args.input.frequency_hz > 0.0,
        "--frequency-hz must be a positive number of Hz, got {}",
        hxai_data::format_number(args.input.frequency_hz)
    );
    hxai_features::check_covers_one_period(rec.len(), rec.fs_hz(), args.input.frequency_hz)
        .with_context(|| args.input.record.display().to_string())?;
    let warnings = args.input.warn(&rec);
    let cfg = FeatureConfig {
        sigma: match args.sigma {
            SigmaArg::Biased => Sigma::Biased,
            SigmaArg::Unbiased => Sigma::Unbiased,
        },
        psd: match args.psd {
            PsdArg::Welch => PsdEstimator::default(),
            PsdArg::Periodogram => PsdEstimator::Periodogram,
        },
    };
    let f = hxai_features::extract_with(&rec.accel_ms2, rec.fs_hz(), args.input.frequency_hz, &cfg)
        .with_context(|| format!("features of {}", args.input.record.display()))?;
    if args.json {
        let mut doc = serde_json::to_value(f)?;
        if let Some(obj) = doc.as_object_mut() {
            obj.insert("warnings".into(), serde_json::json!(warnings));
        }
        crate::safety::emit(&doc.to_string())?;
    } else {
        for ((name, long), v) in Features::NAMES
            .iter()
            .zip(Features::LONG_NAMES)
            .zip(f.to_vec())
        {
            crate::safety::emit(&format!("{name:>4}  {long:<20} {v:.10e}"))?;
        }
    }
    Ok(())
}
