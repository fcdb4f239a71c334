//! What every command shares to stay safe with bad input: refusing outputs that are
//! inputs, printing to a stdout that may be closed, warnings on stderr, and one-line error
//! messages.

use anyhow::Result;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Most worker threads `--threads` accepts: far above any machine this runs on, low enough
/// that a typo (`--threads 100000000`) is refused at once instead of spawning for minutes.
pub const MAX_THREADS: usize = 1024;

/// Installs the handler of SIGINT, SIGTERM and SIGHUP: it removes every unfinished
/// temporary output (`hxai_data::remove_temporary_files`), says so on stderr and ends the
/// process with the shell's code for the signal (128 + its number: 130 for Ctrl-C, 143 for
/// `kill`). Outputs are only ever replaced by a rename of a complete file, so an existing
/// output keeps its old contents. Without the handler the default action would end the
/// process at once and leave the hidden `.NAME.PID-N.tmp` files behind.
/// What a command does on SIGINT/SIGTERM/SIGHUP before its unfinished outputs are removed
/// (see [`on_signal`]); it returns a sentence for stderr.
type OnSignal = Box<dyn FnOnce() -> Option<String> + Send>;

static ON_SIGNAL: std::sync::Mutex<Option<OnSignal>> = std::sync::Mutex::new(None);

/// Set once a signal is being handled: the handler ends the process, so the main thread
/// must not end it first (with its own exit code, or before the handler has kept or
/// removed the outputs).
static STOPPING: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Waits for the signal handler to end the process when a signal is being handled (a
/// stream whose input ended because Ctrl-C stopped its producer too); returns at once
/// otherwise.
pub fn wait_if_stopping() {
    while STOPPING.load(std::sync::atomic::Ordering::SeqCst) {
        std::thread::park_timeout(std::time::Duration::from_secs(1));
    }
}

/// Registers what the command does when stopped by a signal, before the unfinished outputs
/// are removed: `hxai stream` keeps the rows written so far. The sentence it returns is
/// printed after the signal's name.
pub fn on_signal(f: impl FnOnce() -> Option<String> + Send + 'static) {
    if let Ok(mut slot) = ON_SIGNAL.lock() {
        *slot = Some(Box::new(f));
    }
}

#[cfg(unix)]
pub fn remove_temporary_files_on_signal() -> Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])
        .map_err(|e| anyhow::anyhow!("cannot install the signal handler: {e}"))?;
    std::thread::Builder::new()
        .name("hxai-signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                STOPPING.store(true, std::sync::atomic::Ordering::SeqCst);
                let kept = ON_SIGNAL
                    .lock()
                    .ok()
                    .and_then(|mut slot| slot.take())
                    .and_then(|f| f());
                // The registry stays locked until the process has exited, so no other thread
                // renames or creates a file after this point.
                let (n, _held) = hxai_data::remove_temporary_files();
                let name = match signal {
                    SIGINT => "interrupted (SIGINT)",
                    SIGTERM => "terminated (SIGTERM)",
                    _ => "hung up (SIGHUP)",
                };
                #[allow(clippy::print_stderr)]
                {
                    let kept = kept.map(|k| format!("; {k}")).unwrap_or_default();
                    if n > 0 {
                        let files = if n == 1 { "file" } else { "files" };
                        eprintln!(
                            "error: {name}{kept}; removed {n} unfinished output {files}; existing files are unchanged"
                        );
                    } else {
                        eprintln!("error: {name}{kept}");
                    }
                }
                std::process::exit(128 + signal);
            }
        })
        .map_err(|e| anyhow::anyhow!("cannot start the signal handler: {e}"))?;
    Ok(())
}

/// Refuses `output` when it is one of `inputs` (each with its role for the message) or a
/// folder. Call it before any work, so nothing is computed for a command that cannot write.
pub fn check_output(output: &Path, inputs: &[(PathBuf, String)]) -> Result<()> {
    hxai_data::check_output(output, inputs)?;
    Ok(())
}

