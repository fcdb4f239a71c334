//! Butterworth design in zeros-poles-gain form and its conversion to second-order sections,
//! following scipy's `buttap` -> `lp2{lp,hp,bp}_zpk` -> `bilinear_zpk` -> `zpk2sos(pairing='nearest')`
//! step by step, so that the sections (their order and pole-zero pairing) equal scipy's.

use std::f64::consts::PI;

use crate::SignalError;
use crate::complex::C;
use crate::error::check_fs;
use crate::filter::Sos;

/// The pass band of a Butterworth filter; frequencies in Hz.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Band {
    /// Pass frequencies below the cutoff (Hz).
    Lowpass(f64),
    /// Pass frequencies above the cutoff (Hz).
    Highpass(f64),
    /// Pass frequencies between the two edges (Hz, low then high). An order-`N` band-pass has
    /// `2N` poles and `N` sections, as in scipy.
    Bandpass(f64, f64),
}

impl Band {
    /// Checks the band against the sampling rate: every edge in (0, fs/2), low < high.
    pub fn check(&self, fs: f64) -> Result<(), SignalError> {
        check_fs(fs)?;
        let nyquist = fs / 2.0;
        let edge = |cutoff: f64| {
            if cutoff.is_finite() && cutoff > 0.0 && cutoff < nyquist {
                Ok(())
            } else {
                Err(SignalError::InvalidCutoff { cutoff, nyquist })
            }
        };
        match *self {
            Band::Lowpass(f) | Band::Highpass(f) => edge(f),
            Band::Bandpass(low, high) => {
                edge(low)?;
                edge(high)?;
                if low < high {
                    Ok(())
                } else {
                    Err(SignalError::InvalidBand { low, high })
                }
            }
        }
    }
}

/// Highest Butterworth order [`butter`] designs. Orders beyond a few tens are numerically
/// meaningless in double precision (poles crowd onto the unit circle) and make filtering
/// slow; refusing them early turns a minutes-long failure into an immediate error.
pub const MAX_ORDER: usize = 64;

/// Designs a digital Butterworth filter of `order` as second-order sections, equal to
/// `scipy.signal.butter(order, band, btype, fs=fs, output='sos')` (same sections in the same
/// order, gain in the first section).
///
/// # Errors
/// [`SignalError::ZeroOrder`], [`SignalError::OrderTooHigh`] (above [`MAX_ORDER`]),
/// [`SignalError::InvalidSampleRate`], [`SignalError::InvalidCutoff`]
/// (an edge outside (0, fs/2)), [`SignalError::InvalidBand`] (low >= high).
pub fn butter(order: usize, band: Band, fs: f64) -> Result<Sos, SignalError> {
    if order == 0 {
        return Err(SignalError::ZeroOrder);
    }
    if order > MAX_ORDER {
        return Err(SignalError::OrderTooHigh {
            order,
            max: MAX_ORDER,
        });
    }
    band.check(fs)?;
    let n = order as f64;
    // buttap: poles -exp(i pi m / (2N)), m = -N+1, -N+3, ..., N-1; no zeros; gain 1.
    let p: Vec<C> = (0..order)
        .map(|i| {
            let m = -n + 1.0 + 2.0 * i as f64;
            let theta = PI * m / (2.0 * n);
            -C::new(theta.cos(), theta.sin())
        })
        .collect();
    let half = fs / 2.0;
    // Pre-warp for the bilinear transform with scipy's internal fs = 2.
    let warp = |f: f64| 2.0 * 2.0 * (PI * (f / half) / 2.0).tan();
    let (z, p, k) = match band {
        Band::Lowpass(f) => {
            let wo = warp(f);
            let p: Vec<C> = p.iter().map(|&pi| C::real(wo) * pi).collect();
            (Vec::new(), p, wo.powf(n))
        }
        Band::Highpass(f) => {
            let wo = warp(f);
            let ph: Vec<C> = p.iter().map(|&pi| C::real(wo).div(pi)).collect();
            let prod = p.iter().fold(None, |acc: Option<C>, &pi| {
                Some(match acc {
                    None => -pi,
                    Some(a) => a * -pi,
                })
            });
            let k = prod.map_or(1.0, |pr| C::real(1.0).div(pr).re);
            (vec![C::real(0.0); order], ph, k)
        }
        Band::Bandpass(lo, hi) => {
            let (w1, w2) = (warp(lo), warp(hi));
            let bw = w2 - w1;
            let wo = (w1 * w2).sqrt();
            let plp: Vec<C> = p
                .iter()
                .map(|&pi| (pi * C::real(bw)).div(C::real(2.0)))
                .collect();
            let wo2 = wo.powi(2);
            let mut pb: Vec<C> = plp
                .iter()
                .map(|&q| q + (q.square() - C::real(wo2)).sqrt())
                .collect();
            pb.extend(plp.iter().map(|&q| q - (q.square() - C::real(wo2)).sqrt()));
            (vec![C::real(0.0); order], pb, bw.powf(n))
        }
    };
    let (z, p, k) = bilinear(&z, &p, k);
    let sections = zpk2sos(z, p, k)?;
    Sos::from_sections(sections)
}

