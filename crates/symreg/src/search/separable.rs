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
use crate::eval::Evaluator;
use crate::fit::{LmSettings, Unknowns, levenberg_marquardt};
use crate::ops::Op;
use crate::program::{Node, Program};
use crate::{SrError, Table};
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
struct Oracle<'a> {
    prog: &'a Program,
    params: &'a [f64],
    ev: Evaluator,
}

impl Oracle<'_> {
    fn eval(&mut self, cols: &[Vec<f64>]) -> Vec<f64> {
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

fn spread(v: &[f64]) -> f64 {
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
    let mut budget = cfg.max_evaluations.map(|m| m.saturating_sub(spent));
    if budget.is_some_and(|b| b < MIN_EVALUATIONS_LEFT) {
        return none;
    }
    let mut time_left = cfg.time_limit_s.map(|t| t - t0.elapsed().as_secs_f64());
    if time_left.is_some_and(|t| t <= 0.0) {
        return none;
    }
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
    let sum_groups = groups(&mut oracle, &points, &vars, tolerance, &|v| v);
    let (join, parts) = match sum_groups {
        Some(g) if g.len() >= 2 => (Join::Sum, g),
        _ => {
            let base = oracle.eval(&points);
            let one_sign = base.iter().all(|&v| v > 0.0) || base.iter().all(|&v| v < 0.0);
            match one_sign
                .then(|| {
                    groups(&mut oracle, &points, &vars, tolerance, &|v: f64| {
                        v.abs().ln()
                    })
                })
                .flatten()
            {
                Some(g) if g.len() >= 2 => (Join::Product, g),
                _ => return none,
            }
        }
    };
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
        let sub_data = data.select_columns(&names)?;
        let share = (parts.len() - g) as f64;
        let sub_cfg = SearchConfig {
            seed: derive_seed(cfg.seed, u64::from(depth) + 1, g as u64),
            max_evaluations: budget.map(|b| (b as f64 / share) as u64),
            time_limit_s: time_left.map(|t| t / share),
            consensus_runs: 0,
            ..cfg.clone()
        };
        let started = Instant::now();
        let res = match super::run::search_at(&sub_data, &target, &sub_cfg, depth + 1) {
            Ok(r) => r,
            // a group whose target does not vary, or has no finite fit: no decomposition
            Err(SrError::ConstantTarget(_) | SrError::NoModel) => return none,
            Err(e) => return Err(e),
        };
        out.evaluations += res.evaluations;
        budget = budget.map(|b| b.saturating_sub(res.evaluations));
        time_left = time_left.map(|t| t - started.elapsed().as_secs_f64());
        let m = res.best;
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
    // every constant refitted together on the fitting rows, from the join's values
    let (program, mut params) = (program, params);
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
    let complexity = program.complexity_with(cfg.complexity_measure, &problem.op_costs);
    let n_params = params.len();
    out.candidates.push(Fitted {
        score: problem.score(mse, n_params, problem.fit_y.len()),
        program,
        params,
        mse,
        complexity,
        source: u8::MAX,
        tag: 0,
    });
    Ok(out)
}

/// Joins the sub-models `subs` (each `s * root + o` over the full inputs, with the same
/// affine flag) into one program: their sum or their product.
fn join_programs(subs: &[(Program, Vec<f64>)], join: Join) -> Option<(Program, Vec<f64>)> {
    let affine = subs.first()?.0.affine;
    if subs.iter().any(|(p, _)| p.affine != affine) {
        return None;
    }
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
