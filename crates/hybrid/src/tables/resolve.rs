//! The physics equation and the feature columns resolved against a table: every name in
//! the equation a column or a parameter, the settings checked against the table.

use super::TableConfig;
use super::model::compile_physics;
use crate::HybridError;
use hxai_symreg::Table;
use hxai_symreg::infix::{Compiled, Parsed, parse};
use std::collections::BTreeMap;

/// The physics equation resolved against a table.
#[derive(Clone, Debug)]
pub(crate) struct Resolved {
    pub columns: Vec<String>,
    pub calibrate: Vec<String>,
    pub initial: BTreeMap<String, f64>,
    pub compiled: Compiled,
    pub features: Vec<String>,
}

/// The table's columns for a message: the first 12, then how many more (a wide table's
/// list would bury the message).
/// The table's columns for a message about the unknown name `name`: all of them when
/// there are few, else the three nearest to it by edit distance (issue 63: a typo among 40
/// long names listed all 40).
pub(super) fn nearest_columns(table: &Table, name: &str) -> String {
    const ALL_UP_TO: usize = 12;
    const NEAREST: usize = 3;
    let names = table.names();
    if names.len() <= ALL_UP_TO {
        return names.join(", ");
    }
    let mut by: Vec<(usize, &String)> = names.iter().map(|n| (edit_distance(n, name), n)).collect();
    by.sort();
    format!(
        "the nearest of {}: {}",
        names.len(),
        by.iter()
            .take(NEAREST)
            .map(|(_, n)| n.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    )
}

/// Levenshtein's edit distance between `a` and `b` (characters).
pub(super) fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(ca != *cb))
                .min(prev[j + 1] + 1)
                .min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

pub(super) fn cols_list(table: &Table) -> String {
    const SHOWN: usize = 12;
    let names = table.names();
    if names.len() <= SHOWN {
        return names.join(", ");
    }
    format!(
        "{}, and {} more",
        names[..SHOWN].join(", "),
        names.len() - SHOWN
    )
}

fn require_column(table: &Table, name: &str, what: &'static str) -> Result<(), HybridError> {
    if table.column(name).is_none() {
        return Err(HybridError::MissingColumn {
            what,
            name: name.to_string(),
            columns: cols_list(table),
        });
    }
    Ok(())
}

/// The largest target magnitude a fit accepts: its square (1e300) still fits in an `f64`
/// with room for sums of a million rows, where 1e300 itself overflows to infinity.
const HUGE_TARGET: f64 = 1e150;

