//! The shared test kit must catch unsound arithmetics: deliberately broken variants of
//! `Interval` ("mutants") are run through the kit's checks, which must fail.

use arith_core::testkit::{checks, Bin};
use arith_core::{Linear, Range, Real};
use arith_ia::Interval;
use core::ops::{Add, Div, Mul, Neg, Sub};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// `Interval` with one operation broken, selected by `M`:
/// 1: `+` rounds to nearest (no outward rounding);
/// 2: `sqr` is `[lo^2, hi^2]` sorted (wrong across 0);
/// 3: `exp` is plain libm `exp` at both ends, unwidened;
/// 4: `sin` uses the end values only (misses interior extrema);
/// 5: `linear_part` claims the midpoint with no error (`f1 = e = 0`).
#[derive(Clone, Copy, Debug)]
struct Mutant<const M: u8>(Interval);

impl<const M: u8> Add for Mutant<M> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        if M == 1 {
            Mutant(Interval::new(self.0.lo + o.0.lo, self.0.hi + o.0.hi))
        } else {
            Mutant(self.0 + o.0)
        }
    }
}
impl<const M: u8> Sub for Mutant<M> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        self + (-o)
    }
}
impl<const M: u8> Mul for Mutant<M> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Mutant(self.0 * o.0)
    }
}
impl<const M: u8> Div for Mutant<M> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        Mutant(self.0 / o.0)
    }
}
impl<const M: u8> Neg for Mutant<M> {
    type Output = Self;
    fn neg(self) -> Self {
        Mutant(-self.0)
    }
}
impl<const M: u8> Add<f64> for Mutant<M> {
    type Output = Self;
    fn add(self, c: f64) -> Self {
        self + Mutant(Interval::point(c))
    }
}
impl<const M: u8> Sub<f64> for Mutant<M> {
    type Output = Self;
    fn sub(self, c: f64) -> Self {
        self + Mutant(Interval::point(-c))
    }
}
impl<const M: u8> Mul<f64> for Mutant<M> {
    type Output = Self;
    fn mul(self, c: f64) -> Self {
        Mutant(self.0 * c)
    }
}
impl<const M: u8> Div<f64> for Mutant<M> {
    type Output = Self;
    fn div(self, c: f64) -> Self {
        Mutant(self.0 / c)
    }
}

impl<const M: u8> Real for Mutant<M> {
    fn constant(c: f64) -> Self {
        Mutant(Interval::constant(c))
    }
    fn sqr(&self) -> Self {
        if M == 2 {
            let (a, b) = (self.0.lo * self.0.lo, self.0.hi * self.0.hi);
            Mutant(Interval::new(a.min(b), a.max(b).next_up()))
        } else {
            Mutant(self.0.sqr())
        }
    }
    fn powi(&self, n: i32) -> Self {
        Mutant(self.0.powi(n))
    }
    fn sqrt(&self) -> Self {
        Mutant(self.0.sqrt())
    }
    fn recip(&self) -> Self {
        Mutant(self.0.recip())
    }
    fn exp(&self) -> Self {
        if M == 3 {
            Mutant(Interval::new(self.0.lo.exp(), self.0.hi.exp()))
        } else {
            Mutant(self.0.exp())
        }
    }
    fn ln(&self) -> Self {
        Mutant(self.0.ln())
    }
    fn sin(&self) -> Self {
        if M == 4 {
            let (a, b) = (self.0.lo.sin(), self.0.hi.sin());
            Mutant(Interval::new(a.min(b).next_down(), a.max(b).next_up()))
        } else {
            Mutant(self.0.sin())
        }
    }
    fn cos(&self) -> Self {
        Mutant(self.0.cos())
    }
    fn abs(&self) -> Self {
        Mutant(self.0.abs())
    }
    fn min(&self, o: &Self) -> Self {
        Mutant(self.0.min(&o.0))
    }
    fn max(&self, o: &Self) -> Self {
        Mutant(self.0.max(&o.0))
    }
}

impl<const M: u8> Range for Mutant<M> {
    const NAME: &'static str = "mutant";
    const INPUTS: usize = usize::MAX;
    fn input(i: usize, lo: f64, hi: f64) -> Self {
        Mutant(Interval::input(i, lo, hi))
    }
    fn from_interval(lo: f64, hi: f64) -> Self {
        Mutant(Interval::from_interval(lo, hi))
    }
    fn bounds(&self) -> (f64, f64) {
        self.0.bounds()
    }
    fn linear_part(&self) -> Option<Linear> {
        let (lo, hi) = self.0.bounds();
        (M == 5 && lo.is_finite() && hi.is_finite() && lo < hi).then_some(Linear {
            f0: lo * 0.5 + hi * 0.5,
            f1: 0.0,
            e: 0.0,
        })
    }
}

/// Whether `f` panics with a message containing `why` (so a mutant fails for the
/// right reason, not, say, because its run was vacuous).
fn fails_with(why: &str, f: impl FnOnce()) -> bool {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(()) => false,
        Err(e) => {
            let msg = e
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            msg.contains(why)
        }
    }
}

fn fails(f: impl FnOnce()) -> bool {
    fails_with("UNSOUND", f)
}

#[test]
fn missing_outward_rounding_is_caught() {
    assert!(fails(|| checks::check_binary_op::<Mutant<1>>(
        Bin::Add,
        256
    )));
    assert!(fails(|| checks::check_random_trees::<Mutant<1>>(512)));
    // The unbroken operations of the same mutant pass.
    checks::check_binary_op::<Mutant<1>>(Bin::Mul, 64);
}

#[test]
fn wrong_sqr_across_zero_is_caught() {
    assert!(fails(|| checks::check_unary_named::<Mutant<2>>("sqr", 256)));
}

#[test]
fn unwidened_libm_exp_is_caught() {
    assert!(fails(|| checks::check_unary_named::<Mutant<3>>("exp", 256)));
}

#[test]
fn missed_sine_extrema_are_caught() {
    assert!(fails(|| checks::check_unary_named::<Mutant<4>>("sin", 256)));
}

#[test]
fn false_linear_part_is_caught() {
    assert!(fails(|| checks::check_linear_part::<Mutant<5>>(256)));
}

#[test]
fn intervals_are_not_affine() {
    // x - x is not [0, 0] in interval arithmetic: the correlation check must say so.
    assert!(fails_with(
        "x - x",
        || checks::check_correlation::<Interval>(64)
    ));
    // Joint inclusion holds trivially for intervals (bounds_at_inputs = bounds).
    checks::check_joint_inclusion::<Interval>(64);
}
