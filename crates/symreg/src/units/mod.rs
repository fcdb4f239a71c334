//! Dimensional analysis: units per column, Buckingham-π reduction of the inputs, and a
//! search whose result is dimensionally consistent by construction.
//!
//! Given the dimension of every input and of the target, a law `y = f(x1, ..., xn)` that
//! holds in any system of units can be written `y = M(x) g(π1, ..., πk)`, where `M` is a
//! product of powers of the inputs with the target's dimension and each `πj` a
//! dimensionless product of powers of the inputs; `k` is `n` less the rank of the inputs'
//! dimension matrix (Buckingham's π theorem). [`Reduction::of`] finds `M` and the `πj`,
//! [`search`] searches `g` on the π table (fewer inputs, a dimensionless target) and
//! composes every reported model back into the original columns, so each one is
//! `M(x)` times a function of dimensionless groups: consistent in its units whatever the
//! search found. This is AI Feynman's first step (Udrescu and Tegmark 2020); PySR instead
//! charges a penalty for inconsistent models (`dimensional_constraint_penalty`).
//!
//! The groups come from the reduced row echelon form of the dimension matrix, pivots taken
//! left to right over the columns in the table's order: the first columns that are
//! independent in their dimensions are the "repeating" ones, and each other column gives
//! one group, itself times powers of the repeating ones, scaled to whole exponents.
mod parse;

pub use parse::{BASE, Dimension};

use crate::canonical::canonical_program;
use crate::program::{Node, Program, affine};
use crate::{Model, Op, SearchConfig, SearchResult, SrError, Table, ValidSearch};

/// A fraction of two integers, in lowest terms with a positive denominator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ratio {
    /// Numerator.
    pub num: i64,
    /// Denominator (> 0).
    pub den: i64,
}

fn gcd(a: i64, b: i64) -> i64 {
    let (mut a, mut b) = (a.abs(), b.abs());
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a.max(1)
}

impl Ratio {
    const ZERO: Ratio = Ratio { num: 0, den: 1 };

    fn new(num: i64, den: i64) -> Ratio {
        let g = gcd(num, den) * den.signum();
        Ratio {
            num: num / g,
            den: den / g,
        }
    }
    fn int(v: i64) -> Ratio {
        Ratio { num: v, den: 1 }
    }
    fn sub(self, o: Ratio) -> Ratio {
        Ratio::new(self.num * o.den - o.num * self.den, self.den * o.den)
    }
    fn mul(self, o: Ratio) -> Ratio {
        Ratio::new(self.num * o.num, self.den * o.den)
    }
    fn div(self, o: Ratio) -> Ratio {
        Ratio::new(self.num * o.den, self.den * o.num)
    }
    fn neg(self) -> Ratio {
        Ratio::new(-self.num, self.den)
    }
    /// The value as a float.
    pub fn value(self) -> f64 {
        self.num as f64 / self.den as f64
    }
}

/// How the inputs reduce to dimensionless groups (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct Reduction {
    /// The input columns, in the table's order.
    pub inputs: Vec<String>,
    /// The exponent of each input in `M`, the product with the target's dimension.
    pub scale: Vec<Ratio>,
    /// The dimensionless groups: each one's name and the exponent of each input.
    pub groups: Vec<(String, Vec<i64>)>,
}

/// Whole-number exponents: `v` times the least common multiple of its denominators.
fn whole(v: &[Ratio]) -> Vec<i64> {
    let l = v.iter().fold(1i64, |l, r| l / gcd(l, r.den) * r.den);
    v.iter().map(|r| r.num * (l / r.den)).collect()
}

