//! Every check of the data crate: the error variant, and that the message names the file,
//! row and column where the brief asks for them. The bad records and manifests are one
//! table of cases (`BAD_INPUTS`); the other errors have a test each.

use hxai_data::{
    DataError, Format, ManifestEntry, Record, Table, TableError, read_folder, read_record,
    read_table, read_table_with_units, write_folder, write_record,
};
use std::collections::BTreeMap;
use std::path::Path;

type TestResult = Result<(), Box<dyn std::error::Error>>;

/// A new empty folder, removed with what is in it when the guard is dropped.
fn scratch(name: &str) -> Result<tempfile::TempDir, std::io::Error> {
    tempfile::Builder::new()
        .prefix(&format!("hxai-data-err-{name}-"))
        .tempdir()
}

fn write_text(path: &Path, text: &str) -> TestResult {
    std::fs::write(path, text)?;
    Ok(())
}

/// The error of `result` (an error itself when `result` succeeded).
fn error_of<T, E>(result: Result<T, E>) -> Result<E, &'static str> {
    result.err().ok_or("expected an error")
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
    Ok(error_of(read_record(&p))?)
}

/// Writes `text` as the manifest of `dir` and returns the error that reading the folder
/// gives (an error itself when the read succeeds).
fn manifest_error(dir: &Path, text: &str) -> Result<DataError, Box<dyn std::error::Error>> {
    write_text(&dir.join("manifest.csv"), text)?;
    Ok(error_of(read_folder(dir))?)
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

/// Where a bad input's text goes.
enum Input {
    /// A record file of this name.
    Record(&'static str),
    /// The manifest of a folder holding a good record under each of these file names.
    Manifest(&'static [&'static str]),
}

/// One bad input: what it is (the failure message names it), where its text goes, the
/// error it must give, and words the error's message must contain.
struct Case {
    what: &'static str,
    input: Input,
    text: &'static str,
    expect: fn(&DataError) -> bool,
    message: &'static [&'static str],
}

