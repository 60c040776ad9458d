//! The emulated path: every lane through [`crate::round::tight`], the reference the
//! hardware paths are tested against and the fallback on every other processor.

use super::{F64x8, Isa, Path, LANES};
use crate::round::tight::{add_hi, add_lo, div_hi, div_lo, mul_hi, mul_lo, sub_hi, sub_lo};

/// The emulated path's token (always available).
#[derive(Clone, Copy, Debug, Default)]
pub struct Emulated;

type V = [f64; LANES];

#[inline(always)]
fn map(a: V, f: impl Fn(f64) -> f64) -> V {
    core::array::from_fn(|k| f(a[k]))
}

#[inline(always)]
fn zip(a: V, b: V, f: impl Fn(f64, f64) -> f64) -> V {
    core::array::from_fn(|k| f(a[k], b[k]))
}

#[inline(always)]
fn mask(a: V, b: V, f: impl Fn(f64, f64) -> bool) -> u8 {
    (0..LANES).fold(0, |m, k| m | (u8::from(f(a[k], b[k])) << k))
}

/// NaN where the plain operation gives NaN (as the hardware paths' raw forms), else
/// the tight bound.
#[inline(always)]
fn nan_or(plain: f64, bound: f64) -> f64 {
    if plain.is_nan() {
        plain
    } else {
        bound
    }
}

/// `2^-900`: below it the residual of a square root may underflow, so it is taken on
/// the argument scaled by `2^1000` (whose root is the root scaled by `2^500`, exactly).
const SQRT_SMALL: f64 = f64::from_bits((1023 - 900) << 52);
const SQRT_SCALE: f64 = f64::from_bits((1023 + 1000) << 52);
const SQRT_UNSCALE: f64 = f64::from_bits((1023 + 500) << 52);

/// Floor of `sqrt(x)` in `f64`; `-inf` for `x < 0` and NaN.
///
/// `s = fl(sqrt(x))` is at most half an ulp off; `fma(s, s, -x)` has the sign of
/// `s^2 - x` exactly (the one rounding of a nonzero multiple of `ulp(s)^2 >= 2^-1074`
/// cannot reach 0 or change sign), so `s` is moved down exactly when it lies above the
/// root.
pub(crate) fn sqrt_lo(x: f64) -> f64 {
    if x.is_nan() || x < 0.0 {
        return f64::NEG_INFINITY;
    }
    if x == 0.0 || x == f64::INFINITY {
        return x;
    }
    let s = x.sqrt();
    let r = if x < SQRT_SMALL {
        let xs = x * SQRT_SCALE;
        let ss = s * SQRT_UNSCALE;
        ss.mul_add(ss, -xs)
    } else {
        s.mul_add(s, -x)
    };
    if r > 0.0 {
        s.next_down()
    } else {
        s
    }
}

/// Ceiling of `sqrt(x)` in `f64`; `+inf` for `x < 0` and NaN.
pub(crate) fn sqrt_hi(x: f64) -> f64 {
    if x.is_nan() || x < 0.0 {
        return f64::INFINITY;
    }
    if x == 0.0 || x == f64::INFINITY {
        return x;
    }
    let s = x.sqrt();
    let r = if x < SQRT_SMALL {
        let xs = x * SQRT_SCALE;
        let ss = s * SQRT_UNSCALE;
        ss.mul_add(ss, -xs)
    } else {
        s.mul_add(s, -x)
    };
    if r < 0.0 {
        s.next_up()
    } else {
        s
    }
}

/// `a * 2^k` for integral `|k| <= 1022` and a normal result (exact): the power of
/// two built from its bits (any other `k` is clamped into range first).
#[inline(always)]
pub(crate) fn scale_pow2(a: f64, k: f64) -> f64 {
    let k = k.clamp(-1022.0, 1023.0) as i64;
    a * f64::from_bits(((k + 1023) as u64) << 52)
}

/// `(m, e)` with `x = m 2^e`, `m` in `[0.75, 1.5)`, `e` integral, for positive normal
/// `x` (from the bits: the significand in `[1, 2)`, halved from 1.5 on).
#[inline(always)]
pub(crate) fn split_pow2(x: f64) -> (f64, f64) {
    let b = x.to_bits();
    let e = ((b >> 52) & 0x7ff) as i64 - 1023;
    let m = f64::from_bits((b & ((1 << 52) - 1)) | (1023 << 52));
    if m >= 1.5 {
        (0.5 * m, (e + 1) as f64)
    } else {
        (m, e as f64)
    }
}

impl Isa for Emulated {
    type V = V;
    type M = u8;
    const PATH: Path = Path::Emulated;

