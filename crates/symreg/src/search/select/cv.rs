//! Cross-validated selection: each reported model's held-out loss over seeded folds of all
//! rows (its constants refitted per fold), the one-standard-error rule that picks among
//! them, and the models within one standard error of the best ("the data cannot tell these
//! apart").
use super::pick::{likeliest, simplest};
use super::refine::{REFIT_LM_ITERATIONS, REFIT_LM_TOLERANCE};
use crate::eval::Evaluator;
use crate::fit::{LmSettings, Unknowns, levenberg_marquardt};
use crate::model::Model;
use crate::search::config::ErrorModel;
use crate::search::fitting::Problem;
use crate::{SrError, Table};
use hxai_table::Pool;
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Mixed into the seed of [`crate::Criterion::CrossValidation`]'s fold assignment, so the folds
/// do not reuse the random stream of the search's own row subsample.
const CV_SEED_SALT: u64 = 0x6376_5f66_6f6c_6473;

/// Each model's mean held-out squared error over `cv_folds` seeded folds of all rows, and
/// the mean's standard error. Each fold refits every constant of the structure from the
/// model's own (all-rows) values; a fold whose refit fails scores infinity. Identical rows
/// share a fold ([`cv_folds`]).
pub(super) fn cross_validate(
    problem: &Problem,
    models: &[Model],
    data: &Table,
    error_model: ErrorModel,
    pool: &Pool,
) -> Result<Vec<(f64, f64)>, SrError> {
    let cfg = problem.cfg;
    let (fold_of, k) = cv_folds(&problem.cols, &problem.y, cfg.cv_folds, cfg.seed);
    let log_loss = error_model == ErrorModel::Multiplicative;
    pool.install(|| {
        models
            .par_iter()
            .map(|m| {
                let folds = Folds { of: &fold_of, k };
                cv_loss(m, data, &problem.y, folds, log_loss)
            })
            .collect::<Result<_, _>>()
    })
}

/// The fold of each row for cross-validation, and the number of folds: rows equal in every
/// input and the target form one group, the groups are shuffled by `seed` and dealt into
/// `folds` folds of nearly equal size. A bootstrap resample (`--stability`, consensus)
/// repeats rows; were copies of one row split between folds, each fold would be tested on
/// rows it was fitted on, and the cross-validated loss would favour models that fit the
/// noise. Without repeated rows this is a shuffle of the rows.
pub(crate) fn cv_folds(cols: &[&[f64]], y: &[f64], folds: usize, seed: u64) -> (Vec<usize>, usize) {
    let n = y.len();
    let mut group_of = vec![0usize; n];
    let mut groups: std::collections::HashMap<Vec<u64>, usize> = Default::default();
    for (i, g) in group_of.iter_mut().enumerate() {
        let key: Vec<u64> = cols
            .iter()
            .map(|c| c[i].to_bits())
            .chain(std::iter::once(y[i].to_bits()))
            .collect();
        let next = groups.len();
        *g = *groups.entry(key).or_insert(next);
    }
    let n_groups = groups.len();
    let k = folds.min(n_groups);
    let mut order: Vec<usize> = (0..n_groups).collect();
    order.shuffle(&mut ChaCha8Rng::seed_from_u64(seed ^ CV_SEED_SALT));
    let mut fold_of_group = vec![0usize; n_groups];
    for (pos, &g) in order.iter().enumerate() {
        fold_of_group[g] = pos * k / n_groups.max(1);
    }
    (group_of.iter().map(|&g| fold_of_group[g]).collect(), k)
}

/// The lowest cross-validated loss of `cv` (mean, standard error per model) plus its
/// standard error: the band of the one-standard-error rule (infinite when no loss is
/// finite, so nothing is within it).
fn one_standard_error_limit(cv: &[(f64, f64)]) -> f64 {
    cv.iter()
        .filter(|(mean, _)| mean.is_finite())
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map_or(f64::NEG_INFINITY, |(mean, se)| mean + se)
}

/// The models other than `best` whose cross-validated loss is within one standard error of
/// the lowest, simplest first (ties by loss), one per structure (`best`'s excluded).
pub(super) fn within_one_standard_error(
    models: &[Model],
    cv: &[(f64, f64)],
    best: &Model,
) -> Vec<Model> {
    let limit = one_standard_error_limit(cv);
    let mut seen = vec![crate::canonical::structure_of(best)];
    let mut band: Vec<(&Model, f64)> = models
        .iter()
        .zip(cv)
        .filter(|(_, (mean, _))| *mean <= limit)
        .map(|(m, (mean, _))| (m, *mean))
        .collect();
    band.sort_by(|a, b| {
        a.0.complexity
            .cmp(&b.0.complexity)
            .then(a.1.total_cmp(&b.1))
    });
    let mut out = Vec::new();
    for (m, _) in band {
        let key = crate::canonical::structure_of(m);
        if !seen.contains(&key) {
            seen.push(key);
            out.push(m.clone());
        }
    }
    out
}

