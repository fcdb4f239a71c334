//! Hybrid models of any process, on tables (`hxai hybrid ...`).
//!
//! The paper's framework (method.md section 1) for a user's own process: a physics equation
//! `f_p` written as text over the table's columns and named parameters, calibrated
//! parameters fitted by Levenberg-Marquardt on the training rows (grey-box calibration,
//! with standard errors from the Jacobian at the optimum), the physics' error `delta`
//! learned by symbolic regression on feature columns, and the hybrid printed as one
//! equation over the columns.
//!
//! - [`ProcessConfig`]: target, physics text, parameters to calibrate / fix, features,
//!   correction form ([`CorrectionForm`]), split, search settings.
//! - [`fit_process`] (and [`fit_process_split`] for a given split) returns a
//!   [`ProcessModel`], the serialisable model file, with [`ProcessModel::predict`],
//!   [`ProcessModel::evaluate`], [`ProcessModel::to_json`] and [`ProcessModel::from_json`].
//! - [`compare_process`]: physics as given, calibrated physics, symbolic regression alone,
//!   physics + random forest, and the hybrid on the same split, with k-fold CV and paired
//!   t-tests ([`Comparison`]).
//!
//! Design decision: the physics equation is compiled to a symreg
//! [`Program`](hxai_symreg::Program) whose
//! parameters are constant leaves, so physics, correction and the joint refit are all
//! evaluated and differentiated by one evaluator, and the hybrid is itself one program:
//! its printed form is the one equation of the model file, which reproduces `predict`.
//!
//! ```
//! use hxai_hybrid::process::{ProcessConfig, fit_process};
//! use hxai_symreg::Table;
//! let f: Vec<f64> = (0..120).map(|i| 0.05 + 0.002 * i as f64).collect();
//! let r: Vec<f64> = (0..120).map(|i| 0.4 + 0.4 * ((i * 7) % 11) as f64 / 10.0).collect();
//! // "measured" roughness: twice the kinematic law plus an offset
//! let ra: Vec<f64> = f.iter().zip(&r).map(|(f, r)| 2.0 * f * f / (32.0 * r) + 1e-4).collect();
//! let table = Table::new(vec!["f".into(), "r".into(), "Ra".into()], vec![f, r, ra])?;
//! let mut cfg = ProcessConfig::new("Ra", "k*f^2/(32*r)");
//! cfg.calibrate = vec!["k".into()];
//! cfg.search.epochs = 2;
//! cfg.search.candidates_per_epoch = 200;
//! let model = fit_process(&table, &cfg, &mut |_| {})?;
//! assert!((model.physics.parameters["k"] - 2.0).abs() < 0.05);
//! let back = hxai_hybrid::process::ProcessModel::from_json(&model.to_json())?;
//! assert_eq!(back, model);
//! # Ok::<(), hxai_hybrid::HybridError>(())
//! ```
mod calibrate;
mod compare;
mod model;

pub use compare::{Comparison, CvScore, ModelScore, TTestScore, compare_process};
pub use model::{
    CorrectionInfo, EquationInfo, JointInfo, PROCESS_SCHEMA_VERSION, PairScores, PhysicsInfo,
    ProcessEvaluation, ProcessModel, ProcessPrediction, ScoresInfo, SplitInfo,
};

use crate::HybridError;
use hxai_eval::Split;
use hxai_symreg::infix::{Compiled, Parsed, parse};
use hxai_symreg::{ParamEstimate, SearchConfig, Table, Uncertainty};
use model::{
    Combined, columns_of, combine, combine_values, compile_physics, finite_physics, forms,
};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// How the correction enters the hybrid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CorrectionForm {
    /// `y = f_p + delta`, `delta = y - f_p` (eq. 2-5).
    #[default]
    Additive,
    /// `y = f_p (1 + delta)`, `delta = y / f_p - 1`, for laws whose error scales with
    /// the prediction.
    Multiplicative,
}

impl CorrectionForm {
    /// `additive` or `multiplicative`.
    pub fn name(self) -> &'static str {
        match self {
            CorrectionForm::Additive => "additive",
            CorrectionForm::Multiplicative => "multiplicative",
        }
    }
}

