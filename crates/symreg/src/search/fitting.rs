//! Fitting one candidate: the data a search fits on ([`Problem`]), the criterion that scores
//! a fit, the seeds of the random starts, and the checks on the target.
use super::archive::{Candidate, Fitted};
use super::config::{Criterion, DEFINED_BOXES, FEW_ROWS, MIN_ROWS, RandomStart, ValidSearch};
use crate::eval::Evaluator;
use crate::fit::{InputScales, LmSettings, Unknowns, initial_params, levenberg_marquardt};
use crate::ops::Op;
use crate::ops::OpCosts;
use crate::program::{Node, Program};
use crate::{SrError, Table};
use rand::SeedableRng;
use rand::seq::index::sample;
use rand_chacha::ChaCha8Rng;

/// Added to the normalised loss `MSE / var` inside the criterion's logarithm. It keeps the
/// logarithm finite for an exact fit and makes every fit better than a relative RMSE of
/// `1e-6` count alike, so among exact fits the parameter charge alone decides (rounding
/// noise must not buy extra operators).
const LOSS_FLOOR: f64 = 1e-12;

/// Levenberg-Marquardt stops when one step improves the loss by less than this relative
/// amount. During the search a fit only has to rank its structure, so it stops early; the
/// reported models are refitted to [`super::select`]'s tighter tolerance.
const SEARCH_LM_TOLERANCE: f64 = 1e-6;

/// A target whose variance is below this times `max(|mean|, 1)` is treated as constant:
/// that is rounding noise around one value, with nothing to regress.
const CONSTANT_TARGET_VARIANCE: f64 = 1e-300;

/// Mixing constants of [`derive_seed`]: odd 64-bit numbers with well-spread bits (the first
/// is SplitMix64's golden-ratio increment), so that neighbouring epochs and indices give
/// unrelated seeds after the SplitMix64 finaliser.
const EPOCH_MIX: u64 = 0x9E37_79B9_7F4A_7C15;
const INDEX_MIX: u64 = 0xD1B5_4A32_D192_ED03;

/// Everything fixed during a search.
pub(crate) struct Problem<'a> {
    /// All rows, by column (the reported models are refitted on these).
    pub cols: Vec<&'a [f64]>,
    /// The target on all rows.
    pub y: Vec<f64>,
    /// The rows candidates are fitted on (a seeded subsample of at most `max_fit_rows`).
    pub fit_cols: Vec<Vec<f64>>,
    /// The target on the fitting rows.
    pub fit_y: Vec<f64>,
    /// Variance the criterion normalises the loss by (of the fitting rows when non-zero).
    pub y_var: f64,
    /// Input scales for the canonical starting point.
    pub scales: InputScales,
    /// The complexity of each operator (from the settings).
    pub op_costs: OpCosts,
    /// The settings, checked.
    pub cfg: &'a ValidSearch,
    /// The box every candidate must be defined over ([`SearchConfig::defined_margin`]
    /// around every row's inputs); `None` when not asked for.
    pub domain: Option<Vec<(f64, f64)>>,
    /// The values a candidate may take beside the rows, over [`Problem::domain`]
    /// ([`super::beside`]).
    pub allowed: crate::enclosure::Interval,
    /// For each column, whether a `sin` or `cos` may read it
    /// ([`SearchConfig::harmonic_inputs`]); `None` when any may.
    pub harmonic: Option<Vec<bool>>,
}

/// Which columns of `data` a `sin` or `cos` may read, from `cfg.harmonic_inputs`.
fn harmonic_of(data: &Table, cfg: &ValidSearch) -> Option<Vec<bool>> {
    cfg.harmonic_inputs
        .as_ref()
        .map(|allowed| data.names().iter().map(|n| allowed.contains(n)).collect())
}

