//! Floating-point bookkeeping shared by the reduced (AF1) and revised affine forms
//! (centre, input-symbol coefficients, one nonnegative error term): every operation of
//! both crates bounds its rounding error with these helpers.
//!
//! We never change the rounding mode. Each operation computes its centre and
//! coefficients in round-to-nearest and bounds the rounding error it made; the error
//! terms (all `>= 0`) are summed in plain `f64` and that sum is then turned into a
//! guaranteed upper bound by [`up_rel`] or [`up_abs`].
//!
//! Facts used (binary64, round to nearest, `U = 2^-53`, `ETA = 2^-1074`):
//! - `fl(a + b)`: error `<= U * |fl(a + b)|`, and exact when `|a + b| < 2^-1021`
//!   (both operands are multiples of `ETA`); hence `fl(U * |fl(a + b)|)` is itself an
//!   upper bound of the error (no underflow loss: when the error can be non-zero,
//!   `ulp/2 >= ETA` is representable and `U*|z| >= ulp/2`).
//! - `fl(a * b)`, `fl(a / b)`: error `<= U * |result| + ETA/2` (the `ETA/2` for a
//!   subnormal result).
//! - A sum of `m` nonnegative terms computed left to right is `>= (1-U)^(m-1)` times the
//!   exact sum of the computed terms (no underflow loss in additions).

use crate::round::{step_down, step_up, two_sum, ETA, U};

/// `1 + 2(k+2)U`, exactly representable; `c_k (1-U)^(k+2) >= 1`.
#[inline(always)]
pub const fn slack(k: usize) -> f64 {
    1.0 + (2 * (k + 2)) as f64 * U
}

/// Upper bound of a nonnegative real `T`, given `s`, an `f64` left-to-right sum of
/// nonnegative terms, each computed term `>=` its exact target, with at most `k`
/// roundings on any chain (so `s >= (1-U)^k T`, and `s == T` exactly when `s` is
/// subnormal because then every partial sum was exact).
///
/// Returns exactly `0` for `s == 0`, which keeps `x - x` exactly `[0, 0]`.
#[inline(always)]
pub fn up_rel(s: f64, k: usize) -> f64 {
    // Normal product: fl(s c) >= s c (1-U) >= (1-U)^(k+1) c T >= T.
    // Subnormal: s == T and fl(s c) >= s since s is representable and s c >= s.
    s * slack(k)
}

/// Upper bound of a nonnegative real `T`, given `s >= 0` with
/// `s >= (1-U)^k T - k ETA` (products with possibly subnormal results lose up to
/// `ETA/2` each, counted in `k`).
#[inline(always)]
pub fn up_abs(s: f64, k: usize) -> f64 {
    // p = fl(s c) >= (1-U) s c - ETA/2; fl(p + (k+1)ETA) >= (1-U)(p + (k+1)ETA)
    // (exact below 2^-1021). Then r >= (1-U)^2 c s - ETA/2 + (1-U)(k+1/2)ETA
    //                                >= T - c k ETA + (1-U)(k+1/2) ETA >= T.
    s * slack(k) + (k + 1) as f64 * ETA
}

/// `fl(a + b)` rounded towards `+inf` only when it was inexact (tight: exact sums stay).
#[inline(always)]
pub fn add_dir_up(a: f64, b: f64) -> f64 {
    let (s, t) = two_sum(a, b);
    // A select, not a branch: the sign of `t` is data-dependent noise (mispredicted
    // branches made `bounds` a fifth of a CSG evaluation). `t > 0` only for a finite,
    // inexact `s` (an overflow gives a NaN `t`).
    let nu = step_up(s);
    if t > 0.0 {
        nu
    } else {
        s
    }
}

/// `fl(a + b)` rounded towards `-inf` only when it was inexact.
#[inline(always)]
pub fn add_dir_down(a: f64, b: f64) -> f64 {
    let (s, t) = two_sum(a, b);
    let nd = step_down(s);
    if t < 0.0 {
        nd
    } else {
        s
    }
}

/// The radius `Σ |xs[i]| + e` of a form, rounded up by directed steps (exact sums stay
/// exact): what `bounds` and the Chebyshev square's `W` use.
#[inline(always)]
pub fn rad_dir(xs: &[f64], e: f64) -> f64 {
    xs.iter().fold(e, |r, c| add_dir_up(r, c.abs()))
}

