//! The stability of a factor model over bootstrap resamples: which columns are kept, which
//! shape each factor takes, and how far each factor's response spreads.
//!
//! The resamples are [`crate::stability`]'s (run `r` draws the same rows there and here), so
//! a factor correction's stability and a free-form one's are measured on the same rows.
//! A factor's response is compared across runs after normalising away the part the other
//! constants can trade with it: a sum's term minus its mean over the run's rows, a
//! product's factor divided by its mean there.
use super::shape::Shape;
use super::structure::Structure;
use super::{FactorConfig, Link, fit_structure};
use crate::bootstrap::{FactorBand, Stability, bootstrap_rows, r2_spread, shares};
use crate::canonical::structure_of;
use crate::{Par, SrError, Table};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::sync::Mutex;

/// Points of a factor's response grid.
const GRID: usize = 25;

/// What one run kept.
struct Run {
    features: Vec<String>,
    structure: String,
    set: String,
    shapes: Vec<(String, String)>,
    responses: Vec<(String, Vec<f64>)>,
    r2: Option<f64>,
}

/// Alias kept for the entry point's signature.
pub type FactorStability = Stability;

/// Reruns [`super::fit_factors`] on `runs` bootstrap resamples of the rows and reports the
/// shares of columns, of whole structures, of column sets and of each column's shapes, the
/// spread of each factor's response and R² out of bag. `progress` gets `(runs done, runs)`.
///
/// # Errors
/// `runs` of 0, and [`super::fit_factors`]'s errors on a resample.
pub fn factor_stability(
    data: &Table,
    y: &[f64],
    link: Link,
    cfg: &FactorConfig,
    runs: usize,
    progress: &mut (dyn FnMut(usize, usize) + Send),
) -> Result<Stability, SrError> {
    stability_inner(data, y, None, link, cfg, runs, progress)
}

/// [`factor_stability`] of a hybrid's correction with each row's physics prediction, every
/// run fitted as [`super::fit_factors_on_physics`] fits it.
///
/// # Errors
/// [`factor_stability`]'s, and [`super::fit_factors_on_physics`]'s.
pub fn factor_stability_on_physics(
    data: &Table,
    y: &[f64],
    physics: &[f64],
    link: Link,
    cfg: &FactorConfig,
    runs: usize,
    progress: &mut (dyn FnMut(usize, usize) + Send),
) -> Result<Stability, SrError> {
    if physics.len() != y.len() {
        return Err(SrError::TargetLength {
            target: physics.len(),
            data: y.len(),
        });
    }
    stability_inner(data, y, Some(physics), link, cfg, runs, progress)
}

fn stability_inner(
    data: &Table,
    y: &[f64],
    physics: Option<&[f64]>,
    link: Link,
    cfg: &FactorConfig,
    runs: usize,
    progress: &mut (dyn FnMut(usize, usize) + Send),
) -> Result<Stability, SrError> {
    if runs == 0 {
        return Err(SrError::InvalidConfig(
            "--stability needs at least one run".into(),
        ));
    }
    let n = data.n_rows();
    let grids: Vec<Vec<f64>> = data
        .columns()
        .iter()
        .map(|c| {
            let lo = c.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = c.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (0..GRID)
                .map(|k| lo + (hi - lo) * k as f64 / (GRID - 1) as f64)
                .collect()
        })
        .collect();
    let done = Mutex::new((0usize, progress));
    let results: Vec<Result<Run, SrError>> = cfg.par.run(|| {
        (0..runs)
            .into_par_iter()
            .map(|r| {
                let (rows, oob) = bootstrap_rows(cfg.seed, r, n);
                let train = data.select_rows(&rows)?;
                let yr: Vec<f64> = rows.iter().map(|&i| y[i]).collect();
                let run_cfg = FactorConfig {
                    seed: cfg.seed.wrapping_add(r as u64 + 1),
                    par: Par::Current,
                    ..*cfg
                };
                // a row drawn twice stays in one fold of the run's cross-validation
                let pr: Option<Vec<f64>> = physics.map(|p| rows.iter().map(|&i| p[i]).collect());
                let (fit, s) =
                    fit_structure(&train, &yr, link, &run_cfg, Some(&rows), pr.as_deref())?;
                let whole = Whole {
                    data,
                    grids: &grids,
                    y,
                };
                let run = describe(&fit, &s, link, &whole, &train, &oob);
                if let Ok(mut g) = done.lock() {
                    g.0 += 1;
                    let k = g.0;
                    (g.1)(k, runs);
                }
                Ok(run)
            })
            .collect()
    });
    let runs_done: Vec<Run> = results.into_iter().collect::<Result<_, _>>()?;
    Ok(summarise(data, &grids, runs_done, runs))
}

/// The rows every run resamples, their target and the response grids.
struct Whole<'a> {
    data: &'a Table,
    grids: &'a [Vec<f64>],
    y: &'a [f64],
}

