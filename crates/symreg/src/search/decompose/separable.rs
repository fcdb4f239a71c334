//! Separability: the decomposition the oracle ([`super::oracle`]) shows, searched in parts
//! (AI Feynman's insight, Udrescu and Tegmark 2020; issue 24 item 2).
//!
//! [`decompositions`] asks the search's most accurate model which inputs only add or
//! multiply ([`super::oracle::groups`]). Each group becomes a smaller problem: the oracle
//! with the other inputs at their medians is its target, searched on its own columns (and
//! once more decomposed). The sub-models are joined back ([`super::join`]) and offered to
//! selection as one candidate, refitted, snapped and judged like every model, so it replaces
//! the oracle only when the data prefers it. When nothing splits, a symmetric pair
//! ([`super::symmetry`]) is replaced by one input. The sub-searches are the loop's own,
//! passed in as a closure ([`SubSearch`]): this layer never calls the loop by name.
use super::join::{Join, join_programs};
use super::oracle::{Oracle, groups, median};
use super::symmetry;
use crate::eval::Evaluator;
use crate::ops::Op;
use crate::program::{Node, Program};
use crate::search::SearchResult;
use crate::search::archive::{Archive, Fitted};
use crate::search::config::ValidSearch;
use crate::search::fitting::{Problem, derive_seed, refitted};
use crate::{Model, SrError, Table};
use std::time::Instant;

/// Sub-searches may decompose once more (a sum of products, a product of sums); deeper is
/// not tried.
pub(crate) const MAX_DEPTH: u8 = 2;

/// The oracle is trusted only when its training MSE is below this share of the target's
/// variance (R² above 0.999): a rough fit has mixed differences of its own.
const ORACLE_MAX_RELATIVE_MSE: f64 = 1e-3;

/// Pairs of rows each pair of inputs is tested on.
const TEST_POINTS: usize = 200;

/// Mixed differences below this share of the function's spread are taken as zero...
const MIN_TOLERANCE: f64 = 0.02;

/// ... or below this many times the oracle's relative RMS error, whichever is larger: the
/// oracle's own error enters each mixed difference four times.
const ERROR_MULTIPLE: f64 = 6.0;

/// Fewest evaluations left in a budget for a decomposition to be tried.
const MIN_EVALUATIONS_LEFT: u64 = 500;

/// What a decomposition adds to a search: candidates for selection and the evaluations
/// their sub-searches spent.
#[derive(Default)]
pub(crate) struct Decomposition {
    pub candidates: Vec<Fitted>,
    pub evaluations: u64,
}

/// A sub-search of a decomposition: the rows, the target, the settings and the depth of the
/// sub-problem (the loop's own search, without progress).
pub(crate) type SubSearch<'a> =
    dyn Fn(&Table, &[f64], &ValidSearch, u8) -> Result<SearchResult, SrError> + 'a;

/// What the search has spent when it asks for decompositions: the models it fitted and
/// when it started (the sub-searches share what is left of its budget and time).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Spent {
    /// Models fitted so far.
    pub evaluations: u64,
    /// When the search started.
    pub since: Instant,
}

impl Spent {
    /// `evaluations` fitted by a search started at `since`.
    pub(crate) fn new(evaluations: u64, since: Instant) -> Self {
        Self { evaluations, since }
    }
}

/// Where a decomposition's sub-searches run, and what they may spend.
struct Context<'a, 'p> {
    problem: &'p Problem<'a>,
    data: &'p Table,
    budget: Option<u64>,
    time_left: Option<f64>,
    depth: u8,
    /// The test points the oracle was asked on, one column per input.
    points: &'p [Vec<f64>],
    /// The search's operators.
    ops: &'p [Op],
    sub_search: &'p SubSearch<'p>,
}

