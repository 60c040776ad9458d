//! Affine approximations of the functions that are convex or concave on each side of
//! at most one point: `x^n`, `sqrt`, `1/x`, `e^x`, `ln x` and `|x|`.
//!
//! Each chooses its slope `alpha` in plain floating point (Chebyshev, the secant slope,
//! or min-range where that keeps the sign of `f` or is tighter) and then bounds
//! `g = f - alpha*x` rigorously with [`super::bounds`]; `sqrt` and `1/x` on positive
//! ranges, the hot cases of the R-functions and of division, have closed-form fast paths
//! giving the same kind of bound with fewer roundings.

use super::bounds::{bound_piece, g_enc, g_hi, pow_enc, recip_enc, sqrt_enc};
use super::interval::{range_exp, range_ln, range_powi, range_sqrt};
use super::{approx_min, bad, finish, flush, mirror, or_range, Approx};
use crate::round::{self, down, libm_enclose, mul_hi, mul_lo, mul_lo_hi, sub_lo, up};

/// `x^2` on `[a, b]`: Chebyshev, `alpha = a + b` (the secant slope; `x^2` is convex).
pub fn sqr(a: f64, b: f64) -> Approx {
    powi(a, b, 2)
}

/// `x^n` on `[a, b]`, `n >= 2`.
///
/// Even `n`, or odd `n` on one side of 0: convex (or, mirrored, concave), so Chebyshev:
/// `alpha` = secant slope. Odd `n` straddling 0 (inflection exactly at the float 0): the
/// minimax slope, i.e. the secant slope when `min(-a, b) < t*max(-a, b)`, else
/// `n (t*max(-a, b))^(n-1)` (`t = 1/2` for `n = 3`), bounded on `[a, 0]` and `[0, b]`
/// separately. `n < 2` (not part of the contract) gives the sound constant, identity or
/// range approximation.
pub fn powi(a: f64, b: f64, n: i32) -> Approx {
    if bad(a, b) {
        return Approx::ENTIRE;
    }
    match n {
        1 => {
            return Approx {
                alpha: 1.0,
                zeta: 0.0,
                delta: 0.0,
            }
        }
        0 => {
            return Approx {
                alpha: 0.0,
                zeta: 1.0,
                delta: 0.0,
            }
        }
        _ if n < 0 => {
            let (lo, hi) = range_powi(a, b, n);
            return Approx::from_range(lo, hi);
        }
        _ => {}
    }
    let range = || range_powi(a, b, n);
    if a == b || !a.is_finite() || !b.is_finite() {
        let (lo, hi) = range();
        return Approx::from_range(lo, hi);
    }
    let nu = n as u32;
    let odd = !nu.is_multiple_of(2);
    if odd && (b <= 0.0 || (a < 0.0 && -a > b)) {
        return mirror(powi(-b, -a, n));
    }
    let nf = n as f64;
    let f = |x: f64| pow_enc(x, nu);
    let df = |x: f64| {
        let (lo, hi) = pow_enc(x, nu - 1);
        if lo == hi {
            mul_lo_hi(lo, nf)
        } else {
            (mul_lo(lo, nf), mul_hi(hi, nf))
        }
    };
    // Stationary point of g: n p^(n-1) = alpha.
    let stat = |alpha: f64| {
        if nu == 2 {
            0.5 * alpha
        } else {
            alpha.signum() * (alpha.abs() / nf).powf(1.0 / (nf - 1.0))
        }
    };
    let ap = if odd && a < 0.0 {
        // Here 0 < -a <= b: concave on [a, 0], convex on [0, b].
        let t = odd_pow_t(nu);
        let alpha = flush(if -a >= t * b {
            nf * (t * b).powi(n - 1)
        } else {
            pow_secant(a, b, nu)
        });
        let p = stat(alpha);
        let (l1, h1) = bound_piece(&f, &df, alpha, a, 0.0, -p, false);
        let (l2, h2) = bound_piece(&f, &df, alpha, 0.0, b, p, true);
        finish(alpha, l1.min(l2), h1.max(h2))
    } else {
        let alpha = flush(pow_secant(a, b, nu));
        let (lo, hi) = bound_piece(&f, &df, alpha, a, b, stat(alpha), true);
        finish(alpha, lo, hi)
    };
    or_range(ap, range)
}

