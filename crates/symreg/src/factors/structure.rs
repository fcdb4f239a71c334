//! A factor model's terms written as one program, fitted by Levenberg-Marquardt, and scored
//! by cross-validation on fixed folds.
use super::Link;
use super::shape::{Builder, Term, emit};
use crate::eval::Evaluator;
use crate::fit::{LmSettings, Unknowns, levenberg_marquardt};
use crate::program::Program;

/// The terms of a model and its output constant (the sum's offset, or the product's
/// overall constant).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Structure {
    pub terms: Vec<Term>,
    pub constant: f64,
    /// The column holding each row's physics `f_p` when a multiplicative model is fitted on
    /// the hybrid's own scale: the program is then `C * prod_j f_j(x_j) * f_p` against the
    /// measured target, so that every row weighs by its error in the target's units
    /// instead of its relative error (which the rows of small physics dominate).
    pub scale: Option<usize>,
}

/// A structure as a program: its nodes, every parameter (output map first) and which
/// parameters are fitted.
pub(crate) struct Written {
    pub program: Program,
    pub params: Vec<f64>,
    pub free: Vec<usize>,
    /// Where each term's constants start in `params`.
    pub starts: Vec<usize>,
}

impl Structure {
    pub fn empty(link: Link, scale: Option<usize>) -> Self {
        Self {
            terms: Vec::new(),
            constant: match link {
                Link::Additive => 0.0,
                _ => 1.0,
            },
            scale: scale.filter(|_| link == Link::Multiplicative),
        }
    }

    /// The same structure as a correction `delta` (without the physics column).
    pub fn unscaled(&self) -> Self {
        Self {
            scale: None,
            ..self.clone()
        }
    }

    /// The program: additive `offset + sum_j a_j s_j(x_j)` (scale fixed at 1),
    /// multiplicative `C * prod_j f_j(x_j) - 1` (offset fixed at -1, so that the hybrid
    /// `f_p (1 + delta)` is `f_p C prod_j f_j`), log `log(C * prod_j f_j(x_j))` (scale 1,
    /// offset 0 fixed, so that `f_p exp(delta)` is again `f_p C prod_j f_j`).
    pub fn write(&self, link: Link) -> Written {
        let mut b = Builder::default();
        let mut free: Vec<usize> = Vec::new();
        let mut starts = Vec::new();
        let (scale, offset) = match link {
            Link::Additive => (1.0, self.constant),
            Link::Multiplicative if self.scale.is_some() => (self.constant, 0.0),
            Link::Multiplicative => (self.constant, -1.0),
            Link::Log => (1.0, 0.0),
        };
        match link {
            Link::Additive => free.push(1),
            Link::Multiplicative => free.push(0),
            Link::Log => {
                free.push(2);
                b.konst(self.constant);
            }
        }
        let join = if link == Link::Additive {
            crate::Op::Add
        } else {
            crate::Op::Mul
        };
        for (k, t) in self.terms.iter().enumerate() {
            let at = 2 + b.consts.len();
            starts.push(at);
            emit(t, link, &|c| c as u16, &mut b);
            free.extend(
                t.free
                    .iter()
                    .enumerate()
                    .filter(|(_, f)| **f)
                    .map(|(i, _)| at + i),
            );
            if k > 0 || link == Link::Log {
                b.op(join);
            }
        }
        if self.terms.is_empty() && link != Link::Log {
            // the constant model: the output map alone
            b.konst(if link == Link::Additive { 0.0 } else { 1.0 });
        }
        if link == Link::Log {
            b.op(crate::Op::Log);
        }
        if let (Link::Multiplicative, Some(k)) = (link, self.scale) {
            b.var(k as u16);
            b.op(crate::Op::Mul);
        }
        let mut params = vec![scale, offset];
        params.extend(b.consts);
        Written {
            program: Program {
                nodes: b.nodes,
                affine: false,
            },
            params,
            free,
            starts,
        }
    }

    /// Reads the fitted parameters of [`Structure::write`]'s program back into the terms.
    pub fn read(&mut self, link: Link, w: &Written, params: &[f64]) {
        self.constant = match link {
            Link::Additive => params[1],
            Link::Multiplicative => params[0],
            Link::Log => params[2],
        };
        for (t, &at) in self.terms.iter_mut().zip(&w.starts) {
            let n = t.params.len();
            t.params.copy_from_slice(&params[at..at + n]);
        }
    }