/// Settings of [`fit_process`] and [`compare_process`].
#[derive(Clone, Debug)]
pub struct ProcessConfig {
    /// The target column.
    pub target: String,
    /// The physics equation (infix text, see [`hxai_symreg::infix`]).
    pub physics: String,
    /// Parameters fitted on the training rows.
    pub calibrate: Vec<String>,
    /// Starting values of calibrated parameters (default 1).
    pub init: BTreeMap<String, f64>,
    /// Values of parameters that are not calibrated.
    pub set: BTreeMap<String, f64>,
    /// Feature columns of the correction (`None`: every column except the target, the
    /// group column and `exclude`).
    pub features: Option<Vec<String>>,
    /// Columns left out of the default feature set.
    pub exclude: Vec<String>,
    /// Correction form.
    pub correction: CorrectionForm,
    /// Rows sharing this column's value stay on one side of every split.
    pub group: Option<String>,
    /// Share of rows (or groups) held out for testing.
    pub test_fraction: f64,
    /// Test on the rows with the top `test_fraction` of this column (train low, test high).
    pub extrapolate: Option<String>,
    /// Seed of the split and of the search (overrides `search.seed`).
    pub seed: u64,
    /// Refit physics parameters and correction constants together once the correction's
    /// structure is chosen.
    pub joint: bool,
    /// Symbolic-regression settings of the correction (and of `symbolic` in compare).
    pub search: SearchConfig,
}

impl ProcessConfig {
    /// Defaults: additive correction, 20 % random test split, seed 42, symreg's default
    /// search (complexity at most 10).
    pub fn new(target: &str, physics: &str) -> Self {
        Self {
            target: target.to_string(),
            physics: physics.to_string(),
            calibrate: Vec::new(),
            init: BTreeMap::new(),
            set: BTreeMap::new(),
            features: None,
            exclude: Vec::new(),
            correction: CorrectionForm::Additive,
            group: None,
            test_fraction: 0.2,
            extrapolate: None,
            seed: 42,
            joint: false,
            search: SearchConfig::paper(),
        }
    }

    fn search_config(&self) -> SearchConfig {
        SearchConfig {
            seed: self.seed,
            ..self.search.clone()
        }
    }
}

/// Reported while fitting: which task of how many, and the search's own progress.
#[derive(Clone, Debug, PartialEq)]
pub struct ProcessProgress {
    /// Task index (1-based).
    pub task: usize,
    /// Tasks planned.
    pub tasks: usize,
    /// What runs (`correction`, `symbolic`, `fold 2/5 correction`, ...).
    pub label: String,
    /// The search's progress within the task.
    pub search: hxai_symreg::Progress,
}

/// The physics equation resolved against a table.
#[derive(Clone, Debug)]
pub(crate) struct Resolved {
    pub columns: Vec<String>,
    pub calibrate: Vec<String>,
    pub initial: BTreeMap<String, f64>,
    pub compiled: Compiled,
    pub features: Vec<String>,
}

fn cols_list(table: &Table) -> String {
    table.names().join(", ")
}

fn require_column(table: &Table, name: &str, what: &'static str) -> Result<(), HybridError> {
    if table.column(name).is_none() {
        return Err(HybridError::MissingColumn {
            what,
            name: name.to_string(),
            columns: cols_list(table),
        });
    }
    Ok(())
}

