//! Samples of an accelerometer stream read line by line from CSV text (`hxai stream`): a
//! source that may never end, read incrementally, each bad line named by its number.
//!
//! The header names the columns (at least `time_s` and `accel_ms2`, in any order, others
//! ignored; quoted names per RFC 4180 and a UTF-8 byte-order mark are accepted). Every other
//! non-blank line is one sample. [`SampleReader::ready`] says whether a whole line is already
//! buffered, so a caller can flush its output before a read that would wait for the source.

use crate::DataError;
use std::io::{BufRead, BufReader, Read};

/// One sample of the stream.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// The line it was read from (1-based; the header is line 1).
    pub line: usize,
    /// `time_s`, s.
    pub time_s: f64,
    /// `accel_ms2`, m/s^2.
    pub accel_ms2: f64,
}

/// Reads [`Sample`]s from CSV text.
#[derive(Debug)]
pub struct SampleReader<R> {
    reader: BufReader<R>,
    source: String,
    line: usize,
    time: usize,
    accel: usize,
    text: String,
}

/// Input buffer size: large enough that a file is read in few system calls, and output is
/// flushed at most once per this much input when the source is faster than the estimator.
const BUFFER_BYTES: usize = 1 << 16;

/// Longest line accepted, bytes: a stream without line ends must not fill the memory.
pub const MAX_LINE_BYTES: usize = 1 << 20;

fn unquote(cell: &str) -> String {
    let t = cell.trim();
    match t.strip_prefix('"').and_then(|t| t.strip_suffix('"')) {
        Some(inner) => inner.replace("\"\"", "\""),
        None => t.to_owned(),
    }
}

impl<R: Read> SampleReader<R> {
    /// Reads the header from `reader`; `source` names it in errors (a path, or `standard
    /// input`).
    ///
    /// # Errors
    /// [`DataError::StreamLine`] for an empty stream or a header without `time_s` or
    /// `accel_ms2`, [`DataError::Io`] when reading fails.
    pub fn new(reader: R, source: &str) -> Result<Self, DataError> {
        let mut me = Self {
            reader: BufReader::with_capacity(BUFFER_BYTES, reader),
            source: source.to_owned(),
            line: 0,
            time: 0,
            accel: 0,
            text: String::new(),
        };
        if !me.read_line()? {
            return Err(me.error(
                1,
                "the stream is empty; it must start with a header naming `time_s` and `accel_ms2`"
                    .into(),
            ));
        }
        let header = me.text.trim_start_matches('\u{feff}');
        let names: Vec<String> = header.split(',').map(unquote).collect();
        let find = |name: &str| names.iter().position(|n| n == name);
        match (find("time_s"), find("accel_ms2")) {
            (Some(t), Some(a)) => {
                me.time = t;
                me.accel = a;
                Ok(me)
            }
            (t, _) => {
                let missing = if t.is_none() { "time_s" } else { "accel_ms2" };
                Err(me.error(
                    1,
                    format!(
                        "the header has no column `{missing}` (columns found: {}); the first line must name the columns, at least `time_s` and `accel_ms2`",
                        names.join(", ")
                    ),
                ))
            }
        }
    }

    fn error(&self, line: usize, message: String) -> DataError {
        DataError::StreamLine {
            source_name: self.source.clone(),
            line,
            message,
        }
    }

    /// Reads the next line into `self.text`, without its line end; false at the end.
    fn read_line(&mut self) -> Result<bool, DataError> {
        self.text.clear();
        let mut bytes = Vec::new();
        let n = (&mut self.reader)
            .take(MAX_LINE_BYTES as u64 + 1)
            .read_until(b'\n', &mut bytes)
            .map_err(|e| DataError::io(std::path::Path::new(&self.source), e))?;
        if n == 0 {
            return Ok(false);
        }
        self.line += 1;
        if n > MAX_LINE_BYTES {
            return Err(self.error(
                self.line,
                format!(
                    "the line is longer than {MAX_LINE_BYTES} bytes; is this CSV with line ends?"
                ),
            ));
        }
        match String::from_utf8(bytes) {
            Ok(s) => self.text = s,
            Err(_) => {
                return Err(self.error(self.line, "the line is not UTF-8 text".into()));
            }
        }
        let trimmed = self.text.trim_end_matches(['\n', '\r']).len();
        self.text.truncate(trimmed);
        Ok(true)
    }

