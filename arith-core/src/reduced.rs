//! [`Reduced`]: the scalar reduced affine form `x0 + Σ xs[i] εi ± e` of RAA* and RevAA.
//!
//! Both arithmetics keep `N` input symbols and one nonnegative error term, and all their
//! operations but two are the same `f64` operations: the affine ones, the unary
//! approximations (`delta` and the rounding errors go into `e`), `hypot`, the bounds and
//! the inputs. So the form is written once here, generic over a [`ReducedKind`] that
//! supplies what differs, its product and its square (as `simd::ReducedX4` does for four
//! forms in lanes). Every operation bounds its own `f64` rounding errors with
//! [`crate::affine_round`] and adds them to `e`; non-affine operations use the shared
//! [`crate::approx`] approximations.

use crate::affine_round::{self as fp, add_dir_down, add_dir_up, k_lin, mid_rad, up_abs, up_rel};
use crate::approx::{self, Approx};
use crate::round::U;
use crate::{AffinePart, Arithmetic, Range, Real};
use core::marker::PhantomData;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// A reduced arithmetic (a family of [`Reduced`] forms): its product and square, and the
/// names its forms print with.
pub trait ReducedKind: Arithmetic + Sized {
    /// The type name `Debug` writes (`Raa`, `RevAa`).
    const FORM: &'static str;
    /// The name `Debug` writes for the error term `e` (`acc`, `e`).
    const ERR: &'static str;
    /// `x * y`, a sound enclosure of the product with its rounding errors in `e`.
    fn mul<const N: usize>(x: Reduced<N, Self>, y: Reduced<N, Self>) -> Reduced<N, Self>;
    /// `x²`, a sound enclosure never wider than `x * x`.
    fn sqr<const N: usize>(x: &Reduced<N, Self>) -> Reduced<N, Self>;
}

/// A reduced affine form with `N` input symbols, `x0 + Σ xs[i] εi ± e`, `e >= 0`
/// (`e = +inf` for the unbounded form), whose product and square are `K`'s.
///
/// The fields are the raw representation, for the kinds' products and the lane packs:
/// unlike [`Reduced::new`] they do not refuse a negative `e` (which would describe no
/// value). Build forms with `new` or the [`Range`] constructors.
pub struct Reduced<const N: usize, K> {
    /// Centre.
    pub x0: f64,
    /// Coefficients of the `N` input symbols.
    pub xs: [f64; N],
    /// Radius of the error term (non-affine operations and rounding), `>= 0`.
    pub e: f64,
    kind: PhantomData<fn() -> K>,
}

// By hand: derives would ask `K` for the same traits although only a `PhantomData` is
// stored.
impl<const N: usize, K> Clone for Reduced<N, K> {
    #[inline(always)]
    fn clone(&self) -> Self {
        *self
    }
}
impl<const N: usize, K> Copy for Reduced<N, K> {}
impl<const N: usize, K> PartialEq for Reduced<N, K> {
    fn eq(&self, o: &Self) -> bool {
        self.x0 == o.x0 && self.xs == o.xs && self.e == o.e
    }
}
impl<const N: usize, K: ReducedKind> core::fmt::Debug for Reduced<N, K> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct(K::FORM)
            .field("x0", &self.x0)
            .field("xs", &self.xs)
            .field(K::ERR, &self.e)
            .finish()
    }
}

impl<const N: usize, K: ReducedKind> Reduced<N, K> {
    /// The form `x0 + Σ xs[i] εi ± e`. `None` when `e` is negative or NaN (that would
    /// not describe a set).
    pub fn new(x0: f64, xs: [f64; N], e: f64) -> Option<Self> {
        if e >= 0.0 {
            Some(Self::from_parts(x0, xs, e))
        } else {
            None
        }
    }

    /// The form of these parts, as they are (raw: `e` must not be negative).
    #[inline(always)]
    pub const fn from_parts(x0: f64, xs: [f64; N], e: f64) -> Self {
        Reduced {
            x0,
            xs,
            e,
            kind: PhantomData,
        }
    }

    /// The whole real line.
    pub const UNBOUNDED: Self = Self::from_parts(0.0, [0.0; N], f64::INFINITY);

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
    /// [`Reduced::err`] under AF1's name: the coefficient of the accumulating symbol.
    pub fn acc(&self) -> f64 {
        self.e
    }

    /// [`fp::rad_dir`]: an upper bound of `Σ|xs[i]| + e` (exact sums stay exact).
    #[inline(always)]
    pub fn rad_dir(&self) -> f64 {
        fp::rad_dir(&self.xs, self.e)
    }

