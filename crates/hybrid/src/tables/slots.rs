//! Learned slots inside the physics (issue 66): in `A*exp(-((E - E0)/w)^2)*f(C)` the call
//! `f(C)` of a name that is neither a known function nor a column nor a parameter is a
//! function of the listed columns that the data are to write.
//!
//! [`super::fit`], [`super::fit_split`] and [`super::compare`] find the slots
//! ([`hxai_symreg::infix::parse_with_slots`]) and fit them by backfitting on the training
//! rows, jointly with the calibration:
//! 1. every slot starts at 1 (the neutral factor);
//! 2. the physics is calibrated with the slots' values held;
//! 3. each slot in turn is searched on its partial residual: with the others held, the
//!    physics is linear in the slot near its values, `y ~ a + b s` (`b` the derivative by
//!    central differences, exact where the slot enters as a term or a factor), so the slot
//!    is fitted to `(y - a)/b` with each row weighed by `b^2`, the target's own units;
//! 4. 2 and 3 repeat until the training error falls by less than [`MIN_GAIN`] in a round
//!    (at most [`MAX_ROUNDS`]); the best round is kept.
//!
//! The form is the correction's rules: `factors` (the default and `auto`: one closed-form
//! factor per column, forward-selected under cross-validation, harmonics only on
//! `--periodic` columns; fitted in the target's units through the factor form's own
//! weighting, [`hxai_symreg::factors::fit_factors_on_physics`]) or `free` (the search over
//! the slot's columns, on the rows where the slot moves the physics most, `|b|` at least a
//! quarter of its largest: the free search takes no row weights). The slot's structure is
//! then written into the physics with its constants as parameters (`f_c0`, `f_c1`, ...,
//! small integers kept as structure) that are calibrated with the physics' own: every
//! constant is refitted jointly by the calibration's Levenberg-Marquardt, with standard
//! errors, and the model file's `physics.equation` is the hybrid's physics with the slots
//! substituted. `slots` in the model file ([`SlotInfo`]) says what each slot became.

pub use super::model::SlotInfo;
use super::physics::{calibrate_physics, gather, named_values};
use super::resolve::{cols_list, edit_distance, resolve};
use super::{Form, TableConfig, TableProgress, ValidTable};
use crate::HybridError;
use hxai_symreg::Table;
use hxai_symreg::expr::Expr;
use hxai_symreg::factors::Link;
use hxai_symreg::infix::{SlotCall, parse_with_slots};
use hxai_symreg::{Op, ParamEstimate};
use std::collections::BTreeMap;

/// Most backfitting rounds of calibration and slot searches.
pub const MAX_ROUNDS: usize = 8;

/// A round that lowers the training error by less than this share ends the backfitting.
pub const MIN_GAIN: f64 = 1e-3;

/// The infix functions, which a slot's name must not be one letter from.
const FUNCTIONS: [&str; 10] = [
    "exp", "log", "ln", "sqrt", "sin", "cos", "tan", "tanh", "abs", "Abs",
];

/// Share of the largest `|b|` (how much the slot moves the physics) below which a row is
/// left out of a free-form slot's search.
const FREE_ROWS: f64 = 0.25;

/// A physics with slots written out: the configuration to fit (the physics with every slot
/// substituted, the slots' constants among the calibrated parameters) and the slots.
#[derive(Clone, Debug)]
pub(crate) struct Expanded {
    pub(crate) cfg: ValidTable,
    slots: Vec<SlotInfo>,
}

impl Expanded {
    /// The slots with their constants as calibrated in the fitted model: `params` its
    /// calibrated parameters' estimates, `values` every parameter's value (the model
    /// file's `physics.params` and `physics.parameters`).
    pub(crate) fn finished(
        &self,
        params: &BTreeMap<String, ParamEstimate>,
        values: &BTreeMap<String, f64>,
    ) -> Vec<SlotInfo> {
        let mut slots = self.slots.clone();
        for s in &mut slots {
            let names: Vec<String> = s.uncertainty.keys().cloned().collect();
            for n in names {
                if let Some(p) = params.get(&n) {
                    s.uncertainty.insert(n, p.clone());
                }
            }
            s.equation = hxai_symreg::infix::parse(&s.template)
                .map(|p| {
                    substitute(&p.expr, &|n| values.get(n).map(|v| Expr::Num(*v)))
                        .simplify()
                        .to_text(Some(4), false)
                })
                .unwrap_or_default();
        }
        slots
    }
}

