//! What to measure next (`hxai hybrid design`, issue 49, first part): the settings of the
//! next N runs, chosen inside the space the user can run, to settle what the data cannot.
//!
//! Candidates are the rows of a CSV of feasible settings, or 4,000 seeded random points of
//! the ranges given (`col=lo:hi`, with `:step` snapping a column to its levels, `col=a|b|c`
//! for a list of values), so a proposal never leaves the space. Two goals:
//!
//! - `discriminate` (the default when the model file has alternatives the data cannot tell
//!   apart from the selected correction): the hybrid is evaluated with the selected
//!   correction and with each alternative; a run is worth what the equations disagree there
//!   (`spread`, the largest prediction minus the smallest), so the first pick is the
//!   candidate of largest spread, and each further pick the one of largest spread times
//!   `d / (d + 0.1)`, `d` its distance (inputs scaled to the space's ranges) to the runs
//!   already picked: greedy sequential choice with earlier picks fixed, in the spirit of
//!   T-optimality (Atkinson and Fedorov 1975). Where the model file has the covariance of
//!   the hybrid's constants, the spread is replaced by Box and Hill's (1967) criterion: a
//!   candidate is worth, summed over pairs of equations, `(v_a - v_b)^2 / (v_a v_b) +
//!   (y_a - y_b)^2 (1/v_a + 1/v_b)`, `v` the variance of a run's outcome under each
//!   equation there: the residual variance plus its correction constants' `g^T C g` on the
//!   hybrid's scale, from each equation's own covariance (the file stores each
//!   alternative's since 2026-12-02; for an older file, every equation is given the
//!   selected hybrid's).
//! - `coverage`: where the model is least sure and the runs are sparse: the first pick is the
//!   candidate of widest prediction interval (the model's own method, conformal where it
//!   stores the calibration), then each further pick the candidate farthest from the runs
//!   picked (space-filling, maximin), times `0.5 + 0.5 w / w_max` so that among far
//!   candidates the wider intervals win. A model without intervals uses the distance alone.
//!
//! - `precision`: Ds-optimal for the calibrated physics parameters (the correction's
//!   constants nuisance parameters), from the model file's covariance.
//!
//! The space (ranges or a CSV of settings) and its candidates are `space`'s. A model with
//! constants per level of a text column (`--calibrate-per`, `--correction-per`) is designed
//! over that column's levels too (`tool=A|B`, or the text column of a CSV of settings):
//! [`TableModel::add_levels`] gives the candidates the model's level indicators, which the
//! distances count like any other input scaled to its range.

mod space;
mod variance;

pub use space::{Candidates, RANDOM_CANDIDATES, SpaceColumn, candidates, parse_space};

use variance::{Gradients, box_hill, gradients, own_variances};

use super::TableModel;
use super::model::columns_of;
use super::model::combine_values;
use crate::HybridError;
use hxai_symreg::Table;

/// The distance (inputs scaled to the space's ranges) at which a pick's worth is halved.
const CLOSE: f64 = 0.1;

/// How to choose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DesignGoal {
    /// Separate the selected correction from its alternatives.
    Discriminate,
    /// Widest intervals, sparsest runs.
    Coverage,
    /// Ds-optimal for the calibrated physics parameters, the correction's constants as
    /// nuisance parameters: the runs that shrink the parameters' joint confidence region
    /// most, each chosen with the earlier picks counted as done.
    Precision,
}

impl DesignGoal {
    /// `discriminate` or `coverage`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Discriminate => "discriminate",
            Self::Coverage => "coverage",
            Self::Precision => "precision",
        }
    }
}

/// The runs proposed, best first.
#[derive(Clone, Debug, PartialEq)]
pub struct Proposal {
    /// The goal used (`discriminate` falls back to `precision` without alternatives, and
    /// to `coverage` when the model file has no covariance either).
    pub goal: DesignGoal,
    /// Candidate rows picked, in order.
    pub rows: Vec<usize>,
    /// The selected hybrid's prediction at each pick.
    pub predicted: Vec<f64>,
    /// Largest minus smallest prediction of the candidate equations at each pick (0 when the
    /// model has no alternatives).
    pub spread: Vec<f64>,
    /// Why each row was picked.
    pub reason: Vec<String>,
    /// The candidate equations (the selected correction first, then each alternative) and
    /// their predictions at each pick.
    pub equations: Vec<(String, Vec<f64>)>,
    /// Candidates considered.
    pub n_candidates: usize,
    /// Candidates left out because the model has no finite value there (its physics or
    /// correction is outside its domain); 0 when every candidate was considered.
    pub left_out: usize,
}