/// scipy's `bilinear_zpk` with fs = 2.
fn bilinear(z: &[C], p: &[C], k: f64) -> (Vec<C>, Vec<C>, f64) {
    let fs2 = C::real(4.0);
    let degree = p.len() - z.len();
    let mut zz: Vec<C> = z.iter().map(|&zi| (fs2 + zi).div(fs2 - zi)).collect();
    let pz: Vec<C> = p.iter().map(|&pi| (fs2 + pi).div(fs2 - pi)).collect();
    zz.extend(std::iter::repeat_n(C::real(-1.0), degree));
    let prod = |v: &[C]| {
        v.iter().fold(None, |acc: Option<C>, &x| {
            Some(match acc {
                None => fs2 - x,
                Some(a) => a * (fs2 - x),
            })
        })
    };
    let num = prod(z).unwrap_or(C::real(1.0));
    let den = prod(p).unwrap_or(C::real(1.0));
    (zz, pz, k * num.div(den).re)
}

/// scipy's `_cplxreal`: the positive-imaginary halves of the conjugate pairs (averaged) and
/// the real values, both sorted by real part.
fn cplxreal(mut z: Vec<C>) -> Result<(Vec<C>, Vec<f64>), SignalError> {
    let tol = 100.0 * f64::EPSILON;
    z.sort_by(|a, b| {
        a.re.total_cmp(&b.re)
            .then(a.im.abs().total_cmp(&b.im.abs()))
    });
    let is_real = |c: &C| c.im.abs() <= tol * c.abs();
    let zr: Vec<f64> = z.iter().filter(|c| is_real(c)).map(|c| c.re).collect();
    let rest: Vec<C> = z.into_iter().filter(|c| !is_real(c)).collect();
    let mut zp: Vec<C> = rest.iter().copied().filter(|c| c.im > 0.0).collect();
    let mut zn: Vec<C> = rest.iter().copied().filter(|c| c.im < 0.0).collect();
    if zp.len() != zn.len() {
        return Err(SignalError::InvalidConfig(
            "filter design produced a complex value without its conjugate".into(),
        ));
    }
    // Runs of (approximately) equal real part are sorted by |imag|.
    let mut start = 0;
    while start < zp.len() {
        let mut stop = start + 1;
        while stop < zp.len() && zp[stop].re - zp[stop - 1].re <= tol * zp[stop - 1].abs() {
            stop += 1;
        }
        zp[start..stop].sort_by(|a, b| a.im.abs().total_cmp(&b.im.abs()));
        zn[start..stop].sort_by(|a, b| a.im.abs().total_cmp(&b.im.abs()));
        start = stop;
    }
    for (a, b) in zp.iter().zip(&zn) {
        if (*a - b.conj()).abs() > tol * b.abs() {
            return Err(SignalError::InvalidConfig(
                "filter design produced a complex value without its conjugate".into(),
            ));
        }
    }
    let zc = zp
        .iter()
        .zip(&zn)
        .map(|(&a, &b)| {
            let s = a + b.conj();
            C::new(s.re * 0.5, s.im * 0.5)
        })
        .collect();
    Ok((zc, zr))
}

/// Index of the pole closest to the unit circle (first on ties, like `np.argmin`).
fn idx_worst(p: &[C], only_real: bool) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (i, c) in p.iter().enumerate() {
        if only_real && !c.is_real() {
            continue;
        }
        let d = (1.0 - c.abs()).abs();
        if best.is_none_or(|(_, bd)| d < bd) {
            best = Some((i, d));
        }
    }
    best.map(|(i, _)| i)
}

#[derive(Clone, Copy, PartialEq)]
enum Which {
    Real,
    Complex,
    Any,
}

/// scipy's `_nearest_real_complex_idx`.
fn nearest(fro: &[C], to: C, which: Which) -> Option<usize> {
    let mut order: Vec<(usize, f64)> = fro.iter().map(|&c| (c - to).abs()).enumerate().collect();
    order.sort_by(|a, b| a.1.total_cmp(&b.1));
    order.into_iter().map(|(i, _)| i).find(|&i| match which {
        Which::Any => true,
        Which::Real => fro[i].is_real(),
        Which::Complex => !fro[i].is_real(),
    })
}

