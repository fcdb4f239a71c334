//! The search loop shared by every strategy: propose, fit in parallel, rank, update.
pub mod generate;
pub mod genetic;
pub mod qlattice;

use crate::eval::Evaluator;
use crate::fit::{InputScales, initial_params, levenberg_marquardt};
use crate::model::{Model, snap_params};
use crate::ops::{Op, parse_operators};
use crate::program::{ComplexityMeasure, Program};
use crate::{SrError, Table};
use generate::Tables;
use rand::SeedableRng;
use rand::seq::index::sample;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::time::Instant;

/// Which search strategy runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Strategy {
    /// QLattice-style path sampling over lineages (cells).
    QLattice,
    /// Island genetic programming.
    Genetic,
    /// Both, sharing a Pareto archive (default).
    #[default]
    Combined,
}

/// How the selected model is chosen.
///
/// With `Bic` and `Aic`, `k` counts fitted parameters: constants snapped to exact values
/// (0, +-1, integers, halves) are not counted, and the selected model is the simplest one
/// whose criterion is within one parameter's charge (`lambda ln n`, or `2 lambda`) of the
/// lowest. Snapping constants to exact values is judged by the same charge (BIC's under
/// `ParetoScore`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Criterion {
    /// Bayesian information criterion `n ln(MSE/var + 1e-12) + lambda k ln n` (default).
    #[default]
    Bic,
    /// Akaike information criterion `n ln(MSE/var + 1e-12) + 2 lambda k`.
    Aic,
    /// PySR's rule: on the Pareto front, among models with loss within 1.5x of the best,
    /// the largest drop of log-loss per unit of complexity.
    ParetoScore,
}

/// Search settings. `Default` gives the paper's set-up: seed 42, 10 epochs, complexity
/// at most 10, BIC with lambda 1, the paper's operators plus `exp`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct SearchConfig {
    /// Seed of every random choice.
    pub seed: u64,
    /// Number of epochs (each proposes `candidates_per_epoch` models).
    pub epochs: usize,
    /// Largest complexity.
    pub max_complexity: usize,
    /// Allowed operator names (see [`Op::parse`]).
    pub operators: Vec<String>,
    /// Search strategy.
    pub strategy: Strategy,
    /// Model selection criterion.
    pub criterion: Criterion,
    /// Weight lambda of the parameter penalty in BIC/AIC.
    pub complexity_penalty: f64,
    /// Stop after this many seconds (checked between batches of candidates; a run that hits
    /// it depends on timing).
    pub time_limit_s: Option<f64>,
    /// Stop after this many fitted models.
    pub max_evaluations: Option<u64>,
    /// Inputs enter as `w x + b` (QLattice) when true.
    pub affine_inputs: bool,
    /// How complexity is counted.
    pub complexity_measure: ComplexityMeasure,
    /// Candidates proposed per epoch.
    pub candidates_per_epoch: usize,
    /// Rows used to fit candidates during the search (a seeded subsample when the data has
    /// more); the reported models are refitted on all rows.
    pub max_fit_rows: usize,
    /// Levenberg-Marquardt iterations per candidate.
    pub lm_iterations: usize,
    /// Snap constants to simple values in reported models when the loss barely changes.
    pub snap_constants: bool,
    /// Relative loss increase allowed when a constant is rounded to 1-3 significant digits
    /// (snaps to exact values such as 0, 1 or 1/2 are judged by the criterion instead).
    pub snap_tolerance: f64,
}

impl Default for SearchConfig {
    fn default() -> Self {
        Self {
            seed: 42,
            epochs: 10,
            max_complexity: 10,
            operators: [
                "add",
                "sub",
                "mul",
                "div",
                "sin",
                "cos",
                "gaussian",
                "gaussian2",
                "log",
                "abs",
                "exp",
            ]
            .iter()
            .map(|s| s.to_string())
            .collect(),
            strategy: Strategy::Combined,
            criterion: Criterion::Bic,
            complexity_penalty: 1.0,
            time_limit_s: None,
            max_evaluations: None,
            affine_inputs: true,
            complexity_measure: ComplexityMeasure::FeaturesPlusOperators,
            candidates_per_epoch: 1000,
            max_fit_rows: 2000,
            lm_iterations: 25,
            snap_constants: true,
            snap_tolerance: 1e-3,
        }
    }
}

