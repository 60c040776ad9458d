//! `exp`, `ln`, `sin` and `cos` in lanes, with proven error bounds, and their
//! enclosures.
//!
//! The functions use only round-to-nearest operations (`+ - * / fma`, and the exact
//! [`Isa::scale_pow2`] and [`Isa::split_pow2`]), so every path computes the same bits,
//! and so do the one-`f64` forms [`exp_f64`], [`ln_f64`], [`sin_f64`] and [`cos_f64`],
//! which `f64`'s [`crate::Real`] functions use within these domains: a point
//! evaluated alone and in lanes gives the same number. Each is within
//! [`ELEMENTARY_REL`] (relative) of the exact value where it is defined here; the
//! enclosures widen a computed value `v` by `|v| LIBM_REL + ETA`, the margin the scalar
//! arithmetic allows libm ([`crate::round::libm_enclose`]), which this bound, unlike
//! libm's, is proven to satisfy. Lanes outside the domains below get some value; the
//! kernels redo them through the scalar functions.
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
//! ## `sin(x)` and `cos(x)` for `|x| <= TRIG_MAX_ARG` (`10^5`)
//!
//! `k = round(x 2/pi)` (`|k| <= 2^17`), `r = x - k pi/2` in three steps with fdlibm's
//! 33-bit parts `PIO2_1 + PIO2_2 + PIO2_3` of `pi/2`, then `sin r` or `cos r` by
//! their Taylor polynomials (to `r^17` and `r^18`) in `z = r^2`, picked and signed by
//! `k mod 4` (`cos x = sin(x + pi/2)`: the quadrant `k + 1`).
//!
//! - Reduction. `k x 2/pi` is within `0.5 + 1.4e-11` of `k`, so `|r*| <= 0.7854`
//!   (`r* = x - k pi/2`). `k PIO2_i` is exact (`17 + 33` bits). `r1 = x - k PIO2_1`
//!   (one fma) is exact: for `k = 0` it is `x`; else `|x| >= 0.785`, `x` and
//!   `k PIO2_1` are multiples of `2^-53`, and `|r1| < 1`. The two further fmas round:
//!   with `T = pi/2 - PIO2_1 - PIO2_2 - PIO2_3` (`|T| <= 8.5e-32`, fdlibm's
//!   `pio2_3t`), `|r - r*| <= 2.0001 u |r*| + u |k PIO2_3| + |k T| <= 2.0001 u |r*| +
//!   1.2e-26`. Hence `|sin r - sin r*| <= 2.23 u |sin r*| + 1.2e-26` (as
//!   `|r*| <= 1.111 |sin r*|`) and `|cos r - cos r*| <= 0.71 (2.0001 u 0.7854 +
//!   1.2e-26)`, relative to `cos r* >= 0.707`: `1.58 u` and `1.3e-26` absolute.
//! - `sin r = r + (r z) S(z)` with `S(z) = sum_{n=1..8} (-1)^n z^(n-1) / (2n+1)!`
//!   (Horner, fmas), `|r| <= 0.78541`, `z <= 0.6169`: truncation below `0.001 u`
//!   relative; `S` in `[-0.1667, -0.1615]` is within `u (0.1667 + 0.1667 + 0.0052
//!   + 0.006 + ...) <= 0.36 u` (its rounding, the coefficients', the inner terms' and
//!   `z`'s), `2.3 u` relative; `r z` rounds once, so `(r z) S` is within `3.3 u` of its
//!   value, which is at most `0.1028 |r| <= 0.1142 |sin r|`; the last fma rounds by `u`:
//!   in all `<= 1.38 u` relative.
//! - `cos r = 1 + z C(z)`, `C(z) = sum_{n=1..9} (-1)^n z^(n-1) / (2n)!` in
//!   `[-0.5, -0.474]`: `z`'s rounding moves `z C` by `<= 0.31 u`, `C`'s errors
//!   (`<= 0.54 u`) by `<= 0.33 u`, the fma rounds by `<= u`: `1.64 u` absolute, `2.32 u`
//!   relative to `cos r >= 0.707`; truncation `<= 3.3e-21`, below `0.001 u`.
//!
//! In all `|sin_lanes(x) - sin x| <= 3.9 u |sin x| + |k| 8.6e-32`, and likewise for
//! `cos` (the reduction's absolute error is `|k| (u |PIO2_3| + |T|)`, 0 for `k = 0`).
//! Where `z` or the products underflow (`k = 0` and `|x| < 2^-510`), each of the three
//! roundings involved is off by at most `ETA / 2` more, and the terms the polynomial
//! then drops are below `u |x|`: at most `2 ETA` in addition.
//!
//! ## The enclosures
//!
//! A computed `v` with `|v - f| <= 8.3 u |f|` has `|v - f| <= 8.3 u |v| / (1 - 8.3 u)
//! < 16 u |v| = LIBM_REL |v|`, so `[v - m, v + m]` with `m = |v| LIBM_REL + ETA`
//! (`|v| LIBM_REL` is exact or, for subnormal products, covered by `ETA`; the rounded
//! sum is at least the exact one's first term) holds `f`, and so does its directed
//! rounding outward. [`ELEMENTARY_REL`] is that `8.3 u`, rounded up to `9 u`. For
//! `sin` and `cos`, `|v - f| <= 3.9 u |f| + a` (`a = |k| 8.6e-32 + 2 ETA`) gives
//! `|v - f| < 16 u |v| + 2 a`, and the margin is `|v| LIBM_REL + |k| 2^-100 + 4 ETA`,
//! computed with upward rounding (at most [`TRIG_ABS`] more than `|v| LIBM_REL`).

