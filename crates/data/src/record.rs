//! One recording: time, acceleration and the optional position channels.

use crate::cells::{check_all_finite, finite_column, require_column, require_rows};
use crate::raw::{self, OutColumn};
use crate::{DataError, Format};
use std::path::Path;

/// Relative tolerance on uniform sampling: every step of `time_s` must lie within
/// `UNIFORM_TIME_TOLERANCE * median_step` of the median step. (The median, not the mean,
/// so that one bad step is reported where it is rather than skewing the reference.)
///
/// One per cent admits time stamps rounded to a few digits (a 10 kHz record written with
/// 6 decimals is off by at most 0.5 %) and still rejects a single dropped or repeated
/// sample, which moves a step by 100 %.
pub const UNIFORM_TIME_TOLERANCE: f64 = 1e-2;

/// Column names of the recording format, in the order they are written.
pub const RECORD_COLUMNS: [&str; 5] = [
    "time_s",
    "accel_ms2",
    "probe_um",
    "command_um",
    "encoder_um",
];

/// One recording of the machine (see "Recording format" in the interfaces document).
///
/// A `Record` returned by [`read_record`] has passed [`Record::check`]: at least two
/// samples, all channels equally long and finite, time strictly increasing and uniform.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Time stamps in seconds, strictly increasing, uniformly spaced.
    pub time_s: Vec<f64>,
    /// Z acceleration near the tool, m/s^2.
    pub accel_ms2: Vec<f64>,
    /// Ground-truth Z position from the capacitance probe, um (needed to fit and evaluate).
    pub probe_um: Option<Vec<f64>>,
    /// Commanded Z position, um.
    pub command_um: Option<Vec<f64>>,
    /// Encoder Z position, um.
    pub encoder_um: Option<Vec<f64>>,
}

impl Record {
    /// Sampling rate in Hz, `(n - 1) / (t_last - t_first)`.
    ///
    /// Returns NaN when the record has fewer than two samples (a validated record never does).
    pub fn fs_hz(&self) -> f64 {
        match (self.time_s.first(), self.time_s.last()) {
            (Some(a), Some(b)) if self.time_s.len() >= 2 && b > a => {
                (self.time_s.len() - 1) as f64 / (b - a)
            }
            _ => f64::NAN,
        }
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time_s.len()
    }

    /// Whether the record holds no samples.
    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }

    /// Checks the record as if it were the file `path` (used before writing, and by
    /// readers): lengths, finiteness and time, each error naming the row and column.
    pub fn check(&self, path: &Path) -> Result<(), DataError> {
        let n = self.time_s.len();
        for (name, col) in self.channels() {
            if col.len() != n {
                return Err(DataError::LengthMismatch {
                    path: path.to_path_buf(),
                    column: name.to_owned(),
                    len: col.len(),
                    reference: "time_s".to_owned(),
                    expected: n,
                });
            }
        }
        for (name, col) in self.channels() {
            check_all_finite(path, name, col)?;
        }
        check_time(path, &self.time_s)
    }

    /// The channels present, with their column names, `time_s` first.
    pub fn channels(&self) -> Vec<(&'static str, &[f64])> {
        let mut out: Vec<(&'static str, &[f64])> = vec![
            (RECORD_COLUMNS[0], &self.time_s),
            (RECORD_COLUMNS[1], &self.accel_ms2),
        ];
        for (name, col) in [
            (RECORD_COLUMNS[2], &self.probe_um),
            (RECORD_COLUMNS[3], &self.command_um),
            (RECORD_COLUMNS[4], &self.encoder_um),
        ] {
            if let Some(c) = col {
                out.push((name, c));
            }
        }
        out
    }
}

/// Checks that `time` has at least two samples, strictly increases and is uniform within
/// [`UNIFORM_TIME_TOLERANCE`].
pub(crate) fn check_time(path: &Path, time: &[f64]) -> Result<(), DataError> {
    let n = time.len();
    if n < 2 {
        return Err(DataError::TooShort {
            path: path.to_path_buf(),
            rows: n,
        });
    }
    for i in 1..n {
        if time[i] <= time[i - 1] {
            return Err(DataError::TimeNotIncreasing {
                path: path.to_path_buf(),
                row: i + 1,
                previous: time[i - 1],
                value: time[i],
            });
        }
    }
    let mut steps: Vec<f64> = time.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    let median_step = steps[steps.len() / 2];
    for i in 1..n {
        let step = time[i] - time[i - 1];
        if (step - median_step).abs() > UNIFORM_TIME_TOLERANCE * median_step {
            return Err(DataError::TimeNotUniform {
                path: path.to_path_buf(),
                row: i + 1,
                step,
                expected: median_step,
                tolerance: UNIFORM_TIME_TOLERANCE,
            });
        }
    }
    Ok(())
}

/// Reads a record file; CSV or Parquet by extension. Extra columns are ignored.
pub fn read_record(path: &Path) -> Result<Record, DataError> {
    let format = Format::from_path(path)?;
    let raw = raw::read(path, format)?;
    require_rows(path, &raw)?;
    let time_i = require_column(path, &raw, "time_s")?;
    if let Some(dtype) = &raw.integer_type[time_i] {
        // Integer time is nanoseconds or milliseconds in practice, never whole seconds;
        // read as seconds it would give a sampling rate of 1e-5 Hz without a word.
        return Err(DataError::UnsupportedType {
            path: path.to_path_buf(),
            column: "time_s".into(),
            dtype: format!("integers ({dtype})"),
            hint: "`time_s` must be seconds as floating point; integer time is usually \
                   nanoseconds or milliseconds: divide by 1e9 or 1e3 and store as float64",
        });
    }
    let accel_i = require_column(path, &raw, "accel_ms2")?;
    let optional = |name: &str| -> Result<Option<Vec<f64>>, DataError> {
        raw.find(name)
            .map(|i| finite_column(path, &raw, i))
            .transpose()
    };
    let rec = Record {
        time_s: finite_column(path, &raw, time_i)?,
        accel_ms2: finite_column(path, &raw, accel_i)?,
        probe_um: optional("probe_um")?,
        command_um: optional("command_um")?,
        encoder_um: optional("encoder_um")?,
    };
    rec.check(path)?;
    Ok(rec)
}

/// Writes a record file; CSV or Parquet by extension. The record is validated first,
/// so a written file always reads back.
pub fn write_record(path: &Path, rec: &Record) -> Result<(), DataError> {
    stage_record(path, rec)?.commit()
}

/// [`write_record`] staged, not committed (see [`crate::stage`]).
pub(crate) fn stage_record(path: &Path, rec: &Record) -> Result<crate::AtomicFile, DataError> {
    let format = Format::from_path(path)?;
    rec.check(path)?;
    let channels = rec.channels();
    let names: Vec<String> = channels.iter().map(|(n, _)| (*n).to_owned()).collect();
    let cols: Vec<OutColumn<'_>> = channels.iter().map(|(_, c)| OutColumn::Num(c)).collect();
    raw::stage(path, format, &names, &cols)
}