/// Checks the configuration against the table: every name in the equation is a column or
/// a parameter, parameters are not columns and appear in the equation, the target is not
/// in the equation, at least one feature.
pub(crate) fn resolve(table: &Table, cfg: &ProcessConfig) -> Result<Resolved, HybridError> {
    require_column(table, &cfg.target, "target")?;
    if let Some(g) = &cfg.group {
        require_column(table, g, "group column")?;
    }
    if let Some(e) = &cfg.extrapolate {
        require_column(table, e, "extrapolation column")?;
    }
    let parsed: Parsed = parse(&cfg.physics).map_err(|source| HybridError::Equation {
        equation: cfg.physics.clone(),
        source,
    })?;
    let is_col = |n: &str| table.column(n).is_some();
    let named: [(&'static str, Vec<&String>); 3] = [
        ("calibrate", cfg.calibrate.iter().collect()),
        ("set", cfg.set.keys().collect()),
        ("init", cfg.init.keys().collect()),
    ];
    for (flag, names) in &named {
        for n in names {
            if is_col(n) {
                return Err(HybridError::ParameterIsColumn {
                    name: (*n).clone(),
                    flag,
                });
            }
            if parsed.position(n).is_none() {
                return Err(HybridError::ParameterNotInEquation {
                    name: (*n).clone(),
                    flag,
                    equation: cfg.physics.clone(),
                });
            }
        }
    }
    for n in &cfg.calibrate {
        if cfg.set.contains_key(n) {
            return Err(HybridError::InvalidConfig(format!(
                "parameter `{n}` is both calibrated (--calibrate) and fixed (--set): choose one"
            )));
        }
    }
    for n in cfg.init.keys() {
        if !cfg.calibrate.contains(n) {
            return Err(HybridError::InvalidConfig(format!(
                "--init gives a starting value for `{n}`, which is not calibrated: add it to --calibrate or use --set"
            )));
        }
    }
    let mut columns = Vec::new();
    let mut values: BTreeMap<String, f64> = BTreeMap::new();
    for (name, position) in &parsed.positions {
        if *name == cfg.target {
            return Err(HybridError::TargetInPhysics {
                name: name.clone(),
                position: *position,
            });
        }
        if is_col(name) {
            columns.push(name.clone());
        } else if cfg.calibrate.contains(name) {
            values.insert(name.clone(), cfg.init.get(name).copied().unwrap_or(1.0));
        } else if let Some(v) = cfg.set.get(name) {
            values.insert(name.clone(), *v);
        } else {
            return Err(HybridError::UnknownName {
                name: name.clone(),
                position: *position,
                columns: cols_list(table),
            });
        }
    }
    for (n, v) in cfg.set.iter().chain(&cfg.init) {
        if !v.is_finite() {
            return Err(HybridError::InvalidConfig(format!(
                "parameter `{n}` = {v}: give a finite value"
            )));
        }
    }
    let initial: BTreeMap<String, f64> = cfg
        .calibrate
        .iter()
        .map(|n| (n.clone(), values.get(n).copied().unwrap_or(1.0)))
        .collect();
    let compiled = compile_physics(&cfg.physics, &columns, &values)?;
    let features = feature_columns(table, cfg)?;
    Ok(Resolved {
        columns,
        calibrate: cfg.calibrate.clone(),
        initial,
        compiled,
        features,
    })
}

fn feature_columns(table: &Table, cfg: &ProcessConfig) -> Result<Vec<String>, HybridError> {
    let features: Vec<String> = match &cfg.features {
        Some(list) => {
            for f in list {
                require_column(table, f, "feature")?;
                if *f == cfg.target {
                    return Err(HybridError::NoFeatures(format!(
                        "the target `{f}` cannot be a feature of its own correction"
                    )));
                }
                if cfg.group.as_ref() == Some(f) {
                    return Err(HybridError::NoFeatures(format!(
                        "the group column `{f}` cannot be a feature"
                    )));
                }
            }
            list.clone()
        }
        None => {
            for e in &cfg.exclude {
                require_column(table, e, "excluded column")?;
            }
            table
                .names()
                .iter()
                .filter(|n| {
                    **n != cfg.target && cfg.group.as_ref() != Some(*n) && !cfg.exclude.contains(n)
                })
                .cloned()
                .collect()
        }
    };
    if features.is_empty() {
        return Err(HybridError::NoFeatures(format!(
            "no feature column is left for the correction (table columns: {}; target `{}`{}): \
             give --features or exclude fewer columns",
            cols_list(table),
            cfg.target,
            cfg.group
                .as_ref()
                .map(|g| format!(", group `{g}`"))
                .unwrap_or_default()
        )));
    }
    Ok(features)
}

/// The split [`fit_process`] uses: with `extrapolate`, the rows (or groups, by their mean)
/// with the top `test_fraction` of that column are the test set; otherwise a seeded random
/// split, grouped when `group` is set.
///
/// # Errors
/// A missing column, `test_fraction` outside (0, 1), or a side left empty.
pub fn process_split(table: &Table, cfg: &ProcessConfig) -> Result<(Split, String), HybridError> {
    let n = table.n_rows();
    let groups: Option<Vec<u64>> = match &cfg.group {
        Some(g) => {
            let col = table.column(g).ok_or_else(|| HybridError::MissingColumn {
                what: "group column",
                name: g.clone(),
                columns: cols_list(table),
            })?;
            Some(col.iter().map(|v| (v + 0.0).to_bits()).collect())
        }
        None => None,
    };
    if let Some(e) = &cfg.extrapolate {
        let col = table.column(e).ok_or_else(|| HybridError::MissingColumn {
            what: "extrapolation column",
            name: e.clone(),
            columns: cols_list(table),
        })?;
        if !(cfg.test_fraction > 0.0 && cfg.test_fraction < 1.0) {
            return Err(HybridError::InvalidConfig(format!(
                "test fraction {}: choose a value between 0 and 1",
                cfg.test_fraction
            )));
        }
        // units: rows, or groups keyed by first appearance
        let mut unit_of = vec![0usize; n];
        let mut sums: Vec<(f64, usize, usize)> = Vec::new(); // (sum, count, first row)
        match &groups {
            Some(g) => {
                let mut seen: BTreeMap<u64, usize> = BTreeMap::new();
                for (i, key) in g.iter().enumerate() {
                    let u = *seen.entry(*key).or_insert_with(|| {
                        sums.push((0.0, 0, i));
                        sums.len() - 1
                    });
                    unit_of[i] = u;
                    sums[u].0 += col[i];
                    sums[u].1 += 1;
                }
            }
            None => {
                for (i, v) in col.iter().enumerate() {
                    unit_of[i] = i;
                    sums.push((*v, 1, i));
                }
            }
        }
        let mut order: Vec<usize> = (0..sums.len()).collect();
        order.sort_by(|&a, &b| {
            let ma = sums[a].0 / sums[a].1 as f64;
            let mb = sums[b].0 / sums[b].1 as f64;
            mb.total_cmp(&ma).then(sums[a].2.cmp(&sums[b].2))
        });
        let need = (cfg.test_fraction * n as f64).ceil() as usize;
        let mut in_test = vec![false; sums.len()];
        let mut taken = 0;
        for u in order {
            if taken >= need {
                break;
            }
            in_test[u] = true;
            taken += sums[u].1;
        }
        let (test, train): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| in_test[unit_of[i]]);
        if train.is_empty() || test.is_empty() {
            return Err(HybridError::InvalidConfig(format!(
                "the extrapolation split on `{e}` leaves one side empty: change --test-fraction"
            )));
        }
        return Ok((Split { train, test }, "extrapolate".into()));
    }
    Ok(match groups {
        Some(g) => (
            hxai_eval::grouped_train_test_split(&g, cfg.test_fraction, cfg.seed)?,
            "grouped".into(),
        ),
        None => (
            hxai_eval::train_test_split(n, cfg.test_fraction, cfg.seed)?,
            "random".into(),
        ),
    })
}