/// Picks `n` rows of `candidates` (every input column of `model`) for `goal`. Candidates
/// where the model has no finite value (a physics or correction outside its domain, such
/// as a logarithm of a negative number) are left out and counted in
/// [`Proposal::left_out`]; the rows returned index `candidates` as given.
///
/// # Errors
/// [`HybridError::MissingColumn`] for an input column the candidates lack;
/// [`HybridError::InvalidConfig`] for `n` 0 or above the candidates left, a model with no
/// finite value at any candidate, or whose correction cannot be evaluated there.
pub fn design(
    model: &TableModel,
    candidates: &Table,
    n: usize,
    goal: DesignGoal,
) -> Result<Proposal, HybridError> {
    match design_all(model, candidates, n, goal) {
        Err(HybridError::BadPhysics { .. } | HybridError::BadCorrection { .. }) => {}
        other => return other.map(|p| with_sign_notes(model, p)),
    }
    // only where some candidate has no value: design over those that have one
    let m = candidates.n_rows();
    let defined = model.defined_rows(candidates)?;
    let keep: Vec<usize> = (0..m).filter(|&i| defined[i]).collect();
    if keep.is_empty() {
        return Err(HybridError::InvalidConfig(format!(
            "the model has no finite value at any of the {m} candidate settings (its physics \
             or correction is outside its domain there): give settings inside it"
        )));
    }
    let mut p = design_all(model, &candidates.select_rows(&keep)?, n, goal)?;
    for r in &mut p.rows {
        *r = keep[*r];
    }
    p.left_out = m - keep.len();
    Ok(with_sign_notes(model, p))
}

/// `v` rounded to `digits` significant digits (for a reason's text: "2.65e12 %", not
/// "2653995409054 %").
fn round_sig(v: f64, digits: i32) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let scale = 10f64.powi(digits - 1 - v.abs().log10().floor() as i32);
    (v * scale).round() / scale
}

/// `p` with a note in the `reason` of each proposal predicted with a sign the training
/// target never had (issue 63: an extrapolation an engineer should check before running it).
fn with_sign_notes(model: &TableModel, mut p: Proposal) -> Proposal {
    if let Some(t) = &model.training {
        for (why, &v) in p.reason.iter_mut().zip(&p.predicted) {
            if t.sign_warning(&[v], "run").is_some() {
                why.push_str("; predicted with a sign the training target never had (check it)");
            }
        }
    }
    p
}

