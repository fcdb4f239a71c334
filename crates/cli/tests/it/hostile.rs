//! What the second hostile pass of issue 27 found (904 cases over every command), each
//! class kept as a test: a full standard output, outputs that are pipes, a stream rate no
//! window fits, a one-row or repeated test table for `compare`, a typo in a column of
//! numbers, a table that is not the model's, the traps of a constant target and of
//! parameters the data cannot tell apart, negative option values, errors that name the
//! option typed, and model files judged in JSON's words.
#![allow(clippy::unwrap_used)]

use crate::common;

use common::{hxai, s, scratch, stderr};
use std::path::{Path, PathBuf};

/// The good corpus folder of `testdata/bad`.
fn good(file: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../testdata/bad/good")
        .join(file);
    p.to_str().unwrap().to_owned()
}

/// A roughness table of `rows` rows (seed `seed`) in `dir`, and a quick hybrid fitted on
/// the seed-1 table.
fn roughness(dir: &Path, seed: &str) -> PathBuf {
    let t = dir.join(format!("rough{seed}.csv"));
    let o = hxai(&[
        "simulate",
        "--case",
        "roughness",
        "--rows",
        "80",
        "--seed",
        seed,
        "--out",
        s(&t),
    ])
    .unwrap();
    common::ok(&o, "simulate roughness");
    t
}

const PHYSICS: &str = "1000*feed_mm^2/(32*nose_radius_mm) + Ra0";

/// The arguments of a quick `hybrid fit` of `table` written to `out`, then `extra`.
fn hybrid_fit_args<'a>(table: &'a Path, out: &'a Path, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "hybrid",
        "fit",
        "--data",
        s(table),
        "--target",
        "Ra_um",
        "--physics",
        PHYSICS,
        "--calibrate",
        "Ra0",
        "--exclude",
        "tool",
        "--epochs",
        "1",
        "--conformal-folds",
        "0",
        "--out",
        s(out),
    ];
    args.extend_from_slice(extra);
    args
}

fn hybrid_fit(table: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    hxai(&hybrid_fit_args(table, out, extra)).unwrap()
}

/// Runs `hxai` with its standard output on `/dev/full` (a full disk).
fn to_full_stdout(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_hxai"))
        .args(args)
        .stdout(std::fs::File::create("/dev/full").unwrap())
        .output()
        .unwrap()
}

/// Exit code 1 and `needle` in the one error line.
fn refused(o: &std::process::Output, needle: &str) {
    let err = stderr(o);
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(errors.len(), 1, "{err}");
    assert!(errors[0].contains(needle), "`{needle}` not in: {err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn a_full_standard_output_is_an_error_not_a_panic() {
    if !Path::new("/dev/full").exists() {
        return;
    }
    let dir = scratch("hxai-hostile", "full").unwrap();
    let t = roughness(&dir, "1");
    let o = to_full_stdout(&[
        "sr",
        "--csv",
        s(&t),
        "--target",
        "Ra_um",
        "--epochs",
        "1",
        "--json",
    ]);
    refused(&o, "cannot write to standard output");
    // a model file is renamed into place only after its --json document was printed
    let m = dir.join("m.json");
    std::fs::write(&m, "old").unwrap();
    let o = to_full_stdout(&hybrid_fit_args(&t, &m, &["--json"]));
    refused(&o, "cannot write to standard output");
    assert_eq!(std::fs::read_to_string(&m).unwrap(), "old");
    // so is a table whose --json report cannot be printed
    let table = dir.join("t2.csv");
    std::fs::write(&table, "old").unwrap();
    let o = to_full_stdout(&[
        "simulate",
        "--case",
        "roughness",
        "--rows",
        "40",
        "--out",
        s(&table),
        "--json",
        "--force",
    ]);
    refused(&o, "cannot write to standard output");
    assert_eq!(std::fs::read_to_string(&table).unwrap(), "old");
    common::assert_no_temporary_files(&dir);
}

#[test]
fn a_pipe_or_device_is_never_replaced_by_an_output() {
    let dir = scratch("hxai-hostile", "fifo").unwrap();
    let fifo = dir.join("d.csv");
    if !std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|st| st.success())
    {
        return;
    }
    let o = hxai(&[
        "displacement",
        "--record",
        &good("r1.parquet"),
        "--frequency-hz",
        "20",
        "--out",
        s(&fifo),
    ])
    .unwrap();
    refused(&o, "is not a regular file");
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    let o = hxai(&[
        "stream",
        "--model",
        &good("model.json"),
        "--frequency-hz",
        "20",
        "--in",
        &good("r1.parquet"),
        "--out",
        "/dev/null",
    ])
    .unwrap();
    refused(&o, "is not a regular file");
}

#[test]
fn a_stream_rate_no_window_fits_is_refused_before_allocating() {
    let o = hxai(&[
        "stream",
        "--model",
        &good("model.json"),
        "--frequency-hz",
        "20",
        "--fs-hz",
        "1e9",
    ])
    .unwrap();
    refused(&o, "more than the 10000000 a stream holds");
}