/// `sqrt(max(x, 0))` on `[a, b]` (clipped at 0; wholly negative gives exactly 0).
///
/// `a >= 0`: concave, Chebyshev `alpha = 1/(sqrt(a) + sqrt(b))` (the secant slope).
/// `a < 0 < b`: the function is 0 then `sqrt`; the minimax slope over all of `[a, b]`
/// (the approximation must hold on the negative part too): `1/sqrt(b)` when
/// `-a <= b/4`, `1/(2 sqrt(-a))` when `-a <= b`, else the secant `sqrt(b)/(b - a)`.
/// An unbounded `a` gives the constant `[0, sqrt(b)]` (`alpha = 0`).
pub fn sqrt(a: f64, b: f64) -> Approx {
    if bad(a, b) {
        return Approx::ENTIRE;
    }
    if b <= 0.0 {
        return Approx {
            alpha: 0.0,
            zeta: 0.0,
            delta: 0.0,
        };
    }
    let range = || range_sqrt(a, b);
    if a == b || !a.is_finite() || !b.is_finite() {
        let (lo, hi) = range();
        return Approx::from_range(lo, hi);
    }
    let f = |x: f64| if x <= 0.0 { (0.0, 0.0) } else { sqrt_enc(x) };
    let df = |x: f64| {
        let (sl, sh) = sqrt_enc(x);
        (round::div_down(0.5, sh), round::div_up(0.5, sl))
    };
    let sb = b.sqrt();
    if a > 0.0 {
        if let Some(ap) = sqrt_fast(a, b, sb) {
            return ap;
        }
    }
    let ap = if a >= 0.0 {
        let alpha = flush(1.0 / (a.sqrt() + sb));
        let p = 0.25 / (alpha * alpha);
        let (lo, hi) = bound_piece(&f, &df, alpha, a, b, p, false);
        finish(alpha, lo, hi)
    } else {
        let l = -a;
        let alpha = flush(if l <= 0.25 * b {
            1.0 / sb
        } else if l <= b {
            0.5 / l.sqrt()
        } else {
            sb / (b - a)
        });
        if let Some(ap) = sqrt_fast_across(a, b, sb, alpha) {
            return ap;
        }
        // [a, 0]: g = -alpha*x is linear; [0, b]: concave.
        let ga = g_enc((0.0, 0.0), alpha, a);
        let (l2, h2) = bound_piece(&f, &df, alpha, 0.0, b, 0.25 / (alpha * alpha), false);
        finish(alpha, ga.0.min(0.0).min(l2), ga.1.max(0.0).max(h2))
    };
    or_range(ap, range)
}

/// [`sqrt`] on `[a, b]` for an argument known to be `>= floor` as well: the
/// approximation on `[max(a, floor), b]` (sound: the argument lies in both).
#[inline]
pub fn sqrt_at_least(a: f64, b: f64, floor: f64) -> Approx {
    if floor.is_nan() || floor <= a || floor > b {
        return sqrt(a, b);
    }
    sqrt(floor, b)
}

