//! The one error type of `hxai-data`.

use hxai_table::format_number;
use std::path::PathBuf;

/// Everything that can go wrong while reading or writing recordings, manifests and tables.
///
/// Every variant names the file; those about a cell also name the row and the column.
/// Rows are counted from 1 over the data rows, the header not counted, so in a CSV file
/// data row `r` is on line `r + 1`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DataError {
    /// The operating system refused to read or write a file.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// The file name ends in neither `.csv` nor `.parquet`.
    #[error(
        "{}: unknown file type; name the file `*.csv` or `*.parquet` (the extension chooses the format)",
        path.display()
    )]
    UnknownExtension {
        /// The file.
        path: PathBuf,
    },
    /// The file has no data rows (it is empty or holds a header only).
    #[error("{}: the file has no data rows{}", path.display(), if *header_only { " (only a header)" } else { " (it is empty)" })]
    Empty {
        /// The file.
        path: PathBuf,
        /// Whether a header was present.
        header_only: bool,
    },
    /// The CSV or Parquet reader could not make sense of the file.
    #[error("{}: cannot parse the file: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// The reader's message.
        message: String,
    },
    /// Writing a CSV or Parquet file failed.
    #[error("{}: cannot write the file: {message}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The writer's message.
        message: String,
    },
    /// A line of a sample stream (`hxai stream`) is not what the header promised.
    #[error("{source_name}, line {line}: {message}")]
    StreamLine {
        /// Where the stream comes from (a file's path, or `standard input`).
        source_name: String,
        /// The line, counted from 1 with the header as line 1.
        line: usize,
        /// What is wrong with it.
        message: String,
    },
    /// A required column is absent.
    #[error("{}: missing column `{column}` (columns found: {})", path.display(), found.join(", "))]
    MissingColumn {
        /// The file.
        path: PathBuf,
        /// The column that is required.
        column: String,
        /// The columns the file has.
        found: Vec<String>,
    },
    /// Two columns carry the same name.
    #[error("{}: column `{column}` appears more than once; rename one of them", path.display())]
    DuplicateColumn {
        /// The file.
        path: PathBuf,
        /// The repeated name.
        column: String,
    },
    /// A cell that must hold a number is empty.
    #[error("{}: row {row}, column `{column}`: the cell is empty; every row needs a number here", path.display())]
    MissingValue {
        /// The file.
        path: PathBuf,
        /// Data row, counted from 1.
        row: usize,
        /// The column.
        column: String,
    },
    /// A cell that must hold a number holds text.
    #[error("{}: row {row}, column `{column}`: `{value}` is not a number", path.display())]
    NonNumeric {
        /// The file.
        path: PathBuf,
        /// Data row, counted from 1.
        row: usize,
        /// The column.
        column: String,
        /// The offending cell text.
        value: String,
    },
    /// A cell holds NaN or an infinity.
    #[error("{}: row {row}, column `{column}`: value {value} is not finite; remove or repair the sample", path.display())]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// Data row, counted from 1.
        row: usize,
        /// The column.
        column: String,
        /// The value read.
        value: f64,
    },
    /// A number is outside the range its column allows.
    #[error("{}: row {row}, column `{column}`: value `{value}` is invalid: {expected}", path.display())]
    InvalidValue {
        /// The file.
        path: PathBuf,
        /// Data row, counted from 1.
        row: usize,
        /// The column.
        column: String,
        /// The value read, as text.
        value: String,
        /// What the column allows.
        expected: &'static str,
    },
    /// A record has fewer than two samples, so no sampling rate can be read from `time_s`.
    #[error("{}: the record has {rows} sample(s); at least 2 are needed to read the sampling rate", path.display())]
    TooShort {
        /// The file.
        path: PathBuf,
        /// Number of samples found.
        rows: usize,
    },
    /// `time_s` does not strictly increase.
    #[error(
        "{}: row {row}, column `time_s`: time {} s does not exceed the previous time {} s; time must strictly increase",
        path.display(), format_number(*value), format_number(*previous)
    )]
    TimeNotIncreasing {
        /// The file.
        path: PathBuf,
        /// Data row, counted from 1.
        row: usize,
        /// Time at the previous row.
        previous: f64,
        /// Time at this row.
        value: f64,
    },
    /// The sampling of `time_s` is not uniform.
    #[error(
        "{}: row {row}, column `time_s`: step {} s differs from the median step {} s by more than {} %; \
         sampling must be uniform (dropped or repeated samples?)",
        path.display(), format_number(*step), format_number(*expected), format_number(tolerance * 100.0)
    )]
    TimeNotUniform {
        /// The file.
        path: PathBuf,
        /// Data row (counted from 1) at the end of the offending step.
        row: usize,
        /// The step that ends at this row.
        step: f64,
        /// The median step.
        expected: f64,
        /// The relative tolerance, [`crate::UNIFORM_TIME_TOLERANCE`].
        tolerance: f64,
    },
    /// Channels of one record, or columns of one table, differ in length.
    #[error("{}: column `{column}` has {len} values but `{reference}` has {expected}; all columns must be equally long", path.display())]
    LengthMismatch {
        /// The file being written or checked.
        path: PathBuf,
        /// The column of the wrong length.
        column: String,
        /// Its length.
        len: usize,
        /// The reference column.
        reference: String,
        /// The reference length.
        expected: usize,
    },
    #[error("{}: {source}", path.display())]
    /// The columns read do not make a table (an empty column name, ...).
    Table {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        source: hxai_table::TableError,
    },
    /// The table cannot be used as asked (empty cells under `--missing`, ...); the message
    /// names the column and what to do.
    #[error("{}: {message}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong and what to do.
        message: String,
    },
    /// A table was given a different number of names and columns.
    #[error("{}: {names} column names but {columns} columns", path.display())]
    NamesMismatch {
        /// The file being written.
        path: PathBuf,
        /// Number of names.
        names: usize,
        /// Number of columns.
        columns: usize,
    },
    /// The data folder has no `manifest.csv`.
    #[error("{}: no `manifest.csv` in this folder; a data folder holds `manifest.csv` and one file per record", dir.display())]
    MissingManifest {
        /// The folder.
        dir: PathBuf,
    },
    /// The manifest names a record file that does not exist (or is a folder).
    #[error("{}: row {row}: record `{record}` points at `{file}`, which {} ({})", manifest.display(), if resolved.is_dir() { "is a folder, not a file" } else { "does not exist" }, resolved.display())]
    MissingRecordFile {
        /// The manifest.
        manifest: PathBuf,
        /// Data row, counted from 1.
        row: usize,
        /// The record id.
        record: String,
        /// The `file` cell as written.
        file: String,
        /// Where it was looked for.
        resolved: PathBuf,
    },
    /// Two manifest rows use the same record id.
    #[error("{}: row {row}: record id `{record}` is already used on row {first_row}; record ids must be unique", manifest.display())]
    DuplicateRecord {
        /// The manifest.
        manifest: PathBuf,
        /// The first row with the id.
        first_row: usize,
        /// The row repeating it.
        row: usize,
        /// The id.
        record: String,
    },
    /// A path that must be a file is a folder.
    #[error("{}: is a folder, not a file", path.display())]
    IsADirectory {
        /// The path.
        path: PathBuf,
    },
    /// An output path names a device, a pipe or a socket: writing a file and renaming it
    /// into place would replace the node itself (as root, `/dev/null` or `/dev/full`).
    #[error(
        "{}: is not a regular file (a device, pipe or socket); hxai writes its outputs as files and renames them into place, which would replace it: choose a file path",
        path.display()
    )]
    NotARegularFile {
        /// The path.
        path: PathBuf,
    },
    /// A path that must be a folder is a file.
    #[error("{}: is a file, not a folder", path.display())]
    NotADirectory {
        /// The path.
        path: PathBuf,
    },
    /// An output path names one of the command's inputs; writing would destroy it.
    #[error(
        "{}: refusing to write over an input of this command ({}); choose another output path",
        output.display(), role
    )]
    OutputIsInput {
        /// The output as given.
        output: PathBuf,
        /// What the input is (`the record`, `the manifest of data`, ...).
        role: String,
    },
    /// A data row has more or fewer cells than the header has columns.
    #[error("{}: row {row} has {found} cells but the header has {expected} columns", path.display())]
    RaggedRow {
        /// The file.
        path: PathBuf,
        /// Data row, counted from 1.
        row: usize,
        /// Cells found on the row.
        found: usize,
        /// Columns in the header.
        expected: usize,
    },
    /// A table read with a units row (its first row under the header) has none that can be
    /// used.
    #[error("{}: the units row (the first row under the header): {reason}", path.display())]
    UnitsRow {
        /// The file.
        path: PathBuf,
        /// What is wrong, naming the column where there is one.
        reason: String,
    },
    /// A column's stored type is not one this crate reads as numbers or text.
    #[error("{}: column `{column}` is stored as {dtype}, which hxai does not read; {hint}", path.display())]
    UnsupportedType {
        /// The file.
        path: PathBuf,
        /// The column.
        column: String,
        /// The stored type, by name.
        dtype: String,
        /// What to do instead.
        hint: &'static str,
    },
    /// Two manifest rows point at the same record file.
    #[error(
        "{}: row {row}: record `{record}` uses the file `{file}`, which row {first_row} already uses; \
         every record needs its own file (a shared file puts the same data in train and test)",
        manifest.display()
    )]
    SharedRecordFile {
        /// The manifest.
        manifest: PathBuf,
        /// The first row naming the file.
        first_row: usize,
        /// The row naming it again.
        row: usize,
        /// Record id on `row`.
        record: String,
        /// The `file` cell on `row`.
        file: String,
    },
    /// A record id cannot be used as a file name when writing a folder.
    #[error(
        "record id `{record}` cannot be written as a file name; use letters, digits, `-`, `_` and `.` only (not `.` or `..`)"
    )]
    InvalidRecordId {
        /// The id.
        record: String,
    },
}

impl DataError {
    pub(crate) fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        if path.is_dir() && source.kind() != std::io::ErrorKind::PermissionDenied {
            return DataError::IsADirectory {
                path: path.to_path_buf(),
            };
        }
        DataError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}