    /// The Chebyshev square ([`fp::cheb_sqr`]) for `w >= Σ|xs[i]| + e` (its bound may
    /// overflow).
    #[inline(always)]
    pub fn cheb_sqr(&self, w: f64) -> Self {
        let (x0, xs, e) = fp::cheb_sqr(self.x0, &self.xs, self.e, w);
        Self::from_parts(x0, xs, e)
    }

    /// The unary affine operation with the shared approximation `a`: `alpha*x + zeta`,
    /// `e = delta + |alpha| e_x + rounding errors`. Sound wherever `a` holds for every
    /// value the form stands for: on the form's own range, or on any range known by
    /// other means to hold the real value (a carried interval).
    #[inline(always)]
    pub fn apply(&self, a: Approx) -> Self {
        if a.is_entire() {
            return Self::UNBOUNDED;
        }
        if a.alpha == 0.0 {
            // The constant `zeta ± delta`, exact: nothing to round (so `sqrt` of a range
            // below 0 is exactly `[0, 0]`, as the `Range` contract says).
            return Self::from_parts(a.zeta, [0.0; N], a.delta);
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
        Self::from_parts(x0, xs, up_abs(s, k_lin(N)))
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

impl<const N: usize, K: ReducedKind> Add for Reduced<N, K> {
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
        Self::from_parts(x0, xs, up_rel(s, N + 3))
    }
}

impl<const N: usize, K: ReducedKind> Sub for Reduced<N, K> {
    type Output = Self;
    /// The radii add: the two error terms are independent.
    #[inline(always)]
    fn sub(self, y: Self) -> Self {
        let x0 = self.x0 - y.x0;
        let mut s = self.e + y.e + U * x0.abs();
        let mut xs = [0.0; N];
        for ((z, a), b) in xs.iter_mut().zip(&self.xs).zip(&y.xs) {
            *z = a - b;
            s += U * z.abs();
        }
        Self::from_parts(x0, xs, up_rel(s, N + 3))
    }
}

impl<const N: usize, K: ReducedKind> Neg for Reduced<N, K> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        let mut xs = self.xs;
        for c in &mut xs {
            *c = -*c;
        }
        Self::from_parts(-self.x0, xs, self.e)
    }
}

impl<const N: usize, K: ReducedKind> Add<f64> for Reduced<N, K> {
    type Output = Self;
    #[inline(always)]
    fn add(self, c: f64) -> Self {
        let x0 = self.x0 + c;
        Self::from_parts(x0, self.xs, up_rel(self.e + U * x0.abs(), 2))
    }
}

impl<const N: usize, K: ReducedKind> Sub<f64> for Reduced<N, K> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, c: f64) -> Self {
        let x0 = self.x0 - c;
        Self::from_parts(x0, self.xs, up_rel(self.e + U * x0.abs(), 2))
    }
}

impl<const N: usize, K: ReducedKind> Mul<f64> for Reduced<N, K> {
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
        Self::from_parts(x0, xs, up_abs(s, k_lin(N)))
    }
}

impl<const N: usize, K: ReducedKind> Div<f64> for Reduced<N, K> {
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
        Self::from_parts(x0, xs, up_abs(s, k_lin(N)))
    }
}

impl<const N: usize, K: ReducedKind> Mul for Reduced<N, K> {
    type Output = Self;
    /// The kind's product, [`ReducedKind::mul`].
    #[inline(always)]
    fn mul(self, y: Self) -> Self {
        K::mul(self, y)
    }
}

impl<const N: usize, K: ReducedKind> Div for Reduced<N, K> {
    type Output = Self;
    /// `x * recip(y)`.
    #[inline(always)]
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, y: Self) -> Self {
        self * y.recip()
    }
}

crate::impl_f64_lhs_ops!(<const N: usize, K: ReducedKind> Reduced<N, K>);

impl<const N: usize, K: ReducedKind> Real for Reduced<N, K> {
    fn known(&self) -> crate::Known {
        let (lo, hi) = self.bounds();
        crate::Known::Range(lo, hi)
    }
    fn from_bounds(lo: f64, hi: f64) -> Option<Self> {
        Some(<Self as Range>::from_interval(lo, hi))
    }
    fn constant(c: f64) -> Self {
        Self::from_parts(c, [0.0; N], 0.0)
    }

