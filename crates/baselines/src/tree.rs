//! Regression trees: scikit-learn's `DecisionTreeRegressor` split rule, grown best-first
//! (`max_leaf_nodes`) or depth-first (inside the random forest).
//!
//! Splitting follows `sklearn/tree/_splitter.pyx`: MSE criterion, candidate positions only
//! between values more than 1e-7 apart, threshold at the midpoint of the two neighbouring
//! values, the best split maximises the proxy `S_l^2 / W_l + S_r^2 / W_r`, and a node whose
//! impurity is at most machine epsilon stays a leaf. Best-first growth pops the frontier
//! node with the largest weighted impurity decrease, as `BestFirstTreeBuilder` does.
//!
//! Each feature's sample list is sorted once per tree; a split partitions every list
//! stably in place, so a node costs `O(features x samples)` instead of a sort per node.

use crate::matrix::RowMajor;
use crate::matrix::{check_fit, check_predict};
use crate::{BaselineError, Regressor};
use hxai_table::Table;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

const FEATURE_THRESHOLD: f64 = 1e-7;
const EPSILON: f64 = f64::EPSILON;

/// One node of a fitted tree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Node {
    /// Terminal node predicting `value`.
    Leaf { value: f64 },
    /// `x[feature] <= threshold` goes to `left`, otherwise `right`.
    Split {
        feature: usize,
        threshold: f64,
        left: usize,
        right: usize,
    },
}

/// A fitted tree: nodes with the root at index 0.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Tree {
    pub(crate) nodes: Vec<Node>,
}

impl Tree {
    pub(crate) fn predict_row(&self, row: &[f64]) -> f64 {
        let mut k = 0;
        loop {
            match self.nodes.get(k) {
                Some(Node::Leaf { value }) => return *value,
                Some(Node::Split {
                    feature,
                    threshold,
                    left,
                    right,
                }) => {
                    k = if row[*feature] <= *threshold {
                        *left
                    } else {
                        *right
                    };
                }
                None => return f64::NAN,
            }
        }
    }

    pub(crate) fn n_leaves(&self) -> usize {
        self.nodes
            .iter()
            .filter(|n| matches!(n, Node::Leaf { .. }))
            .count()
    }
}

/// Training data of one tree: columns, target, per-sample weights (bootstrap counts).
pub(crate) struct TreeData<'a> {
    pub(crate) cols: &'a [Vec<f64>],
    pub(crate) y: &'a [f64],
    pub(crate) w: &'a [f64],
}

/// Growth limits.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Limits {
    pub(crate) max_depth: Option<usize>,
    pub(crate) min_samples_leaf: usize,
    pub(crate) max_leaf_nodes: Option<usize>,
}

/// Per-feature sample lists, each sorted by that feature; a node owns `start..end` of each.
struct Sorted {
    lists: Vec<Vec<usize>>,
    goes_left: Vec<bool>,
    scratch: Vec<usize>,
}

/// Sufficient statistics of a node.
#[derive(Clone, Copy)]
struct Stats {
    w: f64,
    s: f64,
    q: f64,
}

impl Stats {
    fn impurity(&self) -> f64 {
        let m = self.s / self.w;
        self.q / self.w - m * m
    }
}

#[derive(Clone, Copy)]
struct Candidate {
    feature: usize,
    pos: usize,
    threshold: f64,
    left: Stats,
    right: Stats,
    improvement: f64,
}

/// A node waiting for its split: range, stats, depth, best split (if any), id in `nodes`.
struct Pending {
    start: usize,
    end: usize,
    depth: usize,
    split: Option<Candidate>,
    id: usize,
}

struct Builder<'a> {
    data: TreeData<'a>,
    limits: Limits,
    sorted: Sorted,
    w_total: f64,
    nodes: Vec<Node>,
}

impl<'a> Builder<'a> {
    fn new(data: TreeData<'a>, sorted: Vec<Vec<usize>>, limits: Limits) -> Self {
        let n_rows = data.y.len();
        let n = sorted.first().map_or(0, Vec::len);
        let w_total = sorted
            .first()
            .map_or(0.0, |l| l.iter().map(|&i| data.w[i]).sum());
        Self {
            data,
            limits,
            sorted: Sorted {
                lists: sorted,
                goes_left: vec![false; n_rows],
                scratch: Vec::with_capacity(n),
            },
            w_total,
            nodes: Vec::new(),
        }
    }

    fn stats(&self, start: usize, end: usize) -> Stats {
        let mut st = Stats {
            w: 0.0,
            s: 0.0,
            q: 0.0,
        };
        for &i in &self.sorted.lists[0][start..end] {
            let (w, y) = (self.data.w[i], self.data.y[i]);
            st.w += w;
            st.s += w * y;
            st.q += w * y * y;
        }
        st
    }

