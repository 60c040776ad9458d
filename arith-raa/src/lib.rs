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
//! accumulator (no `½ Σ xi yi` centre shift), see [`Raa`]'s `Mul`.
//!
//! Every operation bounds its own `f64` rounding errors and adds them to `acc` (see the
//! private `fp` module); non-affine operations use the shared [`arith_core::approx`]
//! approximations, except `*` and `sqr` which have closed forms.

#![forbid(unsafe_code)]

use arith_core::affine_round as fp;

use arith_core::approx::{self, Approx};
use arith_core::round::U;
use arith_core::{AffinePart, Arithmetic, Range, Real};
use core::ops::{Add, Div, Mul, Neg, Sub};
use fp::{add_dir_down, add_dir_up, k_lin, k_mul, mid_rad, up_abs, up_rel};

mod pack;
pub use pack::{Raa1x4, Raa3x4, RaaX4};

/// A reduced affine form (AF1) with `N` input symbols:
/// `x0 + Σ xs[i] ε_i + acc ε_{n+1}`, `acc >= 0` (`acc = +inf` for the unbounded form).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Raa<const N: usize> {
    x0: f64,
    xs: [f64; N],
    acc: f64,
}

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

impl<const N: usize> Raa<N> {
    /// The form `x0 + Σ xs[i] ε_i + acc ε_{n+1}`. `None` when `acc` is negative or NaN.
    pub fn new(x0: f64, xs: [f64; N], acc: f64) -> Option<Self> {
        if acc >= 0.0 {
            Some(Raa { x0, xs, acc })
        } else {
            None
        }
    }

    /// The whole real line.
    pub const UNBOUNDED: Self = Raa {
        x0: 0.0,
        xs: [0.0; N],
        acc: f64::INFINITY,
    };

    /// Centre `x0`.
    pub fn centre(&self) -> f64 {
        self.x0
    }
    /// Coefficients of the input symbols.
    pub fn coeffs(&self) -> &[f64; N] {
        &self.xs
    }
    /// Coefficient `acc` of the accumulating symbol.
    pub fn acc(&self) -> f64 {
        self.acc
    }

    /// The unary affine operation (Section 3.3, made sound as in the crate docs) with the shared approximation `a`:
    /// `alpha*x + zeta`, `acc = delta + |alpha| acc_x + rounding errors`.
    #[inline]
    fn apply(&self, a: Approx) -> Self {
        if a.is_entire() {
            return Self::UNBOUNDED;
        }
        if a.alpha == 0.0 {
            // The constant `zeta ± delta`, exact: nothing to round (so `sqrt` of a range
            // below 0 is exactly `[0, 0]`, as the `Range` contract says).
            return Raa {
                x0: a.zeta,
                xs: [0.0; N],
                acc: a.delta,
            };
        }
        let ax0 = a.alpha * self.x0;
        let x0 = ax0 + a.zeta;
        // |values| whose rounding errors we must cover.
        let mut r = ax0.abs() + x0.abs();
        let mut xs = [0.0; N];
        for (z, c) in xs.iter_mut().zip(&self.xs) {
            *z = a.alpha * c;
            r += z.abs();
        }
        let s = a.delta + a.alpha.abs() * self.acc + U * r;
        Raa {
            x0,
            xs,
            acc: up_abs(s, k_lin(N)),
        }
    }

    /// A non-affine function through its shared approximation on the current range.
    /// `unbounded` is the answer when the range itself is unbounded.
    #[inline]
    fn unary(&self, f: fn(f64, f64) -> Approx, unbounded: Self) -> Self {
        // The approximation's domain only has to enclose the values: the cheap bounds
        // (an ulp of slack) do, at a fraction of the directed ones' cost.
        let (lo, hi) = fp::bounds_fast(self.x0, &self.xs, self.acc);
        if !(lo.is_finite() && hi.is_finite()) {
            return unbounded;
        }
        self.apply(f(lo, hi))
    }
}

impl<const N: usize> Add for Raa<N> {
    type Output = Self;
    #[inline]
    fn add(self, y: Self) -> Self {
        let x0 = self.x0 + y.x0;
        let mut s = self.acc + y.acc + U * x0.abs();
        let mut xs = [0.0; N];
        for ((z, a), b) in xs.iter_mut().zip(&self.xs).zip(&y.xs) {
            *z = a + b;
            s += U * z.abs();
        }
        Raa {
            x0,
            xs,
            acc: up_rel(s, N + 3),
        }
    }
}

impl<const N: usize> Sub for Raa<N> {
    type Output = Self;
    /// The accumulators add: the two accumulated errors are independent.
    #[inline]
    fn sub(self, y: Self) -> Self {
        let x0 = self.x0 - y.x0;
        let mut s = self.acc + y.acc + U * x0.abs();
        let mut xs = [0.0; N];
        for ((z, a), b) in xs.iter_mut().zip(&self.xs).zip(&y.xs) {
            *z = a - b;
            s += U * z.abs();
        }
        Raa {
            x0,
            xs,
            acc: up_rel(s, N + 3),
        }
    }
}

