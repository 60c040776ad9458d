//! `exp` and `ln` in lanes, with proven error bounds, and their enclosures.
//!
//! Both functions use only round-to-nearest lane operations (`+ - * / fma`, and the
//! exact [`Isa::scale_pow2`] and [`Isa::split_pow2`]), so every path computes the same
//! bits. Each is within [`ELEMENTARY_REL`] (relative) of the exact value where it is
//! defined here; the enclosures widen a computed value `v` by `|v| LIBM_REL + ETA`,
//! the margin the scalar arithmetic allows libm ([`crate::round::libm_enclose`]), which
//! this bound, unlike libm's, is proven to satisfy. Lanes outside the domains below get
//! some value; the kernels redo them through the scalar functions.
//!
//! Notation: `u = 2^-53`, the unit roundoff; every rounded operation `o` gives
//! `o(1 + d)` with `|d| <= u` (no underflow occurs in the domains below).
//!
//! ## `exp(x)` for `|x| <= EXP_MAX_ARG` (700)
//!
//! `k = round(x log2(e))` (through the `1.5 * 2^52` shift, an integer with
//! `|k| <= 1010`), `r = x - k ln 2` in two steps, `exp(r)` by its Taylor polynomial of
//! degree 13 in Horner's form with fused multiply-adds, then `* 2^k` (exact: the result
//! lies in `[e^-700 (1 - 4u), e^700 (1 + 4u)]`, normal).
//!
//! - Reduction. `LN2_HI` has 32 significant bits, so `k LN2_HI` is exact; `r_hi =
//!   x - k LN2_HI` (one fma) is exact too: for `k = 0` it is `x`; otherwise
//!   `|x| >= 0.3466 > 1/4`, so `x` and `k LN2_HI` are multiples of `2^-54`, and
//!   `|r_hi| < 0.35 < 2^53 2^-54`. `r = fl(r_hi - k LN2_LO)` (one fma) has relative error
//!   `u`, and `|ln 2 - LN2_HI - LN2_LO| <= 2^-86`, so `|r - r*| <= u |r*| + 2^-75.9`
//!   where `r* = x - k ln 2`, `|r*| <= 0.3467`. Since `exp(r*) = exp(r) exp(r* - r)`,
//!   this costs a relative `0.35 u` (the absolute term is below `2^-23 u`).
//! - Truncation. `|exp(r) - T13(r)| <= |r|^14 / 14! e^|r| <= 5.9e-18`, relative to
//!   `exp(r) >= 0.707`: `0.08 u`. Rounding the coefficients `1/k!` (`k >= 3`) changes
//!   the polynomial by at most `u (e^0.3467 - 1 - 0.3467 - 0.3467^2/2) <= 0.008 u`.
//! - Horner. With `q_k = fma(r, q_{k+1}, c_k)`, the error of `q_0` is at most
//!   `u (1 + 14u) sum_k T_k` with `T_k = sum_{j >= k} 0.3467^j / j!` (the exact inner
//!   values times `|r|^k`): `u (1.4144 + 0.4144 + 0.0677 + 0.0076 + 0.0007 + ...)
//!   <= 1.91 u`, relative to `0.707`: `2.7 u`.
//!
//! In all `|exp_lanes(x) - exp(x)| <= 3.2 u exp(x)`.
//!
//! ## `ln(x)` for positive normal `x` (finite, `>= 2^-1022`)
//!
//! `x = m 2^e` with `m` in `[0.75, 1.5)` ([`Isa::split_pow2`], exact), `f = m - 1`
//! (exact by Sterbenz's lemma), `s = f / (m + 1)`, `ln m = 2 atanh(s) = 2 s h(s^2)` with
//! `h(z) = sum_{n <= 11} z^n / (2n + 1)` in Horner's form, then `e LN2_HI + (e LN2_LO +
//! 2 s h)` with two fmas.
//!
//! - `s`: two roundings, `s = s* (1 + t)`, `|t| <= 2.0001 u`, `|s*| <= 0.2`, so
//!   `z = s^2 <= 0.0401` carries a relative error below `5.01 u`.
//! - `h`: truncation `<= 0.0401^12 / 25 / (1 - 0.0401) <= 0.006 u`; the coefficients'
//!   rounding `<= 0.014 u`; Horner's rounding `<= u (1.014 + 0.0401 * 0.35 + ...)
//!   <= 1.03 u`; the error of `z` moves `h` by `<= h'(z) 5.01 u z <= 0.07 u`; `h >= 1`,
//!   so `h` is within `1.13 u` relative.
//! - `2 s h` (one rounding): within `(1 + 2.0001u)(1 + 1.13u)(1 + u) - 1 <= 4.14 u` of
//!   `ln m`, `|ln m| <= ln 1.5 = 0.4055`: absolute `<= 1.68 u`.
//! - For `e = 0` that is the result: relative `4.14 u`. Otherwise `|ln x| >= ln 4/3 =
//!   0.2877` (`e = -1`, `m` near 1.5, is the nearest to 0), `e LN2_HI` is exact
//!   (`|e| <= 1075`), `|ln 2 - LN2_HI - LN2_LO| <= 2^-86` costs `|e| 2^-86 <= 2^-75`, the
//!   fma `t = e LN2_LO + 2 s h` rounds by `<= u |t| <= u (0.4055 + |e| 2^-32)`, and the
//!   last fma by `u |ln x| (1 + 9u)`. Relative to `|ln x|`, which is at least
//!   `0.2877` and at least `|e| ln 2 - 0.4055`: `(1.68 + 0.41) u / 0.2877 + 1.001 u
//!   <= 8.3 u` (for `|e| >= 2` the terms in `|e|` are relatively smaller still).
//!
//! In all `|ln_lanes(x) - ln(x)| <= 8.3 u |ln(x)|`.
//!
//! ## The enclosures
//!
//! A computed `v` with `|v - f| <= 8.3 u |f|` has `|v - f| <= 8.3 u |v| / (1 - 8.3 u)
//! < 16 u |v| = LIBM_REL |v|`, so `[v - m, v + m]` with `m = |v| LIBM_REL + ETA`
//! (`|v| LIBM_REL` is exact or, for subnormal products, covered by `ETA`; the rounded
//! sum is at least the exact one's first term) holds `f`, and so does its directed
//! rounding outward. [`ELEMENTARY_REL`] is that `8.3 u`, rounded up to `9 u`.