    /// Best split of `start..end`, or `None` when the node must stay a leaf.
    fn best_split(&self, start: usize, end: usize, depth: usize, st: Stats) -> Option<Candidate> {
        let n = end - start;
        let min_leaf = self.limits.min_samples_leaf;
        let impurity = st.impurity();
        if n < 2
            || n < 2 * min_leaf
            || impurity <= EPSILON
            || self.limits.max_depth.is_some_and(|d| depth >= d)
        {
            return None;
        }
        let mut best: Option<Candidate> = None;
        let mut best_proxy = f64::NEG_INFINITY;
        for (f, list) in self.sorted.lists.iter().enumerate() {
            let idx = &list[start..end];
            let xs = &self.data.cols[f];
            if xs[idx[n - 1]] <= xs[idx[0]] + FEATURE_THRESHOLD {
                continue;
            }
            let mut left = Stats {
                w: 0.0,
                s: 0.0,
                q: 0.0,
            };
            for p in 1..n {
                let i = idx[p - 1];
                let (w, y) = (self.data.w[i], self.data.y[i]);
                left.w += w;
                left.s += w * y;
                left.q += w * y * y;
                let (a, b) = (xs[i], xs[idx[p]]);
                if b <= a + FEATURE_THRESHOLD || p < min_leaf || n - p < min_leaf {
                    continue;
                }
                let rw = st.w - left.w;
                let rs = st.s - left.s;
                let proxy = left.s * left.s / left.w + rs * rs / rw;
                if proxy > best_proxy {
                    best_proxy = proxy;
                    let mut threshold = a / 2.0 + b / 2.0;
                    if threshold == b || threshold.is_infinite() {
                        threshold = a;
                    }
                    best = Some(Candidate {
                        feature: f,
                        pos: p,
                        threshold,
                        left,
                        right: Stats {
                            w: rw,
                            s: rs,
                            q: st.q - left.q,
                        },
                        improvement: 0.0,
                    });
                }
            }
        }
        let mut c = best?;
        let (il, ir) = (c.left.impurity(), c.right.impurity());
        c.improvement =
            st.w / self.w_total * (impurity - c.right.w / st.w * ir - c.left.w / st.w * il);
        if c.improvement + EPSILON < 0.0 {
            return None;
        }
        Some(c)
    }

    /// Stable in-place partition of every feature list of `start..end` by the split.
    fn partition(&mut self, start: usize, end: usize, c: &Candidate) {
        let Sorted {
            lists,
            goes_left,
            scratch,
        } = &mut self.sorted;
        let xs = &self.data.cols[c.feature];
        for &i in &lists[c.feature][start..end] {
            goes_left[i] = xs[i] <= c.threshold;
        }
        for list in lists.iter_mut() {
            scratch.clear();
            let mut k = start;
            for t in start..end {
                let i = list[t];
                if goes_left[i] {
                    list[k] = i;
                    k += 1;
                } else {
                    scratch.push(i);
                }
            }
            list[k..end].copy_from_slice(scratch);
        }
    }

    fn pending(&mut self, start: usize, end: usize, depth: usize, stats: Stats) -> Pending {
        let split = self.best_split(start, end, depth, stats);
        let id = self.nodes.len();
        self.nodes.push(Node::Leaf {
            value: stats.s / stats.w,
        });
        Pending {
            start,
            end,
            depth,
            split,
            id,
        }
    }

    /// Turns `node` into a split and returns its two children.
    fn expand(&mut self, node: &Pending, c: Candidate) -> (Pending, Pending) {
        self.partition(node.start, node.end, &c);
        let mid = node.start + c.pos;
        let left = self.pending(node.start, mid, node.depth + 1, c.left);
        let right = self.pending(mid, node.end, node.depth + 1, c.right);
        self.nodes[node.id] = Node::Split {
            feature: c.feature,
            threshold: c.threshold,
            left: left.id,
            right: right.id,
        };
        (left, right)
    }

    fn build_depth_first(mut self) -> Tree {
        let n = self.sorted.lists.first().map_or(0, Vec::len);
        let root_stats = self.stats(0, n);
        let root = self.pending(0, n, 0, root_stats);
        let mut stack = vec![root];
        while let Some(node) = stack.pop() {
            if let Some(c) = node.split {
                let (l, r) = self.expand(&node, c);
                stack.push(r);
                stack.push(l);
            }
        }
        Tree { nodes: self.nodes }
    }

    fn build_best_first(mut self, max_leaf_nodes: usize) -> Tree {
        struct Item(f64, usize, Pending);
        impl PartialEq for Item {
            fn eq(&self, o: &Self) -> bool {
                self.cmp(o) == Ordering::Equal
            }
        }
        impl Eq for Item {}
        impl PartialOrd for Item {
            fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
                Some(self.cmp(o))
            }
        }
        impl Ord for Item {
            // Largest improvement first; among equals, the node created first.
            fn cmp(&self, o: &Self) -> Ordering {
                self.0.total_cmp(&o.0).then(o.1.cmp(&self.1))
            }
        }
        let n = self.sorted.lists.first().map_or(0, Vec::len);
        let root_stats = self.stats(0, n);
        let root = self.pending(0, n, 0, root_stats);
        let mut heap = BinaryHeap::new();
        let key = |p: &Pending| p.split.map_or(0.0, |c| c.improvement);
        heap.push(Item(key(&root), root.id, root));
        let mut splits_left = max_leaf_nodes.saturating_sub(1);
        while let Some(Item(_, _, node)) = heap.pop() {
            let Some(c) = node.split else { continue };
            if splits_left == 0 {
                continue;
            }
            splits_left -= 1;
            let (l, r) = self.expand(&node, c);
            heap.push(Item(key(&l), l.id, l));
            heap.push(Item(key(&r), r.id, r));
        }
        Tree { nodes: self.nodes }
    }
}

