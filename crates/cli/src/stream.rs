//! `hxai stream`: the tool position sample by sample, from a CSV stream of acceleration
//! (a file, or standard input that may never end) to one CSV row per sample.
//!
//! The computation is `hxai_hybrid::records::stream::Estimator`; this module reads lines, detects gaps
//! in time, writes rows and flushes them whenever the input has no whole line ready, so a
//! reader of the output sees each row as soon as its sample is read.
use crate::Global;
use anyhow::{Context, Result};
use hxai_data::{AtomicFile, SampleReader, UNIFORM_TIME_TOLERANCE, format_number};
use hxai_hybrid::records::stream::{COLUMNS, Estimator, INTERVAL_COLUMNS, Row, Summary};
use std::io::{BufWriter, Read, Write};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// Arguments of `hxai stream`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Model written by `hxai fit`.
    #[arg(long)]
    pub model: PathBuf,
    /// Commanded frequency of the motion, Hz.
    #[arg(long)]
    pub frequency_hz: f64,
    /// CSV input with a header naming at least `time_s` and `accel_ms2` (default: standard
    /// input, read as it arrives).
    #[arg(long = "in")]
    pub input: Option<PathBuf>,
    /// CSV output (default: standard output, flushed whenever the input has no more data
    /// ready). A file is written through a temporary file renamed into place at the end of
    /// the input, or at the first bad line with every row before it.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Sampling rate, Hz (default: from the first two time stamps).
    #[arg(long)]
    pub fs_hz: Option<f64>,
    /// Add bounds of the hybrid displacement at this level (e.g. 0.95): columns
    /// hybrid_lo_um, hybrid_hi_um.
    #[arg(long)]
    pub interval: Option<f64>,
    /// Write a JSON summary here at the end: delay, warm-up, counts, restarts.
    #[arg(long)]
    pub summary: Option<PathBuf>,
}

/// The output file of a stream, shared with the signal handler: Ctrl-C or SIGTERM is how a
/// live stream usually ends, so the handler keeps the rows written so far (flushes and
/// renames the file into place, as at the end of the input) instead of discarding them.
/// Rows are written under the lock one whole row at a time, so the file never ends inside a
/// row. Once committed it holds the path (`Err`), so whichever of the handler and the end of
/// the run comes second knows the rows are kept.
type SharedFile = Arc<Mutex<std::result::Result<BufWriter<AtomicFile>, String>>>;

/// Where rows go.
enum Sink {
    Stdout(BufWriter<std::io::StdoutLock<'static>>),
    File(SharedFile),
}

/// Flushes and renames the stream's file into place, once (the signal handler or the end of
/// the run, whichever comes first, the other waiting on the lock); the path of the file.
fn commit_shared(file: &SharedFile) -> Result<String> {
    let mut guard = file
        .lock()
        .map_err(|_| anyhow::anyhow!("the output file is unusable"))?;
    let w = match std::mem::replace(&mut *guard, Err(String::new())) {
        Ok(w) => w,
        Err(path) => {
            *guard = Err(path.clone());
            return Ok(path);
        }
    };
    let file = w
        .into_inner()
        .map_err(|e| anyhow::anyhow!("cannot write the output: {}", e.error()))?;
    let path = file.path().display().to_string();
    file.commit()
        .with_context(|| format!("cannot write {path}"))?;
    *guard = Err(path.clone());
    Ok(path)
}

impl Sink {
    /// Runs `f` on the writer; for a file, under its lock.
    fn with<T>(&mut self, f: impl FnOnce(&mut dyn Write) -> Result<T>) -> Result<T> {
        match self {
            Sink::Stdout(w) => f(w),
            Sink::File(shared) => {
                let mut guard = shared
                    .lock()
                    .map_err(|_| anyhow::anyhow!("the output file is unusable"))?;
                match guard.as_mut() {
                    Ok(w) => f(w),
                    Err(_) => anyhow::bail!("the stream was stopped"),
                }
            }
        }
    }

    /// Flushes; a closed standard output ends the run quietly (the reader has gone).
    fn flush(&mut self) -> Result<()> {
        match self.with(|w| Ok(w.flush())) {
            Ok(Ok(())) => Ok(()),
            Ok(Err(e)) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
            Ok(Err(e)) => Err(anyhow::anyhow!("cannot write the output: {e}")),
            Err(e) => Err(e),
        }
    }

