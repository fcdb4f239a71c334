//! Elementary functions written so that the compiler vectorises the batch loops that call
//! them.
//!
//! `std`'s `exp`, `ln`, `sin`, `cos` and `tanh` are calls into the C library, one row at a
//! time; a loop over a batch that calls them cannot use SIMD lanes. The functions here are
//! branch-free straight-line code (integer tricks on the bit pattern instead of
//! float-to-integer conversions, selects instead of branches), so a loop over a slice
//! compiles to 2 (SSE2) or 4 (AVX2) rows per instruction. They use only IEEE add, sub, mul,
//! div and sqrt, never fused multiply-add, so every instruction set gives the same bits.
//!
//! Algorithms: `exp` reduces by `n ln 2` (Cody-Waite, two-part ln 2) and sums the Taylor
//! series to degree 13 on |r| <= ln2/2 (truncation below 5e-18 relative); `ln` is the
//! fdlibm/musl reduction and polynomial (`Lg1..Lg7`); `sin`/`cos` reduce by `q pi/2` with a
//! four-part pi/2 and use the fdlibm/musl kernels (`S1..S6`, `C1..C6`); `tanh` is Cephes'
//! rational form below 0.625 and `1 - 2/(e^{2|x|}+1)` above (one shared division). Agreement with `std` (the C
//! library) is tested in `tests/it/vmath.rs`: within 2 ulp for `exp`, `ln` and `tanh`, and
//! within 2 ulp or 2e-16 absolute for `sin`/`cos`, over the ranges and special values listed
//! there.
//!
//! `sin` and `cos` are vectorised for |x| <= [`TRIG_LIMIT`]; beyond it (and for non-finite
//! x) they take `std`'s answer. Batch code calls [`sin_kernel`]/[`cos_kernel`] in the
//! vectorised loop and then [`trig_fixup`] for the rare rows out of range, which gives the
//! same values as the scalar [`sin`]/[`cos`].

// Published constants are kept digit for digit as their sources print them.
#![allow(clippy::excessive_precision)]

/// 1.5 * 2^52: `x + MAGIC - MAGIC` rounds |x| < 2^51 to an integer (ties to even), and the
/// integer sits in the low bits of the bit pattern of `x + MAGIC`.
const MAGIC: f64 = 6_755_399_441_055_744.0;
const MAGIC_BITS: u64 = 0x4338_0000_0000_0000;

/// `2^k` for an integer-valued `k` in [-1022, 1023].
#[inline(always)]
fn pow2(k: f64) -> f64 {
    let bits = (k + MAGIC)
        .to_bits()
        .wrapping_sub(MAGIC_BITS)
        .wrapping_add(1023);
    f64::from_bits(bits << 52)
}

const LN2_HI: f64 = 6.931_471_803_691_238_164_90e-01;
const LN2_LO: f64 = 1.908_214_929_270_587_700_02e-10;

/// e^r - 1 for |r| <= ln2/2: the Taylor series to r^13 / 13! (truncation below 5e-18
/// relative), summed small terms first in Estrin's scheme (short dependency chains).
#[inline(always)]
fn expm1_reduced(r: f64) -> f64 {
    let r2 = r * r;
    let r4 = r2 * r2;
    let r6 = r4 * r2;
    let q1 = 0.5 + r * (1.0 / 6.0);
    let q2 = 1.0 / 24.0 + r * (1.0 / 120.0);
    let q3 = 1.0 / 720.0 + r * (1.0 / 5_040.0);
    let q4 = 1.0 / 40_320.0 + r * (1.0 / 362_880.0);
    let q5 = 1.0 / 3_628_800.0 + r * (1.0 / 39_916_800.0);
    let q6 = 1.0 / 479_001_600.0 + r * (1.0 / 6_227_020_800.0);
    // r + r^2 (q1 + q2 r^2 + q3 r^4 + (q4 + q5 r^2 + q6 r^4) r^6)
    let hi = q1 + (q2 + q3 * r2) * r2;
    let lo = q4 + (q5 + q6 * r2) * r2;
    r + r2 * (hi + lo * r6)
}