/// Refuses an interval level outside (0, 1), naming the flag, before any work.
pub fn check_level(level: f64, flag: &str) -> Result<()> {
    anyhow::ensure!(
        level > 0.0 && level < 1.0,
        "{flag} must lie strictly between 0 and 1 (a probability such as 0.95), got {}",
        hxai_data::format_number(level)
    );
    Ok(())
}

/// An input with its role, for [`check_output`].
pub fn input(path: &Path, role: &str) -> (PathBuf, String) {
    (path.to_path_buf(), role.to_owned())
}

/// The checks of a `predict` command before any work: the table `out` is neither the table
/// `data` nor the model `model` and has a known extension, and `interval` (`--interval`)
/// lies in (0, 1).
pub fn check_predict(out: &Path, data: &Path, model: &Path, interval: Option<f64>) -> Result<()> {
    check_output(
        out,
        &[
            input(data, "the table (--data)"),
            input(model, "the model (--model)"),
        ],
    )?;
    check_table_path(out)?;
    if let Some(level) = interval {
        check_level(level, "--interval")?;
    }
    Ok(())
}

/// Checks that a table output path has a known extension, before any work.
pub fn check_table_path(path: &Path) -> Result<()> {
    hxai_data::Format::from_path(path)?;
    Ok(())
}

/// Refuses an output folder that exists and is not empty (unless `force`), or that is a
/// file: writing a data folder there would replace some recordings and the manifest and
/// orphan the rest.
pub fn check_empty_folder(dir: &Path, force: bool) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        anyhow::bail!("{}: is a file, not a folder", dir.display());
    }
    if force || !dir.is_dir() {
        return Ok(());
    }
    let mut entries = std::fs::read_dir(dir)
        .map_err(|e| anyhow::anyhow!("cannot list {}: {e}", dir.display()))?;
    if entries.next().is_some() {
        anyhow::bail!(
            "{}: the folder is not empty; choose a new folder, or pass --force to write into it",
            dir.display()
        );
    }
    Ok(())
}

/// A path for JSON output and messages: lossy for names that are not UTF-8, never a panic.
pub fn path_text(path: &Path) -> String {
    path.display().to_string()
}

/// Prints `text` and a newline on stdout. A closed stdout (`hxai features ... | head -1`)
/// ends the process normally with exit code 0: the reader has what it wanted.
pub fn emit(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{text}").and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => Err(anyhow::anyhow!("cannot write to standard output: {e}")),
    }
}

/// Prints a `--json` document on stdout before the command's outputs are renamed into
/// place: a standard output that cannot be written is an error (and the staged outputs are
/// then dropped, every existing file as it was); a closed pipe (`| head`) is not, as the
/// reader has what it wanted and the outputs are still wanted.
pub fn print_document(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{text}").and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(anyhow::anyhow!("cannot write to standard output: {e}")),
    }
}

/// Prints warnings on stderr, one line each.
pub fn warn<S: std::fmt::Display>(warnings: &[S]) {
    for w in warnings {
        #[allow(clippy::print_stderr)]
        {
            eprintln!("warning: {w}");
        }
    }
}

/// Says on stderr which cells `--missing-codes` emptied in the files read since the last
/// call (each note once).
pub fn note_missing_codes() {
    warn(&hxai_data::take_missing_code_notes());
}

/// Installs a panic hook for the one panic that is not a bug: `println!` failing to write
/// stdout. A closed stdout (the reader went away: `| head -1`) ends the process normally
/// with exit code 0; any other failure (a full disk under `> out.json`, `> /dev/full`) is
/// the usual one-line error and exit code 1, after removing unfinished temporary outputs,
/// instead of a panic's report and exit code 101. Every other panic keeps the default
/// report.
pub fn exit_quietly_on_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let msg = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        if let Some(reason) = msg.strip_prefix("failed printing to stdout: ") {
            if reason.contains("Broken pipe") {
                std::process::exit(0);
            }
            let (_, _held) = hxai_data::remove_temporary_files();
            #[allow(clippy::print_stderr)]
            {
                eprintln!("error: cannot write to standard output: {reason}");
            }
            std::process::exit(1);
        }
        default(info);
    }));
}