/// Values of `col` at `rows`.
pub(crate) fn gather(col: &[f64], rows: &[usize]) -> Vec<f64> {
    rows.iter().map(|&i| col[i]).collect()
}

/// The physics calibrated on `rows`: parameters updated in `compiled`, standard errors.
pub(crate) fn calibrate_physics(
    table: &Table,
    cfg: &ProcessConfig,
    res: &Resolved,
    rows: &[usize],
) -> Result<(Compiled, BTreeMap<String, Option<f64>>), HybridError> {
    let mut phys = res.compiled.clone();
    let all = columns_of(table, &res.columns, "physics column")?;
    let cols: Vec<Vec<f64>> = all.iter().map(|c| gather(c, rows)).collect();
    let cols: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    let y = gather(table.require(&cfg.target)?, rows);
    // the start must be finite everywhere, or LM has nothing to descend from
    let start = phys.eval_columns(&cols, rows.len());
    if let Some((k, v)) = start.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(HybridError::BadPhysics {
            row: rows[k],
            value: *v,
            why: if res.calibrate.is_empty() {
                "not a finite number: check the equation's domain at this row".into()
            } else {
                "not a finite number at the starting parameter values: give better ones with --init"
                    .into()
            },
        });
    }
    let groups: Vec<Vec<usize>> = res
        .calibrate
        .iter()
        .map(|n| phys.slots.get(n).cloned().unwrap_or_default())
        .collect();
    let mut ses = BTreeMap::new();
    if !groups.is_empty() {
        calibrate::lm_tied(
            &phys.program,
            &mut phys.params,
            &groups,
            &cols,
            &y,
            500,
            1e-15,
        );
        let se = calibrate::standard_errors(&phys.program, &phys.params, &groups, &cols, &y);
        for (n, s) in res.calibrate.iter().zip(se) {
            ses.insert(n.clone(), s);
        }
    }
    Ok((phys, ses))
}