/// The folds of a cross-validation ([`cv_folds`]'s): the fold of each row, and how many
/// folds there are.
#[derive(Clone, Copy)]
struct Folds<'a> {
    of: &'a [usize],
    k: usize,
}

/// Mean and standard error of one model's held-out MSE over the `folds`; with `log_loss`,
/// of the squared error of `ln y` (a multiplicative error, [`ErrorModel::Multiplicative`];
/// infinite where a prediction is not positive).
fn cv_loss(
    m: &Model,
    data: &Table,
    y: &[f64],
    folds: Folds<'_>,
    log_loss: bool,
) -> Result<(f64, f64), SrError> {
    let Folds { of: fold_of, k } = folds;
    let cols: Vec<&[f64]> = m
        .feature_names
        .iter()
        .map(|name| data.require(name).map_err(SrError::from))
        .collect::<Result<_, _>>()?;
    let prog = &m.program;
    let mut ev = Evaluator::new(prog);
    let free: Vec<usize> = (0..m.params.len()).collect();
    let mut losses = Vec::with_capacity(k);
    for fold in 0..k {
        let pick = |inside: bool| -> (Vec<Vec<f64>>, Vec<f64>) {
            let rows: Vec<usize> = (0..y.len())
                .filter(|&i| (fold_of[i] == fold) == inside)
                .collect();
            let c = cols
                .iter()
                .map(|col| rows.iter().map(|&i| col[i]).collect())
                .collect();
            (c, rows.iter().map(|&i| y[i]).collect())
        };
        let (train_cols, train_y) = pick(false);
        let (test_cols, test_y) = pick(true);
        let train_refs: Vec<&[f64]> = train_cols.iter().map(Vec::as_slice).collect();
        let test_refs: Vec<&[f64]> = test_cols.iter().map(Vec::as_slice).collect();
        let mut params = m.params.clone();
        let fit = levenberg_marquardt(
            prog,
            &mut params,
            Unknowns::Free(&free),
            &train_refs,
            &train_y,
            &LmSettings::new(REFIT_LM_ITERATIONS, REFIT_LM_TOLERANCE),
            &mut ev,
        );
        let loss = if !fit.is_finite() {
            f64::INFINITY
        } else if log_loss {
            let mut pred = Vec::new();
            ev.predict(prog, &params, &test_refs, test_y.len(), &mut pred);
            let sum: f64 = pred
                .iter()
                .zip(&test_y)
                .map(|(p, t)| {
                    if *p > 0.0 {
                        (p.ln() - t.ln()).powi(2)
                    } else {
                        f64::INFINITY
                    }
                })
                .sum();
            sum / test_y.len().max(1) as f64
        } else {
            ev.mse(prog, &params, &test_refs, &test_y)
        };
        losses.push(if loss.is_finite() {
            loss
        } else {
            f64::INFINITY
        });
    }
    let kf = k as f64;
    let mean = losses.iter().sum::<f64>() / kf;
    let var = losses.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / (kf - 1.0);
    let se = if mean.is_finite() {
        (var / kf).sqrt()
    } else {
        f64::INFINITY
    };
    Ok((mean, se))
}

/// The one-standard-error rule (Hastie, Tibshirani and Friedman, *The Elements of
/// Statistical Learning*, 7.10): the simplest model whose cross-validated error is within
/// one standard error of the lowest.
/// `cv[i]` is the mean and standard error of `models[i]`'s held-out loss. With a
/// `codelength` (the laws prior, [`crate::Prior::Laws`]), "simplest" is the likeliest under
/// it ([`likeliest`]); without, the lowest complexity ([`simplest`]).
pub(super) fn one_standard_error_pick(
    models: &[Model],
    cv: &[(f64, f64)],
    codelength: Option<&(dyn Fn(&Model) -> f64 + Sync)>,
) -> Option<Model> {
    let limit = one_standard_error_limit(cv);
    let band = models
        .iter()
        .zip(cv)
        .filter(|(_, (mean, _))| *mean <= limit)
        .map(|(m, _)| m);
    match codelength {
        Some(l) => likeliest(band, l),
        None => simplest(band),
    }
}
