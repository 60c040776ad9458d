//! [`RevAa1x4`]: four ray forms `RevAa<1>` in SIMD registers, one lane each.
//!
//! The affine operations and the products (`+ - *`, `sqr`, constants) run as 4-lane
//! vector instructions that perform, lane for lane, exactly the `f64` operations of the
//! scalar form in the same order (no fused operations, the same selects), so each lane
//! is bit for bit the scalar result and inherits its soundness proof. The rarer
//! operations (`sqrt`, `exp`, `min`, ...) unpack, apply the scalar form and pack again.
//! On a model of squares and products (the decocube) one packed evaluation costs about
//! 1.6 scalar ones.

use crate::RevAa;
use arith_core::affine_round::{k_lin, k_mul, slack, sqr_margin, TINY};
use arith_core::pack::{Pack, LANES};
use arith_core::round::{ETA, U};
use arith_core::Real;
use core::ops::{Add, Div, Mul, Neg, Sub};
use wide::{bytemuck, f64x4, i64x4};

/// Four [`RevAa<1>`] forms, structure of arrays: centres, coefficients, error radii.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RevAa1x4 {
    x0: f64x4,
    x1: f64x4,
    e: f64x4,
}

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

impl RevAa1x4 {
    /// Lane by lane through the scalar form.
    #[inline(always)]
    fn lanewise(&self, f: impl Fn(&RevAa<1>) -> RevAa<1>) -> Self {
        Self::pack(self.unpack().map(|l| f(&l)))
    }

    #[inline(always)]
    fn lanewise2(&self, o: &Self, f: impl Fn(&RevAa<1>, &RevAa<1>) -> RevAa<1>) -> Self {
        let (a, b) = (self.unpack(), o.unpack());
        Self::pack(core::array::from_fn(|k| f(&a[k], &b[k])))
    }
}

impl Pack for RevAa1x4 {
    type Lane = RevAa<1>;
    #[inline(always)]
    fn pack(l: [RevAa<1>; LANES]) -> Self {
        RevAa1x4 {
            x0: f64x4::new(l.map(|v| v.x0)),
            x1: f64x4::new(l.map(|v| v.xs[0])),
            e: f64x4::new(l.map(|v| v.e)),
        }
    }
    /// The scalar `Mul<f64>` then `Add<f64>`, with the constants in lanes.
    #[inline(always)]
    fn mul_add_lanes(self, m: [f64; LANES], c: [f64; LANES]) -> Self {
        let (m, c) = (f64x4::new(m), f64x4::new(c));
        let x0 = self.x0 * m;
        let x1 = self.x1 * m;
        let r = x0.abs() + x1.abs();
        let e = up_abs(m.abs() * self.e + splat(U) * r, k_lin(1));
        let x0 = x0 + c;
        RevAa1x4 {
            x0,
            x1,
            e: up_rel(e + splat(U) * x0.abs(), 2),
        }
    }
    #[inline(always)]
    fn unpack(self) -> [RevAa<1>; LANES] {
        let (x0, x1, e) = (self.x0.to_array(), self.x1.to_array(), self.e.to_array());
        core::array::from_fn(|k| RevAa {
            x0: x0[k],
            xs: [x1[k]],
            e: e[k],
        })
    }
}

impl Add for RevAa1x4 {
    type Output = Self;
    #[inline(always)]
    fn add(self, y: Self) -> Self {
        let x0 = self.x0 + y.x0;
        let s = self.e + y.e + splat(U) * x0.abs();
        let x1 = self.x1 + y.x1;
        let s = s + splat(U) * x1.abs();
        RevAa1x4 {
            x0,
            x1,
            e: up_rel(s, 4),
        }
    }
}

impl Sub for RevAa1x4 {
    type Output = Self;
    #[inline(always)]
    fn sub(self, y: Self) -> Self {
        let x0 = self.x0 - y.x0;
        let s = self.e + y.e + splat(U) * x0.abs();
        let x1 = self.x1 - y.x1;
        let s = s + splat(U) * x1.abs();
        RevAa1x4 {
            x0,
            x1,
            e: up_rel(s, 4),
        }
    }
}

impl Neg for RevAa1x4 {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        RevAa1x4 {
            x0: -self.x0,
            x1: -self.x1,
            e: self.e,
        }
    }
}