impl Context<'_, '_> {
    /// Searches `target` on the columns `names` of the data as sub-problem `index` of
    /// `share` still to come (its part of the budget and time); `None` when the sub-problem
    /// has no model (a target that does not vary, or no finite fit).
    fn sub_search(
        &mut self,
        names: &[String],
        columns: Option<Vec<Vec<f64>>>,
        target: &[f64],
        index: usize,
        share: usize,
        out: &mut Decomposition,
    ) -> Result<Option<(Model, Table)>, SrError> {
        let cfg = self.problem.cfg;
        let sub_data = match columns {
            Some(cols) => Table::new(names.to_vec(), cols)?,
            None => self.data.select_columns(names)?,
        };
        let share = share as f64;
        let sub_cfg = cfg.sub_search(
            derive_seed(cfg.seed, u64::from(self.depth) + 1, index as u64),
            self.budget.map(|b| (b as f64 / share) as u64),
            self.time_left.map(|t| t / share),
        )?;
        let started = Instant::now();
        let res = match (self.sub_search)(&sub_data, target, &sub_cfg, self.depth + 1) {
            Ok(r) => r,
            Err(SrError::ConstantTarget(_) | SrError::NoModel) => return Ok(None),
            Err(e) => return Err(e),
        };
        out.evaluations += res.evaluations;
        self.budget = self.budget.map(|b| b.saturating_sub(res.evaluations));
        self.time_left = self.time_left.map(|t| t - started.elapsed().as_secs_f64());
        Ok(Some((res.best, sub_data)))
    }
}

/// The decomposition of the search's problem, if its most accurate model shows one (see
/// the module docs); empty when it does not, when the oracle is too rough, or at
/// [`MAX_DEPTH`].
///
/// # Errors
/// Only from a sub-search's configuration, which is the caller's own.
pub(crate) fn decompositions(
    problem: &Problem,
    data: &Table,
    archive: &Archive,
    spent: Spent,
    depth: u8,
    sub_search: &SubSearch,
) -> Result<Decomposition, SrError> {
    let cfg = problem.cfg;
    let none = Ok(Decomposition::default());
    if !cfg.separability || depth >= MAX_DEPTH {
        return none;
    }
    let Some(oracle_fit) = archive
        .front()
        .into_iter()
        .filter(|f| f.mse.is_finite())
        .min_by(|a, b| a.mse.total_cmp(&b.mse))
    else {
        return none;
    };
    let relative = oracle_fit.mse / problem.y_var;
    if relative.is_nan() || relative >= ORACLE_MAX_RELATIVE_MSE {
        return none;
    }
    let vars: Vec<usize> = oracle_fit
        .program
        .vars()
        .into_iter()
        .map(usize::from)
        .collect();
    if vars.len() < 2 {
        return none;
    }
    let budget = cfg
        .max_evaluations
        .map(|m| m.saturating_sub(spent.evaluations));
    if budget.is_some_and(|b| b < MIN_EVALUATIONS_LEFT) {
        return none;
    }
    let time_left = cfg
        .time_limit_s
        .map(|t| t - spent.since.elapsed().as_secs_f64());
    if time_left.is_some_and(|t| t <= 0.0) {
        return none;
    }
    let ops = cfg.operators();
    // test points: evenly spaced fitting rows, every input as in the data
    let n_fit = problem.fit_y.len();
    let k = TEST_POINTS.min(n_fit);
    let rows: Vec<usize> = (0..k).map(|i| i * n_fit / k).collect();
    let points: Vec<Vec<f64>> = problem
        .fit_cols
        .iter()
        .map(|c| rows.iter().map(|&r| c[r]).collect())
        .collect();
    let mut oracle = Oracle::new(&oracle_fit.program, &oracle_fit.params);
    let tolerance = MIN_TOLERANCE.max(ERROR_MULTIPLE * relative.sqrt());
    let mut ctx = Context {
        problem,
        data,
        budget,
        time_left,
        depth,
        points: &points,
        ops,
        sub_search,
    };
    let mut out = if let Some((join, parts)) = split(&mut oracle, &points, &vars, tolerance) {
        decompose(&mut ctx, &mut oracle, join, &parts)?
    } else if let Some(found) = symmetry::find(&mut oracle, &points, &vars, tolerance, ops) {
        reduce(&mut ctx, &vars, found)?
    } else {
        return none;
    };
    // the parts keep to the nesting rules; their join or write-back is checked as a whole
    out.candidates.retain(|f| cfg.nesting().allows(&f.program));
    Ok(out)
}

/// The groups of a sum (tested on `f`) or, failing that, of a product (on `ln |f|`, when
/// the oracle keeps one sign on the test points); `None` when neither splits.
fn split(
    oracle: &mut Oracle,
    points: &[Vec<f64>],
    vars: &[usize],
    tolerance: f64,
) -> Option<(Join, Vec<Vec<usize>>)> {
    if let Some(g) = groups(oracle, points, vars, tolerance, &|v| v)
        && g.len() >= 2
    {
        return Some((Join::Sum, g));
    }
    let base = oracle.eval(points);
    let one_sign = base.iter().all(|&v| v > 0.0) || base.iter().all(|&v| v < 0.0);
    if !one_sign {
        return None;
    }
    let g = groups(oracle, points, vars, tolerance, &|v: f64| v.abs().ln())?;
    (g.len() >= 2).then_some((Join::Product, g))
}