/// Fast path of [`sqrt`] for `0 < a < b < inf` (`sb = fl(sqrt(b))`), in closed form.
///
/// `g(x) = sqrt(x) - alpha*x` is concave, so its minimum over `[a, b]` is at an end, and
/// for every real `x > 0` and any `alpha > 0`, `sqrt(x) - alpha*x <= 1/(4 alpha)`
/// (AM-GM: `alpha*x + 1/(4 alpha) >= sqrt(x)`, equality at `x = 1/(4 alpha^2)`). So the
/// upper bound needs no division of its own (see the body), whatever float `alpha` came
/// out. The ends are computed in round to nearest with one allowance for their
/// roundings. `None` when `alpha` is not a normal positive float.
#[inline]
fn sqrt_fast(a: f64, b: f64, sb: f64) -> Option<Approx> {
    let sa = a.sqrt();
    let sum = sa + sb;
    let alpha = 1.0 / sum;
    if !(alpha >= f64::MIN_POSITIVE && alpha.is_finite()) {
        return None;
    }
    // g = sqrt(x) - alpha*x at the ends in round to nearest, then one allowance: the root,
    // the product and the difference are each within U of their result (the product
    // also ETA/2), all at most sb + alpha*b in magnitude (sa <= sb, alpha*a <= alpha*b),
    // so each end is within 2U(sb + alpha*b) + ETA/2 of its exact value, and the final
    // subtraction rounds by U more. (Six directed steps cost more than the rest.)
    let ga = sa - alpha * a;
    let gb = sb - alpha * b;
    let lo = ga.min(gb) - (4.0 * round::U * (sb + alpha * b) + 2.0 * round::ETA);
    // 1/(4 alpha) without a second division: alpha = fl(1/sum) >= (1-U)/sum, so
    // 1/alpha <= sum/(1-U); sum/4 is exact (alpha normal: sum is not subnormal), and
    // fl(sum/4 * (1+8U)) >= sum/4 (1+8U)(1-U) >= sum/(4(1-U)).
    let hi = 0.25 * sum * (1.0 + 8.0 * round::U);
    let ap = finish(alpha, lo, hi);
    if ap.is_entire() {
        None
    } else {
        Some(ap)
    }
}

/// Fast path of [`sqrt`] for `a < 0 < b < inf` with the slope `alpha > 0` chosen there,
/// in closed form: on `[a, 0]` (where the extended `sqrt` is 0) `g = -alpha*x` runs
/// from `-alpha*a` to 0; on `[0, b]` `g` is concave, so its minimum is at an end (`0` or
/// `sqrt(b) - alpha*b`) and its maximum at most `1/(4 alpha)` (see [`sqrt_fast`]), or
/// `g(b)` when the stationary point `1/(4 alpha^2)` lies beyond `b`. The
/// general path computes the same bounds through a tangent at an approximate
/// stationary point, with several more roundings and divisions (R-functions take this
/// path whenever both their arguments' ranges hold 0). `None` when `alpha` is not a
/// normal positive float.
#[inline]
fn sqrt_fast_across(a: f64, b: f64, sb: f64, alpha: f64) -> Option<Approx> {
    if !(alpha >= f64::MIN_POSITIVE && alpha.is_finite()) {
        return None;
    }
    let gb = (sb.next_down() - (alpha * b).next_up()).next_down();
    // The stationary point 1/(4 alpha^2) lies beyond b when alpha sqrt(b) < 1/2 (with
    // a wide margin for rounding): then g increases on [0, b] and g(b) is its maximum.
    let top = if 2.0 * alpha * sb <= 1.0 - 1e-9 {
        (sb.next_up() - (alpha * b).next_down()).next_up()
    } else {
        (0.25 / alpha).next_up()
    };
    let hi = top.max((-(alpha * a)).next_up());
    let ap = finish(alpha, gb.min(0.0), hi);
    if ap.is_entire() {
        None
    } else {
        Some(ap)
    }
}

