//! Uncertainty of fitted constants and of predictions.
//!
//! A least-squares fit `y_i = f(x_i; theta) + e_i` with `k` unknowns on `n` rows has, at its
//! optimum, the asymptotic covariance `s^2 (J^T J)^-1`, where `J` is the `n x k` Jacobian of
//! the predictions with respect to the unknowns and `s^2 = SSE / (n - k)` the residual
//! variance ([`covariance`]; `scipy.optimize.curve_fit`'s `pcov` with `absolute_sigma =
//! False`). Standard errors are the square roots of its diagonal; the 95 % intervals are
//! `theta_j +- t_{n-k, 0.975} se_j` (Student's t with `n - k` degrees of freedom). A
//! prediction at new inputs `x` gets the interval `f(x) +- t_{n-k, (1+P)/2} sqrt(s^2 +
//! g^T C g)` with `g` the gradient of `f(x)` with respect to the unknowns (the delta method).
//!
//! What is assumed: independent residuals of constant variance (Gaussian for the
//! t quantiles to be exact), a model that is smooth near the optimum, and a fixed
//! structure: the uncertainty of having *chosen* the structure among many is not in these
//! numbers (`--stability` addresses that).
//!
//! Snapped constants. The search snaps constants to simple values ([`crate::Model`]):
//! to exact values (0, +-1, whole and half numbers), which are then no longer fitted, or to
//! 1-3 significant digits, which are still fitted values, only rounded. The template keeps
//! exact values as literals and names every other constant `p0`, `p1`, ... (in parameter
//! order, skipping names that are columns). Those free constants are refitted with the
//! exact ones held, and the covariance is taken at that optimum: `fitted` is the optimum,
//! `value` the constant as the equation prints it (so the template with the values
//! substituted is the model's `sympy` form), and `ci95` is centred on `fitted`. A constant
//! counts as exact when it is a whole or half number, the values snapping fixes; the joint
//! refit of `hxai hybrid` uses the same rule.
//!
//! Singular or ill-conditioned `J^T J` (a constant the data do not determine, such as a
//! factor that trades off against another): standard errors and intervals are `None`
//! (JSON `null`) and `reason` says why; the covariance stored for prediction intervals is
//! then the pseudo-inverse, which is still right for predictions (they depend only on the
//! identifiable combinations). No `NaN` is ever written.
use crate::eval::{Evaluator, Inputs};
use crate::expr::Expr;
use crate::fit::{LmSettings, Unknowns, levenberg_marquardt};
pub use crate::model::is_exact;
use crate::program::Program;
use crate::{Model, SrError, Table};
use serde::{Deserialize, Serialize};

/// Eigenvalues of the scaled normal matrix (unit diagonal) below this fraction of the
/// largest count as zero: a condition number above `1e12` leaves at most 4 significant
/// digits in a standard error computed in `f64`, so such errors are not reported.
pub(crate) const SINGULAR_RCOND: f64 = 1e-12;

/// Levenberg-Marquardt settings of the refit of the free constants before the covariance:
/// converged to the limit of `f64`, since the covariance is taken at the optimum.
const REFIT_MAX_ITER: usize = 200;
const REFIT_TOL: f64 = 1e-15;

/// Jacobi sweeps of the symmetric eigen-decomposition; it converges quadratically, a dozen
/// sweeps suffice for the matrices here (at most a few dozen unknowns).
const JACOBI_SWEEPS: usize = 60;

/// The covariance of fitted unknowns at an optimum.
#[derive(Clone, Debug, PartialEq)]
pub struct Covariance {
    /// Rows of the fit.
    pub n_rows: usize,
    /// Residual degrees of freedom `n - k`.
    pub dof: usize,
    /// `s^2 = SSE / (n - k)` (the mean squared error when `n <= k`).
    pub residual_variance: f64,
    /// `s^2 (J^T J)^-1`, `k x k` row-major; the pseudo-inverse where `J^T J` is singular;
    /// empty when the Jacobian is not finite.
    pub matrix: Vec<f64>,
    /// Why standard errors are not reported (`None` when they are).
    pub reason: Option<String>,
}

impl Covariance {
    /// Number of unknowns.
    pub fn len(&self) -> usize {
        (self.matrix.len() as f64).sqrt().round() as usize
    }

    /// True when there is no matrix.
    pub fn is_empty(&self) -> bool {
        self.matrix.is_empty()
    }

