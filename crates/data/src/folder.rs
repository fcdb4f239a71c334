//! Data folders: `manifest.csv` plus one file per record.

use crate::cells::{finite_column, parse_number, require_column, require_rows, text_column};
use crate::raw::{self, OutColumn};
use crate::record::{Record, read_record, stage_record};
use crate::{DataError, Format};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};

/// File name of the manifest inside a data folder.
pub const MANIFEST_FILE: &str = "manifest.csv";

/// The manifest columns every folder must have.
pub const MANIFEST_COLUMNS: [&str; 4] = ["record", "file", "amplitude_um", "frequency_hz"];

/// One row of `manifest.csv`.
#[derive(Debug, Clone, PartialEq)]
pub struct ManifestEntry {
    /// Record id, unique within the folder.
    pub record: String,
    /// Path of the record file, relative to the folder.
    pub file: String,
    /// Commanded amplitude, um.
    pub amplitude_um: f64,
    /// Commanded frequency, Hz (positive).
    pub frequency_hz: f64,
    /// Repeat number of the condition, if the manifest has a `repeat` column.
    pub repeat: Option<u32>,
    /// Any other manifest columns, kept as text (and written back by [`write_folder`]).
    pub extra: BTreeMap<String, String>,
}

/// A data folder: where it is and what its manifest lists.
#[derive(Debug, Clone, PartialEq)]
pub struct DataFolder {
    /// The folder.
    pub root: PathBuf,
    /// Manifest rows, in file order.
    pub entries: Vec<ManifestEntry>,
}

impl DataFolder {
    /// Full path of an entry's record file.
    pub fn path_of(&self, entry: &ManifestEntry) -> PathBuf {
        self.root.join(&entry.file)
    }

    /// Reads the record of a manifest entry.
    pub fn read_record(&self, entry: &ManifestEntry) -> Result<Record, DataError> {
        read_record(&self.path_of(entry))
    }

    /// Every file the folder is made of, `manifest.csv` first, each with its role for an
    /// error message; pass them to [`crate::check_output`] before writing anything.
    pub fn input_files(&self) -> Vec<(PathBuf, String)> {
        let mut out = vec![(
            self.root.join(MANIFEST_FILE),
            format!("the manifest of {}", self.root.display()),
        )];
        out.extend(self.entries.iter().map(|e| {
            (
                self.path_of(e),
                format!("record `{}` of {}", e.record, self.root.display()),
            )
        }));
        out
    }

    /// The entry with the given record id.
    pub fn get(&self, record: &str) -> Option<&ManifestEntry> {
        self.entries.iter().find(|e| e.record == record)
    }
}

