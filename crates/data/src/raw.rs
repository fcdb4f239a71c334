//! The only module that talks to polars: files in, plain columns out (and back).
//!
//! Every cell is handed on either as a number (Parquet numeric columns) or as its text
//! (CSV, and Parquet text columns), so that the checks above this module can name the row
//! and column of a bad cell instead of relaying a reader's message.

use crate::{DataError, Format};
use polars::prelude::*;
use std::fs::File;
use std::path::Path;

/// One column as read from a file.
#[derive(Debug, Clone)]
pub(crate) enum RawColumn {
    /// Numeric cells (Parquet numeric types); `None` is a null.
    Num(Vec<Option<f64>>),
    /// Cells as text (CSV, or Parquet text columns); `None` is an empty cell / null.
    Text(Vec<Option<String>>),
}

impl RawColumn {
    fn len(&self) -> usize {
        match self {
            RawColumn::Num(v) => v.len(),
            RawColumn::Text(v) => v.len(),
        }
    }
}

/// A file's columns before any checking.
#[derive(Debug, Clone)]
pub(crate) struct RawTable {
    pub names: Vec<String>,
    pub columns: Vec<RawColumn>,
}

impl RawTable {
    pub fn height(&self) -> usize {
        self.columns.first().map_or(0, RawColumn::len)
    }

    pub fn find(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
}

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
    if meta.len() == 0 {
        return Err(DataError::Empty {
            path: path.to_path_buf(),
            header_only: false,
        });
    }
    let df = match format {
        Format::Csv => CsvReadOptions::default()
            .with_has_header(true)
            // Read every cell as text: our own parser reports row and column of bad cells.
            .with_infer_schema_length(Some(0))
            .with_n_threads(Some(1))
            .try_into_reader_with_file_path(Some(path.to_path_buf()))
            .and_then(|r| r.finish())
            .map_err(|e| parse_err(path, e))?,
        Format::Parquet => {
            let file = File::open(path).map_err(|e| DataError::io(path, e))?;
            ParquetReader::new(file)
                .finish()
                .map_err(|e| parse_err(path, e))?
        }
    };
    let mut names = Vec::with_capacity(df.width());
    let mut columns = Vec::with_capacity(df.width());
    for col in df.columns() {
        let name = col.name().to_string();
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
        names.push(name);
        columns.push(raw);
    }
    Ok(RawTable { names, columns })
}

/// Writes columns (all of equal length, checked by the caller) as CSV or Parquet.
pub(crate) fn write(
    path: &Path,
    format: Format,
    names: &[String],
    columns: &[OutColumn<'_>],
) -> Result<(), DataError> {
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
    if let Some(parent) = path.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent).map_err(|e| DataError::io(parent, e))?;
    }
    let mut file = File::create(path).map_err(|e| DataError::io(path, e))?;
    match format {
        Format::Csv => CsvWriter::new(&mut file)
            .include_header(true)
            .finish(&mut df)
            .map_err(|e| write_err(path, e))?,
        Format::Parquet => {
            ParquetWriter::new(&mut file)
                .finish(&mut df)
                .map_err(|e| write_err(path, e))?;
        }
    }
    Ok(())
}