    #[inline(always)]
    fn load(self, x: &F64x8) -> V {
        x.0
    }
    #[inline(always)]
    fn store(self, v: V) -> F64x8 {
        F64x8(v)
    }
    #[inline(always)]
    fn splat(self, c: f64) -> V {
        [c; LANES]
    }
    #[inline(always)]
    fn add(self, a: V, b: V) -> V {
        zip(a, b, |a, b| a + b)
    }
    #[inline(always)]
    fn sub(self, a: V, b: V) -> V {
        zip(a, b, |a, b| a - b)
    }
    #[inline(always)]
    fn mul(self, a: V, b: V) -> V {
        zip(a, b, |a, b| a * b)
    }
    #[inline(always)]
    fn div(self, a: V, b: V) -> V {
        zip(a, b, |a, b| a / b)
    }
    #[inline(always)]
    fn sqrt(self, a: V) -> V {
        map(a, f64::sqrt)
    }
    #[inline(always)]
    fn fma(self, a: V, b: V, c: V) -> V {
        core::array::from_fn(|k| a[k].mul_add(b[k], c[k]))
    }
    #[inline(always)]
    fn neg(self, a: V) -> V {
        map(a, |a| -a)
    }
    #[inline(always)]
    fn abs(self, a: V) -> V {
        map(a, f64::abs)
    }
    #[inline(always)]
    fn or_bits(self, a: V, b: V) -> V {
        zip(a, b, |a, b| f64::from_bits(a.to_bits() | b.to_bits()))
    }
    #[inline(always)]
    fn and_bits(self, a: V, b: V) -> V {
        zip(a, b, |a, b| f64::from_bits(a.to_bits() & b.to_bits()))
    }
    #[inline(always)]
    fn min(self, a: V, b: V) -> V {
        zip(a, b, |a, b| if a < b { a } else { b })
    }
    #[inline(always)]
    fn max(self, a: V, b: V) -> V {
        zip(a, b, |a, b| if a > b { a } else { b })
    }
    #[inline(always)]
    fn lt(self, a: V, b: V) -> u8 {
        mask(a, b, |a, b| a < b)
    }
    #[inline(always)]
    fn le(self, a: V, b: V) -> u8 {
        mask(a, b, |a, b| a <= b)
    }
    #[inline(always)]
    fn eq(self, a: V, b: V) -> u8 {
        mask(a, b, |a, b| a == b)
    }
    #[inline(always)]
    fn unord(self, a: V, b: V) -> u8 {
        mask(a, b, |a, b| a.is_nan() || b.is_nan())
    }
    #[inline(always)]
    fn select(self, m: u8, a: V, b: V) -> V {
        core::array::from_fn(|k| if m & (1 << k) != 0 { a[k] } else { b[k] })
    }
    #[inline(always)]
    fn and(self, a: u8, b: u8) -> u8 {
        a & b
    }
    #[inline(always)]
    fn or(self, a: u8, b: u8) -> u8 {
        a | b
    }
    #[inline(always)]
    fn not(self, a: u8) -> u8 {
        !a
    }
    #[inline(always)]
    fn bits(self, m: u8) -> u8 {
        m
    }
    #[inline(always)]
    fn scale_pow2(self, a: V, k: V) -> V {
        zip(a, k, scale_pow2)
    }
    #[inline(always)]
    fn split_pow2(self, x: V) -> (V, V) {
        let p: [(f64, f64); LANES] = core::array::from_fn(|k| split_pow2(x[k]));
        (p.map(|p| p.0), p.map(|p| p.1))
    }
    #[inline(always)]
    fn add_up_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| nan_or(a + b, add_hi(a, b)))
    }
    #[inline(always)]
    fn add_down_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| nan_or(a + b, add_lo(a, b)))
    }
    #[inline(always)]
    fn sub_up_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| nan_or(a - b, sub_hi(a, b)))
    }
    #[inline(always)]
    fn sub_down_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| nan_or(a - b, sub_lo(a, b)))
    }
    #[inline(always)]
    fn mul_up_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| nan_or(a * b, mul_hi(a, b)))
    }
    #[inline(always)]
    fn mul_down_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| nan_or(a * b, mul_lo(a, b)))
    }
    #[inline(always)]
    fn div_up_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| nan_or(a / b, div_hi(a, b)))
    }
    #[inline(always)]
    fn div_down_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| nan_or(a / b, div_lo(a, b)))
    }
    #[inline(always)]
    fn sqrt_up_raw(self, a: V) -> V {
        map(a, |a| nan_or(a.sqrt(), sqrt_hi(a)))
    }
    #[inline(always)]
    fn sqrt_down_raw(self, a: V) -> V {
        map(a, |a| nan_or(a.sqrt(), sqrt_lo(a)))
    }
}
