//! Reading and writing hxai data folders (manifest + CSV/Parquet records) and plain tables.
//!
//! This is the only crate of the workspace that touches the file system for data. Everything
//! above it (signal processing, features, symbolic regression, the hybrid composer) works on
//! slices of `f64`; everything a user brings arrives through here and is checked here.
//!
//! # Main types
//!
//! - [`Record`]: one recording, `time_s`, `accel_ms2` and the optional `probe_um`,
//!   `command_um`, `encoder_um` channels; [`read_record`] / [`write_record`].
//! - [`DataFolder`] and [`ManifestEntry`]: a folder with `manifest.csv` (columns `record`,
//!   `file`, `amplitude_um`, `frequency_hz`, optional `repeat`, extra columns kept as text)
//!   and one file per record; [`read_folder`] / [`write_folder`].
//! - [`Table`] (numbers only; `hxai-table`'s, re-exported) and [`MixedTable`] (numbers and
//!   text, whose numeric part is a [`Table`]): generic tables for
//!   `hxai sr`, `hxai compare` and outputs; [`read_table`], [`write_table`],
//!   [`read_mixed_table`], [`write_mixed_table`].
//! - [`read_gappy_table`], [`GappyTable::resolve`] and [`MissingPolicy`]: tables with empty
//!   cells, refused, dropped or filled with training medians by the user's choice
//!   (`--missing`); [`set_missing_codes`]: numbers a file writes for a missing value
//!   (`-9999`), read as empty cells by every read of the process (`--missing-codes`).
//! - [`read_text`] / [`write_text`]: whole text files such as model JSON, so that file
//!   access stays in this crate.
//! - [`write_atomic`] / [`write_bytes`]: every file this crate writes goes through them
//!   (temporary file in the target folder, sync, rename), so a failed write never leaves a
//!   half-written or emptied file; [`check_output`] refuses an output path that is one of
//!   a command's inputs ([`DataFolder::input_files`] lists a folder's).
//! - [`DataError`]: every failure, naming the file and, for a bad cell, the row and column.
//!
//! The format (CSV or Parquet) is chosen by the file extension, `.csv` or `.parquet`
//! ([`Format::from_path`]).
//!
//! # Design decision: every cell is parsed here, not by the reader
//!
//! CSV files are read with every cell as text and parsed by this crate, and Parquet
//! columns are handed over cell by cell. A reader's own type inference would turn a stray
//! `n/a` into a failed cast with a message about data types, or silently turn a column
//! into text; parsing the cells ourselves lets every error say *which file, which row,
//! which column and what was there*, which is what a user needs to mend a recording.
//! Checking also happens before writing, so a file this crate writes always reads back.
//!
//! polars is used for the file formats only and never appears in the public API, so the
//! crates above do not depend on its version.
//!
//! # Checks on a record
//!
//! Required columns present; no empty, non-numeric, NaN or infinite cell; at least two
//! samples; `time_s` strictly increasing and uniform: every step within
//! [`UNIFORM_TIME_TOLERANCE`] (1 %) of the median step. The sampling rate is
//! `(n - 1) / (t_last - t_first)` ([`Record::fs_hz`]).
//!
//! # Example
//!
//! ```
//! use hxai_data::{Record, read_record, write_record};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let dir = std::env::temp_dir().join(format!("hxai-data-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! let fs = 1000.0;
//! let time_s: Vec<f64> = (0..100).map(|i| i as f64 / fs).collect();
//! let accel_ms2: Vec<f64> = time_s.iter().map(|t| (2.0 * std::f64::consts::PI * 10.0 * t).sin()).collect();
//! let rec = Record { time_s, accel_ms2, probe_um: None, command_um: None, encoder_um: None };
//! let path = dir.join("r1.parquet");
//! write_record(&path, &rec)?;
//! let back = read_record(&path)?;
//! assert_eq!(back, rec);
//! assert!((back.fs_hz() - fs).abs() < 1e-6 * fs);
//! std::fs::remove_dir_all(&dir)?;
//! # Ok(())
//! # }
//! ```
#![deny(missing_docs)]

mod atomic;
mod cells;
mod codes;
pub use codes::{CODE_TOLERANCE, missing_codes, set_missing_codes, take_missing_code_notes};
mod csvscan;
pub use csvscan::{CsvDialect, csv_dialect, set_csv_dialect};
mod error;
mod folder;
mod missing;
mod raw;
mod record;
mod stream;
mod table;
mod text;

pub use atomic::{
    AtomicFile, check_output, remove_temporary_files, stage, write_atomic, write_bytes,
};
pub use error::DataError;
pub use folder::{
    DataFolder, MANIFEST_COLUMNS, MANIFEST_FILE, ManifestEntry, read_folder, write_folder,
    write_manifest,
};
pub use hxai_table::format_number;
pub use hxai_table::{Table, TableError};
pub use missing::{GappyColumn, GappyTable, MissingPolicy, MissingReport, read_gappy_table};
pub use record::{RECORD_COLUMNS, Record, UNIFORM_TIME_TOLERANCE, read_record, write_record};
pub use stream::{MAX_LINE_BYTES, Sample, SampleReader};
pub use table::{
    Column, MixedTable, NumericView, read_mixed_table, read_table, read_table_with_units,
    stage_mixed_table, stage_table, write_mixed_table, write_table,
};
pub use text::{read_text, stage_text, write_text};

use std::path::Path;

/// File format, chosen by extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// Comma-separated text with a header row (`.csv`).
    Csv,
    /// Apache Parquet (`.parquet`).
    Parquet,
}

impl Format {
    /// The format of a file from its extension (`.csv` or `.parquet`, any letter case).
    /// A folder is [`DataError::IsADirectory`], whatever its name.
    pub fn from_path(path: &Path) -> Result<Format, DataError> {
        if path.is_dir() {
            return Err(DataError::IsADirectory {
                path: path.to_path_buf(),
            });
        }
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("csv") => Ok(Format::Csv),
            Some("parquet") => Ok(Format::Parquet),
            _ => Err(DataError::UnknownExtension {
                path: path.to_path_buf(),
            }),
        }
    }

    /// The extension without a dot: `csv` or `parquet`.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Csv => "csv",
            Format::Parquet => "parquet",
        }
    }
}

impl std::str::FromStr for Format {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "csv" => Ok(Format::Csv),
            "parquet" => Ok(Format::Parquet),
            other => Err(format!("unknown format `{other}`; use `csv` or `parquet`")),
        }
    }
}

/// The CSV reader's first pass (the separator, blank lines, Excel's empty rows), exposed
/// for `benches/reader.rs` only: it measures what the one reader of issue 52 costs beyond
/// the read itself. Internal: public and hidden from the docs only for the bench.
#[doc(hidden)]
pub mod bench_support {
    /// Whether `text` (a whole CSV file) needs the rewrite of `normalise` under the
    /// process's dialect: the pass every CSV read makes before polars sees the file.
    pub fn needs_rewrite(text: &str) -> bool {
        crate::csvscan::normalise(text, crate::csvscan::csv_dialect())
            .text
            .is_some()
    }
}
