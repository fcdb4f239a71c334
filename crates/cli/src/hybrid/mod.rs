//! `hxai hybrid fit | predict | evaluate | compare`: hybrid models of any process on a table
//! (a physics equation over the columns, its error learned by symbolic regression).
//!
//! This module parses options, reads and writes files and prints; every computation is
//! `hxai_hybrid::tables`.
use crate::Global;
use crate::strategy::interval_method;
use anyhow::{Context, Result};
use args::{Common, CompareArgs, EvaluateArgs, FitArgs, PredictArgs, Sub};
use hxai_data::NumericView;
use hxai_hybrid::tables::{
    self, TableConfig, TableModel, TableProgress, check_used_columns, model_columns,
};
use indicatif::ProgressBar;
use print::{print_comparison, print_interval, print_model};
use std::path::Path;

pub(crate) mod args;
mod design;
mod print;

pub use args::Args;

/// Runs `hxai hybrid ...`.
pub fn run(args: Args, _g: &Global) -> Result<()> {
    match args.command {
        Sub::Fit(a) => fit(a),
        Sub::Predict(a) => predict(a),
        Sub::Evaluate(a) => evaluate(a),
        Sub::Compare(a) => compare(a),
        Sub::Design(a) => design::run(a),
    }
}

/// Reads the table at `path` as a model grouped by `group` sees it.
pub(crate) fn read(path: &Path, group: Option<&str>) -> Result<NumericView> {
    let mixed = hxai_data::read_mixed_table(path)
        .with_context(|| format!("cannot read the table {}", path.display()))?;
    note_skipped(path, mixed.skipped_rows);
    mixed.numeric_view(group).or_else(|e| {
        // no column is all numbers: name the first bad cell of a column of numbers (a gap,
        // a repeated header, a typo) rather than "no columns"
        let text: Vec<(String, Vec<String>)> = mixed
            .names
            .iter()
            .zip(&mixed.columns)
            .filter_map(|(n, c)| match c {
                hxai_data::Column::Text(cells) => Some((n.clone(), cells.clone())),
                hxai_data::Column::Number(_) => None,
            })
            .collect();
        if let Some(bad) = tables::first_bad_cell(&text) {
            return Err(bad).with_context(|| path.display().to_string());
        }
        Err(e).with_context(|| format!("the table {} has no usable numeric column", path.display()))
    })
}

/// Says on stderr how many blank lines or all-empty rows of the file at `path` the reader
/// skipped.
fn note_skipped(path: &Path, skipped: usize) {
    crate::safety::note_missing_codes();
    if skipped > 0 {
        crate::safety::warn(&[format!(
            "{}: skipped {skipped} blank line(s) or row(s) with every cell empty",
            path.display()
        )]);
    }
}

/// Reads the table at `path` for the fitted `model`; the columns it reads (and the target,
/// `with_target`) must be numbers, a bad cell named by its row.
pub(crate) fn read_for(path: &Path, model: &TableModel, with_target: bool) -> Result<NumericView> {
    let view = read(path, model.group.as_deref())?;
    check_used_columns(&model_columns(model, with_target), &view.text)
        .with_context(|| path.display().to_string())?;
    Ok(view)
}

/// Reads the table at `path` with its empty cells resolved by `policy` (`refuse` reads as
/// [`read`] does): `used` are the columns that matter (a gap elsewhere is ignored; `None`
/// for every column), `protected` those never filled, `medians` those stored by a model.
/// Returns the report of what was done, except under `refuse`.
pub(crate) fn read_missing(
    path: &Path,
    group: Option<&str>,
    policy: hxai_data::MissingPolicy,
    target: Option<&str>,
    (used, protected): (Option<&[String]>, &[String]),
    medians: Option<&std::collections::BTreeMap<String, f64>>,
) -> Result<(NumericView, Option<hxai_data::MissingReport>)> {
    if policy == hxai_data::MissingPolicy::Refuse {
        return Ok((read(path, group)?, None));
    }
    let gappy = hxai_data::read_gappy_table(path)
        .with_context(|| format!("cannot read the table {}", path.display()))?;
    resolve_gappy(
        path,
        gappy,
        group,
        policy,
        target,
        (used, protected),
        medians,
    )
}

