//! Consensus selection of the factor form (issue 68, `--consensus N`): the forward selection
//! is run again on `N` seeded bootstrap resamples of the rows, and the factor set (each
//! factor's columns and shape) that most of the `N + 1` selections give back is kept,
//! its constants fitted again on every row. One selection follows the rows' chance: on
//! correlated columns or weak effects a resample trades one column or shape for a
//! neighbour; the most frequent set is the one the data support (Breiman's bagging of a
//! choice, as [`crate::consensus`] does for the free form).
use super::FactorConfig;
use super::select::{Problem, Scored};
use super::structure::Structure;
use crate::Par;
use crate::bootstrap::bootstrap_rows;
use rayon::prelude::*;
use std::collections::BTreeMap;

/// Mixes the consensus' resamples away from those of `--stability` (which draws run `r`
/// from `seed ^ (r + 1) * RUN_MIX`), so a stability run and its inner consensus never share
/// a resample.
const CONSENSUS_SEED_MIX: u64 = 0xC0FF_EE00_D15E_A5E5;

/// What the consensus found: how many of the resamples' selections gave the kept factor
/// set back (the vote also counts the selection on every row; this share does not, so it
/// reads as "given back by this share of N resamples").
#[derive(Clone, Debug, PartialEq)]
pub struct ConsensusShare {
    /// Resamples whose selection could be run.
    pub runs: usize,
    /// Of them, those that gave the kept factor set back.
    pub agreeing: usize,
}

/// A factor set as text: each term's columns and shape, sorted (the order of entry does
/// not matter).
pub(super) fn key(s: &Structure) -> String {
    let mut parts: Vec<String> = s
        .terms
        .iter()
        .map(|t| {
            let cols: Vec<String> = t.cols.iter().map(|c| c.to_string()).collect();
            format!("{}:{}", cols.join("x"), t.shape.name())
        })
        .collect();
    parts.sort();
    parts.join(" ")
}

/// The consensus over `cfg.consensus` resamples of `problem`'s rows, starting from `full`
/// (the selection on every row): `full` where its factor set is the most frequent (ties go
/// to it), else the most frequent set (ties by text) fitted on every row from a resample's
/// constants. `None` for the share where no resample could be selected.
pub(super) fn consensus(problem: &Problem, full: Scored) -> (Scored, Option<ConsensusShare>) {
    let cfg = problem.cfg;
    let runs = cfg.consensus;
    if runs == 0 {
        return (full, None);
    }
    let n = problem.y.len();
    let seed = cfg.seed ^ CONSENSUS_SEED_MIX;
    let found: Vec<Option<Structure>> = cfg.par.run(|| {
        (0..runs)
            .into_par_iter()
            .map(|r| resample_selection(problem, seed, r, n))
            .collect()
    });
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let full_key = key(&full.s);
    *counts.entry(full_key.clone()).or_default() += 1;
    for s in found.iter().flatten() {
        *counts.entry(key(s)).or_default() += 1;
    }
    let done = found.iter().flatten().count();
    let top = counts.values().copied().max().unwrap_or(0);
    // the resamples that gave `k` back (the vote's count less the selection on every row)
    let share = |k: &str| {
        let c = counts.get(k).copied().unwrap_or(0) - usize::from(k == full_key);
        Some(ConsensusShare {
            runs: done,
            agreeing: c,
        })
    };
    if counts.get(&full_key) == Some(&top) {
        return (full, share(&full_key));
    }
    // the first set (by text) of the highest count, from its first resample
    let Some(mode) = counts
        .iter()
        .find(|(_, c)| **c == top)
        .map(|(k, _)| k.clone())
    else {
        return (full, share(&full_key));
    };
    let Some(start) = found.into_iter().flatten().find(|s| key(s) == mode) else {
        return (full, share(&full_key));
    };
    match problem.score(start) {
        Some(s) if key(&s.s) == mode => (s, share(&mode)),
        _ => (full, share(&full_key)),
    }
}

