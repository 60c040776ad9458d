//! The AVX2 path: two four-lane registers (`wide::f64x4`), directed bounds by rounding
//! to nearest and stepping one ulp outward through the bit pattern.
//!
//! Soundness: a correctly rounded `+ - * /` or `sqrt` is at most half an ulp from the
//! exact result, so the next float beyond the rounded one (towards `+inf` for an upper
//! bound) lies beyond the exact result, including across a power of two (where the
//! spacing halves on the side of the smaller magnitude: the exact value was within half
//! of that smaller spacing), in the subnormal range and at an overflow (the exact value
//! of finite operands rounded to `+inf` lies above `f64::MAX`). The result is therefore
//! at most one ulp beyond the tight bound. Only an exact zero from a square root is kept
//! as it is (the root of `0`); every other result steps, so exact results lose one ulp.

use super::{F64x8, Isa, Path};
use wide::{bytemuck, f64x4, i64x4, u64x4};

/// The AVX2 path's token: exists only where the processor has AVX2 and FMA.
#[derive(Clone, Copy, Debug)]
pub struct Avx2(());

impl Avx2 {
    /// The token, where this processor has AVX2 and FMA.
    pub fn detect() -> Option<Avx2> {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma")
            {
                return Some(Avx2(()));
            }
        }
        None
    }
}

type V = (f64x4, f64x4);

#[inline(always)]
fn split(x: &F64x8) -> V {
    let [a, b, c, d, e, f, g, h] = x.0;
    (f64x4::new([a, b, c, d]), f64x4::new([e, f, g, h]))
}

#[inline(always)]
fn map(a: V, f: impl Fn(f64x4) -> f64x4) -> V {
    (f(a.0), f(a.1))
}

#[inline(always)]
fn zip(a: V, b: V, f: impl Fn(f64x4, f64x4) -> f64x4) -> V {
    (f(a.0, b.0), f(a.1, b.1))
}

/// The next float above each lane, for every lane but NaN (kept) and `+inf` (kept):
/// `-0` becomes `+0` first, then the bits step away from zero for a positive lane and
/// towards it for a negative one.
#[inline(always)]
fn up(r: f64x4) -> f64x4 {
    let r = r + f64x4::splat(0.0);
    let b: i64x4 = bytemuck::cast(r);
    let neg = i64x4::splat(0).simd_gt(b);
    let s: f64x4 = bytemuck::cast(b + (neg | i64x4::splat(1)));
    r.simd_lt(f64x4::splat(f64::INFINITY)).select(s, r)
}

/// The next float below each lane, for every lane but NaN and `-inf` (kept).
#[inline(always)]
fn down(r: f64x4) -> f64x4 {
    -up(-r)
}

/// `2^k` for integral `|k| <= 1023`: `2^52 + 1023 + k` holds `1023 + k` in its
/// significand's bits, which shifted to the exponent field make the power.
#[inline(always)]
fn pow2(k: f64x4) -> f64x4 {
    let t: u64x4 = bytemuck::cast(k + f64x4::splat(4_503_599_627_371_519.0));
    bytemuck::cast(t << 52)
}

/// The emulated path's `split_pow2` on four lanes: the biased exponent and the
/// significand in `[1, 2)` from the bits (the exponent as a float through the same
/// `2^52` offset), halved from 1.5 on.
#[inline(always)]
fn split_pow2(x: f64x4) -> (f64x4, f64x4) {
    let b: u64x4 = bytemuck::cast(x);
    let m: f64x4 = bytemuck::cast((b & u64x4::splat((1 << 52) - 1)) | u64x4::splat(1023 << 52));
    let offset = u64x4::splat(0x433 << 52);
    let e: f64x4 = bytemuck::cast((b >> 52) | offset);
    let e = e - f64x4::splat(4_503_599_627_371_519.0);
    let big = m.simd_ge(f64x4::splat(1.5));
    (
        big.select(m * f64x4::splat(0.5), m),
        big.select(e + f64x4::splat(1.0), e),
    )
}

impl Isa for Avx2 {
    type V = V;
    type M = V;
    const PATH: Path = Path::Avx2;