/// [`read_missing`] of a table already read (`gappy`, from `path`): one parse of the file.
fn resolve_gappy(
    path: &Path,
    gappy: hxai_data::GappyTable,
    group: Option<&str>,
    policy: hxai_data::MissingPolicy,
    target: Option<&str>,
    (used, protected): (Option<&[String]>, &[String]),
    medians: Option<&std::collections::BTreeMap<String, f64>>,
) -> Result<(NumericView, Option<hxai_data::MissingReport>)> {
    let cannot = || format!("cannot read the table {}", path.display());
    note_skipped(path, gappy.skipped_rows);
    let ignore: Vec<&str> = gappy
        .names
        .iter()
        .filter(|n| used.is_some_and(|u| !u.contains(n)))
        .map(String::as_str)
        .collect();
    let protected: Vec<&str> = protected.iter().map(String::as_str).collect();
    let (mixed, report) = gappy
        .resolve(policy, target, &protected, &ignore, medians)
        .with_context(cannot)?;
    let view = mixed
        .numeric_view(group)
        .with_context(|| format!("the table {} has no usable numeric column", path.display()))?;
    Ok((view, Some(report)))
}

/// Adds the level indicators of a model with per-class constants to a table read for it
/// (refusing a level it never saw).
pub(crate) fn add_levels(model: &TableModel, view: &mut NumericView) -> Result<()> {
    Ok(model.add_levels(&mut view.table, &view.text)?)
}

/// [`read_for`] with the empty cells of the columns `model` reads resolved by `policy`:
/// `impute` fills them with the medians the model file stores (refused when it has none).
/// Rows dropped or cells filled are said on stderr.
pub(crate) fn read_for_missing(
    path: &Path,
    model: &TableModel,
    with_target: bool,
    policy: hxai_data::MissingPolicy,
) -> Result<NumericView> {
    if policy == hxai_data::MissingPolicy::Refuse {
        return read_for(path, model, with_target);
    }
    let medians = match (policy, &model.missing) {
        (hxai_data::MissingPolicy::Impute, Some(m)) if !m.medians.is_empty() => Some(&m.medians),
        (hxai_data::MissingPolicy::Impute, _) => anyhow::bail!(
            "--missing impute: the model was fitted without --missing impute and stores no \
             training medians to fill empty cells with; use --missing drop, or refit with \
             --missing impute"
        ),
        _ => None,
    };
    let used = model_columns(model, with_target);
    let (view, report) = read_missing(
        path,
        model.group.as_deref(),
        policy,
        Some(model.target.as_str()),
        (Some(&used), &model.physics.columns),
        medians,
    )?;
    check_used_columns(&used, &view.text).with_context(|| path.display().to_string())?;
    if let Some(r) = report {
        crate::safety::warn(&r.lines());
    }
    Ok(view)
}

/// The physics' column names among `names` (its variables that are not parameters).
fn physics_columns(cfg: &TableConfig, names: &[String]) -> Vec<String> {
    hxai_symreg::infix::parse_with_slots(&cfg.physics)
        .map(|(p, _)| {
            p.names()
                .into_iter()
                .filter(|n| names.iter().any(|c| c == n))
                .map(str::to_string)
                .collect()
        })
        .unwrap_or_default()
}

/// What `fit` and `compare` start from ([`prepare`]).
struct Prepared {
    /// The table and its configuration, ready to fit ([`tables::prepare`]).
    ready: tables::Prepared,
    /// The progress bar of the search.
    bar: ProgressBar,
}

/// Reads the table once, resolves its empty cells by `--missing`, and hands the one
/// configuration with the table to [`tables::prepare`].
fn prepare(c: &Common) -> Result<Prepared> {
    let mut cfg = c.config()?;
    let (loaded, missing) = if c.missing == hxai_data::MissingPolicy::Refuse {
        (read(&c.data, cfg.group.as_deref())?, None)
    } else {
        let gappy = hxai_data::read_gappy_table(&c.data)
            .with_context(|| format!("cannot read the table {}", c.data.display()))?;
        // the columns that matter: the named ones, or every one not excluded
        let protected = physics_columns(&cfg, &gappy.names);
        let used: Option<Vec<String>> = cfg.features.as_ref().map(|f| {
            let mut u = f.clone();
            u.push(cfg.target.clone());
            u.extend(protected.iter().cloned());
            u.extend(cfg.extrapolate.iter().cloned());
            u.extend(cfg.group.iter().cloned());
            u
        });
        let used = used.unwrap_or_else(|| {
            gappy
                .names
                .iter()
                .filter(|n| !cfg.exclude.iter().any(|e| e.trim() == n.as_str()))
                .cloned()
                .collect()
        });
        resolve_gappy(
            &c.data,
            gappy,
            cfg.group.as_deref(),
            c.missing,
            Some(cfg.target.as_str()),
            (Some(&used), &protected),
            None,
        )?
    };
    if let Some(spec) = &c.calibrate_per {
        let (column, parameters) = tables::per_class::parse_spec(spec)?;
        cfg.per_level.calibrate = Some(tables::CalibratePer { column, parameters });
    }
    cfg.per_level.correction.clone_from(&c.correction_per);
    let notes = missing
        .as_ref()
        .map(hxai_data::MissingReport::lines)
        .unwrap_or_default();
    cfg.missing = missing.map(|r| tables::MissingInfo {
        policy: r.policy.name().to_string(),
        medians: r.medians,
    });
    let ready = tables::prepare(&cfg, loaded.table, &loaded.text, notes)
        .with_context(|| c.data.display().to_string())?;
    let bar = crate::progress::styled(
        ready.cfg.search.epochs as u64,
        "{bar:30} {pos}/{len} {msg} [{elapsed}, about {eta} left of this step]",
    );
    bar.set_message(format!("read {} rows", ready.table.n_rows()));
    Ok(Prepared { ready, bar })
}

