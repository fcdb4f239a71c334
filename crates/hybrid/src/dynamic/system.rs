//! The system the integrator runs: the compiled physics of every state plus its learned
//! correction (added, or multiplying `1 + c`), and the runs' data it is simulated on.

use super::spec::{OdeSpec, eval_point, feature_map};
use crate::HybridError;
use crate::tables::CorrectionForm;
use hxai_sim::ode::{OdeError, OdeSettings, integrate};
use hxai_symreg::{Model, Table};

/// One state's learned correction, where its features sit among the variables, and their
/// training ranges: outside them the correction is held at its value on the range's edge
/// (the physics extrapolates, the learned term is not trusted beyond the data).
#[derive(Clone, Debug)]
pub(crate) struct Correction {
    pub(crate) model: Model,
    pub(crate) map: Vec<usize>,
    /// `[low, high]` of each feature; empty: no clamping.
    pub(crate) ranges: Vec<[f64; 2]>,
}

/// The physics with its corrections, ready to integrate.
#[derive(Clone, Debug)]
pub(crate) struct System {
    pub(crate) spec: OdeSpec,
    pub(crate) link: CorrectionForm,
    /// One per state; `None` where no correction is learned.
    pub(crate) corrections: Vec<Option<Correction>>,
}

/// A constant the calibration may move: a named physics parameter, or constant `index` of
/// state `state`'s correction.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Unknown {
    Physics(String),
    Correction { state: usize, index: usize },
}

impl Unknown {
    /// How a message names it: the parameter's name, or `constant 3 of T's correction`.
    pub(crate) fn label(&self, states: &[String]) -> String {
        match self {
            Unknown::Physics(n) => n.clone(),
            Unknown::Correction { state, index } => format!(
                "constant {index} of {}'s correction",
                states.get(*state).map_or("?", String::as_str)
            ),
        }
    }
}

impl System {
    /// The physics alone.
    pub(crate) fn physics(spec: OdeSpec, link: CorrectionForm) -> Self {
        let n = spec.equations.len();
        Self {
            spec,
            link,
            corrections: vec![None; n],
        }
    }

    /// Sets state `state`'s correction.
    ///
    /// # Errors
    /// A feature of the model that is not a variable of the system.
    pub(crate) fn set_correction(
        &mut self,
        state: usize,
        model: Option<Model>,
        ranges: Vec<[f64; 2]>,
    ) -> Result<(), HybridError> {
        self.corrections[state] = match model {
            Some(model) => {
                let map = feature_map(&model, &self.spec.variables)?;
                Some(Correction { model, map, ranges })
            }
            None => None,
        };
        Ok(())
    }

    pub(crate) fn n_states(&self) -> usize {
        self.spec.equations.len()
    }

    /// Writes the physics' groupings (`T - Ta`) into `vars` after the base variables.
    pub(crate) fn fill_groupings(&self, vars: &mut [f64], all: &[usize], stack: &mut Vec<f64>) {
        let nb = self.spec.n_base;
        for (i, g) in self.spec.groupings.iter().enumerate() {
            vars[nb + i] = eval_point(
                &g.compiled.program,
                &g.compiled.params,
                &vars[..nb],
                &all[..nb],
                stack,
            );
        }
    }

    /// The physics' derivative of every state at `vars` (states, inputs, time) into `phys`.
    pub(crate) fn physics_at(&self, vars: &[f64], phys: &mut [f64], stack: &mut Vec<f64>) {
        let all: Vec<usize> = (0..vars.len()).collect();
        for (j, e) in self.spec.equations.iter().enumerate() {
            phys[j] = eval_point(&e.compiled.program, &e.compiled.params, vars, &all, stack);
        }
    }

