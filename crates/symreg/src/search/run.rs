//! The main loop: each epoch the strategy proposes, new structures are fitted in parallel,
//! the archive keeps the best per complexity, the strategy learns, progress is reported.
use super::archive::{Archive, Candidate, Fitted};
use super::config::{ErrorModel, SearchConfig, ValidSearch};
use super::decompose::{Spent, decompositions, polynomials};
use super::fitting::{Problem, check_target, derive_seed, search_target_variance};
use super::mutual_information::input_priors;
use super::power;
use super::progress::Progress;
use super::propose::{self, ROUNDS_PER_EPOCH, Step, Tables};
use super::select::{Counts, Finalists, SearchResult, select};
use super::vote;
use crate::canonical::{self, Effort};
use crate::nesting::NestingRules;
use crate::program::Program;
use crate::{SrError, Table};
use hxai_table::Pool;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::collections::HashMap;
use std::time::Instant;

/// Candidates fitted between two looks at the clock: large enough to keep every thread
/// busy (a few hundred fits of about a millisecond each), small enough that a time limit
/// overshoots by a fraction of a second at most.
const FIT_CHUNK: usize = 256;

/// Runs symbolic regression of `target` on the columns of `data`: one search, or with
/// [`SearchConfig::consensus_runs`] > 0 the consensus of that many bootstrap searches
/// ([`crate::consensus`]).
///
/// Candidates are fitted in parallel on the threads `cfg.par` chooses (by default the
/// caller's rayon pool); every random choice
/// comes from generators seeded by `(cfg.seed, round of the run, candidate index)` and results are
/// collected in proposal order, so the result is bit-identical for any number of threads
/// (unless `time_limit_s` stops the run).
///
/// # Errors
/// Mismatched lengths, non-finite or constant target, too few rows, bad configuration, or
/// no finite model at all.
pub fn search(
    data: &Table,
    target: &[f64],
    cfg: &SearchConfig,
    progress: &mut dyn FnMut(&Progress),
) -> Result<SearchResult, SrError> {
    search_checked(data, target, &cfg.check()?, progress)
}

/// [`search`] with a configuration already checked ([`SearchConfig::check`]): what a caller
/// that runs many searches with one configuration (a hybrid table's fit, its comparison's
/// folds, a stability run's resamples) calls, so the configuration is checked once. What
/// depends on the table (the cross-validation folds against its rows) is checked here.
///
/// # Errors
/// As [`search`], except the configuration's own checks.
pub fn search_checked(
    data: &Table,
    target: &[f64],
    cfg: &ValidSearch,
    progress: &mut dyn FnMut(&Progress),
) -> Result<SearchResult, SrError> {
    if cfg.criterion == crate::Criterion::CrossValidation && cfg.cv_folds > target.len() {
        // cross-validation would quietly use fewer folds; say so instead (as `--folds` does)
        return Err(SrError::InvalidConfig(format!(
            "cannot make {} cross-validation folds (--cv-folds) from {} rows: use at most {}",
            cfg.cv_folds,
            target.len(),
            target.len()
        )));
    }
    if cfg.consensus_runs > 0 {
        return vote::search_with(data, target, cfg, progress, &plain_search);
    }
    plain_search(data, target, cfg, progress)
}

/// One search, whatever [`SearchConfig::consensus_runs`] says.
pub(crate) fn plain_search(
    data: &Table,
    target: &[f64],
    cfg: &ValidSearch,
    progress: &mut dyn FnMut(&Progress),
) -> Result<SearchResult, SrError> {
    search_at_depth(data, target, cfg, progress, 0)
}

/// A sub-search of a decomposition ([`decompositions`]) at `depth`, without progress.
pub(crate) fn search_at(
    data: &Table,
    target: &[f64],
    cfg: &ValidSearch,
    depth: u8,
) -> Result<SearchResult, SrError> {
    search_at_depth(data, target, cfg, &mut |_| {}, depth)
}

