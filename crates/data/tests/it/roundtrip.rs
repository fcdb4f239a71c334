//! Round-trip properties: what this crate writes, it reads back unchanged.

use hxai_data::{
    Column, DataError, Format, ManifestEntry, MixedTable, Record, Table, read_folder,
    read_mixed_table, read_record, read_table, write_folder, write_mixed_table, write_record,
    write_table,
};
use proptest::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;

/// A new empty folder, removed with what is in it when the guard is dropped.
fn scratch() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("hxai-data-rt-")
        .tempdir()
        .expect("a scratch folder in the temporary directory")
}

/// Writes `value` with `write` as CSV and as Parquet (`stem.csv`, `stem.parquet`) in a
/// fresh scratch folder and returns what `read` gives back from each, for the caller to
/// compare with `value`.
fn round_trip<T>(
    stem: &str,
    value: &T,
    write: impl Fn(&Path, &T) -> Result<(), DataError>,
    read: impl Fn(&Path) -> Result<T, DataError>,
) -> Result<Vec<T>, DataError> {
    let scratch_dir = scratch();
    let dir = scratch_dir.path();
    let mut back = Vec::new();
    for ext in ["csv", "parquet"] {
        let p = dir.join(format!("{stem}.{ext}"));
        write(&p, value)?;
        back.push(read(&p)?);
    }
    Ok(back)
}

/// Any finite f64 (normal, subnormal or zero, either sign).
fn finite() -> impl Strategy<Value = f64> {
    prop::num::f64::NORMAL | prop::num::f64::SUBNORMAL | prop::num::f64::ZERO
}

fn record_strategy() -> impl Strategy<Value = Record> {
    (2usize..60, 1.0f64..1e5, 0.0f64..100.0).prop_flat_map(|(n, fs, t0)| {
        let time_s: Vec<f64> = (0..n).map(|i| t0 + i as f64 / fs).collect();
        (
            Just(time_s),
            prop::collection::vec(finite(), n),
            prop::option::of(prop::collection::vec(finite(), n)),
            prop::option::of(prop::collection::vec(finite(), n)),
            prop::option::of(prop::collection::vec(finite(), n)),
        )
            .prop_map(
                |(time_s, accel_ms2, probe_um, command_um, encoder_um)| Record {
                    time_s,
                    accel_ms2,
                    probe_um,
                    command_um,
                    encoder_um,
                },
            )
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    // Invariant: writing any valid record (any finite values, optional channels present or
    // not) as CSV or as Parquet and reading it back gives exactly the same record, value for
    // value (CSV numbers are written in shortest round-trip form, so no precision is lost).
    #[test]
    fn record_round_trips_csv_and_parquet(rec in record_strategy()) {
        let backs = round_trip("r", &rec, write_record, read_record)
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
        for back in &backs {
            prop_assert_eq!(back, &rec);
        }
    }

    // Invariant: a numeric table round-trips exactly through CSV and Parquet.
    #[test]
    fn table_round_trips(cols in prop::collection::vec(prop::collection::vec(finite(), 1..20usize), 1..5)) {
        let n = cols[0].len();
        let columns: Vec<Vec<f64>> = cols.into_iter().map(|mut c| { c.resize(n, 0.5); c }).collect();
        let table = Table::new((0..columns.len()).map(|i| format!("c{i}")).collect(), columns).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let backs = round_trip("t", &table, write_table, read_table)
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
        for back in &backs {
            prop_assert_eq!(back, &table);
        }
    }

    // Invariant: a folder written in either format reads back with the same manifest
    // entries (ids, amplitudes, frequencies, repeats, extra columns) and the same records.
    #[test]
    fn folder_round_trips(recs in prop::collection::vec(record_strategy(), 1..4),
                          amps in prop::collection::vec(0.1f64..20.0, 4),
                          parquet in any::<bool>()) {
        let format = if parquet { Format::Parquet } else { Format::Csv };
        let items: Vec<(ManifestEntry, Record)> = recs.into_iter().enumerate().map(|(i, r)| {
            let mut extra = BTreeMap::new();
            extra.insert("note".to_string(), format!("take, {i}"));
            (ManifestEntry {
                record: format!("rec_{i}"),
                file: String::new(),
                amplitude_um: amps[i],
                frequency_hz: 10.0 + i as f64,
                repeat: if i % 2 == 0 { Some(i as u32) } else { None },
                extra,
            }, r)
        }).collect();
        let scratch_dir = scratch();
        let dir = scratch_dir.path();
        let written = write_folder(dir, &items, format).map_err(|e| TestCaseError::fail(e.to_string()))?;
        let folder = read_folder(dir).map_err(|e| TestCaseError::fail(e.to_string()))?;
        prop_assert_eq!(&folder.entries, &written.entries);
        for ((e, r), w) in items.iter().zip(&folder.entries) {
            prop_assert_eq!(&e.record, &w.record);
            prop_assert_eq!(e.amplitude_um, w.amplitude_um);
            prop_assert_eq!(&e.extra, &w.extra);
            let back = folder.read_record(w).map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert_eq!(&back, r);
        }
    }
}

#[test]
fn mixed_table_round_trips() -> Result<(), Box<dyn std::error::Error>> {
    let t = MixedTable {
        names: vec!["record".into(), "split".into(), "f1".into()],
        columns: vec![
            Column::Text(vec!["a".into(), "b, with comma".into()]),
            Column::Text(vec!["train".into(), "test".into()]),
            Column::Number(vec![10.0, 0.1]),
        ],
        skipped_rows: 0,
    };
    for back in round_trip("m", &t, write_mixed_table, read_mixed_table)? {
        assert_eq!(back, t);
    }
    let (num, skipped) = t.numeric()?;
    assert_eq!(num.names(), ["f1".to_string()]);
    assert_eq!(skipped, vec!["record".to_string(), "split".to_string()]);
    Ok(())
}

/// A quoted CSV header is read as RFC 4180 says: a doubled quote inside quotes is one
/// quote (`"a""b"` is the column `a"b`), and a quoted comma stays in the name.
#[test]
fn quoted_header_names_follow_rfc_4180() -> Result<(), Box<dyn std::error::Error>> {
    let scratch_dir = scratch();
    let dir = scratch_dir.path();
    let path = dir.join("q.csv");
    std::fs::write(&path, "\"a\"\"b\",\"c,d\",e\n1,2,3\n4,5,6\n")?;
    let t = read_mixed_table(&path)?;
    assert_eq!(t.names, ["a\"b", "c,d", "e"]);
    Ok(())
}
