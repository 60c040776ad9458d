//! The single source of affine approximations of non-affine functions, and of the
//! rigorous interval enclosures they are built on.
//!
//! For a function `f` and a finite interval `[a, b]`, an [`Approx`] `{alpha, zeta, delta}`
//! promises, in exact real arithmetic on the three stored `f64` values:
//!
//! ```text
//! for every real x in [a, b]:  alpha*x + zeta - delta <= f(x) <= alpha*x + zeta + delta
//! ```
//!
//! Rounding inside this module is already accounted for; an affine arithmetic only adds
//! the rounding error of *its own* evaluation of `alpha*x̂ + zeta` and decides where
//! `delta` goes (a new symbol in AA, the accumulator in AF1, the radius `e` in RevAA).
//!
//! Construction (robust pattern): `alpha` is chosen in plain floating point (Chebyshev,
//! i.e. the secant slope, where `f` is convex or concave on `[a, b]`; min-range where
//! that is required or tighter), then `g(x) = f(x) - alpha*x` is bounded rigorously over
//! `[a, b]` (ends, and tangent-line bounds at stationary points, outward rounded) to get
//! `zeta` and `delta`. So soundness never depends on `alpha` being exact.
//!
//! Unbounded cases return [`Approx::ENTIRE`] (`delta = +inf`).
//! The `range_*` functions are the rigorous interval enclosures used by interval
//! arithmetic and by the fallbacks here.

use crate::affine_round;
use crate::round::{self, down, libm_enclose, two_sum, up};

/// `f(x) ∈ alpha*x + zeta ± delta` on the interval it was built for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Approx {
    pub alpha: f64,
    pub zeta: f64,
    pub delta: f64,
}

impl Approx {
    /// No information: the whole line.
    pub const ENTIRE: Approx = Approx {
        alpha: 0.0,
        zeta: 0.0,
        delta: f64::INFINITY,
    };

    /// Whether this approximation is unbounded (callers then produce an unbounded form).
    pub fn is_entire(&self) -> bool {
        !(self.delta.is_finite() && self.alpha.is_finite() && self.zeta.is_finite())
    }

    /// The constant approximation enclosing `[lo, hi]` (`alpha = 0`). Exact (`delta = 0`)
    /// for a point; ENTIRE for an unbounded, NaN or reversed range.
    pub fn from_range(lo: f64, hi: f64) -> Approx {
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return Approx::ENTIRE;
        }
        // Directed differences: a range with an exact midpoint stays exact.
        let zeta = 0.5 * lo + 0.5 * hi;
        let delta = sub_hi(hi, zeta).max(sub_hi(zeta, lo)).max(0.0);
        if !(zeta.is_finite() && delta.is_finite()) {
            return Approx::ENTIRE;
        }
        Approx {
            alpha: 0.0,
            zeta,
            delta,
        }
    }
}

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
            mul_pair(lo, nf)
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
        let hi = g_enc(fa, alpha, a).1.max(g_enc(fb, alpha, b).1);
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

/// `sin x` on `[a, b]`.
///
/// Without an inflection (a multiple of `pi`) in `[a, b]`, decided conservatively:
/// Chebyshev, `alpha` = secant slope. With one: the secant slope with a mean-value
/// bound, or `alpha = 0` with the range, whichever is narrower. `|x| > 1e7`: `alpha = 0`.
pub fn sin(a: f64, b: f64) -> Approx {
    trig_approx(Trig::Sin, a, b)
}

/// `cos x` on `[a, b]`: as [`sin`], with inflections at `pi/2 + k*pi`.
pub fn cos(a: f64, b: f64) -> Approx {
    trig_approx(Trig::Cos, a, b)
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
    let ga = g_enc((-a, -a), alpha, a);
    let gb = g_enc((b, b), alpha, b);
    finish(alpha, 0.0, ga.1.max(gb.1))
}

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

// ---------------------------------------------------------------------------------
// Directed operations that stay exact when the exact result is representable (so that
// hand-checkable cases such as `sqr` on `[1, 3]` come out exact), and that never return
// NaN: an undefined bound becomes the infinite bound on its side.
// ---------------------------------------------------------------------------------

/// Products whose magnitude is at least this have an exactly representable error term.
const EXACT_MIN: f64 = 1.0e-280;
/// Factors below this magnitude can be split (Veltkamp) without overflow.
const SPLIT_MAX: f64 = 1.0e299;
/// Factors at least this large split without underflow.
const FACTOR_MIN: f64 = 1.0e-290;

