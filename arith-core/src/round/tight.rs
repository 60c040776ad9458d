//! Tight directed bounds of one `+ - * /`: the floor (`_lo`) or ceiling (`_hi`) in `f64`
//! of the exact result, so exact operations stay exact.
//!
//! The rounded-to-nearest result is kept when an error-free transformation shows it is
//! already on the right side of the exact value, and moved one ulp outward otherwise
//! (one rounding is at most half an ulp off). Near underflow, where the error terms
//! themselves may be inexact, the check runs on operands scaled by `2^600`, so every
//! lower bound is exactly the floor (and every upper bound the ceiling) of the exact
//! result: tight, and monotone in the exact value (which keeps interval operations
//! inclusion-isotone). Interval arithmetic uses these for every bound, the affine
//! approximations for the bounds of `g(x) = f(x) - alpha*x` at chosen points.
//!
//! Edge cases, the same for every function here:
//! - an overflow of finite operands keeps the finite side (`f64::MAX` is a valid lower
//!   bound of a sum or product that rounded to `+inf`), the other bound is infinite;
//! - an infinite operand gives the exact extended-real result (`inf + 1 = inf` on both
//!   sides, `x / inf = ±0`);
//! - an undefined result (`inf - inf`, `0 * inf`, `inf / inf`, `x / 0`) is never NaN: a
//!   lower bound is then `-inf` and an upper bound `+inf`;
//! - a zero result keeps the sign IEEE gives the rounded operation for `_lo`
//!   (`fl(a + b)`, `fl(a * b)`), and for `_hi` the sign of `-(fl(-a + -b))`,
//!   `-(fl(-a * b))` (all upper bounds are negated lower bounds; `x + (-x)` is `+0` as a
//!   lower and `-0` as an upper bound). Both are the exact value `0`.

use super::{dekker_err, two_sum, ETA, EXACT_MIN, FACTOR_MIN, SPLIT_MAX};

/// Below this magnitude the error term of a product/quotient may not be representable,
/// so its sign cannot be trusted: we then scale first. (`2^-960`: for
/// `|a*b| >= 2^-960` the exact error `a*b - fl(a*b)` is a multiple of
/// `ulp(a)*ulp(b) >= 2^-1066` below `ulp(fl(a*b))`, hence an `f64`; likewise the division
/// remainder for `|a| >= 2^-960`.)
pub(crate) const TINY: f64 = f64::from_bits(63 << 52);

/// `2^600`: scales near-underflow operands into the range where the checks are exact.
const SCALE: f64 = f64::from_bits((1023 + 600) << 52);

#[inline]
fn finite2(a: f64, b: f64) -> bool {
    a.is_finite() && b.is_finite()
}

/// The exact error `a*b - p` of `p = fl(a*b)` for `|p| >= TINY` (see [`TINY`]): one FMA
/// where the target has it, Dekker's product where that is exact and `fma` would be a
/// library call, else the (software) FMA.
#[inline(always)]
fn exact_err(a: f64, b: f64, p: f64) -> f64 {
    let dekker_ok = p.abs() >= EXACT_MIN
        && (FACTOR_MIN..SPLIT_MAX).contains(&a.abs())
        && (FACTOR_MIN..SPLIT_MAX).contains(&b.abs());
    if cfg!(target_feature = "fma") || !dekker_ok {
        a.mul_add(b, -p)
    } else {
        dekker_err(a, b, p)
    }
}

/// Floor of `a + b` in `f64`; `-inf` when undefined (`inf - inf`, NaN).
#[inline]
pub fn add_lo(a: f64, b: f64) -> f64 {
    let s = a + b;
    if s.is_finite() {
        let (_, mut e) = two_sum(a, b);
        if !e.is_finite() {
            // An intermediate of the error term overflowed (`a`, `b` near `f64::MAX`):
            // the halves' sum is exactly half of it, rounding included (halving is
            // exact at these magnitudes), so its error has the same sign.
            e = two_sum(0.5 * a, 0.5 * b).1;
        }
        // A select, not a branch: the sign of `e` is data-dependent noise, and a
        // mispredicted branch cost more than the whole sum (profile of the CSG model).
        let dn = s.next_down();
        if e < 0.0 {
            dn
        } else {
            s
        }
    } else if s == f64::INFINITY && finite2(a, b) {
        f64::MAX
    } else if s.is_nan() {
        f64::NEG_INFINITY
    } else {
        s
    }
}

/// Ceiling of `a + b` in `f64`; `+inf` when undefined.
#[inline]
pub fn add_hi(a: f64, b: f64) -> f64 {
    -add_lo(-a, -b)
}

/// Floor of `a - b` in `f64`; `-inf` when undefined.
#[inline]
pub fn sub_lo(a: f64, b: f64) -> f64 {
    add_lo(a, -b)
}