/// `1/x` on `[a, b]`; [`Approx::ENTIRE`] when `0 ∈ [a, b]`.
///
/// Chebyshev (`alpha = -1/(ab)`) while its enclosure keeps the sign of `1/x` (roughly
/// `b < 4a`); otherwise min-range (`alpha = -1/b^2`, the enclosure is then about
/// `[1/b, 1/a]`), so a positive input never yields a range reaching 0. Negative inputs
/// are mirrored. An unbounded end gives the constant range approximation.
pub fn recip(a: f64, b: f64) -> Approx {
    if bad(a, b) || (a <= 0.0 && b >= 0.0) {
        return Approx::ENTIRE;
    }
    if b < 0.0 {
        return mirror(recip(-b, -a));
    }
    let range = || range_powi(a, b, -1);
    if a == b || !b.is_finite() {
        let (lo, hi) = range();
        return Approx::from_range(lo, hi);
    }
    if a > 0.0 {
        if let Some(ap) = recip_fast(a, b) {
            return ap;
        }
    }
    let f = recip_enc;
    let df = |x: f64| {
        let (x2l, x2h) = (mul_lo(x, x).max(0.0), mul_hi(x, x));
        (
            -round::div_up(1.0, x2l),
            // -1/x^2 < 0 (the rounded bound can come out as +2^-1074).
            (-round::div_down(1.0, x2h)).min(0.0),
        )
    };
    let cheb = {
        let alpha = flush(-(1.0 / a) / b);
        let (lo, hi) = bound_piece(&f, &df, alpha, a, b, a.sqrt() * b.sqrt(), true);
        finish(alpha, lo, hi)
    };
    if !cheb.is_entire() && approx_min(&cheb, a, b) > 0.0 {
        return cheb;
    }
    let alpha = flush(-(1.0 / b) / b);
    let (lo, hi) = bound_piece(&f, &df, alpha, a, b, b, true);
    or_range(finish(alpha, lo, hi), range)
}

/// Fast path of [`recip`] for `0 < a < b < inf`: the same choice (Chebyshev
/// `alpha = -1/(ab)` while its enclosure stays positive, else min-range `-1/b^2`), bounded
/// in closed form. With `c = -alpha > 0`, `g(x) = 1/x + c x` is convex, so its maximum is
/// at an end, and `g(x) >= 2 sqrt(c)` for every real `x > 0` (AM-GM), whatever float `c`
/// came out. Each of `1/x`, `c x`, `sqrt(c)` and the sum is one correctly rounded
/// operation, so `next_up`/`next_down` of it bounds the exact value. `None` when a value
/// leaves the normal finite range.
#[inline]
fn recip_fast(a: f64, b: f64) -> Option<Approx> {
    let bound = |c: f64| {
        if !(c >= f64::MIN_POSITIVE && c.is_finite()) {
            return None;
        }
        let ga = up(up(1.0 / a) + up(c * a));
        let gb = up(up(1.0 / b) + up(c * b));
        let ap = finish(-c, 2.0 * down(c.sqrt()), ga.max(gb));
        (!ap.is_entire()).then_some(ap)
    };
    let cheb = bound((1.0 / a) / b)?;
    if approx_min(&cheb, a, b) > 0.0 {
        return Some(cheb);
    }
    bound((1.0 / b) / b)
}

/// `e^x` on `[a, b]`.
///
/// Chebyshev (`alpha = (e^b - e^a)/(b - a)`) while its enclosure stays positive;
/// otherwise min-range (`alpha` = a lower bound of `e^a`, enclosure about `[e^a, e^b]`).
/// `b = +inf` gives ENTIRE, `a = -inf` the constant `[0, e^b]`.
pub fn exp(a: f64, b: f64) -> Approx {
    if bad(a, b) || b == f64::INFINITY {
        return Approx::ENTIRE;
    }
    let range = || range_exp(a, b);
    if a == b || !a.is_finite() {
        let (lo, hi) = range();
        return Approx::from_range(lo, hi);
    }
    // e^x > 0: clipping the lower bound keeps slopes near 0 from turning negative.
    let f = |x: f64| {
        let (lo, hi) = libm_enclose(x.exp());
        (lo.max(0.0), hi)
    };
    let ea = a.exp();
    let (fa, fb) = (libm_enclose(ea), f(b));
    let fa = (fa.0.max(0.0), fa.1);
    // g = e^x - alpha*x is convex: its maximum is at an end, and for alpha > 0 and every
    // real x, g(x) >= alpha - alpha*ln(alpha) (its minimum, at x = ln(alpha)), whatever
    // float alpha came out: one libm `ln` instead of a tangent's `exp` twice.
    let bound = |alpha: f64| {
        let hi = g_hi(fa.1, alpha, a).max(g_hi(fb.1, alpha, b));
        let lo = if alpha > 0.0 {
            mul_lo(alpha, sub_lo(1.0, libm_enclose(alpha.ln()).1))
        } else {
            // alpha = 0 (flushed): g = e^x > 0, at least the lower end's enclosure.
            fa.0
        };
        finish(alpha, lo, hi)
    };
    let w = b - a;
    let alpha = flush(ea * (w.exp_m1() / w));
    if alpha.is_finite() && alpha > 0.0 {
        let cheb = bound(alpha);
        if !cheb.is_entire() && approx_min(&cheb, a, b) > 0.0 {
            return cheb;
        }
    }
    let alpha = flush(fa.0);
    or_range(bound(alpha), range)
}

