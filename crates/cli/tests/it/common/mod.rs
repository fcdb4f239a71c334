//! Helpers shared by the CLI integration tests: run the `hxai` binary, make a scratch
//! folder, read its output, require success.
//!
//! Every test file compiles this module on its own and uses only part of it.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// `hxai simulate --out OUT --repeats 1 --duration-s SECONDS` and `extra`: a small folder of
/// simulated records for a test; fails (naming `what`) unless it succeeds.
pub fn simulate_small(
    out: &Path,
    seconds: &str,
    extra: &[&str],
    what: &str,
) -> Result<Output, std::io::Error> {
    let mut args = vec![
        "simulate",
        "--out",
        s(out),
        "--repeats",
        "1",
        "--duration-s",
        seconds,
    ];
    args.extend_from_slice(extra);
    hxai_ok(&args, what)
}

/// Runs the `hxai` binary built for these tests with `args`.
pub fn hxai(args: &[&str]) -> Result<Output, std::io::Error> {
    Command::new(env!("CARGO_BIN_EXE_hxai")).args(args).output()
}

/// Runs `hxai` and requires success; `what` names the step in the failure message.
pub fn hxai_ok(args: &[&str], what: &str) -> Result<Output, std::io::Error> {
    let out = hxai(args)?;
    ok(&out, what);
    Ok(out)
}

/// The arguments of `hxai predict` for one record at `frequency_hz`, written to `out`;
/// callers append further flags.
pub fn predict_args<'a>(
    model: &'a str,
    record: &'a str,
    frequency_hz: &'a str,
    out: &'a str,
) -> Vec<&'a str> {
    vec![
        "predict",
        "--model",
        model,
        "--record",
        record,
        "--frequency-hz",
        frequency_hz,
        "--out",
        out,
    ]
}

/// The arguments of `hxai evaluate` of `model` on `data`, then the `extra` flags.
pub fn evaluate_args<'a>(model: &'a str, data: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["evaluate", "--model", model, "--data", data];
    args.extend_from_slice(extra);
    args
}

/// A new empty folder `<temp>/<prefix>-<name>-<random>`, removed when the returned guard is
/// dropped.
pub fn scratch(prefix: &str, name: &str) -> Result<Scratch, std::io::Error> {
    let dir = tempfile::Builder::new()
        .prefix(&format!("{prefix}-{name}-"))
        .tempdir()?;
    Ok(Scratch(dir))
}

/// A scratch folder of [`scratch`]: a path (it dereferences to one) whose folder is removed,
/// with everything in it, when the test drops it.
pub struct Scratch(tempfile::TempDir);

impl std::ops::Deref for Scratch {
    type Target = Path;

    fn deref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<std::ffi::OsStr> for Scratch {
    fn as_ref(&self) -> &std::ffi::OsStr {
        self.0.path().as_os_str()
    }
}

/// The path as a `&str` (empty if it is not UTF-8, which the tests' paths always are).
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap_or_default()
}

/// The command's stderr, lossily decoded.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The command's stdout followed by its stderr, lossily decoded.
pub fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), stderr(o))
}

/// Requires that the command succeeded; `what` and stderr make the failure message.
pub fn ok(out: &Output, what: &str) {
    assert!(out.status.success(), "{what}: {}", stderr(out));
}

/// Requires that no temporary file (`.NAME.PID-N.tmp`, the atomic writers' staging files)
/// was left in `dir`.
pub fn assert_no_temporary_files(dir: &Path) {
    let left: Vec<String> = std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    assert!(left.iter().all(|n| !n.contains(".tmp")), "{left:?}");
}

/// Checks what every page of `hxai report` is (issue 50): an HTML5 document with the hybrid
/// as MathML in `<math id="hybrid-equation">`, no address of any resource and no script,
/// the sections in the order a reader asks (model, scores, how sure, where it holds, how to
/// reproduce), every figure an inline `<svg>` in an element with an accessible name, and a
/// print stylesheet. Returns the number of figures.
pub fn assert_self_contained_page(html: &str) -> usize {
    assert!(html.starts_with("<!DOCTYPE html>"));
    let eq = html.find("id=\"hybrid-equation\"");
    assert!(
        eq.is_some_and(|i| html[..i].ends_with("<math display=\"block\" ")),
        "no <math id=\"hybrid-equation\">"
    );
    for bad in ["http:", "https:", "<script", "<link", "@import", "url("] {
        assert!(!html.contains(bad), "{bad} in the page");
    }
    let order: Vec<usize> = ["model", "scores", "sure", "holds", "reproduce"]
        .iter()
        .map(|id| html.find(&format!("id=\"{id}\"")).unwrap_or(usize::MAX))
        .collect();
    assert!(order.windows(2).all(|w| w[0] < w[1]), "{order:?}");
    assert!(html.contains("@media print"));
    let svgs = html.matches("<svg").count();
    assert_eq!(html.matches("role=\"img\" aria-label=").count(), svgs);
    svgs
}