    /// Standard error of unknown `i` (`None` where [`Covariance::reason`] is set).
    pub fn std_error(&self, i: usize) -> Option<f64> {
        if self.reason.is_some() {
            return None;
        }
        let k = self.len();
        let v = *self.matrix.get(i * k + i)?;
        (v.is_finite() && v >= 0.0).then(|| v.sqrt())
    }
}

/// `s^2 (J^T J)^-1` of `unknowns` at `params` on the rows `cols`, `y` (see the module docs).
pub fn covariance(
    prog: &Program,
    params: &[f64],
    unknowns: Unknowns,
    cols: &[&[f64]],
    y: &[f64],
) -> Covariance {
    let k = unknowns.len();
    let n = y.len();
    let mut ev = Evaluator::new(prog);
    let mut jtj = vec![0.0; k * k];
    let mut jtr = vec![0.0; k];
    let inp = Inputs { prog, params, cols };
    let mse = unknowns.normal_equations(&mut ev, inp, y, &mut jtj, &mut jtr);
    let dof = n.saturating_sub(k);
    let plain_mse = ev.mse(prog, params, cols, y);
    let mut out = Covariance {
        n_rows: n,
        dof,
        residual_variance: if dof > 0 {
            plain_mse * n as f64 / dof as f64
        } else {
            plain_mse
        },
        matrix: Vec::new(),
        reason: None,
    };
    if !mse.is_finite() || !plain_mse.is_finite() {
        out.reason = Some(
            "the model or its Jacobian is not finite on the data, so no covariance exists".into(),
        );
        return out;
    }
    if k == 0 {
        return out;
    }
    // the lower triangle is filled in both cases; mirror it
    for i in 0..k {
        for j in i + 1..k {
            jtj[i * k + j] = jtj[j * k + i];
        }
    }
    let (inv, reason) = pseudo_inverse(&jtj, k);
    out.matrix = inv.iter().map(|v| v * out.residual_variance).collect();
    out.reason = reason;
    if dof == 0 {
        out.reason = Some(format!(
            "{n} rows for {k} fitted constants leave no residual degrees of freedom"
        ));
    }
    out
}

/// Inverse of the symmetric positive semi-definite `a` (`k x k`), or its pseudo-inverse with
/// the reason it is not invertible. Works on `D a D` with `D = diag(a)^-1/2` (unit diagonal,
/// so the condition number measures how far the unknowns are from redundant, not their
/// units), decomposed by cyclic Jacobi rotations.
fn pseudo_inverse(a: &[f64], k: usize) -> (Vec<f64>, Option<String>) {
    let mut reason = None;
    let d: Vec<f64> = (0..k)
        .map(|i| {
            let v = a[i * k + i];
            if v > 0.0 && v.is_finite() {
                1.0 / v.sqrt()
            } else {
                0.0
            }
        })
        .collect();
    if let Some(i) = d.iter().position(|&v| v == 0.0) {
        reason = Some(format!(
            "constant {i} of the template does not change the prediction on these rows, so \
             the data do not determine it"
        ));
    }
    let mut s: Vec<f64> = (0..k * k).map(|ij| a[ij] * d[ij / k] * d[ij % k]).collect();
    let mut v = vec![0.0; k * k];
    for i in 0..k {
        v[i * k + i] = 1.0;
    }
    jacobi_eigen(&mut s, &mut v, k);
    let lambda: Vec<f64> = (0..k).map(|i| s[i * k + i]).collect();
    let max = lambda.iter().copied().fold(0.0, f64::max);
    let cut = max * SINGULAR_RCOND;
    if reason.is_none() && lambda.iter().any(|&l| l <= cut) {
        let min = lambda.iter().copied().fold(f64::INFINITY, f64::min);
        reason = Some(format!(
            "J^T J is singular or ill-conditioned (condition number {} after scaling): some \
             constants trade off against others and the data do not determine them apart",
            if min > 0.0 {
                crate::expr::fmt_number(max / min, Some(3))
            } else {
                "infinite".into()
            }
        ));
    }
    let mut inv = vec![0.0; k * k];
    for (e, &l) in lambda.iter().enumerate() {
        if l <= cut || l <= 0.0 {
            continue;
        }
        for i in 0..k {
            let vi = v[i * k + e] / l;
            if vi == 0.0 {
                continue;
            }
            for j in 0..k {
                inv[i * k + j] += vi * v[j * k + e];
            }
        }
    }
    for ij in 0..k * k {
        inv[ij] *= d[ij / k] * d[ij % k];
    }
    (inv, reason)
}

