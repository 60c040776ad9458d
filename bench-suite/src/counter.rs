//! Operation counting: a [`Real`] that evaluates in `f64` and counts every operation a
//! model performs, so the paper's "Number of operations: All / Non-affine /
//! Multiplications" column comes from running the real model code, not from typing it in.
//!
//! # What counts as what
//!
//! Every call of a [`Real`] operation on a [`Counter`] is one operation in **All**:
//! `+ - * /` (with a `Counter` or an `f64` on either side), unary `-`, `sqr`, `powi`,
//! `sqrt`, `recip`, `exp`, `ln`, `sin`, `cos`, `abs`, `min`, `max`, `rsub`, `rdiv`.
//! Making a constant ([`Real::constant`]) and cloning are free.
//!
//! **Non-affine** are the operations an affine arithmetic cannot do exactly, i.e. the
//! ones that create a new noise symbol (AA) or error term (RAA, RevAA):
//! `Counter * Counter`, `Counter / Counter`, `sqr`, `powi`, `sqrt`, `recip`, `exp`, `ln`,
//! `sin`, `cos`, `abs`, `min`, `max`, and `f64 / Counter` (`rdiv`). Operations with an
//! `f64` constant (`x * 2.0`, `x + 1.0`, `x / 4.0`, `1.0 - x`) and `+`, `-`, negation of
//! two ranges are affine.
//!
//! **Multiplications** are the non-affine multiplications: `Counter * Counter`, `sqr`
//! and `powi` (each `powi` counts as one, as the arithmetics evaluate it as one
//! non-affine operation). Division is not counted as a multiplication. This matches the
//! paper's algebraic rows, where Non-affine = Multiplications (Mitchell 6 / 6: three
//! squares, two squares of sums and one product), and its CSG row, where the 8 square
//! roots of the R-functions are the difference 40 − 32.
//!
//! A counter is a point ([`Real::known`]), so a formula tape's comparisons and `if`
//! selections decide at once; they call no counted operation and count 0 (the
//! arithmetic computing their operands counts as usual), and a tape evaluates both
//! branches of an `if`, so both count.
//!
//! Counting is per thread: [`count_ops`] resets the calling thread's counters, runs the
//! closure and returns what it did.

use arith_core::Real;
use core::ops::{Add, Div, Mul, Neg, Sub};
use std::cell::Cell;

/// Operation counts of one evaluation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OpCounts {
    /// Every operation.
    pub all: u64,
    /// Operations that are non-affine in affine arithmetic.
    pub non_affine: u64,
    /// Non-affine multiplications (`x * y`, `sqr`, `powi`).
    pub mul: u64,
}

impl core::fmt::Display for OpCounts {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{} / {} / {}", self.all, self.non_affine, self.mul)
    }
}

thread_local! {
    static COUNTS: Cell<OpCounts> = const { Cell::new(OpCounts { all: 0, non_affine: 0, mul: 0 }) };
}

/// The kind of one operation, for the counters.
#[derive(Clone, Copy)]
enum Kind {
    Affine,
    NonAffine,
    Mul,
}

fn tick(kind: Kind) {
    COUNTS.with(|c| {
        let mut v = c.get();
        v.all += 1;
        match kind {
            Kind::Affine => {}
            Kind::NonAffine => v.non_affine += 1,
            Kind::Mul => {
                v.non_affine += 1;
                v.mul += 1;
            }
        }
        c.set(v);
    });
}

/// Resets this thread's counters, runs `f`, and returns its result with the counts of
/// the [`Counter`] operations it performed on this thread.
pub fn count_ops<T>(f: impl FnOnce() -> T) -> (T, OpCounts) {
    COUNTS.with(|c| c.set(OpCounts::default()));
    let out = f();
    let counts = COUNTS.with(|c| c.get());
    (out, counts)
}

/// An `f64` that counts the operations done on it (see the module docs for the rules).
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub struct Counter(pub f64);

macro_rules! binop {
    ($tr:ident, $m:ident, $op:tt, $kind_self:expr, $kind_f64:expr) => {
        impl $tr for Counter {
            type Output = Counter;
            fn $m(self, rhs: Counter) -> Counter {
                tick($kind_self);
                Counter(self.0 $op rhs.0)
            }
        }
        impl $tr<f64> for Counter {
            type Output = Counter;
            fn $m(self, rhs: f64) -> Counter {
                tick($kind_f64);
                Counter(self.0 $op rhs)
            }
        }
    };
}

binop!(Add, add, +, Kind::Affine, Kind::Affine);
binop!(Sub, sub, -, Kind::Affine, Kind::Affine);
binop!(Mul, mul, *, Kind::Mul, Kind::Affine);
binop!(Div, div, /, Kind::NonAffine, Kind::Affine);

impl Neg for Counter {
    type Output = Counter;
    fn neg(self) -> Counter {
        tick(Kind::Affine);
        Counter(-self.0)
    }
}

arith_core::impl_f64_lhs_ops!(Counter);

impl Real for Counter {
    fn constant(c: f64) -> Self {
        Counter(c)
    }
    fn sqr(&self) -> Self {
        tick(Kind::Mul);
        Counter(self.0 * self.0)
    }
    fn powi(&self, n: i32) -> Self {
        tick(Kind::Mul);
        Counter(self.0.powi(n))
    }
    fn sqrt(&self) -> Self {
        tick(Kind::NonAffine);
        Counter(Real::sqrt(&self.0))
    }
    fn recip(&self) -> Self {
        tick(Kind::NonAffine);
        Counter(1.0 / self.0)
    }
    fn exp(&self) -> Self {
        tick(Kind::NonAffine);
        Counter(self.0.exp())
    }
    fn ln(&self) -> Self {
        tick(Kind::NonAffine);
        Counter(Real::ln(&self.0))
    }
    fn sin(&self) -> Self {
        tick(Kind::NonAffine);
        Counter(self.0.sin())
    }
    fn cos(&self) -> Self {
        tick(Kind::NonAffine);
        Counter(self.0.cos())
    }
    fn abs(&self) -> Self {
        tick(Kind::NonAffine);
        Counter(self.0.abs())
    }
    fn min(&self, other: &Self) -> Self {
        tick(Kind::NonAffine);
        Counter(self.0.min(other.0))
    }
    fn max(&self, other: &Self) -> Self {
        tick(Kind::NonAffine);
        Counter(self.0.max(other.0))
    }
    /// `c - x` is one affine operation (not a negation plus an addition).
    fn rsub(self, c: f64) -> Self {
        tick(Kind::Affine);
        Counter(c - self.0)
    }
    /// `c / x` is one non-affine operation (a scaled reciprocal).
    fn rdiv(self, c: f64) -> Self {
        tick(Kind::NonAffine);
        Counter(c / self.0)
    }
    /// A counter evaluates at a point: conditionals pick their branch, noise its value.
    fn known(&self) -> arith_core::Known {
        arith_core::Known::Point(self.0)
    }
}
