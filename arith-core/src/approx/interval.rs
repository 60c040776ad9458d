//! Rigorous interval enclosures `{f(x) : x in [a, b]}` of the elementary functions.
//!
//! Interval arithmetic uses them as its `sqrt`, `exp`, `ln`, `sin` and `cos`, and every
//! approximation falls back to the constant approximation of one of them when its affine
//! part would overflow, so all arithmetics agree on these ranges. Monotone functions are
//! bounded at the ends (libm values widened by [`crate::round::LIBM_REL`], exact roots
//! and powers where representable); `sin` and `cos` add `±1` wherever an extremum may lie
//! inside (decided conservatively in [`super::periodic`]).

use super::bad;
use super::bounds::{pow_enc, recip_enc, sqrt_enc};
use super::periodic::{may_contain, Trig, TRIG_MAX_ARG};
use crate::round::libm_enclose;

/// Rigorous enclosure of `{x^n : x ∈ [a, b]}` (any integer `n`; `x^0 = 1`). For `n < 0`
/// and `0 ∈ [a, b]`: `(0, +inf)` for even `n`, the whole line for odd `n`.
pub fn range_powi(a: f64, b: f64, n: i32) -> (f64, f64) {
    const WHOLE: (f64, f64) = (f64::NEG_INFINITY, f64::INFINITY);
    if bad(a, b) {
        return WHOLE;
    }
    if n == 0 {
        return (1.0, 1.0);
    }
    let k = n.unsigned_abs();
    let even = k.is_multiple_of(2);
    if n > 0 {
        if !even || a >= 0.0 {
            return (pow_enc(a, k).0, pow_enc(b, k).1);
        }
        if b <= 0.0 {
            return (pow_enc(b, k).0, pow_enc(a, k).1);
        }
        return (0.0, pow_enc(a, k).1.max(pow_enc(b, k).1));
    }
    if a <= 0.0 && b >= 0.0 {
        return if even { (0.0, f64::INFINITY) } else { WHOLE };
    }
    // Magnitudes [ml, mh] > 0; |x|^-k ∈ [1/mh^k, 1/ml^k].
    let (ml, mh) = if a > 0.0 { (a, b) } else { (-b, -a) };
    let lo_pow = pow_enc(ml, k).0;
    let hi_pow = pow_enc(mh, k).1;
    let r_hi = if lo_pow > 0.0 {
        recip_enc(lo_pow).1
    } else {
        f64::INFINITY
    };
    let r_lo = recip_enc(hi_pow).0.max(0.0);
    if a < 0.0 && !even {
        (-r_hi, -r_lo)
    } else {
        (r_lo, r_hi)
    }
}

/// Rigorous enclosure of `{sqrt(max(x,0)) : x ∈ [a, b]}`.
pub fn range_sqrt(a: f64, b: f64) -> (f64, f64) {
    if bad(a, b) {
        return (0.0, f64::INFINITY);
    }
    if b <= 0.0 {
        return (0.0, 0.0);
    }
    let lo = if a <= 0.0 { 0.0 } else { sqrt_enc(a).0 };
    (lo, sqrt_enc(b).1)
}

/// Rigorous enclosure of `{e^x : x ∈ [a, b]}`. From the first float above
/// `ln(f64::MAX)` on, where `e^a` exceeds every float, the lower bound is `f64::MAX`
/// (the largest float not above `e^a`).
pub fn range_exp(a: f64, b: f64) -> (f64, f64) {
    if bad(a, b) {
        return (0.0, f64::INFINITY);
    }
    // The first float above ln(f64::MAX): `EXP_OVER - 1024 ln 2 > 2^-43 - 2^-44 > 0`
    // (`1024 LN_2` is exact, `|LN_2 - ln 2| <= 2^-54`), so `e^EXP_OVER > 2^1024 > MAX`.
    // There libm's `inf` would give `inf - inf`, a NaN lower bound, clipped to 0.
    const EXP_OVER: f64 = 709.782_712_893_384_1;
    let lo = if a >= EXP_OVER {
        f64::MAX
    } else {
        libm_enclose(a.exp()).0.max(0.0)
    };
    (lo, libm_enclose(b.exp()).1)
}

/// Rigorous enclosure of `{ln x : x ∈ [a, b]}` (`-inf` lower bound when `a <= 0`;
/// `(-inf, -inf)` when `b <= 0`, as `ln x = -inf` there).
pub fn range_ln(a: f64, b: f64) -> (f64, f64) {
    if bad(a, b) {
        return (f64::NEG_INFINITY, f64::INFINITY);
    }
    if b <= 0.0 {
        return (f64::NEG_INFINITY, f64::NEG_INFINITY);
    }
    let lo = if a <= 0.0 {
        f64::NEG_INFINITY
    } else {
        libm_enclose(a.ln()).0
    };
    (lo, libm_enclose(b.ln()).1)
}

