//! Every check of the data crate, one test per error: the error variant, and that the
//! message names the file, row and column where the brief asks for them.

use hxai_data::{
    DataError, Format, ManifestEntry, Record, Table, TableError, read_folder, read_record,
    read_table, write_folder, write_record,
};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

type TestResult = Result<(), Box<dyn std::error::Error>>;

fn scratch(name: &str) -> Result<PathBuf, std::io::Error> {
    let dir = std::env::temp_dir().join(format!("hxai-data-err-{}-{name}", std::process::id()));
    if dir.exists() {
        std::fs::remove_dir_all(&dir)?;
    }
    std::fs::create_dir_all(&dir)?;
    Ok(dir)
}

fn write_text(path: &Path, text: &str) -> TestResult {
    std::fs::write(path, text)?;
    Ok(())
}

/// Writes `text` to the file `name` in `dir` and returns the error that reading it as a
/// record gives (an error itself when the read succeeds).
fn record_error(
    dir: &Path,
    name: &str,
    text: &str,
) -> Result<DataError, Box<dyn std::error::Error>> {
    let p = dir.join(name);
    write_text(&p, text)?;
    Ok(read_record(&p).err().ok_or("expected an error")?)
}

/// Writes `text` as the manifest of `dir` and returns the error that reading the folder
/// gives (an error itself when the read succeeds).
fn manifest_error(dir: &Path, text: &str) -> Result<DataError, Box<dyn std::error::Error>> {
    write_text(&dir.join("manifest.csv"), text)?;
    Ok(read_folder(dir).err().ok_or("expected an error")?)
}

fn good_record(n: usize) -> Record {
    let time_s: Vec<f64> = (0..n).map(|i| i as f64 / 1000.0).collect();
    let accel_ms2 = time_s.iter().map(|t| (60.0 * t).sin()).collect();
    let probe = time_s.iter().map(|t| 5.0 * (60.0 * t).sin()).collect();
    Record {
        time_s,
        accel_ms2,
        probe_um: Some(probe),
        command_um: None,
        encoder_um: None,
    }
}

fn entry(id: &str, file: &str) -> ManifestEntry {
    ManifestEntry {
        record: id.into(),
        file: file.into(),
        amplitude_um: 5.0,
        frequency_hz: 10.0,
        repeat: None,
        extra: BTreeMap::new(),
    }
}

#[test]
fn missing_column_names_file_and_column() -> TestResult {
    let dir = scratch("missing-col")?;
    let err = record_error(&dir, "r.csv", "time_s,probe_um\n0,1\n0.001,2\n")?;
    assert!(
        matches!(&err, DataError::MissingColumn { column, .. } if column == "accel_ms2"),
        "{err:?}"
    );
    let msg = err.to_string();
    assert!(msg.contains("r.csv") && msg.contains("accel_ms2"), "{msg}");
    Ok(())
}

#[test]
fn nan_and_inf_name_row_and_column() -> TestResult {
    let dir = scratch("nonfinite")?;
    let err = record_error(&dir, "r.csv", "time_s,accel_ms2\n0,1\n0.001,NaN\n0.002,3\n")?;
    assert!(
        matches!(&err, DataError::NonFinite { row: 2, column, .. } if column == "accel_ms2"),
        "{err:?}"
    );
    assert!(err.to_string().contains("row 2"), "{err}");

    let err = record_error(
        &dir,
        "inf.csv",
        "time_s,accel_ms2,probe_um\n0,1,0\n0.001,2,0\n0.002,3,-inf\n",
    )?;
    assert!(
        matches!(&err, DataError::NonFinite { row: 3, column, value, .. }
            if column == "probe_um" && value.is_infinite()),
        "{err:?}"
    );
    Ok(())
}

#[test]
fn non_increasing_time_names_row() -> TestResult {
    let dir = scratch("nonincreasing")?;
    let err = record_error(
        &dir,
        "r.csv",
        "time_s,accel_ms2\n0,1\n0.001,1\n0.001,1\n0.003,1\n",
    )?;
    assert!(
        matches!(err, DataError::TimeNotIncreasing { row: 3, .. }),
        "{err:?}"
    );
    Ok(())
}

#[test]
fn non_uniform_time_names_row_and_tolerance() -> TestResult {
    let dir = scratch("nonuniform")?;
    // A dropped sample between rows 3 and 4: that step is twice the others.
    let err = record_error(
        &dir,
        "r.csv",
        "time_s,accel_ms2\n0,1\n0.001,1\n0.002,1\n0.004,1\n0.005,1\n0.006,1\n",
    )?;
    assert!(
        matches!(err, DataError::TimeNotUniform { row: 4, tolerance, .. } if tolerance == 0.01),
        "{err:?}"
    );
    assert!(err.to_string().contains("1 %"), "{err}");
    Ok(())
}