impl Reduction {
    /// The reduction of `inputs` with dimensions `dims` for a target of dimension `target`.
    ///
    /// # Errors
    /// [`SrError::InvalidConfig`] when no product of powers of the inputs has the target's
    /// dimension (the law then needs a dimensional constant that is not a column: give it
    /// as a column, or search without units), or when the lengths disagree.
    pub fn of(inputs: &[String], dims: &[Dimension], target: Dimension) -> Result<Self, SrError> {
        if inputs.len() != dims.len() || inputs.is_empty() {
            return Err(SrError::InvalidConfig(format!(
                "{} input columns but {} units",
                inputs.len(),
                dims.len()
            )));
        }
        let n = inputs.len();
        // Rows: the seven base dimensions; columns: the inputs, then the target.
        let mut m: Vec<Vec<Ratio>> = (0..BASE.len())
            .map(|r| {
                dims.iter()
                    .chain(std::iter::once(&target))
                    .map(|d| Ratio::int(i64::from(d.0[r])))
                    .collect()
            })
            .collect();
        let mut pivots: Vec<usize> = Vec::new();
        let mut row = 0;
        for col in 0..n {
            let Some(p) = (row..m.len()).find(|&r| m[r][col] != Ratio::ZERO) else {
                continue;
            };
            m.swap(row, p);
            let lead = m[row][col];
            for v in m[row].iter_mut() {
                *v = v.div(lead);
            }
            for r in 0..m.len() {
                if r != row && m[r][col] != Ratio::ZERO {
                    let f = m[r][col];
                    let pivot_row = m[row].clone();
                    for (v, p) in m[r].iter_mut().zip(pivot_row) {
                        *v = v.sub(f.mul(p));
                    }
                }
            }
            pivots.push(col);
            row += 1;
        }
        if m[row..].iter().any(|r| r[n] != Ratio::ZERO) {
            let shown: Vec<String> = inputs
                .iter()
                .zip(dims)
                .map(|(c, d)| format!("{c} [{d}]"))
                .collect();
            return Err(SrError::InvalidConfig(format!(
                "no product of powers of the inputs has the target's dimension [{target}] \
                 (inputs: {}): the law needs a dimensional constant that is not a column; \
                 add it as a column, or search without units",
                shown.join(", ")
            )));
        }
        let mut scale = vec![Ratio::ZERO; n];
        for (r, &c) in pivots.iter().enumerate() {
            scale[c] = m[r][n];
        }
        let taken: Vec<String> = inputs.to_vec();
        let name_of = |k: usize| {
            let plain = format!("pi{k}");
            if taken.contains(&plain) {
                format!("dimensionless_group{k}")
            } else {
                plain
            }
        };
        let mut groups = Vec::new();
        for free in (0..n).filter(|c| !pivots.contains(c)) {
            let mut e = vec![Ratio::ZERO; n];
            e[free] = Ratio::int(1);
            for (r, &c) in pivots.iter().enumerate() {
                e[c] = m[r][free].neg();
            }
            groups.push((name_of(groups.len() + 1), whole(&e)));
        }
        Ok(Reduction {
            inputs: inputs.to_vec(),
            scale,
            groups,
        })
    }

    /// Each group as text (`pi1 = m2/m1`), then the target as its scale times a function
    /// `phi` of the groups (`F = G*m1^2/r^2 * phi(pi1)`; `c * ...` with no group).
    pub fn describe(&self, target: &str) -> Vec<String> {
        let mut lines: Vec<String> = self
            .groups
            .iter()
            .map(|(name, e)| {
                let r: Vec<Ratio> = e.iter().map(|&k| Ratio::int(k)).collect();
                format!("{name} = {}", monomial_text(&self.inputs, &r))
            })
            .collect();
        let groups: Vec<&str> = self.groups.iter().map(|(n, _)| n.as_str()).collect();
        let scaled = self.scale.iter().any(|r| *r != Ratio::ZERO);
        let monomial = monomial_text(&self.inputs, &self.scale);
        match (scaled, groups.is_empty()) {
            (true, true) => lines.push(format!("{target} = c * {monomial}")),
            (true, false) => lines.push(format!(
                "{target} = {monomial} * phi({})",
                groups.join(", ")
            )),
            (false, true) => lines.push(format!("{target} = c")),
            (false, false) => lines.push(format!("{target} = phi({})", groups.join(", "))),
        }
        lines
    }

