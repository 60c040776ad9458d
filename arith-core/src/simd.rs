//! [`ReducedX4`]: four reduced affine forms `x0 + Σ xs[i] εi ± e` in SIMD registers, one
//! lane each (feature `simd`).
//!
//! The reduced arithmetics (RAA*, RevAA) share every affine operation (`+ - neg`, the
//! `f64`-constant ones, the ray inputs) and differ only in their product and square. So
//! this module runs the shared operations as 4-lane vector instructions, and each
//! arithmetic's crate supplies its own `*` and `sqr` through [`ReducedLanes`]. Every
//! operation performs, lane for lane, exactly the `f64` operations of the scalar form in
//! the same order (no fused operations, the same selects), so each lane is bit for bit
//! the scalar result (but for the sign and payload of a NaN, which no bound reads: NaN
//! fields make the whole line) and inherits its soundness proof. `check_pack` in the test
//! kit holds each arithmetic to that. The rarer operations (`sqrt`, `exp`, `min`, ...)
//! unpack, apply the scalar form and pack again.
//!
//! `wide` uses AVX2 where the build targets it (`.cargo/config.toml`: x86-64-v3), SSE2
//! pairs or plain code elsewhere; the results are the same.

use crate::affine_round::{k_lin, k_mul, slack};
use crate::pack::{Pack, LANES};
use crate::reduced::{Reduced, ReducedKind};
use crate::round::{ETA, U};
use crate::{Range, Real};
use core::marker::PhantomData;
use core::ops::{Add, Div, Mul, Neg, Sub};
pub use wide::f64x4;

pub mod tight;

/// A scalar reduced affine form `x0 + Σ xs[i] εi ± e` whose affine operations are the
/// shared ones of this module, with its own product and square in lanes.
///
/// `parts`, `from_parts` and [`ReducedX4`]'s fields are the raw representation, for
/// packing and for the lane operations: unlike the forms' checked constructors they do
/// not refuse a negative radius `e` (which would describe no value at all, so a range
/// test on it could say "no zero"). Build forms with the arithmetic's own constructors.
pub trait ReducedForm<const N: usize>: Range + Copy {
    /// `(x0, xs, e)`.
    fn parts(&self) -> (f64, [f64; N], f64);
    /// The form of these parts, as they are (`e` must not be negative; a NaN `e`, which
    /// the operations can produce, is kept and reads as the whole line).
    fn from_parts(x0: f64, xs: [f64; N], e: f64) -> Self;
    /// Lane for lane, bit for bit, the scalar `x * y`.
    fn mul_x4(x: ReducedX4<N, Self>, y: ReducedX4<N, Self>) -> ReducedX4<N, Self>;
    /// Lane for lane, bit for bit, the scalar `x.sqr()`.
    fn sqr_x4(x: ReducedX4<N, Self>) -> ReducedX4<N, Self>;
}

/// A [`ReducedKind`]'s product and square in lanes, which make its [`Reduced`] forms a
/// [`ReducedForm`].
pub trait ReducedLanes: ReducedKind {
    /// Lane for lane, bit for bit, the scalar `x * y`.
    fn mul_x4<const N: usize>(
        x: ReducedX4<N, Reduced<N, Self>>,
        y: ReducedX4<N, Reduced<N, Self>>,
    ) -> ReducedX4<N, Reduced<N, Self>>;
    /// Lane for lane, bit for bit, the scalar `x.sqr()`.
    fn sqr_x4<const N: usize>(x: ReducedX4<N, Reduced<N, Self>>) -> ReducedX4<N, Reduced<N, Self>>;
}

