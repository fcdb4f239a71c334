//! Constant fitting by Levenberg-Marquardt.
//!
//! Models have at most a few dozen parameters, so the damped normal equations are solved
//! with a hand-written Cholesky factorisation: for systems this small (≤ ~40 unknowns) a
//! general linear-algebra library costs more in set-up than the solve itself, and the
//! fixed operation order keeps results bit-identical everywhere.
use crate::eval::{Evaluator, Inputs};
use crate::program::{Node, Program};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Solves `A x = b` in place for symmetric positive definite `A` given by its lower
/// triangle (row-major, `m x m`). Returns false if `A` is not positive definite.
pub fn cholesky_solve(a: &mut [f64], b: &mut [f64], m: usize) -> bool {
    for j in 0..m {
        let mut d = a[j * m + j];
        for k in 0..j {
            d -= a[j * m + k] * a[j * m + k];
        }
        if d <= 0.0 || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        a[j * m + j] = d;
        for i in j + 1..m {
            let mut s = a[i * m + j];
            for k in 0..j {
                s -= a[i * m + k] * a[j * m + k];
            }
            a[i * m + j] = s / d;
        }
    }
    for i in 0..m {
        let mut s = b[i];
        for k in 0..i {
            s -= a[i * m + k] * b[k];
        }
        b[i] = s / a[i * m + i];
    }
    for i in (0..m).rev() {
        let mut s = b[i];
        for k in i + 1..m {
            s -= a[k * m + i] * b[k];
        }
        b[i] = s / a[i * m + i];
    }
    true
}

/// The unknowns Levenberg-Marquardt fits: which parameters move, and which move together.
#[derive(Debug, Clone, Copy)]
pub enum Unknowns<'a> {
    /// One unknown per listed parameter index (the search's case).
    Free(&'a [usize]),
    /// One unknown per group of tied parameter indices: a physics parameter used twice in
    /// an equation owns two constant leaves that must move as one. The Jacobian column of
    /// a group is the sum of its leaves' columns, so its normal equations are sums of
    /// blocks of the leaves' normal equations.
    Tied(&'a [Vec<usize>]),
}

impl Unknowns<'_> {
    /// The number of unknowns.
    pub fn len(&self) -> usize {
        match self {
            Unknowns::Free(free) => free.len(),
            Unknowns::Tied(groups) => groups.len(),
        }
    }

    /// True when there is nothing to fit.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Gauss-Newton normal equations of the unknowns at `params`: fills `jtj` (`len()`
    /// squared, row-major; the lower triangle is what [`cholesky_solve`] reads) and `jtr`
    /// (`len()`) and returns the mean squared error (`INFINITY` if not finite). `Free`
    /// fills the lower triangle only; `Tied` fills the whole symmetric matrix.
    pub fn normal_equations(
        &self,
        ev: &mut Evaluator,
        inp: Inputs,
        y: &[f64],
        jtj: &mut [f64],
        jtr: &mut [f64],
    ) -> f64 {
        let Inputs { prog, params, cols } = inp;
        let groups = match self {
            Unknowns::Free(free) => {
                return ev.normal_equations(Inputs { prog, params, cols }, free, y, jtj, jtr);
            }
            Unknowns::Tied(groups) => groups,
        };
        let flat: Vec<usize> = groups.iter().flatten().copied().collect();
        let owner: Vec<usize> = groups
            .iter()
            .enumerate()
            .flat_map(|(g, v)| std::iter::repeat_n(g, v.len()))
            .collect();
        let mf = flat.len();
        let mut leaf_jtj = vec![0.0; mf * mf];
        let mut leaf_jtr = vec![0.0; mf];
        let mse = ev.normal_equations(
            Inputs { prog, params, cols },
            &flat,
            y,
            &mut leaf_jtj,
            &mut leaf_jtr,
        );
        let m = groups.len();
        jtj.fill(0.0);
        jtr.fill(0.0);
        for a in 0..mf {
            jtr[owner[a]] += leaf_jtr[a];
            for b in 0..mf {
                let v = if b <= a {
                    leaf_jtj[a * mf + b]
                } else {
                    leaf_jtj[b * mf + a]
                };
                jtj[owner[a] * m + owner[b]] += v;
            }
        }
        mse
    }

    /// Adds the step `delta` (one entry per unknown) to `params`.
    fn apply(&self, params: &mut [f64], delta: &[f64]) {
        match self {
            Unknowns::Free(free) => {
                for (i, &p) in free.iter().enumerate() {
                    params[p] += delta[i];
                }
            }
            Unknowns::Tied(groups) => {
                for (g, d) in groups.iter().zip(delta) {
                    for &i in g {
                        params[i] += d;
                    }
                }
            }
        }
    }
}

