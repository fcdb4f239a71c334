//! Separability: the search's most accurate model as an oracle for structure (AI Feynman's
//! insight, Udrescu and Tegmark 2020; issue 24 item 2).
//!
//! When the search ends with a model that fits closely but is not the law, that model still
//! answers questions about the law. If `f(x) = g(xA) + h(xB)`, every mixed difference
//! `f(a', b') - f(a', b) - f(a, b') + f(a, b)` across the two groups is zero; with `log |f|`
//! in place of `f` the same test finds `f = g(xA) h(xB)`. [`candidates`] runs that test on
//! every pair of inputs the oracle uses, over pairs of training rows, and joins inputs whose
//! mixed differences are not negligible (union-find). With two or more groups, each group
//! becomes a smaller problem: the oracle with the other inputs held at their medians is its
//! target, searched on its own columns (and, once more, decomposed in turn). The sub-models
//! are joined back (sum or product, with the constants that make the join exact) and handed
//! to selection as one more candidate: refitted on all rows, snapped and judged by the
//! criterion like every model of the search, so it replaces the oracle only when the data
//! prefers it.
use super::archive::{Archive, Fitted};
use super::config::SearchConfig;
use super::fitting::{Problem, derive_seed};
use super::symmetry;
use crate::eval::Evaluator;
use crate::fit::{LmSettings, Unknowns, levenberg_marquardt};
use crate::ops::Op;
use crate::program::{Node, Program};
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

/// Relative tolerance of the joined model's refit on the fitting rows (the reported models
/// are refitted again on all rows by selection).
const JOIN_LM_TOLERANCE: f64 = 1e-8;

/// Fewest evaluations left in a budget for a decomposition to be tried.
const MIN_EVALUATIONS_LEFT: u64 = 500;

/// A join of groups: their sum or their product.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Join {
    Sum,
    Product,
}

/// What a decomposition adds to a search: candidates for selection and the evaluations
/// their sub-searches spent.
#[derive(Default)]
pub(crate) struct Decomposition {
    pub candidates: Vec<Fitted>,
    pub evaluations: u64,
}

/// The oracle's values on points given by columns over every input of `data`.
pub(super) struct Oracle<'a> {
    prog: &'a Program,
    params: &'a [f64],
    ev: Evaluator,
}

impl Oracle<'_> {
    pub(super) fn eval(&mut self, cols: &[Vec<f64>]) -> Vec<f64> {
        let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
        let n = cols.first().map_or(0, |c| c.len());
        let mut out = Vec::new();
        self.ev.predict(self.prog, self.params, &refs, n, &mut out);
        out
    }
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s[s.len() / 2]
}

pub(super) fn spread(v: &[f64]) -> f64 {
    let m = v.iter().sum::<f64>() / v.len() as f64;
    (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / v.len() as f64).sqrt()
}

fn find(parent: &mut [usize], i: usize) -> usize {
    let mut r = i;
    while parent[r] != r {
        r = parent[r];
    }
    parent[i] = r;
    r
}

/// The groups of `vars` that no mixed difference of `values` joins, each sorted; one group
/// when everything interacts. `values` maps the oracle's outputs to the scale tested (`f`
/// or `ln |f|`); `None` when it is not finite on the test points.
fn groups(
    oracle: &mut Oracle,
    points: &[Vec<f64>],
    vars: &[usize],
    tolerance: f64,
    values: &dyn Fn(f64) -> f64,
) -> Option<Vec<Vec<usize>>> {
    let n = points[0].len();
    let half = n / 2;
    let mapped = |v: Vec<f64>| -> Option<Vec<f64>> {
        let m: Vec<f64> = v.into_iter().map(values).collect();
        m.iter().all(|x| x.is_finite()).then_some(m)
    };
    let base = mapped(oracle.eval(points))?;
    let scale = spread(&base);
    if scale <= 0.0 {
        return None;
    }
    // each point a paired with point b = a + n/2: input i (and j) taken from b
    let swapped = |cols: &[usize]| -> Vec<Vec<f64>> {
        let mut p = points.to_vec();
        for &c in cols {
            for a in 0..n {
                p[c][a] = points[c][(a + half) % n];
            }
        }
        p
    };
    let singles: Vec<Vec<f64>> = vars
        .iter()
        .map(|&i| mapped(oracle.eval(&swapped(&[i]))))
        .collect::<Option<_>>()?;
    let mut parent: Vec<usize> = (0..vars.len()).collect();
    for a in 0..vars.len() {
        for b in a + 1..vars.len() {
            let both = mapped(oracle.eval(&swapped(&[vars[a], vars[b]])))?;
            let mixed: f64 = (0..n)
                .map(|k| {
                    let d = both[k] - singles[a][k] - singles[b][k] + base[k];
                    d * d
                })
                .sum::<f64>()
                / n as f64;
            if mixed.sqrt() > tolerance * scale {
                let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
                parent[ra] = rb;
            }
        }
    }
    let mut out: Vec<Vec<usize>> = Vec::new();
    let mut root_of: Vec<usize> = Vec::new();
    for (k, &v) in vars.iter().enumerate() {
        let r = find(&mut parent, k);
        match root_of.iter().position(|&x| x == r) {
            Some(g) => out[g].push(v),
            None => {
                root_of.push(r);
                out.push(vec![v]);
            }
        }
    }
    Some(out)
}

