//! `hxai stream`: rows arrive through a pipe while the input is still open, one row per
//! sample; gaps restart with a warning; a bad line is named after the rows before it; the
//! file output and the summary follow the contract.

use crate::common;

use common::{hxai, s, scratch, stderr};
use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

const MODEL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../testdata/bad/good/model.json"
);

/// CSV text of `n` samples from `start` at 2 kHz of a 25 Hz motion, with an extra column.
fn lines(start: usize, n: usize) -> String {
    let (fs, w) = (2000.0, 2.0 * std::f64::consts::PI * 25.0);
    (start..start + n)
        .map(|i| {
            let t = i as f64 / fs;
            format!("{t},{},7\n", -6e-6 * w * w * (w * t).sin())
        })
        .collect()
}

const HEADER: &str = "time_s,accel_ms2,probe_um\n";

/// `hxai stream` of the test model at 25 Hz on `input`, then the `extra` flags.
fn stream(input: &std::path::Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "stream",
        "--model",
        MODEL,
        "--frequency-hz",
        "25",
        "--in",
        s(input),
    ];
    args.extend_from_slice(extra);
    hxai(&args).expect("run")
}

/// A scratch folder `name` holding `in.csv` with the header and `body`.
fn input_file(name: &str, body: &str) -> (common::Scratch, std::path::PathBuf) {
    let dir = scratch("hxai-stream", name).expect("scratch");
    let input = dir.join("in.csv");
    std::fs::write(&input, format!("{HEADER}{body}")).expect("write input");
    (dir, input)
}

/// Through a pipe that stays open: every row written so far can be read before the input
/// ends (the output is flushed whenever no whole line is ready), then the end of the input
/// ends the run with exit code 0.
#[test]
fn rows_come_through_an_open_pipe() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hxai"))
        .args(["stream", "--model", MODEL, "--frequency-hz", "25"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("hxai starts");
    let mut stdin = child.stdin.take().expect("stdin");
    let stdout = child.stdout.take().expect("stdout");
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines() {
            if tx.send(line.expect("a line of output")).is_err() {
                return;
            }
        }
    });
    stdin
        .write_all(format!("{HEADER}{}", lines(0, 1500)).as_bytes())
        .expect("write");
    stdin.flush().expect("flush");
    // Header and 1500 rows, while the input is still open.
    let mut got = Vec::new();
    while got.len() < 1501 {
        match rx.recv_timeout(Duration::from_secs(20)) {
            Ok(l) => got.push(l),
            Err(_) => panic!(
                "only {} of 1501 lines arrived while the input was open",
                got.len()
            ),
        }
    }
    assert_eq!(got[0], "time_s,physics_um,hybrid_um");
    // Warm-up: one 0.5 s window at 2 kHz, 999 rows without values.
    assert_eq!(got[999], "0.499,,");
    let last: Vec<&str> = got[1500].split(',').collect();
    assert_eq!(last[0], "0.7495");
    assert!(
        last[1].parse::<f64>().is_ok() && last[2].parse::<f64>().is_ok(),
        "{}",
        got[1500]
    );
    stdin.write_all(lines(1500, 10).as_bytes()).expect("write");
    drop(stdin);
    let status = child.wait().expect("exit");
    assert!(status.success());
    let rest: Vec<String> = rx.iter().collect();
    assert_eq!(rest.len(), 10);
}