/// e^x, within 2 ulp of the C library's; `inf` above 709.78, 0 below -745.13, NaN for NaN.
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    // NaN passes through the clamp
    let xc = x.clamp(-745.2, 709.8);
    let n = (xc * std::f64::consts::LOG2_E + MAGIC) - MAGIC;
    let r = (xc - n * LN2_HI) - n * LN2_LO;
    let p = 1.0 + expm1_reduced(r);
    // 2^n as two factors, so that n = 1024 and subnormal results need no special case
    let n1 = (n * 0.5 + MAGIC) - MAGIC;
    let y = p * pow2(n1) * pow2(n - n1);
    if x > 709.782_712_893_384 {
        f64::INFINITY
    } else if x < -745.133_219_101_941_2 {
        0.0
    } else {
        y
    }
}

const LG1: f64 = 6.666_666_666_666_735_130e-01;
const LG2: f64 = 3.999_999_999_940_941_908e-01;
const LG3: f64 = 2.857_142_874_366_239_149e-01;
const LG4: f64 = 2.222_219_843_214_978_396e-01;
const LG5: f64 = 1.818_357_216_161_805_012e-01;
const LG6: f64 = 1.531_383_769_920_937_332e-01;
const LG7: f64 = 1.479_819_860_511_658_591e-01;

/// Natural logarithm: `-inf` at 0, NaN below 0 and for NaN, `inf` at `inf`.
#[inline(always)]
pub fn ln(x: f64) -> f64 {
    // subnormal inputs are scaled into the normal range first
    let tiny = x < f64::MIN_POSITIVE;
    let xs = if tiny {
        x * 18_014_398_509_481_984.0
    } else {
        x
    };
    // x = 2^k (1 + f) with 1 + f in [sqrt(2)/2, sqrt(2))
    let u = xs
        .to_bits()
        .wrapping_add((0x3ff0_0000u64 - 0x3fe6_a09e) << 32);
    let k = f64::from_bits((u >> 52) | 0x4330_0000_0000_0000)
        - (4_503_599_627_370_496.0 + 1023.0)
        - if tiny { 54.0 } else { 0.0 };
    let m = f64::from_bits((u & 0x000f_ffff_ffff_ffff).wrapping_add(0x3fe6_a09eu64 << 32));
    let f = m - 1.0;
    let hfsq = 0.5 * f * f;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * (LG2 + w * (LG4 + w * LG6));
    let t2 = z * (LG1 + w * (LG3 + w * (LG5 + w * LG7)));
    let r = t2 + t1;
    let y = s * (hfsq + r) + k * LN2_LO - hfsq + f + k * LN2_HI;
    if x > 0.0 && x < f64::INFINITY {
        y
    } else if x == 0.0 {
        f64::NEG_INFINITY
    } else if x == f64::INFINITY {
        f64::INFINITY
    } else {
        f64::NAN
    }
}

/// Largest |x| for which the vectorised `sin`/`cos` kernels are used: q = round(2x/pi)
/// stays below 2^20, so `q * PIO2_1` (33 significant bits) is exact.
pub const TRIG_LIMIT: f64 = 1.0e6;

const PIO2_1: f64 = 1.570_796_326_734_125_614_17e+00; // 0x3FF921FB54400000
const PIO2_2: f64 = 6.077_100_506_303_965_976_60e-11; // 0x3DD0B4611A600000
const PIO2_3: f64 = 2.022_266_248_711_166_455_80e-21; // 0x3BA3198A2E000000
const PIO2_3T: f64 = 8.478_427_660_368_899_569_97e-32;

const S1: f64 = -1.666_666_666_666_663_243_48e-01;
const S2: f64 = 8.333_333_333_322_489_461_24e-03;
const S3: f64 = -1.984_126_982_985_794_931_34e-04;
const S4: f64 = 2.755_731_370_707_006_767_89e-06;
const S5: f64 = -2.505_076_025_340_686_341_95e-08;
const S6: f64 = 1.589_690_995_211_550_102_21e-10;

