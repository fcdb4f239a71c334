//! Export: a fitted program over the search's columns becomes a [`Model`] that names only
//! the features it uses.
use crate::Table;
use crate::model::Model;
use crate::program::{Node, Program};
use std::collections::HashMap;

/// The model of `prog` with `params`, its inputs renumbered so that the model names only the
/// columns of `data` it uses (in increasing column order).
pub(crate) fn to_model(
    prog: &Program,
    params: Vec<f64>,
    mse: f64,
    score: f64,
    complexity: usize,
    data: &Table,
) -> Model {
    let used = prog.vars();
    let names: Vec<String> = used
        .iter()
        .map(|&j| data.names()[j as usize].clone())
        .collect();
    let map: HashMap<u16, u16> = used
        .iter()
        .enumerate()
        .map(|(i, &j)| (j, i as u16))
        .collect();
    let nodes = prog
        .nodes
        .iter()
        .map(|n| match n {
            Node::Var(j) => Node::Var(map.get(j).copied().unwrap_or(0)),
            other => *other,
        })
        .collect();
    Model {
        feature_names: names,
        program: Program {
            nodes,
            affine: prog.affine,
        },
        params,
        complexity,
        train_mse: mse,
        score,
    }
}
