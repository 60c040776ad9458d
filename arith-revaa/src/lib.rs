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
//! Soundness: every operation bounds its own `f64` rounding errors and adds them to `e`
//! (see the private `fp` module); non-affine operations use the shared
//! [`arith_core::approx`] approximations, except `*` and `sqr` which have closed forms.

#![forbid(unsafe_code)]

use arith_core::affine_round as fp;

use arith_core::approx::{self, Approx};
use arith_core::round::U;
use arith_core::{AffinePart, Arithmetic, Range, Real};
use core::ops::{Add, Div, Mul, Neg, Sub};

mod pack;
use fp::{add_dir_down, add_dir_up, k_lin, k_mul, mid_rad, up_abs, up_rel};
pub use pack::{RevAa1x4, RevAa3x4, RevAaX4};

/// A revised affine form with `N` input symbols:
/// `x0 + Σ xs[i] ε_i + [-e, e]`, `e >= 0` (`e = +inf` for the unbounded form).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RevAa<const N: usize> {
    x0: f64,
    xs: [f64; N],
    e: f64,
}

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

impl<const N: usize> RevAa<N> {
    /// The form `x0 + Σ xs[i] ε_i + [-e, e]`. `None` when `e` is negative or NaN (that
    /// would not describe a set).
    pub fn new(x0: f64, xs: [f64; N], e: f64) -> Option<Self> {
        if e >= 0.0 {
            Some(RevAa { x0, xs, e })
        } else {
            None
        }
    }

    /// The whole real line.
    pub const UNBOUNDED: Self = RevAa {
        x0: 0.0,
        xs: [0.0; N],
        e: f64::INFINITY,
    };

    /// Centre `x0`.
    pub fn centre(&self) -> f64 {
        self.x0
    }
    /// Coefficients of the input symbols.
    pub fn coeffs(&self) -> &[f64; N] {
        &self.xs
    }
    /// Radius `e` of the accumulated error interval.
    pub fn err(&self) -> f64 {
        self.e
    }

    /// The Chebyshev square of [`Real::sqr`] for `w >= u + e` (its bound may overflow).
    #[inline(always)]
    fn cheb_sqr(&self, w: f64) -> Self {
        let (x0, xs, e) = fp::cheb_sqr(self.x0, &self.xs, self.e, w);
        RevAa { x0, xs, e }
    }

    /// The unary affine operation of Section 3.4 with the shared approximation `a`:
    /// `alpha*x + zeta`, `e = delta + |alpha| e_x + rounding errors`.
    #[inline(always)]
    fn apply(&self, a: Approx) -> Self {
        if a.is_entire() {
            return Self::UNBOUNDED;
        }
        if a.alpha == 0.0 {
            // The constant `zeta ± delta`, exact: nothing to round (so `sqrt` of a range
            // below 0 is exactly `[0, 0]`, as the `Range` contract says).
            return RevAa {
                x0: a.zeta,
                xs: [0.0; N],
                e: a.delta,
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
        let s = a.delta + a.alpha.abs() * self.e + U * r;
        RevAa {
            x0,
            xs,
            e: up_abs(s, k_lin(N)),
        }
    }

    /// A non-affine function through its shared approximation on the current range.
    /// `unbounded` is the answer when the range itself is unbounded.
    #[inline(always)]
    fn unary(&self, f: fn(f64, f64) -> Approx, unbounded: Self) -> Self {
        // The approximation's domain only has to enclose the values: the cheap bounds
        // (an ulp of slack) do, at a fraction of the directed ones' cost.
        let (lo, hi) = fp::bounds_fast(self.x0, &self.xs, self.e);
        if !(lo.is_finite() && hi.is_finite()) {
            return unbounded;
        }
        self.apply(f(lo, hi))
    }
}

impl<const N: usize> Add for RevAa<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, y: Self) -> Self {
        let x0 = self.x0 + y.x0;
        let mut s = self.e + y.e + U * x0.abs();
        let mut xs = [0.0; N];
        for ((z, a), b) in xs.iter_mut().zip(&self.xs).zip(&y.xs) {
            *z = a + b;
            s += U * z.abs();
        }
        RevAa {
            x0,
            xs,
            e: up_rel(s, N + 3),
        }
    }
}