/// Every bad record and manifest, each read in a fresh folder.
const BAD_INPUTS: &[Case] = &[
    Case {
        what: "missing column: names file and column",
        input: Input::Record("r.csv"),
        text: "time_s,probe_um\n0,1\n0.001,2\n",
        expect: |e| matches!(e, DataError::MissingColumn { column, .. } if column == "accel_ms2"),
        message: &["r.csv", "accel_ms2"],
    },
    Case {
        what: "NaN: names row and column",
        input: Input::Record("r.csv"),
        text: "time_s,accel_ms2\n0,1\n0.001,NaN\n0.002,3\n",
        expect: |e| matches!(e, DataError::NonFinite { row: 2, column, .. } if column == "accel_ms2"),
        message: &["row 2"],
    },
    Case {
        what: "-inf: names row and column",
        input: Input::Record("inf.csv"),
        text: "time_s,accel_ms2,probe_um\n0,1,0\n0.001,2,0\n0.002,3,-inf\n",
        expect: |e| {
            matches!(e, DataError::NonFinite { row: 3, column, value, .. }
                if column == "probe_um" && value.is_infinite())
        },
        message: &[],
    },
    Case {
        what: "time not increasing: names the row",
        input: Input::Record("r.csv"),
        text: "time_s,accel_ms2\n0,1\n0.001,1\n0.001,1\n0.003,1\n",
        expect: |e| matches!(e, DataError::TimeNotIncreasing { row: 3, .. }),
        message: &[],
    },
    Case {
        // A dropped sample between rows 3 and 4: that step is twice the others.
        what: "time not uniform: names the row and the tolerance",
        input: Input::Record("r.csv"),
        text: "time_s,accel_ms2\n0,1\n0.001,1\n0.002,1\n0.004,1\n0.005,1\n0.006,1\n",
        expect: |e| matches!(e, DataError::TimeNotUniform { row: 4, tolerance, .. } if *tolerance == 0.01),
        message: &["1 %"],
    },
    Case {
        // polars either refuses the line or leaves the cell empty; both must be an error.
        what: "ragged row",
        input: Input::Record("r.csv"),
        text: "time_s,accel_ms2\n0,1\n0.001\n0.002,3\n",
        expect: |e| {
            matches!(
                e,
                DataError::MissingValue { row: 2, .. }
                    | DataError::Parse { .. }
                    | DataError::RaggedRow {
                        row: 2,
                        found: 1,
                        expected: 2,
                        ..
                    }
            )
        },
        message: &[],
    },
    Case {
        what: "empty file",
        input: Input::Record("empty.csv"),
        text: "",
        expect: |e| {
            matches!(
                e,
                DataError::Empty {
                    header_only: false,
                    ..
                }
            )
        },
        message: &[],
    },
    Case {
        what: "header only",
        input: Input::Record("header.csv"),
        text: "time_s,accel_ms2\n",
        expect: |e| {
            matches!(
                e,
                DataError::Empty {
                    header_only: true,
                    ..
                }
            )
        },
        message: &[],
    },
    Case {
        what: "one row",
        input: Input::Record("one.csv"),
        text: "time_s,accel_ms2\n0,1\n",
        expect: |e| matches!(e, DataError::TooShort { rows: 1, .. }),
        message: &[],
    },
    Case {
        what: "unknown extension: names the known ones",
        input: Input::Record("r.txt"),
        text: "time_s,accel_ms2\n0,1\n0.001,1\n",
        expect: |e| matches!(e, DataError::UnknownExtension { .. }),
        message: &[".parquet"],
    },
    Case {
        what: "non-numeric cell: names row, column and text",
        input: Input::Record("r.csv"),
        text: "time_s,accel_ms2\n0,1\n0.001,1\n0.002,n/a\n",
        expect: |e| {
            matches!(e, DataError::NonNumeric { row: 3, column, value, .. }
                if column == "accel_ms2" && value == "n/a")
        },
        message: &["row 3", "accel_ms2", "n/a"],
    },
    Case {
        what: "manifest pointing at a missing file",
        input: Input::Manifest(&["a.csv"]),
        text: "record,file,amplitude_um,frequency_hz\na,a.csv,5,10\nb,b.csv,5,20\n",
        expect: |e| {
            matches!(e, DataError::MissingRecordFile { row: 2, record, file, .. }
                if record == "b" && file == "b.csv")
        },
        message: &["manifest.csv"],
    },
    Case {
        what: "duplicate record id",
        input: Input::Manifest(&["a.csv", "c.csv"]),
        text: "record,file,amplitude_um,frequency_hz\na,a.csv,5,10\nc,c.csv,5,10\na,d.csv,6,10\n",
        expect: |e| matches!(e, DataError::DuplicateRecord { first_row: 1, row: 3, record, .. } if record == "a"),
        message: &[],
    },
    Case {
        // Two rows naming one file (in any spelling) would share data between train and test.
        what: "two rows naming one file",
        input: Input::Manifest(&["a.csv", "c.csv"]),
        text: "record,file,amplitude_um,frequency_hz\na,a.csv,5,10\nc,./a.csv,5,10\n",
        expect: |e| matches!(e, DataError::SharedRecordFile { first_row: 1, row: 2, record, .. } if record == "c"),
        message: &[],
    },
    Case {
        what: "negative frequency",
        input: Input::Manifest(&["a.csv"]),
        text: "record,file,amplitude_um,frequency_hz\na,a.csv,5,-10\n",
        expect: |e| matches!(e, DataError::InvalidValue { row: 1, column, .. } if column == "frequency_hz"),
        message: &[],
    },
    Case {
        what: "manifest without frequency",
        input: Input::Manifest(&["a.csv"]),
        text: "record,file,amplitude_um\na,a.csv,5\n",
        expect: |e| matches!(e, DataError::MissingColumn { column, .. } if column == "frequency_hz"),
        message: &[],
    },
    Case {
        what: "negative repeat",
        input: Input::Manifest(&["a.csv"]),
        text: "record,file,amplitude_um,frequency_hz,repeat\na,a.csv,5,10,-1\n",
        expect: |e| matches!(e, DataError::InvalidValue { column, .. } if column == "repeat"),
        message: &[],
    },
];

#[test]
fn every_bad_input_gives_its_error_naming_what_is_wrong() -> TestResult {
    for (i, case) in BAD_INPUTS.iter().enumerate() {
        let scratch_dir = scratch(&format!("case-{i}"))?;
        let dir = scratch_dir.path();
        let err = match case.input {
            Input::Record(file) => record_error(dir, file, case.text),
            Input::Manifest(records) => {
                for file in records {
                    write_record(&dir.join(file), &good_record(10))?;
                }
                manifest_error(dir, case.text)
            }
        }
        .map_err(|e| format!("{}: {e}", case.what))?;
        assert!((case.expect)(&err), "{}: {err:?}", case.what);
        let msg = err.to_string();
        for part in case.message {
            assert!(
                msg.contains(part),
                "{}: {part:?} missing in {msg}",
                case.what
            );
        }
    }
    Ok(())
}