impl SearchConfig {
    /// Checks the settings and parses the operators.
    ///
    /// # Errors
    /// [`SrError::UnknownOperator`] or [`SrError::InvalidConfig`].
    pub fn check(&self) -> Result<Vec<Op>, SrError> {
        let ops = parse_operators(&self.operators)?;
        if self.max_complexity == 0 || self.max_complexity > 60 {
            return Err(SrError::InvalidConfig(format!(
                "max_complexity is {}: choose 1 to 60",
                self.max_complexity
            )));
        }
        if self.epochs == 0 {
            return Err(SrError::InvalidConfig(
                "epochs is 0: run at least one epoch".into(),
            ));
        }
        if !(self.complexity_penalty.is_finite() && self.complexity_penalty >= 0.0) {
            return Err(SrError::InvalidConfig(
                "complexity_penalty must be finite and >= 0".into(),
            ));
        }
        if let Some(t) = self.time_limit_s
            && !(t.is_finite() && t > 0.0)
        {
            return Err(SrError::InvalidConfig(
                "time_limit_s must be a positive number of seconds".into(),
            ));
        }
        if self.max_evaluations == Some(0) {
            return Err(SrError::InvalidConfig(
                "max_evaluations is 0: allow at least one model to be fitted".into(),
            ));
        }
        if self.candidates_per_epoch == 0 || self.max_fit_rows < 8 {
            return Err(SrError::InvalidConfig(
                "candidates_per_epoch must be > 0 and max_fit_rows >= 8".into(),
            ));
        }
        Ok(ops)
    }
}

/// Reported after every epoch.
#[derive(Clone, Debug, PartialEq)]
pub struct Progress {
    /// Epochs done (1-based).
    pub epoch: usize,
    /// Epochs planned.
    pub epochs: usize,
    /// Models fitted so far.
    pub evaluations: u64,
    /// Lowest training mean squared error so far.
    pub best_loss: f64,
}

/// What a search returns.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SearchResult {
    /// The model chosen by the criterion.
    pub best: Model,
    /// Best model at each complexity that lowers the loss, by increasing complexity.
    pub pareto: Vec<Model>,
    /// Models fitted.
    pub evaluations: u64,
    /// Wall time in seconds.
    pub seconds: f64,
}

/// A proposed model structure, optionally with parameters to start from.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// The structure.
    pub program: Program,
    /// Warm start (used when its length matches the program).
    pub params: Option<Vec<f64>>,
    /// Which strategy proposed it (index into the combined strategy's parts).
    pub source: u8,
    /// Strategy-specific tag (cell or island).
    pub tag: u32,
}

/// A fitted candidate.
#[derive(Clone, Debug)]
pub struct Fitted {
    /// The structure.
    pub program: Program,
    /// Fitted parameters.
    pub params: Vec<f64>,
    /// Training MSE (on the fitting rows).
    pub mse: f64,
    /// Criterion value, lower is better (`INFINITY` when rejected).
    pub score: f64,
    /// Complexity.
    pub complexity: usize,
    /// Proposing strategy.
    pub source: u8,
    /// Strategy-specific tag.
    pub tag: u32,
}

/// Best fitted model at each complexity so far.
#[derive(Clone, Debug, Default)]
pub struct Archive {
    /// Indexed by complexity.
    pub by_complexity: Vec<Option<Fitted>>,
    /// Best by score.
    pub best: Option<Fitted>,
}

impl Archive {
    fn offer(&mut self, f: &Fitted) {
        if !f.score.is_finite() {
            return;
        }
        if self.by_complexity.len() <= f.complexity {
            self.by_complexity.resize(f.complexity + 1, None);
        }
        let slot = &mut self.by_complexity[f.complexity];
        if slot.as_ref().is_none_or(|s| f.mse < s.mse) {
            *slot = Some(f.clone());
        }
        if self.best.as_ref().is_none_or(|b| f.score < b.score) {
            self.best = Some(f.clone());
        }
    }