/// Whether every `sin` and `cos` of `prog` reads only columns `allowed` marks (true when
/// there is no mask).
pub(crate) fn harmonics_allowed(prog: &Program, allowed: Option<&[bool]>) -> bool {
    let Some(allowed) = allowed else {
        return true;
    };
    // for each subtree on the stack: whether it reads a column a harmonic may not
    let mut stack: Vec<bool> = Vec::with_capacity(prog.nodes.len());
    for n in &prog.nodes {
        let reads_other = match *n {
            Node::Var(j) => !allowed.get(j as usize).copied().unwrap_or(false),
            Node::Const => false,
            Node::Op(op) if op.arity() == 1 => {
                let a = stack.pop().unwrap_or(false);
                if a && matches!(op, Op::Sin | Op::Cos) {
                    return false;
                }
                a
            }
            Node::Op(_) => {
                let b = stack.pop().unwrap_or(false);
                let a = stack.pop().unwrap_or(false);
                a || b
            }
        };
        stack.push(reads_other);
    }
    true
}

/// The box of `cols` widened by `cfg.defined_margin`, when it is set.
fn domain_of(cols: &[&[f64]], cfg: &ValidSearch) -> Option<Vec<(f64, f64)>> {
    cfg.defined_margin
        .map(|m| crate::enclosure::widened_box(cols, m))
}

