//! Corrections an engineer writes: one factor per effect.
//!
//! An engineer writes a correction as a product of correction factors, one per influence
//! (Kienzle's `K_gamma * K_v * K_VB`, the extended Taylor law, Arrhenius' temperature
//! factor), or as a sum of such terms for an additive error. [`fit_factors`] finds that
//! form for a target `y` (a hybrid's `delta`) over feature columns:
//! - additive ([`Link::Additive`]): `y = c + sum_j a_j s_j(x_j) [+ a x_i^p x_k^q]`;
//! - multiplicative ([`Link::Multiplicative`]): `y = C prod_j f_j(x_j) [(1 + a x_i^p x_k^q)] - 1`,
//!   so that the hybrid `f_p (1 + y)` is the physics times its factors;
//! - log ([`Link::Log`]): `y = log(C prod_j f_j(x_j) ...)`, the same product fitted on the
//!   log scale, so that `f_p exp(y)` is again the physics times its factors.
//!
//! Each factor is a short law of one column ([`Shape`]: power, linear, exponential,
//! logarithm, one pole, a saturation, one harmonic `sin(w x + c)` for an effect that
//! repeats over its column), of complexity at most 4; an interaction factor is a product
//! of powers of two columns (complexity 5). No factor holds a transcendental inside a
//! transcendental (so a log correction has no harmonic).
//!
//! How the factors are found (the design of issue 46, after InterpretML's Explainable
//! Boosting Machine, whose shape functions are here closed forms):
//! 1. **Forward selection by cross-validation.** The rows are split into `folds` folds
//!    once. At each step every column not yet in the model is tried with every shape: the
//!    new term starts from the partial residual (a sum's amplitude by projection on it;
//!    several starting values of the shape's own constant), then every constant of the
//!    model is refitted jointly by Levenberg-Marquardt on all rows, and the model is scored
//!    by each row's held-out squared error (refitted on each fold's training rows). For
//!    each column the shape is the earliest in [`Shape::MAIN`]'s order whose held-out error
//!    is within `se_rule` paired standard errors of that column's best shape (power laws
//!    first); the column with the lowest held-out error enters, while it lowers it.
//! 2. **The one-standard-error rule** along the path: the model kept is the one with the
//!    fewest factors whose held-out error is within `se_rule` paired standard errors of the
//!    lowest; a factor is kept only where it pays.
//! 3. **Interactions**, after the main effects: every pair of columns is ranked by FAST on
//!    the main factors' residual (`fast.rs`: the best two-by-two piecewise-constant cut of
//!    the pair, the ranking EBM uses), the best three are fitted as pair factors and scored
//!    by cross-validation, and the best is kept only if it lowers the held-out error by
//!    more than `interaction_se` paired standard errors; then one-column factors the
//!    interaction made redundant are dropped by the same one-standard-error rule; repeated
//!    up to `interactions` times.
//! 4. **Exponents snap** to the nearest whole or half number where the Bayesian
//!    information criterion allows it.
//! 5. **Consensus** (`consensus` > 0, `--consensus N`): the selection runs again on `N`
//!    bootstrap resamples and the factor set most of them give back is kept
//!    (`consensus.rs`).
//!
//! The shapes are enumerated, not evolved: a one-column law of complexity at most 4 has a
//! handful of forms, all of which are fitted, so the choice is exhaustive and does not
//! depend on a random search (Bartlett et al.'s exhaustive symbolic regression argues the
//! same for short equations). Results depend only on the data and `seed` (the folds), never
//! on the thread count: parallel loops collect in index order.
//!
//! Files by job: this file the settings, the result and the entry points; `shape.rs` the
//! shapes and how a factor is written; `structure.rs` a model as one program, its fit and
//! its held-out errors; `select.rs` the selection; `consensus.rs` the consensus over
//! resamples; `bands.rs` the stability over resamples.
mod bands;
mod consensus;
mod fast;
mod select;
mod shape;
mod structure;

