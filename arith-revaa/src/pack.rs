//! [`RevAaX4`]: four revised affine forms in SIMD registers, one lane each: four ray
//! forms ([`RevAa1x4`]) or four cell forms ([`RevAa3x4`]).
//!
//! The affine operations are the reduced forms' shared ones
//! ([`arith_core::simd::ReducedX4`]); this module gives RevAA's own product (with its
//! `½ Σ xi yi` centre shift and cross terms) and square in lanes: the scalar form's
//! `f64` operations in the same order with the same selects, so each lane is bit for bit
//! the scalar `RevAa<N>` (NaN signs and payloads aside) and inherits its soundness proof.
//! On a model of squares and products (the decocube) one packed evaluation costs about
//! 1.6-1.8 scalar ones.

use crate::{RevAa, RevAaArith};
use arith_core::affine_round::{k_mul, sqr_margin, TINY};
use arith_core::round::U;
use arith_core::simd::{splat, up_abs, ReducedLanes, ReducedX4};

/// Four [`RevAa<N>`] forms in SIMD lanes.
pub type RevAaX4<const N: usize> = ReducedX4<N, RevAa<N>>;

/// Four ray forms ([`RevAa<1>`]).
pub type RevAa1x4 = RevAaX4<1>;
/// Four cell forms ([`RevAa<3>`]).
pub type RevAa3x4 = RevAaX4<3>;

impl ReducedLanes for RevAaArith {
    #[inline(always)]
    fn mul_x4<const N: usize>(x: RevAaX4<N>, y: RevAaX4<N>) -> RevAaX4<N> {
        mul_forms(x, y)
    }
    /// The scalar `sqr`: the Chebyshev square where its gain survives and its bound is
    /// finite, else `x * x` (both computed, then the same choice per lane).
    #[inline(always)]
    fn sqr_x4<const N: usize>(x: RevAaX4<N>) -> RevAaX4<N> {
        let w = x.rad_dir();
        let s2 = x.xs.iter().fold(splat(0.0), |s, c| s + *c * *c);
        let m = x.x0.abs() + w;
        let gain = (w * w - s2).simd_gt(splat(sqr_margin(N)) * (m * m) + splat(TINY));
        let cheb = x.cheb_sqr(w);
        RevAaX4::select(gain & cheb.e.is_finite(), cheb, mul_forms(x, x))
    }
}

/// The scalar `mul_forms` with its cross terms, the same sums in the same order, zeros
/// included (`0 + q` is not `q` for `q = -0`). Where the scalar form skips the cross
/// terms (each exactly 0), adding them changes no bit.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // several arrays indexed together
fn mul_forms<const N: usize>(x: RevAaX4<N>, y: RevAaX4<N>) -> RevAaX4<N> {
    let zero = splat(0.0);
    let p0 = x.x0 * y.x0;
    let (mut d, mut diag, mut u, mut v) = (zero, zero, zero, zero);
    let mut r = p0.abs();
    let mut xs = [zero; N];
    for i in 0..N {
        let q = x.xs[i] * y.xs[i];
        d += q;
        diag += q.abs();
        let a = x.x0 * y.xs[i];
        let b = x.xs[i] * y.x0;
        xs[i] = a + b;
        r += q.abs() + d.abs() + a.abs() + b.abs() + xs[i].abs();
        u += x.xs[i].abs();
        v += y.xs[i].abs();
    }
    let mut off = zero;
    for i in 0..N {
        for j in i + 1..N {
            let a = x.xs[i] * y.xs[j];
            let b = x.xs[j] * y.xs[i];
            let s = a + b;
            off += s.abs();
            r += a.abs() + b.abs() + s.abs();
        }
    }
    let hd = splat(0.5) * d;
    let x0 = p0 + hd;
    let r = r + (hd.abs() + x0.abs());
    let main =
        x.e * y.e + y.e * (x.x0.abs() + u) + x.e * (y.x0.abs() + v) + splat(0.5) * diag + off;
    RevAaX4::new(x0, xs, up_abs(main + splat(U) * r, k_mul(N)))
}
