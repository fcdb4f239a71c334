//! An adaptive explicit Runge-Kutta integrator for the grey-box dynamic models of issue 69:
//! Dormand and Prince's 5(4) pair (the tableau of scipy's `RK45` and of Hairer's `DOPRI5`),
//! local extrapolation (the 5th-order solution is kept), an error norm of
//! `atol + rtol * max(|y|, |y_new|)` per component (root mean square), and the step
//! controller of Hairer, Norsett and Wanner (safety 0.9, growth within [0.2, 10]).
//!
//! Inputs are held between samples by the caller: [`integrate`] steps exactly onto each
//! output time, so a right-hand side that reads an input sampled at those times sees it
//! constant over every step. A stiff system is detected by Hairer's test (the step's
//! stability estimate `h |lambda|` above 3.25 on 15 accepted steps) and refused with
//! [`OdeError::Stiff`]; an explicit method would crawl through it.
//!
//! No ODE crate was taken: the well-kept ones (`ode_solvers`, `diffsol`) bring nalgebra or
//! their own matrix types into a workspace that uses faer, and the method is 150 lines
//! checked against scipy's `solve_ivp` (`tests`, vectors from `scripts/ref_ode.py`).

/// A right-hand side `f(t, y, dy)`: writes `dy/dt` at `(t, y)` into `dy`.
pub type Rhs<'a> = dyn FnMut(f64, &[f64], &mut [f64]) + 'a;

/// Settings of [`integrate`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OdeSettings {
    /// Relative tolerance of the local error (default 1e-8).
    pub rtol: f64,
    /// Absolute tolerance of the local error (default 1e-10).
    pub atol: f64,
    /// Most steps over the whole interval (default 100,000).
    pub max_steps: usize,
}

impl Default for OdeSettings {
    fn default() -> Self {
        Self {
            rtol: 1e-8,
            atol: 1e-10,
            max_steps: 100_000,
        }
    }
}

/// Why an integration stopped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OdeError {
    /// The right-hand side gave a value that is not a number, or the state left the finite.
    #[error("the state is not finite at t = {t} (the model blows up there)")]
    NotFinite {
        /// The time reached.
        t: f64,
    },
    /// The step fell below what the time's floating point can resolve.
    #[error("the step size fell to {h:e} at t = {t}: the model is singular there")]
    StepTooSmall {
        /// The time reached.
        t: f64,
        /// The last step tried.
        h: f64,
    },
    /// More than [`OdeSettings::max_steps`] steps.
    #[error("more than {0} steps: the model is too fast or too stiff for an explicit method")]
    TooManySteps(usize),
    /// Hairer's stiffness test fired.
    #[error(
        "the system is stiff near t = {t} (a time constant far shorter than the sampling): an \
         explicit Runge-Kutta method would need tiny steps; rescale the model or its constants"
    )]
    Stiff {
        /// The time reached.
        t: f64,
    },
    /// Bad arguments: unsorted output times, a state of length 0, bad tolerances.
    #[error("invalid integration setting: {0}")]
    Invalid(String),
}

// Dormand-Prince 5(4) coefficients (Hairer, Norsett and Wanner, Table II.5.2).
const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// The 5th-order weights (the last row of `A`, FSAL) less the embedded 4th-order ones.
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Integrates `dy/dt = f(t, y)` from `(t0, y0)` and returns the state at each of `times`
/// (non-decreasing, none before `t0`), stepping exactly onto each: `f(t, y, dy)` writes the
/// derivative into `dy`.
///
/// # Errors
/// [`OdeError`]: a state that is not finite, a vanishing step, too many steps, a stiff
/// system, or bad arguments.
pub fn integrate(
    f: &mut Rhs<'_>,
    t0: f64,
    y0: &[f64],
    times: &[f64],
    s: &OdeSettings,
) -> Result<Vec<Vec<f64>>, OdeError> {
    let n = y0.len();
    if n == 0 {
        return Err(OdeError::Invalid("a state of no component".into()));
    }
    if !(s.rtol > 0.0 && s.atol > 0.0 && s.rtol.is_finite() && s.atol.is_finite()) {
        return Err(OdeError::Invalid(format!(
            "rtol {} and atol {} must be positive",
            s.rtol, s.atol
        )));
    }
    if !t0.is_finite() || times.iter().any(|t| !t.is_finite()) {
        return Err(OdeError::Invalid("a time that is not finite".into()));
    }
    if times.first().is_some_and(|&t| t < t0) || times.windows(2).any(|w| w[1] < w[0]) {
        return Err(OdeError::Invalid(
            "output times must not decrease nor precede the start".into(),
        ));
    }
    if y0.iter().any(|v| !v.is_finite()) {
        return Err(OdeError::NotFinite { t: t0 });
    }
    let mut st = Stepper::new(n, *s);
    let (mut t, mut y) = (t0, y0.to_vec());
    f(t, &y, &mut st.k[0]);
    let mut h = st.initial_step(f, t, &y, times.last().map_or(1.0, |&e| e - t0));
    let mut out = Vec::with_capacity(times.len());
    for &target in times {
        while t < target {
            let span = target - t;
            // land on the output time: a last step a little longer rather than a sliver
            let last = h >= span || span - h < 1e-10 * span.max(t.abs());
            let step = if last { span } else { h };
            let (accepted, next_h) = st.step(f, t, &mut y, step)?;
            if accepted {
                t = if last { target } else { t + step };
                if y.iter().any(|v| !v.is_finite()) {
                    return Err(OdeError::NotFinite { t });
                }
                if st.stiff_steps >= STIFF_STEPS {
                    return Err(OdeError::Stiff { t });
                }
            }
            if next_h <= 16.0 * f64::EPSILON * t.abs().max(1.0) {
                return Err(OdeError::StepTooSmall { t, h: next_h });
            }
            h = if last && accepted {
                h.max(next_h)
            } else {
                next_h
            };
            if st.steps > s.max_steps {
                return Err(OdeError::TooManySteps(s.max_steps));
            }
        }
        out.push(y.clone());
    }
    Ok(out)
}