/// Physics values on every row, refusing a non-finite one (naming the row).
pub(crate) fn physics_values(
    table: &Table,
    res: &Resolved,
    phys: &Compiled,
) -> Result<Vec<f64>, HybridError> {
    finite_physics(table, phys, &res.columns)
}

/// `delta` on `rows` for the correction form, refusing rows where it is undefined.
pub(crate) fn deltas(
    kind: CorrectionForm,
    y: &[f64],
    physics: &[f64],
    rows: &[usize],
) -> Result<Vec<f64>, HybridError> {
    rows.iter()
        .map(|&i| match kind {
            CorrectionForm::Additive => Ok(y[i] - physics[i]),
            CorrectionForm::Multiplicative => {
                if physics[i] == 0.0 {
                    Err(HybridError::BadPhysics {
                        row: i,
                        value: physics[i],
                        why: "so the multiplicative correction y / f_p - 1 is undefined: use --correction additive".into(),
                    })
                } else {
                    Ok(y[i] / physics[i] - 1.0)
                }
            }
        })
        .collect()
}

fn named_values(phys: &Compiled) -> BTreeMap<String, f64> {
    phys.slots
        .keys()
        .map(|n| (n.clone(), phys.get(n).unwrap_or(f64::NAN)))
        .collect()
}

/// The stability of the correction's structure of `model` (fitted with `cfg` on `table`):
/// the correction's search rerun on `runs` bootstrap resamples of the training rows, on
/// `delta` of the model's calibrated physics ([`hxai_symreg::stability()`]). `progress`
/// gets `(runs done, runs)`.
///
/// # Errors
/// A missing column, a physics value that cannot be used, and the search's errors.
pub fn process_stability(
    table: &Table,
    cfg: &ProcessConfig,
    model: &ProcessModel,
    runs: usize,
    progress: &mut (dyn FnMut(usize, usize) + Send),
) -> Result<hxai_symreg::Stability, HybridError> {
    let physics = model.predict(table)?.physics;
    let y = table.require(&model.target)?;
    let delta = deltas(model.correction.kind, y, &physics, &model.split.train)?;
    let ft = table
        .select_columns(&model.correction.candidates)?
        .select_rows(&model.split.train)?;
    Ok(hxai_symreg::stability(
        &ft,
        &delta,
        &cfg.search_config(),
        runs,
        progress,
    )?)
}

/// For each calibrated physics parameter, the indices of its leaves among the parameters
/// of the combined hybrid program `c` (one unknown tied over every leaf that uses it).
fn calibrated_slots(res: &Resolved, phys: &Compiled, c: &Combined) -> Vec<Vec<usize>> {
    res.calibrate
        .iter()
        .map(|n| {
            phys.slots
                .get(n)
                .map(|s| {
                    s.iter()
                        .filter_map(|i| c.phys_map.get(i).copied())
                        .collect()
                })
                .unwrap_or_default()
        })
        .collect()
}

