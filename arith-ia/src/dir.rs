//! Directed (outward) bounds of one `+ * /`, tight when the operation is exact.
//!
//! Each helper returns a lower (`_lo`) or upper (`_hi`) bound of the exact result of one
//! operation on two `f64`s. The rounded-to-nearest result is kept as is when an
//! error-free transformation shows it is already on the right side of the exact value,
//! and moved one ulp outward otherwise (one rounding is at most half an ulp off).
//! Near underflow, where the error terms themselves may be inexact, the check runs on
//! operands scaled by `2^600`, so every lower bound is exactly the floor (and every
//! upper bound the ceiling) of the exact result in `f64`: tight, and monotone in the
//! exact value (which keeps interval operations inclusion-isotone). Overflow to `±inf` of a product of finite numbers keeps the finite side
//! (`f64::MAX` is a valid lower bound of something that rounded to `+inf`).
//!
//! A NaN result (`inf - inf`, `0 * inf`, `inf / inf`) is returned as NaN; the caller
//! turns a NaN lower bound into `-inf` and a NaN upper bound into `+inf`.

use arith_core::round::two_sum;

/// Below this magnitude the error term of a product/quotient may not be representable,
/// so its sign cannot be trusted: we then widen unconditionally. (`2^-960`: for
/// `|a*b| >= 2^-960` the exact error `a*b - fl(a*b)` is a multiple of
/// `ulp(a)*ulp(b) >= 2^-1066` below `ulp(fl(a*b))`, hence an `f64`; likewise the division
/// remainder for `|a| >= 2^-960`.)
const TINY: f64 = f64::from_bits(63 << 52);

/// `2^600`: scales near-underflow operands into the range where the checks are exact.
const SCALE: f64 = f64::from_bits((1023 + 600) << 52);

/// The smallest positive subnormal.
const ETA: f64 = f64::from_bits(1);

#[inline]
fn finite2(a: f64, b: f64) -> bool {
    a.is_finite() && b.is_finite()
}

/// Lower bound of `a + b`.
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
    } else {
        s
    }
}

/// Upper bound of `a + b`.
#[inline]
pub fn add_hi(a: f64, b: f64) -> f64 {
    -add_lo(-a, -b)
}

/// Lower bound of `a * b`.
#[inline]
pub fn mul_lo(a: f64, b: f64) -> f64 {
    let p = a * b;
    if p.is_nan() {
        return p;
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
        a.mul_add(b, -p)
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

/// Upper bound of `a * b`.
#[inline]
pub fn mul_hi(a: f64, b: f64) -> f64 {
    -mul_lo(-a, b)
}

/// Lower bound of `a / b` (NaN for `b == 0`: callers exclude divisors holding 0).
#[inline]
pub fn div_lo(a: f64, b: f64) -> f64 {
    if b == 0.0 {
        return f64::NAN;
    }
    let q = a / b;
    if q.is_nan() {
        return q;
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

/// Upper bound of `a / b`.
#[inline]
pub fn div_hi(a: f64, b: f64) -> f64 {
    -div_lo(-a, b)
}

/// Lower bound of `x^n` for `x >= 0`, `n >= 1` (binary powering; all factors are
/// non-negative lower bounds, so their products stay lower bounds).
pub fn pow_lo_nonneg(x: f64, n: u32) -> f64 {
    pow_nonneg(x, n, |a, b| f64::max(mul_lo(a, b), 0.0))
}

/// Upper bound of `x^n` for `x >= 0`, `n >= 1`.
pub fn pow_hi_nonneg(x: f64, n: u32) -> f64 {
    pow_nonneg(x, n, |a, b| {
        let p = mul_hi(a, b);
        if p.is_nan() {
            f64::INFINITY
        } else {
            p
        }
    })
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
        assert!(mul_lo(0.0, f64::INFINITY).is_nan());
        assert!(add_lo(f64::INFINITY, f64::NEG_INFINITY).is_nan());
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