/// Accepted steps with `h |lambda| > 3.25` after which the system is called stiff.
const STIFF_STEPS: usize = 15;

/// The stages and counters of one integration.
struct Stepper {
    s: OdeSettings,
    k: Vec<Vec<f64>>,
    tmp: Vec<f64>,
    y_new: Vec<f64>,
    steps: usize,
    stiff_steps: usize,
    calm_steps: usize,
}

impl Stepper {
    fn new(n: usize, s: OdeSettings) -> Self {
        Self {
            s,
            k: vec![vec![0.0; n]; 7],
            tmp: vec![0.0; n],
            y_new: vec![0.0; n],
            steps: 0,
            stiff_steps: 0,
            calm_steps: 0,
        }
    }

    /// Hairer's starting step (`hinit`): from the sizes of `y`, `f` and a trial second
    /// derivative, at most `span`.
    fn initial_step(&mut self, f: &mut Rhs<'_>, t: f64, y: &[f64], span: f64) -> f64 {
        let sc: Vec<f64> = y
            .iter()
            .map(|v| self.s.atol + self.s.rtol * v.abs())
            .collect();
        let rms = |v: &[f64]| -> f64 {
            (v.iter().zip(&sc).map(|(a, s)| (a / s).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
        };
        let (d0, d1) = (rms(y), rms(&self.k[0]));
        let h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6
        } else {
            0.01 * d0 / d1
        };
        let h0 = h0.min(span.abs().max(f64::MIN_POSITIVE));
        for (tm, (yv, kv)) in self.tmp.iter_mut().zip(y.iter().zip(&self.k[0])) {
            *tm = yv + h0 * kv;
        }
        let mut f1 = vec![0.0; y.len()];
        f(t + h0, &self.tmp, &mut f1);
        let diff: Vec<f64> = f1.iter().zip(&self.k[0]).map(|(a, b)| a - b).collect();
        let d2 = rms(&diff) / h0;
        let h1 = if d1.max(d2) <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / d1.max(d2)).powf(0.2)
        };
        (100.0 * h0).min(h1).min(span.abs().max(f64::MIN_POSITIVE))
    }

    /// One trial step of size `h` from `(t, y)`: on acceptance `y` and the first stage
    /// (FSAL) move on. Returns whether it was accepted and the next step size.
    fn step(
        &mut self,
        f: &mut Rhs<'_>,
        t: f64,
        y: &mut [f64],
        h: f64,
    ) -> Result<(bool, f64), OdeError> {
        self.steps += 1;
        let n = y.len();
        for i in 1..7 {
            for (j, (tm, yj)) in self.tmp.iter_mut().zip(y.iter()).enumerate() {
                let mut acc = 0.0;
                for (l, a) in A[i].iter().enumerate().take(i) {
                    acc += a * self.k[l][j];
                }
                *tm = yj + h * acc;
            }
            f(t + C[i] * h, &self.tmp, &mut self.k[i]);
        }
        // the 5th-order solution is the last stage's argument (FSAL)
        self.y_new.copy_from_slice(&self.tmp);
        let mut err = 0.0;
        for (j, (yj, nj)) in y.iter().zip(&self.y_new).enumerate() {
            let e: f64 = (0..7).map(|l| E[l] * self.k[l][j]).sum::<f64>() * h;
            let sc = self.s.atol + self.s.rtol * yj.abs().max(nj.abs());
            err += (e / sc).powi(2);
        }
        let err = (err / n as f64).sqrt();
        if !err.is_finite() {
            return Ok((false, 0.2 * h));
        }
        let factor = if err == 0.0 {
            10.0
        } else {
            (0.9 * err.powf(-0.2)).clamp(0.2, 10.0)
        };
        if err > 1.0 {
            return Ok((false, h * factor.min(1.0)));
        }
        self.stiffness(h);
        y.copy_from_slice(&self.y_new);
        let (first, rest) = self.k.split_at_mut(1);
        first[0].copy_from_slice(&rest[5]);
        Ok((true, h * factor))
    }

    /// Hairer's stiffness test on an accepted step: `h |lambda|`, estimated from the last
    /// two stages (both at `t + h`), above 3.25 counts a stiff step; six calm steps reset
    /// the count.
    fn stiffness(&mut self, h: f64) {
        let n = self.tmp.len();
        let (mut num, mut den) = (0.0, 0.0);
        for j in 0..n {
            num += (self.k[6][j] - self.k[5][j]).powi(2);
            // the 6th stage's argument: y + h sum_l A[5][l] k_l, against the solution's
            let stage6: f64 = (0..5).map(|l| A[5][l] * self.k[l][j]).sum::<f64>();
            let sol: f64 = (0..6).map(|l| A[6][l] * self.k[l][j]).sum::<f64>();
            den += (h * (sol - stage6)).powi(2);
        }
        if den > 0.0 && h * (num / den).sqrt() > 3.25 {
            self.stiff_steps += 1;
            self.calm_steps = 0;
        } else {
            self.calm_steps += 1;
            if self.calm_steps >= 6 {
                self.stiff_steps = 0;
            }
        }
    }
}

#[cfg(test)]
mod tests;
