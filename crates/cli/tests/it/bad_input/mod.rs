//! Every command against the corpus of bad files and flags in `testdata/bad/` (see its
//! README): each must fail with exit code 1 and one line on stderr naming the problem,
//! never panic (exit 101), never write over an input, never leave a partial file.
#![allow(clippy::unwrap_used, clippy::print_stderr)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use crate::common;
use common::{evaluate_args, predict_args, s};

fn corpus(rel: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../testdata/bad")
        .join(rel);
    p.to_str().unwrap().to_owned()
}

fn scratch(name: &str) -> common::Scratch {
    common::scratch("hxai-bad", name).unwrap()
}

/// A fresh scratch folder for `name` and the path of `file` in it, as text.
fn scratch_path(name: &str, file: &str) -> (common::Scratch, String) {
    let dir = scratch(name);
    let path = dir.join(file).to_str().unwrap().to_owned();
    (dir, path)
}

fn hxai(args: &[&str]) -> Output {
    common::hxai(args).unwrap()
}

/// The three commands that read one record at 20 Hz: features, displacement and predict
/// (the last two writing to `out`).
fn record_commands<'a>(rec: &'a str, model: &'a str, out: &'a str) -> [Vec<&'a str>; 3] {
    let hz = ["--record", rec, "--frequency-hz", "20"];
    let mut features = vec!["features"];
    features.extend_from_slice(&hz);
    let mut displacement = vec!["displacement"];
    displacement.extend_from_slice(&hz);
    displacement.extend_from_slice(&["--out", out]);
    [features, displacement, predict_args(model, rec, "20", out)]
}

