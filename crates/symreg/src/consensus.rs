//! Consensus selection: the structure the data gives back most often.
//!
//! One search picks one structure, and on noisy data a resample of the rows often picks
//! another that fits as well: the choice among the near-best is a draw. Consensus selection
//! ([`SearchConfig::consensus_runs`](crate::SearchConfig::consensus_runs) = B > 0) turns the
//! draw into a vote:
//! 1. the search runs once on all rows (its Pareto front and its near-best models are
//!    reported as usual);
//! 2. it runs again on B bootstrap resamples of the rows (run `r` draws its rows from a
//!    generator seeded by the seed and `r`, and searches with seed `seed + r + 1`, as
//!    [`crate::stability()`] does), one after the other, each search parallel inside;
//! 3. each run nominates the structures it found: its selected model, its
//!    [`SearchResult::alternatives`] and every member of its Pareto front, each structure
//!    once per run ([`crate::stability::structure_of`]);
//! 4. the structures nominated by at least half the runs ([`STABLE_SHARE`]) are the stable
//!    ones; each is refitted on all rows (the all-rows search's own fit when it found the
//!    structure, else the constants of the run that nominated it first, refitted from
//!    there) and scored by the criterion on all rows; the best-scoring stable structure
//!    wins (ties: the simpler, then by text). When no structure is stable, the most
//!    nominated one wins. The report names the structure of the winner as refitted (snapping
//!    may shorten it), with its own share where the runs nominated it too.
//!
//! The report ([`Consensus`]) gives the winner's share (runs nominating it / B) and the
//! most nominated structures. This is stability selection (Meinshausen and Bühlmann 2010)
//! applied to whole structures: first keep what the data gives back, then choose by fit
//! among what is kept. A structure that only one draw of the rows supports cannot win
//! however well it fits that draw; the price is accuracy where the true correction is more
//! complex than anything the resamples agree on. It costs B + 1 searches.
use crate::canonical::structure_of;
use crate::search::{SearchResult, ValidSearch, fit_structure_from};
use crate::stability::{StructureShare, bootstrap_rows};
use crate::{Model, Progress, SrError, Table};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::time::Instant;

/// Most structures a [`Consensus`] report lists besides the winner.
pub const MAX_LISTED: usize = 5;

/// Share of the runs that must nominate a structure for it to count as stable.
pub const STABLE_SHARE: f64 = 0.5;

/// Largest number of consensus runs accepted.
pub const MAX_CONSENSUS_RUNS: usize = 1000;

/// What consensus selection reports (JSON `consensus` in a search result).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Consensus {
    /// Bootstrap runs (B).
    pub runs: usize,
    /// The winning structure, every constant written `c`.
    pub structure: String,
    /// Share of runs that nominated it (0 to 1).
    pub share: f64,
    /// The winner, then the most nominated other structures (at most [`MAX_LISTED`]);
    /// shares do not sum to 1, since a run nominates every structure it found.
    pub nominated: Vec<StructureShare>,
}

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
