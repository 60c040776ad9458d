//! Rigorous bounds the approximations are built from: enclosures of `sqrt x`, `1/x` and
//! `x^n` at one float (exact when the result is representable), and bounds of
//! `g(x) = f(x) - alpha*x` over an interval where `f` is convex or concave (the far side
//! from the ends, the near side from a tangent at an approximate stationary point).
//!
//! All directed steps come from [`crate::round`]: tight bounds (`add_lo`, `mul_hi`, ...)
//! where exactness keeps hand-checkable cases exact, step bounds for small corrections.
//! Also [`sum_sq_floor`], the lower bound of `x^2 + y^2` the R-functions' `sqrt` uses.

use crate::round::{
    self, add_hi, add_lo, down, mul_hi, mul_lo, mul_lo_hi, prod_err, sub_hi, sub_lo, up,
};

/// A lower bound of `x^2 + y^2` for `x ∈ [x.0, x.1]`, `y ∈ [y.0, y.1]` (mignitudes
/// squared, rounded down; `0` when a range is NaN or holds 0).
#[inline]
pub fn sum_sq_floor(x: (f64, f64), y: (f64, f64)) -> f64 {
    let mig = |(lo, hi): (f64, f64)| {
        if lo > 0.0 {
            lo
        } else if hi < 0.0 {
            -hi
        } else {
            0.0
        }
    };
    let (a, b) = (mig(x), mig(y));
    let s = round::add_down(
        round::mul_down(a, a).max(0.0),
        round::mul_down(b, b).max(0.0),
    );
    if s.is_nan() {
        0.0
    } else {
        s.max(0.0)
    }
}

/// Enclosure of `d * t` for `d ∈ [d.0, d.1]`, `t ∈ [t.0, t.1]` with `t.0 <= 0 <= t.1`
/// (a slope times an offset from a point inside the interval). Then the extremes are
/// `min(d.1*t.0, d.0*t.1)` and `max(d.0*t.0, d.1*t.1)`. Plain outward rounding: these
/// terms are small corrections, exactness buys nothing.
pub(super) fn slope_times_offset(d: (f64, f64), t: (f64, f64)) -> (f64, f64) {
    debug_assert!(t.0 <= 0.0 && t.1 >= 0.0);
    let lo = round::mul_down(d.1, t.0).min(round::mul_down(d.0, t.1));
    let hi = round::mul_up(d.0, t.0).max(round::mul_up(d.1, t.1));
    (lo, hi)
}

/// Enclosure of `sqrt(x)` for `x >= 0` (exact when `x` is a perfect square).
pub(super) fn sqrt_enc(x: f64) -> (f64, f64) {
    let s = x.sqrt();
    if (1.0e-250..=1.0e300).contains(&x) {
        // The residual of a correctly rounded square root is representable here.
        let p = s * s;
        // p - x is exact (Sterbenz) and the rounded sum keeps the sign of s^2 - x.
        let r = (p - x) + prod_err(s, s, p);
        if r == 0.0 {
            return (s, s);
        } else if r > 0.0 {
            return (down(s).max(0.0), s);
        } else {
            return (s, up(s));
        }
    }
    (down(s).max(0.0), up(s))
}

/// Enclosure of `1 / x` for `x != 0` (exact when representable).
pub(super) fn recip_enc(x: f64) -> (f64, f64) {
    let q = 1.0 / x;
    if x.is_finite() && (1.0e-250..=1.0e250).contains(&x.abs()) {
        // q*x - 1 = x*(q - 1/x): its sign tells on which side of 1/x the quotient lies.
        let p = q * x;
        let r = (p - 1.0) + prod_err(q, x, p);
        if r == 0.0 {
            return (q, q);
        }
        let q_above = (r > 0.0) == (x > 0.0);
        return if q_above { (down(q), q) } else { (q, up(q)) };
    }
    (down(q), up(q))
}