const C1: f64 = 4.166_666_666_666_660_190_37e-02;
const C2: f64 = -1.388_888_888_887_410_957_49e-03;
const C3: f64 = 2.480_158_728_947_672_941_78e-05;
const C4: f64 = -2.755_731_435_139_066_330_35e-07;
const C5: f64 = 2.087_572_321_298_174_827_90e-09;
const C6: f64 = -1.135_964_755_778_819_482_65e-11;

/// sin(x + quadrant pi/2) for |x| <= TRIG_LIMIT (garbage beyond; see [`trig_fixup`]).
#[inline(always)]
fn trig_kernel(x: f64, quadrant: u64) -> f64 {
    let t = x * std::f64::consts::FRAC_2_PI + MAGIC;
    let q = t - MAGIC;
    let r = (((x - q * PIO2_1) - q * PIO2_2) - q * PIO2_3) - q * PIO2_3T;
    let z = r * r;
    let w = z * z;
    // sin(r)
    let sr = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
    let s = r + z * r * (S1 + z * sr);
    // cos(r)
    let cr = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let one_minus = 1.0 - hz;
    let c = one_minus + (((1.0 - one_minus) - hz) + z * cr);
    let qi = t.to_bits().wrapping_add(quadrant);
    let v = if qi & 1 == 0 { s } else { c };
    if qi & 2 == 0 { v } else { -v }
}

/// Whether the kernels are valid at `x` (false for NaN and infinities).
#[inline(always)]
fn in_trig_range(x: f64) -> bool {
    x.abs() <= TRIG_LIMIT
}

/// The vectorisable part of [`sin`]: correct for |x| <= [`TRIG_LIMIT`].
#[inline(always)]
pub fn sin_kernel(x: f64) -> f64 {
    trig_kernel(x, 0)
}

/// The vectorisable part of [`cos`]: correct for |x| <= [`TRIG_LIMIT`].
#[inline(always)]
pub fn cos_kernel(x: f64) -> f64 {
    trig_kernel(x, 1)
}

/// sin(x).
#[inline(always)]
pub fn sin(x: f64) -> f64 {
    if in_trig_range(x) {
        sin_kernel(x)
    } else {
        x.sin()
    }
}

/// cos(x).
#[inline(always)]
pub fn cos(x: f64) -> f64 {
    if in_trig_range(x) {
        cos_kernel(x)
    } else {
        x.cos()
    }
}

/// Replaces `dst[i]` by `f(i, a[i])` where `a[i]` is outside the kernels' range: the
/// scalar [`sin`]/[`cos`] after a kernel sweep (`|_, x| sin(x)`), or a derivative built
/// from them. A cheap compare pass when no row is out of range.
#[inline(always)]
pub fn trig_fixup(dst: &mut [f64], a: &[f64], f: impl Fn(usize, f64) -> f64) {
    if !a.iter().all(|&v| in_trig_range(v)) {
        for (i, (d, &x)) in dst.iter_mut().zip(a).enumerate() {
            if !in_trig_range(x) {
                *d = f(i, x);
            }
        }
    }
}

const TP0: f64 = -9.643_991_794_250_522_386_28e-1;
const TP1: f64 = -9.928_772_310_019_185_865_64e1;
const TP2: f64 = -1.614_687_684_417_084_479_52e3;
const TQ0: f64 = 1.128_116_784_916_329_314_02e2;
const TQ1: f64 = 2.235_488_390_601_004_485_83e3;
const TQ2: f64 = 4.844_063_053_251_254_860_48e3;

/// tanh(x): Cephes' rational form `x + x z P(z)/Q(z)` below |x| = 0.625 and
/// `1 - 2/(e^{2|x|} + 1)` above, sharing one division (the lanes select its operands).
#[inline(always)]
pub fn tanh(x: f64) -> f64 {
    let a = x.abs();
    let small = a < 0.625;
    let e = exp(2.0 * a);
    let z = x * x;
    let num_s = x * z * ((TP0 * z + TP1) * z + TP2);
    let den_s = ((z + TQ0) * z + TQ1) * z + TQ2;
    let q = if small { num_s } else { 2.0 } / if small { den_s } else { e + 1.0 };
    if small { x + q } else { (1.0 - q).copysign(x) }
}