/// Fits on the split [`process_split`] chooses.
///
/// # Errors
/// Bad configuration (see [`HybridError`]'s variants `UnknownName`, `ParameterIsColumn`,
/// `ParameterNotInEquation`, `TargetInPhysics`, `MissingColumn`, `NoFeatures`,
/// `Equation`), a physics value that cannot be used (`BadPhysics`), or a failed search.
pub fn fit_process(
    table: &Table,
    cfg: &ProcessConfig,
    progress: &mut dyn FnMut(&ProcessProgress),
) -> Result<ProcessModel, HybridError> {
    let (split, kind) = process_split(table, cfg)?;
    fit_inner(SplitJob::single(table, cfg, &split, &kind), progress)
}

/// Fits on a given split (test rows may be empty: everything is then training data).
///
/// # Errors
/// As [`fit_process`], and row indices out of range.
pub fn fit_process_split(
    table: &Table,
    cfg: &ProcessConfig,
    split: &Split,
    progress: &mut dyn FnMut(&ProcessProgress),
) -> Result<ProcessModel, HybridError> {
    fit_inner(SplitJob::single(table, cfg, split, "given"), progress)
}

pub(crate) fn check_rows(table: &Table, split: &Split) -> Result<(), HybridError> {
    let n = table.n_rows();
    if split.train.is_empty() {
        return Err(HybridError::NoData("the split has no training rows".into()));
    }
    if let Some(&i) = split.train.iter().chain(&split.test).find(|&&i| i >= n) {
        return Err(HybridError::InvalidConfig(format!(
            "row index {i} is out of range: the table has {n} rows"
        )));
    }
    Ok(())
}

/// Symbolic regression of `y` (one value per training row of `split`) on the training rows
/// of the feature columns, reported as task `task.0` of `task.1` named `label`: those rows'
/// feature table and the search's result.
#[allow(clippy::too_many_arguments)]
pub(crate) fn search_training_rows(
    table: &Table,
    res: &Resolved,
    cfg: &ProcessConfig,
    split: &Split,
    y: &[f64],
    task: (usize, usize),
    label: String,
    progress: &mut dyn FnMut(&ProcessProgress),
) -> Result<(Table, hxai_symreg::SearchResult), HybridError> {
    let ft = table
        .select_columns(&res.features)?
        .select_rows(&split.train)?;
    let found = hxai_symreg::search(&ft, y, &cfg.search_config(), &mut |p| {
        progress(&ProcessProgress {
            task: task.0,
            tasks: task.1,
            label: label.clone(),
            search: p.clone(),
        })
    })?;
    Ok((ft, found))
}

/// One fit on one split of a table: what [`fit_inner`] (and the comparison's
/// per-split predictions) work on.
#[derive(Clone, Copy)]
pub(crate) struct SplitJob<'a> {
    pub(crate) table: &'a Table,
    pub(crate) cfg: &'a ProcessConfig,
    pub(crate) split: &'a Split,
    /// Split kind, as the model file reports it (`random`, `given`, `fold`, ...).
    pub(crate) kind: &'a str,
    /// `(this task, tasks in all)`, for progress reports.
    pub(crate) task: (usize, usize),
}

impl<'a> SplitJob<'a> {
    /// The only task of a run.
    fn single(table: &'a Table, cfg: &'a ProcessConfig, split: &'a Split, kind: &'a str) -> Self {
        let task = (1, 1);
        Self {
            table,
            cfg,
            split,
            kind,
            task,
        }
    }
}

