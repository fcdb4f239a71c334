//! Forward selection of factors under cross-validation with the one-standard-error rule,
//! then interactions, a backward pass, and the snapping of exponents.
use super::shape::{ColStats, Shape, Term, starts};
use super::structure::{Folds, Structure, mean, paired};
use super::{FactorConfig, Link, PathStep};
use rayon::prelude::*;

/// The one-sided level of one standard error, `P(Z > 1)`: the level at which the
/// one-standard-error rule calls a gain real ([`Problem::entry_se`]).
const ONE_SE_LEVEL: f64 = 0.158_655_253_931_457;

/// Pairs of columns, the best by FAST, fitted as pair factors at each interaction step.
const FAST_SHORTLIST: usize = 8;

/// Pair factors of the shortlist, the best by their training error, cross-validated at each
/// interaction step.
const INTERACTION_CANDIDATES: usize = 3;

/// A structure fitted on all rows with the held-out error of each row.
#[derive(Clone)]
pub(crate) struct Scored {
    pub s: Structure,
    pub mse: f64,
    pub cv: Vec<f64>,
}

impl Scored {
    pub fn cv_mean(&self) -> f64 {
        mean(&self.cv)
    }
}

/// The data of one selection: columns, target, their statistics and the folds.
pub(crate) struct Problem<'a> {
    pub cols: Vec<&'a [f64]>,
    pub y: &'a [f64],
    pub stats: Vec<ColStats>,
    pub folds: Folds,
    pub link: Link,
    pub cfg: &'a FactorConfig,
    /// How many of `cols` are features (a physics column may follow them).
    pub n_feat: usize,
    /// The physics column of a multiplicative model fitted on the target's scale.
    pub scale: Option<usize>,
    /// The rows' group ids (rows sharing one stay in one fold), kept for the consensus'
    /// resamples.
    pub groups: Option<Vec<usize>>,
    /// Differences of mean squared error below this are ties: `1e-10` of the target's
    /// variance (a gain of R² below 1e-10). On noise-free rows the paired standard error
    /// is itself at rounding level, and without a floor a distractor whose amplitude is
    /// 1e-19 "pays".
    pub floor: f64,
}

impl<'a> Problem<'a> {
    /// `cols` are the features, then (with `scale`) the physics column, in which case `y`
    /// is the measured target rather than the correction.
    pub fn new(
        cols: Vec<&'a [f64]>,
        y: &'a [f64],
        link: Link,
        cfg: &'a FactorConfig,
        groups: Option<&[usize]>,
        scale: Option<usize>,
    ) -> Self {
        let stats = cols.iter().map(|c| ColStats::of(c)).collect();
        let folds = Folds::new(&cols, y, cfg.folds, cfg.seed, groups);
        let n_feat = scale.unwrap_or(cols.len());
        let n = y.len().max(1) as f64;
        let my = y.iter().sum::<f64>() / n;
        let floor = 1e-10 * y.iter().map(|v| (v - my) * (v - my)).sum::<f64>() / n;
        Self {
            floor,
            groups: groups.map(<[usize]>::to_vec),
            cols,
            y,
            stats,
            folds,
            link,
            cfg,
            n_feat,
            scale,
        }
    }

    /// Whether `a`'s held-out errors are within `k` paired standard errors of `b`'s (or
    /// within [`Problem::floor`]): `a` is as good as `b`.
    fn within(&self, a: &Scored, b: &Scored, k: f64) -> bool {
        let (d, se) = paired(&a.cv, &b.cv);
        d <= (k * se).max(self.floor)
    }

    /// The paired standard errors a factor must lower the held-out error by to enter the
    /// forward path, when it was the best of `m` candidate columns: the one-standard-error
    /// rule's one-sided level (`P(Z > 1)`, 0.159) shared among the `m` columns (Bonferroni),
    /// as a Student quantile on the rows' degrees of freedom, times
    /// [`FactorConfig::se_rule`]. With one candidate it is the rule's own `se_rule`; with
    /// more, the best of several columns that carry nothing (each gaining some fraction of
    /// a standard error by chance) no longer enters half the time: measured on the tool-life
    /// table's bootstrap resamples before this rule, a distractor column was kept in half
    /// of them (docs/benchmarks.md, "The factor form").
    fn entry_se(&self, m: usize) -> f64 {
        let dof = (self.y.len().max(3) - 1) as f64;
        let one = hxai_eval::t_upper_quantile(ONE_SE_LEVEL, dof);
        let shared = hxai_eval::t_upper_quantile(ONE_SE_LEVEL / m.max(1) as f64, dof);
        if one.is_finite() && shared.is_finite() && one > 0.0 {
            self.cfg.se_rule * shared / one
        } else {
            self.cfg.se_rule
        }
    }