/// Enclosure of `x^n`, `n >= 1`, by outward-rounded binary powering of `|x|`.
pub(super) fn pow_enc(x: f64, n: u32) -> (f64, f64) {
    let m = x.abs();
    let mut base = (m, m);
    let mut r: Option<(f64, f64)> = None;
    let mut k = n;
    loop {
        if k & 1 == 1 {
            r = Some(match r {
                None => base,
                Some(v) => mul_nonneg(v, base),
            });
        }
        k >>= 1;
        if k == 0 {
            break;
        }
        base = mul_nonneg(base, base);
    }
    let (rl, rh) = r.unwrap_or((1.0, 1.0));
    if x < 0.0 && !n.is_multiple_of(2) {
        (-rh, -rl)
    } else {
        (rl, rh)
    }
}

/// Enclosure of the product of two enclosures of non-negative numbers (one product
/// while both are still exact).
fn mul_nonneg(x: (f64, f64), y: (f64, f64)) -> (f64, f64) {
    if x.0 == x.1 && y.0 == y.1 {
        let (lo, hi) = mul_lo_hi(x.0, y.0);
        (lo.max(0.0), hi)
    } else {
        (mul_lo(x.0, y.0).max(0.0), mul_hi(x.1, y.1))
    }
}

/// Enclosure of `g(x) = f(x) - alpha*x` at a float `x`, given `f(x) ∈ fx`.
#[inline]
pub(super) fn g_enc(fx: (f64, f64), alpha: f64, x: f64) -> (f64, f64) {
    (g_lo(fx.0, alpha, x), g_hi(fx.1, alpha, x))
}

/// A lower bound of `g(x) = f(x) - alpha*x` at a float `x`, given `f(x) >= f_lo`
/// ([`g_enc`]'s lower end, where only it is needed).
#[inline]
pub(super) fn g_lo(f_lo: f64, alpha: f64, x: f64) -> f64 {
    sub_lo(f_lo, mul_hi(alpha, x))
}

/// An upper bound of `g(x) = f(x) - alpha*x` at a float `x`, given `f(x) <= f_hi`
/// ([`g_enc`]'s upper end).
#[inline]
pub(super) fn g_hi(f_hi: f64, alpha: f64, x: f64) -> f64 {
    sub_hi(f_hi, mul_lo(alpha, x))
}

/// `p` moved into `[a, b]` (the midpoint when `p` is NaN).
fn clamp_in(p: f64, a: f64, b: f64) -> f64 {
    if p >= a && p <= b {
        p
    } else if p > b {
        b
    } else if p < a {
        a
    } else {
        mid(a, b)
    }
}

/// A float in `[a, b]` near the midpoint (no overflow).
pub(super) fn mid(a: f64, b: f64) -> f64 {
    clamp_in_finite(0.5 * a + 0.5 * b, a, b)
}

fn clamp_in_finite(m: f64, a: f64, b: f64) -> f64 {
    if m < a {
        a
    } else if m > b {
        b
    } else {
        m
    }
}