/// Reads `dir/manifest.csv` and checks it: required columns, numbers where numbers
/// belong, positive frequencies, unique record ids, that every record file exists and
/// that no two rows name the same file (in any spelling).
/// Record files themselves are read lazily by [`DataFolder::read_record`].
pub fn read_folder(dir: &Path) -> Result<DataFolder, DataError> {
    let manifest = dir.join(MANIFEST_FILE);
    if !manifest.is_file() {
        if dir.is_file() {
            return Err(DataError::NotADirectory {
                path: dir.to_path_buf(),
            });
        }
        if !dir.is_dir() {
            return Err(DataError::Io {
                path: dir.to_path_buf(),
                source: std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    "the data folder does not exist",
                ),
            });
        }
        return Err(DataError::MissingManifest {
            dir: dir.to_path_buf(),
        });
    }
    let raw = raw::read(&manifest, Format::Csv)?;
    require_rows(&manifest, &raw)?;
    let idx: Vec<usize> = MANIFEST_COLUMNS
        .iter()
        .map(|c| require_column(&manifest, &raw, c))
        .collect::<Result<_, _>>()?;
    let records = text_column(&raw, idx[0]);
    let files = text_column(&raw, idx[1]);
    let amplitudes = finite_column(&manifest, &raw, idx[2])?;
    let frequencies = finite_column(&manifest, &raw, idx[3])?;
    let repeats = raw.find("repeat").map(|i| text_column(&raw, i));
    let extra_cols: Vec<(String, Vec<String>)> = raw
        .names
        .iter()
        .enumerate()
        .filter(|(_, n)| !MANIFEST_COLUMNS.contains(&n.as_str()) && n.as_str() != "repeat")
        .map(|(i, n)| (n.clone(), text_column(&raw, i)))
        .collect();

    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut seen_files: HashMap<PathBuf, usize> = HashMap::new();
    let mut entries = Vec::with_capacity(records.len());
    // A cell of a required text column, trimmed; empty is a missing value.
    let required = |cell: &str, row: usize, column: &str| -> Result<String, DataError> {
        let text = cell.trim();
        if text.is_empty() {
            return Err(DataError::MissingValue {
                path: manifest.clone(),
                row,
                column: column.into(),
            });
        }
        Ok(text.to_owned())
    };
    for i in 0..records.len() {
        let row = i + 1;
        let record = required(&records[i], row, "record")?;
        if let Some(&first_row) = seen.get(&record) {
            return Err(DataError::DuplicateRecord {
                manifest: manifest.clone(),
                first_row,
                row,
                record,
            });
        }
        seen.insert(record.clone(), row);
        let file = required(&files[i], row, "file")?;
        if frequencies[i] <= 0.0 {
            return Err(DataError::InvalidValue {
                path: manifest.clone(),
                row,
                column: "frequency_hz".into(),
                value: frequencies[i].to_string(),
                expected: "the commanded frequency must be positive (Hz)",
            });
        }
        let repeat = match &repeats {
            None => None,
            Some(col) => parse_repeat(&manifest, row, &col[i])?,
        };
        let resolved = dir.join(&file);
        if !resolved.is_file() {
            return Err(DataError::MissingRecordFile {
                manifest: manifest.clone(),
                row,
                record,
                file,
                resolved,
            });
        }
        let key = resolved.canonicalize().unwrap_or_else(|_| resolved.clone());
        if let Some(&first_row) = seen_files.get(&key) {
            return Err(DataError::SharedRecordFile {
                manifest: manifest.clone(),
                first_row,
                row,
                record,
                file,
            });
        }
        seen_files.insert(key, row);
        let extra = extra_cols
            .iter()
            .map(|(n, c)| (n.clone(), c[i].clone()))
            .collect();
        entries.push(ManifestEntry {
            record,
            file,
            amplitude_um: amplitudes[i],
            frequency_hz: frequencies[i],
            repeat,
            extra,
        });
    }
    Ok(DataFolder {
        root: dir.to_path_buf(),
        entries,
    })
}

fn parse_repeat(manifest: &Path, row: usize, cell: &str) -> Result<Option<u32>, DataError> {
    let s = cell.trim();
    if s.is_empty() {
        return Ok(None);
    }
    if let Ok(v) = s.parse::<u32>() {
        return Ok(Some(v));
    }
    // Accept integral floats such as `3.0` (what some tools write for integer columns).
    match parse_number(s) {
        Some(v) if v >= 0.0 && v.fract() == 0.0 && v <= f64::from(u32::MAX) => Ok(Some(v as u32)),
        _ => Err(DataError::InvalidValue {
            path: manifest.to_path_buf(),
            row,
            column: "repeat".into(),
            value: s.to_owned(),
            expected: "a non-negative whole number, or empty",
        }),
    }
}

fn check_record_id(id: &str) -> Result<(), DataError> {
    let ok = !id.is_empty()
        && id != "."
        && id != ".."
        && id
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'));
    if ok {
        Ok(())
    } else {
        Err(DataError::InvalidRecordId {
            record: id.to_owned(),
        })
    }
}