impl<'a> Problem<'a> {
    /// The problem of a search: candidates are fitted on at most `cfg.max_fit_rows` rows,
    /// drawn from `rng` (in increasing row order) when the data has more.
    pub(crate) fn sampled(
        data: &'a Table,
        target: &[f64],
        y_var: f64,
        cfg: &'a ValidSearch,
        rng: &mut ChaCha8Rng,
    ) -> Self {
        let n = target.len();
        let cols: Vec<&[f64]> = data.columns().iter().map(|c| c.as_slice()).collect();
        let (fit_cols, fit_y): (Vec<Vec<f64>>, Vec<f64>) = if n > cfg.max_fit_rows {
            let mut idx = sample(rng, n, cfg.max_fit_rows).into_vec();
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
        let fit_var = variance(&fit_y);
        let fit_refs: Vec<&[f64]> = fit_cols.iter().map(|c| c.as_slice()).collect();
        let domain = domain_of(&cols, cfg);
        Problem {
            scales: InputScales::new(&fit_refs),
            domain,
            allowed: super::beside::allowed_of(target),
            harmonic: harmonic_of(data, cfg),
            cols,
            y: target.to_vec(),
            fit_cols,
            fit_y,
            y_var: if fit_var > 0.0 { fit_var } else { y_var },
            op_costs: cfg.op_costs().clone(),
            cfg,
        }
    }

    /// The problem of [`super::fit_structure`]: every row is a fitting row.
    pub(crate) fn all_rows(
        data: &'a Table,
        target: &[f64],
        y_var: f64,
        cfg: &'a ValidSearch,
    ) -> Self {
        let cols: Vec<&[f64]> = data.columns().iter().map(|c| c.as_slice()).collect();
        Problem {
            scales: InputScales::new(&cols),
            fit_cols: data.columns().to_vec(),
            fit_y: target.to_vec(),
            domain: domain_of(&cols, cfg),
            allowed: super::beside::allowed_of(target),
            harmonic: harmonic_of(data, cfg),
            cols,
            y: target.to_vec(),
            y_var,
            op_costs: cfg.op_costs().clone(),
            cfg,
        }
    }

    /// The fitting rows, by column.
    pub(crate) fn fit_cols(&self) -> Vec<&[f64]> {
        self.fit_cols.iter().map(|c| c.as_slice()).collect()
    }

    /// What the criterion charges for one fitted parameter, in units of `n ln(mse)`.
    pub(crate) fn param_penalty(&self, n: usize) -> f64 {
        match self.cfg.criterion {
            Criterion::Aic => 2.0 * self.cfg.complexity_penalty,
            _ => self.cfg.complexity_penalty * (n as f64).ln(),
        }
    }

    /// What [`Criterion::Mdl`] charges per unit of complexity, in units of `n ln(mse)`:
    /// `2 ln(B)`, `B` the symbols a structure is written in (the search's operators and the
    /// inputs, at least 2).
    pub(crate) fn structure_charge(&self) -> f64 {
        let symbols = self.cfg.operators.len() + self.cols.len();
        2.0 * (symbols.max(2) as f64).ln()
    }

    /// The criterion (lower is better) of a fit with loss `mse` and `n_params` fitted
    /// parameters on `n` rows: `n ln(mse/var + LOSS_FLOOR)` plus the parameter charge.
    pub(crate) fn score(&self, mse: f64, n_params: usize, n: usize) -> f64 {
        if !mse.is_finite() {
            return f64::INFINITY;
        }
        let n = n as f64;
        let base = n * (mse / self.y_var + LOSS_FLOOR).ln();
        let k = n_params as f64;
        match self.cfg.criterion {
            Criterion::Aic => base + 2.0 * self.cfg.complexity_penalty * k,
            _ => base + self.cfg.complexity_penalty * k * n.ln(),
        }
    }

    /// A candidate turned down without fitting (infinite loss and score), as [`Problem::fit`]
    /// rejects one, so the strategy that proposed it learns it is no good.
    pub(crate) fn rejected(&self, c: &Candidate) -> Fitted {
        let prog = &c.program;
        Fitted {
            program: prog.clone(),
            params: vec![0.0; prog.n_params()],
            mse: f64::INFINITY,
            score: f64::INFINITY,
            complexity: prog.complexity_with(self.cfg.complexity_measure, &self.op_costs),
            source: c.source,
            tag: c.tag,
        }
    }

    /// Fits one candidate on the fitting rows: from its warm start if it has one, else from
    /// the canonical start and, as [`SearchConfig::random_start`] says (always, or when the
    /// canonical start gives no finite loss), one random start drawn from `seed`; keeps the
    /// better.
    /// Non-finite fits, and structures with at least as many parameters as rows (below
    /// [`FEW_ROWS`] rows: more than `n - 2`), are rejected (infinite loss and score).
    pub(crate) fn fit(&self, c: &Candidate, seed: u64) -> Fitted {
        let cols = self.fit_cols();
        let y = &self.fit_y;
        let prog = &c.program;
        let n_params = prog.n_params();
        let complexity = prog.complexity_with(self.cfg.complexity_measure, &self.op_costs);
        let reject = |params: Vec<f64>| Fitted {
            program: prog.clone(),
            params,
            mse: f64::INFINITY,
            score: f64::INFINITY,
            complexity,
            source: c.source,
            tag: c.tag,
        };
        if n_params >= y.len()
            || (y.len() < FEW_ROWS && n_params + 2 > y.len())
            || !harmonics_allowed(prog, self.harmonic.as_deref())
        {
            return reject(vec![0.0; n_params]);
        }
        let mut ev = Evaluator::new(prog);
        let free: Vec<usize> = (0..n_params).collect();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut best_params = Vec::new();
        let mut best = f64::INFINITY;
        let lm = LmSettings::new(self.cfg.lm_iterations, SEARCH_LM_TOLERANCE);
        let mut fit_from = |mut p: Vec<f64>, ev: &mut Evaluator| {
            let mse = levenberg_marquardt(prog, &mut p, Unknowns::Free(&free), &cols, y, &lm, ev);
            if mse < best {
                best = mse;
                best_params = p;
            }
            best
        };
        if let Some(p) = c.params.as_ref().filter(|p| p.len() == n_params) {
            fit_from(p.clone(), &mut ev);
        } else {
            let start = initial_params(prog, &self.scales, None, &cols, y, &mut ev);
            let first = fit_from(start, &mut ev);
            let random = match self.cfg.random_start {
                RandomStart::Always => true,
                RandomStart::OnFailure => !first.is_finite(),
            };
            if random {
                let start = initial_params(prog, &self.scales, Some(&mut rng), &cols, y, &mut ev);
                fit_from(start, &mut ev);
            }
        }
        if !best.is_finite() {
            return reject(vec![0.0; n_params]);
        }
        if let Some(bounds) = &self.domain
            && crate::enclosure::defined_over(prog, &best_params, bounds, DEFINED_BOXES).is_err()
        {
            // a pole, a log of a value <= 0, ... beside the rows: what an engineer reads
            // the equation over (issue 64)
            return reject(best_params);
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

/// Seed of candidate `index` in `epoch`: a SplitMix64 hash, so it depends on nothing else
/// (not on the thread that fits it, nor on the candidates before it).
pub(crate) fn derive_seed(seed: u64, epoch: u64, index: u64) -> u64 {
    let mut z = seed ^ epoch.wrapping_mul(EPOCH_MIX) ^ index.wrapping_mul(INDEX_MIX);
    // SplitMix64's finaliser (Steele, Lea and Flood 2014), with its published constants.
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Population variance (mean of squared deviations from the mean).
pub(crate) fn variance(v: &[f64]) -> f64 {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n
}

/// The target must have one finite value per row of `data`.
pub(crate) fn check_target(data: &Table, target: &[f64]) -> Result<(), SrError> {
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

/// A search needs at least [`MIN_ROWS`] rows and a target that varies; returns its
/// variance.
pub(crate) fn search_target_variance(target: &[f64]) -> Result<f64, SrError> {
    let n = target.len();
    if n < MIN_ROWS {
        return Err(SrError::TooFewRows {
            rows: n,
            needed: MIN_ROWS,
        });
    }
    let mean = target.iter().sum::<f64>() / n as f64;
    let y_var = variance(target);
    if y_var <= CONSTANT_TARGET_VARIANCE * mean.abs().max(1.0)
        || target.iter().all(|&v| v == target[0])
    {
        return Err(SrError::ConstantTarget(target[0]));
    }
    Ok(y_var)
}

/// Relative tolerance of a refit of given constants on the fitting rows ([`refitted`]: the
/// joins of a decomposition, the polynomials and factor models offered to selection; the
/// reported models are refitted again on all rows by selection).
const JOIN_LM_TOLERANCE: f64 = 1e-8;

/// `program` with every constant refitted together on the fitting rows, from `params`,
/// scored as a candidate of the search; `None` when it has at least as many parameters as
/// there are fitting rows, or no finite loss (the search rejects such candidates too).
pub(crate) fn refitted(
    problem: &Problem,
    program: Program,
    mut params: Vec<f64>,
) -> Option<Fitted> {
    let cfg = problem.cfg;
    if params.len() >= problem.fit_y.len()
        || !harmonics_allowed(&program, problem.harmonic.as_deref())
    {
        return None;
    }
    let fit_cols = problem.fit_cols();
    let mut ev = Evaluator::new(&program);
    let free: Vec<usize> = (0..params.len()).collect();
    let start = params.clone();
    let mut mse = levenberg_marquardt(
        &program,
        &mut params,
        Unknowns::Free(&free),
        &fit_cols,
        &problem.fit_y,
        &LmSettings::new(cfg.lm_iterations, JOIN_LM_TOLERANCE),
        &mut ev,
    );
    if !mse.is_finite() {
        params = start;
        mse = ev.mse(&program, &params, &fit_cols, &problem.fit_y);
    }
    if !mse.is_finite() {
        return None;
    }
    let complexity = program.complexity_with(cfg.complexity_measure, &problem.op_costs);
    let n_params = params.len();
    Some(Fitted {
        score: problem.score(mse, n_params, problem.fit_y.len()),
        program,
        params,
        mse,
        complexity,
        source: u8::MAX,
        tag: 0,
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// A harmonic of a declared column passes, one of another column (alone, or mixed
    /// into the argument) does not, and other operators over any column do.
    #[test]
    fn harmonics_read_only_declared_columns() {
        let allowed = [true, false];
        let p = |nodes: Vec<Node>| Program {
            nodes,
            affine: true,
        };
        let sin_a = p(vec![Node::Var(0), Node::Op(Op::Sin)]);
        let cos_b = p(vec![Node::Var(1), Node::Op(Op::Cos)]);
        let sin_ab = p(vec![
            Node::Var(0),
            Node::Var(1),
            Node::Op(Op::Add),
            Node::Op(Op::Sin),
        ]);
        let b_times_sin_a = p(vec![
            Node::Var(1),
            Node::Var(0),
            Node::Op(Op::Sin),
            Node::Op(Op::Mul),
        ]);
        let exp_b = p(vec![Node::Var(1), Node::Op(Op::Exp)]);
        assert!(harmonics_allowed(&sin_a, Some(&allowed)));
        assert!(!harmonics_allowed(&cos_b, Some(&allowed)));
        assert!(!harmonics_allowed(&sin_ab, Some(&allowed)));
        assert!(harmonics_allowed(&b_times_sin_a, Some(&allowed)));
        assert!(harmonics_allowed(&exp_b, Some(&allowed)));
        assert!(harmonics_allowed(&cos_b, None));
    }
    use crate::Op;
    use crate::program::{Node, Program};
    use crate::search::config::SearchConfig;

    fn log_candidate() -> Candidate {
        let program = Program {
            nodes: vec![Node::Var(0), Node::Op(Op::Log)],
            affine: true,
        };
        Candidate::new(program, None, 0)
    }

    fn fit_with(x: Vec<f64>, start: RandomStart, seed: u64) -> Fitted {
        let y: Vec<f64> = x.iter().map(|v| 2.0 * (v + 0.5).ln() + 1.0).collect();
        let data = Table::new(vec!["x".into()], vec![x]).unwrap();
        let cfg = SearchConfig {
            random_start: start,
            // the starts are under test: the truth `log(x + 0.5)` has no value where the
            // rows' box widened by 10 % reaches (x = -0.8), which the domain rule rejects
            defined_margin: None,
            ..SearchConfig::default()
        };
        let valid = cfg.check().expect("valid");
        let problem = Problem::all_rows(&data, &y, 1.0, &valid);
        problem.fit(&log_candidate(), seed)
    }

    // Where the canonical start fits, `OnFailure` keeps its fit and `Always` the better of
    // it and the random start's.
    #[test]
    fn on_failure_keeps_a_finite_canonical_fit() {
        let x: Vec<f64> = (0..60).map(|i| 0.5 + i as f64 / 10.0).collect();
        let y: Vec<f64> = x.iter().map(|v| 2.0 * (v + 0.5).ln() + 1.0).collect();
        let data = Table::new(vec!["x".into()], vec![x.clone()]).unwrap();
        let cfg = SearchConfig::default();
        let valid = cfg.check().expect("valid");
        let problem = Problem::all_rows(&data, &y, 1.0, &valid);
        let cols = problem.fit_cols();
        let cand = log_candidate();
        let mut ev = Evaluator::new(&cand.program);
        let mut p = initial_params(&cand.program, &problem.scales, None, &cols, &y, &mut ev);
        let free: Vec<usize> = (0..p.len()).collect();
        let lm = LmSettings::new(cfg.lm_iterations, SEARCH_LM_TOLERANCE);
        let mse = levenberg_marquardt(
            &cand.program,
            &mut p,
            Unknowns::Free(&free),
            &cols,
            &y,
            &lm,
            &mut ev,
        );
        assert!(mse.is_finite());
        for seed in 0..5 {
            let once = fit_with(x.clone(), RandomStart::OnFailure, seed);
            assert_eq!(once.params, p, "seed {seed}");
            assert_eq!(once.mse.to_bits(), mse.to_bits(), "seed {seed}");
            let both = fit_with(x.clone(), RandomStart::Always, seed);
            assert!(both.mse <= once.mse, "seed {seed}");
        }
    }

    // Where the canonical start gives no finite loss (`log` of the negative rows at the
    // canonical scale), `OnFailure` fits from the random start, the one `Always` draws.
    #[test]
    fn on_failure_falls_back_on_the_random_start() {
        let x: Vec<f64> = (0..60).map(|i| -0.2 + i as f64 / 10.0).collect();
        let mut rescued = 0;
        for seed in 0..40 {
            let once = fit_with(x.clone(), RandomStart::OnFailure, seed);
            let both = fit_with(x.clone(), RandomStart::Always, seed);
            assert_eq!(once.params, both.params, "seed {seed}");
            assert_eq!(once.mse.to_bits(), both.mse.to_bits(), "seed {seed}");
            rescued += usize::from(once.mse.is_finite());
        }
        assert!(rescued > 0, "no random start gave a finite fit");
    }
}
