//! Second-order sections: filtering with zero or given initial state, steady-state initial
//! conditions (`sosfilt_zi`) and zero-phase forward-backward filtering (`sosfiltfilt`).

use crate::SignalError;
use crate::error::check_signal;

/// A digital filter as a cascade of second-order sections, each `[b0, b1, b2, a0, a1, a2]`
/// (scipy's layout). Sections are stored normalised so that `a0 == 1`.
/// Serialised as the list of sections; deserialising validates like [`Sos::from_sections`].
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "Vec<[f64; 6]>", into = "Vec<[f64; 6]>")]
pub struct Sos {
    sections: Vec<[f64; 6]>,
}

impl TryFrom<Vec<[f64; 6]>> for Sos {
    type Error = SignalError;
    fn try_from(sections: Vec<[f64; 6]>) -> Result<Self, SignalError> {
        Sos::from_sections(sections)
    }
}

impl From<Sos> for Vec<[f64; 6]> {
    fn from(s: Sos) -> Self {
        s.sections
    }
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

    /// The core loop. For up to 8 sections it runs sample by sample through all sections with
    /// the state held in registers (a const-generic kernel): the sections' recurrences are
    /// independent chains, so the CPU overlaps them instead of waiting on one at a time.
    /// Longer cascades run section by section. Both give scipy's `sosfilt` up to rounding.
    fn filter_in_place(&self, y: &mut [f64], state: &mut [[f64; 2]]) {
        match self.sections.len() {
            1 => kernel::<1>(&self.sections, y, state),
            2 => kernel::<2>(&self.sections, y, state),
            3 => kernel::<3>(&self.sections, y, state),
            4 => kernel::<4>(&self.sections, y, state),
            5 => kernel::<5>(&self.sections, y, state),
            6 => kernel::<6>(&self.sections, y, state),
            7 => kernel::<7>(&self.sections, y, state),
            8 => kernel::<8>(&self.sections, y, state),
            _ => {
                for (s, z) in self.sections.iter().zip(state.iter_mut()) {
                    kernel::<1>(std::slice::from_ref(s), y, std::slice::from_mut(z));
                }
            }
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

    /// The magnitude of the frequency response at `frequency_hz` for sampling rate `fs`:
    /// `|H(e^{j 2 pi f / fs})|`, the product of the sections' magnitudes (what
    /// `abs(scipy.signal.sosfreqz(sos, [f], fs=fs)[1])` returns). `filtfilt` applies the
    /// filter twice, so its gain is the square of this.
    pub fn gain(&self, frequency_hz: f64, fs: f64) -> f64 {
        let w = 2.0 * std::f64::consts::PI * frequency_hz / fs;
        // z^-1 = cos w - j sin w; |b0 + b1 z^-1 + b2 z^-2| / |a0 + a1 z^-1 + a2 z^-2|.
        let (s1, c1) = w.sin_cos();
        let (s2, c2) = (2.0 * w).sin_cos();
        let poly = |p0: f64, p1: f64, p2: f64| {
            let re = p0 + p1 * c1 + p2 * c2;
            let im = -(p1 * s1 + p2 * s2);
            re.hypot(im)
        };
        self.sections
            .iter()
            .map(|s| poly(s[0], s[1], s[2]) / poly(s[3], s[4], s[5]))
            .product()
    }
}

/// Transposed direct form II over `N` sections, sample-major, state in local arrays.
/// `secs` and `state` hold exactly `N` entries (checked by the caller's dispatch).
#[inline(always)]
fn kernel<const N: usize>(secs: &[[f64; 6]], y: &mut [f64], state: &mut [[f64; 2]]) {
    let mut c = [[0.0; 6]; N];
    let mut z = [[0.0; 2]; N];
    let m = N.min(secs.len()).min(state.len());
    c[..m].copy_from_slice(&secs[..m]);
    z[..m].copy_from_slice(&state[..m]);
    for v in y.iter_mut() {
        let mut x = *v;
        for k in 0..N {
            let [b0, b1, b2, _, a1, a2] = c[k];
            let out = b0 * x + z[k][0];
            z[k][0] = (b1 * x + z[k][1]) - a1 * out;
            z[k][1] = b2 * x - a2 * out;
            x = out;
        }
        *v = x;
    }
    state[..m].copy_from_slice(&z[..m]);
}