impl<const N: usize> Sub for RevAa<N> {
    type Output = Self;
    /// The radii add: the two error intervals are independent.
    #[inline(always)]
    fn sub(self, y: Self) -> Self {
        let x0 = self.x0 - y.x0;
        let mut s = self.e + y.e + U * x0.abs();
        let mut xs = [0.0; N];
        for ((z, a), b) in xs.iter_mut().zip(&self.xs).zip(&y.xs) {
            *z = a - b;
            s += U * z.abs();
        }
        RevAa {
            x0,
            xs,
            e: up_rel(s, N + 3),
        }
    }
}

impl<const N: usize> Neg for RevAa<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        let mut xs = self.xs;
        for c in &mut xs {
            *c = -*c;
        }
        RevAa {
            x0: -self.x0,
            xs,
            e: self.e,
        }
    }
}

impl<const N: usize> Add<f64> for RevAa<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, c: f64) -> Self {
        let x0 = self.x0 + c;
        RevAa {
            x0,
            xs: self.xs,
            e: up_rel(self.e + U * x0.abs(), 2),
        }
    }
}

impl<const N: usize> Sub<f64> for RevAa<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, c: f64) -> Self {
        let x0 = self.x0 - c;
        RevAa {
            x0,
            xs: self.xs,
            e: up_rel(self.e + U * x0.abs(), 2),
        }
    }
}

impl<const N: usize> Mul<f64> for RevAa<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: f64) -> Self {
        let x0 = self.x0 * c;
        let mut r = x0.abs();
        let mut xs = [0.0; N];
        for (z, a) in xs.iter_mut().zip(&self.xs) {
            *z = a * c;
            r += z.abs();
        }
        let s = c.abs() * self.e + U * r;
        RevAa {
            x0,
            xs,
            e: up_abs(s, k_lin(N)),
        }
    }
}

impl<const N: usize> Div<f64> for RevAa<N> {
    type Output = Self;
    #[inline(always)]
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
        let s = self.e / c.abs() + U * r;
        RevAa {
            x0,
            xs,
            e: up_abs(s, k_lin(N)),
        }
    }
}

impl<const N: usize> Mul for RevAa<N> {
    type Output = Self;
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
    fn mul(self, y: Self) -> Self {
        mul_forms(self, y, true)
    }
}

/// [`Mul`] for [`RevAa`]: inlined into `sqr` as well, whose fallback `x * x` then shares
/// the square's loads and products (the same operations, so the same result).
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
    RevAa {
        x0,
        xs,
        e: up_abs(main + U * r, k_mul(N)),
    }
}

impl<const N: usize> Div for RevAa<N> {
    type Output = Self;
    /// `x * recip(y)`.
    #[inline(always)]
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, y: Self) -> Self {
        self * y.recip()
    }
}

arith_core::impl_f64_lhs_ops!(<const N: usize> RevAa<N>);

impl<const N: usize> Real for RevAa<N> {
    fn constant(c: f64) -> Self {
        RevAa {
            x0: c,
            xs: [0.0; N],
            e: 0.0,
        }
    }

