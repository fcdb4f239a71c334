//! One tree of histogram gradient boosting, grown leaf-wise (best-first) on binned data:
//! scikit-learn's `TreeGrower` (`grower.py`) and `Splitter` (`splitting.pyx`) for the
//! squared error, whose hessians are all 1.
//!
//! A node owns a contiguous range of `partition` (row indices); its histogram holds, for
//! every feature and bin, the sum of the gradients and the count of its rows. The best split
//! of a node scans each feature's bins from left to right, accumulating the left child's
//! gradient sum `G_L` and count `H_L` (the hessian sum), and scores
//!
//! `gain = G_L^2 / (H_L + l2) + G_R^2 / (H_R + l2) - G^2 / (H + l2)`
//!
//! written as scikit-learn writes it, `loss(node) - loss(left) - loss(right)` with
//! `loss = G * value` and `value = -G / (H + l2 + 1e-15)`. A bin position counts only if
//! both children keep `min_samples_leaf` rows; the first position of strictly largest gain
//! wins within a feature, the lowest feature index among equal gains. The root's `value`
//! is 0, as in scikit-learn, so its `loss(node)` term is 0 (a constant added to every
//! candidate of the root: it changes no choice).
//!
//! Growth pops the splittable node of largest gain (ties: the node created first), splits
//! its rows stably, and stops at `max_leaf_nodes` leaves (then every waiting node becomes a
//! leaf), at `max_depth`, or when no node can split. A child with fewer than
//! `2 min_samples_leaf` rows is a leaf at once. The smaller child's histogram is built from
//! its rows and the larger one's is the parent's minus the smaller's, scikit-learn's
//! subtraction trick: sums are then added in scikit-learn's order too. A leaf's value is
//! `-learning_rate * G / (H + l2)`.
//!
//! Gradients are `f32` (scikit-learn's `G_H_DTYPE`), summed in `f64`. Large nodes build their
//! histograms and scan their features in parallel, one feature per task; each feature's sums
//! run in row order whatever the thread count, so the tree does not depend on it.

use rayon::prelude::*;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Work (rows x features) from which a node's histograms are built in parallel; below it,
/// a rayon task costs more than the few microseconds of work it would take over.
const PARALLEL_WORK: usize = 16_384;

/// scikit-learn's `min_hessian_to_split`; with hessians of 1 it binds only for
/// `min_samples_leaf = 0`, which is refused, but the scan keeps the test for fidelity.
const MIN_HESSIAN_TO_SPLIT: f64 = 1e-3;

/// Added to the hessian sum before dividing, as scikit-learn does (no division by zero
/// for `l2_regularization = 0`).
const VALUE_EPS: f64 = 1e-15;

/// Growth limits and regularisation of one tree.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TreeParams {
    pub(crate) max_leaf_nodes: Option<usize>,
    pub(crate) max_depth: Option<usize>,
    pub(crate) min_samples_leaf: usize,
    pub(crate) l2: f64,
    pub(crate) shrinkage: f64,
}

/// One node of a fitted boosting tree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Node {
    /// Adds `value` to the prediction.
    Leaf { value: f64 },
    /// `x[feature] <= threshold` goes to `left`, otherwise `right`.
    Split {
        feature: usize,
        threshold: f64,
        left: usize,
        right: usize,
    },
}

/// A fitted tree, root at index 0.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct BoostTree {
    pub(crate) nodes: Vec<Node>,
}

impl BoostTree {
    /// The leaf value of row `row` of the columns `cols`.
    pub(crate) fn value(&self, cols: &[Vec<f64>], row: usize) -> f64 {
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
                    k = if cols[*feature][row] <= *threshold {
                        *left
                    } else {
                        *right
                    }
                }
                None => return f64::NAN,
            }
        }
    }

    /// Number of leaves.
    pub(crate) fn n_leaves(&self) -> usize {
        self.nodes
            .iter()
            .filter(|n| matches!(n, Node::Leaf { .. }))
            .count()
    }
}

/// One bin of a histogram: gradient sum and row count (the hessian sum, hessians being 1).
#[derive(Debug, Clone, Copy, Default)]
struct Bin {
    g: f64,
    n: u32,
}

