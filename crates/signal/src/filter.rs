//! Second-order sections: filtering with zero or given initial state, steady-state initial
//! conditions (`sosfilt_zi`) and zero-phase forward-backward filtering (`sosfiltfilt`).

use crate::SignalError;
use crate::error::check_signal;

/// A digital filter as a cascade of second-order sections, each `[b0, b1, b2, a0, a1, a2]`
/// (scipy's layout). Sections are stored normalised so that `a0 == 1`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sos {
    sections: Vec<[f64; 6]>,
}

impl Sos {
    /// Builds a filter from sections in scipy's layout. Each section is divided by its `a0`.
    ///
    /// # Errors
    /// [`SignalError::InvalidSection`] when there are no sections, a coefficient is not finite or
    /// `a0 == 0`.
    pub fn from_sections(sections: Vec<[f64; 6]>) -> Result<Self, SignalError> {
        if sections.is_empty() {
            return Err(SignalError::InvalidSection {
                index: 0,
                reason: "a filter needs at least one section",
            });
        }
        let mut out = sections;
        for (index, s) in out.iter_mut().enumerate() {
            if s.iter().any(|v| !v.is_finite()) {
                return Err(SignalError::InvalidSection {
                    index,
                    reason: "a coefficient is NaN or infinite",
                });
            }
            let a0 = s[3];
            if a0 == 0.0 {
                return Err(SignalError::InvalidSection {
                    index,
                    reason: "a0 is zero; the section has no output",
                });
            }
            if a0 != 1.0 {
                for v in s.iter_mut() {
                    *v /= a0;
                }
            }
        }
        Ok(Self { sections: out })
    }

    /// The sections, `[b0, b1, b2, a0, a1, a2]` each, `a0 == 1`.
    pub fn sections(&self) -> &[[f64; 6]] {
        &self.sections
    }

    /// Filters `x` with zero initial state, like `scipy.signal.sosfilt(sos, x)`. Non-finite
    /// input propagates into the output (no error: this is the raw linear operation).
    pub fn filter(&self, x: &[f64]) -> Vec<f64> {
        let mut state = vec![[0.0; 2]; self.sections.len()];
        let mut y = x.to_vec();
        self.filter_in_place(&mut y, &mut state);
        y
    }

    /// Filters `x` starting from the state `zi` (one `[z0, z1]` per section, transposed direct
    /// form II, as `sosfilt(sos, x, zi=zi)`), and returns the output and the final state.
    ///
    /// # Errors
    /// [`SignalError::InvalidConfig`] when `zi` does not hold one pair per section.
    pub fn filter_with_state(
        &self,
        x: &[f64],
        zi: &[[f64; 2]],
    ) -> Result<(Vec<f64>, Vec<[f64; 2]>), SignalError> {
        if zi.len() != self.sections.len() {
            return Err(SignalError::InvalidConfig(format!(
                "the initial state has {} rows but the filter has {} sections; pass one [z0, z1] per section",
                zi.len(),
                self.sections.len()
            )));
        }
        let mut state = zi.to_vec();
        let mut y = x.to_vec();
        self.filter_in_place(&mut y, &mut state);
        Ok((y, state))
    }

    /// The core loop: section by section over the whole signal (each pass is a tight
    /// recurrence over contiguous memory, which is faster than sample-by-sample across
    /// sections and gives the same result).
    fn filter_in_place(&self, y: &mut [f64], state: &mut [[f64; 2]]) {
        for (s, z) in self.sections.iter().zip(state.iter_mut()) {
            let [b0, b1, b2, _, a1, a2] = *s;
            let (mut z0, mut z1) = (z[0], z[1]);
            for v in y.iter_mut() {
                let x = *v;
                let out = b0 * x + z0;
                z0 = b1 * x - a1 * out + z1;
                z1 = b2 * x - a2 * out;
                *v = out;
            }
            *z = [z0, z1];
        }
    }

    /// Steady-state initial conditions for a unit step, like `scipy.signal.sosfilt_zi`: scale by
    /// the first input sample to start the filter without a transient.
    pub fn zi(&self) -> Vec<[f64; 2]> {
        let mut scale = 1.0;
        let mut out = Vec::with_capacity(self.sections.len());
        for s in &self.sections {
            let [b0, b1, b2, _, a1, a2] = *s;
            // lfilter_zi for a biquad: solve (I - A^T) zi = B with A the companion matrix.
            let bb0 = b1 - a1 * b0;
            let bb1 = b2 - a2 * b0;
            let z0 = (bb0 + bb1) / (1.0 + a1 + a2);
            let z1 = bb1 - a2 * z0;
            out.push([scale * z0, scale * z1]);
            scale *= (b0 + b1 + b2) / (1.0 + a1 + a2);
        }
        out
    }

    /// scipy's default pad length for `sosfiltfilt`:
    /// `3 * (2 * n_sections + 1 - min(#(b2 == 0), #(a2 == 0)))`.
    pub fn padlen(&self) -> usize {
        let nb = self.sections.iter().filter(|s| s[2] == 0.0).count();
        let na = self.sections.iter().filter(|s| s[5] == 0.0).count();
        3 * (2 * self.sections.len() + 1 - nb.min(na))
    }

    /// Zero-phase forward-backward filtering equal to `scipy.signal.sosfiltfilt(sos, x)` with
    /// its defaults: odd extension by [`Sos::padlen`] samples at each end, initial state
    /// `zi * first sample` forward and `zi * last sample` backward.
    ///
    /// # Errors
    /// [`SignalError::Empty`], [`SignalError::NonFinite`], and [`SignalError::TooShort`] when
    /// `x.len() <= padlen`.
    pub fn filtfilt(&self, x: &[f64]) -> Result<Vec<f64>, SignalError> {
        check_signal(x, "x")?;
        let edge = self.padlen();
        if x.len() <= edge {
            return Err(SignalError::TooShort {
                len: x.len(),
                needed: edge,
                operation: "filtfilt (odd-extension padding)",
            });
        }
        let n = x.len();
        let mut ext = Vec::with_capacity(n + 2 * edge);
        let (first, last) = (x[0], x[n - 1]);
        ext.extend((1..=edge).rev().map(|i| 2.0 * first - x[i]));
        ext.extend_from_slice(x);
        ext.extend((1..=edge).map(|i| 2.0 * last - x[n - 1 - i]));
        let zi = self.zi();
        let mut state: Vec<[f64; 2]> = zi.iter().map(|z| [z[0] * ext[0], z[1] * ext[0]]).collect();
        self.filter_in_place(&mut ext, &mut state);
        ext.reverse();
        let y0 = ext[0];
        let mut state: Vec<[f64; 2]> = zi.iter().map(|z| [z[0] * y0, z[1] * y0]).collect();
        self.filter_in_place(&mut ext, &mut state);
        ext.reverse();
        ext.truncate(edge + n);
        ext.drain(..edge);
        Ok(ext)
    }
}