fn on_progress(b: &ProgressBar) -> impl FnMut(&TableProgress) + '_ {
    move |p: &TableProgress| {
        if p.step {
            // a phase that is not a search: its own steps, its name
            b.set_length(p.search.epochs.max(1) as u64);
            b.set_position(p.search.epoch as u64);
            b.set_message(p.label.clone());
            return;
        }
        let e = p.search.epochs as u64;
        b.set_length(p.tasks as u64 * e);
        b.set_position((p.task as u64 - 1) * e + p.search.epoch as u64);
        b.set_message(format!("{} epoch {}/{}", p.label, p.search.epoch, e));
    }
}

#[allow(clippy::print_stdout)]
fn fit(a: FitArgs) -> Result<()> {
    // The output is checked before any work: a fit that cannot be written is not started.
    crate::safety::check_output(
        &a.out,
        &[crate::safety::input(&a.common.data, "the table (--data)")],
    )?;
    let Prepared { ready, bar: b } = prepare(&a.common)?;
    let mut model = ready.fit(&mut on_progress(&b))?;
    b.finish_and_clear();
    crate::safety::warn(&ready.warnings);
    crate::safety::warn(&model.warnings);
    if let Some(runs) = a.stability {
        let sb = crate::progress::styled(runs as u64, "{bar:30} {pos}/{len} resamples [{elapsed}]");
        let sbb = sb.clone();
        ready.measure_stability(&mut model, runs, &mut move |done, _| {
            sbb.set_position(done as u64)
        })?;
        sb.finish_and_clear();
    }
    let cannot = || format!("cannot write the model to {}", a.out.display());
    let wb = crate::progress::styled(1, "{msg} [{elapsed}]");
    wb.set_message(format!("writing the model to {}", a.out.display()));
    let json = model.to_checked_json().with_context(cannot)?;
    wb.finish_and_clear();
    let staged = hxai_data::stage_text(&a.out, &json).with_context(cannot)?;
    if a.common.json {
        // the document first: a full stdout then leaves the old model file as it was
        crate::safety::print_document(&json)?;
        return staged.commit().with_context(cannot);
    }
    staged.commit().with_context(cannot)?;
    print_model(&model);
    if let Some(sel) = &model.correction.selection {
        crate::sr::print_selection(sel);
    }
    if let Some(st) = &model.stability {
        crate::sr::print_stability(st);
    }
    println!("model written to {}", a.out.display());
    Ok(())
}

pub(super) fn load_model(path: &Path) -> Result<TableModel> {
    let text = hxai_data::read_text(path)
        .with_context(|| format!("cannot read the model {}", path.display()))?;
    TableModel::from_json(&text)
        .with_context(|| format!("cannot load the model {}", path.display()))
}