/// Indices `0..n` sorted by each column (ties by index).
pub(crate) fn argsort_columns(cols: &[Vec<f64>]) -> Vec<Vec<usize>> {
    cols.iter()
        .map(|c| {
            let mut idx: Vec<usize> = (0..c.len()).collect();
            idx.sort_by(|&a, &b| c[a].total_cmp(&c[b]).then(a.cmp(&b)));
            idx
        })
        .collect()
}

/// Grows one tree on the samples listed (per feature, sorted) in `sorted`.
pub(crate) fn grow(data: TreeData<'_>, sorted: Vec<Vec<usize>>, limits: Limits) -> Tree {
    let b = Builder::new(data, sorted, limits);
    match limits.max_leaf_nodes {
        Some(k) => b.build_best_first(k),
        None => b.build_depth_first(),
    }
}

/// A regression tree like scikit-learn's `DecisionTreeRegressor(max_leaf_nodes=k)`:
/// grown best-first until it has `max_leaf_nodes` leaves (or no split improves the MSE).
///
/// Features are scanned in index order and only a strictly better split replaces the
/// current best, so among splits of exactly equal quality the lowest feature index and the
/// leftmost position win. (scikit-learn scans features in a random order, so on data with
/// such ties the two may pick different, equally good splits.)
#[derive(Debug, Clone)]
pub struct DecisionTree {
    /// Maximum number of leaves; `None` grows depth-first without a leaf limit.
    pub max_leaf_nodes: Option<usize>,
    /// Maximum depth (`None`: unlimited).
    pub max_depth: Option<usize>,
    /// Minimum samples in a leaf (default 1).
    pub min_samples_leaf: usize,
    name: String,
    tree: Tree,
    fitted: Option<usize>,
}

impl DecisionTree {
    /// A best-first tree with at most `max_leaf_nodes` leaves, named `tree_<k>`.
    pub fn with_max_leaf_nodes(max_leaf_nodes: usize) -> Self {
        Self {
            max_leaf_nodes: Some(max_leaf_nodes),
            max_depth: None,
            min_samples_leaf: 1,
            name: format!("tree_{max_leaf_nodes}"),
            tree: Tree::default(),
            fitted: None,
        }
    }

    /// An unlimited depth-first tree, named `tree`.
    pub fn unlimited() -> Self {
        Self {
            max_leaf_nodes: None,
            max_depth: None,
            min_samples_leaf: 1,
            name: "tree".into(),
            tree: Tree::default(),
            fitted: None,
        }
    }

    /// Number of leaves of the fitted tree (0 before `fit`).
    pub fn n_leaves(&self) -> usize {
        self.tree.n_leaves()
    }
}

pub(crate) fn check_limits(
    max_leaf_nodes: Option<usize>,
    min_samples_leaf: usize,
) -> Result<(), BaselineError> {
    if max_leaf_nodes.is_some_and(|k| k < 2) {
        return Err(BaselineError::InvalidParameter {
            what: "max_leaf_nodes",
            detail: "must be at least 2 (scikit-learn's rule)".into(),
        });
    }
    if min_samples_leaf == 0 {
        return Err(BaselineError::InvalidParameter {
            what: "min_samples_leaf",
            detail: "must be at least 1".into(),
        });
    }
    Ok(())
}

impl Regressor for DecisionTree {
    fn name(&self) -> &str {
        &self.name
    }

    fn fit(&mut self, x: &Table, y: &[f64]) -> Result<(), BaselineError> {
        check_fit(x, y)?;
        check_limits(self.max_leaf_nodes, self.min_samples_leaf)?;
        let cols = x.columns();
        let w = vec![1.0; y.len()];
        let sorted = argsort_columns(cols);
        let limits = Limits {
            max_depth: self.max_depth,
            min_samples_leaf: self.min_samples_leaf,
            max_leaf_nodes: self.max_leaf_nodes,
        };
        self.tree = grow(TreeData { cols, y, w: &w }, sorted, limits);
        self.fitted = Some(x.n_cols());
        Ok(())
    }

    fn predict(&self, x: &Table) -> Result<Vec<f64>, BaselineError> {
        check_predict(self.name(), self.fitted, x)?;
        Ok(RowMajor::of(x)
            .rows()
            .map(|r| self.tree.predict_row(r))
            .collect())
    }
}
