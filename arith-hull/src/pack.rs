//! [`HullX4`]: four hulls in SIMD registers, a [`RevAaX4`] and an [`IntervalX4`].
//!
//! Sums, differences, products, the operations with a constant, squares and the ray
//! inputs' `x m + c` run as vector instructions on both parts (each part's pack is its
//! scalar form lane for lane); the rebuilding of an affine part that knows nothing
//! ([`Hull::new`]) and the square's fit on the intersection, where the intersection cuts
//! more than a quarter of the affine range, go lane by lane through the scalar
//! [`Hull`], as does every rarer operation. Each lane is therefore bit for bit the
//! scalar result and inherits its soundness.

use crate::Hull;
use arith_core::pack::{Pack, LANES};
use arith_core::simd::splat;
use arith_core::Real;
use arith_ia::IntervalX4;
use arith_revaa::RevAaX4;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// Four [`Hull<N>`] values, each part in SIMD lanes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HullX4<const N: usize> {
    /// The affine parts.
    pub affine: RevAaX4<N>,
    /// The interval parts.
    pub interval: IntervalX4,
}

impl<const N: usize> HullX4<N> {
    /// [`Hull::new`] per lane: the pair as it is where every affine part is finite,
    /// else each lane through the scalar rebuilding.
    #[inline(always)]
    fn new(affine: RevAaX4<N>, interval: IntervalX4) -> Self {
        if (affine.e.is_finite() & affine.x0.is_finite()).all() {
            HullX4 { affine, interval }
        } else {
            let (a, i) = (affine.unpack(), interval.unpack());
            Self::pack(core::array::from_fn(|k| Hull::new(a[k], i[k])))
        }
    }

    #[inline(always)]
    fn lanewise(&self, f: impl Fn(&Hull<N>) -> Hull<N>) -> Self {
        Self::pack(self.unpack().map(|l| f(&l)))
    }

    #[inline(always)]
    fn lanewise2(&self, o: &Self, f: impl Fn(&Hull<N>, &Hull<N>) -> Hull<N>) -> Self {
        let (a, b) = (self.unpack(), o.unpack());
        Self::pack(core::array::from_fn(|k| f(&a[k], &b[k])))
    }
}

impl<const N: usize> Pack for HullX4<N> {
    type Lane = Hull<N>;
    #[inline(always)]
    fn pack(l: [Hull<N>; LANES]) -> Self {
        HullX4 {
            affine: RevAaX4::pack(l.map(|h| h.affine)),
            interval: IntervalX4::pack(l.map(|h| h.interval)),
        }
    }
    #[inline(always)]
    fn unpack(self) -> [Hull<N>; LANES] {
        let (a, i) = (self.affine.unpack(), self.interval.unpack());
        core::array::from_fn(|k| Hull {
            affine: a[k],
            interval: i[k],
        })
    }
    /// The scalar `* m[k]` then `+ c[k]`. Where the final affine parts are finite so
    /// were the intermediate ones (an infinite or NaN centre or radius stays so through
    /// `+ c`), so neither scalar step rebuilt a part.
    #[inline(always)]
    fn mul_add_lanes(self, m: [f64; LANES], c: [f64; LANES]) -> Self {
        let affine = self.affine.mul_add_lanes(m, c);
        if (affine.e.is_finite() & affine.x0.is_finite()).all() {
            HullX4 {
                affine,
                interval: self.interval.mul_add_lanes(m, c),
            }
        } else {
            let l = self.unpack();
            Self::pack(core::array::from_fn(|k| l[k] * m[k] + c[k]))
        }
    }
}

macro_rules! both_parts {
    ($tr:ident, $f:ident) => {
        impl<const N: usize> $tr for HullX4<N> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, y: Self) -> Self {
                Self::new(self.affine.$f(y.affine), self.interval.$f(y.interval))
            }
        }
    };
    ($tr:ident, $f:ident, f64) => {
        impl<const N: usize> $tr<f64> for HullX4<N> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, c: f64) -> Self {
                Self::new(self.affine.$f(c), self.interval.$f(c))
            }
        }
    };
}
both_parts!(Add, add);
both_parts!(Sub, sub);
both_parts!(Mul, mul);
both_parts!(Add, add, f64);
both_parts!(Sub, sub, f64);
both_parts!(Mul, mul, f64);

