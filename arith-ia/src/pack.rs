//! [`IntervalX4`]: four intervals in SIMD registers, one lane each.
//!
//! Sums, differences, products (of two intervals and by a constant), squares and the
//! ray inputs' `x m + c` run as vector instructions when every lane is on the scalar
//! operation's common path (finite bounds, products of at least `2^-960` in magnitude:
//! [`arith_core::simd::tight`]); otherwise the pack, and every rarer operation, goes lane
//! by lane through the scalar [`Interval`]. Each lane is therefore bit for bit the scalar
//! result and inherits its soundness.
//!
//! The vector product takes the floor of all four corner products and their minimum
//! (the ceilings and their maximum), where the scalar picks the two corners the signs
//! decide: the floor is monotone, so the minimum of the floors is the floor of the
//! least corner, the one the scalar picks (the common path has no zero corner, so no
//! signed zero can tell the two apart).

use crate::Interval;
use arith_core::pack::{Pack, LANES};
use arith_core::simd::tight::{add_hi, add_lo, mul_hi, mul_lo, mul_lo_hi};
use arith_core::simd::{f64x4, splat};
use arith_core::Real;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// Four [`Interval`]s, structure of arrays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntervalX4 {
    /// Lower bounds, one per lane.
    pub lo: f64x4,
    /// Upper bounds, one per lane.
    pub hi: f64x4,
}

impl IntervalX4 {
    /// The vector result where `ok` holds in every lane and the bounds are in order (as
    /// the scalar `from_dir` leaves them), else the scalar operation lane by lane.
    #[inline(always)]
    fn or_lanes(lo: f64x4, hi: f64x4, ok: f64x4, scalar: impl FnOnce() -> Self) -> Self {
        if (ok & lo.simd_le(hi)).all() {
            IntervalX4 { lo, hi }
        } else {
            scalar()
        }
    }

    #[inline(always)]
    fn lanewise(&self, f: impl Fn(&Interval) -> Interval) -> Self {
        Self::pack(self.unpack().map(|l| f(&l)))
    }

    #[inline(always)]
    fn lanewise2(&self, o: &Self, f: impl Fn(&Interval, &Interval) -> Interval) -> Self {
        let (a, b) = (self.unpack(), o.unpack());
        Self::pack(core::array::from_fn(|k| f(&a[k], &b[k])))
    }

    /// The interval `[c, c]` in every lane (the scalar `Interval::point`).
    #[inline(always)]
    fn point(c: f64) -> Self {
        let i = Interval::point(c);
        IntervalX4 {
            lo: splat(i.lo),
            hi: splat(i.hi),
        }
    }

    /// The scalar `mul_point` with the factor in lanes.
    #[inline(always)]
    fn mul_point_lanes(self, c: f64x4) -> Self {
        let pos = c.simd_ge(splat(0.0));
        let (a, b) = (pos.select(self.lo, self.hi), pos.select(self.hi, self.lo));
        let (lo, ok_lo) = mul_lo(a, c);
        let (hi, ok_hi) = mul_hi(b, c);
        Self::or_lanes(lo, hi, ok_lo & ok_hi, || {
            let c = c.to_array();
            let l = self.unpack();
            Self::pack(core::array::from_fn(|k| l[k] * c[k]))
        })
    }

    /// The scalar `self + Interval::point(c)` with the constant in lanes.
    #[inline(always)]
    fn add_point_lanes(self, c: f64x4) -> Self {
        let (lo, ok_lo) = add_lo(self.lo, c);
        let (hi, ok_hi) = add_hi(self.hi, c);
        Self::or_lanes(lo, hi, ok_lo & ok_hi & c.is_finite(), || {
            let c = c.to_array();
            let l = self.unpack();
            Self::pack(core::array::from_fn(|k| l[k] + Interval::point(c[k])))
        })
    }
}

impl Pack for IntervalX4 {
    type Lane = Interval;
    #[inline(always)]
    fn pack(l: [Interval; LANES]) -> Self {
        IntervalX4 {
            lo: f64x4::new(l.map(|i| i.lo)),
            hi: f64x4::new(l.map(|i| i.hi)),
        }
    }
    #[inline(always)]
    fn unpack(self) -> [Interval; LANES] {
        let (lo, hi) = (self.lo.to_array(), self.hi.to_array());
        core::array::from_fn(|k| Interval {
            lo: lo[k],
            hi: hi[k],
        })
    }
    /// The scalar `* m[k]` then `+ c[k]`.
    #[inline(always)]
    fn mul_add_lanes(self, m: [f64; LANES], c: [f64; LANES]) -> Self {
        self.mul_point_lanes(f64x4::new(m))
            .add_point_lanes(f64x4::new(c))
    }
}

