//! The `--record FILE --frequency-hz HZ` pair of the commands that read one record
//! (`displacement`, `features`, `predict`), and the plausibility warnings on it.
use std::path::PathBuf;

/// The record file and its commanded frequency (flattened into each command's arguments).
#[derive(Debug, clap::Args)]
pub struct RecordArgs {
    /// Record file (CSV or Parquet, by extension) with columns `time_s` and `accel_ms2`
    /// (`probe_um` is not needed).
    #[arg(long)]
    pub record: PathBuf,
    /// Commanded frequency of the record, Hz.
    #[arg(long)]
    pub frequency_hz: f64,
}

impl RecordArgs {
    /// The plausibility warnings on the record read from `self.record` (sampling rate,
    /// length, frequency), printed on stderr and returned for the JSON output.
    pub fn warn(&self, rec: &hxai_data::Record) -> Vec<String> {
        let warnings: Vec<String> = hxai_hybrid::records::record_warnings(
            &self.record.display().to_string(),
            rec.fs_hz(),
            self.frequency_hz,
            rec.len(),
        )
        .iter()
        .map(ToString::to_string)
        .collect();
        crate::safety::warn(&warnings);
        warnings
    }
}
