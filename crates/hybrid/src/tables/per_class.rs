//! Per-class constants of the physics (`--calibrate-per COL=P1,P2`, issue 48): the named
//! parameters fitted once per level of a text column (Kienzle's `kc` per material, an
//! offset per machine, a line per insulation state).
//!
//! How: each level gets an indicator column (`COL=level`: 1 on its rows, 0 elsewhere), and
//! every occurrence of a per-class parameter `P` in the physics is written as
//! `` (`P[L1]`*`COL=L1` + `P[L2]`*`COL=L2` + ...) ``, one calibrated parameter per level.
//! The rest is the ordinary calibration: one Levenberg-Marquardt fit of every parameter
//! together on the training rows, standard errors from one Jacobian with the pooled
//! residual variance (so a linear physics gives exactly the least-squares fit of R's
//! `lm(y ~ COL/x)`, which `scripts/ref_per_class.py` checks on `MASS::whiteside`). The
//! model file's `physics.parameters` holds the `P[level]` keys, and `per_class` the column,
//! its levels and the parameters, so that `predict` builds the same indicators and refuses
//! a level it never saw, naming it.
//!
//! The indicator columns are never features of the correction: they are left out of its
//! search (`exclude`).
use super::TableConfig;
use crate::HybridError;
use hxai_symreg::Table;
use serde::{Deserialize, Serialize};

/// Which parameters are per class, of which column, over which levels (the model file's
/// `per_class`).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PerClassInfo {
    /// The text column whose levels the parameters differ by.
    pub column: String,
    /// Its levels, sorted (the order of the `P[level]` parameters).
    pub levels: Vec<String>,
    /// The physics parameters fitted per level.
    pub parameters: Vec<String>,
}

impl PerClassInfo {
    /// The indicator column of `level`.
    pub fn indicator(&self, level: &str) -> String {
        indicator_name(&self.column, level)
    }

    /// The parameter `p` at `level` (`p[level]`).
    pub fn parameter(p: &str, level: &str) -> String {
        format!("{p}[{level}]")
    }

    /// The indicator columns of every level, as [`Self::indicator`] names them.
    pub fn indicators(&self) -> Vec<String> {
        self.levels.iter().map(|l| self.indicator(l)).collect()
    }
}

/// The indicator column of `level` of `column` (`COL=level`: 1 on the level's rows, 0
/// elsewhere), for the physics' per-level parameters and the correction's alike.
pub(crate) fn indicator_name(column: &str, level: &str) -> String {
    format!("{column}={level}")
}

/// `level`'s indicator values over `cells`.
fn indicator_values(cells: &[String], level: &str) -> Vec<f64> {
    cells
        .iter()
        .map(|c| if c == level { 1.0 } else { 0.0 })
        .collect()
}

/// The sorted levels of `cells` (one per row of a table of `n_rows`) for a fit with
/// per-level constants given by `flag`; refused with one line naming it: cells of another
/// length, an empty level name (naming the row), a single level (then `one_level`).
/// The fewest rows a level may have for constants of its own (`--calibrate-per`,
/// `--correction-per`): with two, a stratified split keeps one for training whatever the test
/// fraction, and the fit has a residual to judge it by.
pub const MIN_LEVEL_ROWS: usize = 2;

