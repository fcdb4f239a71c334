//! A minimal complex number, with the arithmetic numpy uses (so designs round like scipy's).

use std::ops::{Add, Mul, Neg, Sub};

/// A complex number (crate-private).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct C {
    pub re: f64,
    pub im: f64,
}

impl C {
    pub const fn new(re: f64, im: f64) -> Self {
        Self { re, im }
    }
    pub const fn real(re: f64) -> Self {
        Self { re, im: 0.0 }
    }
    /// |z| via hypot, like numpy's `abs`.
    pub fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }
    pub fn conj(self) -> Self {
        Self::new(self.re, -self.im)
    }
    pub fn is_real(self) -> bool {
        self.im == 0.0
    }
    /// Smith's division, exactly as numpy's complex division loop.
    pub fn div(self, d: C) -> C {
        let (ar, ai, br, bi) = (self.re, self.im, d.re, d.im);
        if br.abs() >= bi.abs() {
            if br == 0.0 && bi == 0.0 {
                return C::new(ar / br.abs(), ai / br.abs());
            }
            let rat = bi / br;
            let scl = 1.0 / (br + bi * rat);
            C::new((ar + ai * rat) * scl, (ai - ar * rat) * scl)
        } else {
            let rat = br / bi;
            let scl = 1.0 / (bi + br * rat);
            C::new((ar * rat + ai) * scl, (ai * rat - ar) * scl)
        }
    }
    /// Principal square root (C99 `csqrt` branch cuts, signed zero respected).
    pub fn sqrt(self) -> C {
        let (a, b) = (self.re, self.im);
        if a == 0.0 && b == 0.0 {
            return C::new(0.0, b);
        }
        let t = ((a.abs() + a.hypot(b)) / 2.0).sqrt();
        if a >= 0.0 {
            C::new(t, b / (2.0 * t))
        } else {
            C::new(b.abs() / (2.0 * t), t.copysign(b))
        }
    }
    /// z*z as numpy's square.
    pub fn square(self) -> C {
        C::new(
            self.re * self.re - self.im * self.im,
            self.re * self.im + self.im * self.re,
        )
    }
}

impl Add for C {
    type Output = C;
    fn add(self, o: C) -> C {
        C::new(self.re + o.re, self.im + o.im)
    }
}
impl Sub for C {
    type Output = C;
    fn sub(self, o: C) -> C {
        C::new(self.re - o.re, self.im - o.im)
    }
}
impl Mul for C {
    type Output = C;
    fn mul(self, o: C) -> C {
        C::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
}
impl Neg for C {
    type Output = C;
    fn neg(self) -> C {
        C::new(-self.re, -self.im)
    }
}