    /// Fits every free constant on `cols` (one slice per feature) against `y`, in place;
    /// returns the mean squared error (`INFINITY` when the model is not finite there, a
    /// pole falls inside the rows' range, or a harmonic runs through less than
    /// [`super::shape::MIN_CYCLES`] periods over them).
    pub fn fit(&mut self, link: Link, cols: &[&[f64]], y: &[f64]) -> f64 {
        let mse = self.fit_any_period(link, cols, y);
        if mse.is_finite() && self.harmonic_too_slow(cols) {
            return f64::INFINITY;
        }
        mse
    }

    /// [`Structure::fit`] without the harmonics' period rule: a fold's refit of a structure
    /// chosen on every row (a harmonic's period, decided there, may come out a few per cent
    /// longer on a fold's rows without making it another shape).
    pub fn fit_any_period(&mut self, link: Link, cols: &[&[f64]], y: &[f64]) -> f64 {
        let w = self.write(link);
        let mut params = w.params.clone();
        let mut ev = Evaluator::new(&w.program);
        let mse = levenberg_marquardt(
            &w.program,
            &mut params,
            Unknowns::Free(&w.free),
            cols,
            y,
            &LmSettings::new(60, 1e-10),
            &mut ev,
        );
        self.read(link, &w, &params);
        if !mse.is_finite() || self.pole_inside(cols) || self.threshold_outside(cols) {
            return f64::INFINITY;
        }
        // no pole, no log of a value <= 0 and no blow-up beside the rows either: the
        // search's rule (issue 64), over the rows' box widened by the same margin
        let bounds = crate::enclosure::widened_box(cols, crate::enclosure::DEFINED_MARGIN);
        if crate::enclosure::defined_over(
            &w.program,
            &params,
            &bounds,
            crate::enclosure::DEFINED_BOXES,
        )
        .is_err()
        {
            return f64::INFINITY;
        }
        mse
    }

    /// Whether a harmonic `sin(w x + c)` runs through less than
    /// [`super::shape::MIN_CYCLES`] periods over the rows' range of its column: it is then
    /// a bend (a trend or a hump) that the monotone shapes and the pole write plainer, not
    /// an effect the rows show repeating.
    fn harmonic_too_slow(&self, cols: &[&[f64]]) -> bool {
        use super::shape::{MIN_CYCLES, Shape};
        self.terms.iter().any(|t| {
            if t.shape != Shape::Periodic {
                return false;
            }
            let (lo, hi) = range(cols[t.cols[0]]);
            let omega = t.params[t.params.len() - 2];
            (omega.abs() * (hi - lo)).is_nan()
                || omega.abs() * (hi - lo) < MIN_CYCLES * 2.0 * std::f64::consts::PI
        })
    }

    /// The model's values on `cols` (`n` rows).
    pub fn predict(&self, link: Link, cols: &[&[f64]], n: usize) -> Vec<f64> {
        let w = self.write(link);
        let mut out = Vec::new();
        Evaluator::new(&w.program).predict(&w.program, &w.params, cols, n, &mut out);
        out
    }

    /// Whether a hinge's knot or a smooth step's centre lies outside the middle of the rows'
    /// range of its column (the range less [`THRESHOLD_MARGIN`] of its width at each end:
    /// a knot among the few outermost rows is fitted to them, and outside the rows it is a
    /// line or a bend the plainer shapes write), or a step is steeper than
    /// [`MAX_STEP_RATE`] over the range (a jump between two neighbouring rows is a
    /// discontinuity fitted to the scatter, not a smooth switch) (issue 68).
    fn threshold_outside(&self, cols: &[&[f64]]) -> bool {
        use super::shape::Shape;
        self.terms.iter().any(|t| {
            let l = t.params.len();
            let (lo, hi) = range(cols[t.cols[0]]);
            let w = hi - lo;
            let at = match t.shape {
                Shape::Hinge => -t.params[l - 1],
                Shape::Step => {
                    let rate = t.params[l - 2].abs() * w;
                    if rate.is_nan() || rate > MAX_STEP_RATE {
                        return true;
                    }
                    -t.params[l - 1] / t.params[l - 2]
                }
                _ => return false,
            };
            !(at > lo + THRESHOLD_MARGIN * w && at < hi - THRESHOLD_MARGIN * w)
        })
    }