    /// True when a whole line is buffered, so that [`SampleReader::next_sample`] returns
    /// without waiting for the source.
    pub fn ready(&self) -> bool {
        self.reader.buffer().contains(&b'\n')
    }

    /// The next sample, or `None` at the end of the stream. Blank lines are skipped.
    ///
    /// # Errors
    /// [`DataError::StreamLine`] naming the line for a missing cell or a cell that is not a
    /// finite number; [`DataError::Io`] when reading fails.
    pub fn next_sample(&mut self) -> Result<Option<Sample>, DataError> {
        loop {
            if !self.read_line()? {
                return Ok(None);
            }
            if self.text.trim().is_empty() {
                continue;
            }
            let mut time = None;
            let mut accel = None;
            for (k, cell) in self.text.split(',').enumerate() {
                if k == self.time {
                    time = Some(cell);
                }
                if k == self.accel {
                    accel = Some(cell);
                }
            }
            let parse = |name: &str, cell: Option<&str>| -> Result<f64, DataError> {
                let Some(cell) = cell else {
                    return Err(self.error(
                        self.line,
                        format!("no `{name}` cell (the line has fewer cells than the header)"),
                    ));
                };
                let text = unquote(cell);
                match text.parse::<f64>() {
                    Ok(v) if v.is_finite() => Ok(v),
                    _ => Err(self.error(
                        self.line,
                        format!(
                            "`{name}` is `{}`, not a finite number",
                            text.chars().take(40).collect::<String>()
                        ),
                    )),
                }
            };
            let time_s = parse("time_s", time)?;
            let accel_ms2 = parse("accel_ms2", accel)?;
            return Ok(Some(Sample {
                line: self.line,
                time_s,
                accel_ms2,
            }));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_all(text: &str) -> (Vec<Sample>, Option<String>) {
        let mut out = Vec::new();
        let mut r = match SampleReader::new(text.as_bytes(), "test") {
            Ok(r) => r,
            Err(e) => return (out, Some(e.to_string())),
        };
        loop {
            match r.next_sample() {
                Ok(Some(s)) => out.push(s),
                Ok(None) => return (out, None),
                Err(e) => return (out, Some(e.to_string())),
            }
        }
    }

    #[test]
    fn reads_columns_in_any_order_and_skips_blank_lines() {
        let (s, err) =
            read_all("\u{feff}probe_um,\"accel_ms2\",time_s\r\n1,0.5,0.0\r\n\n2,-0.25,1e-4\n");
        assert!(err.is_none(), "{err:?}");
        assert_eq!(s.len(), 2);
        assert_eq!((s[0].line, s[0].time_s, s[0].accel_ms2), (2, 0.0, 0.5));
        assert_eq!((s[1].line, s[1].time_s, s[1].accel_ms2), (4, 1e-4, -0.25));
    }

    /// Each bad line is named by its number (header = line 1), after the good ones.
    #[test]
    fn bad_lines_are_named() {
        for (text, want) in [
            ("", "test, line 1: the stream is empty"),
            (
                "time,accel_ms2\n",
                "test, line 1: the header has no column `time_s`",
            ),
            ("time_s,accel\n", "no column `accel_ms2`"),
            (
                "time_s,accel_ms2\n0,1\n0.1,x\n",
                "test, line 3: `accel_ms2` is `x`, not a finite number",
            ),
            (
                "time_s,accel_ms2\n0,1\n0.1\n",
                "test, line 3: no `accel_ms2` cell",
            ),
            (
                "time_s,accel_ms2\n0,nan\n",
                "test, line 2: `accel_ms2` is `nan`",
            ),
            ("time_s,accel_ms2\n0,inf\n", "not a finite number"),
        ] {
            let (_, err) = read_all(text);
            let err = err.unwrap_or_default();
            assert!(err.contains(want), "{text:?}: {err}");
        }
        let (good, _) = read_all("time_s,accel_ms2\n0,1\n0.1,2\n0.2,\n");
        assert_eq!(good.len(), 2);
    }

    #[test]
    fn ready_says_whether_a_whole_line_is_buffered() {
        let mut r =
            SampleReader::new("time_s,accel_ms2\n0,1\n0.1,2".as_bytes(), "t").expect("header");
        // The first read filled the buffer with everything: one whole line, then a partial one.
        assert!(r.ready());
        assert!(r.next_sample().expect("line 2").is_some());
        assert!(!r.ready());
        assert!(r.next_sample().expect("line 3").is_some());
        assert!(r.next_sample().expect("end").is_none());
    }
}