use super::Isa;
use crate::round::{ETA, LIBM_REL, U};

/// A bound of the relative error of [`exp`] and [`ln`] in their domains (see the
/// module documentation): `9 u`, within the `16 u` of [`LIBM_REL`].
pub const ELEMENTARY_REL: f64 = 9.0 * U;

/// The largest `|x|` for which [`exp`] is proven.
pub const EXP_MAX_ARG: f64 = 700.0;

/// `log2(e)`, rounded.
const LOG2_E: f64 = core::f64::consts::LOG2_E;
/// `ln 2` with 32 significant bits (fdlibm's `ln2_hi`).
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
/// `ln 2 - LN2_HI`, rounded (fdlibm's `ln2_lo`).
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);
/// `1.5 * 2^52`: adding and subtracting it rounds to an integer.
const SHIFT: f64 = 6_755_399_441_055_744.0;

/// `1/k!` for `k = 13` down to `0`, rounded.
const EXP_COEFFS: [f64; 14] = [
    1.0 / 6_227_020_800.0,
    1.0 / 479_001_600.0,
    1.0 / 39_916_800.0,
    1.0 / 3_628_800.0,
    1.0 / 362_880.0,
    1.0 / 40_320.0,
    1.0 / 5040.0,
    1.0 / 720.0,
    1.0 / 120.0,
    1.0 / 24.0,
    1.0 / 6.0,
    0.5,
    1.0,
    1.0,
];

/// `1/(2n + 1)` for `n = 11` down to `0`, rounded.
const ATANH_COEFFS: [f64; 12] = [
    1.0 / 23.0,
    1.0 / 21.0,
    1.0 / 19.0,
    1.0 / 17.0,
    1.0 / 15.0,
    1.0 / 13.0,
    1.0 / 11.0,
    1.0 / 9.0,
    1.0 / 7.0,
    1.0 / 5.0,
    1.0 / 3.0,
    1.0,
];

/// `exp(x)` within [`ELEMENTARY_REL`] for `|x| <= EXP_MAX_ARG`.
#[inline(always)]
pub fn exp<I: Isa>(s: I, x: I::V) -> I::V {
    let shift = s.splat(SHIFT);
    let k = s.sub(s.fma(x, s.splat(LOG2_E), shift), shift);
    let r = s.fma(s.neg(k), s.splat(LN2_HI), x);
    let r = s.fma(s.neg(k), s.splat(LN2_LO), r);
    let mut q = s.splat(EXP_COEFFS[0]);
    for &c in &EXP_COEFFS[1..] {
        q = s.fma(r, q, s.splat(c));
    }
    s.scale_pow2(q, k)
}

/// `ln(x)` within [`ELEMENTARY_REL`] for positive normal `x`.
#[inline(always)]
pub fn ln<I: Isa>(s: I, x: I::V) -> I::V {
    let one = s.splat(1.0);
    let (m, e) = s.split_pow2(x);
    let sv = s.div(s.sub(m, one), s.add(m, one));
    let z = s.mul(sv, sv);
    let mut h = s.splat(ATANH_COEFFS[0]);
    for &c in &ATANH_COEFFS[1..] {
        h = s.fma(z, h, s.splat(c));
    }
    let l = s.mul(s.add(sv, sv), h);
    let t = s.fma(e, s.splat(LN2_LO), l);
    s.fma(e, s.splat(LN2_HI), t)
}

/// A lower and an upper bound of an exact value within [`ELEMENTARY_REL`] of `v`
/// (relative to the exact value): `v` widened by `|v| LIBM_REL + ETA`, rounded outward.
#[inline(always)]
fn widen<I: Isa>(s: I, v: I::V) -> (I::V, I::V) {
    let m = s.fma(s.abs(v), s.splat(LIBM_REL), s.splat(ETA));
    (s.sub_down_raw(v, m), s.add_up_raw(v, m))
}

/// Bounds of `exp(x)` for `|x| <= EXP_MAX_ARG`.
#[inline(always)]
pub fn exp_enclosure<I: Isa>(s: I, x: I::V) -> (I::V, I::V) {
    widen(s, exp(s, x))
}

/// Bounds of `ln(x)` for positive normal `x`.
#[inline(always)]
pub fn ln_enclosure<I: Isa>(s: I, x: I::V) -> (I::V, I::V) {
    widen(s, ln(s, x))
}