/// How long Levenberg-Marquardt runs and how it damps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LmSettings {
    /// At most this many accepted steps.
    pub max_iter: usize,
    /// Stop when an accepted step lowers the error by less than this fraction.
    pub tol: f64,
    /// Damping increases tried per iteration before giving up.
    pub retries: usize,
    /// The damping `lambda` never falls below this after an accepted step.
    pub lambda_floor: f64,
    /// How the normal equations' diagonal is kept positive. `false` (the search's): each
    /// diagonal entry `d` gets `1e-12 (1 + d)`, an absolute floor that also damps an
    /// unknown whose curvature is below `1e-12` in the target's units. `true` (the
    /// calibration's): `1e-12 d` and the smallest positive number, so an unknown's step does
    /// not depend on its units (an activation energy of 3e5 J/mol on rates of 1e-8/s, whose
    /// curvature is 1e-21, moves as freely as a prefactor).
    pub scale_free_floor: bool,
    /// Whether every value of the model must stay above zero (where it is at the start): a
    /// step after which one is not is refused as if it raised the error. The calibration
    /// of a physics under a log correction sets it, since `ln(y / f_p)` needs `f_p > 0`.
    pub keep_positive: bool,
}

impl LmSettings {
    /// The search's settings (8 damping retries, damping floor `1e-10`) with the given
    /// iteration limit and relative tolerance.
    pub fn new(max_iter: usize, tol: f64) -> Self {
        Self {
            max_iter,
            tol,
            retries: 8,
            lambda_floor: 1e-10,
            scale_free_floor: false,
            keep_positive: false,
        }
    }
}

/// Runs Levenberg-Marquardt on `unknowns`, starting from `params` (which is updated in
/// place). Returns the final mean squared error (`INFINITY` when the model is not finite on
/// the data). Stops after `settings.max_iter` accepted steps, when no damping of
/// `settings.retries` tries lowers the error, or early when an accepted step lowers the
/// error by less than the fraction `settings.tol`.
pub fn levenberg_marquardt(
    prog: &Program,
    params: &mut [f64],
    unknowns: Unknowns,
    cols: &[&[f64]],
    y: &[f64],
    settings: &LmSettings,
    ev: &mut Evaluator,
) -> f64 {
    let m = unknowns.len();
    let mut jtj = vec![0.0; m * m];
    let mut jtr = vec![0.0; m];
    let mut a = vec![0.0; m * m];
    let mut delta = vec![0.0; m];
    let mut trial = params.to_vec();
    let inp = Inputs { prog, params, cols };
    let mut mse = unknowns.normal_equations(ev, inp, y, &mut jtj, &mut jtr);
    if !mse.is_finite() || m == 0 {
        // a non-finite Jacobian (sqrt or log at 0, say) ends the fit, but the start's own
        // loss may still be finite
        return ev.mse(prog, params, cols, y);
    }
    let mut values = Vec::new();
    let mut positive = |ev: &mut Evaluator, p: &[f64]| {
        ev.predict(prog, p, cols, y.len(), &mut values);
        values.iter().all(|&v| v > 0.0)
    };
    let keep_positive = settings.keep_positive && positive(ev, params);
    let mut lambda = 1e-3;
    for _ in 0..settings.max_iter {
        let mut accepted = false;
        for _ in 0..settings.retries {
            a.copy_from_slice(&jtj);
            for i in 0..m {
                let d = jtj[i * m + i];
                a[i * m + i] = if settings.scale_free_floor {
                    d * (1.0 + lambda + 1e-12) + f64::MIN_POSITIVE
                } else {
                    d * (1.0 + lambda) + 1e-12 * (1.0 + d)
                };
            }
            for i in 0..m {
                delta[i] = -jtr[i];
            }
            if !cholesky_solve(&mut a, &mut delta, m) {
                lambda *= 10.0;
                continue;
            }
            trial.copy_from_slice(params);
            unknowns.apply(&mut trial, &delta);
            let mut new = ev.mse(prog, &trial, cols, y);
            if keep_positive && new < mse && !positive(ev, &trial) {
                new = f64::INFINITY;
            }
            if new < mse {
                params.copy_from_slice(&trial);
                lambda = (lambda * 0.2).max(settings.lambda_floor);
                accepted = true;
                let improvement = (mse - new) / mse.max(1e-300);
                mse = new;
                if improvement < settings.tol {
                    return mse;
                }
                break;
            }
            lambda *= 8.0;
        }
        if !accepted {
            break;
        }
        let inp = Inputs { prog, params, cols };
        let next = unknowns.normal_equations(ev, inp, y, &mut jtj, &mut jtr);
        if !next.is_finite() {
            // the accepted step's loss stands; only its Jacobian is unusable
            return mse;
        }
        mse = next;
    }
    mse
}