pub use crate::bootstrap::FactorBand;
pub use bands::{FactorStability, factor_stability, factor_stability_on_physics};
pub use consensus::ConsensusShare;
pub use shape::{Shape, Shapes, complexity, template};

use crate::expr::Expr;
use crate::{Model, Par, SrError, Table};
use serde::{Deserialize, Serialize};
use shape::{Builder, Term};
use structure::Structure;

/// How the factors combine into the target.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Link {
    /// `y = c + sum_j a_j s_j(x_j)`.
    Additive,
    /// `y = C prod_j f_j(x_j) - 1`.
    Multiplicative,
    /// `y = log(C prod_j f_j(x_j))`.
    Log,
}

/// Settings of [`fit_factors`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FactorConfig {
    /// Folds of the cross-validation that scores every candidate (default 5).
    pub folds: usize,
    /// Most one-column factors (default 8).
    pub max_factors: usize,
    /// Most interaction factors (default 1).
    pub interactions: usize,
    /// Standard errors of the one-standard-error rule (default 1).
    pub se_rule: f64,
    /// Paired standard errors an interaction must lower the held-out error by (default 2:
    /// an interaction is searched among every pair of columns, so it must pay more than a
    /// main effect).
    pub interaction_se: f64,
    /// Rounds of backfitting after each factor enters (default 2): every one-column
    /// factor's shape is chosen again, by the same rule, with the other factors in the
    /// model. A shape chosen when the column entered first was chosen against a residual
    /// that still held every other effect; 0 keeps the shapes of the entry.
    pub backfit_rounds: usize,
    /// The shapes a factor may take (default all; `hxai sr`'s power-law candidates leave
    /// out the shapes whose operators the user did not allow).
    pub shapes: Shapes,
    /// Which columns may take the harmonic shape [`Shape::Periodic`] (issue 64: harmonics
    /// only where declared): `None` any column (where `shapes` has it), `Some(mask)` only
    /// the columns whose bit is set (bit `j` for the data's column `j`; columns past the
    /// 64th never). The hybrid sets it from `--periodic`, so an undeclared column gets no
    /// sine.
    pub periodic: Option<u64>,
    /// Columns whose factor must not decrease over their training range (issue 68,
    /// `--monotone COL=+`): bit `j` for the data's column `j` (columns past the 64th are
    /// never constrained). A candidate structure whose correction, at a sample of the
    /// rows' other values, falls anywhere along such a column's grid is refused, in every
    /// shape and pair, in the forward steps, backfitting, interactions, the snapping of
    /// exponents and the refit on every row.
    pub increasing: u64,
    /// Columns whose factor must not increase ([`FactorConfig::increasing`]'s opposite,
    /// `--monotone COL=-`).
    pub decreasing: u64,
    /// Seed of the folds (and of the subsample of [`FactorConfig::max_rows`]).
    pub seed: u64,
    /// Threads of the parallel loops (results never depend on it).
    pub par: Par,
    /// Rows the structure is selected on (issue 67): with more, the forward selection,
    /// backfitting and alternatives run on a seeded sample of this many rows stratified on
    /// the target, with each column's extreme rows
    /// ([`hxai_eval::stratified_sample_spanning`]), and the selected structure's constants
    /// are then fitted on every row (default `usize::MAX`: every row).
    pub max_rows: usize,
    /// Bootstrap resamples of the consensus selection (issue 68, `--consensus N`): the
    /// factor set most of the selections on them and on every row give back is kept
    /// (default 0: the selection on every row alone).
    pub consensus: usize,
}

impl FactorConfig {
    /// Whether column `c` may take the harmonic shape ([`FactorConfig::periodic`]).
    pub fn harmonic_allowed(&self, c: usize) -> bool {
        match self.periodic {
            None => true,
            Some(mask) => c < 64 && mask & (1 << c) != 0,
        }
    }

