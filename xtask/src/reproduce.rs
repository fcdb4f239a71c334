//! `cargo xtask reproduce`: runs `hxai_reproduce::run`, shows progress, writes or checks
//! `docs/results/`.

use anyhow::{Context, Result, bail};
use hxai_reproduce::{Progress, ReproduceConfig};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::time::Instant;

struct Options {
    quick: bool,
    check: bool,
    out: Option<PathBuf>,
}

fn parse(args: &[String]) -> Result<Options> {
    let mut o = Options {
        quick: false,
        check: false,
        out: None,
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--quick" => o.quick = true,
            "--check" => o.check = true,
            "--out" => {
                let dir = it.next().context("--out needs a folder")?;
                o.out = Some(PathBuf::from(dir));
            }
            other => bail!("unknown option `{other}` (see `cargo xtask --help`)"),
        }
    }
    Ok(o)
}

pub fn run(args: &[String]) -> Result<()> {
    let o = parse(args)?;
    let cfg = if o.quick {
        ReproduceConfig::quick()
    } else {
        ReproduceConfig::default()
    };
    let dir = o.out.clone().unwrap_or_else(|| {
        if o.quick {
            crate::root().join("target").join("reproduce-quick")
        } else {
            crate::root().join("docs").join("results")
        }
    });

    let started = Instant::now();
    let bar = ProgressBar::new(1);
    bar.set_style(
        ProgressStyle::with_template("{spinner} {prefix:>16} [{bar:30}] {pos}/{len} {msg}")
            .map_err(|e| anyhow::anyhow!("progress bar template: {e}"))?
            .progress_chars("=> "),
    );
    let mut stage = "";
    let out = hxai_reproduce::run(&cfg, &mut |p: Progress| {
        if p.stage != stage {
            if !stage.is_empty() {
                bar.println(format!("  done: {stage}"));
            }
            stage = p.stage;
            bar.set_prefix(p.stage);
        }
        bar.set_length(p.total.max(1));
        bar.set_position(p.done);
        bar.set_message(p.message.clone());
    })?;
    bar.finish_and_clear();

    if o.check {
        let mut stale = Vec::new();
        for (name, content) in &out.files {
            let path = dir.join(name);
            match std::fs::read_to_string(&path) {
                Ok(old) if old == *content => {}
                Ok(old) => {
                    let line = old
                        .lines()
                        .zip(content.lines())
                        .position(|(a, b)| a != b)
                        .unwrap_or_else(|| old.lines().count().min(content.lines().count()));
                    stale.push(format!(
                        "{} (first difference at line {})",
                        path.display(),
                        line + 1
                    ));
                }
                Err(_) => stale.push(format!("{} (missing)", path.display())),
            }
        }
        if !stale.is_empty() {
            bail!(
                "the committed results are stale; run `cargo xtask reproduce{}` and commit:\n  {}",
                if o.quick { " --quick" } else { "" },
                stale.join("\n  ")
            );
        }
        println!(
            "{}: {} files match a fresh run",
            dir.display(),
            out.files.len()
        );
    } else {
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", dir.display()))?;
        for (name, content) in &out.files {
            write_atomic(&dir.join(name), content)?;
        }
        println!("wrote {} files to {}", out.files.len(), dir.display());
    }

    summary(&out, started.elapsed().as_secs_f64());
    Ok(())
}

/// Writes `content` to a temporary file next to `path`, then renames it over `path`, so an
/// interrupted run never leaves a half-written result file.
fn write_atomic(path: &Path, content: &str) -> Result<()> {
    let name = path
        .file_name()
        .with_context(|| format!("{} has no file name", path.display()))?;
    let tmp = path.with_file_name(format!(".{}.tmp", name.to_string_lossy()));
    std::fs::write(&tmp, content).with_context(|| format!("cannot write {}", tmp.display()))?;
    std::fs::rename(&tmp, path)
        .with_context(|| format!("cannot rename {} to {}", tmp.display(), path.display()))
}

fn summary(out: &hxai_reproduce::Reproduction, total_s: f64) {
    let r = &out.results;
    println!("\nsymbolic model of delta: {}", r.symbolic.equation);
    println!(
        "  complexity {}, features {}, {} models evaluated",
        r.symbolic.complexity,
        r.symbolic.features.join(", "),
        r.symbolic.evaluations
    );
    println!(
        "\n{:<10} {:>8} {:>8} {:>12}",
        "model", "R2", "RMSE", "paper R2"
    );
    for m in &r.table3 {
        let paper = m
            .paper_r2
            .map_or_else(|| "-".to_string(), |v| format!("{v:.3}"));
        println!(
            "{:<10} {:>8.3} {:>8.3} {:>12}",
            m.name, m.test.r2, m.test.rmse, paper
        );
    }
    let h = &r.hybrid;
    println!(
        "\ndisplacement, test records: physics RMSE {:.3} um (R2 {:.3}) -> hybrid {:.3} um (R2 {:.3}), {:.1} % lower; p = {}",
        h.physics.rmse,
        h.physics.r2,
        h.hybrid.rmse,
        h.hybrid.r2,
        h.improvement_pct,
        h.t_test
            .map_or_else(|| "n/a".to_string(), |t| format!("{:.2e}", t.p_value))
    );
    println!(
        "paper: physics RMSE 2.87 um (R2 0.814) -> hybrid 0.653 um (R2 0.974), 77.3 % lower; p = 5.97e-8"
    );
    println!();
    for (stage, s) in &out.timings {
        println!("  {stage:<36} {s:>7.1} s");
    }
    println!("  {:<36} {:>7.1} s", "total", total_s);
}
