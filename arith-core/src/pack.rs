//! Four forms evaluated together.
//!
//! A renderer traces many rays (and tests many cells) through the same model; one
//! evaluation of the model over a [`Pack`] computes the ranges of four rays' segments
//! (or four cells' slices) at once. An arithmetic whose forms fit SIMD registers
//! implements [`Pack`] with vector instructions, lane for lane the same operations as its
//! scalar form (so each lane is bit for bit the scalar result, NaN signs and payloads
//! aside, and inherits its soundness): the reduced affine forms share
//! `simd::ReducedX4` (feature `simd`). Every other arithmetic uses [`Lanes`], which
//! applies the scalar operations lane by lane.
//!
//! A model evaluated over a pack must use the [`Real`] operations only: code that looks
//! at the concrete type of its arguments does not know the pack types (the tracer asks
//! such a shape whether it packs).

use crate::{Range, Real};
use core::ops::{Add, Div, Mul, Neg, Sub};

/// Number of lanes of a [`Pack`].
pub const LANES: usize = 4;

/// Four forms of one [`Range`] type evaluated together, each lane exactly as the scalar
/// form would be.
pub trait Pack: Real {
    /// The scalar form of one lane.
    type Lane: Range;
    /// Four lane forms as one pack, lane `k` from `lanes[k]`.
    fn pack(lanes: [Self::Lane; LANES]) -> Self;
    /// The four lane forms.
    fn unpack(self) -> [Self::Lane; LANES];
    /// `self * m + c` with `m[k]` and `c[k]` in lane `k` (a ray's direction and origin
    /// component): each lane exactly the scalar `lane * m[k] + c[k]`.
    fn mul_add_lanes(self, m: [f64; LANES], c: [f64; LANES]) -> Self {
        let l = self.unpack();
        Self::pack(core::array::from_fn(|k| l[k].clone() * m[k] + c[k]))
    }
}

/// The lane-by-lane [`Pack`] of any [`Range`]: no speed-up, the same results.
#[derive(Clone, Debug, PartialEq)]
pub struct Lanes<R>(pub [R; LANES]);

impl<R: Range> Lanes<R> {
    #[inline(always)]
    fn map(&self, f: impl Fn(&R) -> R) -> Self {
        Lanes(core::array::from_fn(|k| f(&self.0[k])))
    }
    #[inline(always)]
    fn zip(&self, o: &Self, f: impl Fn(&R, &R) -> R) -> Self {
        Lanes(core::array::from_fn(|k| f(&self.0[k], &o.0[k])))
    }
}

impl<R: Range> Pack for Lanes<R> {
    type Lane = R;
    fn pack(lanes: [R; LANES]) -> Self {
        Lanes(lanes)
    }
    fn unpack(self) -> [R; LANES] {
        self.0
    }
}

macro_rules! lanes_binary {
    ($tr:ident, $f:ident) => {
        impl<R: Range> $tr for Lanes<R> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                self.zip(&o, |a, b| a.clone().$f(b.clone()))
            }
        }
        impl<R: Range> $tr<f64> for Lanes<R> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, c: f64) -> Self {
                self.map(|a| a.clone().$f(c))
            }
        }
    };
}
lanes_binary!(Add, add);
lanes_binary!(Sub, sub);
lanes_binary!(Mul, mul);
lanes_binary!(Div, div);

impl<R: Range> Neg for Lanes<R> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|a| -a.clone())
    }
}

impl<R: Range> Real for Lanes<R> {
    fn constant(c: f64) -> Self {
        Lanes(core::array::from_fn(|_| R::constant(c)))
    }
    fn sqr(&self) -> Self {
        self.map(R::sqr)
    }
    fn powi(&self, n: i32) -> Self {
        self.map(|a| a.powi(n))
    }
    fn sqrt(&self) -> Self {
        self.map(R::sqrt)
    }
    fn hypot(&self, other: &Self) -> Self {
        self.zip(other, R::hypot)
    }
    fn recip(&self) -> Self {
        self.map(R::recip)
    }
    fn exp(&self) -> Self {
        self.map(R::exp)
    }
    fn ln(&self) -> Self {
        self.map(R::ln)
    }
    fn sin(&self) -> Self {
        self.map(R::sin)
    }
    fn cos(&self) -> Self {
        self.map(R::cos)
    }
    fn abs(&self) -> Self {
        self.map(R::abs)
    }
    fn min(&self, other: &Self) -> Self {
        self.zip(other, R::min)
    }
    fn max(&self, other: &Self) -> Self {
        self.zip(other, R::max)
    }
    fn rsub(self, c: f64) -> Self {
        self.map(|a| a.clone().rsub(c))
    }
    fn rdiv(self, c: f64) -> Self {
        self.map(|a| a.clone().rdiv(c))
    }
}
