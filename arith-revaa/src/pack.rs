//! [`RevAaX4`]: four revised affine forms in SIMD registers, one lane each: four ray
//! forms ([`RevAa1x4`]) or four cell forms ([`RevAa3x4`]).
//!
//! The affine operations and the products (`+ - *`, `sqr`, constants) run as 4-lane
//! vector instructions that perform, lane for lane, exactly the `f64` operations of the
//! scalar form in the same order (no fused operations, the same selects), so each lane
//! is bit for bit the scalar result (but for the sign and payload of a NaN, which no
//! bound or test of a form reads: NaN fields make the whole line) and inherits its
//! soundness proof. The rarer
//! operations (`sqrt`, `exp`, `min`, ...) unpack, apply the scalar form and pack again.
//! `wide` uses AVX2 where the build targets it (`.cargo/config.toml`: x86-64-v3), SSE2
//! pairs or plain code elsewhere; the results are the same.
//! On a model of squares and products (the decocube) one packed evaluation costs about
//! 1.6-1.8 scalar ones.

use crate::RevAa;
use arith_core::affine_round::{k_lin, k_mul, slack, sqr_margin, TINY};
use arith_core::pack::{Pack, LANES};
use arith_core::round::{ETA, U};
use arith_core::Real;
use core::ops::{Add, Div, Mul, Neg, Sub};
use wide::{bytemuck, f64x4, i64x4};

/// Four [`RevAa<N>`] forms, structure of arrays: centres, coefficients, error radii.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RevAaX4<const N: usize> {
    x0: f64x4,
    xs: [f64x4; N],
    e: f64x4,
}

/// Four ray forms ([`RevAa<1>`]).
pub type RevAa1x4 = RevAaX4<1>;
/// Four cell forms ([`RevAa<3>`]).
pub type RevAa3x4 = RevAaX4<3>;

#[inline(always)]
fn splat(c: f64) -> f64x4 {
    f64x4::splat(c)
}

/// [`arith_core::affine_round::up_rel`] per lane.
#[inline(always)]
fn up_rel(s: f64x4, k: usize) -> f64x4 {
    s * splat(slack(k))
}

/// [`arith_core::affine_round::up_abs`] per lane.
#[inline(always)]
fn up_abs(s: f64x4, k: usize) -> f64x4 {
    s * splat(slack(k)) + splat((k + 1) as f64 * ETA)
}

/// `arith_core::round::step_up` per lane: the bits plus 1 (positive) or minus 1
/// (negative).
#[inline(always)]
fn step_up(s: f64x4) -> f64x4 {
    let b: i64x4 = bytemuck::cast(s);
    let neg = i64x4::splat(0).simd_gt(b); // all ones where b < 0
    bytemuck::cast(b + (neg | i64x4::splat(1)))
}

/// [`arith_core::affine_round::add_dir_up`] per lane.
#[inline(always)]
fn add_dir_up(a: f64x4, b: f64x4) -> f64x4 {
    let s = a + b;
    let bb = s - a;
    let t = (a - (s - bb)) + (b - bb);
    t.simd_gt(splat(0.0)).select(step_up(s), s)
}

impl<const N: usize> RevAaX4<N> {
    /// Lane by lane through the scalar form.
    #[inline(always)]
    fn lanewise(&self, f: impl Fn(&RevAa<N>) -> RevAa<N>) -> Self {
        Self::pack(self.unpack().map(|l| f(&l)))
    }

    #[inline(always)]
    fn lanewise2(&self, o: &Self, f: impl Fn(&RevAa<N>, &RevAa<N>) -> RevAa<N>) -> Self {
        let (a, b) = (self.unpack(), o.unpack());
        Self::pack(core::array::from_fn(|k| f(&a[k], &b[k])))
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
        RevAaX4 {
            x0,
            xs,
            e: up_abs(s, k_lin(N)),
        }
    }

    /// The scalar `Add<f64>` with the constant in lanes.
    #[inline(always)]
    fn add_lanes(self, c: f64x4) -> Self {
        let x0 = self.x0 + c;
        RevAaX4 {
            x0,
            xs: self.xs,
            e: up_rel(self.e + splat(U) * x0.abs(), 2),
        }
    }
}

impl<const N: usize> Pack for RevAaX4<N> {
    type Lane = RevAa<N>;
    #[inline(always)]
    fn pack(l: [RevAa<N>; LANES]) -> Self {
        RevAaX4 {
            x0: f64x4::new(l.map(|v| v.x0)),
            xs: core::array::from_fn(|i| f64x4::new(l.map(|v| v.xs[i]))),
            e: f64x4::new(l.map(|v| v.e)),
        }
    }
    #[inline(always)]
    fn unpack(self) -> [RevAa<N>; LANES] {
        let (x0, e) = (self.x0.to_array(), self.e.to_array());
        let xs = self.xs.map(|c| c.to_array());
        core::array::from_fn(|k| RevAa {
            x0: x0[k],
            xs: core::array::from_fn(|i| xs[i][k]),
            e: e[k],
        })
    }
    /// The scalar `Mul<f64>` then `Add<f64>`, with the constants in lanes.
    #[inline(always)]
    fn mul_add_lanes(self, m: [f64; LANES], c: [f64; LANES]) -> Self {
        self.mul_lanes(f64x4::new(m)).add_lanes(f64x4::new(c))
    }
}

impl<const N: usize> Add for RevAaX4<N> {
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
        RevAaX4 {
            x0,
            xs,
            e: up_rel(s, N + 3),
        }
    }
}