/// Writes a data folder: each record as `<record id>.csv` or `<record id>.parquet` and
/// `manifest.csv` listing them. The `file` field of the given entries is ignored and set
/// to the name written; the returned folder holds the entries as written.
///
/// Creates `dir` if needed. Every record is validated, and every target path checked not to
/// be a folder, before anything is written; record ids must be unique and usable as file
/// names (letters, digits, `-`, `_`, `.`).
pub fn write_folder(
    dir: &Path,
    items: &[(ManifestEntry, Record)],
    format: Format,
) -> Result<DataFolder, DataError> {
    let mut seen: HashMap<&str, usize> = HashMap::new();
    let mut entries = Vec::with_capacity(items.len());
    for (i, (entry, rec)) in items.iter().enumerate() {
        check_record_id(&entry.record)?;
        if let Some(&first) = seen.get(entry.record.as_str()) {
            return Err(DataError::DuplicateRecord {
                manifest: dir.join(MANIFEST_FILE),
                first_row: first,
                row: i + 1,
                record: entry.record.clone(),
            });
        }
        seen.insert(&entry.record, i + 1);
        let file = format!("{}.{}", entry.record, format.extension());
        rec.check(&dir.join(&file))?;
        // every target is checked before the first is written: a record whose file name
        // is taken by a folder would otherwise fail halfway, old and new records mixed
        if dir.join(&file).is_dir() {
            return Err(DataError::IsADirectory {
                path: dir.join(&file),
            });
        }
        let mut e = entry.clone();
        e.file = file;
        entries.push(e);
    }
    if dir.join(MANIFEST_FILE).is_dir() {
        return Err(DataError::IsADirectory {
            path: dir.join(MANIFEST_FILE),
        });
    }
    std::fs::create_dir_all(dir).map_err(|e| DataError::io(dir, e))?;
    // All or nothing: every record and the manifest are written in full beside their targets
    // first, and renamed only when all were written; a failure (a full disk) or a signal
    // before then leaves the folder as it was.
    let mut staged = Vec::with_capacity(entries.len() + 1);
    for (entry, (_, rec)) in entries.iter().zip(items) {
        staged.push(stage_record(&dir.join(&entry.file), rec)?);
    }
    staged.push(stage_manifest(&dir.join(MANIFEST_FILE), &entries)?);
    for file in staged {
        file.commit()?;
    }
    Ok(DataFolder {
        root: dir.to_path_buf(),
        entries,
    })
}

/// Writes `manifest.csv` for the given entries (as given: files are not checked).
pub fn write_manifest(path: &Path, entries: &[ManifestEntry]) -> Result<(), DataError> {
    stage_manifest(path, entries)?.commit()
}

/// [`write_manifest`] staged, not committed (see [`crate::stage`]).
fn stage_manifest(path: &Path, entries: &[ManifestEntry]) -> Result<crate::AtomicFile, DataError> {
    let manifest_err = |column: &str, i: usize, v: f64| DataError::NonFinite {
        path: path.to_path_buf(),
        row: i + 1,
        column: column.to_owned(),
        value: v,
    };
    let records: Vec<String> = entries.iter().map(|e| e.record.clone()).collect();
    let files: Vec<String> = entries.iter().map(|e| e.file.clone()).collect();
    let amps: Vec<f64> = entries.iter().map(|e| e.amplitude_um).collect();
    let freqs: Vec<f64> = entries.iter().map(|e| e.frequency_hz).collect();
    for (i, (&a, &f)) in amps.iter().zip(&freqs).enumerate() {
        if !a.is_finite() {
            return Err(manifest_err("amplitude_um", i, a));
        }
        if !f.is_finite() {
            return Err(manifest_err("frequency_hz", i, f));
        }
    }
    let mut names: Vec<String> = MANIFEST_COLUMNS.iter().map(|s| (*s).to_owned()).collect();
    let has_repeat = entries.iter().any(|e| e.repeat.is_some());
    let repeats: Vec<String> = entries
        .iter()
        .map(|e| e.repeat.map(|r| r.to_string()).unwrap_or_default())
        .collect();
    // Extra keys that collide with a standard column are not written (they could not be read back).
    let extra_names: BTreeSet<&String> = entries
        .iter()
        .flat_map(|e| e.extra.keys())
        .filter(|k| !MANIFEST_COLUMNS.contains(&k.as_str()) && k.as_str() != "repeat")
        .collect();
    let extras: Vec<Vec<String>> = extra_names
        .iter()
        .map(|k| {
            entries
                .iter()
                .map(|e| e.extra.get(*k).cloned().unwrap_or_default())
                .collect()
        })
        .collect();
    let mut cols = vec![
        OutColumn::Text(&records),
        OutColumn::Text(&files),
        OutColumn::Num(&amps),
        OutColumn::Num(&freqs),
    ];
    if has_repeat {
        names.push("repeat".into());
        cols.push(OutColumn::Text(&repeats));
    }
    for (k, v) in extra_names.iter().zip(&extras) {
        names.push((*k).clone());
        cols.push(OutColumn::Text(v));
    }
    raw::stage(path, Format::Csv, &names, &cols)
}