/// The selection on bootstrap resample `r` of `problem`'s rows (a row drawn twice stays in
/// one fold), with the seed of the resample's own folds; `None` where nothing could be
/// fitted.
fn resample_selection(problem: &Problem, seed: u64, r: usize, n: usize) -> Option<Structure> {
    let (rows, _) = bootstrap_rows(seed, r, n);
    let cols: Vec<Vec<f64>> = problem
        .cols
        .iter()
        .map(|c| rows.iter().map(|&i| c[i]).collect())
        .collect();
    let y: Vec<f64> = rows.iter().map(|&i| problem.y[i]).collect();
    let groups: Vec<usize> = match &problem.groups {
        Some(g) => rows.iter().map(|&i| g[i]).collect(),
        None => rows.clone(),
    };
    let run_cfg = FactorConfig {
        seed: problem.cfg.seed.wrapping_add(r as u64 + 1),
        par: Par::Current,
        consensus: 0,
        ..*problem.cfg
    };
    let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    let p = Problem::new(
        refs,
        &y,
        problem.link,
        &run_cfg,
        Some(&groups),
        problem.scale,
    );
    p.select().map(|(chosen, _, _)| chosen.s)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::super::{FactorConfig, Link, fit_factors};
    use super::*;
    use crate::Table;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A line in `a` with two neighbours a resample may trade it for: `b` (`a` plus
    /// scatter) and a weak `c`, so the selections on resamples disagree.
    fn rows(n: usize) -> (Table, Vec<f64>) {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let a: Vec<f64> = (0..n).map(|_| rng.gen_range(1.0..3.0)).collect();
        let b: Vec<f64> = a.iter().map(|v| v + rng.gen_range(-0.3..0.3)).collect();
        let c: Vec<f64> = (0..n).map(|_| rng.gen_range(0.0..1.0)).collect();
        let y: Vec<f64> = (0..n)
            .map(|i| 0.4 * a[i] + 0.1 * c[i] + rng.gen_range(-0.5..0.5))
            .collect();
        let t = Table::new(vec!["a".into(), "b".into(), "c".into()], vec![a, b, c]).unwrap();
        (t, y)
    }

    /// The set kept is the most frequent among the selection on every row and those of the
    /// resamples (counted here from the same resamples), and the share says so.
    #[test]
    fn the_most_frequent_factor_set_is_kept() {
        let (t, y) = rows(90);
        let cfg = FactorConfig {
            consensus: 9,
            ..FactorConfig::default()
        };
        let cols: Vec<&[f64]> = t.columns().iter().map(Vec::as_slice).collect();
        let p = Problem::new(cols, &y, Link::Additive, &cfg, None, None);
        let full = p.select().unwrap().0;
        let mut counts: BTreeMap<String, usize> = BTreeMap::new();
        *counts.entry(key(&full.s)).or_default() += 1;
        for r in 0..cfg.consensus {
            let s = resample_selection(&p, cfg.seed ^ CONSENSUS_SEED_MIX, r, y.len()).unwrap();
            *counts.entry(key(&s)).or_default() += 1;
        }
        assert!(counts.len() > 1, "the resamples all agree: {counts:?}");
        let (kept, share) = consensus(&p, full);
        let share = share.unwrap();
        let top = *counts.values().max().unwrap();
        // the share counts the resamples alone
        assert_eq!(share.runs, 9);
        let own = usize::from(key(&kept.s) == key(&p.select().unwrap().0.s));
        assert_eq!(share.agreeing, top - own);
        assert_eq!(
            counts[&key(&kept.s)],
            top,
            "{counts:?} kept {}",
            key(&kept.s)
        );
    }

    /// Without resamples nothing changes and no share is reported; with them the fit
    /// reports the share, and the thread count does not change the result.
    #[test]
    fn consensus_is_reported_and_does_not_depend_on_threads() {
        let (t, y) = rows(90);
        let plain = fit_factors(&t, &y, Link::Additive, &FactorConfig::default()).unwrap();
        assert!(plain.consensus.is_none());
        let fits: Vec<_> = [1, 2]
            .into_iter()
            .map(|k| {
                let cfg = FactorConfig {
                    consensus: 6,
                    par: Par::threads(k),
                    ..FactorConfig::default()
                };
                fit_factors(&t, &y, Link::Additive, &cfg).unwrap()
            })
            .collect();
        let share = fits[0].consensus.clone().unwrap();
        assert_eq!(share.runs, 6);
        assert!(share.agreeing <= 6);
        // (compared as text: an alternative's unscored errors are NaN, never equal)
        assert_eq!(format!("{:?}", fits[0]), format!("{:?}", fits[1]));
    }
}
