//! The one rounding vocabulary of the workspace: outward bounds of single operations,
//! error-free transformations and the libm allowance, shared by the affine
//! approximations ([`crate::approx`]), interval arithmetic and the affine forms. We never
//! switch the FPU rounding mode (undefined behaviour in Rust); every operation rounds to
//! nearest and we bound its error instead.
//!
//! Facts used throughout (IEEE 754 binary64, round to nearest):
//! - the exact result `x` of one `+ - * /` or `sqrt` and its rounded value `r` satisfy
//!   `|x - r| <= ulp(r)/2 <= max(|r| * 2^-53, 2^-1074)` ([`err`]);
//! - hence `next_down(r) <= x <= next_up(r)` ([`add_up`], [`mul_down`], ...).
//!
//! Two families of directed operations, both never NaN (`-inf` for an undefined lower
//! bound, `+inf` for an undefined upper bound):
//! - *step* bounds `add_up`, `mul_down`, ...: the rounded result moved one ulp outward,
//!   unconditionally (cheap; for small correction terms where exactness buys nothing);
//! - *tight* bounds `add_lo`, `mul_hi`, ... ([`tight`]): the floor or ceiling in `f64` of
//!   the exact result, so exact operations stay exact (every interval bound, and the
//!   bounds of the affine approximations at their chosen points).

/// `2^-53`, the unit roundoff of round-to-nearest binary64.
pub const U: f64 = 1.0 / 9_007_199_254_740_992.0;
/// The smallest positive subnormal, `2^-1074`.
pub const ETA: f64 = f64::from_bits(1);

/// Upper bound on the rounding error of one correctly rounded operation whose rounded
/// result is `r` (`+inf` when `r` is infinite or NaN).
#[inline]
pub fn err(r: f64) -> f64 {
    if r.is_finite() {
        f64::max(r.abs() * U, ETA)
    } else {
        f64::INFINITY
    }
}

/// The next float up (`+inf` stays, NaN becomes `+inf` so bounds never turn NaN).
#[inline]
pub fn up(x: f64) -> f64 {
    if x.is_nan() {
        f64::INFINITY
    } else {
        x.next_up()
    }
}

/// The next float down (`-inf` stays, NaN becomes `-inf`).
#[inline]
pub fn down(x: f64) -> f64 {
    if x.is_nan() {
        f64::NEG_INFINITY
    } else {
        x.next_down()
    }
}

/// The float after `s` when `s` is finite or `-inf`, not `-0` (`next_up` without the
/// branches for NaN, `+inf` and `-0`): for callers that know `s` is not one of those,
/// such as the directed sums of `affine_round`, which step only inexact sums.
#[inline(always)]
pub(crate) fn step_up(s: f64) -> f64 {
    let b = s.to_bits() as i64;
    // Positive (incl. +0): one more; negative: one less in magnitude.
    f64::from_bits(b.wrapping_add((b >> 63) | 1) as u64)
}

/// The float before `s` when `s` is finite or `+inf`, not `+0` (as [`step_up`]).
#[inline(always)]
pub(crate) fn step_down(s: f64) -> f64 {
    -step_up(-s)
}

/// [`up`] without branches: `x.next_up()` for every `x` but `+inf` and NaN, which give
/// NaN (so a caller's finiteness check still catches them).
#[inline(always)]
pub fn up_finite(x: f64) -> f64 {
    // `+ 0.0` turns -0 into +0, which `step_up` takes to the least subnormal.
    step_up(x + 0.0)
}

/// [`down`] without branches: `x.next_down()` for every `x` but `-inf` and NaN, which
/// give NaN.
#[inline(always)]
pub fn down_finite(x: f64) -> f64 {
    -up_finite(-x)
}