impl<const N: usize> Neg for Raa<N> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        let mut xs = self.xs;
        for c in &mut xs {
            *c = -*c;
        }
        Raa {
            x0: -self.x0,
            xs,
            acc: self.acc,
        }
    }
}

impl<const N: usize> Add<f64> for Raa<N> {
    type Output = Self;
    #[inline]
    fn add(self, c: f64) -> Self {
        let x0 = self.x0 + c;
        Raa {
            x0,
            xs: self.xs,
            acc: up_rel(self.acc + U * x0.abs(), 2),
        }
    }
}

impl<const N: usize> Sub<f64> for Raa<N> {
    type Output = Self;
    #[inline]
    fn sub(self, c: f64) -> Self {
        let x0 = self.x0 - c;
        Raa {
            x0,
            xs: self.xs,
            acc: up_rel(self.acc + U * x0.abs(), 2),
        }
    }
}

impl<const N: usize> Mul<f64> for Raa<N> {
    type Output = Self;
    #[inline]
    fn mul(self, c: f64) -> Self {
        let x0 = self.x0 * c;
        let mut r = x0.abs();
        let mut xs = [0.0; N];
        for (z, a) in xs.iter_mut().zip(&self.xs) {
            *z = a * c;
            r += z.abs();
        }
        let s = c.abs() * self.acc + U * r;
        Raa {
            x0,
            xs,
            acc: up_abs(s, k_lin(N)),
        }
    }
}

impl<const N: usize> Div<f64> for Raa<N> {
    type Output = Self;
    #[inline]
    fn div(self, c: f64) -> Self {
        if c == 0.0 {
            return Self::UNBOUNDED;
        }
        let x0 = self.x0 / c;
        let mut r = x0.abs();
        let mut xs = [0.0; N];
        for (z, a) in xs.iter_mut().zip(&self.xs) {
            *z = a / c;
            r += z.abs();
        }
        let s = self.acc / c.abs() + U * r;
        Raa {
            x0,
            xs,
            acc: up_abs(s, k_lin(N)),
        }
    }
}

impl<const N: usize> Mul for Raa<N> {
    type Output = Self;
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
    fn mul(self, y: Self) -> Self {
        let x = self;
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
        let main = x.x0.abs() * y.acc + y.x0.abs() * x.acc + (u + x.acc) * (v + y.acc);
        Raa {
            x0,
            xs,
            acc: up_abs(main + U * r, k_mul(N)),
        }
    }
}

impl<const N: usize> Div for Raa<N> {
    type Output = Self;
    /// `x * recip(y)`.
    #[inline]
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, y: Self) -> Self {
        self * y.recip()
    }
}

arith_core::impl_f64_lhs_ops!(<const N: usize> Raa<N>);

impl<const N: usize> Real for Raa<N> {
    fn constant(c: f64) -> Self {
        Raa {
            x0: c,
            xs: [0.0; N],
            acc: 0.0,
        }
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
    fn sqr(&self) -> Self {
        let x0 = self.x0;
        // W: an upper bound of u + acc (exact sums stay exact).
        let w = fp::rad_dir(&self.xs, self.acc);
        // The gain over x * x in width is W². Where it is below what the rounding
        // bookkeeping can blur (a few hundred ulps of (|x0| + W)², see
        // `fp::sqr_margin`), x * x itself is the answer: then sqr is never wider than
        // x * x after rounding either, not only in exact arithmetic. Both are sound.
        let m = x0.abs() + w;
        let gain_survives = w * w > fp::sqr_margin(N) * (m * m) + fp::TINY;
        if !gain_survives {
            return *self * *self;
        }
        let (c0, xs, acc) = fp::cheb_sqr(x0, &self.xs, self.acc, w);
        if !acc.is_finite() {
            // Near the overflow threshold the rounding bookkeeping of the longer
            // formula can overflow first; x * x is the sound, never-wider answer.
            return *self * *self;
        }
        Raa { x0: c0, xs, acc }
    }

    fn powi(&self, n: i32) -> Self {
        match n {
            0 => Self::constant(1.0),
            1 => *self,
            2 => self.sqr(),
            n if n > 2 => {
                let (lo, hi) = self.bounds();
                if !(lo.is_finite() && hi.is_finite()) {
                    return Self::UNBOUNDED;
                }
                self.apply(approx::powi(lo, hi, n))
            }
            n => match n.checked_neg() {
                Some(m) => self.powi(m).recip(),
                None => Self::UNBOUNDED,
            },
        }
    }

    fn sqrt(&self) -> Self {
        self.unary(approx::sqrt, Self::UNBOUNDED)
    }

    /// See [`arith_core::affine_hypot`].
    fn hypot(&self, other: &Self) -> Self {
        arith_core::affine_hypot!(self, other, acc, Raa)
    }

    fn recip(&self) -> Self {
        self.unary(approx::recip, Self::UNBOUNDED)
    }

    fn exp(&self) -> Self {
        self.unary(approx::exp, Self::UNBOUNDED)
    }

    fn ln(&self) -> Self {
        self.unary(approx::ln, Self::UNBOUNDED)
    }

    fn sin(&self) -> Self {
        self.unary(approx::sin, Self::from_interval(-1.0, 1.0))
    }

    fn cos(&self) -> Self {
        self.unary(approx::cos, Self::from_interval(-1.0, 1.0))
    }

    /// Exact (`x` or `-x`) away from 0; the shared approximation across 0.
    fn abs(&self) -> Self {
        let (lo, hi) = self.bounds();
        if lo >= 0.0 {
            *self
        } else if hi <= 0.0 {
            -*self
        } else {
            self.unary(approx::abs, Self::UNBOUNDED)
        }
    }

    /// The lower operand when the ranges do not overlap, else `(x+y)/2 - |x-y|/2`.
    fn min(&self, other: &Self) -> Self {
        let (xl, xh) = self.bounds();
        let (yl, yh) = other.bounds();
        if xh <= yl {
            *self
        } else if yh <= xl {
            *other
        } else {
            ((*self + *other) - (*self - *other).abs()) * 0.5
        }
    }

    /// The higher operand when the ranges do not overlap, else `(x+y)/2 + |x-y|/2`.
    fn max(&self, other: &Self) -> Self {
        let (xl, xh) = self.bounds();
        let (yl, yh) = other.bounds();
        if xh <= yl {
            *other
        } else if yh <= xl {
            *self
        } else {
            ((*self + *other) + (*self - *other).abs()) * 0.5
        }
    }
}

impl<const N: usize> Range for Raa<N> {
    const NAME: &'static str = "raa";
    const INPUTS: usize = N;