/// `message` with each setting named as the user typed it: a library names a setting by
/// its field (`max_complexity`, `duration_s`, `test_fraction`), the command line by its
/// option (`--max-complexity`). A snake_case word that is one of `flags` (the running
/// command's long options) with `_` for `-` becomes the option, unless it names a column or
/// a key of a file (preceded by "column `" or "key `", or in the list of keys after
/// "expected one of"), where the field name is right.
pub fn flag_names(message: &str, flags: &[String]) -> String {
    let mut out = String::with_capacity(message.len());
    let mut word = String::new();
    let flush = |out: &mut String, word: &mut String| {
        let as_flag = word.replace('_', "-");
        // a column, a key of a file, or the keys a file may hold keep their names
        let quoted_name =
            out.ends_with("column `") || out.ends_with("key `") || out.contains("expected one of ");
        if word.contains('_') && !quoted_name && flags.contains(&as_flag) {
            let dashes = if out.ends_with('-') { "" } else { "--" };
            out.push_str(dashes);
            out.push_str(&as_flag);
        } else {
            out.push_str(word);
        }
        word.clear();
    };
    for ch in message.chars() {
        if ch.is_ascii_alphanumeric() || ch == '_' {
            word.push(ch);
        } else {
            flush(&mut out, &mut word);
            out.push(ch);
        }
    }
    flush(&mut out, &mut word);
    out
}

/// One line for an error and its causes: each cause is added only when it says something
/// the line does not already say, and a cause that repeats the end of the line (the same
/// path) is added without that repetition. So `reading r.csv` + `r.csv: missing column`
/// gives `reading r.csv: missing column`, not `reading r.csv: r.csv: missing column`.
pub fn one_line(e: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        let text = text.trim();
        if text.is_empty() || line.contains(text) {
            continue;
        }
        if line.is_empty() {
            line = text.to_owned();
            continue;
        }
        // Longest prefix of the cause (ending before ": ") that the line ends with.
        let mut rest = text;
        let mut from = 0;
        while let Some(i) = text[from..].find(": ") {
            let head = &text[..from + i];
            if line.ends_with(head) || line.contains(&format!("{head}:")) {
                rest = &text[from + i + 2..];
            }
            from += i + 2;
        }
        if !line.contains(rest) {
            line.push_str(": ");
            line.push_str(rest);
        }
    }
    line.replace('\n', " ")
}

#[cfg(test)]
mod flag_tests {
    use super::flag_names;

    #[test]
    fn settings_are_named_by_their_options() {
        let flags: Vec<String> = ["max-complexity", "duration-s", "frequency-hz", "seed"]
            .iter()
            .map(|s| (*s).to_string())
            .collect();
        assert_eq!(
            flag_names("invalid configuration: max_complexity is 0", &flags),
            "invalid configuration: --max-complexity is 0"
        );
        assert_eq!(
            flag_names(
                "invalid simulator parameter `duration_s` = 0: lower `duration_s`",
                &flags
            ),
            "invalid simulator parameter `--duration-s` = 0: lower `--duration-s`"
        );
        // columns and file keys keep their names; unknown words and already-dashed ones stay
        assert_eq!(
            flag_names(
                "row 3, column `frequency_hz`: the key `duration_s` is missing",
                &flags
            ),
            "row 3, column `frequency_hz`: the key `duration_s` is missing"
        );
        assert_eq!(
            flag_names("feed_mm and --max-complexity", &flags),
            "feed_mm and --max-complexity"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeated_paths_are_said_once() {
        let inner = anyhow::anyhow!("r.csv: missing column `time_s`");
        let e = inner.context("reading record r.csv");
        assert_eq!(
            one_line(&e),
            "reading record r.csv: missing column `time_s`"
        );
        let e = anyhow::anyhow!("x: y").context("x: y").context("x: y");
        assert_eq!(one_line(&e), "x: y");
        let e = anyhow::anyhow!("disk full").context("cannot write m.json");
        assert_eq!(one_line(&e), "cannot write m.json: disk full");
    }
}