fn search_at_depth(
    data: &Table,
    target: &[f64],
    cfg: &ValidSearch,
    progress: &mut dyn FnMut(&Progress),
    depth: u8,
) -> Result<SearchResult, SrError> {
    let t0 = Instant::now();
    let (ops, nesting) = (cfg.operators(), cfg.nesting());
    check_target(data, target)?;
    if cfg.error_model == ErrorModel::Multiplicative
        && let Some(row) = target.iter().position(|&v| v <= 0.0)
    {
        return Err(SrError::InvalidConfig(format!(
            "the multiplicative error model needs a positive target, but row {row} is {}: \
             use the additive (or auto) error model",
            hxai_table::format_number(target[row])
        )));
    }
    let y_var = search_target_variance(target)?;
    // One generator draws the fitting rows, then every proposal and update, in that order.
    let mut master = ChaCha8Rng::seed_from_u64(cfg.seed);
    let problem = Problem::sampled(data, target, y_var, cfg, &mut master);
    let in_w = input_priors(&problem.fit_cols(), &problem.fit_y);
    let tables = Tables::for_search(ops.to_vec(), in_w, cfg, problem.op_costs.clone());
    let mut strategy = propose::build(cfg.strategy, cfg.candidates_per_epoch, &tables);
    let mut state = LoopState {
        archive: Archive::with_runners_up(cfg.runners_up),
        ..LoopState::default()
    };
    let pool = cfg.par.pool();
    'epochs: for epoch in 0..cfg.epochs {
        for round in 0..ROUNDS_PER_EPOCH {
            let step = Step {
                round,
                tables: &tables,
            };
            let mut cands = strategy.propose(step, &mut master);
            let budget_spent = state.cut_to_budget(&mut cands, cfg.max_evaluations);
            let (fitted, timed_out) = state.fit_epoch(
                &problem,
                nesting,
                &cands,
                (epoch * ROUNDS_PER_EPOCH + round) as u64,
                t0,
                &pool,
            );
            for f in &fitted {
                state.archive.offer(f);
            }
            strategy.update(&fitted, &state.archive, &mut master);
            if budget_spent || timed_out || time_is_up(cfg, t0) {
                progress(&Progress {
                    epoch: epoch + 1,
                    epochs: cfg.epochs,
                    evaluations: state.evaluations,
                    best_loss: state.archive.best_loss(),
                });
                break 'epochs;
            }
        }
        progress(&Progress {
            epoch: epoch + 1,
            epochs: cfg.epochs,
            evaluations: state.evaluations,
            best_loss: state.archive.best_loss(),
        });
    }
    // the most accurate model as an oracle for separability: a sum or product of smaller
    // problems, searched apart and joined, is one more candidate for selection
    let spent = Spent::new(state.evaluations, t0);
    let mut decomposition =
        decompositions(&problem, data, &state.archive, spent, depth, &search_at)?;
    // and, on a problem of a few inputs, a polynomial of a transformed target
    if cfg.separability {
        decomposition.candidates.extend(polynomials(&problem, ops));
    }
    // and closed-form factor models: products and sums of powers and other one-column
    // shapes (the power primitive), on the top-level problem only
    if cfg.power_laws && depth == 0 {
        decomposition
            .candidates
            .extend(power::factor_models(&problem, ops, nesting));
    }
    state.evaluations += decomposition.evaluations;
    let finalists = Finalists {
        archive: &state.archive,
        extra: &decomposition.candidates,
    };
    let counts = Counts {
        evaluations: state.evaluations,
        duplicate_structures: state.duplicate_structures,
    };
    select(&problem, data, finalists, counts, t0, &pool)
}

/// Whether the run has used up its `time_limit_s`.
fn time_is_up(cfg: &SearchConfig, t0: Instant) -> bool {
    cfg.time_limit_s
        .is_some_and(|t| t0.elapsed().as_secs_f64() > t)
}