/// Cyclic Jacobi eigen-decomposition of the symmetric `s` (`k x k`, row-major): on return
/// the diagonal of `s` holds the eigenvalues and the columns of `v` (which must start as the
/// identity) the eigenvectors.
pub(crate) fn jacobi_eigen(s: &mut [f64], v: &mut [f64], k: usize) {
    for _ in 0..JACOBI_SWEEPS {
        let off: f64 = (0..k)
            .flat_map(|i| (0..k).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| s[i * k + j] * s[i * k + j])
            .sum();
        let diag: f64 = (0..k).map(|i| s[i * k + i] * s[i * k + i]).sum();
        if off <= 1e-32 * diag || off == 0.0 {
            return;
        }
        for p in 0..k {
            for q in p + 1..k {
                let apq = s[p * k + q];
                if apq == 0.0 {
                    continue;
                }
                let app = s[p * k + p];
                let aqq = s[q * k + q];
                let theta = (aqq - app) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let sn = t * c;
                for r in 0..k {
                    let srp = s[r * k + p];
                    let srq = s[r * k + q];
                    s[r * k + p] = c * srp - sn * srq;
                    s[r * k + q] = sn * srp + c * srq;
                }
                for r in 0..k {
                    let spr = s[p * k + r];
                    let sqr = s[q * k + r];
                    s[p * k + r] = c * spr - sn * sqr;
                    s[q * k + r] = sn * spr + c * sqr;
                }
                for r in 0..k {
                    let vrp = v[r * k + p];
                    let vrq = v[r * k + q];
                    v[r * k + p] = c * vrp - sn * vrq;
                    v[r * k + q] = sn * vrp + c * vrq;
                }
            }
        }
    }
}

/// One constant of a template.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ParamEstimate {
    /// The value as the equation prints it (snapped to 1-3 significant digits when the
    /// search snapped it).
    pub value: f64,
    /// The least-squares optimum (the other exact constants held) that the covariance is
    /// taken at.
    pub fitted: f64,
    /// Standard error, `None` (JSON `null`) when the data do not determine it.
    pub std_error: Option<f64>,
    /// 95 % interval `fitted +- t_{n-k, 0.975} std_error`.
    pub ci95: Option<[f64; 2]>,
}

impl ParamEstimate {
    /// The estimate of a constant shown as `value`, fitted at `fitted`, with its standard
    /// error: the 95 % interval is `fitted +- t std_error` (`t` the Student quantile for
    /// the residual degrees of freedom), `None` without a standard error or where it is
    /// not finite.
    pub fn with_interval(value: f64, fitted: f64, std_error: Option<f64>, t: f64) -> Self {
        let ci95 = std_error
            .map(|se| [fitted - t * se, fitted + t * se])
            .filter(|c| c.iter().all(|v| v.is_finite()));
        ParamEstimate {
            value,
            fitted,
            std_error,
            ci95,
        }
    }
}

/// The constants of a model as a template with named parameters, their estimates, and what
/// prediction intervals need. JSON keys `template`, `params` ({name: [`ParamEstimate`]},
/// in template order), `slots`, `covariance`, `residual_variance`, `dof`, `n_rows`,
/// `reason`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Uncertainty {
    /// sympy text over the columns and the parameter names.
    pub template: String,
    /// Each parameter with its estimate, in template order.
    #[serde(with = "ordered_map")]
    pub params: Vec<(String, ParamEstimate)>,
    /// For each parameter, the program parameter indices it stands for (one for a
    /// symbolic model's constant; several for a physics parameter used twice).
    pub slots: Vec<Vec<usize>>,
    /// `s^2 (J^T J)^-1` of the parameters, row by row (pseudo-inverse where singular;
    /// empty when it does not exist).
    pub covariance: Vec<Vec<f64>>,
    /// `s^2`, the residual variance of the fit.
    pub residual_variance: f64,
    /// Residual degrees of freedom `n - k`.
    pub dof: usize,
    /// Rows of the fit.
    pub n_rows: usize,
    /// Why standard errors are `null` (absent when they are given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