    /// Models on the Pareto front (each strictly better than every simpler one).
    pub fn front(&self) -> Vec<Fitted> {
        let mut out: Vec<Fitted> = Vec::new();
        for f in self.by_complexity.iter().flatten() {
            if out.last().is_none_or(|l| f.mse < l.mse) {
                out.push(f.clone());
            }
        }
        out
    }
}

/// A way of proposing candidates and learning from their fits.
pub trait SearchStrategy: Send {
    /// Candidates for this epoch, drawn from `rng` only.
    fn propose(
        &mut self,
        epoch: usize,
        rng: &mut ChaCha8Rng,
        archive: &Archive,
        tables: &Tables,
    ) -> Vec<Candidate>;
    /// Learns from the fitted candidates of this epoch (in proposal order).
    fn update(&mut self, fitted: &[Fitted], archive: &Archive, rng: &mut ChaCha8Rng);
}

/// Everything fixed during a search.
pub(crate) struct Problem<'a> {
    pub cols: Vec<&'a [f64]>,
    pub y: Vec<f64>,
    pub fit_cols: Vec<Vec<f64>>,
    pub fit_y: Vec<f64>,
    pub y_var: f64,
    pub scales: InputScales,
    pub cfg: &'a SearchConfig,
}

impl Problem<'_> {
    fn fit_cols(&self) -> Vec<&[f64]> {
        self.fit_cols.iter().map(|c| c.as_slice()).collect()
    }

    /// What the criterion charges for one fitted parameter, in units of `n ln(mse)`.
    pub(crate) fn param_penalty(&self, n: usize) -> f64 {
        match self.cfg.criterion {
            Criterion::Aic => 2.0 * self.cfg.complexity_penalty,
            _ => self.cfg.complexity_penalty * (n as f64).ln(),
        }
    }

    pub(crate) fn score(&self, mse: f64, n_params: usize, n: usize) -> f64 {
        if !mse.is_finite() {
            return f64::INFINITY;
        }
        let n = n as f64;
        let base = n * (mse / self.y_var + 1e-12).ln();
        let k = n_params as f64;
        match self.cfg.criterion {
            Criterion::Aic => base + 2.0 * self.cfg.complexity_penalty * k,
            _ => base + self.cfg.complexity_penalty * k * n.ln(),
        }
    }

    fn fit(&self, c: &Candidate, seed: u64) -> Fitted {
        let cols = self.fit_cols();
        let y = &self.fit_y;
        let prog = &c.program;
        let n_params = prog.n_params();
        let complexity = prog.complexity(self.cfg.complexity_measure);
        let reject = |params: Vec<f64>| Fitted {
            program: prog.clone(),
            params,
            mse: f64::INFINITY,
            score: f64::INFINITY,
            complexity,
            source: c.source,
            tag: c.tag,
        };
        if n_params >= y.len() {
            return reject(vec![0.0; n_params]);
        }
        let mut ev = Evaluator::new(prog);
        let free: Vec<usize> = (0..n_params).collect();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut best_params = Vec::new();
        let mut best = f64::INFINITY;
        let mut starts: Vec<Vec<f64>> = Vec::new();
        if let Some(p) = c.params.as_ref().filter(|p| p.len() == n_params) {
            starts.push(p.clone());
        } else {
            starts.push(initial_params(prog, &self.scales, None, &cols, y, &mut ev));
            starts.push(initial_params(
                prog,
                &self.scales,
                Some(&mut rng),
                &cols,
                y,
                &mut ev,
            ));
        }
        for mut p in starts {
            let mse = levenberg_marquardt(
                prog,
                &mut p,
                &free,
                &cols,
                y,
                self.cfg.lm_iterations,
                1e-6,
                &mut ev,
            );
            if mse < best {
                best = mse;
                best_params = p;
            }
        }
        if !best.is_finite() {
            return reject(vec![0.0; n_params]);
        }
        Fitted {
            program: prog.clone(),
            params: best_params,
            mse: best,
            score: self.score(best, n_params, y.len()),
            complexity,
            source: c.source,
            tag: c.tag,
        }
    }
}