/// Searches each group of `parts` apart and joins the sub-models (see the module docs).
/// A part of a product that is one input to a power ([`symmetry::power`]) is taken as that
/// power, without a search.
fn decompose(
    ctx: &mut Context,
    oracle: &mut Oracle,
    join: Join,
    parts: &[Vec<usize>],
) -> Result<Decomposition, SrError> {
    let none = Ok(Decomposition::default());
    let (problem, data, points, ops) = (ctx.problem, ctx.data, ctx.points, ctx.ops);
    let affine = problem.cfg.affine_inputs;
    // the reference point: every input at its median over the fitting rows
    let reference: Vec<f64> = problem.fit_cols.iter().map(|c| median(c)).collect();
    let n_rows = data.n_rows();
    // each group's slice of the oracle on every row: its inputs as they are, the others at
    // the reference
    let slices: Vec<Vec<f64>> = parts
        .iter()
        .map(|part| {
            let cols: Vec<Vec<f64>> = (0..data.n_cols())
                .map(|c| {
                    if part.contains(&c) {
                        data.columns()[c].clone()
                    } else {
                        vec![reference[c]; n_rows]
                    }
                })
                .collect();
            oracle.eval(&cols)
        })
        .collect();
    if slices.iter().flatten().any(|v| !v.is_finite())
        || (join == Join::Product && slices.iter().flatten().any(|&v| v == 0.0))
    {
        return none;
    }
    let mut out = Decomposition::default();
    let mut subs: Vec<(Program, Vec<f64>)> = Vec::new();
    let mut found: Vec<Vec<f64>> = Vec::new();
    for (g, part) in parts.iter().enumerate() {
        if join == Join::Product
            && let [v] = part.as_slice()
            && let Some(power) = symmetry::power(oracle, points, *v, &data.columns()[*v], ops)
        {
            let program = power.program(*v as u16, affine);
            let params = symmetry::unit_params(&program);
            let mut values = Vec::new();
            let cols: Vec<&[f64]> = data.columns().iter().map(|c| c.as_slice()).collect();
            Evaluator::new(&program).predict(&program, &params, &cols, n_rows, &mut values);
            if values.iter().any(|&x| x == 0.0 || !x.is_finite()) {
                return none;
            }
            found.push(values);
            subs.push((program, params));
            continue;
        }
        // backfitting, one pass: the data less (or over) the other groups, the models
        // found so far for those before this one and the oracle's slices for those after
        let target: Vec<f64> = (0..n_rows)
            .map(|r| {
                let others = (0..parts.len())
                    .filter(|&j| j != g)
                    .map(|j| if j < g { found[j][r] } else { slices[j][r] });
                match join {
                    Join::Sum => problem.y[r] - others.sum::<f64>(),
                    Join::Product => problem.y[r] / others.product::<f64>(),
                }
            })
            .collect();
        if !target.iter().all(|v| v.is_finite()) {
            return none;
        }
        let names: Vec<String> = part.iter().map(|&c| data.names()[c].clone()).collect();
        let Some((m, sub_data)) =
            ctx.sub_search(&names, None, &target, g, parts.len() - g, &mut out)?
        else {
            return none;
        };
        let prediction = m.predict(&sub_data)?;
        if join == Join::Product && prediction.iter().any(|&v| v == 0.0 || !v.is_finite()) {
            return none;
        }
        found.push(prediction);
        let nodes = m
            .program
            .nodes
            .iter()
            .map(|n| match n {
                Node::Var(k) => Node::Var(part[usize::from(*k)] as u16),
                other => *other,
            })
            .collect();
        subs.push((
            Program {
                nodes,
                affine: m.program.affine,
            },
            m.params,
        ));
    }
    let Some((program, params)) = join_programs(&subs, join) else {
        return none;
    };
    out.candidates.extend(refitted(problem, program, params));
    Ok(out)
}