/// The key by which a search tells structures apart: the program's canonical structure
/// at [`Effort::Fast`], cheap enough to compute for every new candidate.
fn search_key(program: &Program) -> String {
    canonical::structure_with(program, &[], Effort::Fast)
        .expr
        .to_text(None, true)
}

/// What the loop carries from epoch to epoch.
#[derive(Default)]
struct LoopState {
    /// Best fit per complexity.
    archive: Archive,
    /// Every structure fitted so far: a structure is fitted once per search.
    cache: HashMap<Program, Fitted>,
    /// The simplest program fitted of each structure key ([`Effort::Fast`]).
    structures: HashMap<String, Program>,
    /// The structure key of every program keyed so far.
    keys: HashMap<Program, String>,
    /// Models fitted so far (cache hits and skipped equivalents not counted).
    evaluations: u64,
    /// Candidates whose structure key had been fitted under another program.
    duplicate_structures: u64,
}

impl LoopState {
    /// Drops the candidates beyond `max_evaluations`; true when the budget is now spent.
    fn cut_to_budget(&self, cands: &mut Vec<Candidate>, max_evaluations: Option<u64>) -> bool {
        if let Some(maxe) = max_evaluations {
            let left = maxe.saturating_sub(self.evaluations) as usize;
            if cands.len() > left {
                cands.truncate(left);
                return true;
            }
        }
        false
    }