impl Add for IntervalX4 {
    type Output = Self;
    #[inline(always)]
    #[allow(clippy::suspicious_arithmetic_impl)] // `&` joins lane masks
    fn add(self, y: Self) -> Self {
        let (lo, ok_lo) = add_lo(self.lo, y.lo);
        let (hi, ok_hi) = add_hi(self.hi, y.hi);
        Self::or_lanes(lo, hi, ok_lo & ok_hi, || self.lanewise2(&y, |a, b| *a + *b))
    }
}

impl Sub for IntervalX4 {
    type Output = Self;
    /// `self + (-y)`, as the scalar.
    #[inline(always)]
    fn sub(self, y: Self) -> Self {
        self + -y
    }
}

impl Neg for IntervalX4 {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        IntervalX4 {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

impl Mul for IntervalX4 {
    type Output = Self;
    #[inline(always)]
    #[allow(clippy::suspicious_arithmetic_impl)] // `&` joins lane masks
    fn mul(self, y: Self) -> Self {
        let (l1, h1, ok1) = mul_lo_hi(self.lo, y.lo);
        let (l2, h2, ok2) = mul_lo_hi(self.lo, y.hi);
        let (l3, h3, ok3) = mul_lo_hi(self.hi, y.lo);
        let (l4, h4, ok4) = mul_lo_hi(self.hi, y.hi);
        let lo = l1.min(l2).min(l3.min(l4));
        let hi = h1.max(h2).max(h3.max(h4));
        Self::or_lanes(lo, hi, ok1 & ok2 & ok3 & ok4, || {
            self.lanewise2(&y, |a, b| *a * *b)
        })
    }
}

impl Div for IntervalX4 {
    type Output = Self;
    #[inline(always)]
    fn div(self, y: Self) -> Self {
        self.lanewise2(&y, |a, b| *a / *b)
    }
}

impl Add<f64> for IntervalX4 {
    type Output = Self;
    #[inline(always)]
    fn add(self, c: f64) -> Self {
        self.add_point_lanes(splat(c))
    }
}

impl Sub<f64> for IntervalX4 {
    type Output = Self;
    #[inline(always)]
    fn sub(self, c: f64) -> Self {
        self.add_point_lanes(splat(-c))
    }
}

impl Mul<f64> for IntervalX4 {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: f64) -> Self {
        self.mul_point_lanes(splat(c))
    }
}

impl Div<f64> for IntervalX4 {
    type Output = Self;
    #[inline(always)]
    fn div(self, c: f64) -> Self {
        self.lanewise(|a| *a / c)
    }
}

arith_core::impl_f64_lhs_ops!(IntervalX4);

impl Real for IntervalX4 {
    fn constant(c: f64) -> Self {
        Self::point(c)
    }

    /// `[mig², mag²]`: the floor of `mig²` (exactly 0 where `mig` is 0) and the ceiling of
    /// `mag²`, as the scalar `powi_pos(2)`.
    #[inline(always)]
    fn sqr(&self) -> Self {
        let zero = splat(0.0);
        let (lo, hi) = (self.lo, self.hi);
        let above = lo.simd_ge(zero);
        let below = hi.simd_le(zero);
        let mig = above.select(lo, below.select(-hi, zero));
        let mag = above.select(hi, below.select(-lo, (-lo).max(hi)));
        // Where `mig` is 0 the vector floor is `0 * 0 = +0`, the scalar's exact 0.
        let (l, ok_l) = mul_lo(mig, mig);
        let (h, ok_h) = mul_hi(mag, mag);
        let ok = (ok_l | mig.simd_eq(zero)) & ok_h;
        Self::or_lanes(l, h, ok, || self.lanewise(Interval::sqr))
    }
    fn powi(&self, n: i32) -> Self {
        match n {
            2 => self.sqr(),
            _ => self.lanewise(|l| l.powi(n)),
        }
    }
    fn sqrt(&self) -> Self {
        self.lanewise(Interval::sqrt)
    }
    fn hypot(&self, other: &Self) -> Self {
        self.lanewise2(other, Interval::hypot)
    }
    fn recip(&self) -> Self {
        self.lanewise(Interval::recip)
    }
    fn exp(&self) -> Self {
        self.lanewise(Interval::exp)
    }
    fn ln(&self) -> Self {
        self.lanewise(Interval::ln)
    }
    fn sin(&self) -> Self {
        self.lanewise(Interval::sin)
    }
    fn cos(&self) -> Self {
        self.lanewise(Interval::cos)
    }
    fn abs(&self) -> Self {
        self.lanewise(Interval::abs)
    }
    fn min(&self, other: &Self) -> Self {
        self.lanewise2(other, Interval::min)
    }
    fn max(&self, other: &Self) -> Self {
        self.lanewise2(other, Interval::max)
    }
    /// `[c, c] - self`, as the scalar.
    fn rsub(self, c: f64) -> Self {
        Self::point(c) - self
    }
    fn rdiv(self, c: f64) -> Self {
        self.lanewise(|a| a.rdiv(c))
    }
}