#[test]
fn uniform_within_tolerance_is_accepted() -> TestResult {
    // Time stamps rounded to 6 decimals at 3 kHz: steps are 0.000333 s or 0.000334 s,
    // within 0.2 % of the mean step, so the 1 % uniformity tolerance must accept them.
    let scratch_dir = scratch("uniform-ok")?;
    let dir = scratch_dir.path();
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
    let scratch_dir = scratch("lengths")?;
    let dir = scratch_dir.path();
    let mut rec = good_record(10);
    rec.probe_um = Some(vec![0.0; 9]);
    let p = dir.join("r.csv");
    let err = error_of(write_record(&p, &rec))?;
    assert!(
        matches!(&err, DataError::LengthMismatch { column, len: 9, expected: 10, .. } if column == "probe_um"),
        "{err:?}"
    );
    assert!(!p.exists(), "nothing may be written for an invalid record");

    // A ragged numeric table cannot even be built (hxai-table's invariant), so
    // `write_table` can never be handed one.
    let err = error_of(Table::new(
        vec!["a".into(), "b".into()],
        vec![vec![1.0, 2.0], vec![1.0]],
    ))?;
    assert!(matches!(err, TableError::RaggedColumns { .. }), "{err:?}");
    Ok(())
}

#[test]
fn unknown_extension() -> TestResult {
    // Reading a `.txt` record: in `BAD_INPUTS`.
    let scratch_dir = scratch("ext")?;
    let dir = scratch_dir.path();
    let err = error_of(write_record(&dir.join("x.xlsx"), &good_record(4)))?;
    assert!(matches!(err, DataError::UnknownExtension { .. }), "{err:?}");
    assert_eq!(Format::from_path(Path::new("A.CSV"))?, Format::Csv);
    Ok(())
}

#[test]
fn non_numeric_table_cell_names_row_and_column() -> TestResult {
    // A non-numeric cell in a record: in `BAD_INPUTS`.
    let scratch_dir = scratch("nonnumeric")?;
    let dir = scratch_dir.path();
    let p = dir.join("t.csv");
    write_text(&p, "x,y\n1,2\nthree,4\n")?;
    let err = error_of(read_table(&p))?;
    assert!(
        matches!(&err, DataError::NonNumeric { row: 2, column, .. } if column == "x"),
        "{err:?}"
    );
    Ok(())
}

/// A units row: read as the units, the numbers below it as the table (rows counted from the
/// first row of numbers); refused by name when a unit is missing, when the row holds numbers
/// (no units row), when nothing follows it, and for Parquet.
#[test]
fn a_units_row_is_read_or_refused_by_name() -> TestResult {
    let scratch_dir = scratch("units")?;
    let dir = scratch_dir.path();
    let p = dir.join("t.csv");
    write_text(&p, "F,m,a\nN, kg ,m/s^2\n2,1,2\n6,2,3\n")?;
    let (t, units) = read_table_with_units(&p)?;
    assert_eq!(units, ["N", "kg", "m/s^2"]);
    assert_eq!(t.n_rows(), 2);
    assert_eq!(t.column("a"), Some(&[2.0, 3.0][..]));
    write_text(&p, "F,m,a\nN,,m/s^2\n2,1,2\n")?;
    let err = error_of(read_table_with_units(&p))?;
    assert!(err.to_string().contains("column `m` has no unit"), "{err}");
    write_text(&p, "F,m\n1.5,2\n2,1\n")?;
    let err = error_of(read_table_with_units(&p))?;
    assert!(err.to_string().contains("no units row"), "{err}");
    write_text(&p, "F,m\nN,kg\n")?;
    let err = error_of(read_table_with_units(&p))?;
    assert!(matches!(err, DataError::Empty { .. }), "{err:?}");
    write_text(&p, "F,m\nN,kg\n1,x\n")?;
    let err = error_of(read_table_with_units(&p))?;
    assert!(
        matches!(&err, DataError::NonNumeric { row: 1, column, .. } if column == "m"),
        "{err:?}"
    );
    let err = error_of(read_table_with_units(&dir.join("t.parquet")))?;
    assert!(matches!(err, DataError::UnitsRow { .. }), "{err:?}");
    Ok(())
}