/// Ceiling of `a - b` in `f64`; `+inf` when undefined.
#[inline]
pub fn sub_hi(a: f64, b: f64) -> f64 {
    add_hi(a, -b)
}

/// Floor of `a * b` in `f64`; `-inf` when undefined (`0 * inf`, NaN).
#[inline]
pub fn mul_lo(a: f64, b: f64) -> f64 {
    let p = a * b;
    if p.is_nan() {
        return f64::NEG_INFINITY;
    }
    if p.is_infinite() {
        return if p > 0.0 && finite2(a, b) {
            f64::MAX
        } else {
            p
        };
    }
    if a == 0.0 || b == 0.0 {
        return p;
    }
    // e = a*b - p exactly (see TINY); near underflow, on a copy scaled by 2^600.
    let e = if p.abs() >= TINY {
        exact_err(a, b, p)
    } else if p == 0.0 {
        // Underflow to zero: the exact product is a nonzero tiny of the operands' sign.
        return if (a > 0.0) == (b > 0.0) { 0.0 } else { -ETA };
    } else {
        // Scale the smaller factor (|.| < 2^-480 as |a*b| < 2^-960): all exact.
        let (s, t) = if a.abs() <= b.abs() { (a, b) } else { (b, a) };
        (s * SCALE).mul_add(t, -(p * SCALE))
    };
    // Select rather than branch, as in `add_lo`.
    let dn = p.next_down();
    if e < 0.0 {
        dn
    } else {
        p
    }
}

/// Ceiling of `a * b` in `f64`; `+inf` when undefined.
#[inline]
pub fn mul_hi(a: f64, b: f64) -> f64 {
    -mul_lo(-a, b)
}

/// `(mul_lo(a, b), mul_hi(a, b))` with one product and one error term where both need
/// them (bit for bit the same pair).
#[inline]
pub fn mul_lo_hi(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    // Finite and at least TINY: both factors finite and nonzero, the error term exact.
    if p.is_finite() && p.abs() >= TINY {
        let e = exact_err(a, b, p);
        // Selects rather than branches: the sign of `e` is data-dependent noise.
        let (dn, up) = (p.next_down(), p.next_up());
        (if e < 0.0 { dn } else { p }, if e > 0.0 { up } else { p })
    } else {
        (mul_lo(a, b), mul_hi(a, b))
    }
}

/// Floor of `a / b` in `f64`; `-inf` when undefined (`b == 0`, `inf / inf`, NaN).
#[inline]
pub fn div_lo(a: f64, b: f64) -> f64 {
    if b == 0.0 {
        return f64::NEG_INFINITY;
    }
    let q = a / b;
    if q.is_nan() {
        return f64::NEG_INFINITY;
    }
    if q.is_infinite() {
        return if q > 0.0 && finite2(a, b) {
            f64::MAX
        } else {
            q
        };
    }
    if a == 0.0 || !finite2(a, b) {
        // 0 / b and finite / inf are exact (the latter as a limit: the corners of an
        // unbounded interval quotient).
        return q;
    }
    if q == 0.0 {
        return if (a > 0.0) == (b > 0.0) { 0.0 } else { -ETA };
    }
    // r = a - q*b exactly (see TINY), on copies scaled by 2^600 near underflow; then
    // a/b - q has the sign of r/b.
    let r = if q.abs() >= TINY && a.abs() >= TINY {
        (-q).mul_add(b, a)
    } else if q.abs() >= TINY {
        // a tiny, q not: b is small too; scaling both keeps q.
        (-q).mul_add(b * SCALE, a * SCALE)
    } else {
        // q tiny: |a| < 2^64 here, so a*2^600 and q*2^600 are exact and finite.
        (-(q * SCALE)).mul_add(b, a * SCALE)
    };
    if r != 0.0 && ((r < 0.0) != (b < 0.0)) {
        q.next_down()
    } else {
        q
    }
}

/// Ceiling of `a / b` in `f64`; `+inf` when undefined.
#[inline]
pub fn div_hi(a: f64, b: f64) -> f64 {
    -div_lo(-a, b)
}

/// A lower bound of `x^n` for `x >= 0`, `n >= 1`, never below `0` (binary powering of
/// floors; exact while every partial product is).
pub fn pow_lo_nonneg(x: f64, n: u32) -> f64 {
    pow_nonneg(x, n, |a, b| f64::max(mul_lo(a, b), 0.0))
}

/// An upper bound of `x^n` for `x >= 0`, `n >= 1` (binary powering of ceilings).
pub fn pow_hi_nonneg(x: f64, n: u32) -> f64 {
    pow_nonneg(x, n, mul_hi)
}