    /// The fits of this round's candidates (`step` numbers the round in the run), in
    /// proposal order: structures that break the nesting constraints rejected unfitted (and
    /// not counted as evaluations), cached programs reused, and, under
    /// [`SearchConfig::skip_equivalent`], a program whose structure key
    /// ([`Effort::Fast`]) was fitted under another program no more complex given that fit; the first
    /// occurrence of each new structure fitted (in parallel, seeded by its index), later
    /// duplicates given that fit. Also returns whether the time limit cut the epoch short
    /// (the unfitted candidates are then left out).
    fn fit_epoch(
        &mut self,
        problem: &Problem,
        nesting: &NestingRules,
        cands: &[Candidate],
        step: u64,
        t0: Instant,
        pool: &Pool,
    ) -> (Vec<Fitted>, bool) {
        let cfg = problem.cfg;
        let mut fitted: Vec<Option<Fitted>> = vec![None; cands.len()];
        // candidates to fit, and for each skipped equivalent the program whose fit it takes
        let mut todo: Vec<usize> = Vec::new();
        let mut takes: Vec<(usize, Program)> = Vec::new();
        {
            let mut fresh: Vec<usize> = Vec::new();
            let mut seen: HashMap<&Program, usize> = HashMap::new();
            for (i, c) in cands.iter().enumerate() {
                if !nesting.allows(&c.program) {
                    fitted[i] = Some(problem.rejected(c));
                } else if let Some(f) = self.cache.get(&c.program) {
                    fitted[i] = Some(f.relabelled(c));
                } else if seen.insert(&c.program, i).is_none() {
                    fresh.push(i);
                }
            }
            // candidates too long to key are fitted unkeyed
            if let Some(max) = cfg.max_key_nodes {
                let (short, long) = fresh
                    .iter()
                    .partition(|&&i| cands[i].program.nodes.len() <= max);
                fresh = short;
                todo = long;
            }
            // a program skipped as an equivalent is not in `cache`, and comes back often:
            // its key is kept, so the e-graph runs once per program
            let unkeyed: Vec<usize> = fresh
                .iter()
                .copied()
                .filter(|&i| !self.keys.contains_key(&cands[i].program))
                .collect();
            let new_keys: Vec<String> = pool.install(|| {
                unkeyed
                    .par_iter()
                    .map(|&i| search_key(&cands[i].program))
                    .collect()
            });
            for (&i, key) in unkeyed.iter().zip(new_keys) {
                self.keys.insert(cands[i].program.clone(), key);
            }
            let complexity =
                |p: &Program| p.complexity_with(cfg.complexity_measure, &problem.op_costs);
            for i in fresh {
                let program = &cands[i].program;
                let key = match self.keys.get(program) {
                    Some(k) => k.clone(),
                    None => search_key(program),
                };
                match self.structures.get(&key) {
                    // a shorter spelling of a fitted structure is fitted and spells it from
                    // now on, so that the search keeps the simplest form of each structure
                    Some(first) if complexity(program) < complexity(first) => {
                        self.structures.insert(key, program.clone());
                        todo.push(i);
                    }
                    Some(first) => {
                        self.duplicate_structures += 1;
                        if cfg.skip_equivalent {
                            takes.push((i, first.clone()));
                        } else {
                            todo.push(i);
                        }
                    }
                    None => {
                        self.structures.insert(key, program.clone());
                        todo.push(i);
                    }
                }
            }
        }
        let mut timed_out = false;
        for chunk in todo.chunks(FIT_CHUNK) {
            if time_is_up(cfg, t0) {
                timed_out = true;
                break;
            }
            let res: Vec<Fitted> = pool.install(|| {
                chunk
                    .par_iter()
                    .map(|&i| problem.fit(&cands[i], derive_seed(cfg.seed, step, i as u64)))
                    .collect()
            });
            for (&i, f) in chunk.iter().zip(res) {
                self.evaluations += 1;
                self.cache.insert(f.program.clone(), f.clone());
                fitted[i] = Some(f);
            }
        }
        // skipped equivalents take the fit of the structure's first program (unless the
        // time limit left that unfitted)
        for (i, first) in takes {
            if let Some(f) = self.cache.get(&first) {
                fitted[i] = Some(f.relabelled(&cands[i]));
            }
        }
        // duplicates within the epoch take the fit of their first occurrence
        for (i, c) in cands.iter().enumerate() {
            if fitted[i].is_none()
                && let Some(f) = self.cache.get(&c.program)
            {
                fitted[i] = Some(f.relabelled(c));
            }
        }
        (fitted.into_iter().flatten().collect(), timed_out)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::Op;
    use crate::nesting::Nesting;
    use crate::program::Node;

    /// 50 rows of `x0`, `x1` and the target `y = x0 + 2 x1`.
    fn sum_table() -> (Table, Vec<f64>) {
        let x0: Vec<f64> = (0..50).map(|i| 1.0 + i as f64 / 10.0).collect();
        let x1: Vec<f64> = (0..50).map(|i| ((i * 7) % 11) as f64).collect();
        let y: Vec<f64> = x0.iter().zip(&x1).map(|(a, b)| a + 2.0 * b).collect();
        let data = Table::new(vec!["x0".into(), "x1".into()], vec![x0, x1]).unwrap();
        (data, y)
    }

    /// Fits `first` then `second` as two rounds of one search under `cfg` on [`sum_table`]:
    /// the loop's state after them and each round's fits.
    fn two_rounds(
        cfg: &SearchConfig,
        first: &[Candidate],
        second: &[Candidate],
    ) -> (LoopState, Vec<Fitted>, Vec<Fitted>) {
        let (data, y) = sum_table();
        let valid = cfg.check().unwrap();
        let problem = Problem::all_rows(&data, &y, 1.0, &valid);
        let rules = Nesting::none().rules().unwrap();
        let pool = cfg.par.pool();
        let mut state = LoopState::default();
        let t0 = Instant::now();
        let (f1, _) = state.fit_epoch(&problem, &rules, first, 0, t0, &pool);
        let (f2, _) = state.fit_epoch(&problem, &rules, second, 1, t0, &pool);
        (state, f1, f2)
    }

    // `x0 + x1`, `x1 + x0` and `x0 + x1` again, over two rounds: the exact repeat is a cache
    // hit either way; the reordered one is a duplicate structure, fitted again only when
    // `skip_equivalent` is off.
    #[test]
    fn an_equal_structure_takes_the_earlier_fit_unless_told_otherwise() {
        let cand = |nodes: Vec<Node>, tag: u32| {
            Candidate::new(
                Program {
                    nodes,
                    affine: true,
                },
                None,
                tag,
            )
        };
        let ab = vec![Node::Var(0), Node::Var(1), Node::Op(Op::Add)];
        let ba = vec![Node::Var(1), Node::Var(0), Node::Op(Op::Add)];
        for skip in [true, false] {
            let cfg = SearchConfig {
                skip_equivalent: skip,
                ..SearchConfig::default()
            };
            let first = [cand(ab.clone(), 0)];
            let second = [cand(ba.clone(), 1), cand(ab.clone(), 2)];
            let (state, f1, f2) = two_rounds(&cfg, &first, &second);
            assert_eq!(f2.len(), 2);
            assert_eq!(state.duplicate_structures, 1, "skip {skip}");
            assert_eq!(state.evaluations, if skip { 1 } else { 2 }, "skip {skip}");
            assert_eq!(f2[1].mse, f1[0].mse, "the exact repeat is a cache hit");
            assert_eq!(f2[0].tag, 1, "the fit is credited to the proposal");
            if skip {
                assert_eq!(f2[0].program, f1[0].program, "the earlier program's fit");
            } else {
                assert_eq!(f2[0].program.nodes, ba);
            }
        }
    }

    // `max_key_nodes` keys only candidates of at most that many nodes: `x1 + x0` (3 nodes)
    // after `x0 + x1` is skipped as an equivalent when keyed, fitted as new when not
    #[test]
    fn candidates_longer_than_max_key_nodes_are_fitted_unkeyed() {
        let prog = |nodes: Vec<Node>| Program {
            nodes,
            affine: true,
        };
        let ab = prog(vec![Node::Var(0), Node::Var(1), Node::Op(Op::Add)]);
        let ba = prog(vec![Node::Var(1), Node::Var(0), Node::Op(Op::Add)]);
        for (max, keyed) in [
            (None, true),
            (Some(3), true),
            (Some(2), false),
            (Some(0), false),
        ] {
            let cfg = SearchConfig {
                max_key_nodes: max,
                ..SearchConfig::default()
            };
            let c = |p: &Program| Candidate::new(p.clone(), None, 0);
            let (state, _, f) = two_rounds(&cfg, &[c(&ab)], &[c(&ba)]);
            assert_eq!(state.duplicate_structures, u64::from(keyed), "{max:?}");
            assert_eq!(state.evaluations, if keyed { 1 } else { 2 }, "{max:?}");
            assert_eq!(
                f[0].program,
                if keyed { ab.clone() } else { ba.clone() },
                "{max:?}"
            );
            assert_eq!(state.structures.len(), usize::from(keyed), "{max:?}");
        }
    }

    // a shorter spelling of a fitted structure is fitted, not skipped: `(x0 + x1) + c`
    // first, then `x0 + x1`
    #[test]
    fn a_shorter_spelling_is_fitted() {
        let prog = |nodes: Vec<Node>| Program {
            nodes,
            affine: true,
        };
        let long = prog(vec![
            Node::Var(0),
            Node::Var(1),
            Node::Op(Op::Add),
            Node::Const,
            Node::Op(Op::Add),
        ]);
        let short = prog(vec![Node::Var(0), Node::Var(1), Node::Op(Op::Add)]);
        assert_eq!(search_key(&long), search_key(&short), "one structure");
        let c = |p: &Program| Candidate::new(p.clone(), None, 0);
        let cfg = SearchConfig::default();
        let (state, _, f) = two_rounds(&cfg, &[c(&long)], &[c(&short), c(&long)]);
        assert_eq!(state.evaluations, 2);
        assert_eq!(state.duplicate_structures, 0, "the long one is a cache hit");
        assert_eq!(f[0].program, short);
    }
}