    /// Whether `s` respects the monotone constraints ([`Structure::monotone`]).
    pub fn monotone(&self, s: &Structure) -> bool {
        s.monotone(
            self.link,
            &self.cols,
            self.cfg.increasing,
            self.cfg.decreasing,
        )
    }

    /// `s` fitted on every row (from its constants) and scored by CV; `None` where the fit
    /// is not finite or breaks a monotone constraint.
    pub fn score(&self, mut s: Structure) -> Option<Scored> {
        let mse = s.fit(self.link, &self.cols, self.y);
        if !mse.is_finite() || !self.monotone(&s) {
            return None;
        }
        let cv = self.folds.errors(&s, self.link);
        Some(Scored { s, mse, cv })
    }

    /// `base` with one more term of `shape` over `cols`, fitted from each start (a sum's
    /// amplitude set by projection on the partial residual); the best fit on all rows,
    /// scored by CV. `None` where no start gives a finite fit.
    pub fn extend(&self, base: &Scored, shape: Shape, cols: &[usize]) -> Option<Scored> {
        let st: Vec<ColStats> = cols.iter().map(|&c| self.stats[c]).collect();
        if shape.needs_positive() && !st.iter().all(|c| c.positive) {
            return None;
        }
        let resid: Vec<f64> = if self.link == Link::Additive {
            let p = base.s.predict(self.link, &self.cols, self.y.len());
            self.y.iter().zip(&p).map(|(y, p)| y - p).collect()
        } else {
            Vec::new()
        };
        let mut best: Option<Structure> = None;
        let mut best_mse = f64::INFINITY;
        for mut term in starts(shape, self.link, &st) {
            term.cols = cols.to_vec();
            if self.link == Link::Additive {
                term.params[0] = projection(&term, &self.cols, &resid);
            }
            let mut s = base.s.clone();
            s.terms.push(term);
            let mse = s.fit(self.link, &self.cols, self.y);
            if mse < best_mse && self.monotone(&s) {
                best_mse = mse;
                best = Some(s);
            }
        }
        self.score(best?)
    }

    /// The best shape for column `c` added to `base`: the earliest shape in the order of
    /// preference whose held-out error is within one standard error of the best shape's.
    fn best_shape(&self, base: &Scored, c: usize) -> Option<(Scored, Vec<Scored>)> {
        let fits: Vec<Scored> = Shape::MAIN
            .iter()
            .filter(|&&sh| self.cfg.shapes.contains(sh))
            .filter(|&&sh| sh != Shape::Periodic || self.cfg.harmonic_allowed(c))
            .filter_map(|&sh| self.extend(base, sh, &[c]))
            .collect();
        let best = fits
            .iter()
            .min_by(|a, b| a.cv_mean().total_cmp(&b.cv_mean()))?
            .clone();
        let chosen = fits
            .iter()
            .find(|f| self.within(f, &best, self.cfg.se_rule))
            .cloned()
            .unwrap_or(best);
        // a harmonic (three constants, the most flexible one-column shape) must pay as an
        // interaction must: beat the column's best other shape by `interaction_se` paired
        // standard errors, or the plainer shape is kept (measured: without it, bootstrap
        // resamples of issue 46's tables put a sine on columns that carry nothing)
        // (issue 68: so must the smooth step and the saturating power, three constants too)
        let flexible = |s: &Scored| s.s.terms.last().is_some_and(|t| t.shape.flexible());
        if flexible(&chosen) {
            let others: Vec<&Scored> = fits.iter().filter(|f| !flexible(f)).collect();
            if let Some(plain) = others
                .iter()
                .min_by(|a, b| a.cv_mean().total_cmp(&b.cv_mean()))
                .copied()
                && self.within(plain, &chosen, self.cfg.interaction_se)
            {
                let pick = others
                    .iter()
                    .find(|f| self.within(f, plain, self.cfg.se_rule))
                    .copied()
                    .unwrap_or(plain)
                    .clone();
                return Some((pick, fits));
            }
        }
        Some((chosen, fits))
    }