/// Seed of candidate `index` in `epoch`: a SplitMix64 hash, so it depends on nothing else.
pub(crate) fn derive_seed(seed: u64, epoch: u64, index: u64) -> u64 {
    let mut z = seed
        ^ epoch.wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ index.wrapping_mul(0xD1B5_4A32_D192_ED03);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Mutual information (nats) between each column and the target, from 16 equal-count bins.
pub(crate) fn mutual_information(cols: &[&[f64]], y: &[f64]) -> Vec<f64> {
    const B: usize = 16;
    let bins = |v: &[f64]| -> Vec<usize> {
        let mut idx: Vec<usize> = (0..v.len()).collect();
        idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
        let mut out = vec![0; v.len()];
        let mut rank = 0;
        let mut i = 0;
        while i < idx.len() {
            let mut j = i;
            while j + 1 < idx.len() && v[idx[j + 1]] == v[idx[i]] {
                j += 1;
            }
            for &k in &idx[i..=j] {
                out[k] = (rank * B / v.len()).min(B - 1);
            }
            rank += j - i + 1;
            i = j + 1;
        }
        out
    };
    let by = bins(y);
    let n = y.len() as f64;
    cols.iter()
        .map(|c| {
            let bx = bins(c);
            let mut joint = [[0.0f64; B]; B];
            let mut px = [0.0f64; B];
            let mut py = [0.0f64; B];
            for (&a, &b) in bx.iter().zip(&by) {
                joint[a][b] += 1.0;
                px[a] += 1.0;
                py[b] += 1.0;
            }
            let mut mi = 0.0;
            for a in 0..B {
                for b in 0..B {
                    if joint[a][b] > 0.0 {
                        mi += joint[a][b] / n * (joint[a][b] * n / (px[a] * py[b])).ln();
                    }
                }
            }
            mi
        })
        .collect()
}

struct Combined {
    parts: Vec<Box<dyn SearchStrategy>>,
}

impl SearchStrategy for Combined {
    fn propose(
        &mut self,
        epoch: usize,
        rng: &mut ChaCha8Rng,
        archive: &Archive,
        tables: &Tables,
    ) -> Vec<Candidate> {
        let mut out = Vec::new();
        for (i, p) in self.parts.iter_mut().enumerate() {
            for mut c in p.propose(epoch, rng, archive, tables) {
                c.source = i as u8;
                out.push(c);
            }
        }
        out
    }

    fn update(&mut self, fitted: &[Fitted], archive: &Archive, rng: &mut ChaCha8Rng) {
        for (i, p) in self.parts.iter_mut().enumerate() {
            let mine: Vec<Fitted> = fitted
                .iter()
                .filter(|f| f.source as usize == i)
                .cloned()
                .collect();
            p.update(&mine, archive, rng);
        }
    }
}

/// The target must have one finite value per row of `data`.
fn check_target(data: &Table, target: &[f64]) -> Result<(), SrError> {
    if target.len() != data.n_rows() {
        return Err(SrError::TargetLength {
            target: target.len(),
            data: data.n_rows(),
        });
    }
    if let Some((row, &value)) = target.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(SrError::NonFinite {
            name: "target".into(),
            row,
            value,
        });
    }
    Ok(())
}