#[test]
fn compare_refuses_one_test_row_and_warns_on_repeated_rows() {
    let dir = scratch("hxai-hostile", "compare").unwrap();
    let t = roughness(&dir, "1");
    let one = dir.join("one.csv");
    let text = std::fs::read_to_string(&t).unwrap();
    std::fs::write(
        &one,
        text.lines().take(2).collect::<Vec<_>>().join("\n") + "\n",
    )
    .unwrap();
    let base = ["compare", "--train", s(&t), "--target", "Ra_um", "--test"];
    let mut args = base.to_vec();
    args.push(s(&one));
    refused(&hxai(&args).unwrap(), "the test table has 1 row(s)");
    let mut args = base.to_vec();
    args.extend([s(&t), "--json"]);
    let o = hxai(&args).unwrap();
    common::ok(&o, "compare a table with itself");
    assert!(
        stderr(&o).contains("80 of the 80 test rows repeat a training row"),
        "{}",
        stderr(&o)
    );
    // the models of the contract, gradient boosting among them (issue 48)
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let names: Vec<&str> = doc["models"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|m| m["name"].as_str())
        .collect();
    assert_eq!(
        names,
        [
            "linear", "lasso_cv", "tree_5", "tree_6", "tree_8", "forest", "boosting", "symbolic"
        ]
    );
}

#[test]
fn table_traps_and_bad_cells_are_named() {
    let dir = scratch("hxai-hostile", "traps").unwrap();
    let t = roughness(&dir, "1");
    let text = std::fs::read_to_string(&t).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let edit = |name: &str, f: &dyn Fn(usize, &mut Vec<String>)| -> PathBuf {
        let p = dir.join(name);
        let rows: Vec<String> = text
            .lines()
            .enumerate()
            .map(|(i, l)| {
                let mut cells: Vec<String> = l.split(',').map(str::to_owned).collect();
                if i > 0 {
                    f(i, &mut cells);
                }
                cells.join(",")
            })
            .collect();
        std::fs::write(&p, rows.join("\n") + "\n").unwrap();
        p
    };
    let m = dir.join("m.json");
    // a typo in a column of numbers, used as a default feature
    let speed = col("cutting_speed_m_min");
    let typo = edit("typo.csv", &|i, c| {
        if i == 60 {
            c[speed] = "12O.5".into()
        }
    });
    refused(
        &hybrid_fit(&typo, &m, &[]),
        "row 60, column `cutting_speed_m_min`: `12O.5` is not a number",
    );
    assert!(!m.exists());
    // a constant target, and parameters only their product is fitted of
    let ra = col("Ra_um");
    let constant = edit("constant.csv", &|_, c| c[ra] = "2.5".into());
    let o = hybrid_fit(&constant, &m, &[]);
    common::ok(&o, "fit a constant target");
    assert!(
        stderr(&o).contains("the target `Ra_um` is constant"),
        "{}",
        stderr(&o)
    );
    let o = hxai(&[
        "hybrid",
        "fit",
        "--data",
        s(&t),
        "--target",
        "Ra_um",
        "--physics",
        "a*b*feed_mm",
        "--calibrate",
        "a,b",
        "--exclude",
        "tool",
        "--epochs",
        "1",
        "--conformal-folds",
        "0",
        "--out",
        s(&m),
    ])
    .unwrap();
    common::ok(&o, "fit a*b*x");
    assert!(
        stderr(&o).contains("cannot tell the calibrated parameter(s) a, b apart"),
        "{}",
        stderr(&o)
    );
    // explain with another table of the same length
    common::ok(&hybrid_fit(&t, &m, &[]), "fit");
    let other = roughness(&dir, "7");
    let pics = dir.join("pics");
    let o = hxai(&[
        "explain",
        "--model",
        s(&m),
        "--data",
        s(&other),
        "--out",
        s(&pics),
    ])
    .unwrap();
    refused(&o, "this is not the table the model was fitted on");
    common::ok(
        &hxai(&[
            "explain",
            "--model",
            s(&m),
            "--data",
            s(&t),
            "--out",
            s(&pics),
        ])
        .unwrap(),
        "explain with the model's table",
    );
    // a hand-edited model file is judged in JSON's words
    let json = std::fs::read_to_string(&m).unwrap();
    let bad = dir.join("bad.json");
    std::fs::write(&bad, json.replacen("\"additive\"", "\"cubic\"", 1)).unwrap();
    let o = hxai(&[
        "hybrid",
        "predict",
        "--model",
        s(&bad),
        "--data",
        s(&t),
        "--out",
        s(&dir.join("p.csv")),
    ])
    .unwrap();
    refused(&o, "unknown value `cubic`");
}

#[test]
fn options_are_named_as_typed_and_take_negative_values() {
    let dir = scratch("hxai-hostile", "options").unwrap();
    let t = roughness(&dir, "1");
    let o = hxai(&[
        "sr",
        "--csv",
        s(&t),
        "--target",
        "Ra_um",
        "--max-complexity",
        "0",
    ])
    .unwrap();
    refused(&o, "--max-complexity is 0");
    let o = hybrid_fit(&t, &dir.join("m.json"), &["--test-fraction", "-0.1"]);
    refused(
        &o,
        "--test-fraction must lie strictly between 0 and 1, got -0.1",
    );
    assert!(!stderr(&o).contains("evaluation failed"));
    // a negative whole number is refused in words by the parser (exit 2, as clap's errors)
    let o = hxai(&["sr", "--csv", s(&t), "--target", "Ra_um", "--epochs", "-1"]).unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("'-1' for '--epochs <EPOCHS>': not a whole number of 0 or more"),
        "{}",
        stderr(&o)
    );
}