    /// `x0 = (lo+hi)/2`, `xs[i] = (hi-lo)/2`, so `ε_i = -1 ↦ lo`, `+1 ↦ hi`; any rounding
    /// of the midpoint or radius goes into `acc`. An index `i >= N` gets no symbol: the
    /// whole radius goes into `acc` (sound, uncorrelated). Reversed bounds are swapped;
    /// NaN gives the whole line.
    fn input(i: usize, lo: f64, hi: f64) -> Self {
        if lo.is_nan() || hi.is_nan() {
            return Self::UNBOUNDED;
        }
        let (lo, hi) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        let (m, r, err) = mid_rad(lo, hi);
        if i < N {
            // Built lane by lane: a store at index `i` read back as a vector stalls.
            let xs = core::array::from_fn(|k| if k == i { r } else { 0.0 });
            Raa {
                x0: m,
                xs,
                acc: err,
            }
        } else {
            Raa {
                x0: m,
                xs: [0.0; N],
                acc: add_dir_up(r, err),
            }
        }
    }

    fn from_interval(lo: f64, hi: f64) -> Self {
        Self::input(usize::MAX, lo, hi)
    }

    /// The coefficients as they are; those past `N` symbols join the error term.
    fn from_affine(c0: f64, cs: &[f64], err: f64) -> Self {
        match fp::form_of(c0, cs, err) {
            Some((x0, xs, acc)) => Raa { x0, xs, acc },
            None => Self::UNBOUNDED,
        }
    }

    /// `x0 ∓ (Σ|xi| + acc)`, outward rounded (exact results stay exact).
    fn bounds(&self) -> (f64, f64) {
        fp::bounds_dir(self.x0, fp::rad_dir(&self.xs, self.acc))
    }

    /// `0 ∈ bounds()` without the bounds ([`fp::holds_zero`]).
    #[inline(always)]
    fn contains_zero(&self) -> bool {
        fp::holds_zero(self.x0, fp::rad_dir(&self.xs, self.acc))
    }

    fn affine_part<const K: usize>(&self) -> Option<AffinePart<K>> {
        fp::affine_at(self.x0, &self.xs, self.acc)
    }

    /// `x0 + Σ xs[i] eps[i] ± acc`, outward rounded; symbols without an `eps` stay free.
    fn bounds_at_inputs(&self, eps: &[f64]) -> (f64, f64) {
        let mut v = self.x0;
        let mut r = 0.0; // Σ |computed values| whose rounding errors we cover
        let mut free = self.acc;
        for (i, c) in self.xs.iter().enumerate() {
            match eps.get(i) {
                Some(&t) => {
                    let p = c * t;
                    v += p;
                    r += p.abs() + v.abs();
                }
                None => free += c.abs(),
            }
        }
        let rad = up_abs(free + U * r, k_lin(N));
        let lo = add_dir_down(v, -rad);
        let hi = add_dir_up(v, rad);
        if lo.is_finite() && hi.is_finite() {
            (lo, hi)
        } else {
            (f64::NEG_INFINITY, f64::INFINITY)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn input_is_exact_and_correlated() {
        let x = Raa::<1>::input(0, 1.0, 3.0);
        assert_eq!((x.centre(), x.coeffs()[0], x.acc()), (2.0, 1.0, 0.0));
        assert_eq!(x.bounds(), (1.0, 3.0));
        assert_eq!((x - x).bounds(), (0.0, 0.0));
    }
}
