//! Postfix programs: the compact form every candidate expression takes during search.
//!
//! A program is a postfix (reverse Polish) sequence of [`Node`]s. Parameters are not stored
//! in the nodes but in a separate `Vec<f64>` laid out as
//! `[output scale, output offset, then each node's own parameters in node order]`:
//! an input under affine scaling owns `(w, b)` (it enters as `w * x + b`), a constant owns one
//! value, operators own none. The output of every program is `scale * root + offset`, as in
//! QLattice, so a model never needs a separate constant for its scale.
use crate::ops::{Op, OpCosts};
use serde::{Deserialize, Serialize};

/// One postfix code.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Node {
    /// An input column, by index into the feature list of its program's owner.
    Var(u16),
    /// A fitted constant.
    Const,
    /// An operator applied to the top one or two values of the stack.
    Op(Op),
}

/// How complexity is counted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ComplexityMeasure {
    /// The paper's count: input leaves + operators; constants and affine scalings are free.
    #[default]
    FeaturesPlusOperators,
    /// Number of edges of the expression tree including the edge to the output: one per
    /// node, constants included.
    Edges,
}

/// A postfix program and whether its inputs carry affine scalings.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Program {
    /// Postfix codes; the last one is the root.
    pub nodes: Vec<Node>,
    /// Inputs enter as `w * x + b` when true, as `x` when false.
    pub affine: bool,
}

impl Program {
    /// Number of parameters (output scale and offset included).
    pub fn n_params(&self) -> usize {
        2 + self
            .nodes
            .iter()
            .map(|n| self.node_params(n))
            .sum::<usize>()
    }

    /// Parameters owned by one node.
    pub fn node_params(&self, n: &Node) -> usize {
        match n {
            Node::Var(_) => {
                if self.affine {
                    2
                } else {
                    0
                }
            }
            Node::Const => 1,
            Node::Op(_) => 0,
        }
    }

    /// Index of each node's first parameter (only meaningful for nodes that own some).
    pub fn param_offsets(&self) -> Vec<usize> {
        let mut off = Vec::with_capacity(self.nodes.len());
        let mut p = 2;
        for n in &self.nodes {
            off.push(p);
            p += self.node_params(n);
        }
        off
    }

    /// Whether the sequence is a well-formed single expression.
    pub fn is_valid(&self) -> bool {
        let mut depth: usize = 0;
        for n in &self.nodes {
            match n {
                Node::Var(_) | Node::Const => depth += 1,
                Node::Op(op) => {
                    let a = op.arity();
                    if depth < a {
                        return false;
                    }
                    depth = depth - a + 1;
                }
            }
        }
        depth == 1
    }

    /// Complexity under the given measure, every operator counting 1.
    pub fn complexity(&self, measure: ComplexityMeasure) -> usize {
        self.complexity_with(measure, &OpCosts::default())
    }

    /// Complexity under the given measure with each operator counting its cost in `costs`
    /// (inputs count 1, constants 1 under [`ComplexityMeasure::Edges`] and 0 otherwise).
    pub fn complexity_with(&self, measure: ComplexityMeasure, costs: &OpCosts) -> usize {
        self.nodes
            .iter()
            .map(|n| match n {
                Node::Var(_) => 1,
                Node::Const => usize::from(measure == ComplexityMeasure::Edges),
                Node::Op(op) => costs.of(*op),
            })
            .sum()
    }

    /// For each node the indices of its children (`usize::MAX` where absent).
    pub fn children(&self) -> Vec<[usize; 2]> {
        let mut stack: Vec<usize> = Vec::with_capacity(self.nodes.len());
        let mut ch = Vec::with_capacity(self.nodes.len());
        for (i, n) in self.nodes.iter().enumerate() {
            match n {
                Node::Op(op) if op.arity() == 2 => {
                    let b = stack.pop().unwrap_or(usize::MAX);
                    let a = stack.pop().unwrap_or(usize::MAX);
                    ch.push([a, b]);
                }
                Node::Op(_) => {
                    let a = stack.pop().unwrap_or(usize::MAX);
                    ch.push([a, usize::MAX]);
                }
                _ => ch.push([usize::MAX, usize::MAX]),
            }
            stack.push(i);
        }
        ch
    }

    /// Index of the first node of the subtree that ends (has its root) at `end`.
    pub fn subtree_start(&self, end: usize) -> usize {
        let mut need: usize = 1;
        let mut i = end;
        loop {
            need -= 1;
            if let Node::Op(op) = self.nodes[i] {
                need += op.arity();
            }
            if need == 0 || i == 0 {
                return i;
            }
            i -= 1;
        }
    }

    /// Distinct input indices used, sorted.
    pub fn vars(&self) -> Vec<u16> {
        let mut v: Vec<u16> = self
            .nodes
            .iter()
            .filter_map(|n| if let Node::Var(j) = n { Some(*j) } else { None })
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Depth of the tree (a single leaf has depth 1).
    pub fn depth(&self) -> usize {
        let mut stack: Vec<usize> = Vec::new();
        for n in &self.nodes {
            match n {
                Node::Op(op) => {
                    let mut d = 0;
                    for _ in 0..op.arity() {
                        d = d.max(stack.pop().unwrap_or(0));
                    }
                    stack.push(d + 1);
                }
                _ => stack.push(1),
            }
        }
        stack.pop().unwrap_or(0)
    }
}

/// Pushes `w * top + b` onto the program, leaving out a unit weight and a zero offset.
pub(crate) fn affine(w: f64, b: f64, nodes: &mut Vec<Node>, params: &mut Vec<f64>) {
    if w != 1.0 {
        nodes.push(Node::Const);
        params.push(w);
        nodes.push(Node::Op(Op::Mul));
    }
    if b != 0.0 {
        nodes.push(Node::Const);
        params.push(b);
        nodes.push(Node::Op(Op::Add));
    }
}
