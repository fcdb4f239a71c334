//! Integration and trend removal.

/// Which trend [`detrend`] removes (scipy.signal.detrend's `type`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Detrend {
    /// Leave the signal as it is.
    None,
    /// Subtract the mean.
    #[default]
    Constant,
    /// Subtract the least-squares straight line.
    Linear,
}

/// Removes the trend `kind` from `x`, like `scipy.signal.detrend(x, type=...)`. An empty input
/// gives an empty output; non-finite values propagate.
pub fn detrend(x: &[f64], kind: Detrend) -> Vec<f64> {
    let mut y = x.to_vec();
    detrend_in_place(&mut y, kind);
    y
}

/// [`detrend`] without allocating.
pub fn detrend_in_place(y: &mut [f64], kind: Detrend) {
    let n = y.len();
    if n == 0 {
        return;
    }
    let nf = n as f64;
    match kind {
        Detrend::None => {}
        Detrend::Constant => {
            let mean = y.iter().sum::<f64>() / nf;
            y.iter_mut().for_each(|v| *v -= mean);
        }
        Detrend::Linear => {
            // Least squares on centred time t_i = i - (n-1)/2, so the two unknowns decouple.
            let tc = (nf - 1.0) / 2.0;
            let mean = y.iter().sum::<f64>() / nf;
            let (mut sty, mut stt) = (0.0, 0.0);
            for (i, v) in y.iter().enumerate() {
                let t = i as f64 - tc;
                sty += t * v;
                stt += t * t;
            }
            let slope = if stt > 0.0 { sty / stt } else { 0.0 };
            for (i, v) in y.iter_mut().enumerate() {
                *v -= mean + slope * (i as f64 - tc);
            }
        }
    }
}

/// Cumulative trapezoidal integral with spacing `dx`, same length as `y` and starting at 0,
/// like `scipy.integrate.cumulative_trapezoid(y, dx=dx, initial=0)`. An empty input gives an
/// empty output.
pub fn cumulative_trapezoid(y: &[f64], dx: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(y.len());
    if y.is_empty() {
        return out;
    }
    let mut acc = 0.0;
    out.push(acc);
    for w in y.windows(2) {
        acc += dx * (w[1] + w[0]) / 2.0;
        out.push(acc);
    }
    out
}
