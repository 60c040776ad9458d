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
//!
//! Layout: this file holds [`Approx`] and the steps every construction shares (flushing
//! a subnormal slope, turning a bounded `g` into `zeta ± delta`, the range fallback);
//! `chebyshev` the approximations of the convex and concave functions, `trig` those of
//! `sin` and `cos` with their argument tests, `interval` the `range_*` enclosures and
//! `bounds` the rigorous bounds of `g` over an interval they are all built from.

mod bounds;
mod chebyshev;
mod interval;
mod periodic;
mod trig;

pub use bounds::sum_sq_floor;
pub use chebyshev::{abs, exp, ln, powi, recip, sqr, sqrt, sqrt_at_least};
pub use interval::{range_cos, range_exp, range_ln, range_powi, range_sin, range_sqrt};
pub use trig::{cos, sin};

use crate::round::{self, sub_hi};

/// `f(x) ∈ alpha*x + zeta ± delta` on the interval it was built for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Approx {
    /// Slope of the linear part.
    pub alpha: f64,
    /// Offset of the linear part.
    pub zeta: f64,
    /// Maximum error of `alpha*x + zeta` against `f` on the interval, rounded up.
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

/// A slope too small to matter (subnormal) is replaced by 0: a subnormal `alpha` carries
/// few significant bits, so `alpha*x` would only add rounding noise.
fn flush(alpha: f64) -> f64 {
    if alpha.abs() < f64::MIN_POSITIVE {
        0.0
    } else {
        alpha
    }
}

/// Whether `[a, b]` is empty or malformed (NaN bounds, `a > b`).
fn bad(a: f64, b: f64) -> bool {
    a.is_nan() || b.is_nan() || a > b
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

#[cfg(test)]
mod tests {
    use super::*;

    pub(super) fn check(ap: Approx, alpha: f64, zeta: f64, delta: f64) {
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

    pub(super) fn zero_width(v: f64) -> Approx {
        Approx {
            alpha: 0.0,
            zeta: v,
            delta: 0.0,
        }
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
}