    /// Whether the correction respects the monotone constraints `up` and `down` (bit `j`:
    /// column `j`'s effect must not decrease, resp. increase; issue 68): along a grid of
    /// [`MONOTONE_GRID`] values over each constrained column's range in `cols`, the other
    /// columns held at each of [`MONOTONE_ROWS`] rows spread over `cols`, the correction
    /// (without the physics of a scaled fit) never moves the wrong way by more than
    /// `1e-9` of its spread. Every shape and pair is checked by its values, so a factor's
    /// direction, a product's sign and a pair's other column are all accounted for.
    pub fn monotone(&self, link: Link, cols: &[&[f64]], up: u64, down: u64) -> bool {
        if up | down == 0 {
            return true;
        }
        let n = cols.first().map_or(0, |c| c.len());
        if n == 0 {
            return true;
        }
        let me = self.unscaled();
        let refs: Vec<usize> = (0..MONOTONE_ROWS.min(n))
            .map(|k| k * n / MONOTONE_ROWS.min(n))
            .collect();
        for c in 0..cols.len().min(64) {
            let sign = match (up >> c & 1, down >> c & 1) {
                (1, _) => 1.0,
                (_, 1) => -1.0,
                _ => continue,
            };
            if !me.terms.iter().any(|t| t.cols.contains(&c)) {
                continue;
            }
            let (lo, hi) = range(cols[c]);
            let m = refs.len() * MONOTONE_GRID;
            let grid: Vec<Vec<f64>> = (0..cols.len())
                .map(|j| {
                    (0..m)
                        .map(|i| {
                            let (r, g) = (refs[i / MONOTONE_GRID], i % MONOTONE_GRID);
                            if j == c {
                                lo + (hi - lo) * g as f64 / (MONOTONE_GRID - 1) as f64
                            } else {
                                cols[j][r]
                            }
                        })
                        .collect()
                })
                .collect();
            let gc: Vec<&[f64]> = grid.iter().map(Vec::as_slice).collect();
            let v = me.predict(link, &gc, m);
            if v.iter().any(|x| !x.is_finite()) {
                return false;
            }
            let (vlo, vhi) = range(&v);
            let tol = 1e-9 * (vhi - vlo).max(vhi.abs().max(vlo.abs()) * 1e-6);
            let wrong = v.chunks(MONOTONE_GRID).any(|run| {
                run.windows(2)
                    .any(|w| sign * (w[1] - w[0]) < -tol.max(f64::MIN_POSITIVE))
            });
            if wrong {
                return false;
            }
        }
        true
    }

    /// Whether a pole or a saturation's denominator `x + c` changes sign over the rows.
    fn pole_inside(&self, cols: &[&[f64]]) -> bool {
        use super::shape::Shape;
        self.terms.iter().any(|t| {
            if !matches!(t.shape, Shape::Pole | Shape::Saturation) {
                return false;
            }
            let c = t.params[t.params.len() - 1];
            let x = cols[t.cols[0]];
            let (mut neg, mut pos) = (false, false);
            for &v in x {
                let d = v + c;
                neg |= d <= 0.0;
                pos |= d >= 0.0;
            }
            neg && pos
        })
    }
}

/// Rows split into folds once, with each fold's training and held-out columns gathered.
pub(crate) struct Folds {
    pub folds: Vec<Fold>,
    pub n: usize,
}

pub(crate) struct Fold {
    pub train_cols: Vec<Vec<f64>>,
    pub train_y: Vec<f64>,
    pub test_cols: Vec<Vec<f64>>,
    pub test_y: Vec<f64>,
    pub test_rows: Vec<usize>,
}

