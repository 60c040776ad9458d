//! [`RaaX4`]: four reduced affine (AF1) forms in SIMD registers, one lane each: four ray
//! forms ([`Raa1x4`]) or four cell forms ([`Raa3x4`]).
//!
//! The affine operations are the reduced forms' shared ones
//! ([`arith_core::simd::ReducedX4`]); this module gives AF1's own product (the whole
//! quadratic term to the accumulator) and square in lanes: the scalar form's `f64`
//! operations in the same order with the same selects, so each lane is bit for bit the
//! scalar `Raa<N>` (NaN signs and payloads aside) and inherits its soundness proof.

use crate::{Raa, RaaArith};
use arith_core::affine_round::{k_mul, sqr_margin, TINY};
use arith_core::round::U;
use arith_core::simd::{splat, up_abs, ReducedLanes, ReducedX4};

/// Four [`Raa<N>`] forms in SIMD lanes.
pub type RaaX4<const N: usize> = ReducedX4<N, Raa<N>>;

/// Four ray forms ([`Raa<1>`]).
pub type Raa1x4 = RaaX4<1>;
/// Four cell forms ([`Raa<3>`]).
pub type Raa3x4 = RaaX4<3>;

impl ReducedLanes for RaaArith {
    /// The scalar AF1 product.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // several arrays indexed together
    fn mul_x4<const N: usize>(x: RaaX4<N>, y: RaaX4<N>) -> RaaX4<N> {
        let zero = splat(0.0);
        let x0 = x.x0 * y.x0;
        let (mut u, mut v) = (zero, zero);
        let mut r = x0.abs();
        let mut xs = [zero; N];
        for i in 0..N {
            let a = x.x0 * y.xs[i];
            let b = x.xs[i] * y.x0;
            xs[i] = a + b;
            r += a.abs() + b.abs() + xs[i].abs();
            u += x.xs[i].abs();
            v += y.xs[i].abs();
        }
        let main = x.x0.abs() * y.e + y.x0.abs() * x.e + (u + x.e) * (v + y.e);
        RaaX4::new(x0, xs, up_abs(main + splat(U) * r, k_mul(N)))
    }

    /// The scalar `sqr`: the Chebyshev square where its gain survives and its bound is
    /// finite, else `x * x` (both computed, then the same choice per lane).
    #[inline(always)]
    fn sqr_x4<const N: usize>(x: RaaX4<N>) -> RaaX4<N> {
        let w = x.rad_dir();
        let m = x.x0.abs() + w;
        let gain = (w * w).simd_gt(splat(sqr_margin(N)) * (m * m) + splat(TINY));
        let cheb = x.cheb_sqr(w);
        RaaX4::select(gain & cheb.e.is_finite(), cheb, Self::mul_x4(x, x))
    }
}