/// `ln x` on `[a, b]`; [`Approx::ENTIRE`] when `a <= 0` (or `b = +inf`).
///
/// Concave: Chebyshev, `alpha = ln(b/a)/(b - a)` (the secant slope).
pub fn ln(a: f64, b: f64) -> Approx {
    if bad(a, b) || a <= 0.0 || b == f64::INFINITY {
        return Approx::ENTIRE;
    }
    let range = || range_ln(a, b);
    if a == b {
        let (lo, hi) = range();
        return Approx::from_range(lo, hi);
    }
    let f = |x: f64| libm_enclose(x.ln());
    let df = |x: f64| (round::div_down(1.0, x), round::div_up(1.0, x));
    let w = b - a;
    let r = w / a;
    let alpha = flush(if r.is_finite() {
        r.ln_1p() / w
    } else {
        (b.ln() - a.ln()) / w
    });
    let (lo, hi) = bound_piece(&f, &df, alpha, a, b, 1.0 / alpha, false);
    or_range(finish(alpha, lo, hi), range)
}

/// `|x|` on `[a, b]`: exact (`alpha = ±1`, `delta = 0`) on one side of 0; straddling 0,
/// Chebyshev `alpha = (a + b)/(b - a)` (the secant slope; `|x|` is convex).
pub fn abs(a: f64, b: f64) -> Approx {
    if bad(a, b) {
        return Approx::ENTIRE;
    }
    if a >= 0.0 {
        return Approx {
            alpha: 1.0,
            zeta: 0.0,
            delta: 0.0,
        };
    }
    if b <= 0.0 {
        return Approx {
            alpha: -1.0,
            zeta: 0.0,
            delta: 0.0,
        };
    }
    if !a.is_finite() || !b.is_finite() {
        return Approx::ENTIRE;
    }
    // |alpha| <= 1 in floating point too (|fl(a+b)| <= fl(b-a)), so g = |x| - alpha*x
    // >= 0, with its maximum at an end.
    let alpha = flush(((a + b) / (b - a)).clamp(-1.0, 1.0));
    finish(alpha, 0.0, g_hi(-a, alpha, a).max(g_hi(b, alpha, b)))
}

/// Secant slope of `x^n` on `[a, b]`: `sum_{k<n} a^k b^(n-1-k)` (no cancellation).
fn pow_secant(a: f64, b: f64, n: u32) -> f64 {
    if n > 64 {
        return (b.powi(n as i32) - a.powi(n as i32)) / (b - a);
    }
    let (mut acc, mut bp) = (1.0f64, 1.0f64);
    for _ in 1..n {
        bp *= b;
        acc = acc * a + bp;
    }
    acc
}

