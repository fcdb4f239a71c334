//! The consensus of [`crate::consensus`] run: the search on all rows and on B bootstrap
//! resamples, the structures at least half the runs nominate, the best of them refitted on
//! all rows. Each search is passed in ([`OneSearch`]), so this layer never calls the loop
//! by name: [`super::search_checked`] passes the plain search, `crate::units` its search on
//! the dimensionless groups.
use super::config::ValidSearch;
use super::progress::Progress;
use super::select::SearchResult;
use super::structure::fit_structure_from;
use crate::bootstrap::{StructureShare, bootstrap_rows};
use crate::canonical::structure_of;
use crate::consensus::{Consensus, MAX_LISTED, STABLE_SHARE};
use crate::{Model, SrError, Table};
use std::collections::BTreeMap;
use std::time::Instant;

/// A nominated structure: in how many runs, and the first nomination's model.
struct Nominee {
    runs: usize,
    model: Model,
}

/// One search of a consensus: the rows, the target, the settings (`consensus_runs` 0) and
/// the progress of that search.
pub(crate) type OneSearch<'a> = dyn Fn(&Table, &[f64], &ValidSearch, &mut dyn FnMut(&Progress)) -> Result<SearchResult, SrError>
    + 'a;

/// The consensus search of the module docs (`cfg.consensus_runs` > 0) on the configuration
/// checked once; `progress` sees the epochs of the B + 1 searches as one count. Each search
/// is run by `one_search` (passed in by the search, so this module does not call it by
/// name), whose models are models of `data`'s columns (with units: the group model
/// composed back, so that the votes and the refit are on the composed structures).
pub(crate) fn search_with(
    data: &Table,
    target: &[f64],
    cfg: &ValidSearch,
    progress: &mut dyn FnMut(&Progress),
    one_search: &OneSearch,
) -> Result<SearchResult, SrError> {
    let t0 = Instant::now();
    let runs = cfg.consensus_runs;
    let one = cfg.one_run(cfg.seed);
    let total = cfg.epochs * (runs + 1);
    let mut report = |done: usize, p: &Progress| {
        progress(&Progress {
            epoch: done * cfg.epochs + p.epoch,
            epochs: total,
            ..p.clone()
        });
    };
    let full = one_search(data, target, &one, &mut |p| report(0, p))?;
    let mut evaluations = full.evaluations;
    let mut duplicate_structures = full.duplicate_structures;
    let simplified = full.simplified;
    let n = data.n_rows();
    let mut nominees: BTreeMap<String, Nominee> = BTreeMap::new();
    for r in 0..runs {
        let (rows, _) = bootstrap_rows(cfg.seed, r, n);
        let train = data.select_rows(&rows)?;
        let y: Vec<f64> = rows.iter().map(|&i| target[i]).collect();
        let run_cfg = one.one_run(cfg.seed.wrapping_add(r as u64 + 1));
        let res = one_search(&train, &y, &run_cfg, &mut |p| report(r + 1, p))?;
        evaluations += res.evaluations;
        duplicate_structures += res.duplicate_structures;
        let mut this_run: Vec<String> = Vec::new();
        for m in std::iter::once(res.best)
            .chain(res.alternatives)
            .chain(res.pareto)
        {
            let key = structure_of(&m);
            if this_run.contains(&key) {
                continue;
            }
            this_run.push(key.clone());
            nominees
                .entry(key)
                .or_insert(Nominee { runs: 0, model: m })
                .runs += 1;
        }
    }
    let mut ranked: Vec<(String, Nominee)> = nominees.into_iter().collect();
    ranked.sort_by(|a, b| {
        b.1.runs
            .cmp(&a.1.runs)
            .then(a.1.model.complexity.cmp(&b.1.model.complexity))
            .then(a.0.cmp(&b.0))
    });
    let share = |k: usize| k as f64 / runs as f64;
    let all_rows_fits: Vec<(String, &Model)> = std::iter::once(&full.best)
        .chain(&full.alternatives)
        .chain(&full.pareto)
        .map(|m| (structure_of(m), m))
        .collect();
    let refit = |key: &str, nominee: &Nominee| match all_rows_fits.iter().find(|(k, _)| k == key) {
        Some((_, m)) => Ok((*m).clone()),
        None => fit_structure_from(data, target, &nominee.model, &one),
    };
    let stable: Vec<&(String, Nominee)> = ranked
        .iter()
        .filter(|(_, nom)| share(nom.runs) >= STABLE_SHARE)
        .collect();
    let mut winner: Option<(Model, &String, usize)> = None;
    for (key, nom) in &stable {
        let m = refit(key, nom)?;
        let better = winner.as_ref().is_none_or(|(w, wk, _)| {
            m.score
                .total_cmp(&w.score)
                .then(m.complexity.cmp(&w.complexity))
                .then(key.cmp(wk))
                .is_lt()
        });
        if m.score.is_finite() && better {
            winner = Some((m, key, nom.runs));
        }
    }
    let (best, key, votes) = match winner {
        Some(w) => w,
        None => {
            let Some((key, nom)) = ranked.first() else {
                // no nomination: the all-rows search stands
                return Ok(full);
            };
            (refit(key, nom)?, key, nom.runs)
        }
    };
    // the refit snaps and prunes, and may leave a shorter structure than the one voted for
    // (`theta^2 (theta + c)` whose `c` snaps to 0): the report names the structure
    // returned, with its own votes where the runs nominated it too
    let refitted = structure_of(&best);
    let (key, votes) = if refitted == *key {
        (key.clone(), votes)
    } else {
        match ranked.iter().find(|(k, _)| *k == refitted) {
            Some((_, nom)) => (refitted, nom.runs.max(votes)),
            None => (refitted, votes),
        }
    };
    let consensus = Consensus {
        runs,
        structure: key.clone(),
        share: share(votes),
        nominated: std::iter::once(StructureShare {
            template: key.clone(),
            share: share(votes),
        })
        .chain(
            ranked
                .iter()
                .filter(|(k, _)| *k != key)
                .take(MAX_LISTED)
                .map(|(k, nom)| StructureShare {
                    template: k.clone(),
                    share: share(nom.runs),
                }),
        )
        .collect(),
    };
    // what the data cannot tell apart from the winner: the all-rows band, winner excluded
    let mut seen = vec![key.clone()];
    let mut alternatives: Vec<Model> = Vec::new();
    for (k, m) in all_rows_fits.iter().take(1 + full.alternatives.len()) {
        if !seen.contains(k) {
            seen.push(k.clone());
            alternatives.push((*m).clone());
        }
    }
    Ok(SearchResult {
        best,
        pareto: full.pareto,
        alternatives,
        consensus: Some(consensus),
        evaluations,
        duplicate_structures,
        simplified,
        seconds: t0.elapsed().as_secs_f64(),
        error_model: full.error_model,
    })
}
