//! A command stopped by SIGINT or SIGTERM leaves no hidden temporary file and no output
//! changed (issue 27): `simulate --force` over an existing data folder is stopped while it
//! writes, and the folder must read back exactly as before.
#![cfg(unix)]

use crate::common::{assert_no_temporary_files, s, scratch, simulate_small};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Every file of `dir` (hidden ones too) with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .filter_map(Result::ok)
        .map(|e| {
            let bytes = std::fs::read(e.path()).unwrap_or_default();
            (e.file_name().to_string_lossy().into_owned(), bytes)
        })
        .collect()
}

/// Whether a staging file (`.NAME.PID-N.tmp`) exists in `dir`.
fn staging(dir: &Path) -> bool {
    std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .filter_map(Result::ok)
        .any(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
}

/// Stops `simulate --force` over `data` with `signal` once it has begun to write (its
/// forty 20 s records take seconds to stage), and returns its exit code (`None`: ended by
/// the signal itself, the default action without a handler).
fn stop_while_writing(data: &Path, signal: &str) -> Option<i32> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hxai"))
        .args([
            "simulate",
            "--out",
            s(data),
            "--force",
            "--format",
            "csv",
            "--repeats",
            "1",
            "--duration-s",
            "20",
            "--seed",
            "2",
            "--threads",
            "1",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("start simulate");
    let start = Instant::now();
    while !staging(data) {
        if child.try_wait().expect("poll").is_some() || start.elapsed() > Duration::from_secs(300) {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let killed = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .expect("run kill");
    assert!(killed.success());
    child.wait().expect("wait").code()
}

#[test]
fn a_signal_while_writing_leaves_the_folder_as_it_was() {
    let dir = scratch("hxai-signals", "simulate").expect("scratch");
    let data = dir.join("data");
    simulate_small(&data, "0.5", &["--format", "csv"], "the old folder").expect("run");
    let before = snapshot(&data);
    for (signal, code) in [("-TERM", 143), ("-INT", 130)] {
        assert_eq!(stop_while_writing(&data, signal), Some(code), "{signal}");
        assert_no_temporary_files(&data);
        assert_eq!(snapshot(&data), before, "{signal} changed the folder");
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// Ctrl-C is how a live stream ends: the rows written so far are kept in `--out` (whole
/// rows, renamed into place), not lost with the temporary file.
#[test]
fn a_stopped_stream_keeps_its_rows() {
    use std::io::Write;
    let dir = scratch("hxai-signals", "stream").expect("scratch");
    let data = dir.join("data");
    let one_record = [
        "--format",
        "csv",
        "--amplitudes",
        "4",
        "--frequencies",
        "20",
    ];
    simulate_small(&data, "0.8", &one_record, "a record").expect("run");
    let record = std::fs::read_dir(&data)
        .expect("list")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| p.file_name().is_some_and(|n| n != "manifest.csv"))
        .expect("a record file");
    let text = std::fs::read_to_string(&record).expect("read the record");
    let model =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/bad/good/model.json");
    let out = dir.join("o.csv");
    let mut child = Command::new(env!("CARGO_BIN_EXE_hxai"))
        .args([
            "stream",
            "--model",
            s(&model),
            "--frequency-hz",
            "20",
            "--out",
            s(&out),
        ])
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start stream");
    let mut stdin = child.stdin.take().expect("stdin");
    stdin.write_all(text.as_bytes()).expect("feed the stream");
    stdin.flush().expect("flush");
    // The input stays open (a live stream); wait until the rows reach the temporary file.
    let start = Instant::now();
    let written = || {
        std::fs::read_dir(&dir)
            .into_iter()
            .flatten()
            .filter_map(Result::ok)
            .any(|e| {
                e.file_name().to_string_lossy().ends_with(".tmp")
                    && e.metadata().is_ok_and(|m| m.len() > 0)
            })
    };
    while !written() {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no rows written"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    std::thread::sleep(Duration::from_millis(200));
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    assert!(killed.is_ok_and(|k| k.success()));
    let done = child.wait_with_output().expect("wait");
    drop(stdin);
    assert_eq!(done.status.code(), Some(130));
    let err = String::from_utf8_lossy(&done.stderr);
    assert!(err.contains("the rows so far are in"), "{err}");
    let rows = std::fs::read_to_string(&out).expect("the rows were kept");
    // one row per input sample after the header; every row whole
    assert_eq!(rows.lines().count(), text.lines().count(), "{err}");
    assert!(rows.ends_with('\n'));
    assert_no_temporary_files(&dir);
    std::fs::remove_dir_all(&dir).expect("clean up");
}