/// Root `t ∈ (0, 1)` of `(n-1) t^n + n t^(n-1) = 1`: for odd `n` the minimax slope of
/// `x^n` on `[-r, r]` is `n (t r)^(n-1)` (`t = 1/2` for `n = 3`).
fn odd_pow_t(n: u32) -> f64 {
    let nf = n as f64;
    let mut t = 1.0f64;
    for _ in 0..60 {
        let tn1 = t.powi(n as i32 - 2);
        let h = (nf - 1.0) * tn1 * t * t + nf * tn1 * t - 1.0;
        let dh = nf * (nf - 1.0) * tn1 * (t + 1.0);
        let step = h / dh;
        if !step.is_finite() {
            break;
        }
        t -= step;
        if step.abs() < 1e-16 {
            break;
        }
    }
    t.clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    //! Hand-derived values (closed forms of the Chebyshev / min-range construction,
    //! evaluated independently); `delta` must cover the hand value and be at most a few
    //! rounding errors wider.
    use super::super::tests::{check, zero_width};
    use super::*;

    #[test]
    fn sqrt_chebyshev_and_clipped() {
        // Secant 1/3; g = sqrt(x) - x/3 is 2/3 at both ends, 3/4 at x = 9/4.
        check(sqrt(1.0, 4.0), 1.0 / 3.0, 17.0 / 24.0, 1.0 / 24.0);
        // -a = b/4: alpha = 1/2; g: 1/2 at -1, 0 at 0, 1/2 at 1, 0 at 4.
        check(sqrt(-1.0, 4.0), 0.5, 0.25, 0.25);
        // -a = b: alpha = 1/4; g: 1 at -4, 0 at 0, 1 at 4.
        check(sqrt(-4.0, 4.0), 0.25, 0.5, 0.5);
        // -a > b: secant 2/13; g = 18/13 at both ends, 0 at 0.
        check(sqrt(-9.0, 4.0), 2.0 / 13.0, 9.0 / 13.0, 9.0 / 13.0);
        let zero = Approx {
            alpha: 0.0,
            zeta: 0.0,
            delta: 0.0,
        };
        assert_eq!(sqrt(-3.0, -1.0), zero);
        assert_eq!(sqrt(f64::NEG_INFINITY, 0.0), zero);
        assert_eq!(sqrt(4.0, 4.0), zero_width(2.0));
    }

    #[test]
    fn sqrt_at_least_uses_a_higher_floor() {
        // A floor above the range's own lower end replaces it; one below is ignored.
        assert_eq!(sqrt_at_least(-1.0, 4.0, 1.0), sqrt(1.0, 4.0));
        assert_eq!(sqrt_at_least(2.0, 4.0, 1.0), sqrt(2.0, 4.0));
    }

    #[test]
    fn sqr_and_powi() {
        // alpha = 4, g = x^2 - 4x ∈ [-4, -3].
        check(sqr(1.0, 3.0), 4.0, -3.5, 0.5);
        // alpha = 1, g = x^2 - x: 2 at both ends, -1/4 at 1/2.
        check(sqr(-1.0, 2.0), 1.0, 0.875, 1.125);
        assert_eq!(sqr(3.0, 3.0), zero_width(9.0));
        // x^3 on [-2, 2]: alpha = 3*(2/2)^2 = 3, g = x^3 - 3x ∈ [-2, 2].
        check(powi(-2.0, 2.0, 3), 3.0, 0.0, 2.0);
        // x^3 on [-1/2, 1]: -a = b/2 still takes the symmetric slope 3/4; g ∈ [-1/4, 1/4].
        check(powi(-0.5, 1.0, 3), 0.75, 0.0, 0.25);
        // x^3 on [-1/4, 1]: secant 0.8125, g = 0.1875 at both ends, min at sqrt(0.8125/3).
        check(
            powi(-0.25, 1.0, 3),
            0.8125,
            -0.047_196_135_380_519_4,
            0.2346961353805194,
        );
        // Mirrored: x^3 is odd.
        check(
            powi(-1.0, 0.25, 3),
            0.8125,
            0.047_196_135_380_519_4,
            0.2346961353805194,
        );
        // x^4 on [1, 2]: secant 15; g = -14 at the ends, min at (15/4)^(1/3).
        check(
            powi(1.0, 2.0, 4),
            15.0,
            -15.739091422995228,
            1.739091422995228,
        );
        // x^3 on [1, 2]: secant 7, g = -6 at the ends, min at sqrt(7/3): -14/3*sqrt(7/3).
        let gmin = -14.0 / 3.0 * (7.0f64 / 3.0).sqrt();
        check(
            powi(1.0, 2.0, 3),
            7.0,
            0.5 * (gmin - 6.0),
            0.5 * (-6.0 - gmin),
        );
    }

    #[test]
    fn recip_chebyshev_then_min_range() {
        // b < 4a: Chebyshev -1/2; g = 1/x + x/2: 3/2 at the ends, sqrt(2) at sqrt(2).
        let (z, d) = (0.5 * (1.5 + 2f64.sqrt()), 0.5 * (1.5 - 2f64.sqrt()));
        check(recip(1.0, 2.0), -0.5, z, d);
        check(recip(-2.0, -1.0), -0.5, -z, d);
        // b > 4a: min-range -1/25; g = 1/x + x/25 decreasing from 1.04 to 0.4.
        check(recip(1.0, 5.0), -0.04, 0.72, 0.32);
        assert!(recip(-1.0, 1.0).is_entire());
        assert!(recip(0.0, 1.0).is_entire());
        assert!(recip(-1.0, -0.0).is_entire());
    }

    #[test]
    fn exp_chebyshev_then_min_range() {
        // Secant e - 1; g = 1 at both ends, (e-1)(1 - ln(e-1)) at ln(e-1).
        check(
            exp(0.0, 1.0),
            std::f64::consts::E - 1.0,
            0.8940665837422167,
            0.10593341625778326,
        );
        // Chebyshev would go below 0: min-range alpha = 1, g = e^x - x ∈ [1, e^4 - 4].
        check(exp(0.0, 4.0), 1.0, 25.79907501657212, 24.79907501657212);
        assert!(exp(0.0, f64::INFINITY).is_entire());
        assert!(exp(0.0, 1000.0).is_entire());
    }

    #[test]
    fn ln_chebyshev() {
        // Secant ln(8)/7; g = -ln(8)/7 at both ends, -ln(alpha) - 1 at 1/alpha.
        check(
            ln(1.0, 8.0),
            0.2970630773828337,
            -0.04162614820698288,
            0.2554369291758508,
        );
        assert!(ln(0.0, 1.0).is_entire());
        assert!(ln(-2.0, -1.0).is_entire());
    }

    #[test]
    fn abs_cases() {
        // alpha = 1/2; g = |x| - x/2: 3/2 at both ends, 0 at 0.
        check(abs(-1.0, 3.0), 0.5, 0.75, 0.75);
        assert_eq!(
            abs(2.0, 5.0),
            Approx {
                alpha: 1.0,
                zeta: 0.0,
                delta: 0.0
            }
        );
        assert_eq!(
            abs(-5.0, -2.0),
            Approx {
                alpha: -1.0,
                zeta: 0.0,
                delta: 0.0
            }
        );
        assert!(abs(f64::NEG_INFINITY, 1.0).is_entire());
    }

    #[test]
    fn fast_paths_are_taken_and_agree() {
        // sqrt on [1, 4]: alpha = 1/3, g ∈ [2/3, 3/4] (1/(4 alpha) = 3/4 exactly).
        let ap = sqrt_fast(1.0, 4.0, 2.0).expect("fast path");
        assert_eq!(ap, sqrt(1.0, 4.0));
        check(ap, 1.0 / 3.0, 17.0 / 24.0, 1.0 / 24.0);
        // recip on [1, 2] (Chebyshev) and [1, 5] (min-range), as in the general path.
        assert_eq!(recip_fast(1.0, 2.0), Some(recip(1.0, 2.0)));
        let (z, d) = (0.5 * (1.5 + 2f64.sqrt()), 0.5 * (1.5 - 2f64.sqrt()));
        check(recip_fast(1.0, 2.0).unwrap(), -0.5, z, d);
        check(recip_fast(1.0, 5.0).unwrap(), -0.04, 0.72, 0.32);
    }
}
