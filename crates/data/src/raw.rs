//! The only module that talks to polars: files in, plain columns out (and back).
//!
//! Every cell is handed on either as a number (Parquet numeric columns) or as its text
//! (CSV, and Parquet text columns), so that the checks above this module can name the row
//! and column of a bad cell instead of relaying a reader's message.

use crate::cells::{RawColumn, RawTable};
use crate::codes;
use crate::{DataError, Format};
use polars::prelude::*;
use std::fs::File;
use std::path::Path;

/// A column to write.
#[derive(Debug)]
pub(crate) enum OutColumn<'a> {
    Num(&'a [f64]),
    Text(&'a [String]),
}

fn parse_err(path: &Path, e: PolarsError) -> DataError {
    DataError::Parse {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

fn write_err(path: &Path, e: PolarsError) -> DataError {
    DataError::Write {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Reads a CSV or Parquet file into raw columns.
pub(crate) fn read(path: &Path, format: Format) -> Result<RawTable, DataError> {
    let meta = std::fs::metadata(path).map_err(|e| DataError::io(path, e))?;
    if meta.is_dir() {
        return Err(DataError::IsADirectory {
            path: path.to_path_buf(),
        });
    }
    if meta.len() == 0 {
        return Err(DataError::Empty {
            path: path.to_path_buf(),
            header_only: false,
        });
    }
    // the CSV header as RFC 4180 reads it (polars leaves doubled quotes doubled)
    let mut header: Option<Vec<String>> = None;
    let mut skipped = 0usize;
    let df = match format {
        Format::Csv => {
            // The header and the row lengths are checked here, not by polars: polars
            // renames a repeated column (`y_duplicated_0`) and reports ragged rows in
            // its own terms.
            let text = std::fs::read(path).map_err(|e| DataError::io(path, e))?;
            let utf8 =
                std::str::from_utf8(&text).map_err(|e| crate::csvscan::not_utf8(path, &e))?;
            // Another separator (`;`, tab, found from the header or given), a decimal comma,
            // an old Mac's `\r` line ends, blank lines or Excel's trailing `,,,,` rows: the
            // text is rewritten as a plain CSV first (the common file is read as it is).
            let utf8 = utf8.strip_prefix('\u{feff}').unwrap_or(utf8);
            let normal = crate::csvscan::normalise(utf8, crate::csvscan::csv_dialect());
            skipped = normal.skipped;
            let options = CsvReadOptions::default()
                .with_has_header(true)
                // Read every cell as text: our own parser reports row and column of bad cells.
                .with_infer_schema_length(Some(0))
                .with_n_threads(Some(1));
            match normal.text {
                None => {
                    header = Some(crate::csvscan::check(path, &text)?);
                    options
                        .try_into_reader_with_file_path(Some(path.to_path_buf()))
                        .and_then(|r| r.finish())
                        .map_err(|e| parse_err(path, e))?
                }
                Some(clean) => {
                    header = Some(crate::csvscan::check(path, clean.as_bytes())?);
                    options
                        .into_reader_with_file_handle(std::io::Cursor::new(clean.into_bytes()))
                        .finish()
                        .map_err(|e| parse_err(path, e))?
                }
            }
        }
        Format::Parquet => {
            let file = File::open(path).map_err(|e| DataError::io(path, e))?;
            let mut reader = ParquetReader::new(file);
            // The reader's own messages describe its internals; what the user needs is this.
            let not_parquet = |_| DataError::Parse {
                path: path.to_path_buf(),
                message: "not a readable Parquet file (damaged, cut short, or another format \
                          named `.parquet`)"
                    .into(),
            };
            // Repeated names are looked for in the file's own schema: polars cannot build
            // its schema from them and would report an unreadable file.
            let fields: Vec<String> = reader
                .get_metadata()
                .map_err(not_parquet)?
                .schema()
                .fields()
                .iter()
                .map(|f| f.name().to_owned())
                .collect();
            for (i, name) in fields.iter().enumerate() {
                if fields[..i].contains(name) {
                    return Err(DataError::DuplicateColumn {
                        path: path.to_path_buf(),
                        column: name.clone(),
                    });
                }
            }
            let schema = reader.schema().map_err(not_parquet)?;
            for (name, field) in schema.iter() {
                check_parquet_type(path, name.as_str(), field.dtype())?;
            }
            reader.finish().map_err(not_parquet)?
        }
    };
    let mut names = Vec::with_capacity(df.width());
    let mut columns = Vec::with_capacity(df.width());
    let mut integer_type = Vec::with_capacity(df.width());
    for (i, col) in df.columns().iter().enumerate() {
        let name = match &header {
            Some(h) if h.len() == df.width() && !h[i].is_empty() => h[i].clone(),
            _ => col.name().to_string(),
        };
        if names.contains(&name) {
            return Err(DataError::DuplicateColumn {
                path: path.to_path_buf(),
                column: name,
            });
        }
        let dtype = col.dtype();
        let raw = if dtype.is_primitive_numeric() {
            let c = col
                .cast(&DataType::Float64)
                .map_err(|e| parse_err(path, e))?;
            let ca = c.f64().map_err(|e| parse_err(path, e))?;
            RawColumn::Num(ca.iter().collect())
        } else {
            let c = col
                .cast(&DataType::String)
                .map_err(|e| parse_err(path, e))?;
            let ca = c.str().map_err(|e| parse_err(path, e))?;
            RawColumn::Text(ca.iter().map(|s| s.map(str::to_owned)).collect())
        };
        integer_type.push(dtype.is_integer().then(|| dtype.to_string()));
        names.push(name);
        columns.push(raw);
    }
    let mut raw = RawTable {
        names,
        columns,
        integer_type,
        skipped,
    };
    codes::apply(path, &mut raw);
    Ok(raw)
}

/// Refuses, by name, a Parquet type that is neither a number nor text this crate reads.
/// Checked on the file's schema before polars decodes anything (some types, such as
/// float16, it cannot decode without features this workspace does not build).
fn check_parquet_type(path: &Path, column: &str, dtype: &ArrowDataType) -> Result<(), DataError> {
    use ArrowDataType as A;
    let refuse = |dtype: &str, hint: &'static str| {
        Err(DataError::UnsupportedType {
            path: path.to_path_buf(),
            column: column.to_owned(),
            dtype: dtype.to_owned(),
            hint,
        })
    };
    const NUMBERS: &str = "store numbers as float64 (or float32, int32, int64)";
    const WIDE: &str = "store it as int32, int64 or float64";
    const TIME: &str = "store time as float64 seconds (for timestamps: (t - t0) in seconds)";
    match dtype {
        A::Null
        | A::Boolean
        | A::Int32
        | A::Int64
        | A::UInt32
        | A::UInt64
        | A::Float32
        | A::Float64
        | A::Utf8
        | A::LargeUtf8
        | A::Utf8View => Ok(()),
        A::Dictionary(_, value, _) if matches!(**value, A::Utf8 | A::LargeUtf8 | A::Utf8View) => {
            Ok(())
        }
        A::Float16 => refuse("float16", NUMBERS),
        // polars decodes these only with features this workspace does not build.
        A::Int8 => refuse("int8", WIDE),
        A::Int16 => refuse("int16", WIDE),
        A::UInt8 => refuse("uint8", WIDE),
        A::UInt16 => refuse("uint16", WIDE),
        A::Int128 | A::UInt128 => refuse("a 128-bit integer", NUMBERS),
        A::Decimal(p, s) => refuse(&format!("decimal({p}, {s})"), NUMBERS),
        A::Decimal32(p, s) => refuse(&format!("decimal({p}, {s})"), NUMBERS),
        A::Decimal64(p, s) => refuse(&format!("decimal({p}, {s})"), NUMBERS),
        A::Decimal256(p, s) => refuse(&format!("decimal256({p}, {s})"), NUMBERS),
        A::Timestamp(unit, _) => refuse(&format!("a timestamp ({unit:?})"), TIME),
        A::Date32 | A::Date64 => refuse("a date", TIME),
        A::Time32(unit) | A::Time64(unit) => refuse(&format!("a time of day ({unit:?})"), TIME),
        A::Duration(unit) => refuse(&format!("a duration ({unit:?})"), TIME),
        A::Interval(_) => refuse("an interval", TIME),
        A::Binary | A::LargeBinary | A::FixedSizeBinary(_) | A::BinaryView => {
            refuse("binary data", NUMBERS)
        }
        A::List(_) | A::LargeList(_) | A::FixedSizeList(..) => {
            refuse("a list", "store one number per cell")
        }
        A::Struct(_) | A::Map(..) | A::Union(_) => {
            refuse("a nested type", "store one number per cell")
        }
        other => refuse(&format!("{other:?}"), NUMBERS),
    }
}

/// Writes columns (all of equal length, checked by the caller) as CSV or Parquet into a
/// staged file, not committed (see [`crate::stage`]).
pub(crate) fn stage(
    path: &Path,
    format: Format,
    names: &[String],
    columns: &[OutColumn<'_>],
) -> Result<crate::AtomicFile, DataError> {
    let height = columns.first().map_or(0, |c| match c {
        OutColumn::Num(v) => v.len(),
        OutColumn::Text(v) => v.len(),
    });
    let cols: Vec<Column> = names
        .iter()
        .zip(columns)
        .map(|(n, c)| match c {
            OutColumn::Num(v) => Column::new(PlSmallStr::from(n.as_str()), *v),
            OutColumn::Text(v) => Column::new(PlSmallStr::from(n.as_str()), *v),
        })
        .collect();
    let mut df = DataFrame::new(height, cols).map_err(|e| write_err(path, e))?;
    crate::atomic::stage(path, |file| {
        match format {
            Format::Csv => CsvWriter::new(file)
                .include_header(true)
                .finish(&mut df)
                .map_err(|e| write_err(path, e))?,
            Format::Parquet => {
                ParquetWriter::new(file)
                    .finish(&mut df)
                    .map_err(|e| write_err(path, e))?;
            }
        }
        Ok(())
    })
}