#[test]
fn uniform_within_tolerance_is_accepted() -> TestResult {
    // Time stamps rounded to 6 decimals at 3 kHz: steps are 0.000333 s or 0.000334 s,
    // within 0.2 % of the mean step, so the 1 % uniformity tolerance must accept them.
    let dir = scratch("uniform-ok")?;
    let p = dir.join("r.csv");
    let mut text = String::from("time_s,accel_ms2\n");
    for i in 0..300 {
        text.push_str(&format!("{:.6},0\n", i as f64 / 3000.0));
    }
    write_text(&p, &text)?;
    let rec = read_record(&p)?;
    // fs from the end points: 299 / 0.099667 s = 2999.99 Hz; tolerance 0.03 Hz (1e-5 relative),
    // three times the rounding effect of 3.3e-6.
    assert!((rec.fs_hz() - 3000.0).abs() < 0.03, "{}", rec.fs_hz());
    Ok(())
}

#[test]
fn mismatched_lengths_are_refused_before_writing() -> TestResult {
    let dir = scratch("lengths")?;
    let mut rec = good_record(10);
    rec.probe_um = Some(vec![0.0; 9]);
    let p = dir.join("r.csv");
    let err = write_record(&p, &rec).err().ok_or("expected an error")?;
    assert!(
        matches!(&err, DataError::LengthMismatch { column, len: 9, expected: 10, .. } if column == "probe_um"),
        "{err:?}"
    );
    assert!(!p.exists(), "nothing may be written for an invalid record");

    // A ragged numeric table cannot even be built (hxai-table's invariant), so
    // `write_table` can never be handed one.
    let err = Table::new(
        vec!["a".into(), "b".into()],
        vec![vec![1.0, 2.0], vec![1.0]],
    )
    .err()
    .ok_or("expected an error")?;
    assert!(matches!(err, TableError::RaggedColumns { .. }), "{err:?}");
    Ok(())
}

#[test]
fn ragged_csv_row_is_an_error() -> TestResult {
    let dir = scratch("ragged")?;
    let err = record_error(&dir, "r.csv", "time_s,accel_ms2\n0,1\n0.001\n0.002,3\n")?;
    // polars either refuses the line or leaves the cell empty; both must be an error.
    assert!(
        matches!(
            err,
            DataError::MissingValue { row: 2, .. }
                | DataError::Parse { .. }
                | DataError::RaggedRow {
                    row: 2,
                    found: 1,
                    expected: 2,
                    ..
                }
        ),
        "{err:?}"
    );
    Ok(())
}

#[test]
fn empty_file_and_header_only() -> TestResult {
    let dir = scratch("empty")?;
    for (name, text, header_only) in [
        ("empty.csv", "", false),
        ("header.csv", "time_s,accel_ms2\n", true),
    ] {
        let err = record_error(&dir, name, text)?;
        assert!(
            matches!(err, DataError::Empty { header_only: h, .. } if h == header_only),
            "{name}: {err:?}"
        );
    }
    let err = record_error(&dir, "one.csv", "time_s,accel_ms2\n0,1\n")?;
    assert!(
        matches!(err, DataError::TooShort { rows: 1, .. }),
        "{err:?}"
    );
    Ok(())
}

#[test]
fn unknown_extension() -> TestResult {
    let dir = scratch("ext")?;
    let err = record_error(&dir, "r.txt", "time_s,accel_ms2\n0,1\n0.001,1\n")?;
    assert!(matches!(err, DataError::UnknownExtension { .. }), "{err:?}");
    assert!(err.to_string().contains(".parquet"), "{err}");
    let err = write_record(&dir.join("x.xlsx"), &good_record(4))
        .err()
        .ok_or("expected an error")?;
    assert!(matches!(err, DataError::UnknownExtension { .. }), "{err:?}");
    assert_eq!(Format::from_path(Path::new("A.CSV"))?, Format::Csv);
    Ok(())
}

#[test]
fn non_numeric_cell_names_row_column_and_text() -> TestResult {
    let dir = scratch("nonnumeric")?;
    let err = record_error(&dir, "r.csv", "time_s,accel_ms2\n0,1\n0.001,1\n0.002,n/a\n")?;
    assert!(
        matches!(&err, DataError::NonNumeric { row: 3, column, value, .. }
            if column == "accel_ms2" && value == "n/a"),
        "{err:?}"
    );
    let msg = err.to_string();
    assert!(
        msg.contains("row 3") && msg.contains("accel_ms2") && msg.contains("n/a"),
        "{msg}"
    );
    let p = dir.join("t.csv");
    write_text(&p, "x,y\n1,2\nthree,4\n")?;
    let err = read_table(&p).err().ok_or("expected an error")?;
    assert!(
        matches!(&err, DataError::NonNumeric { row: 2, column, .. } if column == "x"),
        "{err:?}"
    );
    Ok(())
}

#[test]
fn manifest_pointing_at_missing_file() -> TestResult {
    let dir = scratch("missing-file")?;
    write_record(&dir.join("a.csv"), &good_record(10))?;
    let err = manifest_error(
        &dir,
        "record,file,amplitude_um,frequency_hz\na,a.csv,5,10\nb,b.csv,5,20\n",
    )?;
    assert!(
        matches!(&err, DataError::MissingRecordFile { row: 2, record, file, .. }
            if record == "b" && file == "b.csv"),
        "{err:?}"
    );
    assert!(err.to_string().contains("manifest.csv"), "{err}");
    Ok(())
}