    /// The mask of [`FactorConfig::periodic`] (or of [`FactorConfig::increasing`],
    /// [`FactorConfig::decreasing`]) for the `declared` columns among `columns` (the data's
    /// column names, in order).
    pub fn periodic_mask(columns: &[String], declared: &[String]) -> u64 {
        columns
            .iter()
            .enumerate()
            .filter(|(j, c)| *j < 64 && declared.contains(c))
            .fold(0, |m, (j, _)| m | (1 << j))
    }
}

impl Default for FactorConfig {
    fn default() -> Self {
        Self {
            folds: 5,
            max_factors: 8,
            interactions: 1,
            se_rule: 1.0,
            interaction_se: 2.0,
            backfit_rounds: 2,
            shapes: Shapes::CLASSIC,
            periodic: None,
            increasing: 0,
            decreasing: 0,
            seed: 42,
            par: Par::Current,
            max_rows: usize::MAX,
            consensus: 0,
        }
    }
}

/// One factor of a fitted model (JSON: an entry of `correction.factors`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Factor {
    /// The column of a one-column factor.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub column: Option<String>,
    /// The two columns of an interaction factor.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub columns: Option<Vec<String>>,
    /// The shape's name (`power`, `linear`, ..., `pair`).
    pub shape: Shape,
    /// The factor with its constants (a sum's term with its amplitude).
    pub equation: String,
    /// The factor's structure with constants `p0`, `p1`, ... ([`template`]).
    pub template: String,
    /// The factor's complexity ([`complexity`]).
    pub complexity: usize,
}

/// One model of the forward path: its factors' columns and its errors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PathStep {
    /// The columns of each factor, by index into the feature table.
    pub columns: Vec<Vec<usize>>,
    /// Mean held-out squared error.
    pub cv_mse: f64,
    /// Mean squared error on all rows.
    pub train_mse: f64,
    /// Whether this is the model selected.
    pub kept: bool,
}

/// What [`fit_factors`] returns.
#[derive(Clone, Debug, PartialEq)]
pub struct FactorFit {
    /// The model as one program over the feature table's columns (`score` is the mean
    /// held-out squared error, `train_mse` the error on all rows).
    pub model: Model,
    /// Its factors, in the order they entered.
    pub factors: Vec<Factor>,
    /// The overall constant (a sum's offset, a product's `C`).
    pub constant: f64,
    /// The forward path (each model's held-out error), the selected one marked.
    pub path: Vec<PathStep>,
    /// Models of the selected columns with another shape whose held-out error is within one
    /// standard error of the selected one's: the shapes the data cannot tell apart.
    pub alternatives: Vec<Model>,
    /// With [`FactorConfig::consensus`]: how many of the resamples' selections gave the
    /// kept factor set back.
    pub consensus: Option<ConsensusShare>,
}

/// Fits a factor model of `y` over every column of `data` (see the module docs).
///
/// # Errors
/// [`SrError::InvalidConfig`] for fewer than two folds, a target whose length is not the
/// table's, fewer rows than `2 * folds`, a value that is not finite, or a model that cannot
/// be fitted at all.
pub fn fit_factors(
    data: &Table,
    y: &[f64],
    link: Link,
    cfg: &FactorConfig,
) -> Result<FactorFit, SrError> {
    Ok(fit_structure(data, y, link, cfg, None, None)?.0)
}