/// Runs symbolic regression of `target` on the columns of `data`.
///
/// Candidates are fitted in parallel on the current rayon thread pool; every random choice
/// comes from generators seeded by `(cfg.seed, epoch, candidate index)` and results are
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
    let t0 = Instant::now();
    let ops = cfg.check()?;
    check_target(data, target)?;
    let n = target.len();
    let needed = 2 + if cfg.affine_inputs { 2 } else { 1 } + 2;
    if n < needed.max(8) {
        return Err(SrError::TooFewRows {
            rows: n,
            needed: needed.max(8),
        });
    }
    let mean = target.iter().sum::<f64>() / n as f64;
    let y_var = target.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n as f64;
    if y_var <= 1e-300 * mean.abs().max(1.0) || target.iter().all(|&v| v == target[0]) {
        return Err(SrError::ConstantTarget(target[0]));
    }
    let cols: Vec<&[f64]> = data.columns().iter().map(|c| c.as_slice()).collect();
    let mut master = ChaCha8Rng::seed_from_u64(cfg.seed);
    let (fit_cols, fit_y): (Vec<Vec<f64>>, Vec<f64>) = if n > cfg.max_fit_rows {
        let mut idx = sample(&mut master, n, cfg.max_fit_rows).into_vec();
        idx.sort_unstable();
        (
            cols.iter()
                .map(|c| idx.iter().map(|&i| c[i]).collect())
                .collect(),
            idx.iter().map(|&i| target[i]).collect(),
        )
    } else {
        (cols.iter().map(|c| c.to_vec()).collect(), target.to_vec())
    };
    let fit_refs: Vec<&[f64]> = fit_cols.iter().map(|c: &Vec<f64>| c.as_slice()).collect();
    let mi = mutual_information(&fit_refs, &fit_y);
    let max_mi = mi.iter().cloned().fold(0.0, f64::max);
    let in_w: Vec<f64> = mi
        .iter()
        .map(|&m| if max_mi > 0.0 { 0.1 + m / max_mi } else { 1.0 })
        .collect();
    let fit_mean = fit_y.iter().sum::<f64>() / fit_y.len() as f64;
    let fit_var = fit_y
        .iter()
        .map(|v| (v - fit_mean) * (v - fit_mean))
        .sum::<f64>()
        / fit_y.len() as f64;
    let problem = Problem {
        scales: InputScales::new(&fit_refs),
        cols,
        y: target.to_vec(),
        fit_cols,
        fit_y,
        y_var: if fit_var > 0.0 { fit_var } else { y_var },
        cfg,
    };
    let tables = Tables {
        op_w: ops
            .iter()
            .map(|o| if o.arity() == 2 { 5.3 } else { 1.0 })
            .collect(),
        ops,
        in_w,
        affine: cfg.affine_inputs,
        measure: cfg.complexity_measure,
        max_complexity: cfg.max_complexity,
    };
    let per = cfg.candidates_per_epoch;
    let mut strategy: Box<dyn SearchStrategy> = match cfg.strategy {
        Strategy::QLattice => Box::new(qlattice::QLattice::new(per, &tables)),
        Strategy::Genetic => Box::new(genetic::Genetic::new(per)),
        Strategy::Combined => Box::new(Combined {
            parts: vec![
                Box::new(qlattice::QLattice::new(per / 2, &tables)),
                Box::new(genetic::Genetic::new(per - per / 2)),
            ],
        }),
    };
    let mut archive = Archive::default();
    let mut cache: HashMap<Program, Fitted> = HashMap::new();
    let mut evaluations: u64 = 0;
    let mut stop = false;
    for epoch in 0..cfg.epochs {
        let mut cands = strategy.propose(epoch, &mut master, &archive, &tables);
        if let Some(maxe) = cfg.max_evaluations {
            let left = maxe.saturating_sub(evaluations) as usize;
            if cands.len() > left {
                cands.truncate(left);
                stop = true;
            }
        }
        let mut fitted: Vec<Option<Fitted>> = vec![None; cands.len()];
        let mut todo: Vec<usize> = Vec::new();
        {
            let mut seen: HashMap<&Program, usize> = HashMap::new();
            for (i, c) in cands.iter().enumerate() {
                if let Some(f) = cache.get(&c.program) {
                    let mut f = f.clone();
                    f.source = c.source;
                    f.tag = c.tag;
                    fitted[i] = Some(f);
                } else if seen.insert(&c.program, i).is_none() {
                    todo.push(i);
                }
            }
        }
        // fit in chunks so a time limit can stop between them
        for chunk in todo.chunks(256) {
            if let Some(t) = cfg.time_limit_s
                && t0.elapsed().as_secs_f64() > t
            {
                stop = true;
                break;
            }
            let res: Vec<Fitted> = chunk
                .par_iter()
                .map(|&i| problem.fit(&cands[i], derive_seed(cfg.seed, epoch as u64, i as u64)))
                .collect();
            for (&i, f) in chunk.iter().zip(res) {
                evaluations += 1;
                cache.insert(f.program.clone(), f.clone());
                fitted[i] = Some(f);
            }
        }
        // duplicates within the epoch take the fit of their first occurrence
        for (i, c) in cands.iter().enumerate() {
            if fitted[i].is_none()
                && let Some(f) = cache.get(&c.program)
            {
                let mut f = f.clone();
                f.source = c.source;
                f.tag = c.tag;
                fitted[i] = Some(f);
            }
        }
        let fitted: Vec<Fitted> = fitted.into_iter().flatten().collect();
        for f in &fitted {
            archive.offer(f);
        }
        strategy.update(&fitted, &archive, &mut master);
        let best_loss = archive
            .front()
            .iter()
            .map(|f| f.mse)
            .fold(f64::INFINITY, f64::min);
        progress(&Progress {
            epoch: epoch + 1,
            epochs: cfg.epochs,
            evaluations,
            best_loss,
        });
        if stop
            || cfg
                .time_limit_s
                .is_some_and(|t| t0.elapsed().as_secs_f64() > t)
        {
            break;
        }
    }
    finish(&problem, data, &archive, evaluations, t0)
}