impl Add<f64> for RevAa1x4 {
    type Output = Self;
    #[inline(always)]
    fn add(self, c: f64) -> Self {
        let x0 = self.x0 + splat(c);
        RevAa1x4 {
            x0,
            x1: self.x1,
            e: up_rel(self.e + splat(U) * x0.abs(), 2),
        }
    }
}

impl Sub<f64> for RevAa1x4 {
    type Output = Self;
    #[inline(always)]
    fn sub(self, c: f64) -> Self {
        let x0 = self.x0 - splat(c);
        RevAa1x4 {
            x0,
            x1: self.x1,
            e: up_rel(self.e + splat(U) * x0.abs(), 2),
        }
    }
}

impl Mul<f64> for RevAa1x4 {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: f64) -> Self {
        let x0 = self.x0 * splat(c);
        let x1 = self.x1 * splat(c);
        let r = x0.abs() + x1.abs();
        let s = splat(c.abs()) * self.e + splat(U) * r;
        RevAa1x4 {
            x0,
            x1,
            e: up_abs(s, k_lin(1)),
        }
    }
}

impl Div<f64> for RevAa1x4 {
    type Output = Self;
    #[inline(always)]
    fn div(self, c: f64) -> Self {
        if c == 0.0 {
            return Self::pack([RevAa::UNBOUNDED; LANES]);
        }
        let x0 = self.x0 / splat(c);
        let x1 = self.x1 / splat(c);
        let r = x0.abs() + x1.abs();
        let s = self.e / splat(c.abs()) + splat(U) * r;
        RevAa1x4 {
            x0,
            x1,
            e: up_abs(s, k_lin(1)),
        }
    }
}

/// `mul_forms` of the scalar form for `N = 1` (no cross terms), the same sums in the
/// same order, zeros included (`0 + q` is not `q` for `q = -0`).
#[inline(always)]
fn mul_forms(x: RevAa1x4, y: RevAa1x4) -> RevAa1x4 {
    let zero = splat(0.0);
    let p0 = x.x0 * y.x0;
    let q = x.x1 * y.x1;
    let d = zero + q;
    let diag = zero + q.abs();
    let a = x.x0 * y.x1;
    let b = x.x1 * y.x0;
    let x1 = a + b;
    let r = p0.abs() + (q.abs() + d.abs() + a.abs() + b.abs() + x1.abs());
    let u = zero + x.x1.abs();
    let v = zero + y.x1.abs();
    let hd = splat(0.5) * d;
    let x0 = p0 + hd;
    let r = r + (hd.abs() + x0.abs());
    let main =
        x.e * y.e + y.e * (x.x0.abs() + u) + x.e * (y.x0.abs() + v) + splat(0.5) * diag + zero;
    RevAa1x4 {
        x0,
        x1,
        e: up_abs(main + splat(U) * r, k_mul(1)),
    }
}

impl Mul for RevAa1x4 {
    type Output = Self;
    #[inline(always)]
    fn mul(self, y: Self) -> Self {
        mul_forms(self, y)
    }
}

impl Div for RevAa1x4 {
    type Output = Self;
    #[inline(always)]
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, y: Self) -> Self {
        self * y.recip()
    }
}

impl Real for RevAa1x4 {
    fn constant(c: f64) -> Self {
        RevAa1x4 {
            x0: splat(c),
            x1: splat(0.0),
            e: splat(0.0),
        }
    }

    /// The scalar `sqr` for `N = 1`: both the product and the Chebyshev square, then
    /// the same select.
    #[inline(always)]
    fn sqr(&self) -> Self {
        let x0 = self.x0;
        let w = add_dir_up(self.e, self.x1.abs());
        let s2 = splat(0.0) + self.x1 * self.x1;
        let m = x0.abs() + w;
        let gain = (w * w - s2).simd_gt(splat(sqr_margin(1)) * (m * m) + splat(TINY));
        let prod = mul_forms(*self, *self);
        // `affine_round::cheb_sqr`.
        let p0 = x0 * x0;
        let ww = w * w;
        let h = splat(0.5) * ww;
        let c0 = p0 + h;
        let tx0 = splat(2.0) * x0;
        let z = tx0 * self.x1;
        let r = p0.abs() + ww + c0.abs() + z.abs();
        let main = h + tx0.abs() * self.e;
        let ce = up_abs(main + splat(U) * r, k_mul(1));
        let ok = gain & ce.is_finite();
        RevAa1x4 {
            x0: ok.select(c0, prod.x0),
            x1: ok.select(z, prod.x1),
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

arith_core::impl_f64_lhs_ops!(RevAa1x4);