/// [`fit_factors`] of a hybrid's correction `y` (its `delta`) with each row's physics
/// prediction `physics`: a multiplicative model is then fitted and scored with each row
/// weighed by the inverse of its scatter. A pilot is fitted by the hybrid's error in the
/// target's units, `f_p (1 + delta)` against `f_p (1 + y)`; the pilot's residuals tell how
/// the scatter grows with the physics (`Var ~ |f_p|^(2 theta)`, `theta` in [0, 1] by a
/// log-log regression); where `theta` is above 0.1 the model is selected again with the
/// weights `|f_p|^(2 - 2 theta)` on `delta` (at `theta` 1, `delta`'s own squared error).
/// Unweighted, the error of `delta` weighs every row by `f_p^2` less than the target does,
/// and with scatter in the target's units the rows of small physics decide the fit (R²
/// 0.03 on a roughness table); weighted in the target's units alone, scatter in proportion
/// (wear, cutting force) lets the rows of large physics decide it. (Additive and log models
/// are fitted as [`fit_factors`] does: an additive `delta` is already in the target's units,
/// and the log form is chosen for relative errors.) The model returned is the correction
/// `delta`; its `score` and `train_mse` and the path's errors are on the weighted scale.
///
/// # Errors
/// [`fit_factors`]'s, and a `physics` of another length or not finite.
pub fn fit_factors_on_physics(
    data: &Table,
    y: &[f64],
    physics: &[f64],
    link: Link,
    cfg: &FactorConfig,
) -> Result<FactorFit, SrError> {
    Ok(fit_structure(data, y, link, cfg, None, Some(physics))?.0)
}

/// [`fit_factors`], with the selected structure itself; `groups` (one id per row) keeps
/// rows sharing an id in one fold; `physics` as [`fit_factors_on_physics`].
fn fit_structure(
    data: &Table,
    y: &[f64],
    link: Link,
    cfg: &FactorConfig,
    groups: Option<&[usize]>,
    physics: Option<&[f64]>,
) -> Result<(FactorFit, Structure), SrError> {
    check(data, y, cfg)?;
    let all_cols: Vec<&[f64]> = data.columns().iter().map(Vec::as_slice).collect();
    let physics = physics.filter(|_| link == Link::Multiplicative);
    if let Some(fp) = physics {
        if fp.len() != y.len() {
            return Err(SrError::TargetLength {
                target: fp.len(),
                data: y.len(),
            });
        }
        if let Some(i) = fp.iter().position(|v| !v.is_finite()) {
            return Err(SrError::InvalidConfig(format!(
                "the physics is not finite at row {} ({})",
                i + 1,
                fp[i]
            )));
        }
    }
    // the structure is selected on at most `max_rows` rows (stratified on the target),
    // its constants fitted again on every row below
    let rows = (y.len() > cfg.max_rows.max(2 * cfg.folds)).then(|| {
        hxai_eval::stratified_sample_spanning(
            y,
            cfg.max_rows.max(2 * cfg.folds),
            cfg.seed,
            &all_cols,
        )
    });
    let pick = |v: &[f64]| -> Vec<f64> {
        rows.as_ref()
            .map_or_else(|| v.to_vec(), |r| r.iter().map(|&i| v[i]).collect())
    };
    let sub_cols: Vec<Vec<f64>> = match &rows {
        Some(_) => all_cols.iter().map(|c| pick(c)).collect(),
        None => Vec::new(),
    };
    let cols: Vec<&[f64]> = match &rows {
        Some(_) => sub_cols.iter().map(Vec::as_slice).collect(),
        None => all_cols.clone(),
    };
    let (sub_y, sub_fp) = (pick(y), physics.map(pick));
    let sub_groups: Option<Vec<usize>> = groups.map(pick_rows(rows.as_deref()));
    let (y_s, groups_s) = (sub_y.as_slice(), sub_groups.as_deref());
    let select = |scale: Option<&[f64]>| -> Result<Selected, SrError> {
        let mut cols = cols.clone();
        let target: Vec<f64>;
        let (yy, at) = match scale {
            Some(sc) => {
                target = sc.iter().zip(y_s).map(|(s, d)| s * (1.0 + d)).collect();
                cols.push(sc);
                (target.as_slice(), Some(cols.len() - 1))
            }
            None => (y_s, None),
        };
        let problem = select::Problem::new(cols, yy, link, cfg, groups_s, at);
        let (chosen, path, mut alts) = problem.select().ok_or_else(|| {
            SrError::InvalidConfig("no factor model could be fitted to the rows".into())
        })?;
        let before = consensus::key(&chosen.s);
        let (chosen, share) = consensus::consensus(&problem, chosen);
        if consensus::key(&chosen.s) != before {
            // the alternatives were those of the set no longer kept
            alts.clear();
        }
        Ok((problem.snap(chosen), path, alts, share))
    };
    // the scale of the fit kept: the pilot's (the physics itself) or `|f_p|^(1 - theta)`
    let ((mut chosen, path, alts, share), theta) = match &sub_fp {
        Some(fp) => {
            // a pilot on the target's scale, then the scatter's growth with the physics
            // (the variance power) sets the weights of the fit that is kept
            let pilot = select(Some(fp))?;
            let delta = pilot.0.s.unscaled().predict(link, &cols, y_s.len());
            let measured: Vec<f64> = fp.iter().zip(y_s).map(|(p, d)| p * (1.0 + d)).collect();
            let theta = variance_power(fp, &measured, &delta);
            if theta > VARIANCE_POWER_STEP {
                (
                    select(Some(&weight_scale(fp, Some(theta))))?,
                    Some(Some(theta)),
                )
            } else {
                (pilot, Some(None))
            }
        }
        None => (select(None)?, None),
    };
    if rows.is_some() {
        // every row: the selected structure's free constants fitted again, from the
        // subsample's values (kept when the refit fails)
        let mut cols = all_cols.clone();
        let scale: Option<Vec<f64>> = match (physics, theta) {
            (Some(fp), Some(t)) => Some(weight_scale(fp, t)),
            _ => None,
        };
        let target: Vec<f64>;
        let yy = match &scale {
            Some(sc) => {
                target = sc.iter().zip(y).map(|(s, d)| s * (1.0 + d)).collect();
                cols.push(sc);
                target.as_slice()
            }
            None => y,
        };
        let mut s = chosen.s.clone();
        let mse = s.fit_any_period(link, &cols, yy);
        if mse.is_finite() && s.monotone(link, &cols, cfg.increasing, cfg.decreasing) {
            chosen.s = s;
            chosen.mse = mse;
        }
    }
    chosen.s = chosen.s.unscaled();
    let names = data.names();
    let mut model = model_of(&chosen.s, link, names)?;
    model.train_mse = chosen.mse;
    model.score = chosen.cv_mean();
    let alternatives = alts
        .iter()
        .map(|a| model_of(&a.s.unscaled(), link, names))
        .collect::<Result<Vec<_>, _>>()?;
    let fit = FactorFit {
        factors: chosen
            .s
            .terms
            .iter()
            .map(|t| factor_of(t, link, names))
            .collect(),
        constant: chosen.s.constant,
        model,
        path,
        alternatives,
        consensus: share,
    };
    Ok((fit, chosen.s))
}