/// Fits the constants of one given structure (inputs by column index of `data`) to `target`
/// with Levenberg-Marquardt on all rows, from the canonical start and one seeded random
/// start, then snaps constants as [`search`] does. Useful to test whether a law is
/// expressible, and to refit a known structure on new data.
///
/// # Errors
/// As [`search`], plus [`SrError::MalformedModel`] for an invalid program.
pub fn fit_structure(
    data: &Table,
    target: &[f64],
    program: &Program,
    cfg: &SearchConfig,
) -> Result<Model, SrError> {
    cfg.check()?;
    if !program.is_valid() || program.vars().iter().any(|&j| j as usize >= data.n_cols()) {
        return Err(SrError::MalformedModel(
            "the program is not a valid expression over the data's columns".into(),
        ));
    }
    check_target(data, target)?;
    let n = target.len();
    if n <= program.n_params() {
        return Err(SrError::TooFewRows {
            rows: n,
            needed: program.n_params() + 1,
        });
    }
    let mean = target.iter().sum::<f64>() / n as f64;
    let y_var = target.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n as f64;
    if target.iter().all(|&v| v == target[0]) {
        return Err(SrError::ConstantTarget(target[0]));
    }
    let cols: Vec<&[f64]> = data.columns().iter().map(|c| c.as_slice()).collect();
    let problem = Problem {
        scales: InputScales::new(&cols),
        fit_cols: data.columns().to_vec(),
        fit_y: target.to_vec(),
        cols,
        y: target.to_vec(),
        y_var,
        cfg,
    };
    let cand = Candidate {
        program: program.clone(),
        params: None,
        source: 0,
        tag: 0,
    };
    let f = problem.fit(&cand, cfg.seed);
    let mut archive = Archive::default();
    archive.offer(&f);
    finish(&problem, data, &archive, 1, Instant::now()).map(|r| r.best)
}

