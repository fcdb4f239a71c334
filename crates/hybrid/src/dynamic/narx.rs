//! The black-box peer of `hxai dynamic compare`: a NARX gradient boosting. One model per
//! state predicts the state's step `x[k+1] - x[k]` from the states `x[k]`, the inputs
//! `u[k]` (held over the step) and the step's length; a run is rolled out from its first
//! reading, each prediction fed back as the next step's state (a free run, like the ODEs).

use super::system::Run;
use crate::HybridError;
use hxai_baselines::{GradientBoosting, Regressor};
use hxai_symreg::Table;

/// One boosting per state.
pub(crate) struct Narx {
    models: Vec<GradientBoosting>,
    names: Vec<String>,
}

fn names(ns: usize, ni: usize) -> Vec<String> {
    let mut n: Vec<String> = (0..ns).map(|j| format!("x{j}")).collect();
    n.extend((0..ni).map(|i| format!("u{i}")));
    n.push("dt".into());
    n
}

impl Narx {
    /// Fits on every step of the training runs.
    ///
    /// # Errors
    /// The boosting's.
    pub(crate) fn fit(runs: &[Run], seed: u64) -> Result<Self, HybridError> {
        let ns = runs.first().map_or(0, |r| r.states.len());
        let ni = runs.first().map_or(0, |r| r.inputs.len());
        let names = names(ns, ni);
        let mut cols: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
        let mut steps: Vec<Vec<f64>> = vec![Vec::new(); ns];
        for run in runs {
            for k in 0..run.times.len() - 1 {
                for j in 0..ns {
                    cols[j].push(run.states[j][k]);
                    steps[j].push(run.states[j][k + 1] - run.states[j][k]);
                }
                for i in 0..ni {
                    cols[ns + i].push(run.inputs[i][k]);
                }
                cols[ns + ni].push(run.times[k + 1] - run.times[k]);
            }
        }
        let x = Table::new(names.clone(), cols)?;
        let mut models = Vec::with_capacity(ns);
        for y in &steps {
            let mut m = GradientBoosting::with_seed(seed);
            m.fit(&x, y)?;
            models.push(m);
        }
        Ok(Self { models, names })
    }

    /// Rolls `run` out from its first reading: the state at every sample (`[sample][state]`).
    ///
    /// # Errors
    /// The boosting's.
    pub(crate) fn roll_out(&self, run: &Run) -> Result<Vec<Vec<f64>>, HybridError> {
        let mut x = run.state_at(0);
        let mut out = vec![x.clone()];
        for k in 0..run.times.len() - 1 {
            let mut row: Vec<Vec<f64>> = x.iter().map(|v| vec![*v]).collect();
            row.extend(run.inputs.iter().map(|u| vec![u[k]]));
            row.push(vec![run.times[k + 1] - run.times[k]]);
            let t = Table::new(self.names.clone(), row)?;
            let mut next = x.clone();
            for (v, m) in next.iter_mut().zip(&self.models) {
                *v += m.predict(&t)?[0];
            }
            x = next;
            out.push(x.clone());
        }
        Ok(out)
    }
}