    /// The π table (one column per group; `None` when there is no group) and the
    /// dimensionless target `y / M`.
    ///
    /// # Errors
    /// [`SrError::InvalidConfig`] when a group or `M` is not finite on a row (a zero
    /// raised to a negative power, a negative value to a fractional one), naming the row.
    pub fn transform(&self, data: &Table, y: &[f64]) -> Result<(Option<Table>, Vec<f64>), SrError> {
        let cols: Vec<&[f64]> = self
            .inputs
            .iter()
            .map(|c| data.require(c))
            .collect::<Result<_, _>>()?;
        let value = |e: &[f64], row: usize| -> f64 {
            cols.iter()
                .zip(e)
                .filter(|(_, k)| **k != 0.0)
                .map(|(c, k)| power(c[row], *k))
                .product()
        };
        let check = |v: f64, what: &str, row: usize| -> Result<f64, SrError> {
            if v.is_finite() && v != 0.0 {
                Ok(v)
            } else {
                Err(SrError::InvalidConfig(format!(
                    "with the units given, {what} is {v} on row {row} (a zero or negative \
                     input where the dimensional analysis raises it to a negative or \
                     fractional power): search without units, or leave out such rows"
                )))
            }
        };
        let scale: Vec<f64> = self.scale.iter().map(|r| r.value()).collect();
        let mut target = Vec::with_capacity(y.len());
        for (row, v) in y.iter().enumerate() {
            let s = check(value(&scale, row), "the target's scale", row)?;
            target.push(v / s);
        }
        let mut names = Vec::new();
        let mut columns = Vec::new();
        for (name, e) in &self.groups {
            let e: Vec<f64> = e.iter().map(|&k| k as f64).collect();
            let col = (0..data.n_rows())
                .map(|row| check(value(&e, row), name, row))
                .collect::<Result<Vec<_>, _>>()?;
            names.push(name.clone());
            columns.push(col);
        }
        if names.is_empty() {
            return Ok((None, target));
        }
        Ok((Some(Table::new(names, columns)?), target))
    }

    /// `model`, a function of the groups, as a model of the inputs: `M(x) * model(π(x))`.
    ///
    /// # Errors
    /// [`SrError::MalformedModel`] if `model` names a feature that is not a group.
    pub fn compose(&self, model: &Model) -> Result<Model, SrError> {
        let p = &model.program;
        let off = p.param_offsets();
        let mut nodes = Vec::new();
        let mut params = vec![1.0, 0.0];
        for (i, n) in p.nodes.iter().enumerate() {
            match n {
                Node::Var(v) => {
                    let name = &model.feature_names[usize::from(*v)];
                    let Some((_, e)) = self.groups.iter().find(|(g, _)| g == name) else {
                        return Err(SrError::MalformedModel(format!(
                            "`{name}` is not a dimensionless group of this reduction"
                        )));
                    };
                    let e: Vec<Ratio> = e.iter().map(|&k| Ratio::int(k)).collect();
                    monomial_nodes(&e, &mut nodes, &mut params);
                    if p.affine {
                        affine(
                            model.params[off[i]],
                            model.params[off[i] + 1],
                            &mut nodes,
                            &mut params,
                        );
                    }
                }
                Node::Const => {
                    nodes.push(Node::Const);
                    params.push(model.params[off[i]]);
                }
                Node::Op(op) => nodes.push(Node::Op(*op)),
            }
        }
        let (scale, offset) = (model.params[0], model.params[1]);
        if self.scale.iter().all(|r| *r == Ratio::ZERO) {
            params[0] = scale;
            params[1] = offset;
        } else {
            affine(scale, offset, &mut nodes, &mut params);
            monomial_nodes(&self.scale, &mut nodes, &mut params);
            nodes.push(Node::Op(Op::Mul));
        }
        let program = Program {
            nodes,
            affine: false,
        };
        let mut out = Model::new(self.inputs.clone(), program, params)?;
        // the groups' monomials and the model's own factors often cancel (`m2/m1 * m1^2` is
        // `m1*m2`): the composition is returned in its canonical form when that is shorter
        if let Some((program, params)) =
            canonical_program(&out.program, &out.params, &out.feature_names)
            && let Ok(shorter) = Model::new(self.inputs.clone(), program, params)
            && shorter.complexity < out.complexity
        {
            out = shorter;
        }
        out.score = model.score;
        Ok(out)
    }
}

