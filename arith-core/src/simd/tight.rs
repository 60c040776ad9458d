//! Tight directed bounds of one `+` or `*` in four lanes: [`crate::round::tight`]'s
//! `add_lo`, `mul_lo` and `mul_hi` on their common path, each with the mask of the lanes
//! where that path is the one the scalar function takes.
//!
//! The scalar functions branch on overflow, undefined results, zeros and underflow; here
//! every lane computes the common path (a finite result, a finite error term, for products
//! a magnitude of at least `2^-960` so the error term is exact) and reports in its mask
//! whether the scalar function would have taken it. Where a mask is set, the lane is bit
//! for bit the scalar result (the same rounded operation, the same error-free
//! transformation, the same one-ulp step); a caller computes the other lanes with the
//! scalar function. Products need a fused multiply-add for their error term: on targets
//! without one every product mask is clear.

use super::{f64x4, splat, two_sum};
use crate::round::tight::TINY;
use wide::{bytemuck, i64x4};

/// `f64::next_up` per lane, for finite nonzero lanes and `-inf` (bits one step away
/// from zero for a positive lane, towards zero for a negative one).
#[inline(always)]
pub fn next_up(s: f64x4) -> f64x4 {
    let b: i64x4 = bytemuck::cast(s);
    let neg = i64x4::splat(0).simd_gt(b);
    bytemuck::cast(b + (neg | i64x4::splat(1)))
}

/// `f64::next_down` per lane, for finite nonzero lanes and `+inf`.
#[inline(always)]
pub fn next_down(s: f64x4) -> f64x4 {
    -next_up(-s)
}

/// `round::add_lo(a, b)` where the mask is set: the rounded sum, one ulp down where
/// Knuth's error term is negative. The mask is clear where the sum or its error term
/// is not finite. (A sum that rounds to 0 is exact, so a zero lane is never stepped.)
#[inline(always)]
pub fn add_lo(a: f64x4, b: f64x4) -> (f64x4, f64x4) {
    let (s, e) = two_sum(a, b);
    let ok = s.is_finite() & e.is_finite();
    (e.simd_lt(splat(0.0)).select(next_down(s), s), ok)
}

/// `round::add_hi(a, b)` where the mask is set: `-add_lo(-a, -b)`, as the scalar.
#[inline(always)]
pub fn add_hi(a: f64x4, b: f64x4) -> (f64x4, f64x4) {
    let (s, ok) = add_lo(-a, -b);
    (-s, ok)
}

/// Whether products have an exact error term in lanes (a fused multiply-add).
const FUSED: bool = cfg!(all(target_feature = "avx", target_feature = "fma"));

/// `round::mul_lo(a, b)` where the mask is set: the rounded product, one ulp down where
/// its exact error `fma(a, b, -p)` is negative. The mask is clear where the product is
/// not finite or below `2^-960` in magnitude (zeros, underflow: the scalar's other
/// branches), and everywhere on targets without a fused multiply-add.
#[inline(always)]
pub fn mul_lo(a: f64x4, b: f64x4) -> (f64x4, f64x4) {
    let (p, e, ok) = product(a, b);
    (e.simd_lt(splat(0.0)).select(next_down(p), p), ok)
}

/// The rounded product, its exact error and the common-path mask of [`mul_lo`].
#[inline(always)]
fn product(a: f64x4, b: f64x4) -> (f64x4, f64x4, f64x4) {
    let p = a * b;
    let ok = if FUSED {
        p.is_finite() & p.abs().simd_ge(splat(TINY))
    } else {
        splat(0.0)
    };
    (p, a.mul_add(b, -p), ok)
}

/// `round::mul_hi(a, b)` where the mask is set: `-mul_lo(-a, b)`, as the scalar.
#[inline(always)]
pub fn mul_hi(a: f64x4, b: f64x4) -> (f64x4, f64x4) {
    let (p, ok) = mul_lo(-a, b);
    (-p, ok)
}