    /// The kind's square, [`ReducedKind::sqr`].
    #[inline(always)]
    fn sqr(&self) -> Self {
        K::sqr(self)
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

    /// Each square is the Chebyshev square (`x0² + ½Wx² + 2 x0 Lx ± (2|x0| ex + ½Wx²)`,
    /// `Wx >= u + ex`, as both kinds' `sqr`), the two summed before a single rounding
    /// bound; `sqrt` is approximated on the sum's range ([`fp::bounds_fast`]) cut at the
    /// floor `mig(x)² + mig(y)²` ([`approx::sum_sq_floor`]). The R-functions spend most
    /// of an evaluation here.
    fn hypot(&self, other: &Self) -> Self {
        let (x, y) = (self, other);
        let wx = fp::rad_up(&x.xs, x.e);
        let wy = fp::rad_up(&y.xs, y.e);
        let (px, py) = (x.x0 * x.x0, y.x0 * y.x0);
        let (wwx, wwy) = (wx * wx, wy * wy);
        let h = 0.5 * (wwx + wwy);
        let c0 = px + py + h;
        let (tx0, ty0) = (2.0 * x.x0, 2.0 * y.x0);
        let mut r = px + py + wwx + wwy + h + c0.abs();
        let mut xs = [0.0; N];
        for ((z, xi), yi) in xs.iter_mut().zip(&x.xs).zip(&y.xs) {
            let a = tx0 * xi;
            let b = ty0 * yi;
            *z = a + b;
            r += a.abs() + b.abs() + z.abs();
        }
        let main = h + tx0.abs() * x.e + ty0.abs() * y.e;
        let e = up_abs(main + U * r, fp::k_mul(N) + 4);
        let (lo, hi) = fp::bounds_fast(c0, &xs, e);
        if !(lo.is_finite() && hi.is_finite()) {
            Self::UNBOUNDED
        } else {
            // The radii are the ones the squares used.
            let mx = fp::mig_below(x.x0, wx);
            let my = fp::mig_below(y.x0, wy);
            let floor = approx::sum_sq_floor((mx, mx), (my, my));
            Self::from_parts(c0, xs, e).apply(approx::sqrt_at_least(lo, hi, floor))
        }
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

impl<const N: usize, K: ReducedKind> Range for Reduced<N, K> {
    const NAME: &'static str = <K as Arithmetic>::NAME;
    const INPUTS: usize = N;

    /// `x0 = (lo+hi)/2`, `xs[i] = (hi-lo)/2`, so `ε_i = -1 ↦ lo`, `+1 ↦ hi`; any rounding
    /// of the midpoint or radius goes into `e`. An index `i >= N` gets no symbol: the
    /// whole radius goes into `e` (sound, uncorrelated). Reversed bounds are swapped;
    /// NaN or an infinite bound gives [`Reduced::UNBOUNDED`] (a half-line has no finite
    /// centre and radius; `mid_rad` would make them infinite and `e` NaN).
    fn input(i: usize, lo: f64, hi: f64) -> Self {
        if !(lo.is_finite() && hi.is_finite()) {
            return Self::UNBOUNDED;
        }
        let (lo, hi) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        let (m, r, err) = mid_rad(lo, hi);
        if i < N {
            // Built lane by lane: a store at index `i` read back as a vector stalls.
            let xs = core::array::from_fn(|k| if k == i { r } else { 0.0 });
            Self::from_parts(m, xs, err)
        } else {
            Self::from_parts(m, [0.0; N], add_dir_up(r, err))
        }
    }

    fn from_interval(lo: f64, hi: f64) -> Self {
        Self::input(usize::MAX, lo, hi)
    }

    /// The coefficients as they are; those past `N` symbols join the error term.
    fn from_affine(c0: f64, cs: &[f64], err: f64) -> Self {
        match fp::form_of(c0, cs, err) {
            Some((x0, xs, e)) => Self::from_parts(x0, xs, e),
            None => Self::UNBOUNDED,
        }
    }

    /// `x0 ∓ (Σ|xi| + e)`, outward rounded (exact results stay exact).
    fn bounds(&self) -> (f64, f64) {
        fp::bounds_dir(self.x0, self.rad_dir())
    }

    /// `0 ∈ bounds()` without the bounds ([`fp::holds_zero`]).
    #[inline(always)]
    fn contains_zero(&self) -> bool {
        fp::holds_zero(self.x0, self.rad_dir())
    }

    fn affine_part<const J: usize>(&self) -> Option<AffinePart<J>> {
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