/// `x^k`, with whole powers by repeated products (exact for negative `x`).
fn power(x: f64, k: f64) -> f64 {
    if k.fract() == 0.0 && k.abs() < 64.0 {
        x.powi(k as i32)
    } else {
        x.powf(k)
    }
}

/// Pushes one input to a positive power: whole powers as products and squares, halves as
/// the square root of a whole power, others as `pow` with the exponent as a constant.
fn power_nodes(var: u16, r: Ratio, nodes: &mut Vec<Node>, params: &mut Vec<f64>) {
    let whole_power = |k: i64, nodes: &mut Vec<Node>| {
        nodes.push(Node::Var(var));
        match k {
            1 => {}
            2 => nodes.push(Node::Op(Op::Square)),
            _ => {
                for _ in 1..k {
                    nodes.push(Node::Var(var));
                    nodes.push(Node::Op(Op::Mul));
                }
            }
        }
    };
    match r.den {
        1 => whole_power(r.num, nodes),
        2 => {
            whole_power(r.num, nodes);
            nodes.push(Node::Op(Op::Sqrt));
        }
        _ => {
            nodes.push(Node::Var(var));
            nodes.push(Node::Const);
            params.push(r.value());
            nodes.push(Node::Op(Op::Pow));
        }
    }
}

/// Pushes the product of the inputs to the powers `e` (as `numerator / denominator`).
fn monomial_nodes(e: &[Ratio], nodes: &mut Vec<Node>, params: &mut Vec<f64>) {
    let side = |sign: i64, nodes: &mut Vec<Node>, params: &mut Vec<f64>| -> bool {
        let mut any = false;
        for (i, r) in e.iter().enumerate() {
            if r.num * sign > 0 {
                let r = if sign < 0 { r.neg() } else { *r };
                power_nodes(i as u16, r, nodes, params);
                if any {
                    nodes.push(Node::Op(Op::Mul));
                }
                any = true;
            }
        }
        any
    };
    let num = side(1, nodes, params);
    let den = side(-1, nodes, params);
    match (num, den) {
        (true, true) => nodes.push(Node::Op(Op::Div)),
        (false, true) => nodes.push(Node::Op(Op::Inverse)),
        (true, false) => {}
        (false, false) => {
            nodes.push(Node::Const);
            params.push(1.0);
        }
    }
}

/// `a*b^2/c`-style text of a product of powers.
fn monomial_text(inputs: &[String], e: &[Ratio]) -> String {
    let factor = |name: &str, r: Ratio| match (r.num.abs(), r.den) {
        (1, 1) => name.to_string(),
        (k, 1) => format!("{name}^{k}"),
        (k, d) => format!("{name}^({k}/{d})"),
    };
    let side = |sign: i64| -> Vec<String> {
        inputs
            .iter()
            .zip(e)
            .filter(|(_, r)| r.num * sign > 0)
            .map(|(n, r)| factor(n, *r))
            .collect()
    };
    parse::fraction_text(&side(1), &side(-1))
}

/// Units of every input and of the target, read from text.
///
/// # Errors
/// [`SrError::InvalidConfig`] naming a column without a unit, a unit for a column that is
/// not in the table, or a unit that does not parse.
pub fn dimensions(
    inputs: &[String],
    target: &str,
    units: &[(String, String)],
) -> Result<(Vec<Dimension>, Dimension), SrError> {
    for (col, _) in units {
        if col != target && !inputs.contains(col) {
            return Err(SrError::InvalidConfig(format!(
                "a unit is given for `{col}`, which is not a column: the columns are {}, {}",
                inputs.join(", "),
                target
            )));
        }
    }
    let find = |col: &str| -> Result<Dimension, SrError> {
        let Some((_, text)) = units.iter().find(|(c, _)| c == col) else {
            return Err(SrError::InvalidConfig(format!(
                "no unit for `{col}`: dimensional analysis needs one for every input and for \
                 the target (`1` for a dimensionless column)"
            )));
        };
        Dimension::parse(text).map_err(|e| match e {
            SrError::InvalidConfig(m) => SrError::InvalidConfig(format!("column `{col}`: {m}")),
            other => other,
        })
    };
    let dims = inputs
        .iter()
        .map(|c| find(c))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((dims, find(target)?))
}