/// Checks the configuration against the table: every name in the equation is a column or
/// a parameter, parameters are not columns and appear in the equation, the target is not
/// in the equation, at least one feature.
pub(crate) fn resolve(table: &Table, cfg: &TableConfig) -> Result<Resolved, HybridError> {
    require_column(table, &cfg.target, "target")?;
    if let Some(y) = table.column(&cfg.target) {
        // a value whose square overflows leaves every candidate without a finite loss, and
        // the search's own message ("no candidate model had a finite loss") names no row
        if let Some((row, v)) = y.iter().enumerate().find(|(_, v)| v.abs() > HUGE_TARGET) {
            return Err(HybridError::InvalidConfig(format!(
                "row {}: the target `{}` is {}, too large for squared errors (beyond +-1e150): \
                 is it a missing-value code or a unit mistake? Repair or remove the row",
                row + 1,
                cfg.target,
                crate::error::num(*v)
            )));
        }
    }
    if let Some(g) = &cfg.group {
        require_column(table, g, "group column")?;
        if *g == cfg.target {
            return Err(HybridError::InvalidConfig(format!(
                "the group column `{g}` is the target: a group keeps rows of one value (an \
                 insert, a batch) on one side of every split; name that column"
            )));
        }
    }
    if let Some(e) = &cfg.extrapolate {
        require_column(table, e, "extrapolation column")?;
    }
    let parsed: Parsed = parse(&cfg.physics).map_err(|source| HybridError::Equation {
        equation: cfg.physics.clone(),
        source,
    })?;
    let is_col = |n: &str| table.column(n).is_some();
    let named: [(&'static str, Vec<&String>); 3] = [
        ("calibrate", cfg.calibrate.iter().collect()),
        ("set", cfg.set.keys().collect()),
        ("init", cfg.init.keys().collect()),
    ];
    for (flag, names) in &named {
        for n in names {
            if is_col(n) {
                return Err(HybridError::ParameterIsColumn {
                    name: (*n).clone(),
                    flag,
                });
            }
            if parsed.position(n).is_none() {
                return Err(HybridError::ParameterNotInEquation {
                    name: (*n).clone(),
                    flag,
                    equation: cfg.physics.clone(),
                });
            }
        }
    }
    for (i, n) in cfg.calibrate.iter().enumerate() {
        if cfg.calibrate[..i].contains(n) {
            return Err(HybridError::InvalidConfig(format!(
                "parameter `{n}` is named twice in --calibrate: name each parameter once"
            )));
        }
        if cfg.set.contains_key(n) {
            return Err(HybridError::InvalidConfig(format!(
                "parameter `{n}` is both calibrated (--calibrate) and fixed (--set): choose one"
            )));
        }
    }
    for n in cfg.init.keys() {
        if !cfg.calibrate.contains(n) {
            return Err(HybridError::InvalidConfig(format!(
                "--init gives a starting value for `{n}`, which is not calibrated: add it to --calibrate or use --set"
            )));
        }
    }
    let mut columns = Vec::new();
    let mut values: BTreeMap<String, f64> = BTreeMap::new();
    for (name, position) in &parsed.positions {
        if *name == cfg.target {
            return Err(HybridError::TargetInPhysics {
                name: name.clone(),
                position: *position,
            });
        }
        if is_col(name) {
            columns.push(name.clone());
        } else if cfg.calibrate.contains(name) {
            values.insert(name.clone(), cfg.init.get(name).copied().unwrap_or(1.0));
        } else if let Some(v) = cfg.set.get(name) {
            values.insert(name.clone(), *v);
        } else {
            return Err(HybridError::UnknownName {
                name: name.clone(),
                position: *position,
                columns: nearest_columns(table, name),
            });
        }
    }
    for (n, v) in cfg.set.iter().chain(&cfg.init) {
        if !v.is_finite() {
            return Err(HybridError::InvalidConfig(format!(
                "parameter `{n}` = {v}: give a finite value"
            )));
        }
    }
    let initial: BTreeMap<String, f64> = cfg
        .calibrate
        .iter()
        .map(|n| (n.clone(), values.get(n).copied().unwrap_or(1.0)))
        .collect();
    let compiled = compile_physics(&cfg.physics, &columns, &values)?;
    let features = feature_columns(table, cfg)?;
    // `pi` in an equation is the constant, in the physics as in the printed hybrid (and in
    // sympy): a column of that name would be read as 3.14159 in the one and be ambiguous in
    // the other
    if table.column(PI).is_some() {
        let in_physics = uses_word(&cfg.physics, PI);
        if in_physics || features.iter().any(|f| f == PI) {
            return Err(HybridError::InvalidConfig(format!(
                "a column is named `pi`, which equations read as the constant 3.14159{}: \
                 rename the column{}",
                if in_physics {
                    " (as the physics does here)"
                } else {
                    ""
                },
                if in_physics {
                    ""
                } else {
                    " or leave it out with --exclude pi"
                }
            )));
        }
    }
    Ok(Resolved {
        columns,
        calibrate: cfg.calibrate.clone(),
        initial,
        compiled,
        features,
    })
}

/// The constant `pi`, the one name equations read as a number.
const PI: &str = "pi";

/// Whether `word` occurs in `text` as a name (not inside a longer name).
fn uses_word(text: &str, word: &str) -> bool {
    let is_name = |c: char| c.is_alphanumeric() || c == '_';
    text.match_indices(word).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + word.len()..].chars().next();
        !before.is_some_and(is_name) && !after.is_some_and(is_name)
    })
}

fn feature_columns(table: &Table, cfg: &TableConfig) -> Result<Vec<String>, HybridError> {
    let features: Vec<String> = match &cfg.features {
        Some(list) => {
            for f in list {
                require_column(table, f, "feature")?;
                if *f == cfg.target {
                    return Err(HybridError::NoFeatures(format!(
                        "the target `{f}` cannot be a feature of its own correction"
                    )));
                }
                if cfg.group.as_ref() == Some(f) {
                    return Err(HybridError::NoFeatures(format!(
                        "the group column `{f}` cannot be a feature"
                    )));
                }
            }
            list.clone()
        }
        None => {
            for e in &cfg.exclude {
                require_column(table, e, "excluded column")?;
            }
            table
                .names()
                .iter()
                .filter(|n| {
                    **n != cfg.target && cfg.group.as_ref() != Some(*n) && !cfg.exclude.contains(n)
                })
                .cloned()
                .collect()
        }
    };
    if features.is_empty() {
        return Err(HybridError::NoFeatures(format!(
            "no feature column is left for the correction (table columns: {}; target `{}`{}): \
             give --features or exclude fewer columns",
            cols_list(table),
            cfg.target,
            cfg.group
                .as_ref()
                .map(|g| format!(", group `{g}`"))
                .unwrap_or_default()
        )));
    }
    if let Some(p) = cfg.periodic.iter().find(|p| !features.contains(p)) {
        return Err(HybridError::InvalidConfig(format!(
            "--periodic {p}: `{p}` is not a feature of the correction (its features: {}); a \
             harmonic is a correction's repeating effect over one of its columns",
            features.join(", ")
        )));
    }
    if let Some(c) = cfg
        .increasing
        .iter()
        .chain(&cfg.decreasing)
        .find(|c| !features.contains(c))
    {
        return Err(HybridError::InvalidConfig(format!(
            "--monotone {c}: `{c}` is not a feature of the correction (its features: {}); \
             a monotone constraint bounds the correction's effect of one of its columns",
            features.join(", ")
        )));
    }
    Ok(features)
}