/// numpy's `poly`, real part.
fn poly(roots: &[C]) -> Vec<f64> {
    let mut a = vec![C::real(1.0)];
    for &r in roots {
        let mut out = vec![C::real(0.0); a.len() + 1];
        for (k, o) in out.iter_mut().enumerate() {
            let mut terms: Vec<C> = Vec::with_capacity(2);
            if k < a.len() {
                terms.push(a[k] * C::real(1.0));
            }
            if k >= 1 {
                terms.push(a[k - 1] * -r);
            }
            *o = match terms.as_slice() {
                [t] => *t,
                [t0, t1] => *t1 + *t0,
                _ => C::real(0.0),
            };
        }
        a = out;
    }
    a.into_iter().map(|c| c.re).collect()
}

/// scipy's `_single_zpksos` with k = 1.
fn single(z: &[C], p: &[C]) -> [f64; 6] {
    let mut s = [0.0; 6];
    let b = poly(z);
    let a = poly(p);
    for (i, v) in b.iter().enumerate() {
        s[3 - b.len() + i] = *v;
    }
    for (i, v) in a.iter().enumerate() {
        s[6 - a.len() + i] = *v;
    }
    s
}

fn internal(msg: &'static str) -> SignalError {
    SignalError::InvalidConfig(format!("internal filter-design error: {msg}"))
}

/// scipy's `zpk2sos(z, p, k, pairing='nearest')` for a digital filter.
pub(crate) fn zpk2sos(z: Vec<C>, p: Vec<C>, k: f64) -> Result<Vec<[f64; 6]>, SignalError> {
    if z.is_empty() && p.is_empty() {
        return Ok(vec![[k, 0.0, 0.0, 1.0, 0.0, 0.0]]);
    }
    let (mut z, mut p) = (z, p);
    let np_ = p.len();
    let nz = z.len();
    p.extend(std::iter::repeat_n(C::real(0.0), nz.saturating_sub(np_)));
    z.extend(std::iter::repeat_n(C::real(0.0), np_.saturating_sub(nz)));
    let n_sections = p.len().max(z.len()).div_ceil(2);
    if p.len() % 2 == 1 {
        p.push(C::real(0.0));
        z.push(C::real(0.0));
    }
    let (zc, zr) = cplxreal(z)?;
    let mut z: Vec<C> = zc.into_iter().chain(zr.into_iter().map(C::real)).collect();
    let (pc, pr) = cplxreal(p)?;
    let mut p: Vec<C> = pc.into_iter().chain(pr.into_iter().map(C::real)).collect();

    let mut sos = vec![[0.0; 6]; n_sections];
    for si in (0..n_sections).rev() {
        let i1 = idx_worst(&p, false).ok_or_else(|| internal("ran out of poles"))?;
        let p1 = p.remove(i1);
        let n_real_p = p.iter().filter(|c| c.is_real()).count();
        if p1.is_real() && n_real_p == 0 {
            // Special case (1): last remaining real pole.
            let iz = nearest(&z, p1, Which::Real).ok_or_else(|| internal("no real zero"))?;
            let z1 = z.remove(iz);
            sos[si] = single(&[z1, C::real(0.0)], &[p1, C::real(0.0)]);
        } else if p.len() + 1 == z.len()
            && !p1.is_real()
            && n_real_p == 1
            && z.iter().filter(|c| c.is_real()).count() == 1
        {
            // Special case (2): must pair with a complex zero.
            let iz = nearest(&z, p1, Which::Complex).ok_or_else(|| internal("no complex zero"))?;
            let z1 = z.remove(iz);
            sos[si] = single(&[z1, z1.conj()], &[p1, p1.conj()]);
        } else {
            let p2 = if p1.is_real() {
                let i2 = idx_worst(&p, true).ok_or_else(|| internal("no real pole"))?;
                p.remove(i2)
            } else {
                p1.conj()
            };
            if z.is_empty() {
                sos[si] = single(&[], &[p1, p2]);
            } else {
                let iz = nearest(&z, p1, Which::Any).ok_or_else(|| internal("no zero"))?;
                let z1 = z.remove(iz);
                if !z1.is_real() {
                    sos[si] = single(&[z1, z1.conj()], &[p1, p2]);
                } else if z.is_empty() {
                    sos[si] = single(&[z1], &[p1, p2]);
                } else {
                    let iz2 =
                        nearest(&z, p1, Which::Real).ok_or_else(|| internal("no real zero"))?;
                    let z2 = z.remove(iz2);
                    sos[si] = single(&[z1, z2], &[p1, p2]);
                }
            }
        }
    }
    for v in &mut sos[0][..3] {
        *v *= k;
    }
    Ok(sos)
}