/// Step upper bound of `a + b`: `fl(a + b)` one ulp up (`+inf` for a NaN result).
#[inline]
pub fn add_up(a: f64, b: f64) -> f64 {
    up(a + b)
}
/// Step lower bound of `a + b`: `fl(a + b)` one ulp down (`-inf` for a NaN result).
#[inline]
pub fn add_down(a: f64, b: f64) -> f64 {
    down(a + b)
}
/// Step upper bound of `a - b`: `fl(a - b)` one ulp up (`+inf` for a NaN result).
#[inline]
pub fn sub_up(a: f64, b: f64) -> f64 {
    up(a - b)
}
/// Step lower bound of `a - b`: `fl(a - b)` one ulp down (`-inf` for a NaN result).
#[inline]
pub fn sub_down(a: f64, b: f64) -> f64 {
    down(a - b)
}
/// Step upper bound of `a * b`: `fl(a * b)` one ulp up (`+inf` for `0 * inf` or NaN).
#[inline]
pub fn mul_up(a: f64, b: f64) -> f64 {
    let p = a * b;
    // 0 * inf is NaN: the product of a bound with an unbounded factor is unbounded.
    if p.is_nan() {
        f64::INFINITY
    } else {
        up(p)
    }
}
/// Step lower bound of `a * b`: `fl(a * b)` one ulp down (`-inf` for `0 * inf` or NaN).
#[inline]
pub fn mul_down(a: f64, b: f64) -> f64 {
    let p = a * b;
    if p.is_nan() {
        f64::NEG_INFINITY
    } else {
        down(p)
    }
}
/// Step upper bound of `a / b`: `fl(a / b)` one ulp up (`+inf` for a NaN result).
#[inline]
pub fn div_up(a: f64, b: f64) -> f64 {
    up(a / b)
}
/// Step lower bound of `a / b`: `fl(a / b)` one ulp down (`-inf` for a NaN result).
#[inline]
pub fn div_down(a: f64, b: f64) -> f64 {
    down(a / b)
}

pub mod tight;
pub use tight::{
    add_hi, add_lo, div_hi, div_lo, mul_hi, mul_lo, mul_lo_hi, pow_hi_nonneg, pow_lo_nonneg,
    sub_hi, sub_lo,
};

/// Error-free sum (Knuth's TwoSum): `s + e == a + b` exactly, `s = fl(a + b)`.
#[inline]
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// Error-free product via fused multiply-add: `p + e == a * b` exactly (barring
/// underflow of `e`, which the callers cover with [`ETA`]).
#[inline]
pub fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let e = a.mul_add(b, -p);
    (p, e)
}

/// Products whose magnitude is at least this have an exactly representable error term.
pub(crate) const EXACT_MIN: f64 = 1.0e-280;
/// Factors below this magnitude can be split (Veltkamp) without overflow.
pub(crate) const SPLIT_MAX: f64 = 1.0e299;
/// Factors at least this large split without underflow.
pub(crate) const FACTOR_MIN: f64 = 1.0e-290;

/// The exact error `a*b - p` of `p = fl(a*b)`, for `EXACT_MIN <= |p|` and
/// `FACTOR_MIN <= |a|, |b| < SPLIT_MAX`: one FMA where the target has it, else Dekker's
/// product (a call to a software `fma` would cost more than the rest of an approximation).
#[inline]
pub(crate) fn prod_err(a: f64, b: f64, p: f64) -> f64 {
    if cfg!(target_feature = "fma") {
        a.mul_add(b, -p)
    } else {
        dekker_err(a, b, p)
    }
}

/// Dekker's error of `p = fl(a*b)` with Veltkamp splitting (exact under the conditions
/// of [`prod_err`]).
#[inline]
pub(crate) fn dekker_err(a: f64, b: f64, p: f64) -> f64 {
    let split = |x: f64| {
        let c = 134_217_729.0 * x; // 2^27 + 1
        let hi = c - (c - x);
        (hi, x - hi)
    };
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    ((ah * bh - p) + ah * bl + al * bh) + al * bl
}

/// Relative error we allow std's `exp`, `ln`, `sin`, `cos` (whose precision Rust does
/// not specify). glibc and the Rust fallbacks are within 1-2 ulp; we assume at most
/// 8 ulp, i.e. `|fl(f(x)) - f(x)| <= 8 * 2 * U * |fl(f(x))| + ETA`, a generous margin.
pub const LIBM_REL: f64 = 16.0 * U;