    /// Backfitting of the shapes: each one-column factor of `cur` in turn is taken out and
    /// its column's shape chosen again ([`Problem::best_shape`]) with the other factors in
    /// the model, for at most [`FactorConfig::backfit_rounds`] rounds or until no shape
    /// changes. A factor keeps its place in the product (or sum). Measured on the wear
    /// table of issue 46: the temperature entered first, as a line (within one standard
    /// error of the exponential while the speed's effect was still in the residual), and
    /// an interaction then stood in for its true exponential shape.
    fn backfit(&self, mut cur: Scored) -> Scored {
        // one factor alone was chosen against the empty model already
        if cur.s.terms.len() < 2 {
            return cur;
        }
        for _ in 0..self.cfg.backfit_rounds {
            let mut changed = false;
            for i in 0..cur.s.terms.len() {
                let (shape, c) = (cur.s.terms[i].shape, cur.s.terms[i].cols[0]);
                if shape == Shape::Pair {
                    continue;
                }
                let mut rest = cur.s.clone();
                rest.terms.remove(i);
                let base = Scored {
                    s: rest,
                    mse: f64::NAN,
                    cv: Vec::new(),
                };
                let Some((mut new, _)) = self.best_shape(&base, c) else {
                    continue;
                };
                if new.s.terms.last().map(|t| t.shape) == Some(shape) {
                    continue;
                }
                if let Some(t) = new.s.terms.pop() {
                    new.s.terms.insert(i, t);
                }
                cur = new;
                changed = true;
            }
            if !changed {
                break;
            }
        }
        cur
    }

    /// Forward selection, the one-standard-error back-off, interactions and a backward
    /// pass; returns the selected structure, the path and the runner-up shapes of the
    /// selected columns (the alternatives the data cannot tell apart).
    pub fn select(&self) -> Option<(Scored, Vec<PathStep>, Vec<Scored>)> {
        let empty = self.score(Structure::empty(self.link, self.scale))?;
        let mut path: Vec<(Scored, String)> = vec![(empty, String::new())];
        let mut used: Vec<usize> = Vec::new();
        let mut runners: Vec<Vec<Scored>> = vec![Vec::new()];
        let n_cols = self.n_feat;
        while used.len() < self.cfg.max_factors.min(n_cols) {
            let base = &path[path.len() - 1].0;
            let cands: Vec<usize> = (0..n_cols).filter(|c| !used.contains(c)).collect();
            let found: Vec<Option<(Scored, Vec<Scored>)>> = self.cfg.par.run(|| {
                cands
                    .par_iter()
                    .map(|&c| self.best_shape(base, c))
                    .collect()
            });
            let Some((k, (next, fits))) = found
                .into_iter()
                .enumerate()
                .filter_map(|(k, f)| f.map(|f| (k, f)))
                .min_by(|a, b| a.1.0.cv_mean().total_cmp(&b.1.0.cv_mean()))
            else {
                break;
            };
            if next.cv_mean() >= base.cv_mean() - self.floor
                || self.within(base, &next, self.entry_se(cands.len()))
            {
                break;
            }
            used.push(cands[k]);
            let label = next.s.terms[next.s.terms.len() - 1]
                .shape
                .name()
                .to_string();
            let next = self.backfit(next);
            path.push((next, label));
            runners.push(fits);
        }
        // the one-standard-error rule along the path
        let best = path
            .iter()
            .map(|(p, _)| p)
            .min_by(|a, b| a.cv_mean().total_cmp(&b.cv_mean()))?
            .clone();
        let k = path
            .iter()
            .position(|(p, _)| self.within(p, &best, self.cfg.se_rule))
            .unwrap_or(path.len() - 1);
        let mut chosen = path[k].0.clone();
        let mut alternatives: Vec<Scored> = runners[k]
            .iter()
            .filter(|f| f.s != chosen.s)
            .filter(|f| self.within(f, &chosen, self.cfg.se_rule))
            .cloned()
            .collect();
        let mut steps: Vec<PathStep> = path
            .iter()
            .map(|(p, _)| PathStep {
                columns: p.s.terms.iter().map(|t| t.cols.clone()).collect(),
                cv_mse: p.cv_mean(),
                train_mse: p.mse,
                kept: false,
            })
            .collect();
        steps[k].kept = true;
        for _ in 0..self.cfg.interactions {
            let Some(with) = self.interaction(&chosen) else {
                break;
            };
            if self.within(&chosen, &with, self.cfg.interaction_se) {
                break;
            }
            chosen = self.backward(with);
            alternatives.clear();
            for s in &mut steps {
                s.kept = false;
            }
            steps.push(PathStep {
                columns: chosen.s.terms.iter().map(|t| t.cols.clone()).collect(),
                cv_mse: chosen.cv_mean(),
                train_mse: chosen.mse,
                kept: true,
            });
        }
        Some((chosen, steps, alternatives))
    }