fn finish(
    problem: &Problem,
    data: &Table,
    archive: &Archive,
    evaluations: u64,
    t0: Instant,
) -> Result<SearchResult, SrError> {
    let cfg = problem.cfg;
    let mut reported: Vec<Fitted> = archive.front();
    if let Some(b) = &archive.best
        && !reported.iter().any(|f| f.program == b.program)
    {
        reported.push(b.clone());
    }
    if reported.is_empty() {
        return Err(SrError::NoModel);
    }
    let full_cols = &problem.cols;
    let y = &problem.y;
    let n = y.len();
    let refined: Vec<Model> = reported
        .par_iter()
        .map(|f| {
            let prog = &f.program;
            let mut ev = Evaluator::new(prog);
            let mut params = f.params.clone();
            let free: Vec<usize> = (0..params.len()).collect();
            let mut mse =
                levenberg_marquardt(prog, &mut params, &free, full_cols, y, 50, 1e-12, &mut ev);
            if !mse.is_finite() {
                params = f.params.clone();
                mse = ev.mse(prog, &params, full_cols, y);
            }
            let mut n_exact = 0;
            if cfg.snap_constants && mse.is_finite() {
                (mse, n_exact) = snap_params(
                    prog,
                    &mut params,
                    full_cols,
                    y,
                    cfg.snap_tolerance,
                    1e-14 * problem.y_var,
                    problem.param_penalty(n),
                );
            }
            // parameters fixed at exact values are no longer fitted: the criterion does not
            // charge for them
            to_model(
                prog,
                params,
                mse,
                problem.score(mse, prog.n_params() - n_exact, n),
                f.complexity,
                data,
            )
        })
        .collect();
    let mut models: Vec<Model> = refined
        .into_iter()
        .filter(|m| m.train_mse.is_finite())
        .collect();
    if models.is_empty() {
        return Err(SrError::NoModel);
    }
    models.sort_by(|a, b| {
        a.complexity
            .cmp(&b.complexity)
            .then(a.train_mse.total_cmp(&b.train_mse))
    });
    let mut pareto: Vec<Model> = Vec::new();
    for m in &models {
        if pareto
            .last()
            .is_none_or(|l: &Model| m.train_mse < l.train_mse && m.complexity > l.complexity)
        {
            pareto.push(m.clone());
        }
    }
    let best = match cfg.criterion {
        Criterion::ParetoScore => pareto_score_pick(&pareto),
        _ => {
            // The simplest model whose criterion is within one parameter's charge of the
            // best: a structure picked out of thousands must earn at least that much to
            // justify extra operators (otherwise a near-dead term that happens to fit the
            // noise, its constants snapped, would win).
            let best_score = models
                .iter()
                .map(|m| m.score)
                .min_by(|a, b| a.total_cmp(b))
                .unwrap_or(f64::INFINITY);
            let margin = problem.param_penalty(n);
            models
                .iter()
                .filter(|m| m.score <= best_score + margin)
                .min_by(|a, b| {
                    a.complexity
                        .cmp(&b.complexity)
                        .then(a.score.total_cmp(&b.score))
                })
                .cloned()
        }
    }
    .ok_or(SrError::NoModel)?;
    Ok(SearchResult {
        best,
        pareto,
        evaluations,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

fn pareto_score_pick(pareto: &[Model]) -> Option<Model> {
    let min_loss = pareto
        .iter()
        .map(|m| m.train_mse)
        .fold(f64::INFINITY, f64::min);
    let mut best: Option<(f64, &Model)> = None;
    let mut prev: Option<&Model> = None;
    for m in pareto {
        let s = match prev {
            None => 0.0,
            Some(p) => {
                -((m.train_mse.max(1e-300)).ln() - (p.train_mse.max(1e-300)).ln())
                    / (m.complexity as f64 - p.complexity as f64).max(1.0)
            }
        };
        if m.train_mse <= 1.5 * min_loss && best.is_none_or(|(b, _)| s > b) {
            best = Some((s, m));
        }
        prev = Some(m);
    }
    best.map(|(_, m)| m.clone())
}

fn to_model(
    prog: &Program,
    params: Vec<f64>,
    mse: f64,
    score: f64,
    complexity: usize,
    data: &Table,
) -> Model {
    // Renumber the inputs so the model names only the features it uses.
    let used = prog.vars();
    let names: Vec<String> = used
        .iter()
        .map(|&j| data.names()[j as usize].clone())
        .collect();
    let map: HashMap<u16, u16> = used
        .iter()
        .enumerate()
        .map(|(i, &j)| (j, i as u16))
        .collect();
    let nodes = prog
        .nodes
        .iter()
        .map(|n| match n {
            crate::program::Node::Var(j) => {
                crate::program::Node::Var(map.get(j).copied().unwrap_or(0))
            }
            other => *other,
        })
        .collect();
    Model {
        feature_names: names,
        program: Program {
            nodes,
            affine: prog.affine,
        },
        params,
        complexity,
        train_mse: mse,
        score,
    }
}