use super::emulated::{scale_pow2, split_pow2};
use super::Isa;
use crate::round::{ETA, LIBM_REL, U};

/// A bound of the relative error of [`exp`] and [`ln`] in their domains (see the
/// module documentation): `9 u`, within the `16 u` of [`LIBM_REL`].
pub const ELEMENTARY_REL: f64 = 9.0 * U;

/// The largest `|x|` for which [`exp`] is proven.
pub const EXP_MAX_ARG: f64 = 700.0;

/// The largest `|x|` for which [`sin`] and [`cos`] are proven.
pub const TRIG_MAX_ARG: f64 = 1.0e5;

/// The largest absolute term the enclosures of [`sin`] and [`cos`] add to the relative
/// one, over their domain: `2^-84` (at most `|k| 2^-100 + 4 ETA`, `|k| < 2^16`).
pub const TRIG_ABS: f64 = 5.169_878_828_456_423e-26;

/// `2/pi`, rounded.
const FRAC_2_PI: f64 = core::f64::consts::FRAC_2_PI;
/// `pi/2` in three parts of 33 significant bits (fdlibm's `pio2_1`, `pio2_2`, `pio2_3`).
const PIO2_1: f64 = f64::from_bits(0x3ff9_21fb_5440_0000);
const PIO2_2: f64 = f64::from_bits(0x3dd0_b461_1a60_0000);
const PIO2_3: f64 = f64::from_bits(0x3ba3_198a_2e00_0000);

/// `(-1)^n / (2n+1)!` for `n = 8` down to `1`.
const SIN_COEFFS: [f64; 8] = [
    1.0 / 355_687_428_096_000.0,
    -1.0 / 1_307_674_368_000.0,
    1.0 / 6_227_020_800.0,
    -1.0 / 39_916_800.0,
    1.0 / 362_880.0,
    -1.0 / 5040.0,
    1.0 / 120.0,
    -1.0 / 6.0,
];

/// `(-1)^n / (2n)!` for `n = 9` down to `1`.
const COS_COEFFS: [f64; 9] = [
    -1.0 / 6_402_373_705_728_000.0,
    1.0 / 20_922_789_888_000.0,
    -1.0 / 87_178_291_200.0,
    1.0 / 479_001_600.0,
    -1.0 / 3_628_800.0,
    1.0 / 40_320.0,
    -1.0 / 720.0,
    1.0 / 24.0,
    -0.5,
];

/// `log2(e)`, rounded.
const LOG2_E: f64 = core::f64::consts::LOG2_E;
/// `ln 2` with 32 significant bits (fdlibm's `ln2_hi`).
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
/// `ln 2 - LN2_HI`, rounded (fdlibm's `ln2_lo`).
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);
/// `1.5 * 2^52`: adding and subtracting it rounds to an integer.
const SHIFT: f64 = 6_755_399_441_055_744.0;

