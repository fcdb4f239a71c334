//! Progress on long work, wherever stderr goes. On a terminal, indicatif's bar redraws in
//! place. Elsewhere (a log file, a pipe, a Jupyter cell running `!hxai ...`, CI) indicatif
//! would draw nothing and a long command would look hung; there the same bar is written as
//! a plain line now and then: the first after [`FIRST_LINE`], then one per [`EVERY`], so a
//! command of a few seconds prints none and an hour-long one a few hundred.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle, TermLike};
use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Quiet time before the first plain progress line.
const FIRST_LINE: Duration = Duration::from_secs(5);

/// Time between plain progress lines.
const EVERY: Duration = Duration::from_secs(15);

/// A progress bar of `len` steps drawn on stderr: in place on a terminal, as occasional
/// plain lines otherwise. It redraws every second even when no step ends (a forest or a
/// calibration between two searches), so its elapsed time moves and a log gets its lines.
pub fn bar(len: u64) -> ProgressBar {
    let b = ProgressBar::with_draw_target(Some(len), target());
    b.enable_steady_tick(Duration::from_secs(1));
    b
}

/// [`bar`] with indicatif's `template`. Under `--json` too: the document goes to stdout,
/// progress to stderr, and a notebook running `!hxai ... --json` is as long as any other.
pub fn styled(len: u64, template: &str) -> ProgressBar {
    let b = bar(len);
    b.set_style(
        ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    b
}

/// Where bars draw: stderr when it is a terminal, else [`PlainLines`].
fn target() -> ProgressDrawTarget {
    if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::term_like_with_hz(Box::new(PlainLines::new()), 1)
    }
}

/// A stand-in terminal that keeps the last drawn bar and writes it to stderr as one line,
/// at most once per [`EVERY`] (and not before [`FIRST_LINE`]); cursor moves and clears,
/// meaningless in a log, are ignored.
#[derive(Debug)]
struct PlainLines {
    state: Mutex<Lines>,
}

#[derive(Debug)]
struct Lines {
    /// The text drawn since the last flush.
    current: String,
    /// When the next line may be written.
    next: Instant,
}

impl PlainLines {
    fn new() -> Self {
        Self {
            state: Mutex::new(Lines {
                current: String::new(),
                next: Instant::now() + FIRST_LINE,
            }),
        }
    }

    fn push(&self, s: &str) {
        let s = s.trim();
        if let (false, Ok(mut st)) = (s.is_empty(), self.state.lock()) {
            if !st.current.is_empty() {
                st.current.push(' ');
            }
            st.current.push_str(s);
        }
    }
}

impl TermLike for PlainLines {
    fn width(&self) -> u16 {
        100
    }

    fn move_cursor_up(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }

    fn move_cursor_down(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }

    fn move_cursor_right(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }

    fn move_cursor_left(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }

    fn write_line(&self, s: &str) -> std::io::Result<()> {
        self.push(s);
        Ok(())
    }

    fn write_str(&self, s: &str) -> std::io::Result<()> {
        self.push(s);
        Ok(())
    }

    fn clear_line(&self) -> std::io::Result<()> {
        Ok(())
    }

    fn flush(&self) -> std::io::Result<()> {
        let Ok(mut st) = self.state.lock() else {
            return Ok(());
        };
        let line = std::mem::take(&mut st.current);
        let now = Instant::now();
        if line.is_empty() || now < st.next {
            return Ok(());
        }
        st.next = now + EVERY;
        // A closed or full stderr must not stop the work: progress is best effort.
        let _ = writeln!(std::io::stderr().lock(), "progress: {line}");
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_wait_for_the_first_interval_and_keep_the_last_drawing() {
        let t = PlainLines::new();
        t.write_str("1/10 a").ok();
        t.flush().ok();
        // Not yet due: nothing is kept for later either (the next draw replaces it).
        let st = t
            .state
            .lock()
            .map(|s| s.current.clone())
            .unwrap_or_default();
        assert!(st.is_empty());
        if let Ok(mut st) = t.state.lock() {
            st.next = Instant::now();
        }
        t.write_line("2/10").ok();
        t.write_str("b").ok();
        assert_eq!(
            t.state
                .lock()
                .map(|s| s.current.clone())
                .unwrap_or_default(),
            "2/10 b"
        );
        t.flush().ok();
        let next = t
            .state
            .lock()
            .map(|s| s.next)
            .unwrap_or_else(|_| Instant::now());
        assert!(next > Instant::now() + EVERY - Duration::from_secs(1));
    }
}