/// `params` as a JSON object in template order (`p10` after `p9`, not after `p1`).
pub(crate) mod ordered_map {
    use super::ParamEstimate;
    use serde::de::{MapAccess, Visitor};
    use serde::ser::SerializeMap;
    use serde::{Deserializer, Serializer};

    pub(crate) fn serialize<S: Serializer>(
        v: &[(String, ParamEstimate)],
        s: S,
    ) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(v.len()))?;
        for (k, e) in v {
            m.serialize_entry(k, e)?;
        }
        m.end()
    }

    struct V;
    impl<'de> Visitor<'de> for V {
        type Value = Vec<(String, ParamEstimate)>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("an object of parameter estimates")
        }
        fn visit_map<A: MapAccess<'de>>(self, mut a: A) -> Result<Self::Value, A::Error> {
            let mut out = Vec::new();
            while let Some((k, e)) = a.next_entry::<String, ParamEstimate>()? {
                out.push((k, e));
            }
            Ok(out)
        }
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Vec<(String, ParamEstimate)>, D::Error> {
        d.deserialize_map(V)
    }
}

/// Template names `p0`, `p1`, ... for `count` parameters, skipping names in `taken`.
pub fn parameter_names(count: usize, taken: &[String]) -> Vec<String> {
    let mut out = Vec::with_capacity(count);
    let mut i = 0;
    while out.len() < count {
        let name = format!("p{i}");
        if !taken.contains(&name) {
            out.push(name);
        }
        i += 1;
    }
    out
}

impl Uncertainty {
    /// Builds the template and the estimates of the unknowns `slots` named `names` of
    /// `prog` over the inputs `inputs`, from the printed values `shown`, the optimum
    /// `fitted` and its covariance `cov`.
    pub fn build(
        prog: &Program,
        shown: &[f64],
        fitted: &[f64],
        inputs: &[String],
        names: Vec<String>,
        slots: Vec<Vec<usize>>,
        cov: &Covariance,
    ) -> Self {
        let mut symbols: Vec<Option<String>> = vec![None; shown.len()];
        for (name, group) in names.iter().zip(&slots) {
            for &i in group {
                if let Some(s) = symbols.get_mut(i) {
                    *s = Some(name.clone());
                }
            }
        }
        let template =
            Expr::from_program_with_symbols(prog, shown, inputs, &symbols).to_text(None, true);
        let t = hxai_eval::t_upper_quantile(0.025, cov.dof as f64);
        let k = names.len();
        let params = names
            .iter()
            .zip(&slots)
            .enumerate()
            .map(|(i, (name, group))| {
                let first = group.first().copied().unwrap_or(0);
                let value = shown.get(first).copied().unwrap_or(f64::NAN);
                let centre = fitted.get(first).copied().unwrap_or(value);
                let std_error = cov.std_error(i).filter(|_| cov.dof > 0);
                (
                    name.clone(),
                    ParamEstimate::with_interval(value, centre, std_error, t),
                )
            })
            .collect();
        let covariance = if cov.matrix.len() == k * k && cov.matrix.iter().all(|v| v.is_finite()) {
            cov.matrix.chunks(k.max(1)).map(<[f64]>::to_vec).collect()
        } else {
            Vec::new()
        };
        Uncertainty {
            template,
            params,
            slots,
            covariance,
            residual_variance: cov.residual_variance,
            dof: cov.dof,
            n_rows: cov.n_rows,
            reason: cov.reason.clone(),
        }
    }

