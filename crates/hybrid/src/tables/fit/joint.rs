//! The joint refit (`--joint`): the physics' parameters and the correction's constants
//! fitted together once the correction's structure is chosen.

use super::super::calibrate;
use super::super::model::{JointInfo, columns_of, combine};
use super::super::physics::{calibrated_slots, gather, named_values, physics_values};
use super::super::resolve::Resolved;
use super::assemble::train_rmse;
use super::job::SplitJob;
use crate::HybridError;
use hxai_symreg::infix::Compiled;
use std::collections::BTreeMap;

/// The joint refit: physics parameters and the correction's fitted constants together on the
/// training rows, kept only when it does not raise the training RMSE; updates `phys`,
/// `correction` and `ses` then, and returns the record of both fits.
pub(super) fn joint_refit(
    job: SplitJob,
    res: &Resolved,
    phys: &mut Compiled,
    correction: &mut hxai_symreg::Model,
    ses: &mut BTreeMap<String, Option<f64>>,
    y_train: &[f64],
) -> Result<JointInfo, HybridError> {
    let (table, cfg, split) = (job.table, job.cfg, job.split);
    let rmse_on_train = |phys: &Compiled, correction: &hxai_symreg::Model| {
        train_rmse(table, res, phys, correction, cfg.correction, split, y_train)
    };
    let before = rmse_on_train(phys, correction)?;
    let sequential_parameters = named_values(phys);
    let sequential_standard_errors = ses.clone();
    let sequential_correction = correction.sympy();
    let mut c = combine(phys, correction, cfg.correction);
    // physics unknowns (tied leaves), then each fitted correction constant; constants
    // the search snapped to exact values (integers, halves) stay fixed
    let mut groups = calibrated_slots(res, phys, &c);
    let n_phys = groups.len();
    for (i, &ci) in c.corr_map.iter().enumerate() {
        let v = correction.params[i];
        if (2.0 * v).fract() != 0.0 {
            groups.push(vec![ci]);
        }
    }
    let all = columns_of(table, &c.names, "column")?;
    let cols: Vec<Vec<f64>> = all.iter().map(|col| gather(col, &split.train)).collect();
    let cols: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    let mut trial = c.params.clone();
    let mse = calibrate::lm_tied(
        &c.program,
        &mut trial,
        &groups,
        &cols,
        y_train,
        &calibrate::settings(200, 1e-15),
    );
    if mse.is_finite() && mse.sqrt() <= before {
        let se = calibrate::standard_errors(&c.program, &trial, &groups, &cols, y_train);
        c.params = trial;
        for (&pi, &ci) in &c.phys_map {
            phys.params[pi] = c.params[ci];
        }
        for (i, &ci) in c.corr_map.iter().enumerate() {
            correction.params[i] = c.params[ci];
        }
        *ses = res
            .calibrate
            .iter()
            .cloned()
            .zip(se.into_iter().take(n_phys))
            .collect();
        // the physics must still be usable everywhere
        physics_values(table, res, phys)?;
    }
    let after = rmse_on_train(phys, correction)?;
    Ok(JointInfo {
        sequential_parameters,
        sequential_standard_errors,
        sequential_correction,
        sequential_train_rmse: before,
        joint_train_rmse: after,
    })
}