/// Searches the problem with the pair of a symmetry replaced by its one combined input
/// (`x_a - x_b`, ...) and writes the sub-model back over the inputs: one candidate.
fn reduce(
    ctx: &mut Context,
    vars: &[usize],
    found: symmetry::Found,
) -> Result<Decomposition, SrError> {
    let (problem, data) = (ctx.problem, ctx.data);
    let (a, b) = (found.a, found.b);
    let rest: Vec<usize> = vars.iter().copied().filter(|&v| v != a && v != b).collect();
    let mut names = vec![found.symmetry.name(&data.names()[a], &data.names()[b])];
    let mut columns = vec![
        data.columns()[a]
            .iter()
            .zip(&data.columns()[b])
            .map(|(&x, &y)| found.symmetry.combine(x, y))
            .collect::<Vec<f64>>(),
    ];
    if !columns[0].iter().all(|v| v.is_finite()) {
        return Ok(Decomposition::default());
    }
    for &v in &rest {
        names.push(data.names()[v].clone());
        columns.push(data.columns()[v].clone());
    }
    let mut out = Decomposition::default();
    let Some((m, _)) = ctx.sub_search(&names, Some(columns), &problem.y, 0, 1, &mut out)? else {
        return Ok(out);
    };
    let mut inputs: Vec<Vec<Node>> = vec![vec![
        Node::Var(a as u16),
        Node::Var(b as u16),
        Node::Op(found.symmetry.op()),
    ]];
    inputs.extend(rest.iter().map(|&v| vec![Node::Var(v as u16)]));
    let (program, params) = symmetry::substitute(&m.program, &m.params, &inputs);
    if program.is_valid() && params.iter().all(|v| v.is_finite()) {
        out.candidates.extend(refitted(problem, program, params));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::config::SearchConfig;
    use crate::search::fitting::variance;

    /// The loop's sub-search, as the loop passes it.
    fn sub_search(
        data: &Table,
        target: &[f64],
        cfg: &ValidSearch,
        depth: u8,
    ) -> Result<SearchResult, SrError> {
        crate::search::run::search_at(data, target, cfg, depth)
    }

    fn table(rows: usize) -> Table {
        let cols: Vec<Vec<f64>> = (0..3)
            .map(|c| {
                (0..rows)
                    .map(|r| 1.0 + 2.0 * (((r * (7 + 4 * c) + 3 * c) % 97) as f64) / 97.0)
                    .collect()
            })
            .collect();
        Table::new(vec!["a".into(), "b".into(), "c".into()], cols).expect("table")
    }

    /// An archive whose one model is `nodes` with `params` (the oracle), scored on the rows.
    fn archive_of(problem: &Problem, nodes: Vec<Node>, params: Vec<f64>) -> Archive {
        let program = Program {
            nodes,
            affine: false,
        };
        let cols = problem.fit_cols();
        let mse = Evaluator::new(&program).mse(&program, &params, &cols, &problem.fit_y);
        let mut archive = Archive::default();
        archive.offer(&Fitted {
            complexity: program.complexity(crate::ComplexityMeasure::FeaturesPlusOperators),
            score: problem.score(mse, params.len(), cols[0].len()),
            program,
            params,
            mse,
            source: 0,
            tag: 0,
        });
        archive
    }

    fn small() -> SearchConfig {
        SearchConfig {
            epochs: 2,
            candidates_per_epoch: 300,
            separability: true,
            ..SearchConfig::default()
        }
    }

    /// `2 sin(a) + b c`, written by the oracle as one expression: the mixed differences split
    /// it into `{a}` and `{b, c}`, and the join of the two sub-searches fits the rows exactly.
    #[test]
    fn a_sum_is_split_and_joined_exactly() {
        let data = table(150);
        let y: Vec<f64> = (0..150)
            .map(|r| {
                let c = |k: usize| data.columns()[k][r];
                2.0 * c(0).sin() + c(1) * c(2)
            })
            .collect();
        let cfg = small();
        let valid = cfg.check().expect("valid");
        let problem = Problem::all_rows(&data, &y, variance(&y), &valid);
        let nodes = vec![
            Node::Var(0),
            Node::Op(Op::Sin),
            Node::Const,
            Node::Op(Op::Mul),
            Node::Var(1),
            Node::Var(2),
            Node::Op(Op::Mul),
            Node::Op(Op::Add),
        ];
        let archive = archive_of(&problem, nodes.clone(), vec![1.0, 0.0, 2.0]);
        let front = archive.front();
        let mut oracle = Oracle::new(&front[0].program, &[1.0, 0.0, 2.0]);
        let g = groups(&mut oracle, data.columns(), &[0, 1, 2], 0.02, &|v| v).expect("finite");
        assert_eq!(g, vec![vec![0], vec![1, 2]]);
        let d = decompositions(
            &problem,
            &data,
            &archive,
            Spent::new(0, Instant::now()),
            0,
            &sub_search,
        )
        .expect("decompose");
        assert_eq!(d.candidates.len(), 1);
        assert!(d.evaluations > 0);
        let f = &d.candidates[0];
        assert!(f.mse < 1e-12 * problem.y_var, "mse {}", f.mse);
        // off, or at the depth limit, nothing is tried
        let off = SearchConfig {
            separability: false,
            ..cfg.clone()
        };
        let valid = off.check().expect("valid");
        let p_off = Problem::all_rows(&data, &y, variance(&y), &valid);
        let none = decompositions(
            &p_off,
            &data,
            &archive,
            Spent::new(0, Instant::now()),
            0,
            &sub_search,
        )
        .expect("off");
        assert!(none.candidates.is_empty() && none.evaluations == 0);
        let deep = decompositions(
            &problem,
            &data,
            &archive,
            Spent::new(0, Instant::now()),
            MAX_DEPTH,
            &sub_search,
        );
        assert!(deep.expect("deep").candidates.is_empty());
    }

    /// `exp(a/2) b / c` interacts in every pair as it is, and splits in three on `ln |f|`.
    #[test]
    fn a_product_is_split_on_the_log_scale() {
        let data = table(150);
        let y: Vec<f64> = (0..150)
            .map(|r| {
                let c = |k: usize| data.columns()[k][r];
                (0.5 * c(0)).exp() * c(1) / c(2)
            })
            .collect();
        let cfg = small();
        let valid = cfg.check().expect("valid");
        let problem = Problem::all_rows(&data, &y, variance(&y), &valid);
        let nodes = vec![
            Node::Var(0),
            Node::Const,
            Node::Op(Op::Mul),
            Node::Op(Op::Exp),
            Node::Var(1),
            Node::Op(Op::Mul),
            Node::Var(2),
            Node::Op(Op::Div),
        ];
        let params = vec![1.0, 0.0, 0.5];
        let archive = archive_of(&problem, nodes, params.clone());
        let prog = archive.front()[0].program.clone();
        let mut oracle = Oracle::new(&prog, &params);
        let plain = groups(&mut oracle, data.columns(), &[0, 1, 2], 0.02, &|v| v);
        assert_eq!(plain.expect("finite").len(), 1);
        let logs = groups(&mut oracle, data.columns(), &[0, 1, 2], 0.02, &|v: f64| {
            v.abs().ln()
        });
        assert_eq!(logs.expect("finite"), vec![vec![0], vec![1], vec![2]]);
        let d = decompositions(
            &problem,
            &data,
            &archive,
            Spent::new(0, Instant::now()),
            0,
            &sub_search,
        )
        .expect("decompose");
        let f = &d.candidates[0];
        assert!(f.mse < 1e-12 * problem.y_var, "mse {}", f.mse);
    }

    /// `1 / (a - b + c + 2)` is neither a sum nor a product of parts; its difference
    /// symmetry leaves a search on two inputs, and the sub-model written back over the three
    /// fits the rows exactly.
    #[test]
    fn a_symmetry_reduces_the_problem_and_is_written_back() {
        let data = table(150);
        let y: Vec<f64> = (0..150)
            .map(|r| {
                let c = |k: usize| data.columns()[k][r];
                1.0 / (c(0) - c(1) + c(2) + 2.0)
            })
            .collect();
        let cfg = small();
        let valid = cfg.check().expect("valid");
        let problem = Problem::all_rows(&data, &y, variance(&y), &valid);
        let nodes = vec![
            Node::Var(0),
            Node::Var(1),
            Node::Op(Op::Sub),
            Node::Var(2),
            Node::Op(Op::Add),
            Node::Const,
            Node::Op(Op::Add),
            Node::Op(Op::Inverse),
        ];
        let archive = archive_of(&problem, nodes, vec![1.0, 0.0, 2.0]);
        let d = decompositions(
            &problem,
            &data,
            &archive,
            Spent::new(0, Instant::now()),
            0,
            &sub_search,
        )
        .expect("reduce");
        assert_eq!(d.candidates.len(), 1);
        assert!(d.evaluations > 0);
        let f = &d.candidates[0];
        assert!(f.mse < 1e-12 * problem.y_var, "mse {}", f.mse);
        assert!(!f.program.affine);
        assert_eq!(f.program.vars().len(), 3, "{:?}", f.program.nodes);
    }
}