    /// Flushes and, for a file, renames it into place.
    fn finish(self) -> Result<()> {
        match self {
            Sink::Stdout(mut w) => match w.flush() {
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
                r => r.context("cannot write to standard output"),
            },
            Sink::File(shared) => commit_shared(&shared).map(|_| ()),
        }
    }
}

/// The state of one run: the estimator (once the sampling rate is known) and the counts.
struct Run {
    args_fs: Option<f64>,
    frequency_hz: f64,
    interval: Option<f64>,
    model: hxai_hybrid::records::RecordModel,
    estimator: Option<Estimator>,
    /// The first sample, held until the second gives the sampling rate.
    first: Option<hxai_data::Sample>,
    previous_time: Option<f64>,
    samples: u64,
    restarts: u64,
    rows: Vec<Row>,
    line: String,
}

impl Run {
    fn build(&self, fs: f64) -> Result<Estimator> {
        let est = Estimator::new(&self.model, self.frequency_hz, fs).with_context(|| {
            format!(
                "cannot stream at {} Hz sampling with this model",
                format_number(fs)
            )
        })?;
        let est = match self.interval {
            Some(level) => est.with_interval(level)?,
            None => est,
        };
        crate::safety::warn(
            &hxai_hybrid::records::record_warnings("the stream", fs, self.frequency_hz, usize::MAX)
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>(),
        );
        Ok(est)
    }

    /// Takes one sample: builds the estimator when the rate becomes known, restarts it on a
    /// gap, and writes the rows the sample completes.
    fn take(&mut self, s: hxai_data::Sample, out: &mut dyn Write) -> Result<()> {
        if self.estimator.is_none() {
            let fs = match (self.args_fs, self.first) {
                (Some(fs), _) => fs,
                (None, None) => {
                    self.first = Some(s);
                    return Ok(());
                }
                (None, Some(first)) => {
                    let step = s.time_s - first.time_s;
                    anyhow::ensure!(
                        step > 0.0,
                        "line {}: time_s {} does not increase from line {} ({}); the sampling \
                         rate is read from the first two time stamps (or give --fs-hz)",
                        s.line,
                        format_number(s.time_s),
                        first.line,
                        format_number(first.time_s)
                    );
                    1.0 / step
                }
            };
            self.estimator = Some(self.build(fs)?);
            if let Some(first) = self.first.take() {
                self.one(first, out)?;
            }
        }
        self.one(s, out)
    }

    fn one(&mut self, s: hxai_data::Sample, out: &mut dyn Write) -> Result<()> {
        let Some(est) = self.estimator.as_mut() else {
            return Ok(());
        };
        if let Some(prev) = self.previous_time {
            let expected = 1.0 / est.fs_hz();
            let step = s.time_s - prev;
            if (step - expected).abs() > UNIFORM_TIME_TOLERANCE * expected {
                crate::safety::warn(&[format!(
                    "gap at t = {} s (line {}): the time step from {} s is {} s, not the sampling \
                     step {} s; the estimator restarts, rows resume after {} samples of warm-up",
                    format_number(s.time_s),
                    s.line,
                    format_number(prev),
                    format_number(step),
                    format_number(expected),
                    est.warmup_samples()
                )]);
                est.restart();
                self.restarts += 1;
            }
        }
        self.previous_time = Some(s.time_s);
        self.rows.clear();
        est.push_into(&[s.accel_ms2], &mut self.rows)
            .with_context(|| format!("line {}", s.line))?;
        for r in &self.rows {
            self.line.clear();
            write_row(&mut self.line, s.time_s, r, self.interval.is_some());
            out.write_all(self.line.as_bytes())
                .context("cannot write the output")?;
        }
        self.samples += 1;
        Ok(())
    }

    /// At the end of the input: a sample still held for the sampling rate (a stream of one
    /// sample) gets its row too, without values, so every input sample has one.
    fn finish(&mut self, out: &mut dyn Write) -> Result<()> {
        if let Some(first) = self.first.take() {
            let row = Row {
                sample: 0,
                time_s: 0.0,
                physics_um: None,
                hybrid_um: None,
                interval_um: None,
            };
            self.line.clear();
            write_row(&mut self.line, first.time_s, &row, self.interval.is_some());
            out.write_all(self.line.as_bytes())
                .context("cannot write the output")?;
            self.samples += 1;
        }
        Ok(())
    }