/// Where a decomposition's sub-searches run, and what they may spend.
struct Context<'a, 'p> {
    problem: &'p Problem<'a>,
    data: &'p Table,
    budget: Option<u64>,
    time_left: Option<f64>,
    depth: u8,
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
        let sub_cfg = SearchConfig {
            seed: derive_seed(cfg.seed, u64::from(self.depth) + 1, index as u64),
            max_evaluations: self.budget.map(|b| (b as f64 / share) as u64),
            time_limit_s: self.time_left.map(|t| t / share),
            consensus_runs: 0,
            ..cfg.clone()
        };
        let started = Instant::now();
        let res = match super::run::search_at(&sub_data, target, &sub_cfg, self.depth + 1) {
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
pub(crate) fn candidates(
    problem: &Problem,
    data: &Table,
    archive: &Archive,
    spent: u64,
    t0: Instant,
    depth: u8,
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
    let budget = cfg.max_evaluations.map(|m| m.saturating_sub(spent));
    if budget.is_some_and(|b| b < MIN_EVALUATIONS_LEFT) {
        return none;
    }
    let time_left = cfg.time_limit_s.map(|t| t - t0.elapsed().as_secs_f64());
    if time_left.is_some_and(|t| t <= 0.0) {
        return none;
    }
    let ops = cfg.check()?;
    // test points: evenly spaced fitting rows, every input as in the data
    let n_fit = problem.fit_y.len();
    let k = TEST_POINTS.min(n_fit);
    let rows: Vec<usize> = (0..k).map(|i| i * n_fit / k).collect();
    let points: Vec<Vec<f64>> = problem
        .fit_cols
        .iter()
        .map(|c| rows.iter().map(|&r| c[r]).collect())
        .collect();
    let mut oracle = Oracle {
        prog: &oracle_fit.program,
        params: &oracle_fit.params,
        ev: Evaluator::new(&oracle_fit.program),
    };
    let tolerance = MIN_TOLERANCE.max(ERROR_MULTIPLE * relative.sqrt());
    let mut ctx = Context {
        problem,
        data,
        budget,
        time_left,
        depth,
    };
    let mut out = if let Some((join, parts)) = split(&mut oracle, &points, &vars, tolerance) {
        decompose(&mut ctx, &mut oracle, (&points, &ops), join, &parts)?
    } else if let Some(found) = symmetry::find(&mut oracle, &points, &vars, tolerance, &ops) {
        reduce(&mut ctx, &vars, found)?
    } else {
        return none;
    };
    // the parts keep to the nesting rules; their join or write-back is checked as a whole
    let rules = cfg.nesting.rules()?;
    out.candidates.retain(|f| rules.allows(&f.program));
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
    (points, ops): (&[Vec<f64>], &[Op]),
    join: Join,
    parts: &[Vec<usize>],
) -> Result<Decomposition, SrError> {
    let none = Ok(Decomposition::default());
    let (problem, data) = (ctx.problem, ctx.data);
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

/// `program` with every constant refitted together on the fitting rows, from `params`,
/// scored as a candidate of the search; `None` when it has at least as many parameters as
/// there are fitting rows, or no finite loss (the search rejects such candidates too).
pub(super) fn refitted(
    problem: &Problem,
    program: Program,
    mut params: Vec<f64>,
) -> Option<Fitted> {
    let cfg = problem.cfg;
    if params.len() >= problem.fit_y.len() {
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

/// Joins the sub-models `subs` (each `s * root + o` over the full inputs) into one program:
/// their sum or their product.
fn join_programs(subs: &[(Program, Vec<f64>)], join: Join) -> Option<(Program, Vec<f64>)> {
    let mut affine = subs.first()?.0.affine;
    let plain: Vec<(Program, Vec<f64>)>;
    let subs = if subs.iter().any(|(p, _)| p.affine != affine) {
        // a sub-model that is itself a decomposition (or a shorter form) may have no affine
        // leaves where the others have: every part is then written without them
        affine = false;
        plain = subs
            .iter()
            .map(|(p, ps)| {
                let n = p.vars().into_iter().max().map_or(0, |v| usize::from(v) + 1);
                let same: Vec<Vec<Node>> = (0..n).map(|k| vec![Node::Var(k as u16)]).collect();
                symmetry::substitute(p, ps, &same)
            })
            .collect();
        &plain
    } else {
        subs
    };
    let mut nodes: Vec<Node> = Vec::new();
    let mut params = vec![1.0, 0.0];
    let (mut scale, mut offset) = (1.0, 0.0);
    let first_scale = subs[0].1[0];
    for (i, (p, ps)) in subs.iter().enumerate() {
        let (s, o) = (ps[0], ps[1]);
        nodes.extend_from_slice(&p.nodes);
        params.extend_from_slice(&ps[2..]);
        match join {
            Join::Sum => {
                offset += o;
                if i == 0 {
                    scale = s;
                } else {
                    nodes.push(Node::Const);
                    params.push(s / first_scale);
                    nodes.push(Node::Op(Op::Mul));
                    nodes.push(Node::Op(Op::Add));
                }
            }
            Join::Product => {
                scale *= s;
                if o != 0.0 {
                    nodes.push(Node::Const);
                    params.push(o / s);
                    nodes.push(Node::Op(Op::Add));
                }
                if i > 0 {
                    nodes.push(Node::Op(Op::Mul));
                }
            }
        }
    }
    params[0] = scale;
    params[1] = offset;
    let program = Program { nodes, affine };
    (program.is_valid() && params.iter().all(|v| v.is_finite())).then_some((program, params))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::fitting::variance;

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
        let problem = Problem::all_rows(&data, &y, variance(&y), &cfg);
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
        let mut oracle = Oracle {
            prog: &archive.front()[0].program,
            params: &[1.0, 0.0, 2.0],
            ev: Evaluator::new(&archive.front()[0].program),
        };
        let g = groups(&mut oracle, data.columns(), &[0, 1, 2], 0.02, &|v| v).expect("finite");
        assert_eq!(g, vec![vec![0], vec![1, 2]]);
        let d = candidates(&problem, &data, &archive, 0, Instant::now(), 0).expect("decompose");
        assert_eq!(d.candidates.len(), 1);
        assert!(d.evaluations > 0);
        let f = &d.candidates[0];
        assert!(f.mse < 1e-12 * problem.y_var, "mse {}", f.mse);
        // off, or at the depth limit, nothing is tried
        let off = SearchConfig {
            separability: false,
            ..cfg.clone()
        };
        let p_off = Problem::all_rows(&data, &y, variance(&y), &off);
        let none = candidates(&p_off, &data, &archive, 0, Instant::now(), 0).expect("off");
        assert!(none.candidates.is_empty() && none.evaluations == 0);
        let deep = candidates(&problem, &data, &archive, 0, Instant::now(), MAX_DEPTH);
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
        let problem = Problem::all_rows(&data, &y, variance(&y), &cfg);
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
        let mut oracle = Oracle {
            prog: &prog,
            params: &params,
            ev: Evaluator::new(&prog),
        };
        let plain = groups(&mut oracle, data.columns(), &[0, 1, 2], 0.02, &|v| v);
        assert_eq!(plain.expect("finite").len(), 1);
        let logs = groups(&mut oracle, data.columns(), &[0, 1, 2], 0.02, &|v: f64| {
            v.abs().ln()
        });
        assert_eq!(logs.expect("finite"), vec![vec![0], vec![1], vec![2]]);
        let d = candidates(&problem, &data, &archive, 0, Instant::now(), 0).expect("decompose");
        let f = &d.candidates[0];
        assert!(f.mse < 1e-12 * problem.y_var, "mse {}", f.mse);
    }

    /// The oracle of `prog` (postfix nodes, no affine leaves) with `params`.
    fn oracle_of(nodes: Vec<Node>, params: Vec<f64>) -> (Program, Vec<f64>) {
        (
            Program {
                nodes,
                affine: false,
            },
            params,
        )
    }

    /// Each symmetry is found on the pair that has it, and none where no pair has one.
    #[test]
    fn symmetries_are_found_on_the_pair_that_has_them() {
        use super::symmetry::{Found, Symmetry, find};
        let data = table(150);
        let ops = crate::ops::parse_operators(&SearchConfig::default().operators).expect("ops");
        let v = Node::Var;
        let op = Node::Op;
        let cases = [
            // (x0 - x1) * x2
            (
                vec![v(0), v(1), op(Op::Sub), v(2), op(Op::Mul)],
                Some((0, 1, Symmetry::Difference)),
            ),
            // x0 / x2 + exp(x1)  (x1 is not a part of the pair)
            (
                vec![v(0), v(2), op(Op::Div), v(1), op(Op::Exp), op(Op::Add)],
                Some((0, 2, Symmetry::Ratio)),
            ),
            // sin(x1 * x2) * x0
            (
                vec![v(1), v(2), op(Op::Mul), op(Op::Sin), v(0), op(Op::Mul)],
                Some((1, 2, Symmetry::Product)),
            ),
            // x0 * x1 + x0 * x2^2: every pair interacts, and no move leaves it as it is (x0 * x1
            // + x0 * x2 would be x0 (x1 + x2), a sum)
            (
                vec![
                    v(0),
                    v(1),
                    op(Op::Mul),
                    v(0),
                    v(2),
                    op(Op::Square),
                    op(Op::Mul),
                    op(Op::Add),
                ],
                None,
            ),
        ];
        for (nodes, want) in cases {
            let (prog, params) = oracle_of(nodes, vec![1.0, 0.0]);
            let mut oracle = Oracle {
                prog: &prog,
                params: &params,
                ev: Evaluator::new(&prog),
            };
            let got = find(&mut oracle, data.columns(), &[0, 1, 2], 0.02, &ops);
            let want = want.map(|(a, b, symmetry)| Found { a, b, symmetry });
            assert_eq!(got, want, "{:?}", prog.nodes);
        }
        // without `sub` among the operators, a difference is not offered
        let (prog, params) = oracle_of(
            vec![v(0), v(1), op(Op::Sub), v(2), op(Op::Mul)],
            vec![1.0, 0.0],
        );
        let mut oracle = Oracle {
            prog: &prog,
            params: &params,
            ev: Evaluator::new(&prog),
        };
        let no_sub: Vec<Op> = ops.iter().copied().filter(|&o| o != Op::Sub).collect();
        assert_eq!(
            find(&mut oracle, data.columns(), &[0, 1, 2], 0.02, &no_sub),
            None
        );
    }

    /// `x0^1.5 x1` is a power in x0 (three halves) and in x1 (one); `exp(x0) x1` is none in
    /// x0; a half power is not taken where the input has a negative value.
    #[test]
    fn a_power_is_read_off_the_elasticity() {
        use super::symmetry::{power, unit_params};
        let data = table(150);
        let ops = crate::ops::parse_operators(&SearchConfig::default().operators).expect("ops");
        let v = Node::Var;
        let op = Node::Op;
        let (prog, params) = oracle_of(
            vec![
                v(0),
                v(0),
                op(Op::Mul),
                v(0),
                op(Op::Mul),
                op(Op::Sqrt),
                v(1),
                op(Op::Mul),
            ],
            vec![2.0, 0.0],
        );
        let mut oracle = Oracle {
            prog: &prog,
            params: &params,
            ev: Evaluator::new(&prog),
        };
        let cols = data.columns();
        let p = power(&mut oracle, cols, 0, &cols[0], &ops).expect("x0^1.5");
        // the power's program is x0^1.5 over the inputs, at its unit parameters
        for affine in [false, true] {
            let program = p.program(0, affine);
            let unit = unit_params(&program);
            let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
            let mut out = Vec::new();
            Evaluator::new(&program).predict(&program, &unit, &refs, 150, &mut out);
            for (o, x) in out.iter().zip(&cols[0]) {
                assert!(
                    (o - x.powf(1.5)).abs() < 1e-12 * x.powf(1.5),
                    "{o} vs {x}^1.5"
                );
            }
        }
        assert!(power(&mut oracle, cols, 1, &cols[1], &ops).is_some());
        let negative: Vec<f64> = cols[0].iter().map(|x| x - 2.0).collect();
        assert!(power(&mut oracle, cols, 0, &negative, &ops).is_none());
        let (prog, params) = oracle_of(vec![v(0), op(Op::Exp), v(1), op(Op::Mul)], vec![1.0, 0.0]);
        let mut oracle = Oracle {
            prog: &prog,
            params: &params,
            ev: Evaluator::new(&prog),
        };
        assert!(power(&mut oracle, cols, 0, &cols[0], &ops).is_none());
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
        let problem = Problem::all_rows(&data, &y, variance(&y), &cfg);
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
        let d = candidates(&problem, &data, &archive, 0, Instant::now(), 0).expect("reduce");
        assert_eq!(d.candidates.len(), 1);
        assert!(d.evaluations > 0);
        let f = &d.candidates[0];
        assert!(f.mse < 1e-12 * problem.y_var, "mse {}", f.mse);
        assert!(!f.program.affine);
        assert_eq!(f.program.vars().len(), 3, "{:?}", f.program.nodes);
    }

    /// A substituted input takes its affine leaf's weight and bias around its expression.
    #[test]
    fn substitution_keeps_the_values() {
        use super::symmetry::substitute;
        // 3 * exp(w0 * z + b0) * (w1 * x2 + b1) + 1, with z = x0 / x1
        let program = Program {
            nodes: vec![
                Node::Var(0),
                Node::Op(Op::Exp),
                Node::Var(1),
                Node::Op(Op::Mul),
            ],
            affine: true,
        };
        let params = vec![3.0, 1.0, 0.5, -0.25, 2.0, 0.75];
        let inputs = vec![
            vec![Node::Var(0), Node::Var(1), Node::Op(Op::Div)],
            vec![Node::Var(2)],
        ];
        let (p, q) = substitute(&program, &params, &inputs);
        let cols: Vec<Vec<f64>> = vec![
            vec![0.5, 2.0, -1.0],
            vec![1.5, -0.25, 4.0],
            vec![2.0, 3.0, 0.1],
        ];
        let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
        let mut out = Vec::new();
        Evaluator::new(&p).predict(&p, &q, &refs, 3, &mut out);
        for r in 0..3 {
            let z = cols[0][r] / cols[1][r];
            let want = 3.0 * (0.5 * z - 0.25).exp() * (2.0 * cols[2][r] + 0.75) + 1.0;
            assert!(
                (out[r] - want).abs() < 1e-12 * want.abs(),
                "{} vs {want}",
                out[r]
            );
        }
    }

    /// The join of `2 x0 + 1` and `3 x1 - 1` is their sum, and their product.
    #[test]
    fn joins_add_and_multiply_the_parts() {
        let line = |v: u16, s: f64, o: f64| {
            (
                Program {
                    nodes: vec![Node::Var(v)],
                    affine: false,
                },
                vec![s, o],
            )
        };
        let subs = [line(0, 2.0, 1.0), line(1, 3.0, -1.0)];
        let cols: Vec<Vec<f64>> = vec![vec![0.5, 2.0, -1.0], vec![1.5, -0.25, 4.0]];
        let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
        for (join, want) in [
            (Join::Sum, [5.5, 3.25, 10.0]),
            (Join::Product, [7.0, -8.75, -11.0]),
        ] {
            let (p, params) = join_programs(&subs, join).expect("join");
            let mut out = Vec::new();
            Evaluator::new(&p).predict(&p, &params, &refs, 3, &mut out);
            for (g, w) in out.iter().zip(want) {
                assert!((g - w).abs() < 1e-12, "{join:?}: {out:?} vs {want:?}");
            }
        }
    }
}