#[allow(clippy::print_stdout)]
fn predict(a: PredictArgs) -> Result<()> {
    crate::safety::check_predict(&a.out, &a.data, &a.model, a.interval)?;
    let model = load_model(&a.model)?;
    let mut loaded = read_for_missing(&a.data, &model, false, a.missing)?;
    add_levels(&model, &mut loaded)?;
    let p = model.predict(&loaded.table)?;
    crate::safety::warn(&model.range_warnings(&loaded.table));
    crate::safety::warn(&model.value_warnings(&loaded.table));
    crate::safety::warn(&model.prediction_warnings(&loaded.table, &p.hybrid));
    let bounds = match a.interval {
        Some(level) => {
            let method = interval_method(a.interval_method, model.default_interval_method(level));
            let iv = model.intervals_with(&loaded.table, level, method)?;
            let undefined = iv
                .iter()
                .filter(|(lo, hi)| lo.is_nan() || hi.is_nan())
                .count();
            if undefined > 0 {
                crate::safety::warn(&[format!(
                    "{undefined} row(s) have no prediction interval (the {} method has no value \
                     there, e.g. a fold's model predicts a value the interval's log scale cannot \
                     take): `hybrid_lo` and `hybrid_hi` are empty there",
                    method.name()
                )]);
            }
            Some(iv)
        }
        None => None,
    };
    let outside: Vec<f64> = model
        .outside_training(&loaded.table)
        .into_iter()
        .map(|o| if o { 1.0 } else { 0.0 })
        .collect();
    let mut t = hxai_data::MixedTable::default();
    if let (Some(g), Some(cells)) = (&model.group, loaded.group_cells) {
        t.push(g, cells);
    }
    let with_bounds = bounds.is_some();
    let (lo, hi): (Vec<f64>, Vec<f64>) = bounds.unwrap_or_default().into_iter().unzip();
    let columns = [
        ("physics", p.physics),
        ("correction", p.correction),
        ("hybrid", p.hybrid),
        ("hybrid_lo", lo),
        ("hybrid_hi", hi),
        ("outside_training", outside),
    ];
    for (n, v) in columns
        .into_iter()
        .filter(|(n, _)| with_bounds || !n.starts_with("hybrid_"))
    {
        t.push(n, hxai_data::Column::Number(v));
    }
    hxai_data::write_mixed_table(&a.out, &t)
        .with_context(|| format!("cannot write the predictions to {}", a.out.display()))?;
    println!(
        "{} rows written to {}",
        loaded.table.n_rows(),
        a.out.display()
    );
    Ok(())
}

#[allow(clippy::print_stdout)]
fn evaluate(a: EvaluateArgs) -> Result<()> {
    crate::safety::check_level(a.interval, "--interval")?;
    let model = load_model(&a.model)?;
    let mut loaded = read_for_missing(&a.data, &model, true, a.missing)?;
    add_levels(&model, &mut loaded)?;
    let e = match (a.interval_method, model.default_interval_method(a.interval)) {
        (None, None) => model.evaluate_at(&loaded.table, a.interval)?,
        (asked, _) => model.evaluate_with(
            &loaded.table,
            a.interval,
            interval_method(asked, model.default_interval_method(a.interval)),
        )?,
    };
    crate::safety::warn(&e.warnings);
    if a.json {
        println!("{}", serde_json::to_string_pretty(&e)?);
    } else {
        println!(
            "{} rows: physics RMSE {} R^2 {:.4}; hybrid RMSE {} R^2 {:.4}; improvement {:.2} %; paired t-test {}",
            e.n_samples,
            hxai_data::format_number(e.physics.rmse),
            e.physics.r2,
            hxai_data::format_number(e.hybrid.rmse),
            e.hybrid.r2,
            e.improvement_pct,
            match (&e.t_test, &e.t_test_reason) {
                (Some(t), _) => format!("p = {}", hxai_data::format_number(t.p_value)),
                (None, r) => format!("none ({})", r.as_deref().unwrap_or("undefined")),
            }
        );
        if let Some(iv) = e.interval {
            print_interval(&iv, "rows");
        }
    }
    Ok(())
}

#[allow(clippy::print_stdout)]
fn compare(a: CompareArgs) -> Result<()> {
    crate::safety::check_level(a.interval, "--interval")?;
    let Prepared { ready, bar: b } = prepare(&a.common)?;
    let mut c = ready.compare(a.folds, &mut on_progress(&b))?;
    b.finish_and_clear();
    crate::safety::warn(&c.hybrid.warnings);
    if a.interval_method.is_some() || a.interval != hxai_hybrid::DEFAULT_INTERVAL {
        let method = interval_method(
            a.interval_method,
            c.hybrid.default_interval_method(a.interval),
        );
        c.interval = c.hybrid.test_interval(&ready.table, a.interval, method)?;
    }
    crate::safety::warn(&ready.warnings);
    if a.common.json {
        println!("{}", serde_json::to_string_pretty(&c)?);
    } else {
        print_comparison(&c);
    }
    Ok(())
}