/// A slope too small to matter (subnormal) is replaced by 0: a subnormal `alpha` carries
/// few significant bits, so `alpha*x` would only add rounding noise.
fn flush(alpha: f64) -> f64 {
    if alpha.abs() < f64::MIN_POSITIVE {
        0.0
    } else {
        alpha
    }
}

/// The exact error `a*b - p` of `p = fl(a*b)`, for `EXACT_MIN <= |p|` and
/// `|a|, |b| < SPLIT_MAX`: one FMA where the target has it, else Dekker's product
/// (a call to a software `fma` would cost more than the rest of an approximation).
#[inline]
fn prod_err(a: f64, b: f64, p: f64) -> f64 {
    if cfg!(target_feature = "fma") {
        a.mul_add(b, -p)
    } else {
        dekker_err(a, b, p)
    }
}

/// Dekker's error of `p = fl(a*b)` with Veltkamp splitting (exact under the same
/// conditions as [`prod_err`]).
#[inline]
fn dekker_err(a: f64, b: f64, p: f64) -> f64 {
    let split = |x: f64| {
        let c = 134_217_729.0 * x; // 2^27 + 1
        let hi = c - (c - x);
        (hi, x - hi)
    };
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    ((ah * bh - p) + ah * bl + al * bh) + al * bl
}

/// Lower and upper bound of `a * b` from one product (exact when representable;
/// `0 * inf` gives `(-inf, +inf)`).
#[inline]
fn mul_pair(a: f64, b: f64) -> (f64, f64) {
    if (a == 0.0 && b.is_finite()) || (b == 0.0 && a.is_finite()) {
        return (0.0, 0.0);
    }
    let p = a * b;
    let (ma, mb) = (a.abs(), b.abs());
    // Normal, splittable factors and a product far from underflow: the error term is exact.
    if p.is_finite()
        && p.abs() >= EXACT_MIN
        && (FACTOR_MIN..SPLIT_MAX).contains(&ma)
        && (FACTOR_MIN..SPLIT_MAX).contains(&mb)
    {
        let e = prod_err(a, b, p);
        // Selects rather than branches: the sign of `e` is data-dependent noise.
        let (dn, upv) = (p.next_down(), p.next_up());
        (if e < 0.0 { dn } else { p }, if e > 0.0 { upv } else { p })
    } else {
        (round::mul_down(a, b), round::mul_up(a, b))
    }
}

/// An upper bound of `a * b` (exact when representable; `0 * inf` gives `+inf`).
fn mul_hi(a: f64, b: f64) -> f64 {
    mul_pair(a, b).1
}

/// A lower bound of `a * b` (exact when representable; `0 * inf` gives `-inf`).
fn mul_lo(a: f64, b: f64) -> f64 {
    mul_pair(a, b).0
}

/// An upper bound of `a + b` (exact when representable).
fn add_hi(a: f64, b: f64) -> f64 {
    let (s, e) = two_sum(a, b);
    if s.is_finite() && e.is_finite() {
        if e > 0.0 {
            up(s)
        } else {
            s
        }
    } else {
        up(s)
    }
}

/// A lower bound of `a + b` (exact when representable).
fn add_lo(a: f64, b: f64) -> f64 {
    let (s, e) = two_sum(a, b);
    if s.is_finite() && e.is_finite() {
        if e < 0.0 {
            down(s)
        } else {
            s
        }
    } else {
        down(s)
    }
}

fn sub_hi(a: f64, b: f64) -> f64 {
    add_hi(a, -b)
}

fn sub_lo(a: f64, b: f64) -> f64 {
    add_lo(a, -b)
}

/// Enclosure of `d * t` for `d ∈ [d.0, d.1]`, `t ∈ [t.0, t.1]` with `t.0 <= 0 <= t.1`
/// (a slope times an offset from a point inside the interval). Then the extremes are
/// `min(d.1*t.0, d.0*t.1)` and `max(d.0*t.0, d.1*t.1)`. Plain outward rounding: these
/// terms are small corrections, exactness buys nothing.
fn slope_times_offset(d: (f64, f64), t: (f64, f64)) -> (f64, f64) {
    debug_assert!(t.0 <= 0.0 && t.1 >= 0.0);
    let lo = round::mul_down(d.1, t.0).min(round::mul_down(d.0, t.1));
    let hi = round::mul_up(d.0, t.0).max(round::mul_up(d.1, t.1));
    (lo, hi)
}