/// The scale column of a multiplicative fit weighed by the hybrid's error: the physics
/// itself for the pilot (`theta` `None`), `|f_p|^(1 - theta)` for the fit kept.
fn weight_scale(fp: &[f64], theta: Option<f64>) -> Vec<f64> {
    match theta {
        None => fp.to_vec(),
        Some(t) => fp.iter().map(|p| p.abs().powf(1.0 - t)).collect(),
    }
}

/// Picks the entries of `rows` (all of them without rows) from a slice of group ids.
fn pick_rows(rows: Option<&[usize]>) -> impl Fn(&[usize]) -> Vec<usize> + '_ {
    move |g| rows.map_or_else(|| g.to_vec(), |r| r.iter().map(|&i| g[i]).collect())
}

/// A selection's result: the chosen structure (scored), the path, the alternatives and the
/// consensus' share.
type Selected = (
    select::Scored,
    Vec<PathStep>,
    Vec<select::Scored>,
    Option<ConsensusShare>,
);

/// Variance powers at or below this are taken for 0 (the pilot's weights are kept).
const VARIANCE_POWER_STEP: f64 = 0.1;

/// How the scatter of a multiplicative hybrid grows with its physics: `theta` in
/// `Var(y - f_p (1 + delta)) ~ |f_p|^(2 theta)`, the slope of `log r^2` on `log |f_p|` over
/// the rows, halved and kept within [0, 1] (0: scatter in the target's units, as a gauge's;
/// 1: scatter in proportion, as tool life's and wear's). 0 where it cannot be told (fewer
/// than 8 usable rows, or physics within a factor 1.5 over the rows). The fit that is kept
/// weighs each row's `delta` by `|f_p|^(2 - 2 theta)`, the inverse of its variance.
fn variance_power(fp: &[f64], y: &[f64], delta: &[f64]) -> f64 {
    let pts: Vec<(f64, f64)> = fp
        .iter()
        .zip(y)
        .zip(delta)
        .filter_map(|((&p, &yy), &d)| {
            let r = yy - p * (1.0 + d);
            (p != 0.0 && r != 0.0 && r.is_finite()).then(|| (p.abs().ln(), (r * r).ln()))
        })
        .collect();
    if pts.len() < 8 {
        return 0.0;
    }
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let spread = pts.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max)
        - pts.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
    if spread < 1.5f64.ln() || sxx <= 0.0 {
        return 0.0;
    }
    (0.5 * sxy / sxx).clamp(0.0, 1.0)
}