/// The file output equals standard output; the summary has the contract's keys; a gap in
/// time restarts the estimator with a warning naming the time, and rows go on.
#[test]
fn file_output_summary_and_gaps() {
    // 3000 samples, then a gap of 0.5 s, then 2000 more.
    let (dir, input) = input_file("files", &format!("{}{}", lines(0, 3000), lines(4000, 2000)));
    let (out, summary) = (dir.join("out.csv"), dir.join("summary.json"));
    let o = stream(&input, &["--out", s(&out), "--summary", s(&summary)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("gap at t = 2 s (line 3002)"),
        "{}",
        stderr(&o)
    );
    let piped = stream(&input, &[]);
    let written = std::fs::read_to_string(&out).expect("output");
    assert_eq!(written.as_bytes(), piped.stdout.as_slice());
    let rows: Vec<&str> = written.lines().collect();
    assert_eq!(rows.len(), 1 + 5000);
    // After the gap the warm-up starts again: 999 empty rows, then values.
    assert!(rows[1 + 3000 + 998].ends_with(",,"), "{}", rows[1 + 3998]);
    assert!(!rows[1 + 3000 + 999].ends_with(",,"));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary).expect("summary")).expect("json");
    for (key, want) in [
        ("delay_samples", 0.0),
        ("warmup_samples", 999.0),
        ("samples", 5000.0),
        ("restarts", 1.0),
        ("frequency_hz", 25.0),
        ("fs_hz", 2000.0),
    ] {
        assert_eq!(doc[key].as_f64(), Some(want), "{key}: {doc}");
    }
    assert!(doc["seconds"].as_f64().is_some_and(|v| v >= 0.0));
    // No temporary file is left beside the outputs.
    common::assert_no_temporary_files(&dir);
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// A bad line stops the run with exit code 1 and an error naming the line; every row before
/// it has been written, to standard output and to `--out` alike.
#[test]
fn a_bad_line_is_named_after_the_rows_before_it() {
    let body = format!("{}0.6,oops,1\n{}", lines(0, 1200), lines(1201, 10));
    let (dir, input) = input_file("bad", &body);
    let out = dir.join("out.csv");
    for to_file in [false, true] {
        let extra = if to_file {
            vec!["--out", s(&out)]
        } else {
            vec![]
        };
        let o = stream(&input, &extra);
        assert_eq!(o.status.code(), Some(1));
        let err = stderr(&o);
        assert!(
            err.contains("line 1202") && err.contains("`accel_ms2` is `oops`"),
            "{err}"
        );
        let written = if to_file {
            std::fs::read_to_string(&out).expect("output")
        } else {
            String::from_utf8_lossy(&o.stdout).into_owned()
        };
        assert_eq!(written.lines().count(), 1 + 1200, "to a file: {to_file}");
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Short streams: a header alone gives a header alone; one sample (its sampling rate never
/// known) still gets its row, without values; the summary says so.
#[test]
fn short_streams_have_one_row_per_sample() {
    for (body, rows) in [("", 0), ("0.5,1.25,0\n", 1)] {
        let (dir, input) = input_file("short", body);
        let summary = dir.join("s.json");
        let o = stream(&input, &["--summary", s(&summary)]);
        assert!(o.status.success(), "{}", stderr(&o));
        let text = String::from_utf8_lossy(&o.stdout).into_owned();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 1 + rows, "{text}");
        if rows == 1 {
            assert_eq!(lines[1], "0.5,,");
        }
        let doc: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&summary).expect("summary"))
                .expect("json");
        assert_eq!(doc["samples"].as_u64(), Some(rows as u64));
        assert!(doc["fs_hz"].is_null());
        std::fs::remove_dir_all(&dir).expect("clean up");
    }
}

/// Settings that cannot work are refused before any input is read, by name.
#[test]
fn bad_settings_are_refused() {
    let (dir, input) = input_file("settings", &lines(0, 10));
    for (args, want) in [
        (
            vec!["--frequency-hz", "0"],
            "--frequency-hz must be a positive",
        ),
        (vec!["--frequency-hz", "500"], "outside"),
        (
            vec!["--frequency-hz", "25", "--fs-hz=-3"],
            "--fs-hz must be a positive",
        ),
        (vec!["--frequency-hz", "25", "--out", s(&input)], "input"),
        (
            vec!["--frequency-hz", "25", "--interval", "0.95"],
            "uncertainty",
        ),
    ] {
        let mut all = vec!["stream", "--model", MODEL, "--in", s(&input)];
        all.extend(args.iter().copied());
        let o = hxai(&all).expect("run");
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        let err = stderr(&o);
        assert!(err.contains(want), "{args:?}: {err}");
    }
    assert_eq!(
        std::fs::read_to_string(&input).expect("input"),
        format!("{HEADER}{}", lines(0, 10)),
        "the input is untouched"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// The README's tour runs `hxai stream` on a simulated record through a pipe: its two lines
/// (the `hxai simulate --out live` and the `cat live/... | hxai stream` line), taken from the
/// README as written, run by `sh` in a scratch folder with the test model as `model.json`.
#[test]
fn the_readme_tour_streams_through_a_pipe() {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md"))
        .expect("README");
    let lines: Vec<&str> = readme
        .lines()
        .filter(|l| l.starts_with("hxai simulate --out live") || l.starts_with("cat live/"))
        .collect();
    assert_eq!(lines.len(), 2, "the README's streaming step: {lines:?}");
    let dir = scratch("hxai-stream", "readme").expect("scratch");
    std::fs::copy(MODEL, dir.join("model.json")).expect("model");
    let bin = std::path::Path::new(env!("CARGO_BIN_EXE_hxai"))
        .parent()
        .expect("bin folder")
        .to_path_buf();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let o = Command::new("sh")
        .args(["-ec", &lines.join("\n")])
        .current_dir(&dir)
        .env("PATH", path)
        .output()
        .expect("sh");
    assert!(o.status.success(), "{}", stderr(&o));
    let out = std::fs::read_to_string(dir.join("position.csv")).expect("position.csv");
    let record = std::fs::read_to_string(dir.join("live/a8um_f25hz_r1.csv")).expect("record");
    assert_eq!(out.lines().count(), record.lines().count());
    let summary = std::fs::read_to_string(dir.join("live.json")).expect("summary");
    assert!(summary.contains("\"delay_samples\": 0"), "{summary}");
    std::fs::remove_dir_all(&dir).expect("clean up");
}