pub(crate) fn levels_for_fit(
    flag: &str,
    column: &str,
    cells: &[String],
    n_rows: usize,
    one_level: &str,
) -> Result<Vec<String>, HybridError> {
    if cells.len() != n_rows {
        return Err(HybridError::InvalidConfig(format!(
            "{flag}: column `{column}` has {} cells for {n_rows} rows",
            cells.len()
        )));
    }
    if let Some(i) = cells.iter().position(|c| c.trim().is_empty()) {
        return Err(HybridError::InvalidConfig(format!(
            "{flag} {column}: row {} has an empty level name; fill it or drop the row",
            i + 1
        )));
    }
    let mut levels: Vec<String> = cells.to_vec();
    levels.sort();
    levels.dedup();
    if levels.len() < 2 {
        return Err(HybridError::InvalidConfig(format!(
            "{flag} {column}: the column has one level ({:?}), so per-level {one_level}",
            levels.first().map(String::as_str).unwrap_or("")
        )));
    }
    let few: Vec<String> = levels
        .iter()
        .filter_map(|l| {
            let n = cells.iter().filter(|c| *c == l).count();
            (n < MIN_LEVEL_ROWS).then(|| format!("{l:?} ({n} row)"))
        })
        .collect();
    if !few.is_empty() {
        return Err(HybridError::InvalidConfig(format!(
            "{flag} {column}: level(s) {} have fewer than {MIN_LEVEL_ROWS} rows, too few for \
             constants of their own that a split can test; merge each with another level or \
             drop its rows",
            few.join(", ")
        )));
    }
    Ok(levels)
}

/// For prediction with a model whose `what` (`physics`, `correction`) has constants per
/// level of `column`: refuses a cell that is empty or not one of `levels` (naming the row),
/// then appends to `table` the indicator columns it lacks.
///
/// # Errors
/// [`HybridError::InvalidConfig`] as described, or cells of another length.
pub(crate) fn add_level_indicators(
    column: &str,
    levels: &[String],
    what: &str,
    table: &mut Table,
    cells: &[String],
) -> Result<(), HybridError> {
    if cells.len() != table.n_rows() {
        return Err(HybridError::InvalidConfig(format!(
            "column `{column}` has {} cells for {} rows",
            cells.len(),
            table.n_rows()
        )));
    }
    for (i, c) in cells.iter().enumerate() {
        if c.trim().is_empty() {
            return Err(HybridError::InvalidConfig(format!(
                "row {} has an empty `{column}`: the model's {what} has constants per level of \
                 that column ({}), so every row needs one",
                i + 1,
                levels.join(", ")
            )));
        }
        if !levels.contains(c) {
            return Err(HybridError::InvalidConfig(format!(
                "row {} has `{column}` = {c:?}, a level the model was not fitted on (it knows \
                 {}): its {what} constants are unknown there",
                i + 1,
                levels.join(", ")
            )));
        }
    }
    push_missing_indicators(column, levels, table, cells)
}

/// Appends to `table` the indicator columns of `levels` of `column` it lacks.
pub(crate) fn push_missing_indicators(
    column: &str,
    levels: &[String],
    table: &mut Table,
    cells: &[String],
) -> Result<(), HybridError> {
    for level in levels {
        let name = indicator_name(column, level);
        if table.column(&name).is_none() {
            table
                .push_column(name, indicator_values(cells, level))
                .map_err(|e| HybridError::InvalidConfig(e.to_string()))?;
        }
    }
    Ok(())
}

/// Parses `COL=P1,P2` (the value of `--calibrate-per`) into the column and its parameters.
///
/// # Errors
/// [`HybridError::InvalidConfig`] without `=`, with an empty column or no parameter.
pub fn parse_spec(spec: &str) -> Result<(String, Vec<String>), HybridError> {
    let bad = |why: &str| {
        HybridError::InvalidConfig(format!(
            "--calibrate-per {spec:?}: {why}; write COLUMN=P1,P2 (the text column, then the \
             physics parameters fitted once per level of it)"
        ))
    };
    let (col, params) = spec.split_once('=').ok_or_else(|| bad("no `=`"))?;
    let col = col.trim().trim_matches('`').to_string();
    if col.is_empty() {
        return Err(bad("no column before `=`"));
    }
    let params: Vec<String> = params
        .split(',')
        .map(|p| p.trim().trim_matches('`').to_string())
        .collect();
    if params.iter().any(String::is_empty) {
        return Err(bad("an empty parameter name"));
    }
    let mut seen = params.clone();
    seen.sort();
    seen.dedup();
    if seen.len() != params.len() {
        return Err(bad("a parameter named twice"));
    }
    Ok((col, params))
}