impl Folds {
    /// `k` folds of the rows, by a shuffle from `seed`. With `groups` (one id per row),
    /// rows sharing an id stay in one fold: a bootstrap resample's copies of one row must
    /// not be scored on a copy of themselves, or the held-out error rewards overfitting.
    pub fn new(cols: &[&[f64]], y: &[f64], k: usize, seed: u64, groups: Option<&[usize]>) -> Self {
        use rand::SeedableRng;
        use rand::seq::SliceRandom;
        let n = y.len();
        let ids: Vec<usize> = match groups {
            Some(g) => g.to_vec(),
            None => (0..n).collect(),
        };
        let mut distinct: Vec<usize> = ids.clone();
        distinct.sort_unstable();
        distinct.dedup();
        distinct.shuffle(&mut rand_chacha::ChaCha8Rng::seed_from_u64(seed ^ 0xFAC7));
        let fold_of: std::collections::HashMap<usize, usize> = distinct
            .iter()
            .enumerate()
            .map(|(pos, &g)| (g, pos % k))
            .collect();
        let of: Vec<usize> = ids.iter().map(|g| fold_of[g]).collect();
        let folds = (0..k)
            .map(|f| {
                let test_rows: Vec<usize> = (0..n).filter(|&i| of[i] == f).collect();
                let train_rows: Vec<usize> = (0..n).filter(|&i| of[i] != f).collect();
                let take =
                    |rows: &[usize], c: &[f64]| rows.iter().map(|&i| c[i]).collect::<Vec<f64>>();
                Fold {
                    train_cols: cols.iter().map(|c| take(&train_rows, c)).collect(),
                    train_y: take(&train_rows, y),
                    test_cols: cols.iter().map(|c| take(&test_rows, c)).collect(),
                    test_y: take(&test_rows, y),
                    test_rows,
                }
            })
            .collect();
        Self { folds, n }
    }

    /// The held-out squared error of every row: `s` (fitted on all rows) refitted on each
    /// fold's training rows from its constants, then predicted on the fold's held-out rows
    /// (`INFINITY` where the fit or the prediction is not finite).
    pub fn errors(&self, s: &Structure, link: Link) -> Vec<f64> {
        let mut e = vec![f64::INFINITY; self.n];
        for f in &self.folds {
            let mut t = s.clone();
            let tc: Vec<&[f64]> = f.train_cols.iter().map(Vec::as_slice).collect();
            if !t.fit_any_period(link, &tc, &f.train_y).is_finite() {
                continue;
            }
            let hc: Vec<&[f64]> = f.test_cols.iter().map(Vec::as_slice).collect();
            let p = t.predict(link, &hc, f.test_y.len());
            for ((&row, &pi), &yi) in f.test_rows.iter().zip(&p).zip(&f.test_y) {
                let d = pi - yi;
                e[row] = if d.is_finite() { d * d } else { f64::INFINITY };
            }
        }
        e
    }
}

/// The share of a column's range at each end where a hinge's knot or a step's centre may
/// not lie ([`Structure::fit`]).
pub(crate) const THRESHOLD_MARGIN: f64 = 0.05;

/// The steepest smooth step `tanh(w x + c)`: `|w|` times the column's range at most this
/// (the switch from -0.76 to 0.76 then spans at least 1/20 of the range).
pub(crate) const MAX_STEP_RATE: f64 = 40.0;

/// Points along a constrained column of [`Structure::monotone`]'s grid.
pub(crate) const MONOTONE_GRID: usize = 33;

/// Rows whose other columns [`Structure::monotone`] holds fixed.
pub(crate) const MONOTONE_ROWS: usize = 16;

/// The smallest and largest value of `x`.
fn range(x: &[f64]) -> (f64, f64) {
    x.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, &v| {
        (a.0.min(v), a.1.max(v))
    })
}

/// Mean of the per-row errors.
pub(crate) fn mean(e: &[f64]) -> f64 {
    e.iter().sum::<f64>() / e.len().max(1) as f64
}

/// `(mean(a - b), its standard error)` of paired per-row errors.
pub(crate) fn paired(a: &[f64], b: &[f64]) -> (f64, f64) {
    let n = a.len().max(1) as f64;
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
    let m = d.iter().sum::<f64>() / n;
    if !m.is_finite() {
        return (m, 0.0);
    }
    let var = d.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0).max(1.0);
    (m, (var / n).sqrt())
}