/// The best split of a node.
#[derive(Debug, Clone, Copy)]
struct SplitInfo {
    gain: f64,
    feature: usize,
    bin: u8,
    g_left: f64,
    g_right: f64,
    n_left: usize,
    value_left: f64,
    value_right: f64,
}

/// A node that may still be split: its rows `start..stop`, sums, value (before shrinkage),
/// depth, id in the output, and while it waits for a split its histograms and best split.
#[derive(Debug)]
struct Grown {
    id: usize,
    start: usize,
    stop: usize,
    depth: usize,
    g: f64,
    value: f64,
    hist: Vec<Bin>,
    split: Option<SplitInfo>,
}

impl Grown {
    fn n(&self) -> usize {
        self.stop - self.start
    }
}

/// A leaf of the tree just grown: rows `start..stop` of the partition get `value`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LeafRows {
    pub(crate) start: usize,
    pub(crate) stop: usize,
    pub(crate) value: f64,
}

/// The binned training data, with the buffers one tree needs; reused from tree to tree.
#[derive(Debug)]
pub(crate) struct Grower<'a> {
    bins: &'a [Vec<u8>],
    thresholds: &'a [Vec<f64>],
    /// Bins per feature (`thresholds[f].len() + 1`).
    n_bins: Vec<usize>,
    /// Histogram slots per feature (the largest `n_bins`).
    stride: usize,
    params: TreeParams,
    /// Row indices; a node owns a contiguous range.
    pub(crate) partition: Vec<usize>,
    scratch: Vec<usize>,
    ordered: Vec<f32>,
}

impl<'a> Grower<'a> {
    /// A grower over binned columns `bins` (all of one length) with edges `thresholds`.
    pub(crate) fn new(bins: &'a [Vec<u8>], thresholds: &'a [Vec<f64>], params: TreeParams) -> Self {
        let n_bins: Vec<usize> = thresholds.iter().map(|t| t.len() + 1).collect();
        let stride = n_bins.iter().copied().max().unwrap_or(1);
        let n = bins.first().map_or(0, Vec::len);
        Self {
            bins,
            thresholds,
            n_bins,
            stride,
            params,
            partition: Vec::with_capacity(n),
            scratch: Vec::with_capacity(n),
            ordered: Vec::with_capacity(n),
        }
    }

    /// Grows one tree on the gradients `grad` (one per row); returns it and its leaves'
    /// row ranges in [`Grower::partition`], for updating the training predictions.
    pub(crate) fn grow(&mut self, grad: &[f32]) -> (BoostTree, Vec<LeafRows>) {
        let n = grad.len();
        self.partition.clear();
        self.partition.extend(0..n);
        let p = self.params;
        let hist = self.histograms(grad, 0, n);
        // the root's sums from the first feature's histogram, as scikit-learn takes them
        let g: f64 = hist[..self.n_bins[0]].iter().map(|b| b.g).sum();
        let mut nodes = vec![Node::Leaf { value: 0.0 }];
        let mut leaves: Vec<Grown> = Vec::new();
        let mut waiting: BinaryHeap<Waiting> = BinaryHeap::new();
        let root = Grown {
            id: 0,
            start: 0,
            stop: n,
            depth: 0,
            g,
            value: 0.0,
            hist,
            split: None,
        };
        if n < 2 * p.min_samples_leaf {
            leaves.push(root);
        } else {
            self.push_or_finalize(root, &mut waiting, &mut leaves);
        }
        while let Some(Waiting(node)) = waiting.pop() {
            let Some(s) = node.split else {
                leaves.push(node);
                continue;
            };
            let mid = self.apply_split(node.start, node.stop, &s);
            let depth = node.depth + 1;
            let (left_id, right_id) = (nodes.len(), nodes.len() + 1);
            nodes.push(Node::Leaf { value: 0.0 });
            nodes.push(Node::Leaf { value: 0.0 });
            nodes[node.id] = Node::Split {
                feature: s.feature,
                threshold: self.thresholds[s.feature][usize::from(s.bin)],
                left: left_id,
                right: right_id,
            };
            let child = |id, start, stop, g, value| Grown {
                id,
                start,
                stop,
                depth,
                g,
                value,
                hist: Vec::new(),
                split: None,
            };
            let mut left = child(left_id, node.start, mid, s.g_left, s.value_left);
            let mut right = child(right_id, mid, node.stop, s.g_right, s.value_right);
            let n_leaf_nodes = leaves.len() + waiting.len() + 2;
            if p.max_leaf_nodes == Some(n_leaf_nodes) {
                leaves.push(left);
                leaves.push(right);
                leaves.extend(waiting.drain().map(|w| w.0));
                break;
            }
            if p.max_depth == Some(depth) {
                leaves.push(left);
                leaves.push(right);
                continue;
            }
            let left_can = left.n() >= 2 * p.min_samples_leaf;
            let right_can = right.n() >= 2 * p.min_samples_leaf;
            if left_can || right_can {
                // the smaller child from its rows, the larger by subtraction (on equal
                // counts the right child is built, as in scikit-learn)
                let parent = node.hist;
                if left.n() < right.n() {
                    left.hist = self.histograms(grad, left.start, left.stop);
                    right.hist = subtract(parent, &left.hist);
                } else {
                    right.hist = self.histograms(grad, right.start, right.stop);
                    left.hist = subtract(parent, &right.hist);
                }
            }
            for (c, can) in [(left, left_can), (right, right_can)] {
                if can {
                    self.push_or_finalize(c, &mut waiting, &mut leaves);
                } else {
                    leaves.push(c);
                }
            }
        }
        let rows = leaves
            .iter()
            .map(|l| {
                let value = l.value * p.shrinkage;
                nodes[l.id] = Node::Leaf { value };
                LeafRows {
                    start: l.start,
                    stop: l.stop,
                    value,
                }
            })
            .collect();
        (BoostTree { nodes }, rows)
    }