/// [`crate::search()`] on the π table of `reduction`, every reported model (best, front,
/// alternatives) composed back into the inputs and scored on them (`train_mse` on the
/// original rows; `score` stays the criterion on the π table). A reduction to no group
/// (`y = c M(x)`) takes `c` as the mean of `y / M` without a search. Without a reduction,
/// [`crate::search()`] itself, so a front end calls this one function with or without units.
///
/// # Errors
/// As [`Reduction::transform`] and [`crate::search()`].
pub fn search(
    data: &Table,
    y: &[f64],
    reduction: Option<&Reduction>,
    cfg: &SearchConfig,
    progress: &mut dyn FnMut(&crate::Progress),
) -> Result<SearchResult, SrError> {
    search_checked(data, y, reduction, &cfg.check()?, progress)
}

/// [`search`] with a configuration already checked: what the consensus runs and the
/// stability resamples call, so the configuration is checked once.
fn search_checked(
    data: &Table,
    y: &[f64],
    reduction: Option<&Reduction>,
    cfg: &ValidSearch,
    progress: &mut dyn FnMut(&crate::Progress),
) -> Result<SearchResult, SrError> {
    let Some(reduction) = reduction else {
        return crate::search_checked(data, y, cfg, progress);
    };
    if cfg.consensus_runs > 0 {
        // each of the B + 1 searches runs on the groups and is composed back, so the votes
        // are on the composed structures and the winner is refitted on the columns
        return crate::search::search_with(data, y, cfg, progress, &|d, t, c, p| {
            search_checked(d, t, Some(reduction), c, p)
        });
    }
    let (pi, py) = reduction.transform(data, y)?;
    let t0 = std::time::Instant::now();
    let mut res = if let Some(pi) = pi {
        crate::search_checked(&pi, &py, cfg, progress)?
    } else {
        let c = py.iter().sum::<f64>() / py.len().max(1) as f64;
        let program = Program {
            nodes: vec![Node::Const],
            affine: false,
        };
        let m = Model::new(Vec::new(), program, vec![1.0, 0.0, c])?;
        SearchResult {
            best: m.clone(),
            pareto: vec![m],
            alternatives: Vec::new(),
            consensus: None,
            evaluations: 1,
            duplicate_structures: 0,
            simplified: 0,
            seconds: t0.elapsed().as_secs_f64(),
            error_model: crate::ErrorModel::Additive,
        }
    };
    let back = |m: &Model| -> Result<Model, SrError> {
        let mut out = reduction.compose(m)?;
        let pred = out.predict(data)?;
        out.train_mse = pred
            .iter()
            .zip(y)
            .map(|(p, t)| (p - t).powi(2))
            .sum::<f64>()
            / y.len().max(1) as f64;
        Ok(out)
    };
    res.best = back(&res.best)?;
    res.pareto = res.pareto.iter().map(back).collect::<Result<_, _>>()?;
    res.alternatives = res
        .alternatives
        .iter()
        .map(back)
        .collect::<Result<_, _>>()?;
    Ok(res)
}

/// [`crate::stability()`] of the search with units: each bootstrap run searches its
/// resample's groups and composes back, so structures, features and out-of-bag R² are
/// those of the composed models, as the selected one is reported. Without a reduction,
/// [`crate::stability()`] itself.
///
/// # Errors
/// As [`crate::stability()`] and [`search`].
pub fn stability(
    data: &Table,
    y: &[f64],
    reduction: Option<&Reduction>,
    cfg: &SearchConfig,
    runs: usize,
    progress: &mut (dyn FnMut(usize, usize) + Send),
) -> Result<crate::Stability, SrError> {
    if reduction.is_none() {
        return crate::stability(data, y, cfg, runs, progress);
    }
    crate::stability::stability_of(
        data,
        y,
        &cfg.check()?,
        runs,
        progress,
        &|train, ty, run_cfg| search_checked(train, ty, reduction, run_cfg, &mut |_| {}),
    )
}

#[cfg(test)]
mod tests;