    /// The best interaction factor to add to `base`: every pair of columns not yet in an
    /// interaction ranked by FAST on `base`'s residual ([`super::fast`], issue 68); the
    /// best [`FAST_SHORTLIST`] fitted as pair factors, and the [`INTERACTION_CANDIDATES`]
    /// of lowest training error scored by CV.
    fn interaction(&self, base: &Scored) -> Option<Scored> {
        use super::fast::{FAST_BINS, bin_of, pair_gain};
        let n = self.n_feat;
        let taken: Vec<Vec<usize>> = base.s.terms.iter().map(|t| t.cols.clone()).collect();
        let pairs: Vec<[usize; 2]> = (0..n)
            .flat_map(|i| (i + 1..n).map(move |j| [i, j]))
            .filter(|p| !taken.iter().any(|t| t.as_slice() == p))
            .collect();
        let pred = base.s.predict(self.link, &self.cols, self.y.len());
        let resid: Vec<f64> = self.y.iter().zip(&pred).map(|(y, p)| y - p).collect();
        if resid.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let bins: Vec<(Vec<usize>, usize)> =
            (0..n).map(|c| bin_of(self.cols[c], FAST_BINS)).collect();
        let mut ranked: Vec<(f64, [usize; 2])> = pairs
            .iter()
            .map(|p| {
                let (a, b) = (&bins[p[0]], &bins[p[1]]);
                (pair_gain(&a.0, a.1, &b.0, b.1, &resid), *p)
            })
            .collect();
        // the largest gain first; ties in the pairs' order
        ranked.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        // FAST's shortlist fitted as pair factors, ranked by their training error (the pair
        // factor is one parametric shape, which a two-by-two cut only approximates)
        let fits: Vec<Option<(Structure, f64)>> = self.cfg.par.run(|| {
            ranked
                .into_par_iter()
                .take(FAST_SHORTLIST)
                .map(|(_, p)| self.fit_pair(base, &p))
                .collect()
        });
        let mut fits: Vec<(Structure, f64)> = fits.into_iter().flatten().collect();
        fits.sort_by(|a, b| a.1.total_cmp(&b.1));
        let scored: Vec<Option<Scored>> = self.cfg.par.run(|| {
            fits.into_par_iter()
                .take(INTERACTION_CANDIDATES)
                .map(|(s, _)| self.score(s))
                .collect()
        });
        scored
            .into_iter()
            .flatten()
            .min_by(|a, b| a.cv_mean().total_cmp(&b.cv_mean()))
    }

    /// `base` with a pair term over `p`, fitted on all rows from each start.
    fn fit_pair(&self, base: &Scored, p: &[usize; 2]) -> Option<(Structure, f64)> {
        if !self.cfg.shapes.contains(Shape::Pair) {
            return None;
        }
        let st: Vec<ColStats> = p.iter().map(|&c| self.stats[c]).collect();
        let resid: Vec<f64> = if self.link == Link::Additive {
            let pr = base.s.predict(self.link, &self.cols, self.y.len());
            self.y.iter().zip(&pr).map(|(y, p)| y - p).collect()
        } else {
            Vec::new()
        };
        let mut best: Option<(Structure, f64)> = None;
        for mut term in starts(Shape::Pair, self.link, &st) {
            term.cols = p.to_vec();
            if self.link == Link::Additive {
                term.params[0] = projection(&term, &self.cols, &resid);
            }
            let mut s = base.s.clone();
            s.terms.push(term);
            let mse = s.fit(self.link, &self.cols, self.y);
            if mse.is_finite()
                && best.as_ref().is_none_or(|b| mse < b.1)
                && s.terms.last().is_some_and(reads_both)
                && self.monotone(&s)
            {
                best = Some((s, mse));
            }
        }
        best
    }

