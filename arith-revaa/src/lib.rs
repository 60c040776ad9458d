//! # arith-revaa: Revised Affine Arithmetic
//!
//! The revised affine form of Vu, Sam-Haroud and Faltings, as used for ray tracing by
//! Fryazinov, Pasko and Comninos (2009, Section 3.4):
//!
//! ```text
//! x = x0 + Σ xs[i] ε_i + [-e, e],   ε_i ∈ [-1, 1] the input symbols,  e >= 0.
//! ```
//!
//! Only the input symbols are kept (`N` of them: `N = 1` for a ray, `N = 3` for a cell);
//! every approximation error goes into the symmetric radius `e`. The form is `Copy`, of
//! fixed size and allocation-free, so the hot path of a ray (`RevAa<1>`, three `f64`s)
//! stays in registers. [`RevAa1x4`] holds four ray forms in SIMD registers (and
//! [`RevAa3x4`] four cell forms), each lane computed exactly as the scalar form (the
//! tracer searches four rays, or narrows four cells, at once with them).
//!
//! The form is [`arith_core::reduced::Reduced`], shared with RAA*. Soundness: every
//! operation bounds its own `f64` rounding errors and adds them to `e`; non-affine
//! operations use the shared [`arith_core::approx`] approximations. This crate gives only
//! RevAA's own `*` and `sqr`, which have closed forms.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

use arith_core::affine_round::{self as fp, k_mul, up_abs};
use arith_core::reduced::{Reduced, ReducedKind};
use arith_core::round::U;
use arith_core::Arithmetic;

mod pack;
pub use pack::{RevAa1x4, RevAa3x4, RevAaX4};

/// A revised affine form with `N` input symbols:
/// `x0 + Σ xs[i] ε_i + [-e, e]`, `e >= 0` (`e = +inf` for the unbounded form).
pub type RevAa<const N: usize> = Reduced<N, RevAaArith>;

/// The revised affine arithmetic as a family: one symbol on a ray, three in a cell.
#[derive(Clone, Copy, Debug, Default)]
pub struct RevAaArith;

impl Arithmetic for RevAaArith {
    const NAME: &'static str = "revaa";
    const LABEL: &'static str = "RevAA";
    type Ray = RevAa<1>;
    type Cell = RevAa<3>;
    type RayPack = RevAa1x4;
    type CellPack = RevAa3x4;
}

impl ReducedKind for RevAaArith {
    const FORM: &'static str = "RevAa";
    const ERR: &'static str = "e";

    /// The tight product of Section 3.4, sound for every `N`.
    ///
    /// With `x = x0 + Lx + tx`, `Lx = Σ xi εi`, `|tx| <= ex` (and alike for `y`):
    ///
    /// ```text
    /// x y = x0 y0 + Σ (x0 yi + xi y0) εi            (affine part, kept)
    ///     + Σ_i xi yi εi²                              (diagonal)
    ///     + Σ_{i<j} (xi yj + xj yi) εi εj              (off-diagonal)
    ///     + x0 ty + y0 tx + Lx ty + Ly tx + tx ty       (error terms)
    /// ```
    ///
    /// - Diagonal: `εi² ∈ [0, 1]`, so `xi yi εi² ∈ ½ xi yi ± ½|xi yi|`: the paper's
    ///   centre shift `½ Σ xi yi` and radius `½ Σ |xi yi|`.
    /// - Off-diagonal: `|εi εj| <= 1`, bounded by `Σ_{i<j} |xi yj + xj yi|`, which is
    ///   `<= Σ_{i≠j} |xi||yj| = u v - Σ |xi yi|` (`u = Σ|xi|`, `v = Σ|yi|`).
    /// - Error terms: `<= ex ey + ey (|x0| + u) + ex (|y0| + v)`.
    ///
    /// Summing gives the paper's `e_xy = ex ey + ey(|x0|+u) + ex(|y0|+v) + uv - ½Σ|xi yi|`
    /// with the off-diagonal part tightened by pairing `(i, j)` with `(j, i)`. So the
    /// paper's formula is sound for `N > 1` as well (the `½` reduction only touches the
    /// diagonal terms, where `εi² >= 0` justifies it); for `N = 1` both coincide.
    /// Written with nonnegative sums only, so rounding is bounded without cancellation.
    #[inline(always)]
    fn mul<const N: usize>(x: RevAa<N>, y: RevAa<N>) -> RevAa<N> {
        mul_forms(x, y, true)
    }