pub(crate) fn fit_inner(
    job: SplitJob,
    progress: &mut dyn FnMut(&ProcessProgress),
) -> Result<ProcessModel, HybridError> {
    let (table, cfg, split, kind, task) = (job.table, job.cfg, job.split, job.kind, job.task);
    check_rows(table, split)?;
    let res = resolve(table, cfg)?;
    let (mut phys, mut ses) = calibrate_physics(table, cfg, &res, &split.train)?;
    let y_all = table.require(&cfg.target)?;
    let physics = physics_values(table, &res, &phys)?;
    let delta = deltas(cfg.correction, y_all, &physics, &split.train)?;
    let label = if task.1 > 1 {
        format!("correction ({}/{})", task.0, task.1)
    } else {
        "correction".to_string()
    };
    let (ft, found) = search_training_rows(table, &res, cfg, split, &delta, task, label, progress)?;
    let mut correction = found.best;
    let y_train = gather(y_all, &split.train);
    let rmse_on_train = |phys: &Compiled, correction: &hxai_symreg::Model| {
        train_rmse(
            table,
            &res,
            phys,
            correction,
            cfg.correction,
            split,
            &y_train,
        )
    };

    let mut joint = None;
    if cfg.joint {
        let before = rmse_on_train(&phys, &correction)?;
        let sequential_parameters = named_values(&phys);
        let sequential_standard_errors = ses.clone();
        let sequential_correction = correction.sympy();
        let mut c = combine(&phys, &correction, cfg.correction);
        // physics unknowns (tied leaves), then each fitted correction constant; constants
        // the search snapped to exact values (integers, halves) stay fixed
        let mut groups = calibrated_slots(&res, &phys, &c);
        let n_phys = groups.len();
        for (i, &ci) in c.corr_map.iter().enumerate() {
            let v = correction.params[i];
            if (2.0 * v).fract() != 0.0 {
                groups.push(vec![ci]);
            }
        }
        let all = columns_of(table, &c.names, "column")?;
        let cols: Vec<Vec<f64>> = all.iter().map(|col| gather(col, &split.train)).collect();
        let cols: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
        let mut trial = c.params.clone();
        let mse = calibrate::lm_tied(&c.program, &mut trial, &groups, &cols, &y_train, 200, 1e-15);
        if mse.is_finite() && mse.sqrt() <= before {
            let se = calibrate::standard_errors(&c.program, &trial, &groups, &cols, &y_train);
            c.params = trial;
            for (&pi, &ci) in &c.phys_map {
                phys.params[pi] = c.params[ci];
            }
            for (i, &ci) in c.corr_map.iter().enumerate() {
                correction.params[i] = c.params[ci];
            }
            ses = res
                .calibrate
                .iter()
                .cloned()
                .zip(se.into_iter().take(n_phys))
                .collect();
            // the physics must still be usable everywhere
            physics_values(table, &res, &phys)?;
        }
        let after = rmse_on_train(&phys, &correction)?;
        joint = Some(JointInfo {
            sequential_parameters,
            sequential_standard_errors,
            sequential_correction,
            sequential_train_rmse: before,
            joint_train_rmse: after,
        });
    }

    let parameters = named_values(&phys);
    let correction_uncertainty = correction.uncertainty(
        &ft,
        &delta_train(cfg, y_all, &physics_values(table, &res, &phys)?, split)?,
    )?;
    let hybrid_uncertainty =
        hybrid_uncertainty(table, &res, &phys, &correction, cfg, split, &y_train)?;
    let n_cal = res.calibrate.len();
    let t = hxai_eval::t_upper_quantile(0.025, split.train.len().saturating_sub(n_cal) as f64);
    let physics_params: BTreeMap<String, ParamEstimate> = res
        .calibrate
        .iter()
        .map(|n| {
            let value = parameters.get(n).copied().unwrap_or(f64::NAN);
            let std_error = ses.get(n).copied().flatten();
            (
                n.clone(),
                ParamEstimate::with_interval(value, value, std_error, t),
            )
        })
        .collect();
    let phys_expr = phys.expr();
    let phys_forms = forms(&phys_expr);
    let combined = combine(&phys, &correction, cfg.correction);
    let hybrid_expr =
        hxai_symreg::expr::Expr::from_program(&combined.program, &combined.params, &combined.names);
    let mut model = ProcessModel {
        schema_version: PROCESS_SCHEMA_VERSION,
        target: cfg.target.clone(),
        physics: PhysicsInfo {
            equation: cfg.physics.clone(),
            columns: res.columns.clone(),
            parameters,
            standard_errors: ses,
            calibrated: res.calibrate.clone(),
            initial: res.initial.clone(),
            sympy: phys_forms.sympy,
            latex: phys_forms.latex,
            params: physics_params,
        },
        correction: CorrectionInfo {
            kind: cfg.correction,
            equation: correction.equation(),
            sympy: correction.sympy(),
            latex: correction.latex(),
            complexity: correction.complexity(),
            features: correction.features(),
            candidates: res.features.clone(),
            model: correction,
            uncertainty: Some(correction_uncertainty),
            pareto: Some(crate::explain::ParetoMember::front(&found.pareto)),
        },
        hybrid: EquationInfo {
            uncertainty: Some(hybrid_uncertainty),
            ..forms(&hybrid_expr)
        },
        split: SplitInfo {
            kind: kind.to_string(),
            train: split.train.clone(),
            test: split.test.clone(),
        },
        group: cfg.group.clone(),
        joint,
        stability: None,
        scores: ScoresInfo {
            train: PairScores {
                physics: zero_metrics(),
                hybrid: zero_metrics(),
            },
            test: None,
        },
    };
    let pred = model.predict(table)?;
    let pair = |rows: &[usize]| -> Result<PairScores, HybridError> {
        let y = gather(y_all, rows);
        Ok(PairScores {
            physics: hxai_eval::score(&y, &gather(&pred.physics, rows))?,
            hybrid: hxai_eval::score(&y, &gather(&pred.hybrid, rows))?,
        })
    };
    model.scores.train = pair(&split.train)?;
    model.scores.test = if split.test.is_empty() {
        None
    } else {
        Some(pair(&split.test)?)
    };
    Ok(model)
}