impl<const N: usize, K: ReducedLanes> ReducedForm<N> for Reduced<N, K> {
    #[inline(always)]
    fn parts(&self) -> (f64, [f64; N], f64) {
        (self.x0, self.xs, self.e)
    }
    #[inline(always)]
    fn from_parts(x0: f64, xs: [f64; N], e: f64) -> Self {
        debug_assert!(e >= 0.0 || e.is_nan(), "negative radius {e}");
        Reduced::from_parts(x0, xs, e)
    }
    #[inline(always)]
    fn mul_x4(x: ReducedX4<N, Self>, y: ReducedX4<N, Self>) -> ReducedX4<N, Self> {
        K::mul_x4(x, y)
    }
    #[inline(always)]
    fn sqr_x4(x: ReducedX4<N, Self>) -> ReducedX4<N, Self> {
        K::sqr_x4(x)
    }
}

/// Four forms `F`, structure of arrays: centres, coefficients, error radii (raw: see
/// [`ReducedForm`]; no radius may be negative).
pub struct ReducedX4<const N: usize, F> {
    /// Centres, one per lane.
    pub x0: f64x4,
    /// Coefficients of the `N` input symbols, one per lane.
    pub xs: [f64x4; N],
    /// Error radii, one per lane.
    pub e: f64x4,
    form: PhantomData<F>,
}

// By hand: derives would ask `F` for the same traits although only `PhantomData<F>` is
// stored.
impl<const N: usize, F> Clone for ReducedX4<N, F> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<const N: usize, F> Copy for ReducedX4<N, F> {}
impl<const N: usize, F> PartialEq for ReducedX4<N, F> {
    fn eq(&self, o: &Self) -> bool {
        self.x0 == o.x0 && self.xs == o.xs && self.e == o.e
    }
}
impl<const N: usize, F> core::fmt::Debug for ReducedX4<N, F> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ReducedX4")
            .field("x0", &self.x0)
            .field("xs", &self.xs)
            .field("e", &self.e)
            .finish()
    }
}

/// `c` in every lane.
#[inline(always)]
pub fn splat(c: f64) -> f64x4 {
    f64x4::splat(c)
}

/// [`crate::affine_round::up_rel`] per lane.
#[inline(always)]
pub fn up_rel(s: f64x4, k: usize) -> f64x4 {
    s * splat(slack(k))
}

/// [`crate::affine_round::up_abs`] per lane.
#[inline(always)]
pub fn up_abs(s: f64x4, k: usize) -> f64x4 {
    s * splat(slack(k)) + splat((k + 1) as f64 * ETA)
}

/// Knuth's TwoSum per lane: `s = fl(a + b)` and `e` with `s + e == a + b` exactly.
#[inline(always)]
pub(crate) fn two_sum(a: f64x4, b: f64x4) -> (f64x4, f64x4) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// [`crate::affine_round::add_dir_up`] per lane.
#[inline(always)]
pub fn add_dir_up(a: f64x4, b: f64x4) -> f64x4 {
    let (s, t) = two_sum(a, b);
    t.simd_gt(splat(0.0)).select(tight::next_up(s), s)
}

/// [`crate::affine_round::add_dir_down`] per lane.
#[inline(always)]
pub fn add_dir_down(a: f64x4, b: f64x4) -> f64x4 {
    let (s, t) = two_sum(a, b);
    t.simd_lt(splat(0.0)).select(tight::next_down(s), s)
}

impl<const N: usize, F> ReducedX4<N, F> {
    /// [`crate::reduced::Reduced`]'s `bounds` per lane where both are finite (the
    /// scalar then gives the whole line): `x0 ∓ rad_dir()`, outward rounded.
    #[inline(always)]
    pub fn bounds_dir(&self) -> (f64x4, f64x4) {
        let rad = self.rad_dir();
        (add_dir_down(self.x0, -rad), add_dir_up(self.x0, rad))
    }

    /// The forms of these parts, as they are (no radius may be negative).
    #[inline(always)]
    pub fn new(x0: f64x4, xs: [f64x4; N], e: f64x4) -> Self {
        debug_assert!(!e.simd_lt(splat(0.0)).any(), "negative radius {e:?}");
        ReducedX4 {
            x0,
            xs,
            e,
            form: PhantomData,
        }
    }