    /// Prediction intervals at level `level` (for example 0.95) of `prog` with `params`
    /// on the rows `cols`: `(lo, hi)` per row, `f +- t_{dof, (1+level)/2} sqrt(s^2 +
    /// g^T C g)`.
    ///
    /// # Errors
    /// [`SrError::InvalidConfig`] for a level outside (0, 1), [`SrError::MalformedModel`]
    /// when the covariance is missing or does not match the parameters (a model file from
    /// an older version, or edited), and a non-finite prediction or gradient.
    pub fn intervals(
        &self,
        prog: &Program,
        params: &[f64],
        cols: &[&[f64]],
        n_rows: usize,
        level: f64,
    ) -> Result<Vec<(f64, f64)>, SrError> {
        if !(level > 0.0 && level < 1.0) {
            return Err(SrError::InvalidConfig(format!(
                "interval level {level}: give a probability between 0 and 1, such as 0.95"
            )));
        }
        let k = self.slots.len();
        if self.dof == 0
            || self.covariance.len() != k
            || self.covariance.iter().any(|r| r.len() != k)
        {
            return Err(SrError::MalformedModel(format!(
                "no usable covariance for prediction intervals ({}); refit the model",
                self.reason
                    .clone()
                    .unwrap_or_else(|| "the covariance does not match the parameters".into())
            )));
        }
        if self.slots.iter().flatten().any(|&i| i >= params.len()) {
            return Err(SrError::MalformedModel(
                "a parameter slot of the uncertainty is out of range".into(),
            ));
        }
        let flat: Vec<usize> = self.slots.iter().flatten().copied().collect();
        let mut ev = Evaluator::new(prog);
        let mut pred = Vec::new();
        ev.predict(prog, params, cols, n_rows, &mut pred);
        let mut jac = Vec::new();
        ev.jacobian(prog, params, &flat, cols, n_rows, &mut jac);
        let t = hxai_eval::t_upper_quantile((1.0 - level) / 2.0, self.dof as f64);
        let mf = flat.len();
        let mut g = vec![0.0; k];
        let mut out = Vec::with_capacity(n_rows);
        for (r, &f) in pred.iter().enumerate() {
            g.fill(0.0);
            let mut a = 0;
            for (u, group) in self.slots.iter().enumerate() {
                for _ in group {
                    g[u] += jac[r * mf + a];
                    a += 1;
                }
            }
            let mut var = self.residual_variance;
            for (i, row) in self.covariance.iter().enumerate() {
                for (j, c) in row.iter().enumerate() {
                    var += g[i] * c * g[j];
                }
            }
            let half = t * var.max(0.0).sqrt();
            if !(f.is_finite() && half.is_finite()) {
                return Err(SrError::NonFinite {
                    name: "prediction interval".into(),
                    row: r,
                    value: if f.is_finite() { half } else { f },
                });
            }
            out.push((f - half, f + half));
        }
        Ok(out)
    }
}

impl Model {
    /// The model's constants as a template with named parameters and their uncertainty on
    /// the rows `data`, `target` (the rows it was fitted on): exact constants (whole and half
    /// numbers) stay literals, the others are refitted with those held and their covariance
    /// taken at the optimum (see the [module docs](crate::uncertainty)).
    ///
    /// # Errors
    /// [`SrError::UnknownColumn`] for a feature missing from `data`,
    /// [`SrError::TargetLength`] for a target of another length.
    pub fn uncertainty(&self, data: &Table, target: &[f64]) -> Result<Uncertainty, SrError> {
        self.check()?;
        if target.len() != data.n_rows() {
            return Err(SrError::TargetLength {
                target: target.len(),
                data: data.n_rows(),
            });
        }
        let cols = self.columns(data)?;
        let free: Vec<usize> = (0..self.params.len())
            .filter(|&i| !is_exact(self.params[i]))
            .collect();
        let mut fitted = self.params.clone();
        let mut ev = Evaluator::new(&self.program);
        let before = ev.mse(&self.program, &fitted, &cols, target);
        if !free.is_empty() && before.is_finite() {
            let mse = levenberg_marquardt(
                &self.program,
                &mut fitted,
                Unknowns::Free(&free),
                &cols,
                target,
                &LmSettings::new(REFIT_MAX_ITER, REFIT_TOL),
                &mut ev,
            );
            if !mse.is_finite() {
                fitted = self.params.clone();
            }
        }
        let cov = covariance(&self.program, &fitted, Unknowns::Free(&free), &cols, target);
        let names = parameter_names(free.len(), &self.feature_names);
        Ok(Uncertainty::build(
            &self.program,
            &self.params,
            &fitted,
            &self.feature_names,
            names,
            free.iter().map(|&i| vec![i]).collect(),
            &cov,
        ))
    }

    /// Prediction intervals `(lo, hi)` at level `level` for every row of `data`, from the
    /// model's [`Uncertainty`] (see [`Uncertainty::intervals`]).
    ///
    /// # Errors
    /// As [`Model::predict`] and [`Uncertainty::intervals`].
    pub fn prediction_intervals(
        &self,
        uncertainty: &Uncertainty,
        data: &Table,
        level: f64,
    ) -> Result<Vec<(f64, f64)>, SrError> {
        self.check()?;
        let cols = self.columns(data)?;
        uncertainty.intervals(&self.program, &self.params, &cols, data.n_rows(), level)
    }
}