/// Sets up per-class parameters for a fit: checks the levels of `cells` (the text column's
/// cells, one per row of `table`), appends one indicator column per level to `table`,
/// rewrites `cfg`'s physics with one parameter per level (each starting from the value
/// `--init` gave the shared one) and leaves the indicators out of the correction's
/// features. Returns the model file's `per_class`.
///
/// # Errors
/// [`HybridError::InvalidConfig`]: a column of another length, an empty level name (naming
/// the row), a single level, a parameter that is not in the physics, that is fixed by
/// `--set` or that is a column, or an indicator name that is already a column.
pub fn expand(
    cfg: &mut TableConfig,
    table: &mut Table,
    column: &str,
    cells: &[String],
    params: &[String],
) -> Result<PerClassInfo, HybridError> {
    let levels = levels_for_fit(
        "--calibrate-per",
        column,
        cells,
        table.n_rows(),
        "parameters are the shared ones; use --calibrate",
    )?;
    let (parsed, _) = hxai_symreg::infix::parse_with_slots(&cfg.physics).map_err(|source| {
        HybridError::Equation {
            equation: cfg.physics.clone(),
            source,
        }
    })?;
    for p in params {
        if parsed.position(p).is_none() {
            return Err(HybridError::ParameterNotInEquation {
                name: p.clone(),
                flag: "calibrate-per",
                equation: cfg.physics.clone(),
            });
        }
        if table.column(p).is_some() {
            return Err(HybridError::ParameterIsColumn {
                name: p.clone(),
                flag: "calibrate-per",
            });
        }
        if cfg.set.contains_key(p) {
            return Err(HybridError::InvalidConfig(format!(
                "parameter `{p}` is both fitted per level (--calibrate-per) and fixed (--set): \
                 choose one"
            )));
        }
    }
    let info = PerClassInfo {
        column: column.to_string(),
        levels,
        parameters: params.to_vec(),
    };
    for level in &info.levels {
        let name = info.indicator(level);
        if table.column(&name).is_some() {
            return Err(HybridError::InvalidConfig(format!(
                "--calibrate-per {column}: the table already has a column `{name}`, the name \
                 of the indicator of level {level:?}; rename that column"
            )));
        }
        table
            .push_column(name, indicator_values(cells, level))
            .map_err(|e| HybridError::InvalidConfig(e.to_string()))?;
    }
    cfg.physics = rewrite(&cfg.physics, &info);
    for p in params {
        let start = cfg.init.remove(p);
        cfg.calibrate.retain(|c| c != p);
        for level in &info.levels {
            let name = PerClassInfo::parameter(p, level);
            cfg.calibrate.push(name.clone());
            if let Some(v) = start {
                cfg.init.insert(name, v);
            }
        }
    }
    if cfg.features.is_none() {
        cfg.exclude.extend(info.indicators());
    }
    cfg.strata.extend(info.indicators());
    Ok(info)
}

/// Appends `info`'s indicator columns to `table` for prediction, from the text column's
/// `cells`.
///
/// # Errors
/// [`HybridError::InvalidConfig`] naming a level the model was not fitted on (and the
/// levels it knows), an empty level name, or cells of another length.
pub fn add_indicators(
    info: &PerClassInfo,
    table: &mut Table,
    cells: &[String],
) -> Result<(), HybridError> {
    add_level_indicators(&info.column, &info.levels, "physics", table, cells)
}