#[test]
fn writing_a_duplicate_record_id_is_refused() -> TestResult {
    // Reading a manifest with a duplicate id or file: in `BAD_INPUTS`; writing one:
    let scratch_dir = scratch("dup")?;
    let dir = scratch_dir.path();
    let items = vec![
        (entry("x", ""), good_record(5)),
        (entry("x", ""), good_record(5)),
    ];
    let err = error_of(write_folder(&dir.join("out"), &items, Format::Csv))?;
    assert!(matches!(err, DataError::DuplicateRecord { .. }), "{err:?}");
    Ok(())
}

/// A record whose file name is taken by a folder is refused before anything is written
/// (`simulate --force` into an old folder used to fail halfway, old and new records mixed):
/// the other records and the manifest stay as they were.
#[test]
fn a_target_taken_by_a_folder_is_refused_before_any_write() -> TestResult {
    let scratch_dir = scratch("taken")?;
    let dir = scratch_dir.path();
    write_text(&dir.join("a.csv"), "old")?;
    std::fs::create_dir_all(dir.join("b.csv"))?;
    let items = vec![
        (entry("a", ""), good_record(5)),
        (entry("b", ""), good_record(5)),
    ];
    let err = error_of(write_folder(dir, &items, Format::Csv))?;
    assert!(matches!(err, DataError::IsADirectory { .. }), "{err:?}");
    assert!(err.to_string().contains("b.csv"), "{err}");
    assert_eq!(std::fs::read_to_string(dir.join("a.csv"))?, "old");
    assert!(!dir.join("manifest.csv").exists());
    // and a manifest taken by a folder, the same
    let scratch_dir = scratch("taken-manifest")?;
    let dir = scratch_dir.path();
    std::fs::create_dir_all(dir.join("manifest.csv"))?;
    let err = error_of(write_folder(dir, &items[..1], Format::Csv))?;
    assert!(err.to_string().contains("manifest.csv"), "{err}");
    assert!(!dir.join("a.csv").exists());
    Ok(())
}

#[test]
fn missing_manifest_and_missing_folder() -> TestResult {
    let scratch_dir = scratch("manifest")?;
    let dir = scratch_dir.path();
    let err = error_of(read_folder(dir))?;
    assert!(matches!(err, DataError::MissingManifest { .. }), "{err:?}");
    // The manifest's numbers and columns: in `BAD_INPUTS`.
    let err = error_of(read_folder(&dir.join("nope")))?;
    assert!(matches!(err, DataError::Io { .. }), "{err:?}");
    Ok(())
}

#[test]
fn invalid_record_id_for_writing() -> TestResult {
    let scratch_dir = scratch("badid")?;
    let dir = scratch_dir.path();
    let items = vec![(entry("../evil", ""), good_record(5))];
    let err = error_of(write_folder(dir, &items, Format::Csv))?;
    assert!(matches!(err, DataError::InvalidRecordId { .. }), "{err:?}");
    Ok(())
}

#[test]
fn folder_reads_extra_columns_and_records() -> TestResult {
    let scratch_dir = scratch("folder-ok")?;
    let dir = scratch_dir.path();
    write_record(&dir.join("a.parquet"), &good_record(10))?;
    write_text(
        &dir.join("manifest.csv"),
        "record,file,amplitude_um,frequency_hz,repeat,operator\na,a.parquet,5,10,2,kim\n",
    )?;
    let folder = read_folder(dir)?;
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
    let scratch_dir = scratch("parquet-text")?;
    let dir = scratch_dir.path();
    let p = dir.join("t.parquet");
    let t = hxai_data::MixedTable {
        names: vec!["time_s".into(), "accel_ms2".into()],
        columns: vec![
            hxai_data::Column::Number(vec![0.0, 0.001, 0.002]),
            hxai_data::Column::Text(vec!["1".into(), "x".into(), "2".into()]),
        ],
        skipped_rows: 0,
    };
    hxai_data::write_mixed_table(&p, &t)?;
    let err = error_of(read_record(&p))?;
    assert!(
        matches!(&err, DataError::NonNumeric { row: 2, column, .. } if column == "accel_ms2"),
        "{err:?}"
    );
    Ok(())
}