/// Enclosure of `sqrt(x)` for `x >= 0` (exact when `x` is a perfect square).
fn sqrt_enc(x: f64) -> (f64, f64) {
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
fn recip_enc(x: f64) -> (f64, f64) {
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
fn pow_enc(x: f64, n: u32) -> (f64, f64) {
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
        let (lo, hi) = mul_pair(x.0, y.0);
        (lo.max(0.0), hi)
    } else {
        (mul_lo(x.0, y.0).max(0.0), mul_hi(x.1, y.1))
    }
}

/// Whether `[a, b]` is empty or malformed (NaN bounds, `a > b`).
fn bad(a: f64, b: f64) -> bool {
    a.is_nan() || b.is_nan() || a > b
}

/// Enclosure of `g(x) = f(x) - alpha*x` at a float `x`, given `f(x) ∈ fx`.
fn g_enc(fx: (f64, f64), alpha: f64, x: f64) -> (f64, f64) {
    (
        sub_lo(fx.0, mul_hi(alpha, x)),
        sub_hi(fx.1, mul_lo(alpha, x)),
    )
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
fn mid(a: f64, b: f64) -> f64 {
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
fn bound_piece<F, D>(f: &F, df: &D, alpha: f64, a: f64, b: f64, p: f64, convex: bool) -> (f64, f64)
where
    F: Fn(f64) -> (f64, f64),
    D: Fn(f64) -> (f64, f64),
{
    let ga = g_enc(f(a), alpha, a);
    let gb = g_enc(f(b), alpha, b);
    let p = clamp_in(p, a, b);
    let gp = g_enc(f(p), alpha, p);
    let d = df(p);
    let dg = (sub_lo(d.0, alpha), sub_hi(d.1, alpha));
    let (tlo, thi) = slope_times_offset(dg, (sub_lo(a, p), sub_hi(b, p)));
    if convex {
        (add_lo(gp.0, tlo), ga.1.max(gb.1))
    } else {
        (ga.0.min(gb.0), add_hi(gp.1, thi))
    }
}

/// The approximation `alpha*x + zeta ± delta` from `g = f - alpha*x ∈ [lo, hi]`:
/// `zeta` near the midpoint, `delta` an upper bound of both exact half-widths, so that
/// `[zeta - delta, zeta + delta] ⊇ [lo, hi]` exactly. Anything unbounded gives ENTIRE.
fn finish(alpha: f64, lo: f64, hi: f64) -> Approx {
    if !(alpha.is_finite() && lo.is_finite() && hi.is_finite() && lo <= hi) {
        return Approx::ENTIRE;
    }
    let zeta = 0.5 * lo + 0.5 * hi;
    // Each difference is within U (relative) of the exact one, and exact when subnormal;
    // `(1-U)^2 (1+4U) > 1`, so scaling the larger by `1 + 4U` bounds both from above
    // (cheaper than two directed subtractions; 0 stays 0).
    let delta = (hi - zeta).max(zeta - lo).max(0.0) * (1.0 + 4.0 * round::U);
    if !(zeta.is_finite() && delta.is_finite()) {
        return Approx::ENTIRE;
    }
    Approx { alpha, zeta, delta }
}

/// If `ap` came out unbounded (overflow inside the affine part), try the constant
/// approximation of the rigorous range instead.
fn or_range(ap: Approx, range: impl FnOnce() -> (f64, f64)) -> Approx {
    if ap.is_entire() {
        let (lo, hi) = range();
        Approx::from_range(lo, hi)
    } else {
        ap
    }
}

/// For an odd `f`: the approximation on `[a, b]` from one on `[-b, -a]`.
fn mirror(ap: Approx) -> Approx {
    Approx {
        alpha: ap.alpha,
        zeta: -ap.zeta,
        delta: ap.delta,
    }
}

/// The affine range `min alpha*x + zeta - delta` over `x ∈ {a, b}` in plain floating point
/// (only used to choose between two sound approximations).
fn approx_min(ap: &Approx, a: f64, b: f64) -> f64 {
    (ap.alpha * a).min(ap.alpha * b) + ap.zeta - ap.delta
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

/// Largest argument magnitude for which `sin`/`cos` get more than `[-1, 1]`.
const TRIG_MAX_ARG: f64 = 1.0e7;
/// Safety margin (in periods) of [`may_contain`]; float errors are below `1e-9` there.
const PERIOD_EPS: f64 = 1.0e-6;

/// Conservatively: whether `[a, b]` (finite, `|a|, |b| <= TRIG_MAX_ARG`) may contain a
/// point `offset + k*period` (`k` integer). The float quotient `(x - offset)/period` is
/// within `1e-9` of the exact one at these magnitudes; `PERIOD_EPS` covers that with room.
fn may_contain(a: f64, b: f64, offset: f64, period: f64) -> bool {
    let u = (a - offset) / period - PERIOD_EPS;
    let v = (b - offset) / period + PERIOD_EPS;
    u.ceil() <= v.floor()
}

#[derive(Clone, Copy, PartialEq)]
enum Trig {
    Sin,
    Cos,
}

impl Trig {
    fn f(self, x: f64) -> (f64, f64) {
        match self {
            Trig::Sin => libm_enclose(x.sin()),
            Trig::Cos => libm_enclose(x.cos()),
        }
    }
    fn df(self, x: f64) -> (f64, f64) {
        match self {
            Trig::Sin => libm_enclose(x.cos()),
            Trig::Cos => {
                let (lo, hi) = libm_enclose(x.sin());
                (-hi, -lo)
            }
        }
    }
    fn range(self, a: f64, b: f64) -> (f64, f64) {
        match self {
            Trig::Sin => range_sin(a, b),
            Trig::Cos => range_cos(a, b),
        }
    }
    /// Derivative range over `[a, b]` (`cos` for sin, `-sin` for cos).
    fn drange(self, a: f64, b: f64) -> (f64, f64) {
        match self {
            Trig::Sin => range_cos(a, b),
            Trig::Cos => {
                let (lo, hi) = range_sin(a, b);
                (-hi, -lo)
            }
        }
    }
}

/// Largest half-width for which [`trig_taylor`] is tried (its excess over Chebyshev is
/// `O(h)` relative; wider intervals rarely pass its acceptance test).
const TAYLOR_MAX_H: f64 = 0.5;

/// Fast path of [`sin`] / [`cos`] on a narrow `[a, b]` (midpoint `m`, half-width `h`):
/// one libm call (`sin_cos m`) instead of about nine, no inflection test.
///
/// Second-order Taylor form with Lagrange remainder, valid with or without an
/// inflection: `g(x) = f(x) - alpha*x = g(m) + g'(m)(x - m) + f''(xi)(x - m)^2/2` for some
/// `xi ∈ [a, b]`, where `f'' = -f` and `|f(xi) - f(m)| <= |xi - m| <= r` (`|f'| <= 1`,
/// `r >= max(b - m, m - a)`). So `g ∈ g(m) ± |g'(m)| r + [min(-fmax, 0), max(-fmin, 0)] r²/2`
/// with `f(xi) ∈ [fmin, fmax] = f(m) ± r`. `alpha` (secant slope `f'(m) sinc(h)`, `sinc`
/// by its Taylor series; only tightness depends on it). Computed in round-to-nearest with
/// one bulk allowance for all roundings (see the body), which halved the cost of `sin`
/// on narrow ranges against directed rounding of every step.
///
/// Accepted only when its `delta` is within 1/8 of the Chebyshev `delta ≈ |f(m)| h²/4`
/// (a float estimate used for the choice only) plus `h³/2`, so tightness is kept; else
/// `None`.
fn trig_taylor(t: Trig, a: f64, b: f64, m: f64, h: f64) -> Option<Approx> {
    use round::{ETA, LIBM_REL, U};
    // Plain round-to-nearest throughout, then one bulk allowance for every rounding
    // (directed rounding of each step cost more than the libm calls). All magnitudes
    // here are at most |alpha m| + 3 <= 1e7 + 3 (|m| <= TRIG_MAX_ARG, |alpha| <= 1).
    let (s, c) = m.sin_cos();
    // f(m), f'(m) as floats; the true values are within `LIBM_REL |v| + ETA` of them.
    let (fv, dv) = match t {
        Trig::Sin => (s, c),
        Trig::Cos => (c, -s),
    };
    let h2 = h * h;
    let sinc = 1.0 - h2 / 6.0 * (1.0 - h2 / 20.0);
    let alpha = flush((dv * sinc).clamp(-1.0, 1.0));
    // r >= max(b - m, m - a): each difference is within an ulp of the exact one.
    let r = (b - m).max(m - a) * (1.0 + 4.0 * U) + ETA;
    let es = fv.abs() * LIBM_REL + ETA;
    let ed = dv.abs() * LIBM_REL + ETA;
    let am = alpha * m;
    let gm = fv - am;
    // |g'(m)| r with g'(m) = f'(m) - alpha.
    let lin = ((dv - alpha).abs() + ed) * r;
    // -f(xi) r^2/2 for f(xi) ∈ [fmin, fmax] = (f(m) ± r) ∩ [-1, 1].
    let fmax = (fv + es + r).min(1.0);
    let fmin = (fv - es - r).max(-1.0);
    let r2h = 0.5 * (r * r);
    let qlo = (-fmax).min(0.0) * r2h;
    let qhi = (-fmin).max(0.0) * r2h;
    // Third order as well (tighter near an inflection, where f(m) ≈ 0):
    // g = g(m) + g'(m) u - f(m) u^2/2 - f'(xi) u^3/6, |f'(xi)| <= min(|f'(m)| + r, 1).
    let q3lo = (-(fv + es)).min(0.0) * r2h;
    let q3hi = (-(fv - es)).max(0.0) * r2h;
    let c3 = r * r2h * (1.0 / 3.0) * (dv.abs() + ed + r).min(1.0);
    // Both enclose g on [a, b]: keep their intersection.
    let lo = (gm - lin + qlo).max(gm - lin + q3lo - c3);
    let hi = (gm + lin + qhi).min(gm + lin + q3hi + c3);
    let zeta = 0.5 * lo + 0.5 * hi;
    let half = 0.5 * (hi - lo);
    // Rounding allowance: f(m) (es), alpha*m and the difference gm (U each, plus ETA for
    // a subnormal product), lin and the q and c3 terms (a few U relative each: products
    // of rounded upper bounds), the three- and four-term sums lo, hi, then zeta, half.
    let mags = gm.abs() + am.abs() + lin + qhi - qlo + q3hi - q3lo + c3;
    let slack = es + 16.0 * U * mags + 8.0 * ETA;
    let delta = affine_round::up_abs(half + slack + U * (zeta.abs() + half), 8);
    let ap = if alpha.is_finite() && zeta.is_finite() && delta.is_finite() {
        Approx { alpha, zeta, delta }
    } else {
        return None;
    };
    // Accepted only when not much wider than Chebyshev (`|f(m)| h^2/4`, an estimate used
    // for the choice only) plus the floor of the general path's own roundings, plus
    // `h^3/2`: near an inflection (`f(m) ≈ 0`) the general path's mean-value form is
    // itself `O(h^3)` wide (about `h^3/4`; this form's third order gives about `h^3/3`),
    // at several times the cost (measured: the general path was most of the time of the
    // sine models; taking this one on them costs under 1% more range evaluations).
    let cheb = 0.25 * fv.abs() * h2 + 32.0 * U * (fv.abs() + am.abs());
    if ap.delta <= 1.125 * cheb + 0.5 * h2 * h {
        Some(ap)
    } else {
        None
    }
}

/// Shared body of [`sin`] and [`cos`].
fn trig_approx(t: Trig, a: f64, b: f64) -> Approx {
    use core::f64::consts::{FRAC_PI_2, PI, TAU};
    if bad(a, b) {
        return Approx::ENTIRE;
    }
    let range = || t.range(a, b);
    // The constant approximation of the rigorous range.
    let fallback = || {
        let (lo, hi) = range();
        Approx::from_range(lo, hi)
    };
    if a == b || !(a.abs() <= TRIG_MAX_ARG && b.abs() <= TRIG_MAX_ARG) {
        return fallback();
    }
    let m = mid(a, b);
    let h = 0.5 * (b - a);
    // Extrema of f (zeros of its derivative) at `extremum + k*pi`.
    let extremum = match t {
        Trig::Sin => FRAC_PI_2,
        Trig::Cos => 0.0,
    };
    if h <= TAYLOR_MAX_H {
        if let Some(ap) = trig_taylor(t, a, b, m, h) {
            // Around an extremum the Chebyshev slope is about 0 and the best delta is
            // half the range; the Taylor remainder (`|f(xi)| <= 1`) is `O(h^4)` wider
            // there, so the constant approximation of the range is narrower: take it.
            if may_contain(a, b, extremum, PI) {
                let fb = fallback();
                if fb.delta < ap.delta {
                    return fb;
                }
            }
            return ap;
        }
    }
    let sinc = if h < 1e-8 { 1.0 } else { h.sin() / h };
    // Secant slope: sin b - sin a = 2 cos(m) sin(h), cos b - cos a = -2 sin(m) sin(h).
    let alpha = match t {
        Trig::Sin => m.cos() * sinc,
        Trig::Cos => -m.sin() * sinc,
    }
    .clamp(-1.0, 1.0);
    let alpha = flush(alpha);
    let inflection = match t {
        Trig::Sin => 0.0,
        Trig::Cos => FRAC_PI_2,
    };
    if may_contain(a, b, inflection, PI) {
        // Neither convex nor concave: mean-value form g(x) ∈ g(m) + (f'([a,b]) - alpha)(x - m),
        // or alpha = 0 with the range, whichever is narrower.
        let gm = g_enc(t.f(m), alpha, m);
        let d = t.drange(a, b);
        let dg = (sub_lo(d.0, alpha), sub_hi(d.1, alpha));
        let (tlo, thi) = slope_times_offset(dg, (sub_lo(a, m), sub_hi(b, m)));
        let mv = finish(alpha, add_lo(gm.0, tlo), add_hi(gm.1, thi));
        let fb = fallback();
        return if !mv.is_entire() && mv.delta < fb.delta {
            mv
        } else {
            fb
        };
    }
    // No inflection inside: f'' = -f has the sign of -f(m) on all of [a, b].
    let concave = match t {
        Trig::Sin => m.sin() > 0.0,
        Trig::Cos => m.cos() > 0.0,
    };
    // Stationary point of g: f'(p) = alpha on the branch matching the convexity.
    let p0 = match (t, concave) {
        (Trig::Sin, true) => alpha.acos(),
        (Trig::Sin, false) => -alpha.acos(),
        (Trig::Cos, true) => (-alpha).asin(),
        (Trig::Cos, false) => PI - (-alpha).asin(),
    };
    let p = p0 + TAU * ((m - p0) / TAU).round();
    let (lo, hi) = bound_piece(&|x| t.f(x), &|x| t.df(x), alpha, a, b, p, !concave);
    or_range(finish(alpha, lo, hi), range)
}

#[cfg(test)]
mod tests {
    //! Hand-derived values (closed forms of the Chebyshev / min-range construction,
    //! evaluated independently); `delta` must cover the hand value and be at most a few
    //! rounding errors wider.
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
        // A floor above the range's own lower end replaces it; one below is ignored.
        assert_eq!(sqrt_at_least(-1.0, 4.0, 1.0), sqrt(1.0, 4.0));
        assert_eq!(sqrt_at_least(2.0, 4.0, 1.0), sqrt(2.0, 4.0));
    }

    fn check(ap: Approx, alpha: f64, zeta: f64, delta: f64) {
        let scale = 1.0 + zeta.abs() + delta;
        assert!(
            (ap.alpha - alpha).abs() <= 1e-12 * (1.0 + alpha.abs()),
            "alpha {ap:?} vs {alpha}"
        );
        assert!(
            (ap.zeta - zeta).abs() <= 1e-12 * scale,
            "zeta {ap:?} vs {zeta}"
        );
        // The decimal hand value may be one rounding above the real one.
        assert!(
            ap.delta >= delta * (1.0 - 1e-15),
            "delta too small {ap:?} vs {delta}"
        );
        assert!(
            ap.delta <= delta + 1e-12 * scale,
            "delta too wide {ap:?} vs {delta}"
        );
    }

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

    fn zero_width(v: f64) -> Approx {
        Approx {
            alpha: 0.0,
            zeta: v,
            delta: 0.0,
        }
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
    fn sin_cos_chebyshev_and_fallbacks() {
        // Concave (sin > 0), no multiple of pi inside: secant slope.
        check(
            sin(0.5, 2.5),
            0.059523302749876747,
            0.6789684686476725,
            0.22930458141840787,
        );
        // Convex (cos < 0), no pi/2 + k*pi inside.
        check(
            cos(2.0, 4.0),
            -0.11874839215823476,
            -0.4063249432647849,
            0.22767489103411206,
        );
        // Inflection at 0, wide: secant sin(0.6)/0.6 with the mean-value bound
        // 0.6 * (alpha - cos(0.6)); g(0) = 0 so zeta = 0.
        check(sin(-0.6, 0.6), 0.9410707889917257, 0.0, 0.06944110444922842);
        // Inflection at 0, narrow (the Taylor path): alpha = 1 - h^2/6 (1 - h^2/20) with
        // h = 0.1, then |f'(0) - alpha| h + h^3/6 (third order; f(0) = 0).
        check(
            sin(-0.1, 0.1),
            0.9983341666666666,
            0.0,
            3.3325000000000336e-4,
        );
        // Narrow around the maximum pi/2 (the Taylor path would be O(h^4) wider): the
        // constant approximation of the range [sin(1.2191...), 1]. Found by
        // `delta_at_most_half_the_range`.
        let (a, b) = (1.2191931412375574, 1.9222052783827024);
        let ap = sin(a, b);
        let (lo, hi) = range_sin(a, b);
        assert_eq!(ap, Approx::from_range(lo, hi));
        assert!(ap.delta <= 0.5 * (1.0 - a.sin()) * (1.0 + 1e-12), "{ap:?}");
        // Wide with inflections: the mean-value bound is worse than the range [-1, 1].
        check(sin(-3.0, 3.0), 0.0, 0.0, 1.0);
        check(cos(0.0, 100.0), 0.0, 0.0, 1.0);
        check(sin(1e8, 1e8 + 1.0), 0.0, 0.0, 1.0);
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

    #[test]
    fn fast_paths_are_taken_and_agree() {
        // sqrt on [1, 4]: alpha = 1/3, g ∈ [2/3, 3/4] (1/(4 alpha) = 3/4 exactly).
        let ap = sqrt_fast(1.0, 4.0, 2.0).expect("fast path");
        assert_eq!(ap, sqrt(1.0, 4.0));
        check(ap, 1.0 / 3.0, 17.0 / 24.0, 1.0 / 24.0);
        // sin on [1, 1.02]: concave, secant slope; Chebyshev delta = sin(m) h²/4 to
        // first order, which the Taylor form must meet within its acceptance margin.
        let (a, b) = (1.0, 1.02);
        let ap = trig_taylor(Trig::Sin, a, b, mid(a, b), 0.01).expect("taylor path");
        assert_eq!(ap, sin(a, b));
        let cheb = 0.25 * 1.01f64.sin() * 1e-4;
        assert!(
            ap.delta >= 0.99 * cheb && ap.delta <= 1.125 * cheb,
            "{ap:?}"
        );
        // Near an inflection the third-order form answers, as tight as the general
        // path's mean-value form (secant 1 - h^2/6; both give 2 h^3/6 here).
        let ap = trig_taylor(Trig::Sin, -0.01, 0.01, 0.0, 0.01).expect("taylor path");
        assert_eq!(ap, sin(-0.01, 0.01));
        assert!(ap.delta >= 3.3e-7 && ap.delta <= 3.34e-7, "{ap:?}");
        assert!(trig_taylor(Trig::Cos, 3.0, 3.02, 3.01, 0.01).is_some());
        // recip on [1, 2] (Chebyshev) and [1, 5] (min-range), as in the general path.
        assert_eq!(recip_fast(1.0, 2.0), Some(recip(1.0, 2.0)));
        let (z, d) = (0.5 * (1.5 + 2f64.sqrt()), 0.5 * (1.5 - 2f64.sqrt()));
        check(recip_fast(1.0, 2.0).unwrap(), -0.5, z, d);
        check(recip_fast(1.0, 5.0).unwrap(), -0.04, 0.72, 0.32);
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
    fn from_range_cases() {
        assert_eq!(
            Approx::from_range(1.0, 3.0),
            Approx {
                alpha: 0.0,
                zeta: 2.0,
                delta: 1.0
            }
        );
        assert_eq!(Approx::from_range(2.0, 2.0), zero_width(2.0));
        assert!(Approx::from_range(0.0, f64::INFINITY).is_entire());
        assert!(Approx::from_range(f64::NAN, 1.0).is_entire());
        // 0.1 + 0.2 style inexact midpoints: the half-widths are still covered.
        let ap = Approx::from_range(0.1, 0.7);
        assert!(ap.zeta - ap.delta <= 0.1 && ap.zeta + ap.delta >= 0.7);
    }

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
}