    /// The hybrid's derivative of every state at `vars` into `dy` (`buf`: scratch for the
    /// clamped features).
    pub(crate) fn rhs(
        &self,
        vars: &[f64],
        dy: &mut [f64],
        all: &[usize],
        stack: &mut Vec<f64>,
        buf: &mut Vec<f64>,
    ) {
        for (j, e) in self.spec.equations.iter().enumerate() {
            let p = eval_point(&e.compiled.program, &e.compiled.params, vars, all, stack);
            dy[j] = match &self.corrections[j] {
                None => p,
                Some(c) => {
                    buf.clear();
                    buf.extend(
                        c.map
                            .iter()
                            .enumerate()
                            .map(|(i, &m)| match c.ranges.get(i) {
                                Some([lo, hi]) => vars[m].clamp(*lo, *hi),
                                None => vars[m],
                            }),
                    );
                    let v = eval_point(
                        &c.model.program,
                        &c.model.params,
                        buf,
                        &all[..buf.len()],
                        stack,
                    );
                    match self.link {
                        CorrectionForm::Multiplicative => p * (1.0 + v),
                        CorrectionForm::Log => p * v.exp(),
                        CorrectionForm::Additive => p + v,
                    }
                }
            };
        }
    }

    /// The constants a joint calibration moves: the named physics parameters `calibrate`,
    /// then (with `corrections`) every constant of every correction.
    pub(crate) fn unknowns(&self, calibrate: &[String], corrections: bool) -> Vec<Unknown> {
        let mut u: Vec<Unknown> = calibrate.iter().cloned().map(Unknown::Physics).collect();
        if corrections {
            for (state, c) in self.corrections.iter().enumerate() {
                if let Some(c) = c {
                    u.extend(
                        (0..c.model.params.len()).map(|index| Unknown::Correction { state, index }),
                    );
                }
            }
        }
        u
    }

    pub(crate) fn get(&self, u: &Unknown) -> f64 {
        match u {
            Unknown::Physics(n) => self.spec.parameters.get(n).copied().unwrap_or(f64::NAN),
            Unknown::Correction { state, index } => self.corrections[*state]
                .as_ref()
                .map_or(f64::NAN, |c| c.model.params[*index]),
        }
    }

    pub(crate) fn set(&mut self, u: &Unknown, v: f64) {
        match u {
            Unknown::Physics(n) => self.spec.set(n, v),
            Unknown::Correction { state, index } => {
                if let Some(c) = self.corrections[*state].as_mut() {
                    c.model.params[*index] = v;
                }
            }
        }
    }

    /// Simulates `run` from the state `y0` at its first sample, its inputs held from each
    /// sample to the next: the state at every sample (`[sample][state]`).
    ///
    /// # Errors
    /// The integrator's ([`OdeError`]): a blow-up, a stiff system, too many steps.
    pub(crate) fn simulate(
        &self,
        run: &Run,
        y0: &[f64],
        s: &OdeSettings,
    ) -> Result<Vec<Vec<f64>>, OdeError> {
        let ns = self.n_states();
        let ni = run.inputs.len();
        let nv = self.spec.variables.len();
        let all: Vec<usize> = (0..nv).collect();
        let ti = self.spec.time_index();
        let mut vars = vec![0.0; nv];
        let mut stack = Vec::with_capacity(32);
        let mut buf = Vec::with_capacity(nv);
        let mut y = y0.to_vec();
        let mut out = Vec::with_capacity(run.times.len());
        out.push(y.clone());
        for k in 0..run.times.len().saturating_sub(1) {
            for i in 0..ni {
                vars[ns + i] = run.inputs[i][k];
            }
            let mut f = |t: f64, yy: &[f64], dy: &mut [f64]| {
                vars[..ns].copy_from_slice(yy);
                vars[ti] = t;
                self.fill_groupings(&mut vars, &all, &mut stack);
                self.rhs(&vars, dy, &all, &mut stack, &mut buf);
            };
            let next = integrate(&mut f, run.times[k], &y, &[run.times[k + 1]], s)?;
            y.clone_from(&next[0]);
            out.push(y.clone());
        }
        Ok(out)
    }
}