#[test]
fn duplicate_record_id() -> TestResult {
    let dir = scratch("dup")?;
    write_record(&dir.join("a.csv"), &good_record(10))?;
    write_record(&dir.join("c.csv"), &good_record(10))?;
    let err = manifest_error(
        &dir,
        "record,file,amplitude_um,frequency_hz\na,a.csv,5,10\nc,c.csv,5,10\na,d.csv,6,10\n",
    )?;
    assert!(
        matches!(&err, DataError::DuplicateRecord { first_row: 1, row: 3, record, .. } if record == "a"),
        "{err:?}"
    );
    // Two rows naming one file (in any spelling) are refused too: they would share data
    // between train and test.
    let err = manifest_error(
        &dir,
        "record,file,amplitude_um,frequency_hz\na,a.csv,5,10\nc,./a.csv,5,10\n",
    )?;
    assert!(
        matches!(&err, DataError::SharedRecordFile { first_row: 1, row: 2, record, .. } if record == "c"),
        "{err:?}"
    );
    let items = vec![
        (entry("x", ""), good_record(5)),
        (entry("x", ""), good_record(5)),
    ];
    let err = write_folder(&dir.join("out"), &items, Format::Csv)
        .err()
        .ok_or("expected an error")?;
    assert!(matches!(err, DataError::DuplicateRecord { .. }), "{err:?}");
    Ok(())
}

#[test]
fn manifest_checks_numbers_and_folder() -> TestResult {
    let dir = scratch("manifest")?;
    let err = read_folder(&dir).err().ok_or("expected an error")?;
    assert!(matches!(err, DataError::MissingManifest { .. }), "{err:?}");
    write_record(&dir.join("a.csv"), &good_record(10))?;
    let err = manifest_error(
        &dir,
        "record,file,amplitude_um,frequency_hz\na,a.csv,5,-10\n",
    )?;
    assert!(
        matches!(&err, DataError::InvalidValue { row: 1, column, .. } if column == "frequency_hz"),
        "{err:?}"
    );
    let err = manifest_error(&dir, "record,file,amplitude_um\na,a.csv,5\n")?;
    assert!(
        matches!(&err, DataError::MissingColumn { column, .. } if column == "frequency_hz"),
        "{err:?}"
    );
    let err = manifest_error(
        &dir,
        "record,file,amplitude_um,frequency_hz,repeat\na,a.csv,5,10,-1\n",
    )?;
    assert!(
        matches!(&err, DataError::InvalidValue { column, .. } if column == "repeat"),
        "{err:?}"
    );
    let err = read_folder(&dir.join("nope"))
        .err()
        .ok_or("expected an error")?;
    assert!(matches!(err, DataError::Io { .. }), "{err:?}");
    Ok(())
}

#[test]
fn invalid_record_id_for_writing() -> TestResult {
    let dir = scratch("badid")?;
    let items = vec![(entry("../evil", ""), good_record(5))];
    let err = write_folder(&dir, &items, Format::Csv)
        .err()
        .ok_or("expected an error")?;
    assert!(matches!(err, DataError::InvalidRecordId { .. }), "{err:?}");
    Ok(())
}

#[test]
fn folder_reads_extra_columns_and_records() -> TestResult {
    let dir = scratch("folder-ok")?;
    write_record(&dir.join("a.parquet"), &good_record(10))?;
    write_text(
        &dir.join("manifest.csv"),
        "record,file,amplitude_um,frequency_hz,repeat,operator\na,a.parquet,5,10,2,kim\n",
    )?;
    let folder = read_folder(&dir)?;
    assert_eq!(folder.entries.len(), 1);
    let e = &folder.entries[0];
    assert_eq!(e.repeat, Some(2));
    assert_eq!(e.extra.get("operator").map(String::as_str), Some("kim"));
    assert_eq!(folder.read_record(e)?, good_record(10));
    Ok(())
}

#[test]
fn parquet_with_null_and_text_cells() -> TestResult {
    // A Parquet file with a text column that is not numeric: the record check names it.
    let dir = scratch("parquet-text")?;
    let p = dir.join("t.parquet");
    let t = hxai_data::MixedTable {
        names: vec!["time_s".into(), "accel_ms2".into()],
        columns: vec![
            hxai_data::Column::Number(vec![0.0, 0.001, 0.002]),
            hxai_data::Column::Text(vec!["1".into(), "x".into(), "2".into()]),
        ],
    };
    hxai_data::write_mixed_table(&p, &t)?;
    let err = read_record(&p).err().ok_or("expected an error")?;
    assert!(
        matches!(&err, DataError::NonNumeric { row: 2, column, .. } if column == "accel_ms2"),
        "{err:?}"
    );
    Ok(())
}