    /// Drops one-column terms the data no longer needs once an interaction is in (the
    /// column's effect may be all in the interaction): the one whose removal costs least,
    /// while the cost is within one standard error.
    fn backward(&self, mut cur: Scored) -> Scored {
        loop {
            let mains: Vec<usize> = (0..cur.s.terms.len())
                .filter(|&i| cur.s.terms[i].shape != Shape::Pair)
                .collect();
            let tries: Vec<Option<Scored>> = self.cfg.par.run(|| {
                mains
                    .par_iter()
                    .map(|&i| {
                        let mut s = cur.s.clone();
                        s.terms.remove(i);
                        self.score(s)
                    })
                    .collect()
            });
            let Some(best) = tries
                .into_iter()
                .flatten()
                .min_by(|a, b| a.cv_mean().total_cmp(&b.cv_mean()))
            else {
                return cur;
            };
            if !self.within(&best, &cur, self.cfg.se_rule) {
                return cur;
            }
            cur = best;
        }
    }

    /// Snaps each fitted exponent to the nearest whole or half number where the Bayesian
    /// information criterion allows it (the fit loses less than `ln(n)` in `n ln(mse)`,
    /// the price of the constant it saves).
    pub fn snap(&self, mut cur: Scored) -> Scored {
        let n = self.y.len() as f64;
        for ti in 0..cur.s.terms.len() {
            let idx: Vec<usize> = match cur.s.terms[ti].shape {
                Shape::Power | Shape::SaturatingPower => vec![cur.s.terms[ti].params.len() - 1],
                Shape::Pair => {
                    let l = cur.s.terms[ti].params.len();
                    vec![l - 2, l - 1]
                }
                _ => continue,
            };
            for i in idx {
                if !cur.s.terms[ti].free[i] {
                    continue;
                }
                let v = cur.s.terms[ti].params[i];
                let h = (2.0 * v).round() / 2.0;
                if h == 0.0 || (v - h).abs() > 0.15 * h.abs().max(1.0) {
                    continue;
                }
                let mut s = cur.s.clone();
                s.terms[ti].params[i] = h;
                s.terms[ti].free[i] = false;
                let mse = s.fit(self.link, &self.cols, self.y);
                if mse.is_finite() && n * (mse / cur.mse).ln() <= n.ln() && self.monotone(&s) {
                    let cv = self.folds.errors(&s, self.link);
                    cur = Scored { s, mse, cv };
                }
            }
        }
        cur
    }
}

/// Exponents of a pair factor smaller than this in size leave its column out: the pair is
/// then the other column's main effect (measured: an additive pair `r^(-8.8e-17) v` was
/// kept as an interaction), which the forward selection already offered.
const PAIR_MIN_EXPONENT: f64 = 0.01;

/// Whether a fitted pair term reads both its columns (each exponent at least
/// [`PAIR_MIN_EXPONENT`] in size).
pub(super) fn reads_both(t: &Term) -> bool {
    let l = t.params.len();
    l >= 2
        && t.params[l - 2].abs() >= PAIR_MIN_EXPONENT
        && t.params[l - 1].abs() >= PAIR_MIN_EXPONENT
}

/// The least-squares amplitude of a sum's term (its shape with amplitude 1) against `r`.
fn projection(term: &Term, cols: &[&[f64]], r: &[f64]) -> f64 {
    let mut unit = term.clone();
    unit.params[0] = 1.0;
    let s = Structure {
        terms: vec![unit],
        constant: 0.0,
        scale: None,
    };
    let v = s.predict(Link::Additive, cols, r.len());
    let n = r.len() as f64;
    let (mv, mr) = (v.iter().sum::<f64>() / n, r.iter().sum::<f64>() / n);
    let (mut num, mut den) = (0.0, 0.0);
    for (a, b) in v.iter().zip(r) {
        num += (a - mv) * (b - mr);
        den += (a - mv) * (a - mv);
    }
    let a = num / den;
    if a.is_finite() { a } else { 0.0 }
}