    /// Finds `node`'s best split; a node with a positive gain waits, any other is a leaf.
    fn push_or_finalize(
        &self,
        mut node: Grown,
        waiting: &mut BinaryHeap<Waiting>,
        leaves: &mut Vec<Grown>,
    ) {
        node.split = self.best_split(&node);
        if node.split.is_some() {
            waiting.push(Waiting(node));
        } else {
            node.hist = Vec::new();
            leaves.push(node);
        }
    }

    /// Histograms of the rows `start..stop` of the partition, feature after feature.
    fn histograms(&mut self, grad: &[f32], start: usize, stop: usize) -> Vec<Bin> {
        let rows = &self.partition[start..stop];
        self.ordered.clear();
        self.ordered.extend(rows.iter().map(|&i| grad[i]));
        let (ordered, bins, stride) = (&self.ordered, self.bins, self.stride);
        let mut hist = vec![Bin::default(); stride * bins.len()];
        let fill = |(f, h): (usize, &mut [Bin])| {
            let col = &bins[f];
            for (&i, &g) in rows.iter().zip(ordered) {
                let b = &mut h[usize::from(col[i])];
                b.g += f64::from(g);
                b.n += 1;
            }
        };
        if rows.len() * bins.len() >= PARALLEL_WORK && bins.len() > 1 {
            hist.par_chunks_mut(stride).enumerate().for_each(fill);
        } else {
            hist.chunks_mut(stride).enumerate().for_each(fill);
        }
        hist
    }

    /// The best split of `node` over all features, if one has a positive gain.
    fn best_split(&self, node: &Grown) -> Option<SplitInfo> {
        let n_features = self.bins.len();
        let scan = |f: usize| self.best_bin(node, f);
        let per_feature: Vec<Option<SplitInfo>> =
            if node.n() * n_features >= PARALLEL_WORK && n_features > 1 {
                (0..n_features).into_par_iter().map(scan).collect()
            } else {
                (0..n_features).map(scan).collect()
            };
        // lowest feature index among equal gains (scikit-learn's strict `>`)
        let mut best: Option<SplitInfo> = None;
        for s in per_feature.into_iter().flatten() {
            if best.is_none_or(|b| s.gain > b.gain) {
                best = Some(s);
            }
        }
        best
    }