/// `(round::mul_lo(a, b), round::mul_hi(a, b))` where the mask is set, from one
/// product and one error term (as the scalar `round::mul_lo_hi`).
#[inline(always)]
pub fn mul_lo_hi(a: f64x4, b: f64x4) -> (f64x4, f64x4, f64x4) {
    let (p, e, ok) = product(a, b);
    let zero = splat(0.0);
    let lo = e.simd_lt(zero).select(next_down(p), p);
    let hi = e.simd_gt(zero).select(next_up(p), p);
    (lo, hi, ok)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::round;

    fn samples() -> Vec<f64> {
        let mut v = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.1,
            -0.3,
            3.0,
            1e-300,
            -1e-310,
            f64::MIN_POSITIVE,
            f64::MAX,
            -f64::MAX,
            1e308,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::EPSILON,
            1.0 + f64::EPSILON,
            7.0 / 3.0,
            -2.0f64.powi(-480),
        ];
        let mut x = 0.7f64;
        for _ in 0..40 {
            x = (x * 3.7 + 0.123).fract();
            v.push((x - 0.5) * 10f64.powi((x * 40.0) as i32 - 20));
        }
        v
    }

    /// Every masked lane is bit for bit the scalar bound, and the common cases are
    /// masked (so the vector path is taken at all).
    #[test]
    fn masked_lanes_match_the_scalar_bounds() {
        let s = samples();
        type Lane = fn(f64x4, f64x4) -> (f64x4, f64x4);
        type Scalar = fn(f64, f64) -> f64;
        let ops: [(Lane, Scalar, bool); 4] = [
            (add_lo, round::add_lo, false),
            (add_hi, round::add_hi, false),
            (mul_lo, round::mul_lo, true),
            (mul_hi, round::mul_hi, true),
        ];
        for (lanes, scalar, product) in ops {
            let mut masked = 0;
            for a in s.chunks(4).filter(|c| c.len() == 4) {
                for &b in &s {
                    let av = f64x4::new([a[0], a[1], a[2], a[3]]);
                    let (got, ok) = lanes(av, splat(b));
                    let (got, ok) = (got.to_array(), ok.to_array());
                    for k in 0..4 {
                        if ok[k] != 0.0 {
                            masked += 1;
                            let want = scalar(a[k], b);
                            assert_eq!(got[k].to_bits(), want.to_bits(), "{} {}", a[k], b);
                        }
                    }
                }
            }
            if !product || FUSED {
                assert!(masked > 1000, "{masked} lanes took the vector path");
            }
        }
        for a in s.chunks(4).filter(|c| c.len() == 4) {
            for &b in &s {
                let (lo, hi, ok) = mul_lo_hi(f64x4::new([a[0], a[1], a[2], a[3]]), splat(b));
                let (l1, ok1) = mul_lo(f64x4::new([a[0], a[1], a[2], a[3]]), splat(b));
                let (h1, _) = mul_hi(f64x4::new([a[0], a[1], a[2], a[3]]), splat(b));
                for k in 0..4 {
                    assert_eq!(ok.to_array()[k].to_bits(), ok1.to_array()[k].to_bits());
                    if ok.to_array()[k] != 0.0 {
                        assert_eq!(lo.to_array()[k].to_bits(), l1.to_array()[k].to_bits());
                        assert_eq!(hi.to_array()[k].to_bits(), h1.to_array()[k].to_bits());
                    }
                }
            }
        }
    }

    #[test]
    fn steps_match_next_up_and_down() {
        for x in [1.0, -1.0, 5e-324, -5e-324, f64::MAX, -f64::MAX, 0.1, -7.5] {
            let v = next_up(splat(x)).to_array()[0];
            assert_eq!(v.to_bits(), x.next_up().to_bits(), "{x}");
            let v = next_down(splat(x)).to_array()[0];
            assert_eq!(v.to_bits(), x.next_down().to_bits(), "{x}");
        }
    }
}
