//! The search's most accurate model as an oracle (AI Feynman's insight, Udrescu and Tegmark
//! 2020; issue 24 item 2): [`Oracle`] evaluates it on any points, and [`groups`] asks it which
//! inputs interact. If `f(x) = g(xA) + h(xB)`, every mixed difference
//! `f(a', b') - f(a', b) - f(a, b') + f(a, b)` across the two groups is zero; with `log |f|`
//! in place of `f` the same test finds `f = g(xA) h(xB)`. The test runs on every pair of
//! inputs the oracle uses, over pairs of test points, and joins inputs whose mixed
//! differences are not negligible (union-find).
use crate::eval::Evaluator;
use crate::program::Program;

/// The oracle's values on points given by columns over every input of `data`.
pub(super) struct Oracle<'a> {
    prog: &'a Program,
    params: &'a [f64],
    ev: Evaluator,
}

impl<'a> Oracle<'a> {
    /// The oracle `prog` with `params`.
    pub(super) fn new(prog: &'a Program, params: &'a [f64]) -> Self {
        Self {
            prog,
            params,
            ev: Evaluator::new(prog),
        }
    }

    /// Its values on the points whose coordinates are the columns `cols`.
    pub(super) fn eval(&mut self, cols: &[Vec<f64>]) -> Vec<f64> {
        let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
        let n = cols.first().map_or(0, |c| c.len());
        let mut out = Vec::new();
        self.ev.predict(self.prog, self.params, &refs, n, &mut out);
        out
    }
}

/// The median of `v` (the upper one of an even count).
pub(super) fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    s[s.len() / 2]
}

/// The standard deviation of `v` (population form).
pub(super) fn spread(v: &[f64]) -> f64 {
    let m = v.iter().sum::<f64>() / v.len() as f64;
    (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / v.len() as f64).sqrt()
}

/// The root of `i` in the union-find forest `parent`, with the path to it shortened.
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
pub(super) fn groups(
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