/// [`design`] on candidates where the model has a value at every one.
///
/// # Errors
/// Those of [`design`], and [`HybridError::BadPhysics`] or
/// [`HybridError::BadCorrection`] at a candidate without one.
fn design_all(
    model: &TableModel,
    candidates: &Table,
    n: usize,
    goal: DesignGoal,
) -> Result<Proposal, HybridError> {
    let m = candidates.n_rows();
    if n == 0 || n > m {
        return Err(HybridError::InvalidConfig(format!(
            "--n {n}: choose between 1 and the {m} candidate settings"
        )));
    }
    let selected = model.predict(candidates)?;
    let phys = &selected.physics;
    let mut equations = vec![(
        model.correction.forms.equation.clone(),
        selected.hybrid.clone(),
    )];
    // each equation's correction values and the covariance of its constants, where the
    // model file has it (for Box and Hill's weighting by each one's own variance)
    let mut own = vec![(
        selected.correction.clone(),
        model.correction.uncertainty.as_ref(),
    )];
    let alternatives = model
        .correction
        .selection
        .as_ref()
        .map(|s| s.alternatives.clone())
        .unwrap_or_default();
    for a in &alternatives {
        let Ok(c) = hxai_symreg::infix::compile_text(&a.sympy, &Default::default()) else {
            continue;
        };
        let Ok(cols) = columns_of(candidates, &c.inputs, "input of an alternative") else {
            continue;
        };
        let delta = c.eval_columns(&cols, m);
        let h: Vec<f64> = phys
            .iter()
            .zip(&delta)
            .map(|(p, d)| combine_values(model.correction.kind, *p, *d))
            .collect();
        if h.iter().all(|v| v.is_finite()) {
            equations.push((a.equation.clone(), h));
            own.push((delta, a.uncertainty.as_ref()));
        }
    }
    let spread: Vec<f64> = (0..m)
        .map(|i| {
            let (lo, hi) = equations
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |a, e| {
                    (a.0.min(e.1[i]), a.1.max(e.1[i]))
                });
            hi - lo
        })
        .collect();
    let has_covariance = model
        .hybrid
        .uncertainty
        .as_ref()
        .is_some_and(|u| !u.covariance.is_empty() && u.residual_variance > 0.0);
    let goal = match goal {
        DesignGoal::Discriminate if equations.len() < 2 && has_covariance => DesignGoal::Precision,
        DesignGoal::Discriminate if equations.len() < 2 => DesignGoal::Coverage,
        g => g,
    };
    if goal == DesignGoal::Precision {
        return precision(model, candidates, n, (selected.hybrid, spread, equations));
    }
    let width: Option<Vec<f64>> = match goal {
        DesignGoal::Coverage => model
            .intervals(candidates, crate::DEFAULT_INTERVAL)
            .ok()
            .map(|iv| iv.iter().map(|(lo, hi)| hi - lo).collect()),
        DesignGoal::Discriminate | DesignGoal::Precision => None,
    };
    // Box and Hill's (1967) weighting: each equation's prediction variance there, the
    // variance of a run's outcome under it (the scatter plus its constants' uncertainty).
    // Where the file has every equation's own covariance (a fit since 2026-12-02), each
    // has its own, its correction's constants' `g^T C g` on the hybrid's scale (the
    // physics held at its calibrated values for all alike); otherwise every equation is
    // given the selected hybrid's. Without the model's covariance (or where a template
    // does not evaluate), the spread alone.
    let run_variance: Option<Vec<Vec<f64>>> = match (goal, model.hybrid.uncertainty.as_ref()) {
        (DesignGoal::Discriminate, Some(u)) if has_covariance => own_variances(
            u.residual_variance,
            &own,
            phys,
            model.correction.kind,
            candidates,
        )
        .or_else(|| {
            gradients(u, candidates).ok().map(|g| {
                let v: Vec<f64> = (0..m).map(|i| g.s2 + g.variance(i).max(0.0)).collect();
                vec![v; equations.len()]
            })
        }),
        _ => None,
    };
    let worth: Vec<f64> = match (goal, &width, &run_variance) {
        (DesignGoal::Discriminate, _, Some(v)) => (0..m)
            .map(|i| {
                let vars: Vec<f64> = v.iter().map(|e| e[i]).collect();
                let ys: Vec<f64> = equations.iter().map(|e| e.1[i]).collect();
                box_hill(&ys, &vars)
            })
            .collect(),
        (DesignGoal::Discriminate | DesignGoal::Precision, _, _) => spread.clone(),
        (DesignGoal::Coverage, Some(w), _) => w.clone(),
        (DesignGoal::Coverage, None, _) => vec![1.0; m],
    };
    let worth_max = worth
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0_f64, f64::max)
        .max(f64::MIN_POSITIVE);
    // inputs scaled to the candidates' ranges
    let scaled: Vec<Vec<f64>> = candidates
        .columns()
        .iter()
        .map(|c| {
            let (lo, hi) = c.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, v| {
                (a.0.min(*v), a.1.max(*v))
            });
            let w = if hi > lo { hi - lo } else { 1.0 };
            c.iter().map(|v| (v - lo) / w).collect()
        })
        .collect();
    let dist = |a: usize, b: usize| -> f64 {
        scaled
            .iter()
            .map(|c| (c[a] - c[b]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let mut nearest = vec![f64::INFINITY; m];
    let mut rows = Vec::with_capacity(n);
    let mut reason = Vec::with_capacity(n);
    for k in 0..n {
        let score = |i: usize| {
            if rows.contains(&i) || !worth[i].is_finite() {
                return f64::NEG_INFINITY;
            }
            let d = nearest[i];
            match goal {
                DesignGoal::Discriminate | DesignGoal::Precision => {
                    worth[i] * if d.is_finite() { d / (d + CLOSE) } else { 1.0 }
                }
                // the widest interval first, then space-filling: the farthest from the runs
                // picked, wider intervals preferred among the far
                DesignGoal::Coverage if d.is_finite() => d * (0.5 + 0.5 * worth[i] / worth_max),
                DesignGoal::Coverage => worth[i],
            }
        };
        // the first best candidate (ties to the lowest index: deterministic)
        let mut best = 0;
        let mut best_score = f64::NEG_INFINITY;
        for i in 0..m {
            let s = score(i);
            if s > best_score {
                best = i;
                best_score = s;
            }
        }
        let why = match goal {
            DesignGoal::Discriminate | DesignGoal::Precision => format!(
                "the {} equations differ by {} here{}{}",
                equations.len(),
                crate::error::num(spread[best]),
                match &run_variance {
                    Some(v) => format!(
                        ", {} sd of a run's outcome there (Box and Hill's weighting: the \
                         scatter and the constants' uncertainty)",
                        crate::error::num(spread[best] / v[0][best].sqrt())
                    ),
                    None => String::new(),
                },
                if k > 0 {
                    format!(
                        ", {} (scaled) from the runs picked before",
                        crate::error::num(nearest[best])
                    )
                } else {
                    String::new()
                }
            ),
            DesignGoal::Coverage => match &width {
                Some(w) if k == 0 => format!(
                    "the widest prediction interval of the space ({} wide)",
                    crate::error::num(w[best])
                ),
                Some(w) => format!(
                    "{} (scaled) from the runs picked before, prediction interval {} wide",
                    crate::error::num(nearest[best]),
                    crate::error::num(w[best])
                ),
                None if k == 0 => "the first run (the model has no intervals)".into(),
                None => format!(
                    "{} (scaled) from the runs picked before (the model has no intervals)",
                    crate::error::num(nearest[best])
                ),
            },
        };
        rows.push(best);
        reason.push(why);
        for (i, d) in nearest.iter_mut().enumerate() {
            *d = d.min(dist(i, best));
        }
    }
    Ok(proposal(
        goal,
        (rows, reason),
        (selected.hybrid, spread, equations),
        m,
    ))
}

/// The [`Proposal`] of the picks `rows` (with their `reason`s) among `m` candidates: the
/// predictions at the picks.
fn proposal(
    goal: DesignGoal,
    (rows, reason): (Vec<usize>, Vec<String>),
    (hybrid, spread, equations): Predictions,
    m: usize,
) -> Proposal {
    Proposal {
        goal,
        predicted: rows.iter().map(|&i| hybrid[i]).collect(),
        spread: rows.iter().map(|&i| spread[i]).collect(),
        equations: equations
            .into_iter()
            .map(|(e, v)| (e, rows.iter().map(|&i| v[i]).collect()))
            .collect(),
        rows,
        reason,
        n_candidates: m,
        left_out: 0,
    }
}

/// The inverse of the small symmetric matrix `a` by the crate's Cholesky solve
/// ([`hxai_symreg::fit::cholesky_solve`], one unit column at a time); `None` where it is not
/// positive definite.
fn invert(a: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let k = a.len();
    let flat: Vec<f64> = a.iter().flatten().copied().collect();
    let mut inv = vec![vec![0.0; k]; k];
    for j in 0..k {
        let mut col: Vec<f64> = (0..k).map(|i| if i == j { 1.0 } else { 0.0 }).collect();
        if !hxai_symreg::fit::cholesky_solve(&mut flat.clone(), &mut col, k) {
            return None;
        }
        for (row, v) in inv.iter_mut().zip(col) {
            row[j] = v;
        }
    }
    Some(inv)
}

/// The candidate equations' values at every candidate: the selected hybrid's, the spread
/// of all, and each equation with its values.
type Predictions = (Vec<f64>, Vec<f64>, Vec<(String, Vec<f64>)>);

/// [`design`] for [`DesignGoal::Precision`]: the greedy sequential Ds-optimal design for the
/// calibrated physics parameters, the correction's constants as nuisance parameters (each
/// pick with the earlier ones fixed). With `C` the constants' covariance `s^2 (J^T J)^-1`
/// of the model file and `g` the gradient of the hybrid's prediction with respect to its
/// constants at a candidate (central differences on the hybrid equation), a run there
/// multiplies the determinant of the physics block `C_ss` by `1 - u^T C_ss^-1 u / (s^2 +
/// g^T C g)`, `u` the physics part of `C g`; the pick is the candidate that shrinks it most,
/// and `C` is then updated as if the run were done (Sherman-Morrison: `C - C g g^T C /
/// (s^2 + g^T C g)`). Where nothing is calibrated, or the physics block is singular, the pick is
/// the D-optimal one for every constant (the largest `g^T C g`). Measured against the
/// D-optimal design for every constant in docs/benchmarks.md ("What to measure next").
fn precision(
    model: &TableModel,
    candidates: &Table,
    n: usize,
    predictions: Predictions,
) -> Result<Proposal, HybridError> {
    let m = candidates.n_rows();
    let u = model
        .hybrid
        .uncertainty
        .as_ref()
        .filter(|u| !u.covariance.is_empty() && u.residual_variance > 0.0)
        .ok_or_else(|| {
            HybridError::InvalidConfig(
                "--goal precision needs the covariance of the hybrid's constants, which this \
                 model file does not have (its `hybrid.uncertainty` gives the reason); use \
                 --goal coverage or discriminate"
                    .into(),
            )
        })?;
    let Gradients { grads, mut cov, s2 } = gradients(u, candidates)?;
    let times = |cov: &[Vec<f64>], g: &[f64]| -> Vec<f64> {
        cov.iter()
            .map(|row| row.iter().zip(g).map(|(c, gj)| c * gj).sum())
            .collect()
    };
    let dot = |a: &[f64], b: &[f64]| -> f64 { a.iter().zip(b).map(|(x, y)| x * y).sum() };
    // the calibrated physics parameters: their block of the covariance is what the runs
    // should shrink (Ds-optimality); the correction's constants are nuisance parameters
    let physics: Vec<usize> = u
        .params
        .iter()
        .enumerate()
        .filter(|(_, (name, _))| model.physics.calibrated.contains(name))
        .map(|(j, _)| j)
        .collect();
    let mut rows: Vec<usize> = Vec::with_capacity(n);
    let mut reason = Vec::with_capacity(n);
    let mut gain = 0.0_f64;
    for _ in 0..n {
        let block: Vec<Vec<f64>> = physics
            .iter()
            .map(|&a| physics.iter().map(|&b| cov[a][b]).collect())
            .collect();
        let block_inv = invert(&block);
        let mut best = None;
        let mut best_v = f64::NEG_INFINITY;
        let mut best_score = f64::NEG_INFINITY;
        for (i, g) in grads.iter().enumerate() {
            if rows.contains(&i) {
                continue;
            }
            let cg = times(&cov, g);
            let v = dot(g, &cg);
            // Ds: the share by which the run shrinks the physics block's determinant,
            // `u' C_ss^-1 u / (s^2 + v)` with `u` the physics part of `C g`; D (every
            // constant) where nothing is calibrated or the block is singular
            let score = match &block_inv {
                Some(inv) if !physics.is_empty() => {
                    let us: Vec<f64> = physics.iter().map(|&a| cg[a]).collect();
                    dot(&us, &times(inv, &us)) / (s2 + v)
                }
                _ => v,
            };
            if v.is_finite() && score.is_finite() && score > best_score {
                best = Some(i);
                best_v = v;
                best_score = score;
            }
        }
        let Some(i) = best else {
            return Err(HybridError::InvalidConfig(
                "the hybrid's gradient is not finite at any candidate left".into(),
            ));
        };
        let cg = times(&cov, &grads[i]);
        for (a, row) in cov.iter_mut().enumerate() {
            for (b, c) in row.iter_mut().enumerate() {
                *c -= cg[a] * cg[b] / (s2 + best_v);
            }
        }
        let ds = !physics.is_empty() && block_inv.is_some();
        // the factor the region's determinant is multiplied by
        let shrink = if ds {
            1.0 - best_score.clamp(0.0, 1.0 - f64::EPSILON)
        } else {
            1.0 / (1.0 + best_v.max(0.0) / s2)
        };
        gain -= shrink.ln();
        let what = if ds {
            "physics parameters'"
        } else {
            "all constants'"
        };
        reason.push(format!(
            "the run that shrinks the {what} joint confidence region most (the constants' \
             uncertainty moves the prediction by sd {} here, {} % of the scatter's), the \
             runs picked before counted as done; that region's volume x {} so far",
            crate::error::num(best_v.max(0.0).sqrt()),
            crate::error::num(round_sig(100.0 * (best_v.max(0.0) / s2).sqrt(), 3)),
            crate::error::num(round_sig((-0.5 * gain).exp(), 3))
        ));
        rows.push(i);
    }
    Ok(proposal(
        DesignGoal::Precision,
        (rows, reason),
        predictions,
        m,
    ))
}