/// [`crate::Range::affine_part`] of `x0 + Σ xs[i] εi ± e`: the first `K` coefficients as
/// they are (0 past `xs`), the others' magnitudes added to `e` rounded up. `None` when a
/// value is not finite.
#[inline]
pub fn affine_at<const K: usize>(x0: f64, xs: &[f64], e: f64) -> Option<crate::AffinePart<K>> {
    let cs: [f64; K] = core::array::from_fn(|i| xs.get(i).copied().unwrap_or(0.0));
    let e = xs.iter().skip(K).fold(e, |r, c| add_dir_up(r, c.abs()));
    (x0.is_finite() && e.is_finite() && cs.iter().all(|c| c.is_finite()))
        .then_some(crate::AffinePart { x0, xs: cs, e })
}

/// The form `c0 + Σ cs[i] εi ± err` of `N` symbols for [`crate::Range::from_affine`]:
/// the coefficients as they are, those past `N` added to the error rounded up. `None`
/// when a value is not finite.
#[inline]
pub fn form_of<const N: usize>(c0: f64, cs: &[f64], err: f64) -> Option<(f64, [f64; N], f64)> {
    if !(c0.is_finite() && err.is_finite() && cs.iter().all(|c| c.is_finite())) {
        return None;
    }
    let xs = core::array::from_fn(|i| cs.get(i).copied().unwrap_or(0.0));
    let e = cs
        .iter()
        .skip(N)
        .fold(err.abs(), |r, c| add_dir_up(r, c.abs()));
    Some((c0, xs, e))
}

/// The directed bounds `x0 ∓ rad` of a form with radius `rad` (from [`rad_dir`]), the
/// whole line when one is not finite.
#[inline(always)]
pub fn bounds_dir(x0: f64, rad: f64) -> (f64, f64) {
    let lo = add_dir_down(x0, -rad);
    let hi = add_dir_up(x0, rad);
    if lo.is_finite() && hi.is_finite() {
        (lo, hi)
    } else {
        (f64::NEG_INFINITY, f64::INFINITY)
    }
}

/// `0 ∈ bounds_dir(x0, rad)` without the bounds: the directed `x0 - rad` is above 0
/// exactly when `x0 > rad` (a positive difference of two floats is at least the smallest
/// subnormal), and alike for `x0 + rad < 0`; the bound away from 0 is
/// `±add_dir_up(|x0|, rad)` (rounding is symmetric), and an overflowing or NaN one
/// makes the whole line.
#[inline(always)]
pub fn holds_zero(x0: f64, rad: f64) -> bool {
    let x = x0.abs();
    !(x > rad && add_dir_up(x, rad).is_finite())
}

/// The Chebyshev square of `x0 + Σ xs[i] εi ± e` for `w >= Σ|xs[i]| + e`: centre
/// `x0² + ½w²`, coefficients `2 x0 xs[i]`, error `2|x0| e + ½w²` plus its rounding
/// (the bound may overflow). Shared by the reduced and revised forms, whose `sqr`
/// documents the derivation.
#[inline(always)]
pub fn cheb_sqr<const N: usize>(x0: f64, xs: &[f64; N], e: f64, w: f64) -> (f64, [f64; N], f64) {
    let p0 = x0 * x0;
    let ww = w * w;
    let h = 0.5 * ww;
    let c0 = p0 + h;
    let tx0 = 2.0 * x0;
    let mut r = p0.abs() + ww + c0.abs();
    let mut zs = [0.0; N];
    for (z, c) in zs.iter_mut().zip(xs) {
        *z = tx0 * c;
        r += z.abs();
    }
    // h stands for ½W² in the radius; its own rounding (<= U ww/2 + ETA) is in r.
    let main = h + tx0.abs() * e;
    (c0, zs, up_abs(main + U * r, k_mul(N)))
}

/// Midpoint and radius of `[lo, hi]` (`lo <= hi`) with a bound on how far they are from
/// the real midpoint and radius: `|m - (lo+hi)/2| + |r - (hi-lo)/2| <= err`.
/// `err == 0` whenever both are exact (the usual case).
#[inline]
pub fn mid_rad(lo: f64, hi: f64) -> (f64, f64, f64) {
    let hl = 0.5 * lo;
    let hh = 0.5 * hi;
    // Halving is exact unless the result is subnormal; then it is off by <= ETA/2.
    let halving = if hl * 2.0 == lo && hh * 2.0 == hi {
        0.0
    } else {
        2.0 * ETA
    };
    let (m, tm) = two_sum(hl, hh);
    let (r, tr) = two_sum(hh, -hl);
    let err = add_dir_up(add_dir_up(tm.abs(), tr.abs()), halving);
    (m, r, err)
}

