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

/// `f(x) ∈ alpha*x + zeta ± delta` on the interval it was built for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Approx {
    pub alpha: f64,
    pub zeta: f64,
    pub delta: f64,
}

impl Approx {
    /// No information: the whole line.
    pub const ENTIRE: Approx = Approx { alpha: 0.0, zeta: 0.0, delta: f64::INFINITY };

    /// Whether this approximation is unbounded (callers then produce an unbounded form).
    pub fn is_entire(&self) -> bool {
        !(self.delta.is_finite() && self.alpha.is_finite() && self.zeta.is_finite())
    }

    /// The constant approximation enclosing `[lo, hi]` (`alpha = 0`).
    pub fn from_range(lo: f64, hi: f64) -> Approx {
        todo!("approx::Approx::from_range")
    }
}

/// `x^2` on `[a, b]`.
pub fn sqr(a: f64, b: f64) -> Approx {
    todo!()
}
/// `x^n` on `[a, b]`, `n >= 2`.
pub fn powi(a: f64, b: f64, n: i32) -> Approx {
    todo!()
}
/// `sqrt(max(x, 0))` on `[a, b]` (clipped at 0; wholly negative gives exactly 0).
pub fn sqrt(a: f64, b: f64) -> Approx {
    todo!()
}
/// `1/x` on `[a, b]`; [`Approx::ENTIRE`] when `0 ∈ [a, b]`.
pub fn recip(a: f64, b: f64) -> Approx {
    todo!()
}
/// `e^x` on `[a, b]`.
pub fn exp(a: f64, b: f64) -> Approx {
    todo!()
}
/// `ln x` on `[a, b]`; [`Approx::ENTIRE`] when `a <= 0`.
pub fn ln(a: f64, b: f64) -> Approx {
    todo!()
}
/// `sin x` on `[a, b]`.
pub fn sin(a: f64, b: f64) -> Approx {
    todo!()
}
/// `cos x` on `[a, b]`.
pub fn cos(a: f64, b: f64) -> Approx {
    todo!()
}
/// `|x|` on `[a, b]`.
pub fn abs(a: f64, b: f64) -> Approx {
    todo!()
}

/// Rigorous enclosure of `{x^n : x ∈ [a, b]}` (any integer `n`; `x^0 = 1`).
pub fn range_powi(a: f64, b: f64, n: i32) -> (f64, f64) {
    todo!()
}
/// Rigorous enclosure of `{sqrt(max(x,0)) : x ∈ [a, b]}`.
pub fn range_sqrt(a: f64, b: f64) -> (f64, f64) {
    todo!()
}
/// Rigorous enclosure of `{e^x : x ∈ [a, b]}`.
pub fn range_exp(a: f64, b: f64) -> (f64, f64) {
    todo!()
}
/// Rigorous enclosure of `{ln x : x ∈ [a, b]}` (`-inf` lower bound when `a <= 0`).
pub fn range_ln(a: f64, b: f64) -> (f64, f64) {
    todo!()
}
/// Rigorous enclosure of `{sin x : x ∈ [a, b]}`.
pub fn range_sin(a: f64, b: f64) -> (f64, f64) {
    todo!()
}
/// Rigorous enclosure of `{cos x : x ∈ [a, b]}`.
pub fn range_cos(a: f64, b: f64) -> (f64, f64) {
    todo!()
}