/// Runs the command and requires exit code 1 with one stderr line containing `expect`.
fn refused(args: &[&str], expect: &str) {
    let out = hxai(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = stderr
        .lines()
        .filter(|l| !l.starts_with("warning: "))
        .collect();
    assert_eq!(
        out.status.code(),
        Some(1),
        "{args:?}: expected exit code 1, got {:?}; stderr:\n{stderr}",
        out.status.code()
    );
    assert_eq!(
        lines.len(),
        1,
        "{args:?}: expected one line, got:\n{stderr}"
    );
    assert!(lines[0].starts_with("error: "), "{args:?}: {stderr}");
    assert!(
        lines[0].contains(expect),
        "{args:?}: the message should contain {expect:?}:\n{stderr}"
    );
    assert!(lines[0].len() < 600, "{args:?}: message too long: {stderr}");
    assert!(
        !stderr.contains("polars"),
        "{args:?}: library internals: {stderr}"
    );
}

const BAD_RECORDS: &[(&str, &str)] = &[
    (
        "records/duplicate_column.csv",
        "`accel_ms2` appears more than once",
    ),
    (
        "records/duplicate_column.parquet",
        "`accel_ms2` appears more than once",
    ),
    (
        "records/ragged_row.csv",
        "row 10 has 2 cells but the header has 3 columns",
    ),
    (
        "records/text_cell.csv",
        "row 5, column `accel_ms2`: `n/a` is not a number",
    ),
    (
        "records/nan_cell.csv",
        "row 7, column `accel_ms2`: value NaN is not finite",
    ),
    (
        "records/huge_number.csv",
        "row 4, column `accel_ms2`: value inf is not finite",
    ),
    ("records/time_not_increasing.csv", "row 11, column `time_s`"),
    ("records/time_gap.csv", "sampling must be uniform"),
    ("records/missing_time.csv", "missing column `time_s`"),
    ("records/header_only.csv", "no data rows (only a header)"),
    ("records/empty.csv", "no data rows (it is empty)"),
    ("records/binary.csv", "not UTF-8"),
    ("records/latin1.csv", "not UTF-8"),
    ("records/record.txt", "unknown file type"),
    ("records/float16.parquet", "stored as float16"),
    ("records/int16.parquet", "stored as int16"),
    ("records/uint8.parquet", "stored as uint8"),
    ("records/decimal128.parquet", "stored as decimal(12, 6)"),
    (
        "records/time_ns_int64.parquet",
        "`time_s` is stored as integers",
    ),
    ("records/time_timestamp.parquet", "stored as a timestamp"),
    ("records/csv_named.parquet", "not a readable Parquet file"),
    ("records/truncated.parquet", "not a readable Parquet file"),
    ("records", "is a folder"),
    ("records/nowhere.csv", "No such file"),
];

/// For each (corpus file, expected message) of `cases`, every command line that
/// `commands(path of the file)` gives is refused with that message, and none writes `out`.
fn each_refused(cases: &[(&str, &str)], out: &str, commands: impl Fn(&str) -> Vec<Vec<String>>) {
    for (file, expect) in cases {
        for args in commands(&corpus(file)) {
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            refused(&args, expect);
        }
        assert!(!Path::new(out).exists(), "{file}: an output was written");
    }
}

/// The command line as owned strings.
fn owned(args: &[&str]) -> Vec<String> {
    args.iter().map(|a| a.to_string()).collect()
}

#[test]
fn bad_records_are_refused_by_every_command_that_reads_one() {
    let (_dir, out) = scratch_path("records", "out.csv");
    let out = out.as_str();
    let model = corpus("good/model.json");
    each_refused(BAD_RECORDS, out, |rec| {
        record_commands(rec, &model, out)
            .iter()
            .map(|a| owned(a))
            .collect()
    });
    // Too short for what each command needs, with the minimum named.
    let two = corpus("records/two_samples.csv");
    let expects = ["needs at least 51", "samples", "one window needs 1 s"];
    for (args, expect) in record_commands(&two, &model, out).iter().zip(expects) {
        refused(args, expect);
    }
}

#[test]
fn integer_channels_of_any_width_are_read() {
    let out = hxai(&[
        "features",
        "--record",
        &corpus("records/int_channels.parquet"),
        "--frequency-hz",
        "20",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

const BAD_TABLES: &[(&str, &str)] = &[
    (
        "tables/duplicate_y.csv",
        "column `y` appears more than once",
    ),
    (
        "tables/text_column.csv",
        "row 1, column `name`: `n0` is not a number",
    ),
    ("records/huge_number.csv", "value inf is not finite"),
    ("records/ragged_row.csv", "row 10 has 2 cells"),
    ("records/float16.parquet", "float16"),
    ("records/empty.csv", "no data rows"),
];

#[test]
fn bad_tables_are_refused_by_sr_and_compare() {
    for (file, expect) in BAD_TABLES {
        let t = corpus(file);
        // `accel_ms2` is the target where the file is a record, `y` otherwise.
        let target = if file.starts_with("records") {
            "accel_ms2"
        } else {
            "y"
        };
        refused(
            &["sr", "--csv", &t, "--target", target, "--epochs", "1"],
            expect,
        );
        refused(
            &["compare", "--train", &t, "--test", &t, "--target", target],
            expect,
        );
    }
    let good = corpus("tables/good.csv");
    refused(
        &[
            "compare",
            "--train",
            &good,
            "--test",
            &corpus("tables/duplicate_y.csv"),
            "--target",
            "y",
        ],
        "appears more than once",
    );
    refused(
        &[
            "sr",
            "--csv",
            &corpus("tables/target_only.csv"),
            "--target",
            "y",
        ],
        "y",
    );
    refused(
        &[
            "sr",
            "--csv",
            &corpus("tables/empty_name.csv"),
            "--target",
            "y",
        ],
        "name",
    );
}

const BAD_FOLDERS: &[(&str, &str)] = &[
    ("folders/shared_file", "row 2: record `b` uses the file"),
    (
        "folders/same_file_two_spellings",
        "which row 1 already uses",
    ),
    (
        "folders/frequency_300hz",
        "outside the physics model's pass band 5..200 Hz",
    ),
    ("folders/frequency_0_5hz", "frequency 0.5 Hz lies outside"),
    ("folders/frequency_4000hz", "frequency 4000 Hz lies outside"),
    ("folders/record_is_folder", "is a folder, not a file"),
    ("folders/missing_file", "does not exist"),
    ("folders/negative_frequency", "must be positive"),
    (
        "folders/short_records",
        "record `a` lasts 0.2 s but one window needs 1 s",
    ),
    ("good/manifest.csv", "is a file, not a folder"),
    ("folders/nowhere", "does not exist"),
];

#[test]
fn bad_folders_are_refused_by_fit_and_evaluate() {
    let (_dir, out) = scratch_path("folders", "m.json");
    let out = out.as_str();
    let model = corpus("good/model.json");
    each_refused(BAD_FOLDERS, out, |d| {
        vec![
            owned(&["fit", "--data", d, "--out", out, "--epochs", "1"]),
            owned(&evaluate_args(&model, d, &["--all"])),
        ]
    });
}

const BAD_MODELS: &[(&str, &str)] = &[
    (
        "models/input_index_out_of_range.json",
        "input index 7 has no feature name",
    ),
    (
        "models/schema_version_text.json",
        "schema_version \"1\" (text, not a number)",
    ),
    (
        "models/schema_version_2.json",
        "schema_version 2 but this hxai reads version 1",
    ),
    (
        "models/window_1e18.json",
        "window length must be a positive number of seconds up to 1e6, got 1e18",
    ),
    ("models/discard_1e300.json", "got 1e300"),
    (
        "models/order_100000.json",
        "filter order 100000 is too high",
    ),
    ("models/params_missing.json", "parameters"),
    (
        "models/feature_names_renamed.json",
        "`features.names` must be f1",
    ),
    ("models/truncated.json", "not a valid hxai hybrid model"),
    ("models", "is a folder"),
    ("models/nowhere.json", "No such file"),
];

#[test]
fn bad_models_are_refused_by_predict_and_evaluate() {
    let (_dir, out) = scratch_path("models", "p.csv");
    let out = out.as_str();
    let (rec, good) = (corpus("good/r1.parquet"), corpus("good"));
    each_refused(BAD_MODELS, out, |m| {
        vec![
            owned(&predict_args(m, &rec, "20", out)),
            owned(&evaluate_args(m, &good, &["--all"])),
        ]
    });
}

#[test]
fn bad_flags_are_refused_at_once() {
    let dir = scratch("flags");
    let rec = corpus("good/r1.parquet");
    let good = corpus("good");
    let model = corpus("good/model.json");
    let out = dir.join("o.csv");
    let out = out.to_str().unwrap();
    let m = dir.join("m.json");
    let m = m.to_str().unwrap();
    let feats = ["features", "--record", &rec, "--frequency-hz", "20"];
    for threads in ["0", "100000000"] {
        let mut a = vec!["--threads", threads];
        a.extend_from_slice(&feats);
        refused(&a, "--threads must be 1 to 1024");
    }
    let t0 = std::time::Instant::now();
    refused(
        &[
            "displacement",
            "--record",
            &rec,
            "--frequency-hz",
            "20",
            "--out",
            out,
            "--order",
            "100000",
        ],
        "filter order 100000 is too high; at most 64",
    );
    assert!(
        t0.elapsed().as_secs() < 20,
        "--order 100000 took {:?}",
        t0.elapsed()
    );
    refused(
        &[
            "displacement",
            "--record",
            &rec,
            "--frequency-hz",
            "1e300",
            "--out",
            out,
        ],
        "--frequency-hz 1e300 lies outside the pass band 5..200 Hz",
    );
    refused(
        &predict_args(&model, &rec, "300", out),
        "commanded frequency 300 Hz lies outside the physics model's pass band 5..200 Hz",
    );
    refused(
        &["features", "--record", &rec, "--frequency-hz=-5"],
        "positive",
    );
    for (flag, value, expect) in [
        (
            "--window-s",
            "1e18",
            "window length must be a positive number of seconds up to 1e6, got 1e18",
        ),
        ("--discard-s", "1e300", "got 1e300"),
        ("--test-fraction", "2", "test fraction"),
    ] {
        refused(
            &[
                "fit", "--data", &good, "--out", m, flag, value, "--epochs", "1",
            ],
            expect,
        );
    }
    refused(
        &[
            "fit",
            "--data",
            &good,
            "--out",
            m,
            "--samples",
            &format!("{}/x.txt", dir.display()),
        ],
        "unknown file type",
    );
    assert!(
        !Path::new(m).exists(),
        "the model was written before --samples was refused"
    );
    let new = dir.join("new");
    let new = new.to_str().unwrap();
    refused(
        &[
            "simulate",
            "--out",
            new,
            "--config",
            &corpus("configs/typo_key.json"),
        ],
        "unknown key `seeed`",
    );
    refused(
        &[
            "simulate",
            "--out",
            new,
            "--config",
            &corpus("configs/not_json.json"),
        ],
        "not a valid simulator configuration",
    );
    assert!(!Path::new(new).exists());
    // Interval levels are checked before any work, by flag, not deep in a library.
    for level in ["0", "1", "1.5", "-0.2"] {
        let flag = format!("--interval={level}");
        let mut p = predict_args(&model, &rec, "20", out);
        p.push(&flag);
        refused(&p, "--interval must lie strictly between 0 and 1");
        refused(
            &["evaluate", "--model", &model, "--data", &good, &flag],
            "--interval must lie strictly between 0 and 1",
        );
    }
    let mut inverted = record_commands(&rec, &model, out)[1].clone();
    inverted.extend(["--low-hz", "100", "--high-hz", "10"]);
    refused(&inverted, "--low-hz 100 must be below --high-hz 10");
    refused(&["simulate", "--out", &good], "the folder is not empty");
    refused(&["simulate", "--out", &rec], "is a file, not a folder");
}

fn bytes(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap()
}

#[test]
fn inputs_are_never_written_over() {
    let dir = scratch("sacred");
    let data = dir.join("data");
    std::fs::create_dir_all(&data).unwrap();
    for f in [
        "manifest.csv",
        "r1.parquet",
        "r2.parquet",
        "r3.parquet",
        "r4.parquet",
    ] {
        std::fs::copy(corpus(&format!("good/{f}")), data.join(f)).unwrap();
    }
    let model = dir.join("model.json");
    std::fs::copy(corpus("good/model.json"), &model).unwrap();
    let rec = data.join("r1.parquet");
    let manifest = data.join("manifest.csv");
    let before: Vec<(PathBuf, Vec<u8>)> = [&rec, &manifest, &model]
        .iter()
        .map(|p| (p.to_path_buf(), bytes(p)))
        .collect();
    let dotted = format!("{}/./r1.parquet", data.display());
    let (m_json, m_csv) = (dir.join("m.json"), dir.join("m.csv"));
    let (rec, manifest, model, data) = (s(&rec), s(&manifest), s(&model), s(&data));
    let displacement = |out| {
        vec![
            "displacement",
            "--record",
            rec,
            "--frequency-hz",
            "20",
            "--out",
            out,
        ]
    };
    let fit = |out| vec!["fit", "--data", data, "--out", out];
    let cases: Vec<Vec<&str>> = vec![
        displacement(rec),
        displacement(&dotted),
        predict_args(model, rec, "20", rec),
        predict_args(model, rec, "20", model),
        fit(manifest),
        fit(rec),
        [fit(s(&m_json)), vec!["--samples", manifest]].concat(),
        [fit(s(&m_csv)), vec!["--samples", s(&m_csv)]].concat(),
    ];
    for args in &cases {
        refused(args, "refusing to write over an input");
        for (p, b) in &before {
            assert_eq!(&bytes(p), b, "{args:?} changed {}", p.display());
        }
    }
    assert!(!dir.join("m.json").exists());
}

#[cfg(unix)]
#[test]
fn json_output_with_a_non_utf8_path_does_not_panic() {
    use std::os::unix::ffi::OsStrExt;
    let dir = scratch("nonutf8");
    let out = dir.join(std::ffi::OsStr::from_bytes(b"p\xff.csv"));
    let o = Command::new(env!("CARGO_BIN_EXE_hxai"))
        .args(["predict", "--model", &corpus("good/model.json"), "--record"])
        .arg(corpus("good/r1.parquet"))
        .args(["--frequency-hz", "20", "--json", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(doc["warnings"].is_array());
    assert!(out.exists());
}

#[test]
fn closed_stdout_is_a_normal_exit() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hxai"))
        .args([
            "features",
            "--record",
            &corpus("good/r1.parquet"),
            "--frequency-hz",
            "20",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}

mod warnings;