impl<const N: usize> Div for HullX4<N> {
    type Output = Self;
    #[inline(always)]
    fn div(self, y: Self) -> Self {
        self.lanewise2(&y, |a, b| *a / *b)
    }
}

impl<const N: usize> Div<f64> for HullX4<N> {
    type Output = Self;
    #[inline(always)]
    fn div(self, c: f64) -> Self {
        self.lanewise(|a| *a / c)
    }
}

impl<const N: usize> Neg for HullX4<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        HullX4 {
            affine: -self.affine,
            interval: -self.interval,
        }
    }
}

arith_core::impl_f64_lhs_ops!(<const N: usize> HullX4<N>);

impl<const N: usize> Real for HullX4<N> {
    fn constant(c: f64) -> Self {
        Self::pack([Hull::constant(c); LANES])
    }

    /// The scalar `sqr` where every lane's affine range is finite and its intersection
    /// with the interval is not empty: revised affine arithmetic's square and the
    /// interval square of the intersection, in lanes, except in the lanes where the
    /// intersection cuts more than a quarter of the affine range (the scalar square
    /// there).
    #[inline(always)]
    fn sqr(&self) -> Self {
        let (al, ah) = self.affine.bounds_dir();
        let i = &self.interval;
        let (lo, hi) = (al.max(i.lo), ah.min(i.hi));
        let cut = ((lo - al) + (ah - hi)).simd_gt(splat(0.25) * (ah - al));
        if !(al.is_finite() & ah.is_finite() & lo.simd_le(hi)).all() {
            return self.lanewise(Hull::sqr);
        }
        let (affine, interval) = (self.affine.sqr(), IntervalX4 { lo, hi }.sqr());
        if !cut.any() {
            return Self::new(affine, interval);
        }
        // The lanes that cut take the scalar square (its second fit).
        let (cut, l) = (cut.to_array(), self.unpack());
        let (a, i) = (affine.unpack(), interval.unpack());
        Self::pack(core::array::from_fn(|k| {
            if cut[k] != 0.0 {
                l[k].sqr()
            } else {
                Hull::new(a[k], i[k])
            }
        }))
    }
    fn powi(&self, n: i32) -> Self {
        match n {
            2 => self.sqr(),
            _ => self.lanewise(|l| l.powi(n)),
        }
    }
    fn sqrt(&self) -> Self {
        self.lanewise(Hull::sqrt)
    }
    /// The squares and their sum in lanes, the rest lane by lane (the scalar `hypot`
    /// from that sum).
    fn hypot(&self, other: &Self) -> Self {
        let s = (self.sqr() + other.sqr()).unpack();
        let own = self.affine.hypot(&other.affine).unpack();
        let (a, b) = (self.unpack(), other.unpack());
        Self::pack(core::array::from_fn(|k| {
            a[k].hypot_of_sum(&b[k], s[k], own[k])
        }))
    }
    fn recip(&self) -> Self {
        self.lanewise(Hull::recip)
    }
    fn exp(&self) -> Self {
        self.lanewise(Hull::exp)
    }
    fn ln(&self) -> Self {
        self.lanewise(Hull::ln)
    }
    fn sin(&self) -> Self {
        self.lanewise(Hull::sin)
    }
    fn cos(&self) -> Self {
        self.lanewise(Hull::cos)
    }
    fn abs(&self) -> Self {
        self.lanewise(Hull::abs)
    }
    fn min(&self, other: &Self) -> Self {
        self.lanewise2(other, Hull::min)
    }
    fn max(&self, other: &Self) -> Self {
        self.lanewise2(other, Hull::max)
    }
    fn rdiv(self, c: f64) -> Self {
        self.lanewise(|a| a.rdiv(c))
    }
}