/// Rigorous enclosure of `g = f - alpha*x` over `[a, b]` where `f` (hence `g`) is convex
/// (`convex = true`) or concave there. The far side comes from the ends; the near side
/// from the tangent at `p` (an approximate stationary point of `g`):
/// convex `g(x) >= g(p) + g'(p)(x - p)`, concave `g(x) <= g(p) + g'(p)(x - p)`, with an
/// enclosure of `g'(p) = f'(p) - alpha` and `x - p ∈ [a - p, b - p]`.
pub(super) fn bound_piece<F, D>(
    f: &F,
    df: &D,
    alpha: f64,
    a: f64,
    b: f64,
    p: f64,
    convex: bool,
) -> (f64, f64)
where
    F: Fn(f64) -> (f64, f64),
    D: Fn(f64) -> (f64, f64),
{
    // Only the sides each shape needs: the ends' far side, the tangent point's near one.
    let (fa, fb) = (f(a), f(b));
    let p = clamp_in(p, a, b);
    let fp = f(p);
    let d = df(p);
    let dg = (sub_lo(d.0, alpha), sub_hi(d.1, alpha));
    let (tlo, thi) = slope_times_offset(dg, (sub_lo(a, p), sub_hi(b, p)));
    if convex {
        let far = g_hi(fa.1, alpha, a).max(g_hi(fb.1, alpha, b));
        (add_lo(g_lo(fp.0, alpha, p), tlo), far)
    } else {
        let far = g_lo(fa.0, alpha, a).min(g_lo(fb.0, alpha, b));
        (far, add_hi(g_hi(fp.1, alpha, p), thi))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sum_sq_floor_is_the_mignitudes_squared() {
        // Rounded down (by an ulp or two even when exact).
        let near = |got: f64, want: f64| got <= want && got >= want * (1.0 - 1e-15);
        assert!(near(sum_sq_floor((1.0, 2.0), (-3.0, -2.0)), 5.0));
        assert!(near(sum_sq_floor((-1.0, 2.0), (-3.0, -2.0)), 4.0));
        assert_eq!(sum_sq_floor((-1.0, 2.0), (0.0, 0.0)), 0.0);
        assert_eq!(sum_sq_floor((f64::NAN, 2.0), (f64::NAN, 1.0)), 0.0);
        let f = sum_sq_floor((0.1, 1.0), (0.3, 1.0));
        assert!(f <= 0.1 * 0.1 + 0.3 * 0.3 && f > 0.0999);
    }

    #[test]
    fn tangent_bound_holds_for_any_tangent_point() {
        // sqrt on [1, 4], alpha = 1/3: g = sqrt(x) - x/3 peaks at 3/4 (x = 9/4). A tangent
        // at any p in [1, 4] bounds it from above; at p = 1 it is 2/3 + (1/2 - 1/3)*3 = 7/6,
        // at p = 4 it is 2/3 + (1/4 - 1/3)*(-3) = 11/12; at p = 9/4 it is exactly 3/4.
        let f = sqrt_enc;
        let df = |x: f64| {
            let (sl, sh) = sqrt_enc(x);
            (round::div_down(0.5, sh), round::div_up(0.5, sl))
        };
        let alpha = 1.0 / 3.0;
        for (p, want) in [(1.0, 7.0 / 6.0), (4.0, 11.0 / 12.0), (2.25, 0.75)] {
            let (lo, hi) = bound_piece(&f, &df, alpha, 1.0, 4.0, p, false);
            assert!(
                hi >= want && hi <= want + 1e-14,
                "p = {p}: hi {hi} vs {want}"
            );
            assert!((2.0 / 3.0 - 1e-14..=2.0 / 3.0).contains(&lo));
        }
        // Convex: x^2 on [1, 3], alpha = 4, g = x^2 - 4x has minimum -4 at 2. Tangent at
        // p = 1: -3 + (2 - 4)*2 = -7; at p = 3: -3 + (6 - 4)*(-2) = -7; at p = 2: -4.
        let f = |x: f64| pow_enc(x, 2);
        let df = |x: f64| (2.0 * x, 2.0 * x);
        for (p, want) in [(1.0, -7.0), (3.0, -7.0), (2.0, -4.0), (f64::NAN, -4.0)] {
            let (lo, hi) = bound_piece(&f, &df, 4.0, 1.0, 3.0, p, true);
            assert!(
                lo <= want && lo >= want - 1e-14,
                "p = {p}: lo {lo} vs {want}"
            );
            assert_eq!(hi, -3.0);
        }
    }

    /// A difference whose error term overflows (near `f64::MAX`) moves one bound only
    /// (both used to be stepped outward).
    #[test]
    fn g_near_the_largest_float_is_tight() {
        let big = 3.9820977904504927e307;
        let (lo, hi) = g_enc((big, big), 1.0, f64::MAX);
        assert!(lo < hi && lo.next_up() == hi, "[{lo:e}, {hi:e}]");
    }
}
