//! `sin` and `cos`: their affine approximations (the argument tests they share with
//! the interval ranges are in [`super::periodic`]).
//!
//! No argument is reduced exactly. For `|x| <= 1e7` the float quotient
//! `(x - offset)/period` is within `1e-9` of the exact one, so [`may_contain`] decides
//! with a `1e-6` period margin whether `[a, b]` may hold an extremum or an inflection
//! `offset + k*period`; beyond `1e7` only `[-1, 1]` is claimed. Narrow ranges take a
//! Taylor form with one libm call ([`trig_taylor`]); the general path uses the secant
//! slope where `f` is convex or concave, else a mean-value form or the range.

use super::bounds::{bound_piece, g_enc, mid, slope_times_offset};
use super::interval::{range_cos, range_sin};
use super::periodic::{may_contain, Trig, TRIG_MAX_ARG};
use super::{bad, finish, flush, or_range, Approx};
use crate::affine_round;
use crate::round::{self, add_hi, add_lo, sub_hi, sub_lo};

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

impl Trig {
    pub(super) fn range(self, a: f64, b: f64) -> (f64, f64) {
        match self {
            Trig::Sin => range_sin(a, b),
            Trig::Cos => range_cos(a, b),
        }
    }
    /// Derivative range over `[a, b]` (`cos` for sin, `-sin` for cos).
    pub(super) fn drange(self, a: f64, b: f64) -> (f64, f64) {
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
    use super::super::tests::check;
    use super::*;

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
    fn taylor_fast_path_is_taken_and_agrees() {
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
    }
}