    /// The best bin of feature `f` for `node` (scikit-learn's
    /// `_find_best_bin_to_split_left_to_right` without missing values).
    fn best_bin(&self, node: &Grown, f: usize) -> Option<SplitInfo> {
        let p = &self.params;
        let n = node.n();
        let (g, h) = (node.g, n as f64);
        let hist = &node.hist[f * self.stride..f * self.stride + self.n_bins[f]];
        let loss_node = loss(node.value, g);
        let (mut g_left, mut h_left, mut n_left) = (0.0, 0.0, 0usize);
        let mut best_gain = -1.0;
        let mut best: Option<(usize, f64, f64, usize)> = None;
        // the last bin never goes left: the right child would be empty
        for (b, bin) in hist.iter().enumerate().take(self.n_bins[f] - 1) {
            // An empty bin leaves every sum as it was, so its position scores exactly as
            // the previous one and cannot beat it (strict `>`): skipping it changes no
            // choice, and a small node has far fewer rows than bins.
            if bin.n == 0 {
                continue;
            }
            n_left += bin.n as usize;
            let n_right = n - n_left;
            h_left += f64::from(bin.n);
            let h_right = h - h_left;
            g_left += bin.g;
            let g_right = g - g_left;
            if n_left < p.min_samples_leaf {
                continue;
            }
            if n_right < p.min_samples_leaf {
                break;
            }
            if h_left < MIN_HESSIAN_TO_SPLIT {
                continue;
            }
            if h_right < MIN_HESSIAN_TO_SPLIT {
                break;
            }
            let mut gain = loss_node;
            gain -= loss(node_value(g_left, h_left, p.l2), g_left);
            gain -= loss(node_value(g_right, h_right, p.l2), g_right);
            if gain > best_gain && gain > 0.0 {
                best_gain = gain;
                best = Some((b, g_left, h_left, n_left));
            }
        }
        let (b, g_left, h_left, n_left) = best?;
        let g_right = g - g_left;
        Some(SplitInfo {
            gain: best_gain,
            feature: f,
            bin: b as u8,
            g_left,
            g_right,
            n_left,
            value_left: node_value(g_left, h_left, p.l2),
            value_right: node_value(g_right, h - h_left, p.l2),
        })
    }

    /// Stable partition of the rows `start..stop` by the split; returns where the right
    /// child starts.
    fn apply_split(&mut self, start: usize, stop: usize, s: &SplitInfo) -> usize {
        let col = &self.bins[s.feature];
        self.scratch.clear();
        let mut k = start;
        for t in start..stop {
            let i = self.partition[t];
            if col[i] <= s.bin {
                self.partition[k] = i;
                k += 1;
            } else {
                self.scratch.push(i);
            }
        }
        debug_assert_eq!(k - start, s.n_left);
        self.partition[k..stop].copy_from_slice(&self.scratch);
        k
    }
}

/// A node's value before shrinkage: `-G / (H + l2)` (scikit-learn's `compute_node_value`).
fn node_value(g: f64, h: f64, l2: f64) -> f64 {
    -g / (h + l2 + VALUE_EPS)
}

/// A node's loss term from its value (scikit-learn's `_loss_from_value`).
fn loss(value: f64, g: f64) -> f64 {
    g * value
}

/// `parent - child`, bin by bin, reusing the parent's histogram.
fn subtract(mut parent: Vec<Bin>, child: &[Bin]) -> Vec<Bin> {
    for (a, b) in parent.iter_mut().zip(child) {
        a.g -= b.g;
        a.n -= b.n;
    }
    parent
}

/// A node waiting in the frontier, ordered by gain, then by creation (smaller id first).
#[derive(Debug)]
struct Waiting(Grown);

impl Waiting {
    fn key(&self) -> f64 {
        self.0.split.map_or(f64::NEG_INFINITY, |s| s.gain)
    }
}

impl PartialEq for Waiting {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}

impl Eq for Waiting {}

impl PartialOrd for Waiting {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

impl Ord for Waiting {
    // the max-heap pops the largest gain first; among equal gains the node created first
    fn cmp(&self, o: &Self) -> Ordering {
        self.key().total_cmp(&o.key()).then(o.0.id.cmp(&self.0.id))
    }
}