fn check(data: &Table, y: &[f64], cfg: &FactorConfig) -> Result<(), SrError> {
    if cfg.folds < 2 {
        return Err(SrError::InvalidConfig(
            "the factor form needs at least 2 folds".into(),
        ));
    }
    if y.len() != data.n_rows() {
        return Err(SrError::TargetLength {
            target: y.len(),
            data: data.n_rows(),
        });
    }
    if y.len() < 2 * cfg.folds {
        return Err(SrError::InvalidConfig(format!(
            "the factor form needs at least {} rows for {} folds, got {}",
            2 * cfg.folds,
            cfg.folds,
            y.len()
        )));
    }
    if let Some(i) = y.iter().position(|v| !v.is_finite()) {
        return Err(SrError::InvalidConfig(format!(
            "the target is not finite at row {} ({})",
            i + 1,
            y[i]
        )));
    }
    for (name, col) in data.names().iter().zip(data.columns()) {
        if let Some(i) = col.iter().position(|v| !v.is_finite()) {
            return Err(SrError::InvalidConfig(format!(
                "column {name} is not finite at row {} ({})",
                i + 1,
                col[i]
            )));
        }
    }
    Ok(())
}

/// The model of a structure, over every column of the table (only the factors' columns
/// appear in the program).
fn model_of(s: &Structure, link: Link, names: &[String]) -> Result<Model, SrError> {
    let w = s.write(link);
    Model::new(names.to_vec(), w.program, w.params)
}

/// A factor alone, written with its constants.
fn factor_of(t: &Term, link: Link, names: &[String]) -> Factor {
    let mut b = Builder::default();
    let mut local = t.clone();
    local.cols = (0..t.cols.len()).collect();
    shape::emit(&local, link, &|c| c as u16, &mut b);
    let own: Vec<String> = t.cols.iter().map(|&c| names[c].clone()).collect();
    let mut params = vec![1.0, 0.0];
    params.extend(b.consts);
    let program = crate::Program {
        nodes: b.nodes,
        affine: false,
    };
    let equation = Expr::from_program(&program, &params, &own).to_text(Some(4), false);
    let refs: Vec<&str> = own.iter().map(String::as_str).collect();
    let (column, columns) = if own.len() == 1 {
        (Some(own[0].clone()), None)
    } else {
        (None, Some(own.clone()))
    };
    Factor {
        column,
        columns,
        shape: t.shape,
        equation,
        template: template(t.shape, &refs),
        complexity: complexity(t.shape),
    }
}

#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_shapes;