    fn summary(&self, seconds: f64) -> Summary {
        match &self.estimator {
            Some(est) => est.summary(self.samples, seconds, self.restarts),
            None => Summary {
                delay_samples: 0,
                warmup_samples: 0,
                samples: self.samples,
                seconds,
                restarts: self.restarts,
                frequency_hz: self.frequency_hz,
                fs_hz: None,
                window_samples: 0,
                update_step_samples: 0,
                undefined_reports: 0,
            },
        }
    }
}

/// One CSV row: the input's time, then the values (empty during the warm-up).
fn write_row(line: &mut String, time_s: f64, r: &Row, interval: bool) {
    use std::fmt::Write as _;
    let cell = |line: &mut String, v: Option<f64>| {
        line.push(',');
        if let Some(v) = v {
            let _ = write!(line, "{v}");
        }
    };
    let _ = write!(line, "{time_s}");
    cell(line, r.physics_um);
    cell(line, r.hybrid_um);
    if interval {
        cell(line, r.interval_um.map(|b| b.0));
        cell(line, r.interval_um.map(|b| b.1));
    }
    line.push('\n');
}

/// Runs `hxai stream`.
pub fn run(args: Args, _g: &Global) -> Result<()> {
    anyhow::ensure!(
        args.frequency_hz.is_finite() && args.frequency_hz > 0.0,
        "--frequency-hz must be a positive number of Hz, got {}",
        format_number(args.frequency_hz)
    );
    if let Some(fs) = args.fs_hz {
        anyhow::ensure!(
            fs.is_finite() && fs > 0.0,
            "--fs-hz must be a positive number of Hz, got {}",
            format_number(fs)
        );
    }
    if let Some(level) = args.interval {
        crate::safety::check_level(level, "--interval")?;
    }
    let mut inputs = vec![crate::safety::input(&args.model, "the model (--model)")];
    if let Some(i) = &args.input {
        inputs.push(crate::safety::input(i, "the input (--in)"));
    }
    if let Some(o) = &args.out {
        crate::safety::check_output(o, &inputs)?;
    }
    if let Some(s) = &args.summary {
        let mut all = inputs.clone();
        if let Some(o) = &args.out {
            all.push(crate::safety::input(o, "the output (--out)"));
        }
        crate::safety::check_output(s, &all)?;
    }
    let model = crate::predict::load_model(&args.model)?;
    // The settings are checked before any input is read: a model or frequency that cannot
    // stream fails at once, not after the first two samples.
    if let Some(fs) = args.fs_hz {
        Estimator::new(&model, args.frequency_hz, fs).context("cannot stream with this model")?;
    } else {
        hxai_hybrid::records::stream::check_frequency(&model, args.frequency_hz)
            .context("cannot stream with this model")?;
    }
    let (reader, source): (Box<dyn Read>, String) = match &args.input {
        Some(p) => (
            Box::new(
                std::fs::File::open(p).with_context(|| format!("cannot open {}", p.display()))?,
            ),
            p.display().to_string(),
        ),
        None => (Box::new(std::io::stdin()), "standard input".into()),
    };
    let mut sink = match &args.out {
        Some(p) => {
            let file: SharedFile = Arc::new(Mutex::new(Ok(BufWriter::with_capacity(
                1 << 16,
                AtomicFile::create(p).with_context(|| format!("cannot write {}", p.display()))?,
            ))));
            let on_signal = Arc::clone(&file);
            crate::safety::on_signal(move || match commit_shared(&on_signal) {
                Ok(path) => Some(format!("the rows so far are in {path}")),
                Err(e) => Some(format!("the rows so far could not be kept: {e:#}")),
            });
            Sink::File(file)
        }
        None => Sink::Stdout(BufWriter::with_capacity(1 << 16, std::io::stdout().lock())),
    };
    let mut header: Vec<&str> = COLUMNS.to_vec();
    if args.interval.is_some() {
        header.extend(INTERVAL_COLUMNS);
    }
    sink.with(|w| writeln!(w, "{}", header.join(",")).context("cannot write the output"))?;
    let start = Instant::now();
    let mut run = Run {
        args_fs: args.fs_hz,
        frequency_hz: args.frequency_hz,
        interval: args.interval,
        model,
        estimator: None,
        first: None,
        previous_time: None,
        samples: 0,
        restarts: 0,
        rows: Vec::with_capacity(1),
        line: String::with_capacity(128),
    };
    let result = (|| -> Result<()> {
        let mut reader = SampleReader::new(reader, &source)?;
        loop {
            if !reader.ready() {
                sink.flush()?;
            }
            match reader.next_sample()? {
                Some(s) => sink.with(|w| run.take(s, w))?,
                None => return sink.with(|w| run.finish(w)),
            }
        }
    })();
    // Every row before a bad line is kept: the output is finished either way.
    sink.finish()?;
    if let Some(path) = &args.summary {
        let summary = run.summary(start.elapsed().as_secs_f64());
        let text = serde_json::to_string_pretty(&summary).context("cannot format the summary")?;
        hxai_data::write_text(path, &(text + "\n"))
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    result
}