/// One run of a long table: its samples' times, states and inputs, in time order.
#[derive(Clone, Debug)]
pub(crate) struct Run {
    /// The run column's value (1.0 for a table without one).
    pub(crate) id: f64,
    /// Row indices in the table, in time order.
    pub(crate) rows: Vec<usize>,
    pub(crate) times: Vec<f64>,
    /// `[state][sample]`.
    pub(crate) states: Vec<Vec<f64>>,
    /// `[input][sample]`.
    pub(crate) inputs: Vec<Vec<f64>>,
}

impl Run {
    /// The measured state at sample `k`.
    pub(crate) fn state_at(&self, k: usize) -> Vec<f64> {
        self.states.iter().map(|s| s[k]).collect()
    }

    /// The run keeping only the samples at or before `t` (at least the first).
    pub(crate) fn until(&self, t: f64) -> Run {
        let n = self.times.iter().filter(|&&x| x <= t).count().max(1);
        Run {
            id: self.id,
            rows: self.rows[..n].to_vec(),
            times: self.times[..n].to_vec(),
            states: self.states.iter().map(|s| s[..n].to_vec()).collect(),
            inputs: self.inputs.iter().map(|s| s[..n].to_vec()).collect(),
        }
    }
}

/// The runs of `table` (in order of first appearance of the run value; one run without a
/// run column), each sorted by time.
///
/// # Errors
/// A missing column; a run whose times repeat; a run of fewer than 3 samples.
pub(crate) fn runs_of(
    table: &Table,
    time: &str,
    run: Option<&str>,
    states: &[String],
    inputs: &[String],
) -> Result<Vec<Run>, HybridError> {
    let col = |name: &str, what: &'static str| {
        table
            .column(name)
            .ok_or_else(|| HybridError::MissingColumn {
                what,
                name: name.to_string(),
                columns: table.names().join(", "),
            })
    };
    let t = col(time, "time (--time)")?;
    let ids: Vec<f64> = match run {
        Some(r) => col(r, "run (--run)")?.to_vec(),
        None => vec![1.0; table.n_rows()],
    };
    let sc: Vec<&[f64]> = states
        .iter()
        .map(|s| col(s, "state (--state)"))
        .collect::<Result<_, _>>()?;
    let ic: Vec<&[f64]> = inputs
        .iter()
        .map(|s| col(s, "input (--inputs)"))
        .collect::<Result<_, _>>()?;
    let mut order: Vec<f64> = Vec::new();
    let mut members: Vec<Vec<usize>> = Vec::new();
    for (i, &id) in ids.iter().enumerate() {
        match order.iter().position(|&o| o == id) {
            Some(j) => members[j].push(i),
            None => {
                order.push(id);
                members.push(vec![i]);
            }
        }
    }
    let mut out = Vec::with_capacity(order.len());
    for (id, mut rows) in order.into_iter().zip(members) {
        rows.sort_by(|&a, &b| t[a].total_cmp(&t[b]).then(a.cmp(&b)));
        if let Some(w) = rows.windows(2).find(|w| t[w[0]] == t[w[1]]) {
            return Err(HybridError::InvalidConfig(format!(
                "run {id}: two samples at time {} (rows {} and {}); one sample per time in a run \
                 (is --run the right column?)",
                t[w[0]],
                w[0] + 1,
                w[1] + 1
            )));
        }
        if rows.len() < 3 {
            return Err(HybridError::NoData(format!(
                "run {id} has {} sample(s); a run needs at least 3",
                rows.len()
            )));
        }
        out.push(Run {
            id,
            times: rows.iter().map(|&i| t[i]).collect(),
            states: sc
                .iter()
                .map(|c| rows.iter().map(|&i| c[i]).collect())
                .collect(),
            inputs: ic
                .iter()
                .map(|c| rows.iter().map(|&i| c[i]).collect())
                .collect(),
            rows,
        });
    }
    Ok(out)
}