/// `delta` on the training rows with the final physics parameters (those of the joint refit
/// when there was one), the target of the correction's uncertainty.
fn delta_train(
    cfg: &ProcessConfig,
    y_all: &[f64],
    physics: &[f64],
    split: &Split,
) -> Result<Vec<f64>, HybridError> {
    deltas(cfg.correction, y_all, physics, &split.train)
}

/// The hybrid as one template over the columns, the calibrated parameters (by name) and
/// the correction's free constants (those that are not whole or half numbers, named `p0`,
/// `p1`, ... past the names already taken), with their covariance at the model's values on
/// the training rows.
fn hybrid_uncertainty(
    table: &Table,
    res: &Resolved,
    phys: &Compiled,
    correction: &hxai_symreg::Model,
    cfg: &ProcessConfig,
    split: &Split,
    y_train: &[f64],
) -> Result<Uncertainty, HybridError> {
    let c = combine(phys, correction, cfg.correction);
    let mut slots = calibrated_slots(res, phys, &c);
    let mut names: Vec<String> = res.calibrate.clone();
    let mut taken: Vec<String> = c.names.clone();
    taken.extend(phys.slots.keys().cloned());
    let free: Vec<usize> = c
        .corr_map
        .iter()
        .enumerate()
        .filter(|(i, _)| !hxai_symreg::uncertainty::is_exact(correction.params[*i]))
        .map(|(_, &ci)| ci)
        .collect();
    names.extend(hxai_symreg::uncertainty::parameter_names(
        free.len(),
        &taken,
    ));
    slots.extend(free.iter().map(|&i| vec![i]));
    let all = columns_of(table, &c.names, "column")?;
    let cols: Vec<Vec<f64>> = all.iter().map(|col| gather(col, &split.train)).collect();
    let cols: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    let cov = hxai_symreg::uncertainty::covariance(
        &c.program,
        &c.params,
        hxai_symreg::fit::Unknowns::Tied(&slots),
        &cols,
        y_train,
    );
    Ok(Uncertainty::build(
        &c.program, &c.params, &c.params, &c.names, names, slots, &cov,
    ))
}

fn zero_metrics() -> hxai_eval::Metrics {
    hxai_eval::Metrics {
        r2: 0.0,
        rmse: 0.0,
        mae: 0.0,
    }
}

fn train_rmse(
    table: &Table,
    res: &Resolved,
    phys: &Compiled,
    correction: &hxai_symreg::Model,
    kind: CorrectionForm,
    split: &Split,
    y_train: &[f64],
) -> Result<f64, HybridError> {
    let p = physics_values(table, res, phys)?;
    let d = correction.predict(table)?;
    let h: Vec<f64> = split
        .train
        .iter()
        .map(|&i| combine_values(kind, p[i], d[i]))
        .collect();
    Ok(hxai_eval::rmse(y_train, &h)?)
}