    /// The Chebyshev square in closed form. With `x = x0 + w`, `w = Lx + tx`,
    /// `|w| <= W` for any `W >= u + ex`: `x² = x0² + 2 x0 Lx + 2 x0 tx + w²` and
    /// `w² ∈ [0, W²] = ½W² ± ½W²`. So centre `x0² + ½W²`, coefficients `2 x0 xi`,
    /// radius `2|x0| ex + ½W²`. (This is exactly what the Chebyshev approximation of
    /// `x²` on `[x0 - W, x0 + W]` gives.) Compared with `x * x`, whose quadratic part
    /// is `[S - W², W²]` (`S = Σ xi²`), the upper end is the same and the lower end is
    /// higher by `W² - S >= 0`, so it is never wider in exact arithmetic.
    #[inline(always)]
    fn sqr(&self) -> Self {
        let x0 = self.x0;
        // W: an upper bound of u + ex (exact sums stay exact, so N = 1, ex = 0 gives |x1|).
        let w = fp::rad_dir(&self.xs, self.e);
        // Σ xi²: x * x's quadratic part is [S - W², W²].
        let s2 = self.xs.iter().fold(0.0, |s, c| s + c * c);
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
            let prod = mul_forms(*self, *self, true);
            let cheb = self.cheb_sqr(w);
            let ok = gain_survives && cheb.e.is_finite();
            let pick = |a: f64, b: f64| if ok { a } else { b };
            return RevAa {
                x0: pick(cheb.x0, prod.x0),
                xs: core::array::from_fn(|k| pick(cheb.xs[k], prod.xs[k])),
                e: pick(cheb.e, prod.e),
            };
        }
        if !gain_survives {
            // A form of one symbol (a cell's input) has no cross terms.
            let single = self.xs.iter().all(|c| c.is_finite())
                && self.xs.iter().filter(|c| **c != 0.0).count() <= 1;
            return mul_forms(*self, *self, !single);
        }
        let cheb = self.cheb_sqr(w);
        if !cheb.e.is_finite() {
            // Near the overflow threshold the rounding bookkeeping of the longer
            // formula can overflow first; x * x is the sound, never-wider answer.
            return *self * *self;
        }
        cheb
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
        arith_core::affine_hypot!(self, other, e, RevAa)
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

impl<const N: usize> Range for RevAa<N> {
    const NAME: &'static str = "revaa";
    const INPUTS: usize = N;

    /// `x0 = (lo+hi)/2`, `xs[i] = (hi-lo)/2`, so `ε_i = -1 ↦ lo`, `+1 ↦ hi`; any rounding
    /// of the midpoint or radius goes into `e`. An index `i >= N` gets no symbol: the
    /// whole radius goes into `e` (sound, uncorrelated). Reversed bounds are swapped;
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
            RevAa { x0: m, xs, e: err }
        } else {
            RevAa {
                x0: m,
                xs: [0.0; N],
                e: add_dir_up(r, err),
            }
        }
    }

    fn from_interval(lo: f64, hi: f64) -> Self {
        Self::input(usize::MAX, lo, hi)
    }

    /// The coefficients as they are; those past `N` symbols join the error term.
    fn from_affine(c0: f64, cs: &[f64], err: f64) -> Self {
        match fp::form_of(c0, cs, err) {
            Some((x0, xs, e)) => RevAa { x0, xs, e },
            None => Self::UNBOUNDED,
        }
    }

    /// `x0 ∓ (Σ|xi| + e)`, outward rounded (exact results stay exact).
    fn bounds(&self) -> (f64, f64) {
        fp::bounds_dir(self.x0, fp::rad_dir(&self.xs, self.e))
    }

    /// `0 ∈ bounds()` without the bounds ([`fp::holds_zero`]).
    #[inline(always)]
    fn contains_zero(&self) -> bool {
        fp::holds_zero(self.x0, fp::rad_dir(&self.xs, self.e))
    }

    fn affine_part<const K: usize>(&self) -> Option<AffinePart<K>> {
        fp::affine_at(self.x0, &self.xs, self.e)
    }

    /// `x0 + Σ xs[i] eps[i] ± e`, outward rounded; symbols without an `eps` stay free.
    fn bounds_at_inputs(&self, eps: &[f64]) -> (f64, f64) {
        let mut v = self.x0;
        let mut r = 0.0; // Σ |computed values| whose rounding errors we cover
        let mut free = self.e;
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