/// The slots of `cfg`'s physics fitted on the training rows `train` of `table`; `None`
/// when the physics has none.
///
/// # Errors
/// A slot named as a column or a parameter, over a column the table lacks or over the
/// target, with `--form none`; the calibration's and the slot searches' errors.
pub(crate) fn expand(
    table: &Table,
    cfg: &ValidTable,
    train: &[usize],
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<Option<Expanded>, HybridError> {
    let (parsed, calls) =
        parse_with_slots(&cfg.physics).map_err(|source| HybridError::Equation {
            equation: cfg.physics.clone(),
            source,
        })?;
    if calls.is_empty() {
        return Ok(None);
    }
    check_calls(table, cfg, &calls)?;
    let form = match cfg.form {
        Form::None => {
            return Err(HybridError::InvalidConfig(format!(
                "the physics has learned slot(s) ({}) but --form none learns nothing: use auto, \
                 factors or free",
                names(&calls)
            )));
        }
        Form::Free => Form::Free,
        Form::Factors | Form::Auto => Form::Factors,
    };
    // the physics with each slot a column of its own, held while the physics is calibrated
    let mut held = table.clone();
    for c in &calls {
        held.push_column(c.name.clone(), vec![1.0; table.n_rows()])
            .map_err(|e| HybridError::InvalidConfig(e.to_string()))?;
    }
    let mut inner: TableConfig = cfg.config().clone();
    inner.physics = parsed.expr.to_text(None, false);
    inner.features = Some(calls[0].columns.clone());
    let y = gather(table.require(&cfg.target)?, train);
    let mut fits: Vec<Option<Expr>> = vec![None; calls.len()];
    let mut best: Option<Round> = None;
    let mut rounds = 0;
    for round in 1..=MAX_ROUNDS {
        rounds = round;
        let res = resolve(&held, &inner)?;
        let (phys, _) = calibrate_physics(&held, &inner, &res, train)?;
        let values = named_values(&phys);
        for p in &inner.calibrate {
            if let Some(v) = values.get(p) {
                inner.init.insert(p.clone(), *v);
            }
        }
        let cols: Vec<Vec<f64>> = res
            .columns
            .iter()
            .map(|c| held.require(c).map(|v| gather(v, train)))
            .collect::<Result<_, _>>()?;
        for (j, call) in calls.iter().enumerate() {
            let at = res.columns.iter().position(|c| *c == call.name);
            let (a, b) = linearised(&phys, &cols, at, train.len());
            let label = format!("slot {} (round {round})", call.name);
            let expr = fit_slot(
                table,
                cfg,
                call,
                form,
                train,
                (&y, &a, &b),
                &label,
                progress,
            )?;
            let values = eval_on(&expr, table)?;
            held.remove_column(&call.name)
                .and_then(|_| held.push_column(call.name.clone(), values))
                .map_err(|e| HybridError::InvalidConfig(e.to_string()))?;
            fits[j] = Some(expr);
        }
        let cols: Vec<Vec<f64>> = res
            .columns
            .iter()
            .map(|c| held.require(c).map(|v| gather(v, train)))
            .collect::<Result<_, _>>()?;
        let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
        let p = phys.eval_columns(&refs, train.len());
        let mse = p.iter().zip(&y).map(|(p, y)| (y - p).powi(2)).sum::<f64>() / y.len() as f64;
        let last = best.as_ref().map_or(f64::INFINITY, |b| b.0);
        if mse.is_finite() && mse < last {
            best = Some((mse, fits.clone(), inner.init.clone()));
        }
        if mse.is_nan() || mse >= last * (1.0 - MIN_GAIN) {
            break;
        }
    }
    let Some((_, fits, init)) = best else {
        return Err(HybridError::NoData(format!(
            "the learned slot(s) {} gave no finite fit on the training rows",
            names(&calls)
        )));
    };
    let taken: Vec<String> = table
        .names()
        .iter()
        .chain(parsed.positions.iter().map(|(n, _)| n))
        .cloned()
        .collect();
    let mut out = cfg.config().clone();
    out.init.extend(init);
    let mut slots = Vec::new();
    let mut templates = BTreeMap::new();
    for (call, fit) in calls.iter().zip(fits) {
        let fit = fit.unwrap_or(Expr::Num(1.0));
        let (template, constants) = named_constants(&fit, &call.name, &taken);
        for (n, v) in &constants {
            out.calibrate.push(n.clone());
            out.init.insert(n.clone(), *v);
        }
        slots.push(SlotInfo {
            name: call.name.clone(),
            columns: call.columns.clone(),
            form: form.name().to_string(),
            template: template.to_text(None, false),
            equation: fit.to_text(Some(4), false),
            uncertainty: constants
                .iter()
                .map(|(n, v)| (n.clone(), ParamEstimate::with_interval(*v, *v, None, 0.0)))
                .collect(),
            rounds,
        });
        templates.insert(call.name.clone(), template);
    }
    out.physics = substitute(&parsed.expr, &|n| templates.get(n).cloned()).to_text(None, false);
    hold_undetermined(table, &mut out, &mut slots, train)?;
    let cfg = out.check()?;
    Ok(Some(Expanded { cfg, slots }))
}

/// Fixes at their values the slots' constants that the rows cannot tell apart from the
/// physics' own parameters (a slot's scale beside the law's `A` in `A*f(C)`): they move
/// from the calibrated parameters to the fixed ones, so the physics' parameters keep
/// their standard errors. Where the rows determine no parameter at all (as many
/// parameters as rows), nothing is fixed.
fn hold_undetermined(
    table: &Table,
    cfg: &mut TableConfig,
    slots: &mut [SlotInfo],
    train: &[usize],
) -> Result<(), HybridError> {
    let res = resolve(table, cfg)?;
    let (phys, ses) = calibrate_physics(table, cfg, &res, train)?;
    if ses.values().all(Option::is_none) {
        return Ok(());
    }
    let values = named_values(&phys);
    for s in slots {
        for (n, est) in &mut s.uncertainty {
            if ses.get(n).is_some_and(Option::is_none) {
                let v = values.get(n).copied().unwrap_or(est.value);
                cfg.calibrate.retain(|c| c != n);
                cfg.init.remove(n);
                cfg.set.insert(n.clone(), v);
                *est = ParamEstimate::with_interval(v, v, None, 0.0);
            }
        }
    }
    Ok(())
}

/// A backfitting round's result: its training mean squared error, each slot's expression
/// and the calibrated parameters' values.
type Round = (f64, Vec<Option<Expr>>, BTreeMap<String, f64>);

/// The slots' names, comma-separated.
fn names(calls: &[SlotCall]) -> String {
    calls
        .iter()
        .map(|c| c.name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

/// Refuses a slot named as a column or a parameter, or over a column the table lacks or
/// over the target.
fn check_calls(table: &Table, cfg: &TableConfig, calls: &[SlotCall]) -> Result<(), HybridError> {
    for c in calls {
        // a misspelt function is not a slot: `sqr(f)` is refused, not learned
        if let Some(f) = FUNCTIONS.iter().find(|f| edit_distance(f, &c.name) <= 1) {
            return Err(HybridError::Equation {
                equation: cfg.physics.clone(),
                source: hxai_symreg::SrError::Parse {
                    position: c.position,
                    message: format!(
                        "unknown function `{}` (one letter from `{f}`): use exp, log, sqrt, \
                         sin, cos, tan, tanh or abs; a learned slot needs a name that is not one \
                         letter from a function (`g(...)`)",
                        c.name
                    ),
                },
            });
        }
        let as_param = cfg.calibrate.contains(&c.name) || cfg.set.contains_key(&c.name);
        if table.column(&c.name).is_some() || as_param {
            return Err(HybridError::InvalidConfig(format!(
                "`{}(...)` at character {} is a learned slot, but `{}` is also a {}: name the \
                 slot otherwise",
                c.name,
                c.position,
                c.name,
                if as_param { "parameter" } else { "column" }
            )));
        }
        for col in &c.columns {
            if *col == cfg.target {
                return Err(HybridError::InvalidConfig(format!(
                    "the slot `{}` reads the target `{col}`: a slot is a function of inputs",
                    c.name
                )));
            }
            if table.column(col).is_none() {
                return Err(HybridError::MissingColumn {
                    what: "slot column",
                    name: col.clone(),
                    columns: cols_list(table),
                });
            }
        }
    }
    Ok(())
}

/// The physics near the slot's current values, `p ~ a + b s` on each row: `b` by central
/// differences in the slot's column `at` (of `cols`), `a = p - b s`. `(p, 0)` where the
/// physics does not read the slot.
fn linearised(
    phys: &hxai_symreg::infix::Compiled,
    cols: &[Vec<f64>],
    at: Option<usize>,
    n: usize,
) -> (Vec<f64>, Vec<f64>) {
    let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    let p = phys.eval_columns(&refs, n);
    let Some(at) = at else {
        return (p, vec![0.0; n]);
    };
    let s = &cols[at];
    let h: Vec<f64> = s.iter().map(|v| 1e-4 * v.abs().max(1.0)).collect();
    let moved = |sign: f64| {
        let col: Vec<f64> = s.iter().zip(&h).map(|(v, h)| v + sign * h).collect();
        let mut refs = refs.clone();
        refs[at] = &col;
        phys.eval_columns(&refs, n)
    };
    let (up, down) = (moved(1.0), moved(-1.0));
    let b: Vec<f64> = (0..n).map(|i| (up[i] - down[i]) / (2.0 * h[i])).collect();
    let a = (0..n).map(|i| p[i] - b[i] * s[i]).collect();
    (a, b)
}

/// One slot searched on its partial residual: `target = (a, b)` with `y ~ a + b s` on the
/// training rows; the slot's expression over its columns.
#[allow(clippy::too_many_arguments)]
fn fit_slot(
    table: &Table,
    cfg: &ValidTable,
    call: &SlotCall,
    form: Form,
    train: &[usize],
    (y, a, b): (&[f64], &[f64], &[f64]),
    label: &str,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<Expr, HybridError> {
    let ok = |b: f64| b.is_finite() && b != 0.0;
    let data = table.select_columns(&call.columns)?;
    if form == Form::Factors {
        // y - a = b (1 + delta): the factor form's multiplicative fit with `b` as physics
        let delta: Vec<f64> = (0..y.len())
            .map(|i| {
                if ok(b[i]) {
                    (y[i] - a[i]) / b[i] - 1.0
                } else {
                    0.0
                }
            })
            .collect();
        let scale: Vec<f64> = b.iter().map(|&b| if ok(b) { b } else { 0.0 }).collect();
        let fit = hxai_symreg::factors::fit_factors_on_physics(
            &data.select_rows(train)?,
            &delta,
            &scale,
            Link::Multiplicative,
            &cfg.factor_config(&call.columns),
        )?;
        return Ok(one_plus(fit.model.expr()));
    }
    let largest = b.iter().map(|b| b.abs()).fold(0.0, f64::max);
    let rows: Vec<usize> = (0..y.len())
        .filter(|&i| ok(b[i]) && b[i].abs() >= FREE_ROWS * largest)
        .collect();
    let target: Vec<f64> = rows.iter().map(|&i| (y[i] - a[i]) / b[i]).collect();
    let picked: Vec<usize> = rows.iter().map(|&i| train[i]).collect();
    let found = hxai_symreg::search_checked(
        &data.select_rows(&picked)?,
        &target,
        cfg.search(),
        &mut |p| {
            progress(&TableProgress {
                task: 1,
                tasks: 1,
                label: label.to_string(),
                search: p.clone(),
                step: false,
            })
        },
    )?;
    Ok(found.best.expr())
}

/// `1 + e`, where a multiplicative factor model writes `C prod f - 1`.
fn one_plus(e: Expr) -> Expr {
    match e {
        Expr::Bin(Op::Sub, a, b) if *b == Expr::Num(1.0) => *a,
        Expr::Bin(Op::Add, a, b) if *b == Expr::Num(-1.0) => *a,
        e => Expr::Bin(Op::Add, Box::new(e), Box::new(Expr::Num(1.0))).simplify(),
    }
}

/// The values of `e` on every row of `table`.
fn eval_on(e: &Expr, table: &Table) -> Result<Vec<f64>, HybridError> {
    fn vars<'e>(e: &'e Expr, out: &mut Vec<&'e str>) {
        match e {
            Expr::Var(n) => out.push(n),
            Expr::Num(_) => {}
            Expr::Neg(a) | Expr::Un(_, a) => vars(a, out),
            Expr::Bin(_, a, b) => {
                vars(a, out);
                vars(b, out);
            }
        }
    }
    let mut read = Vec::new();
    vars(e, &mut read);
    let mut cols: BTreeMap<&str, &[f64]> = BTreeMap::new();
    for n in read {
        let col = table.column(n).ok_or_else(|| {
            HybridError::InvalidConfig(format!(
                "a slot's equation reads `{n}`, which the table lacks"
            ))
        })?;
        cols.insert(n, col);
    }
    Ok((0..table.n_rows())
        .map(|i| e.eval(&|n| cols.get(n).map_or(f64::NAN, |c| c[i])))
        .collect())
}

/// `e` with every variable `rename` maps replaced by its expression.
fn substitute(e: &Expr, rename: &dyn Fn(&str) -> Option<Expr>) -> Expr {
    match e {
        Expr::Var(n) => rename(n).unwrap_or_else(|| e.clone()),
        Expr::Num(_) => e.clone(),
        Expr::Neg(a) => Expr::Neg(Box::new(substitute(a, rename))),
        Expr::Un(op, a) => Expr::Un(*op, Box::new(substitute(a, rename))),
        Expr::Bin(op, a, b) => Expr::Bin(
            *op,
            Box::new(substitute(a, rename)),
            Box::new(substitute(b, rename)),
        ),
    }
}

/// `e` with its fitted constants named `{slot}_c0`, `{slot}_c1`, ... (a name the table or
/// the physics already uses gets a `_` appended until free); small integers (|v| <= 4)
/// stay numbers, as structure. The template and each constant's value.
fn named_constants(e: &Expr, slot: &str, taken: &[String]) -> (Expr, Vec<(String, f64)>) {
    fn walk(e: &Expr, out: &mut Vec<(String, f64)>, name: &dyn Fn(usize) -> String) -> Expr {
        match e {
            Expr::Num(v) if v.fract() == 0.0 && v.abs() <= 4.0 => e.clone(),
            Expr::Num(v) => {
                let n = name(out.len());
                out.push((n.clone(), *v));
                Expr::Var(n)
            }
            Expr::Var(_) => e.clone(),
            Expr::Neg(a) => Expr::Neg(Box::new(walk(a, out, name))),
            Expr::Un(op, a) => Expr::Un(*op, Box::new(walk(a, out, name))),
            Expr::Bin(op, a, b) => Expr::Bin(
                *op,
                Box::new(walk(a, out, name)),
                Box::new(walk(b, out, name)),
            ),
        }
    }
    let name = |k: usize| {
        let mut n = format!("{slot}_c{k}");
        while taken.contains(&n) {
            n.push('_');
        }
        n
    };
    let mut out = Vec::new();
    let t = walk(e, &mut out, &name);
    (t, out)
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
#[path = "slots_tests.rs"]
mod tests;
