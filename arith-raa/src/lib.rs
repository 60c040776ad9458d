//! # arith-raa: Reduced Affine Arithmetic (Messine's affine form AF1)
//!
//! The reduced affine form used as "RAA*" by Fryazinov, Pasko and Comninos (2009,
//! Section 3.3):
//!
//! ```text
//! x = x0 + Σ xs[i] ε_i + acc ε_{n+1},   ε ∈ [-1, 1],  acc >= 0,
//! ```
//!
//! with `N` input symbols (`N = 1` for a ray, `N = 3` for a cell) and one accumulating
//! symbol that collects every approximation error. The form is `Copy`, of fixed size and
//! allocation-free. [`Raa1x4`] and [`Raa3x4`] hold four ray or cell forms in SIMD
//! registers, each lane computed exactly as the scalar form.
//!
//! **Soundness note.** The paper's general operation (Section 3.3) sets the new
//! accumulator to `|δ + α x_{n+1} + β y_{n+1}|`, i.e. it treats the accumulated errors of
//! two *different* values as one correlated symbol. That is unsound: `x - y` with equal
//! accumulators would cancel them although the two errors are unrelated. We do the
//! sound thing, `acc = |α| acc_x + |β| acc_y + δ` (the accumulating symbol is fresh
//! after each operation), which makes the affine operations coincide with RevAA's.
//! What distinguishes AF1 is its multiplication: the whole quadratic term goes to the
//! accumulator (no `½ Σ xi yi` centre shift), see `mul` of [`RaaArith`]'s
//! [`ReducedKind`] impl.
//!
//! The form is [`arith_core::reduced::Reduced`], shared with RevAA: every operation
//! bounds its own `f64` rounding errors and adds them to `acc` (its error term `e`), and
//! non-affine operations use the shared [`arith_core::approx`] approximations. This
//! crate gives only AF1's own `*` and `sqr`, which have closed forms.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

use arith_core::affine_round::{self as fp, k_mul, up_abs};
use arith_core::reduced::{Reduced, ReducedKind};
use arith_core::round::U;
use arith_core::Arithmetic;

mod pack;
pub use pack::{Raa1x4, Raa3x4, RaaX4};

/// A reduced affine form (AF1) with `N` input symbols:
/// `x0 + Σ xs[i] ε_i + acc ε_{n+1}`, `acc >= 0` (`acc = +inf` for the unbounded form).
/// [`Reduced::acc`] reads `acc`, the form's error term `e`.
pub type Raa<const N: usize> = Reduced<N, RaaArith>;

/// The reduced affine arithmetic (AF1) as a family: one symbol on a ray, three in a cell.
#[derive(Clone, Copy, Debug, Default)]
pub struct RaaArith;

impl Arithmetic for RaaArith {
    const NAME: &'static str = "raa";
    const LABEL: &'static str = "RAA*";
    type Ray = Raa<1>;
    type Cell = Raa<3>;
    type RayPack = Raa1x4;
    type CellPack = Raa3x4;
}

impl ReducedKind for RaaArith {
    const FORM: &'static str = "Raa";
    const ERR: &'static str = "acc";

    /// AF1's standard product.
    ///
    /// With `x = x0 + Lx + ax ε'`, `Lx = Σ xi εi`, `|Lx| <= u = Σ|xi|` (alike for `y`):
    ///
    /// ```text
    /// x y = x0 y0 + Σ (x0 yi + xi y0) εi + x0 ay ε'' + y0 ax ε' + (Lx + ax ε')(Ly + ay ε'')
    /// ```
    ///
    /// and the last product lies in `± (u + ax)(v + ay)`. So centre `x0 y0`,
    /// coefficients `x0 yi + xi y0`, `acc = |x0| ay + |y0| ax + (u + ax)(v + ay)`: the
    /// whole quadratic term goes to the accumulator, with no centre shift (this is
    /// what RevAA's tighter product improves on).
    #[inline]
    #[allow(clippy::needless_range_loop)] // several arrays indexed together
    fn mul<const N: usize>(x: Raa<N>, y: Raa<N>) -> Raa<N> {
        let x0 = x.x0 * y.x0;
        let mut u = 0.0;
        let mut v = 0.0;
        let mut r = x0.abs(); // Σ |computed values| whose rounding errors we cover
        let mut xs = [0.0; N];
        for i in 0..N {
            let a = x.x0 * y.xs[i];
            let b = x.xs[i] * y.x0;
            xs[i] = a + b;
            r += a.abs() + b.abs() + xs[i].abs();
            u += x.xs[i].abs();
            v += y.xs[i].abs();
        }
        let main = x.x0.abs() * y.e + y.x0.abs() * x.e + (u + x.e) * (v + y.e);
        Raa::from_parts(x0, xs, up_abs(main + U * r, k_mul(N)))
    }

    /// The Chebyshev square in closed form (tighter than AF1's product of `x` with
    /// itself). With `x = x0 + w`, `w = Lx + acc ε'`, `|w| <= W` for any
    /// `W >= u + acc`: `x² = x0² + 2 x0 Lx + 2 x0 acc ε' + w²` and
    /// `w² ∈ [0, W²] = ½W² ± ½W²`. So centre `x0² + ½W²`, coefficients `2 x0 xi`,
    /// accumulator `2|x0| acc + ½W²`. (This is exactly what the Chebyshev approximation
    /// of `x²` on `[x0 - W, x0 + W]` gives.) Compared with `x * x`, whose quadratic part
    /// is `±W²`, the upper end is the same and the lower end is higher by `W²`, so it is
    /// never wider in exact arithmetic.
    #[inline]
    fn sqr<const N: usize>(x: &Raa<N>) -> Raa<N> {
        let x0 = x.x0;
        // W: an upper bound of u + acc (exact sums stay exact).
        let w = x.rad_dir();
        // The gain over x * x in width is W². Where it is below what the rounding
        // bookkeeping can blur (a few hundred ulps of (|x0| + W)², see
        // `fp::sqr_margin`), x * x itself is the answer: then sqr is never wider than
        // x * x after rounding either, not only in exact arithmetic. Both are sound.
        let m = x0.abs() + w;
        let gain_survives = w * w > fp::sqr_margin(N) * (m * m) + fp::TINY;
        if !gain_survives {
            return *x * *x;
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

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::Range;

    #[test]
    fn input_is_exact_and_correlated() {
        let x = Raa::<1>::input(0, 1.0, 3.0);
        assert_eq!((x.centre(), x.coeffs()[0], x.acc()), (2.0, 1.0, 0.0));
        assert_eq!(x.bounds(), (1.0, 3.0));
        assert_eq!((x - x).bounds(), (0.0, 0.0));
    }
}