#[inline]
fn pow_nonneg(x: f64, mut n: u32, mul: impl Fn(f64, f64) -> f64) -> f64 {
    // `None` stands for the exact 1, so no bound is ever widened by a product with 1.
    let mut result: Option<f64> = None;
    let mut base = x;
    loop {
        if n & 1 == 1 {
            result = Some(match result {
                None => base,
                Some(r) => mul(r, base),
            });
        }
        n >>= 1;
        if n == 0 {
            return result.unwrap_or(1.0);
        }
        base = mul(base, base);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiny_is_two_to_minus_960() {
        assert_eq!(TINY, 2f64.powi(-960));
    }

    #[test]
    fn exact_ops_stay_tight_inexact_ones_widen() {
        assert_eq!(add_lo(1.0, 2.0), 3.0);
        assert_eq!(add_hi(1.0, 2.0), 3.0);
        // 0.1 + 0.2 rounds up to 0.30000000000000004: the lower bound must move down.
        let s = 0.1 + 0.2;
        assert!(add_lo(0.1, 0.2) < s && add_hi(0.1, 0.2) == s);
        assert_eq!(sub_lo(3.0, 1.0), 2.0);
        assert!(sub_lo(1.0, 1e-20) < sub_hi(1.0, 1e-20) && sub_hi(1.0, 1e-20) == 1.0);
        assert_eq!(mul_lo(3.0, 0.5), 1.5);
        assert!(mul_lo(0.1, 0.1) < mul_hi(0.1, 0.1));
        assert_eq!(div_lo(1.0, 4.0), 0.25);
        assert!(div_lo(1.0, 3.0) < div_hi(1.0, 3.0));
        assert!(div_lo(1.0, 3.0) * 3.0 <= 1.0);
    }

    /// Sums near `f64::MAX`, where the error-free sum's own intermediates overflow, stay
    /// tight (found by `point_ops_are_tight_and_sound`: two ulps apart before).
    #[test]
    fn sums_near_the_largest_float_stay_tight() {
        let (a, b) = (3.9820977904504927e307, -f64::MAX);
        let (lo, hi) = (add_lo(a, b), add_hi(a, b));
        assert!(lo == hi || lo.next_up() == hi, "[{lo:e}, {hi:e}]");
        assert!(
            two_sum(0.5 * a, 0.5 * b).1 != 0.0,
            "the sum is inexact: one bound moves"
        );
        for (a, b) in [(f64::MAX, -1e292), (-f64::MAX, 1e292), (1.7e308, -0.3e308)] {
            let (lo, hi) = (add_lo(a, b), add_hi(a, b));
            assert!(lo <= a + b && a + b <= hi && (lo == hi || lo.next_up() == hi));
        }
    }

    #[test]
    fn overflow_and_underflow_are_outward() {
        assert_eq!(add_lo(f64::MAX, f64::MAX), f64::MAX);
        assert_eq!(add_hi(f64::MAX, f64::MAX), f64::INFINITY);
        assert_eq!(mul_lo(1e300, 1e300), f64::MAX);
        assert!(mul_hi(1e-300, 1e-300) > 0.0);
        assert!(mul_lo(1e-300, 1e-300) < mul_hi(1e-300, 1e-300));
        assert!(div_hi(1e-300, 1e300) > 0.0);
    }

    /// Infinite operands give the exact extended-real result; undefined ones the
    /// infinite bound on each side, never NaN.
    #[test]
    fn infinities_are_exact_and_nothing_is_nan() {
        let inf = f64::INFINITY;
        assert_eq!((add_lo(inf, 1.0), add_hi(inf, 1.0)), (inf, inf));
        assert_eq!((add_lo(-inf, 1.0), add_hi(-inf, 1.0)), (-inf, -inf));
        assert_eq!((mul_lo(inf, 2.0), mul_hi(inf, 2.0)), (inf, inf));
        assert_eq!((mul_lo(inf, -2.0), mul_hi(inf, -2.0)), (-inf, -inf));
        assert_eq!((div_lo(1.0, inf), div_hi(1.0, inf)), (0.0, 0.0));
        for (lo, hi) in [
            (add_lo(inf, -inf), add_hi(inf, -inf)),
            (sub_lo(inf, inf), sub_hi(inf, inf)),
            (mul_lo(0.0, inf), mul_hi(0.0, inf)),
            (mul_lo(-inf, 0.0), mul_hi(-inf, 0.0)),
            (div_lo(inf, inf), div_hi(inf, inf)),
            (div_lo(1.0, 0.0), div_hi(1.0, 0.0)),
            (div_lo(0.0, -0.0), div_hi(0.0, -0.0)),
            (add_lo(f64::NAN, 1.0), add_hi(f64::NAN, 1.0)),
            (mul_lo(f64::NAN, 1.0), mul_hi(f64::NAN, 1.0)),
            (div_lo(f64::NAN, 1.0), div_hi(f64::NAN, 1.0)),
            mul_lo_hi(0.0, inf),
        ] {
            assert_eq!((lo, hi), (-inf, inf));
        }
        assert_eq!(pow_hi_nonneg(inf, 2), inf);
        assert_eq!(pow_lo_nonneg(inf, 2), inf);
    }

    /// Zero results: the sign of the rounded operation for `_lo`, of the negated one for
    /// `_hi` (numerically both exact).
    #[test]
    fn signed_zero_results() {
        let bits = |x: f64| x.to_bits();
        assert_eq!(bits(add_lo(1.0, -1.0)), bits(0.0));
        assert_eq!(bits(add_hi(1.0, -1.0)), bits(-0.0));
        assert_eq!(bits(add_lo(-0.0, -0.0)), bits(-0.0));
        assert_eq!(bits(add_hi(0.0, 0.0)), bits(0.0));
        assert_eq!(bits(mul_lo(0.0, -1.0)), bits(-0.0));
        assert_eq!(bits(mul_hi(0.0, -1.0)), bits(-0.0));
        assert_eq!(bits(mul_lo(-0.0, -1.0)), bits(0.0));
        assert_eq!(bits(mul_hi(-0.0, -1.0)), bits(0.0));
    }

    #[test]
    fn near_underflow_is_floor_and_ceiling() {
        let t = f64::from_bits(1);
        assert_eq!(mul_lo(t, 1.0), t);
        assert_eq!(mul_hi(t, 1.0), t);
        assert_eq!(mul_lo(t, 0.5), 0.0);
        assert_eq!(mul_hi(t, 0.5), t);
        assert_eq!(mul_lo(-t, 0.5), -t);
        assert_eq!(mul_lo(3.0 * t, 0.5), t);
        assert_eq!(mul_hi(3.0 * t, 0.5), 2.0 * t);
        assert_eq!(mul_lo(1e-200, 1e-200), 0.0);
        assert_eq!(mul_hi(1e-200, 1e-200), t);
        assert_eq!(mul_lo(1e-300, -1e-300), -t);
        assert_eq!(div_lo(t, 2.0), 0.0);
        assert_eq!(div_hi(t, 2.0), t);
        assert_eq!(div_lo(3.0 * t, 2.0), t);
        assert_eq!(div_hi(3.0 * t, 2.0), 2.0 * t);
        assert_eq!(div_lo(4.0 * t, 2.0), 2.0 * t);
        assert_eq!(div_hi(4.0 * t, 2.0), 2.0 * t);
        assert_eq!(div_lo(3.0 * t, 3.0 * t), 1.0);
        assert_eq!(div_hi(3.0 * t, 3.0 * t), 1.0);
        assert!(div_lo(t, 3.0 * t) < div_hi(t, 3.0 * t));
        assert_eq!(div_lo(1.0, 1e300 * 1e10), 0.0);
    }

    /// The pair agrees bit for bit with the two separate bounds, on every kind of float.
    #[test]
    fn mul_pair_matches_lo_and_hi() {
        let mut r = 0x2545_F491_4F6C_DD1Du64;
        let mut xs = vec![
            0.0,
            -0.0,
            ETA,
            -ETA,
            1e-300,
            -1e-160,
            f64::MIN_POSITIVE,
            1.0,
            -3.0,
            0.1,
            1e299,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        for _ in 0..20_000 {
            r ^= r << 13;
            r ^= r >> 7;
            r ^= r << 17;
            xs.push(f64::from_bits(r));
        }
        for w in xs.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (lo, hi) = mul_lo_hi(a, b);
            assert_eq!(lo.to_bits(), mul_lo(a, b).to_bits(), "{a:e} * {b:e}");
            assert_eq!(hi.to_bits(), mul_hi(a, b).to_bits(), "{a:e} * {b:e}");
        }
    }

    #[test]
    fn powers_bracket() {
        assert_eq!(pow_lo_nonneg(3.0, 4), 81.0);
        assert_eq!(pow_hi_nonneg(3.0, 4), 81.0);
        assert_eq!(pow_lo_nonneg(1.5, 5), 7.59375);
        // 1.1^5 is not a float: the bounds must differ, by a few ulps at most.
        let (lo, hi) = (pow_lo_nonneg(1.1, 5), pow_hi_nonneg(1.1, 5));
        assert!(lo < hi && hi - lo < 1e-14);
        assert_eq!(pow_hi_nonneg(1e200, 3), f64::INFINITY);
        assert_eq!(pow_lo_nonneg(1e200, 3), f64::MAX);
    }
}