/// What a run kept, and its factors' normalised responses on the grids.
fn describe(
    fit: &super::FactorFit,
    s: &Structure,
    link: Link,
    whole: &Whole,
    train: &Table,
    oob: &[usize],
) -> Run {
    let Whole { data, grids, y } = *whole;
    let names = data.names();
    let key = |cols: &[usize]| {
        cols.iter()
            .map(|&c| names[c].as_str())
            .collect::<Vec<_>>()
            .join(":")
    };
    let mut set: Vec<String> = s.terms.iter().map(|t| key(&t.cols)).collect();
    set.sort();
    let shapes = s
        .terms
        .iter()
        .zip(&fit.factors)
        .map(|(t, f)| (key(&t.cols), f.template.clone()))
        .collect();
    let train_cols: Vec<&[f64]> = train.columns().iter().map(Vec::as_slice).collect();
    let mut responses = Vec::new();
    for t in s.terms.iter().filter(|t| t.shape != Shape::Pair) {
        let c = t.cols[0];
        let alone = |cols: &[&[f64]], m: usize| {
            let one = Structure {
                terms: vec![t.clone()],
                constant: if link == Link::Additive { 0.0 } else { 1.0 },
                scale: None,
            };
            let v = one.predict(link, cols, m);
            match link {
                Link::Additive => v,
                Link::Multiplicative => v.into_iter().map(|x| x + 1.0).collect(),
                Link::Log => v.into_iter().map(f64::exp).collect(),
            }
        };
        let on_rows = alone(&train_cols, train.n_rows());
        let centre = on_rows.iter().sum::<f64>() / on_rows.len().max(1) as f64;
        let mut cols: Vec<Vec<f64>> = vec![vec![1.0; GRID]; names.len()];
        cols[c] = grids[c].clone();
        let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
        let g = alone(&refs, GRID);
        let g = match link {
            Link::Additive => g.into_iter().map(|v| v - centre).collect(),
            _ => g.into_iter().map(|v| v / centre).collect(),
        };
        responses.push((names[c].clone(), g));
    }
    let r2 = (oob.len() >= 2)
        .then(|| {
            let test = data.select_rows(oob).ok()?;
            let p = fit.model.predict(&test).ok()?;
            let yt: Vec<f64> = oob.iter().map(|&i| y[i]).collect();
            hxai_eval::r2(&yt, &p).ok().filter(|v| v.is_finite())
        })
        .flatten();
    Run {
        features: fit.model.features(),
        structure: structure_of(&fit.model),
        set: set.join(", "),
        shapes,
        responses,
        r2,
    }
}

fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let pos = q * (sorted.len() - 1) as f64;
    let (i, f) = (pos.floor() as usize, pos.fract());
    let j = (i + 1).min(sorted.len() - 1);
    sorted[i] * (1.0 - f) + sorted[j] * f
}

fn summarise(data: &Table, grids: &[Vec<f64>], all: Vec<Run>, runs: usize) -> Stability {
    let mut used: BTreeMap<String, usize> = data.names().iter().map(|n| (n.clone(), 0)).collect();
    let mut structures = BTreeMap::new();
    let mut sets = BTreeMap::new();
    let mut shapes: BTreeMap<String, BTreeMap<String, usize>> = BTreeMap::new();
    let mut responses: BTreeMap<String, Vec<Vec<f64>>> = BTreeMap::new();
    let mut r2s = Vec::new();
    for run in all {
        for f in run.features {
            *used.entry(f).or_insert(0) += 1;
        }
        *structures.entry(run.structure).or_insert(0) += 1;
        *sets.entry(run.set).or_insert(0) += 1;
        for (col, t) in run.shapes {
            *shapes.entry(col).or_default().entry(t).or_insert(0) += 1;
        }
        for (col, g) in run.responses {
            responses.entry(col).or_default().push(g);
        }
        r2s.extend(run.r2);
    }
    let share = |c: usize| c as f64 / runs as f64;
    let bands = responses
        .into_iter()
        .map(|(col, gs)| {
            let c = data.index_of(&col).unwrap_or(0);
            let at = |k: usize, q: f64| {
                let mut v: Vec<f64> = gs.iter().map(|g| g[k]).filter(|v| v.is_finite()).collect();
                v.sort_by(f64::total_cmp);
                quantile(&v, q)
            };
            let band = FactorBand {
                runs: gs.len(),
                grid: grids[c].clone(),
                lo: (0..GRID).map(|k| at(k, 0.05)).collect(),
                median: (0..GRID).map(|k| at(k, 0.5)).collect(),
                hi: (0..GRID).map(|k| at(k, 0.95)).collect(),
            };
            (col, band)
        })
        .collect();
    let r2 = r2_spread(&r2s);
    Stability {
        runs,
        features: used.into_iter().map(|(k, c)| (k, share(c))).collect(),
        structures: shares(structures, runs),
        r2,
        factors: Some(
            shapes
                .into_iter()
                .map(|(col, m)| (col, m.into_iter().map(|(t, c)| (t, share(c))).collect()))
                .collect(),
        ),
        factor_sets: Some(shares(sets, runs)),
        bands: Some(bands),
    }
}