/// A lower and an upper bound of the true value of a libm function whose computed
/// value is `v`, under the [`LIBM_REL`] assumption.
#[inline]
pub fn libm_enclose(v: f64) -> (f64, f64) {
    if v.is_nan() {
        return (f64::NEG_INFINITY, f64::INFINITY);
    }
    let m = v.abs() * LIBM_REL + ETA;
    (down(v - m), up(v + m))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Finite floats of every kind: zeros, subnormals, the extremes and random bits.
    fn finite_samples() -> Vec<f64> {
        let mut xs = vec![
            0.0,
            -0.0,
            ETA,
            -ETA,
            2.0 * ETA,
            7e-310,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            f64::MAX,
            f64::MIN,
            1.0,
            -1.0,
            0.1,
            -3.5e-300,
            -3.5e300,
        ];
        let mut r = 0x9E37_79B9_7F4A_7C15u64;
        for _ in 0..100_000 {
            r ^= r << 13;
            r ^= r >> 7;
            r ^= r << 17;
            let x = f64::from_bits(r);
            if x.is_finite() {
                xs.push(x);
            }
        }
        xs
    }

    /// The branch-free steps agree with `next_up`/`next_down`: `step_up`/`step_down` on
    /// every float they are used on (not a zero; `-inf` up and `+inf` down included),
    /// `up_finite`/`down_finite` on every finite float (zeros, subnormals, the largest
    /// floats) and inward from the infinities; outward from an infinity or from NaN the
    /// latter give NaN.
    #[test]
    fn steps_match_next_up_and_down() {
        for x in finite_samples() {
            if x != 0.0 {
                assert_eq!(step_up(x).to_bits(), x.next_up().to_bits(), "step up {x:e}");
                assert_eq!(
                    step_down(x).to_bits(),
                    x.next_down().to_bits(),
                    "step down {x:e}"
                );
            }
            assert_eq!(up_finite(x).to_bits(), x.next_up().to_bits(), "up {x:e}");
            assert_eq!(
                down_finite(x).to_bits(),
                x.next_down().to_bits(),
                "down {x:e}"
            );
        }
        assert_eq!(step_up(0.0), ETA);
        assert_eq!(step_up(f64::NEG_INFINITY), f64::MIN);
        assert_eq!(step_down(f64::INFINITY), f64::MAX);
        assert_eq!(up_finite(f64::NEG_INFINITY), f64::MIN);
        assert_eq!(down_finite(f64::INFINITY), f64::MAX);
        for x in [f64::INFINITY, f64::NAN, -f64::NAN] {
            assert!(up_finite(x).is_nan() && down_finite(-x).is_nan(), "{x}");
        }
    }

    #[test]
    fn err_bounds_one_rounding() {
        // 0.1 + 0.2 is not exact; the error bound must cover the true error.
        let (s, e) = two_sum(0.1, 0.2);
        assert!(e != 0.0);
        assert!(e.abs() <= err(s));
        let (p, e) = two_prod(0.1, 0.3);
        assert!(e.abs() <= err(p));
        assert_eq!(err(f64::INFINITY), f64::INFINITY);
        assert_eq!(err(0.0), ETA);
    }

    #[test]
    fn directed_ops_bracket_exact() {
        let (s, e) = two_sum(1.0, 1e-20);
        assert!(add_down(1.0, 1e-20) <= s && s + e <= add_up(1.0, 1e-20));
        assert!(add_up(1.0, 1e-20) > 1.0);
        assert!(mul_up(0.0, f64::INFINITY) == f64::INFINITY);
        assert!(mul_down(0.0, f64::INFINITY) == f64::NEG_INFINITY);
        assert_eq!(up(f64::NAN), f64::INFINITY);
        assert_eq!(down(f64::NAN), f64::NEG_INFINITY);
    }

    #[test]
    fn dekker_error_matches_fma() {
        // Pseudo-random normal factors across the allowed magnitudes; std's mul_add is a
        // correctly rounded FMA (hardware or software), so it gives the exact error.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for _ in 0..20_000 {
            let m = |r: u64| 1.0 + (r >> 11) as f64 / (1u64 << 53) as f64;
            let (ra, rb, rs) = (next(), next(), next());
            let ea = (ra % 1100) as i32 - 600;
            let eb = (rb % 1100) as i32 - 600;
            let a = m(ra) * 2f64.powi(ea) * if rs & 1 == 0 { 1.0 } else { -1.0 };
            let b = m(rb) * 2f64.powi(eb);
            let p = a * b;
            let usable = p.is_finite()
                && p.abs() >= EXACT_MIN
                && (FACTOR_MIN..SPLIT_MAX).contains(&a.abs())
                && (FACTOR_MIN..SPLIT_MAX).contains(&b.abs());
            if !usable {
                continue;
            }
            assert_eq!(dekker_err(a, b, p), a.mul_add(b, -p), "{a:e} * {b:e}");
        }
    }

    #[test]
    fn libm_enclosure_holds_known_values() {
        let (lo, hi) = libm_enclose(1.0f64.exp());
        assert!(lo < std::f64::consts::E && std::f64::consts::E < hi);
        let (lo, hi) = libm_enclose(0.0);
        assert!(lo < 0.0 && hi > 0.0);
    }
}