    #[inline(always)]
    fn load(self, x: &F64x8) -> V {
        split(x)
    }
    #[inline(always)]
    fn store(self, v: V) -> F64x8 {
        let (a, b) = (v.0.to_array(), v.1.to_array());
        F64x8([a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]])
    }
    #[inline(always)]
    fn splat(self, c: f64) -> V {
        (f64x4::splat(c), f64x4::splat(c))
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
        map(a, f64x4::sqrt)
    }
    #[inline(always)]
    fn fma(self, a: V, b: V, c: V) -> V {
        (a.0.mul_add(b.0, c.0), a.1.mul_add(b.1, c.1))
    }
    #[inline(always)]
    fn neg(self, a: V) -> V {
        map(a, |a| -a)
    }
    #[inline(always)]
    fn abs(self, a: V) -> V {
        map(a, f64x4::abs)
    }
    #[inline(always)]
    fn or_bits(self, a: V, b: V) -> V {
        zip(a, b, |a, b| a | b)
    }
    #[inline(always)]
    fn and_bits(self, a: V, b: V) -> V {
        zip(a, b, |a, b| a & b)
    }
    #[inline(always)]
    fn min(self, a: V, b: V) -> V {
        zip(a, b, f64x4::fast_min)
    }
    #[inline(always)]
    fn max(self, a: V, b: V) -> V {
        zip(a, b, f64x4::fast_max)
    }
    #[inline(always)]
    fn lt(self, a: V, b: V) -> V {
        zip(a, b, |a, b| a.simd_lt(b))
    }
    #[inline(always)]
    fn le(self, a: V, b: V) -> V {
        zip(a, b, |a, b| a.simd_le(b))
    }
    #[inline(always)]
    fn eq(self, a: V, b: V) -> V {
        zip(a, b, |a, b| a.simd_eq(b))
    }
    #[inline(always)]
    fn unord(self, a: V, b: V) -> V {
        zip(a, b, |a, b| a.is_nan() | b.is_nan())
    }
    #[inline(always)]
    fn select(self, m: V, a: V, b: V) -> V {
        (m.0.select(a.0, b.0), m.1.select(a.1, b.1))
    }
    #[inline(always)]
    fn and(self, a: V, b: V) -> V {
        zip(a, b, |a, b| a & b)
    }
    #[inline(always)]
    fn or(self, a: V, b: V) -> V {
        zip(a, b, |a, b| a | b)
    }
    #[inline(always)]
    fn not(self, a: V) -> V {
        let ones: f64x4 = bytemuck::cast(i64x4::splat(-1));
        map(a, |a| a ^ ones)
    }
    #[inline(always)]
    fn bits(self, m: V) -> u8 {
        (m.0.to_bitmask() | (m.1.to_bitmask() << 4)) as u8
    }
    #[inline(always)]
    fn scale_pow2(self, a: V, k: V) -> V {
        zip(a, k, |a, k| a * pow2(k))
    }
    #[inline(always)]
    fn split_pow2(self, x: V) -> (V, V) {
        let (m0, e0) = split_pow2(x.0);
        let (m1, e1) = split_pow2(x.1);
        ((m0, m1), (e0, e1))
    }
    #[inline(always)]
    fn add_up_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| up(a + b))
    }
    #[inline(always)]
    fn add_down_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| down(a + b))
    }
    #[inline(always)]
    fn sub_up_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| up(a - b))
    }
    #[inline(always)]
    fn sub_down_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| down(a - b))
    }
    #[inline(always)]
    fn mul_up_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| up(a * b))
    }
    #[inline(always)]
    fn mul_down_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| down(a * b))
    }
    #[inline(always)]
    fn div_up_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| up(a / b))
    }
    #[inline(always)]
    fn div_down_raw(self, a: V, b: V) -> V {
        zip(a, b, |a, b| down(a / b))
    }
    #[inline(always)]
    fn sqrt_up_raw(self, a: V) -> V {
        map(a, |a| {
            let s = a.sqrt();
            s.simd_eq(f64x4::splat(0.0)).select(s, up(s))
        })
    }
    #[inline(always)]
    fn sqrt_down_raw(self, a: V) -> V {
        map(a, |a| {
            let s = a.sqrt();
            s.simd_eq(f64x4::splat(0.0)).select(s, down(s))
        })
    }
}