/// An enclosure of the form `x0 + Σ xs[i] εi ± e`, cheaper than the tight directed
/// bounds and up to a few ulps wider: `x0 ∓ rad` (`rad` rounded up) in round to nearest,
/// each end then moved out by `2U` of itself plus `ETA` (more than its rounding error
/// and the rounding of that move). For the domains of approximations, where an ulp of
/// slack is harmless; infinite `rad` gives infinite ends.
#[inline]
pub fn bounds_fast(x0: f64, xs: &[f64], e: f64) -> (f64, f64) {
    let rad = rad_up(xs, e);
    let (lo, hi) = (x0 - rad, x0 + rad);
    (
        lo - (lo.abs() * (2.0 * U) + ETA),
        hi + (hi.abs() * (2.0 * U) + ETA),
    )
}

/// A lower bound of `min |x|` over the form `x0 + Σ xs[i] εi ± e` (`0` when the range may
/// hold 0), without directed rounding: `|x0| - rad` with `rad` rounded up, the difference
/// (within `U` relative when positive) scaled down by `1 - 2U`.
#[inline]
pub fn mig_lower(x0: f64, xs: &[f64], e: f64) -> f64 {
    mig_below(x0, rad_up(xs, e))
}

/// An upper bound of the radius `Σ |xs[i]| + e` of a form, without directed rounding.
#[inline]
pub fn rad_up(xs: &[f64], e: f64) -> f64 {
    up_rel(xs.iter().fold(e, |s, c| s + c.abs()), xs.len() + 1)
}

/// [`mig_lower`] from the centre and an upper bound `rad` of the radius.
#[inline]
pub fn mig_below(x0: f64, rad: f64) -> f64 {
    let m = x0.abs() - rad;
    if m > 0.0 {
        m * (1.0 - 2.0 * U)
    } else {
        0.0
    }
}

/// `k` for the cheap `up_abs` calls of the linear operations with products
/// (scaling, unary approximations): generous, costs nothing at run time.
#[inline]
pub const fn k_lin(n: usize) -> usize {
    2 * n + 8
}

/// `k` for the multiplication and the square: covers the `O(n^2)` terms.
#[inline]
pub const fn k_mul(n: usize) -> usize {
    16 + 8 * n + 2 * n * n
}

/// Relative margin (times `(|x0| + W)²`) above which the Chebyshev square's gain in width
/// over `x * x` certainly survives the rounding allowances of both computations: each
/// adds at most `2(k+2)U` of a radius `<= 3(|x0|+W)²`, `U` times `<= 6(|x0|+W)²` of
/// rounded values, and the outward rounding of the bounds a few ulps more. We take
/// twice that.
#[inline]
pub const fn sqr_margin(n: usize) -> f64 {
    (16 * (k_mul(n) + 2) + 128) as f64 * U
}

/// Absolute floor for the same comparison: below it (values under about `1e-150`)
/// subnormal-range allowances dominate, and `x * x` is used.
pub const TINY: f64 = 1e-300;

#[cfg(test)]
mod tests {
    use super::*;

    /// `bounds_fast` and `mig_lower` against the tight directed bounds of the same forms:
    /// never inside them, and only a few ulps outside.
    #[test]
    fn fast_bounds_enclose_the_tight_ones() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for k in 0..20_000 {
            let scale = 10f64.powi((k % 40) - 20);
            let x0 = (next() - 0.5) * scale;
            let xs = [(next() - 0.5) * scale, (next() - 0.5) * scale * 1e-3];
            let e = next() * scale * if k % 3 == 0 { 0.0 } else { 1e-2 };
            let mut rad = e;
            for c in &xs {
                rad = add_dir_up(rad, c.abs());
            }
            let (tlo, thi) = (add_dir_down(x0, -rad), add_dir_up(x0, rad));
            let (lo, hi) = bounds_fast(x0, &xs, e);
            assert!(
                lo <= tlo && hi >= thi,
                "{x0} {xs:?} {e}: {lo} {hi} vs {tlo} {thi}"
            );
            let slack = 16.0 * U * (x0.abs() + rad) + 4.0 * ETA;
            assert!(tlo - lo <= slack && hi - thi <= slack, "too wide");
            let m = mig_lower(x0, &xs, e);
            let tight = if tlo > 0.0 {
                tlo
            } else if thi < 0.0 {
                -thi
            } else {
                0.0
            };
            assert!(m <= tight && m >= 0.0, "mig {m} vs {tight}");
        }
        let m = mig_lower(2.0, &[1.0], 0.5);
        assert!(m <= 0.5 && m > 0.5 - 1e-14, "{m}");
        assert_eq!(mig_lower(1.0, &[1.0], 0.5), 0.0);
    }
}
