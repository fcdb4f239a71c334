//! The physics on a table: calibrated on the training rows (Levenberg-Marquardt over tied
//! leaves, standard errors), its values on every row, and the correction's target `delta`.

pub(crate) use super::model::deltas;
use super::model::{Combined, columns_of, finite_physics};
use super::resolve::Resolved;
use super::{CorrectionForm, TableConfig, calibrate};
use crate::HybridError;
use hxai_symreg::Table;
use hxai_symreg::fit::LmSettings;
use hxai_symreg::infix::Compiled;
use std::collections::BTreeMap;

/// Values of `col` at `rows`.
pub(crate) fn gather(col: &[f64], rows: &[usize]) -> Vec<f64> {
    rows.iter().map(|&i| col[i]).collect()
}

/// The physics calibrated on `rows`: parameters updated in `compiled`, standard errors.
pub(crate) fn calibrate_physics(
    table: &Table,
    cfg: &TableConfig,
    res: &Resolved,
    rows: &[usize],
) -> Result<(Compiled, BTreeMap<String, Option<f64>>), HybridError> {
    let mut phys = res.compiled.clone();
    let all = columns_of(table, &res.columns, "physics column")?;
    let cols: Vec<Vec<f64>> = all.iter().map(|c| gather(c, rows)).collect();
    let cols: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    let y = gather(table.require(&cfg.target)?, rows);
    // the start must be finite everywhere, or LM has nothing to descend from
    let start = phys.eval_columns(&cols, rows.len());
    if let Some((k, v)) = start.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(HybridError::BadPhysics {
            row: rows[k],
            value: *v,
            why: if res.calibrate.is_empty() {
                "not a finite number: check the equation's domain at this row".into()
            } else {
                "not a finite number at the starting parameter values: give better ones with --init"
                    .into()
            },
        });
    }
    let groups: Vec<Vec<usize>> = res
        .calibrate
        .iter()
        .map(|n| phys.slots.get(n).cloned().unwrap_or_default())
        .collect();
    let mut ses = BTreeMap::new();
    if !groups.is_empty() {
        calibrate::lm_tied(
            &phys.program,
            &mut phys.params,
            &groups,
            &cols,
            &y,
            &LmSettings {
                // a log correction needs the physics above zero on every row: a step of
                // an Arrhenius energy into the region where the law underflows to 0 is
                // refused
                keep_positive: cfg.correction == CorrectionForm::Log,
                ..calibrate::settings(500, 1e-15)
            },
        );
        let se = calibrate::standard_errors(&phys.program, &phys.params, &groups, &cols, &y);
        for (n, s) in res.calibrate.iter().zip(se) {
            ses.insert(n.clone(), s);
        }
    }
    Ok((phys, ses))
}

/// Physics values on every row, refusing a non-finite one (naming the row).
pub(crate) fn physics_values(
    table: &Table,
    res: &Resolved,
    phys: &Compiled,
) -> Result<Vec<f64>, HybridError> {
    finite_physics(table, phys, &res.columns)
}

pub(super) fn named_values(phys: &Compiled) -> BTreeMap<String, f64> {
    phys.slots
        .keys()
        .map(|n| (n.clone(), phys.get(n).unwrap_or(f64::NAN)))
        .collect()
}

/// For each calibrated physics parameter, the indices of its leaves among the parameters
/// of the combined hybrid program `c` (one unknown tied over every leaf that uses it).
pub(super) fn calibrated_slots(res: &Resolved, phys: &Compiled, c: &Combined) -> Vec<Vec<usize>> {
    res.calibrate
        .iter()
        .map(|n| {
            phys.slots
                .get(n)
                .map(|s| {
                    s.iter()
                        .filter_map(|i| c.phys_map.get(i).copied())
                        .collect()
                })
                .unwrap_or_default()
        })
        .collect()
}
