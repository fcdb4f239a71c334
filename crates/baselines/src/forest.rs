//! Random forest of bootstrap regression trees (scikit-learn's `RandomForestRegressor`
//! defaults: every feature considered at each split, no depth limit, leaves of 1 sample).

use crate::matrix::RowMajor;
use crate::matrix::{check_fit, check_predict};
use crate::tree::{Limits, Tree, TreeData, argsort_columns, check_limits, grow};
use crate::{BaselineError, Regressor};
use hxai_table::{Par, Table};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Bagged regression trees, built in parallel with rayon (on the threads `par` chooses).
///
/// Tree `t` draws its bootstrap sample from `ChaCha8Rng::seed_from_u64(seed)` on stream
/// `t`, so every tree depends only on `(seed, t)` and the data: the forest is the same for
/// any number of threads. Bootstrap duplicates become integer sample weights, as in
/// scikit-learn. The random streams differ from numpy's, so individual trees differ from
/// scikit-learn's; only the quality of the ensemble is comparable.
#[derive(Debug, Clone)]
pub struct RandomForest {
    /// Number of trees (default 200, as in the paper).
    pub n_trees: usize,
    /// Seed of the bootstrap draws (default 42, as in the paper).
    pub seed: u64,
    /// Maximum depth (default `None`: unlimited).
    pub max_depth: Option<usize>,
    /// Minimum samples per leaf (default 1).
    pub min_samples_leaf: usize,
    /// Threads that build the trees (default [`Par::Current`], the caller's pool); the
    /// forest does not depend on it.
    pub par: Par,
    trees: Vec<Tree>,
    fitted: Option<usize>,
}

impl Default for RandomForest {
    fn default() -> Self {
        Self {
            n_trees: 200,
            seed: 42,
            max_depth: None,
            min_samples_leaf: 1,
            par: Par::Current,
            trees: Vec::new(),
            fitted: None,
        }
    }
}

impl RandomForest {
    /// 200 trees, seed 42, no depth limit.
    pub fn new() -> Self {
        Self::default()
    }

    /// The paper's forest with another seed.
    pub fn with_seed(seed: u64) -> Self {
        Self {
            seed,
            ..Self::default()
        }
    }

    /// Total leaves over all trees (a cheap fingerprint of the fitted forest).
    pub fn n_leaves(&self) -> usize {
        self.trees.iter().map(Tree::n_leaves).sum()
    }
}

/// Rows a forest's prediction walks every tree over at once.
const PREDICT_BLOCK: usize = 2048;

impl Regressor for RandomForest {
    fn name(&self) -> &str {
        "forest"
    }

    fn fit(&mut self, x: &Table, y: &[f64]) -> Result<(), BaselineError> {
        check_fit(x, y)?;
        check_limits(None, self.min_samples_leaf)?;
        if self.n_trees == 0 {
            return Err(BaselineError::InvalidParameter {
                what: "n_trees",
                detail: "must be at least 1".into(),
            });
        }
        let n = x.n_rows();
        let cols = x.columns();
        let sorted_all = argsort_columns(cols);
        let limits = Limits {
            max_depth: self.max_depth,
            min_samples_leaf: self.min_samples_leaf,
            max_leaf_nodes: None,
        };
        let seed = self.seed;
        self.trees = self.par.run(|| {
            (0..self.n_trees)
                .into_par_iter()
                .map(|t| {
                    let mut rng = ChaCha8Rng::seed_from_u64(seed);
                    rng.set_stream(t as u64);
                    let mut w = vec![0.0; n];
                    for _ in 0..n {
                        w[rng.gen_range(0..n)] += 1.0;
                    }
                    let sorted: Vec<Vec<usize>> = sorted_all
                        .iter()
                        .map(|l| l.iter().copied().filter(|&i| w[i] > 0.0).collect())
                        .collect();
                    grow(TreeData { cols, y, w: &w }, sorted, limits)
                })
                .collect()
        });
        self.fitted = Some(x.n_cols());
        Ok(())
    }

    fn predict(&self, x: &Table) -> Result<Vec<f64>, BaselineError> {
        check_predict(self.name(), self.fitted, x)?;
        let k = self.trees.len() as f64;
        let rm = RowMajor::of(x);
        let rows: Vec<&[f64]> = rm.rows().collect();
        // blocks of rows in parallel, each tree over a whole block before the next (its
        // nodes stay in cache: row by row, 10^5 rows took a minute), every row's trees
        // summed in the trees' order, so the result does not depend on the threads
        Ok(self.par.run(|| {
            rows.par_chunks(PREDICT_BLOCK)
                .flat_map_iter(|block| {
                    let mut sum = vec![0.0; block.len()];
                    for t in &self.trees {
                        for (s, r) in sum.iter_mut().zip(block) {
                            *s += t.predict_row(r);
                        }
                    }
                    sum.into_iter().map(move |s| s / k)
                })
                .collect()
        }))
    }
}