    /// `a` where `mask` is set, else `b`, lane by lane.
    #[inline(always)]
    pub fn select(mask: f64x4, a: Self, b: Self) -> Self {
        Self::new(
            mask.select(a.x0, b.x0),
            core::array::from_fn(|i| mask.select(a.xs[i], b.xs[i])),
            mask.select(a.e, b.e),
        )
    }

    /// [`crate::affine_round::rad_dir`] per lane: an upper bound of `Σ|xs[i]| + e`.
    #[inline(always)]
    pub fn rad_dir(&self) -> f64x4 {
        self.xs.iter().fold(self.e, |r, c| add_dir_up(r, c.abs()))
    }

    /// [`crate::affine_round::cheb_sqr`] per lane, for `w >= Σ|xs[i]| + e`.
    #[inline(always)]
    pub fn cheb_sqr(&self, w: f64x4) -> Self {
        let x0 = self.x0;
        let p0 = x0 * x0;
        let ww = w * w;
        let h = splat(0.5) * ww;
        let c0 = p0 + h;
        let tx0 = splat(2.0) * x0;
        let mut r = p0.abs() + ww + c0.abs();
        let mut zs = self.xs;
        for z in &mut zs {
            *z = tx0 * *z;
            r += z.abs();
        }
        let main = h + tx0.abs() * self.e;
        Self::new(c0, zs, up_abs(main + splat(U) * r, k_mul(N)))
    }

    /// The scalar `Mul<f64>` with the factor in lanes.
    #[inline(always)]
    fn mul_lanes(self, c: f64x4) -> Self {
        let x0 = self.x0 * c;
        let mut r = x0.abs();
        let mut xs = self.xs;
        for z in &mut xs {
            *z *= c;
            r += z.abs();
        }
        let s = c.abs() * self.e + splat(U) * r;
        Self::new(x0, xs, up_abs(s, k_lin(N)))
    }

    /// The scalar `Add<f64>` with the constant in lanes.
    #[inline(always)]
    fn add_lanes(self, c: f64x4) -> Self {
        let x0 = self.x0 + c;
        Self::new(x0, self.xs, up_rel(self.e + splat(U) * x0.abs(), 2))
    }
}

impl<const N: usize, F: ReducedForm<N>> ReducedX4<N, F> {
    /// Lane by lane through the scalar form.
    #[inline(always)]
    fn lanewise(&self, f: impl Fn(&F) -> F) -> Self {
        Self::pack(self.unpack().map(|l| f(&l)))
    }

    #[inline(always)]
    fn lanewise2(&self, o: &Self, f: impl Fn(&F, &F) -> F) -> Self {
        let (a, b) = (self.unpack(), o.unpack());
        Self::pack(core::array::from_fn(|k| f(&a[k], &b[k])))
    }
}

impl<const N: usize, F: ReducedForm<N>> Pack for ReducedX4<N, F> {
    type Lane = F;
    #[inline(always)]
    fn pack(l: [F; LANES]) -> Self {
        let p = l.map(|v| v.parts());
        Self::new(
            f64x4::new(p.map(|v| v.0)),
            core::array::from_fn(|i| f64x4::new(p.map(|v| v.1[i]))),
            f64x4::new(p.map(|v| v.2)),
        )
    }
    #[inline(always)]
    fn unpack(self) -> [F; LANES] {
        let (x0, e) = (self.x0.to_array(), self.e.to_array());
        let xs = self.xs.map(|c| c.to_array());
        core::array::from_fn(|k| F::from_parts(x0[k], core::array::from_fn(|i| xs[i][k]), e[k]))
    }
    /// The scalar `Mul<f64>` then `Add<f64>`, with the constants in lanes.
    #[inline(always)]
    fn mul_add_lanes(self, m: [f64; LANES], c: [f64; LANES]) -> Self {
        self.mul_lanes(f64x4::new(m)).add_lanes(f64x4::new(c))
    }
}

impl<const N: usize, F: ReducedForm<N>> Add for ReducedX4<N, F> {
    type Output = Self;
    #[inline(always)]
    fn add(self, y: Self) -> Self {
        let x0 = self.x0 + y.x0;
        let mut s = self.e + y.e + splat(U) * x0.abs();
        let mut xs = self.xs;
        for (z, b) in xs.iter_mut().zip(&y.xs) {
            *z += *b;
            s += splat(U) * z.abs();
        }
        Self::new(x0, xs, up_rel(s, N + 3))
    }
}