/// `1/k!` for `k = 13` down to `0`, rounded: `exp`'s Taylor coefficients in Horner's
/// order (the first 13 are those of `(e^w - 1) / w = sum_k w^k / (k + 1)!` to `w^12`).
pub const EXP_COEFFS: [f64; 14] = [
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

/// The round-to-nearest operations the functions are written in: a lane path's
/// ([`Isa`]), or those of one `f64` ([`One`]). Every operation is an IEEE operation
/// rounded to nearest or exact, so one `f64` gets, bit for bit, what each lane gets.
trait Ops: Copy {
    type V: Copy;
    type M: Copy;
    fn splat(self, c: f64) -> Self::V;
    fn add(self, a: Self::V, b: Self::V) -> Self::V;
    fn sub(self, a: Self::V, b: Self::V) -> Self::V;
    fn mul(self, a: Self::V, b: Self::V) -> Self::V;
    fn div(self, a: Self::V, b: Self::V) -> Self::V;
    fn fma(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V;
    fn neg(self, a: Self::V) -> Self::V;
    fn abs(self, a: Self::V) -> Self::V;
    fn eq(self, a: Self::V, b: Self::V) -> Self::M;
    fn or(self, a: Self::M, b: Self::M) -> Self::M;
    fn select(self, m: Self::M, a: Self::V, b: Self::V) -> Self::V;
    fn scale_pow2(self, a: Self::V, k: Self::V) -> Self::V;
    fn split_pow2(self, x: Self::V) -> (Self::V, Self::V);
}

impl<I: Isa> Ops for I {
    type V = I::V;
    type M = I::M;
    #[inline(always)]
    fn splat(self, c: f64) -> I::V {
        Isa::splat(self, c)
    }
    #[inline(always)]
    fn add(self, a: I::V, b: I::V) -> I::V {
        Isa::add(self, a, b)
    }
    #[inline(always)]
    fn sub(self, a: I::V, b: I::V) -> I::V {
        Isa::sub(self, a, b)
    }
    #[inline(always)]
    fn mul(self, a: I::V, b: I::V) -> I::V {
        Isa::mul(self, a, b)
    }
    #[inline(always)]
    fn div(self, a: I::V, b: I::V) -> I::V {
        Isa::div(self, a, b)
    }
    #[inline(always)]
    fn fma(self, a: I::V, b: I::V, c: I::V) -> I::V {
        Isa::fma(self, a, b, c)
    }
    #[inline(always)]
    fn neg(self, a: I::V) -> I::V {
        Isa::neg(self, a)
    }
    #[inline(always)]
    fn abs(self, a: I::V) -> I::V {
        Isa::abs(self, a)
    }
    #[inline(always)]
    fn eq(self, a: I::V, b: I::V) -> I::M {
        Isa::eq(self, a, b)
    }
    #[inline(always)]
    fn or(self, a: I::M, b: I::M) -> I::M {
        Isa::or(self, a, b)
    }
    #[inline(always)]
    fn select(self, m: I::M, a: I::V, b: I::V) -> I::V {
        Isa::select(self, m, a, b)
    }
    #[inline(always)]
    fn scale_pow2(self, a: I::V, k: I::V) -> I::V {
        Isa::scale_pow2(self, a, k)
    }
    #[inline(always)]
    fn split_pow2(self, x: I::V) -> (I::V, I::V) {
        Isa::split_pow2(self, x)
    }
}

/// One `f64`, with the emulated path's operations on one lane.
#[derive(Clone, Copy)]
struct One;

impl Ops for One {
    type V = f64;
    type M = bool;
    #[inline(always)]
    fn splat(self, c: f64) -> f64 {
        c
    }
    #[inline(always)]
    fn add(self, a: f64, b: f64) -> f64 {
        a + b
    }
    #[inline(always)]
    fn sub(self, a: f64, b: f64) -> f64 {
        a - b
    }
    #[inline(always)]
    fn mul(self, a: f64, b: f64) -> f64 {
        a * b
    }
    #[inline(always)]
    fn div(self, a: f64, b: f64) -> f64 {
        a / b
    }
    #[inline(always)]
    fn fma(self, a: f64, b: f64, c: f64) -> f64 {
        a.mul_add(b, c)
    }
    #[inline(always)]
    fn neg(self, a: f64) -> f64 {
        -a
    }
    #[inline(always)]
    fn abs(self, a: f64) -> f64 {
        a.abs()
    }
    #[inline(always)]
    fn eq(self, a: f64, b: f64) -> bool {
        a == b
    }
    #[inline(always)]
    fn or(self, a: bool, b: bool) -> bool {
        a | b
    }
    #[inline(always)]
    fn select(self, m: bool, a: f64, b: f64) -> f64 {
        if m {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn scale_pow2(self, a: f64, k: f64) -> f64 {
        scale_pow2(a, k)
    }
    #[inline(always)]
    fn split_pow2(self, x: f64) -> (f64, f64) {
        split_pow2(x)
    }
}

/// `exp(x)` within [`ELEMENTARY_REL`] for `|x| <= EXP_MAX_ARG`.
#[inline(always)]
pub fn exp<I: Isa>(s: I, x: I::V) -> I::V {
    exp_in(s, x)
}

/// `exp` in `O`'s operations.
#[inline(always)]
fn exp_in<O: Ops>(s: O, x: O::V) -> O::V {
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
    ln_in(s, x)
}

/// `ln` in `O`'s operations.
#[inline(always)]
fn ln_in<O: Ops>(s: O, x: O::V) -> O::V {
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
/// [`exp_enclosure`] is `widen(exp(x))`; a caller that needs the value as well takes
/// both apart.
#[inline(always)]
pub fn widen<I: Isa>(s: I, v: I::V) -> (I::V, I::V) {
    let m = Isa::fma(
        s,
        Isa::abs(s, v),
        Isa::splat(s, LIBM_REL),
        Isa::splat(s, ETA),
    );
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

/// `sin(x)` (`cos`: `cos(x)`) within `3.9 u |f(x)| + |k| 8.6e-32 + 2 ETA` for
/// `|x| <= TRIG_MAX_ARG`, and `k`, the multiple of `pi/2` taken off `x`.
#[inline(always)]
fn trig<O: Ops>(s: O, x: O::V, cos: bool) -> (O::V, O::V) {
    let shift = s.splat(SHIFT);
    let k = s.sub(s.fma(x, s.splat(FRAC_2_PI), shift), shift);
    let nk = s.neg(k);
    let r = s.fma(nk, s.splat(PIO2_1), x);
    let r = s.fma(nk, s.splat(PIO2_2), r);
    let r = s.fma(nk, s.splat(PIO2_3), r);
    let z = s.mul(r, r);
    let mut t = s.splat(SIN_COEFFS[0]);
    for &c in &SIN_COEFFS[1..] {
        t = s.fma(z, t, s.splat(c));
    }
    let sin_r = s.fma(s.mul(r, z), t, r);
    let mut c = s.splat(COS_COEFFS[0]);
    for &k in &COS_COEFFS[1..] {
        c = s.fma(z, c, s.splat(k));
    }
    let cos_r = s.fma(z, c, s.splat(1.0));
    // The quadrant `q mod 4` as `q - 4 round(q / 4)`, in {-2, -1, 0, 1, 2}.
    let q = if cos { s.add(k, s.splat(1.0)) } else { k };
    let quarter = s.sub(s.fma(q, s.splat(0.25), shift), shift);
    let m = s.fma(quarter, s.splat(-4.0), q);
    let (one, two) = (s.splat(1.0), s.splat(2.0));
    let odd = s.eq(s.abs(m), one);
    let negative = s.or(s.eq(s.abs(m), two), s.eq(m, s.neg(one)));
    let v = s.select(odd, cos_r, sin_r);
    (s.select(negative, s.neg(v), v), k)
}

/// `sin(x)` within `3.9 u |sin x| + TRIG_ABS / 2` for `|x| <= TRIG_MAX_ARG`.
#[inline(always)]
pub fn sin<I: Isa>(s: I, x: I::V) -> I::V {
    trig(s, x, false).0
}

/// `cos(x)` within `3.9 u |cos x| + TRIG_ABS / 2` for `|x| <= TRIG_MAX_ARG`.
#[inline(always)]
pub fn cos<I: Isa>(s: I, x: I::V) -> I::V {
    trig(s, x, true).0
}

/// `2^-100`, the margin per multiple of `pi/2` taken off the argument.
const TRIG_PER_K: f64 = 7.888_609_052_210_118e-31;

/// Bounds of `sin(x)` (`cos`: `cos(x)`) for `|x| <= TRIG_MAX_ARG`: the value widened
/// by `|v| LIBM_REL + |k| 2^-100 + 4 ETA` (rounded up), rounded outward.
#[inline(always)]
pub fn trig_enclosure<I: Isa>(s: I, x: I::V, cos: bool) -> (I::V, I::V) {
    let (v, k) = trig(s, x, cos);
    let (per_k, eta4) = (Isa::splat(s, TRIG_PER_K), Isa::splat(s, 4.0 * ETA));
    let abs = Isa::fma(s, Isa::abs(s, k), per_k, eta4);
    let rel = s.mul_up_raw(Isa::abs(s, v), Isa::splat(s, LIBM_REL));
    let m = s.add_up_raw(rel, abs);
    (s.sub_down_raw(v, m), s.add_up_raw(v, m))
}

/// [`exp`] of one `f64`: the bits each lane of [`exp`] gets for `x` (within
/// [`ELEMENTARY_REL`] for `|x| <= EXP_MAX_ARG`; some value elsewhere).
#[inline]
pub fn exp_f64(x: f64) -> f64 {
    exp_in(One, x)
}

/// [`ln`] of one `f64`: the bits each lane of [`ln`] gets for `x` (within
/// [`ELEMENTARY_REL`] for positive normal `x`; some value elsewhere).
#[inline]
pub fn ln_f64(x: f64) -> f64 {
    ln_in(One, x)
}

/// [`sin`] of one `f64`: the bits each lane of [`sin`] gets for `x` (bounded as
/// [`sin`] for `|x| <= TRIG_MAX_ARG`; some value elsewhere).
#[inline]
pub fn sin_f64(x: f64) -> f64 {
    trig(One, x, false).0
}

/// [`cos`] of one `f64`: the bits each lane of [`cos`] gets for `x` (bounded as
/// [`cos`] for `|x| <= TRIG_MAX_ARG`; some value elsewhere).
#[inline]
pub fn cos_f64(x: f64) -> f64 {
    trig(One, x, true).0
}