    /// The Chebyshev square in closed form. With `x = x0 + w`, `w = Lx + tx`,
    /// `|w| <= W` for any `W >= u + ex`: `x² = x0² + 2 x0 Lx + 2 x0 tx + w²` and
    /// `w² ∈ [0, W²] = ½W² ± ½W²`. So centre `x0² + ½W²`, coefficients `2 x0 xi`,
    /// radius `2|x0| ex + ½W²`. (This is exactly what the Chebyshev approximation of
    /// `x²` on `[x0 - W, x0 + W]` gives.) Compared with `x * x`, whose quadratic part
    /// is `[S - W², W²]` (`S = Σ xi²`), the upper end is the same and the lower end is
    /// higher by `W² - S >= 0`, so it is never wider in exact arithmetic.
    #[inline(always)]
    fn sqr<const N: usize>(x: &RevAa<N>) -> RevAa<N> {
        let x0 = x.x0;
        // W: an upper bound of u + ex (exact sums stay exact, so N = 1, ex = 0 gives |x1|).
        let w = x.rad_dir();
        // Σ xi²: x * x's quadratic part is [S - W², W²].
        let s2 = x.xs.iter().fold(0.0, |s, c| s + c * c);
        // The gain over x * x in width is G = W² - S. Where it is below what the
        // rounding bookkeeping can blur (a few hundred ulps of (|x0| + W)², see
        // `fp::sqr_margin`), x * x itself is the answer: then sqr is never wider than
        // x * x after rounding either, not only in exact arithmetic. Both are sound.
        let m = x0.abs() + w;
        let gain_survives = w * w - s2 > fp::sqr_margin(N) * (m * m) + fp::TINY;
        if N == 1 {
            // Both, then a select: whether the gain survives follows the model's
            // operations (the first squares of a ray's coordinates never gain), and a
            // mispredicted branch costs more than the short product.
            let prod = mul_forms(*x, *x, true);
            let cheb = x.cheb_sqr(w);
            let ok = gain_survives && cheb.e.is_finite();
            let pick = |a: f64, b: f64| if ok { a } else { b };
            return RevAa::from_parts(
                pick(cheb.x0, prod.x0),
                core::array::from_fn(|k| pick(cheb.xs[k], prod.xs[k])),
                pick(cheb.e, prod.e),
            );
        }
        if !gain_survives {
            // A form of one symbol (a cell's input) has no cross terms.
            let single = x.xs.iter().all(|c| c.is_finite())
                && x.xs.iter().filter(|c| **c != 0.0).count() <= 1;
            return mul_forms(*x, *x, !single);
        }
        let cheb = x.cheb_sqr(w);
        if !cheb.e.is_finite() {
            // Near the overflow threshold the rounding bookkeeping of the longer
            // formula can overflow first; x * x is the sound, never-wider answer.
            return *x * *x;
        }
        cheb
    }
}

/// RevAA's product (`mul` of [`RevAaArith`]'s [`ReducedKind`] impl): inlined into `sqr`
/// as well, whose fallback `x * x` then shares the square's loads and products (the same
/// operations, so the same result).
///
/// `cross == false` skips the off-diagonal terms; only for operands where each of them
/// is exactly zero (finite coefficients, at most one index non-zero in both), where the
/// result is then the same bit for bit.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // several arrays indexed together
fn mul_forms<const N: usize>(x: RevAa<N>, y: RevAa<N>, cross: bool) -> RevAa<N> {
    let p0 = x.x0 * y.x0;
    let mut d = 0.0; // Σ xi yi
    let mut diag = 0.0; // Σ |xi yi|
    let mut u = 0.0;
    let mut v = 0.0;
    let mut r = p0.abs(); // Σ |computed values| whose rounding errors we cover
    let mut xs = [0.0; N];
    for i in 0..N {
        let q = x.xs[i] * y.xs[i];
        d += q;
        diag += q.abs();
        let a = x.x0 * y.xs[i];
        let b = x.xs[i] * y.x0;
        xs[i] = a + b;
        r += q.abs() + d.abs() + a.abs() + b.abs() + xs[i].abs();
        u += x.xs[i].abs();
        v += y.xs[i].abs();
    }
    let mut off = 0.0;
    for i in 0..N * usize::from(cross) {
        for j in i + 1..N {
            let a = x.xs[i] * y.xs[j];
            let b = x.xs[j] * y.xs[i];
            let s = a + b;
            off += s.abs();
            r += a.abs() + b.abs() + s.abs();
        }
    }
    let hd = 0.5 * d;
    let x0 = p0 + hd;
    r += hd.abs() + x0.abs();
    let main = x.e * y.e + y.e * (x.x0.abs() + u) + x.e * (y.x0.abs() + v) + 0.5 * diag + off;
    RevAa::from_parts(x0, xs, up_abs(main + U * r, k_mul(N)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::{Range, Real};

    /// The R-functions' root uses that `x^2 + y^2 >= mig(x)^2 + mig(y)^2`: for
    /// `x ∈ [1, 3]`, `y ∈ [-3, -1]` held only in the error term, the affine range of
    /// `x^2 + y^2` is `[0, 18]`; `hypot` approximates `sqrt` on `[2, 18]` instead (its
    /// result still spans the form's whole range, but far less of it below `sqrt(2)`).
    #[test]
    fn hypot_uses_the_mignitude_floor() {
        let x = RevAa::<1>::from_interval(1.0, 3.0);
        let y = RevAa::<1>::from_interval(-3.0, -1.0);
        let plain = (x.sqr() + y.sqr()).sqrt().bounds();
        let h = x.hypot(&y).bounds();
        assert!(
            h.0 > plain.0 + 0.5 && h.1 - h.0 < plain.1 - plain.0,
            "{h:?} vs {plain:?}"
        );
        // Still an enclosure of the true range [sqrt(2), sqrt(18)].
        assert!(h.0 <= 2f64.sqrt() && 18f64.sqrt() <= h.1, "{h:?}");
    }

    #[test]
    fn input_is_exact_and_correlated() {
        let x = RevAa::<1>::input(0, 1.0, 3.0);
        assert_eq!((x.centre(), x.coeffs()[0], x.err()), (2.0, 1.0, 0.0));
        assert_eq!(x.bounds(), (1.0, 3.0));
        assert_eq!((x - x).bounds(), (0.0, 0.0));
    }
}