/// Enclosure of a sine-like function over `[a, b]`: the ends (libm, widened) plus `1`/`-1`
/// when `[a, b]` may hold a maximum at `max_at + 2k*pi` / a minimum at `min_at + 2k*pi`.
fn range_trig(t: Trig, a: f64, b: f64, max_at: f64, min_at: f64) -> (f64, f64) {
    use core::f64::consts::TAU;
    if bad(a, b) || !(a.abs() <= TRIG_MAX_ARG && b.abs() <= TRIG_MAX_ARG) || b - a >= 6.2 {
        return (-1.0, 1.0);
    }
    let (fa, fb) = (t.f(a), t.f(b));
    let mut lo = fa.0.min(fb.0);
    let mut hi = fa.1.max(fb.1);
    if may_contain(a, b, max_at, TAU) {
        hi = 1.0;
    }
    if may_contain(a, b, min_at, TAU) {
        lo = -1.0;
    }
    (lo.max(-1.0), hi.min(1.0))
}

/// Rigorous enclosure of `{sin x : x ∈ [a, b]}` (`[-1, 1]` for `|x| > 1e7` or width `>= 6.2`).
pub fn range_sin(a: f64, b: f64) -> (f64, f64) {
    use core::f64::consts::FRAC_PI_2;
    range_trig(Trig::Sin, a, b, FRAC_PI_2, -FRAC_PI_2)
}

/// Rigorous enclosure of `{cos x : x ∈ [a, b]}` (`[-1, 1]` for `|x| > 1e7` or width `>= 6.2`).
pub fn range_cos(a: f64, b: f64) -> (f64, f64) {
    use core::f64::consts::PI;
    range_trig(Trig::Cos, a, b, 0.0, PI)
}

#[cfg(test)]
mod tests {
    use super::super::sqr;
    use super::super::tests::zero_width;
    use super::*;

    #[test]
    fn ranges_by_hand() {
        assert_eq!(range_powi(-2.0, 3.0, 2), (0.0, 9.0));
        assert_eq!(range_powi(-2.0, 3.0, 3), (-8.0, 27.0));
        assert_eq!(range_powi(-3.0, -2.0, 2), (4.0, 9.0));
        assert_eq!(range_powi(2.0, 4.0, -1), (0.25, 0.5));
        assert_eq!(range_powi(-4.0, -2.0, -1), (-0.5, -0.25));
        assert_eq!(range_powi(-2.0, -1.0, -2), (0.25, 1.0));
        assert_eq!(range_powi(-1.0, 1.0, -2), (0.0, f64::INFINITY));
        assert_eq!(
            range_powi(-1.0, 1.0, -1),
            (f64::NEG_INFINITY, f64::INFINITY)
        );
        assert_eq!(range_powi(-7.0, 5.0, 0), (1.0, 1.0));
        assert_eq!(range_sqrt(-1.0, 4.0), (0.0, 2.0));
        assert_eq!(range_sqrt(-2.0, -1.0), (0.0, 0.0));
        let (lo, hi) = range_exp(0.0, 1.0);
        let e = std::f64::consts::E;
        assert!(lo <= 1.0 && lo > 1.0 - 1e-14 && hi >= e && hi < e + 1e-14);
        let (lo, hi) = range_ln(0.0, 1.0);
        assert!(lo == f64::NEG_INFINITY && (0.0..1e-300).contains(&hi));
        assert_eq!(range_ln(-2.0, -1.0), (f64::NEG_INFINITY, f64::NEG_INFINITY));
        // sin on [0, 3]: contains pi/2, min at 0.
        let (lo, hi) = range_sin(0.0, 3.0);
        assert!(lo <= 0.0 && lo > -1e-300 && hi == 1.0);
        // sin on [4, 5]: contains 3pi/2; max sin(4) = -0.7568024953079283.
        let (lo, hi) = range_sin(4.0, 5.0);
        assert!(lo == -1.0 && (-0.7568024953079283..-0.7568024953079).contains(&hi));
        // cos on [1, 2]: monotone.
        let (lo, hi) = range_cos(1.0, 2.0);
        assert!(lo <= -0.4161468365471424 && lo > -0.41614683654715);
        assert!((0.5403023058681398..0.54030230586815).contains(&hi));
        assert_eq!(range_sin(0.0, 100.0), (-1.0, 1.0));
        assert_eq!(range_cos(1e8, 1e8 + 0.5), (-1.0, 1.0));
    }

    /// Extreme values are as tight as the shared tight bounds make them (these bounds
    /// used to be stepped outward unconditionally there): exact tiny products stay exact and
    /// infinite arguments give exact infinite bounds.
    #[test]
    fn extreme_values_stay_tight() {
        let t = 2f64.powi(-500);
        assert_eq!(range_powi(t, t, 2), (t * t, t * t));
        assert_eq!(sqr(t, t), zero_width(t * t));
        let inf = f64::INFINITY;
        assert_eq!(range_powi(inf, inf, 2), (inf, inf));
        assert_eq!(range_powi(-inf, -inf, 3), (-inf, -inf));
    }
}