impl<const N: usize, F: ReducedForm<N>> Sub for ReducedX4<N, F> {
    type Output = Self;
    /// `x + (-y)`: IEEE subtraction is the sum with the negation, so these are the
    /// scalar `Sub`'s operations.
    #[inline(always)]
    fn sub(self, y: Self) -> Self {
        self + -y
    }
}

impl<const N: usize, F: ReducedForm<N>> Neg for ReducedX4<N, F> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.x0, self.xs.map(|c| -c), self.e)
    }
}

impl<const N: usize, F: ReducedForm<N>> Add<f64> for ReducedX4<N, F> {
    type Output = Self;
    #[inline(always)]
    fn add(self, c: f64) -> Self {
        self.add_lanes(splat(c))
    }
}

impl<const N: usize, F: ReducedForm<N>> Sub<f64> for ReducedX4<N, F> {
    type Output = Self;
    /// `x + (-c)`, as for [`Sub`].
    #[inline(always)]
    fn sub(self, c: f64) -> Self {
        self.add_lanes(splat(-c))
    }
}

impl<const N: usize, F: ReducedForm<N>> Mul<f64> for ReducedX4<N, F> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: f64) -> Self {
        self.mul_lanes(splat(c))
    }
}

impl<const N: usize, F: ReducedForm<N>> Div<f64> for ReducedX4<N, F> {
    type Output = Self;
    #[inline(always)]
    fn div(self, c: f64) -> Self {
        if c == 0.0 {
            return self.lanewise(|l| *l / c);
        }
        let x0 = self.x0 / splat(c);
        let mut r = x0.abs();
        let mut xs = self.xs;
        for z in &mut xs {
            *z /= splat(c);
            r += z.abs();
        }
        let s = self.e / splat(c.abs()) + splat(U) * r;
        Self::new(x0, xs, up_abs(s, k_lin(N)))
    }
}

impl<const N: usize, F: ReducedForm<N>> Mul for ReducedX4<N, F> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, y: Self) -> Self {
        F::mul_x4(self, y)
    }
}

impl<const N: usize, F: ReducedForm<N>> Div for ReducedX4<N, F> {
    type Output = Self;
    #[inline(always)]
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, y: Self) -> Self {
        self * y.recip()
    }
}

impl<const N: usize, F: ReducedForm<N>> Real for ReducedX4<N, F> {
    fn constant(c: f64) -> Self {
        Self::new(splat(c), [splat(0.0); N], splat(0.0))
    }
    #[inline(always)]
    fn sqr(&self) -> Self {
        F::sqr_x4(*self)
    }
    fn powi(&self, n: i32) -> Self {
        match n {
            2 => self.sqr(),
            _ => self.lanewise(|l| l.powi(n)),
        }
    }
    fn sqrt(&self) -> Self {
        self.lanewise(F::sqrt)
    }
    fn hypot(&self, other: &Self) -> Self {
        self.lanewise2(other, F::hypot)
    }
    fn recip(&self) -> Self {
        self.lanewise(F::recip)
    }
    fn exp(&self) -> Self {
        self.lanewise(F::exp)
    }
    fn ln(&self) -> Self {
        self.lanewise(F::ln)
    }
    fn sin(&self) -> Self {
        self.lanewise(F::sin)
    }
    fn cos(&self) -> Self {
        self.lanewise(F::cos)
    }
    fn abs(&self) -> Self {
        self.lanewise(F::abs)
    }
    fn min(&self, other: &Self) -> Self {
        self.lanewise2(other, F::min)
    }
    fn max(&self, other: &Self) -> Self {
        self.lanewise2(other, F::max)
    }
}

crate::impl_f64_lhs_ops!(<const N: usize, F: ReducedForm<N>> ReducedX4<N, F>);