impl<const N: usize> Sub for RevAaX4<N> {
    type Output = Self;
    /// `x + (-y)`: IEEE subtraction is the sum with the negation, so these are the
    /// scalar `Sub`'s operations.
    #[inline(always)]
    fn sub(self, y: Self) -> Self {
        self + -y
    }
}

impl<const N: usize> Neg for RevAaX4<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        RevAaX4 {
            x0: -self.x0,
            xs: self.xs.map(|c| -c),
            e: self.e,
        }
    }
}

impl<const N: usize> Add<f64> for RevAaX4<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, c: f64) -> Self {
        self.add_lanes(splat(c))
    }
}

impl<const N: usize> Sub<f64> for RevAaX4<N> {
    type Output = Self;
    /// `x + (-c)`, as for [`Sub`].
    #[inline(always)]
    fn sub(self, c: f64) -> Self {
        self.add_lanes(splat(-c))
    }
}

impl<const N: usize> Mul<f64> for RevAaX4<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: f64) -> Self {
        self.mul_lanes(splat(c))
    }
}

impl<const N: usize> Div<f64> for RevAaX4<N> {
    type Output = Self;
    #[inline(always)]
    fn div(self, c: f64) -> Self {
        if c == 0.0 {
            return Self::pack([RevAa::UNBOUNDED; LANES]);
        }
        let x0 = self.x0 / splat(c);
        let mut r = x0.abs();
        let mut xs = self.xs;
        for z in &mut xs {
            *z /= splat(c);
            r += z.abs();
        }
        let s = self.e / splat(c.abs()) + splat(U) * r;
        RevAaX4 {
            x0,
            xs,
            e: up_abs(s, k_lin(N)),
        }
    }
}

/// The scalar `mul_forms` with its cross terms, the same sums in the same order, zeros
/// included (`0 + q` is not `q` for `q = -0`). Where the scalar form skips the cross
/// terms (each exactly 0), adding them changes no bit.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // several arrays indexed together
fn mul_forms<const N: usize>(x: RevAaX4<N>, y: RevAaX4<N>) -> RevAaX4<N> {
    let zero = splat(0.0);
    let p0 = x.x0 * y.x0;
    let (mut d, mut diag, mut u, mut v) = (zero, zero, zero, zero);
    let mut r = p0.abs();
    let mut xs = [zero; N];
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
    let mut off = zero;
    for i in 0..N {
        for j in i + 1..N {
            let a = x.xs[i] * y.xs[j];
            let b = x.xs[j] * y.xs[i];
            let s = a + b;
            off += s.abs();
            r += a.abs() + b.abs() + s.abs();
        }
    }
    let hd = splat(0.5) * d;
    let x0 = p0 + hd;
    let r = r + (hd.abs() + x0.abs());
    let main =
        x.e * y.e + y.e * (x.x0.abs() + u) + x.e * (y.x0.abs() + v) + splat(0.5) * diag + off;
    RevAaX4 {
        x0,
        xs,
        e: up_abs(main + splat(U) * r, k_mul(N)),
    }
}

impl<const N: usize> Mul for RevAaX4<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, y: Self) -> Self {
        mul_forms(self, y)
    }
}

impl<const N: usize> Div for RevAaX4<N> {
    type Output = Self;
    #[inline(always)]
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, y: Self) -> Self {
        self * y.recip()
    }
}

impl<const N: usize> Real for RevAaX4<N> {
    fn constant(c: f64) -> Self {
        RevAaX4 {
            x0: splat(c),
            xs: [splat(0.0); N],
            e: splat(0.0),
        }
    }

    /// The scalar `sqr`: the Chebyshev square where its gain survives and its bound is
    /// finite, else `x * x` (both computed, then the same choice per lane).
    #[inline(always)]
    fn sqr(&self) -> Self {
        let x0 = self.x0;
        let w = self.xs.iter().fold(self.e, |r, c| add_dir_up(r, c.abs()));
        let s2 = self.xs.iter().fold(splat(0.0), |s, c| s + *c * *c);
        let m = x0.abs() + w;
        let gain = (w * w - s2).simd_gt(splat(sqr_margin(N)) * (m * m) + splat(TINY));
        let prod = mul_forms(*self, *self);
        // `affine_round::cheb_sqr`.
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
        let ce = up_abs(main + splat(U) * r, k_mul(N));
        let ok = gain & ce.is_finite();
        RevAaX4 {
            x0: ok.select(c0, prod.x0),
            xs: core::array::from_fn(|i| ok.select(zs[i], prod.xs[i])),
            e: ok.select(ce, prod.e),
        }
    }

    fn powi(&self, n: i32) -> Self {
        match n {
            2 => self.sqr(),
            _ => self.lanewise(|l| l.powi(n)),
        }
    }
    fn sqrt(&self) -> Self {
        self.lanewise(RevAa::sqrt)
    }
    fn hypot(&self, other: &Self) -> Self {
        self.lanewise2(other, RevAa::hypot)
    }
    fn recip(&self) -> Self {
        self.lanewise(RevAa::recip)
    }
    fn exp(&self) -> Self {
        self.lanewise(RevAa::exp)
    }
    fn ln(&self) -> Self {
        self.lanewise(RevAa::ln)
    }
    fn sin(&self) -> Self {
        self.lanewise(RevAa::sin)
    }
    fn cos(&self) -> Self {
        self.lanewise(RevAa::cos)
    }
    fn abs(&self) -> Self {
        self.lanewise(RevAa::abs)
    }
    fn min(&self, other: &Self) -> Self {
        self.lanewise2(other, RevAa::min)
    }
    fn max(&self, other: &Self) -> Self {
        self.lanewise2(other, RevAa::max)
    }
}

arith_core::impl_f64_lhs_ops!(<const N: usize> RevAaX4<N>);