/// Scale statistics of the input columns used to initialise affine inputs.
#[derive(Debug, Clone)]
pub struct InputScales {
    /// Root mean square of each column (1 where the column is all zero).
    pub rms: Vec<f64>,
}

impl InputScales {
    /// Computes the statistics.
    pub fn new(cols: &[&[f64]]) -> Self {
        let rms = cols
            .iter()
            .map(|c| {
                let s = (c.iter().map(|v| v * v).sum::<f64>() / c.len().max(1) as f64).sqrt();
                if s > 0.0 && s.is_finite() { s } else { 1.0 }
            })
            .collect();
        Self { rms }
    }
}

/// Initial parameters for a fresh program: inputs scaled to unit RMS (keeping their sign,
/// so `log` and `sqrt` of positive inputs stay defined), randomly perturbed when `rng` is
/// given; constants 1 (or random); output map by least squares.
pub fn initial_params(
    prog: &Program,
    scales: &InputScales,
    rng: Option<&mut ChaCha8Rng>,
    cols: &[&[f64]],
    y: &[f64],
    ev: &mut Evaluator,
) -> Vec<f64> {
    let mut p = vec![0.0; prog.n_params()];
    p[0] = 1.0;
    let offs = prog.param_offsets();
    let mut rng = rng;
    for (k, n) in prog.nodes.iter().enumerate() {
        match n {
            Node::Var(j) if prog.affine => {
                let w = 1.0 / scales.rms[*j as usize];
                let (f, b) = match rng.as_deref_mut() {
                    Some(r) => {
                        let f: f64 =
                            r.gen_range(0.5..2.0) * if r.gen_bool(0.2) { -1.0 } else { 1.0 };
                        let b = if r.gen_bool(0.5) {
                            r.gen_range(-1.0..1.0)
                        } else {
                            0.0
                        };
                        (f, b)
                    }
                    None => (1.0, 0.0),
                };
                p[offs[k]] = w * f;
                p[offs[k] + 1] = b;
            }
            Node::Const => {
                p[offs[k]] = match rng.as_deref_mut() {
                    Some(r) => r.gen_range(-2.0..2.0),
                    None => 1.0,
                };
            }
            _ => {}
        }
    }
    fit_output_map(prog, &mut p, cols, y, ev);
    p
}

/// Sets the output scale and offset to the least-squares fit of `y` on the root value.
pub fn fit_output_map(
    prog: &Program,
    p: &mut [f64],
    cols: &[&[f64]],
    y: &[f64],
    ev: &mut Evaluator,
) {
    let root = ev.root_values(
        Inputs {
            prog,
            params: p,
            cols,
        },
        y.len(),
    );
    let n = y.len() as f64;
    let mx = root.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let mut sxx = 0.0;
    let mut sxy = 0.0;
    for (x, yv) in root.iter().zip(y) {
        sxx += (x - mx) * (x - mx);
        sxy += (x - mx) * (yv - my);
    }
    if sxx > 0.0 && sxx.is_finite() && sxy.is_finite() {
        p[0] = sxy / sxx;
        p[1] = my - p[0] * mx;
    } else {
        p[0] = 1.0;
        p[1] = 0.0;
    }
}