/// The physics with every per-class parameter `P` (a bare name or backquoted) replaced by
/// `` (`P[L1]`*`COL=L1` + ...) ``.
fn rewrite(physics: &str, info: &PerClassInfo) -> String {
    let expansion = |p: &str| {
        let terms: Vec<String> = info
            .levels
            .iter()
            .map(|l| {
                format!(
                    "`{}`*`{}`",
                    PerClassInfo::parameter(p, l),
                    info.indicator(l)
                )
            })
            .collect();
        format!("({})", terms.join(" + "))
    };
    let chars: Vec<char> = physics.chars().collect();
    let mut out = String::new();
    let mut i = 0;
    let is_start = |c: char| c.is_alphabetic() || c == '_';
    let is_name = |c: char| c.is_alphanumeric() || c == '_';
    while i < chars.len() {
        let c = chars[i];
        if c == '`' {
            let end = chars[i + 1..]
                .iter()
                .position(|&d| d == '`')
                .map_or(chars.len(), |k| i + 1 + k);
            let inner: String = chars[i + 1..end.min(chars.len())].iter().collect();
            if info.parameters.contains(&inner) {
                out.push_str(&expansion(&inner));
            } else {
                out.extend(&chars[i..(end + 1).min(chars.len())]);
            }
            i = end + 1;
        } else if is_start(c) && (i == 0 || !is_name(chars[i - 1])) {
            let mut j = i;
            while j < chars.len() && is_name(chars[j]) {
                j += 1;
            }
            let word: String = chars[i..j].iter().collect();
            if info.parameters.contains(&word) {
                out.push_str(&expansion(&word));
            } else {
                out.push_str(&word);
            }
            i = j;
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// The cells of `col` as level names: a text column's cells in `text` (trimmed), or a
/// numeric column of `table` (its numbers as written); where neither has it, `Err` with
/// the columns there are, comma-separated.
pub(crate) fn level_cells(
    table: &Table,
    text: &[(String, Vec<String>)],
    col: &str,
) -> Result<Vec<String>, String> {
    if let Some((_, cells)) = text.iter().find(|(n, _)| n == col) {
        return Ok(cells.iter().map(|c| c.trim().to_string()).collect());
    }
    match table.column(col) {
        Some(v) => Ok(v.iter().map(|x| x.to_string()).collect()),
        None => Err(table
            .names()
            .iter()
            .chain(text.iter().map(|(n, _)| n))
            .cloned()
            .collect::<Vec<_>>()
            .join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info() -> PerClassInfo {
        PerClassInfo {
            column: "insul".into(),
            levels: vec!["After".into(), "Before".into()],
            parameters: vec!["a".into(), "b".into()],
        }
    }

    #[test]
    fn the_physics_is_rewritten_per_level_and_nothing_else() {
        let r = rewrite("a + b*temp + ab*`a` + 1e-3*b2", &info());
        assert_eq!(
            r,
            "(`a[After]`*`insul=After` + `a[Before]`*`insul=Before`) + \
             (`b[After]`*`insul=After` + `b[Before]`*`insul=Before`)*temp + \
             ab*(`a[After]`*`insul=After` + `a[Before]`*`insul=Before`) + 1e-3*b2"
        );
        assert!(hxai_symreg::infix::parse(&r).is_ok());
    }

    #[test]
    fn specs_are_parsed_and_bad_ones_refused() {
        assert_eq!(
            parse_spec("insul=a, b").expect("ok"),
            ("insul".to_string(), vec!["a".to_string(), "b".to_string()])
        );
        for bad in ["insul", "=a", "insul=", "insul=a,,b", "insul=a,a"] {
            let e = parse_spec(bad).expect_err("refused").to_string();
            assert!(e.contains("--calibrate-per"), "{e}");
        }
    }

    #[test]
    fn an_unseen_or_empty_level_is_refused_by_name() {
        let mut t = Table::new(vec!["temp".into()], vec![vec![1.0, 2.0]]).expect("ok");
        let e = add_indicators(&info(), &mut t, &["Before".into(), "Later".into()])
            .expect_err("refused")
            .to_string();
        assert!(e.contains("\"Later\"") && e.contains("row 2"), "{e}");
        let e = add_indicators(&info(), &mut t, &["".into(), "After".into()])
            .expect_err("refused")
            .to_string();
        assert!(e.contains("row 1") && e.contains("empty"), "{e}");
        assert_eq!(t.n_cols(), 1, "nothing added on a refusal");
        add_indicators(&info(), &mut t, &["Before".into(), "After".into()]).expect("ok");
        assert_eq!(t.column("insul=After").expect("ok"), [0.0, 1.0]);
        assert_eq!(t.column("insul=Before").expect("ok"), [1.0, 0.0]);
    }
}
