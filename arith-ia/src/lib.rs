//! # arith-ia: interval arithmetic with outward rounding
//!
//! [`Interval`] is the simplest sound [`Range`]: a pair of `f64` bounds `[lo, hi]`.
//! Every operation rounds to nearest and then widens by at most one ulp per bound, and
//! only when the operation was actually inexact (checked with error-free
//! transformations), so exact results such as `[1, 1] + [2, 2] = [3, 3]` stay tight. The
//! FPU rounding mode is never changed.
//!
//! Non-affine functions (`sqrt`, `exp`, `ln`, `sin`, `cos`) use the shared rigorous
//! enclosures [`arith_core::approx`]`::range_*`, so every arithmetic agrees on them.
//!
//! Interval arithmetic has no noise symbols: the same input used twice is treated as
//! two independent values (`x - x` over `[0, 1]` is `[-1, 1]`), which is the dependency
//! problem the affine arithmetics of this workspace address.
//!
//! ```
//! use arith_core::{Range, Real};
//! use arith_ia::Interval;
//!
//! let x = Interval::input(0, 1.0, 2.0);
//! let y = 2.0 * x.sqr() - x; // [2*1 - 2, 2*4 - 1] = [0, 7]
//! assert_eq!(y.bounds(), (0.0, 7.0));
//! // 0.1 + 0.2 is not a float: the result strictly brackets the real sum.
//! let s = Interval::constant(0.1) + Interval::constant(0.2);
//! assert!(s.lo < s.hi);
//! // Division by a range holding 0 is the whole line.
//! assert_eq!((x / Interval::new(-1.0, 1.0)).bounds(), (f64::NEG_INFINITY, f64::INFINITY));
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

use arith_core::{approx, Arithmetic, Range, Real};

mod pack;
use core::ops::{Add, Div, Mul, Neg, Sub};
pub use pack::IntervalX4;

use arith_core::round::{
    add_hi, add_lo, div_hi, div_lo, mul_hi, mul_lo, pow_hi_nonneg, pow_lo_nonneg,
};

/// A closed interval `[lo, hi]` of the extended reals.
///
/// Invariants kept by every constructor and operation: `lo <= hi` and neither bound is
/// NaN (NaN would make [`Range::contains_zero`] meaningless). `-inf`/`+inf` bounds mean
/// "unbounded"; an interval `[-inf, -inf]` is the value `ln(0)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
}

/// Interval arithmetic as an [`Arithmetic`]: rays and cells both use [`Interval`].
#[derive(Clone, Copy, Debug, Default)]
pub struct IaArith;

impl Arithmetic for IaArith {
    const NAME: &'static str = "ia";
    const LABEL: &'static str = "IA";
    type Ray = Interval;
    type Cell = Interval;
    type RayPack = IntervalX4;
    type CellPack = IntervalX4;
}

impl Interval {
    /// The whole line `(-inf, +inf)`.
    pub const ENTIRE: Interval = Interval {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    /// `[lo, hi]`, made safe for any input: a NaN bound gives the whole line and swapped
    /// bounds are put in order (both choices still enclose what the caller meant).
    pub fn new(lo: f64, hi: f64) -> Interval {
        if lo.is_nan() || hi.is_nan() {
            Interval::ENTIRE
        } else if lo <= hi {
            Interval { lo, hi }
        } else {
            Interval { lo: hi, hi: lo }
        }
    }

    /// The degenerate interval `[c, c]` (whole line for NaN).
    pub fn point(c: f64) -> Interval {
        Interval::new(c, c)
    }

    /// Builds from bounds computed by the directed helpers of [`arith_core::round`] (never
    /// NaN) or the shared range enclosures: a NaN lower bound would become `-inf` and a NaN
    /// upper bound `+inf`, so an undefined bound widens instead of poisoning.
    #[inline]
    fn from_dir(lo: f64, hi: f64) -> Interval {
        let lo = if lo.is_nan() { f64::NEG_INFINITY } else { lo };
        let hi = if hi.is_nan() { f64::INFINITY } else { hi };
        if lo <= hi {
            Interval { lo, hi }
        } else {
            // Cannot happen for sound lower/upper bounds of a non-empty set; widen to be safe.
            Interval { lo: hi, hi: lo }
        }
    }

    /// `hi - lo`, rounded up (`+inf` for unbounded intervals).
    pub fn width(&self) -> f64 {
        // `inf - inf` (an interval at one infinity) is undefined: `add_hi` gives `+inf`.
        add_hi(self.hi, -self.lo)
    }

    /// Whether `x` lies in `[lo, hi]`.
    pub fn contains(&self, x: f64) -> bool {
        self.lo <= x && x <= self.hi
    }

    /// Whether this is the whole line.
    pub fn is_entire(&self) -> bool {
        self.lo == f64::NEG_INFINITY && self.hi == f64::INFINITY
    }

    /// The interval between `f(lo)` and `f(hi)`, for a monotone `f` that is exact on
    /// both ends.
    fn map_ends(self, f: impl Fn(f64) -> f64) -> Interval {
        let (a, b) = (f(self.lo), f(self.hi));
        Interval::from_dir(a.min(b), a.max(b))
    }

    /// `self * c` for a point `c`.
    ///
    /// An infinite `c` (`[inf, inf]` holds no real number: it is a value such as `ln(0)`,
    /// never a rounded bound of a real) is taken as a number beyond every bound of its
    /// sign, so `0 * c` is `0`: the limit of `self * [M, M]` as `M` grows, which keeps
    /// the product within that of any half-line holding `c`. An exact `0` gives `[0, 0]`
    /// whatever `self` is: every number it holds is real, so none is `0 * inf`.
    fn mul_point(self, c: f64) -> Interval {
        if c.is_nan() {
            return Interval::ENTIRE;
        }
        if c == 0.0 {
            return Interval { lo: 0.0, hi: 0.0 };
        }
        if c.is_infinite() {
            return self.map_ends(|x| if x == 0.0 { 0.0 } else { x * c });
        }
        if c >= 0.0 {
            Interval::from_dir(mul_lo(self.lo, c), mul_hi(self.hi, c))
        } else {
            Interval::from_dir(mul_lo(self.hi, c), mul_hi(self.lo, c))
        }
    }

    /// `self / c` for a point `c`; the whole line when `c == 0`. An infinite `c` is taken
    /// as in [`Interval::mul_point`]: finite bounds go to `0`, infinite ones keep their
    /// sign times `c`'s.
    fn div_point(self, c: f64) -> Interval {
        if c.is_nan() || c == 0.0 {
            return Interval::ENTIRE;
        }
        if c.is_infinite() {
            return self.map_ends(|x| if x.is_infinite() { x * c.signum() } else { 0.0 });
        }
        if c > 0.0 {
            Interval::from_dir(div_lo(self.lo, c), div_hi(self.hi, c))
        } else {
            Interval::from_dir(div_lo(self.hi, c), div_hi(self.lo, c))
        }
    }

    /// The smallest and largest of `|x|` over the interval (`mig`, `mag`).
    fn mig_mag(&self) -> (f64, f64) {
        if self.lo >= 0.0 {
            (self.lo, self.hi)
        } else if self.hi <= 0.0 {
            (-self.hi, -self.lo)
        } else {
            (0.0, f64::max(-self.lo, self.hi))
        }
    }

    /// `x^n` for `n >= 1`.
    fn powi_pos(&self, n: u32) -> Interval {
        let (mig, mag) = self.mig_mag();
        if n & 1 == 0 {
            return Interval::from_dir(pow_lo_nonneg(mig, n), pow_hi_nonneg(mag, n));
        }
        // Odd power: increasing, and x^n = -(|x|^n) for x < 0.
        let lo = if self.lo >= 0.0 {
            pow_lo_nonneg(self.lo, n)
        } else {
            -pow_hi_nonneg(-self.lo, n)
        };
        let hi = if self.hi >= 0.0 {
            pow_hi_nonneg(self.hi, n)
        } else {
            -pow_lo_nonneg(-self.hi, n)
        };
        Interval::from_dir(lo, hi)
    }

    /// Wraps a `(lo, hi)` pair from [`arith_core::approx`].
    fn from_pair((lo, hi): (f64, f64)) -> Interval {
        Interval::from_dir(lo, hi)
    }
}

impl Add for Interval {
    type Output = Interval;
    fn add(self, rhs: Interval) -> Interval {
        Interval::from_dir(add_lo(self.lo, rhs.lo), add_hi(self.hi, rhs.hi))
    }
}

impl Sub for Interval {
    type Output = Interval;
    fn sub(self, rhs: Interval) -> Interval {
        self + (-rhs)
    }
}

impl Mul for Interval {
    type Output = Interval;
    fn mul(self, rhs: Interval) -> Interval {
        let (a, b) = (self, rhs);
        // Degenerate (point) factors are common (constants): one product per bound, an
        // infinite point first (see `mul_point`).
        if a.lo == a.hi && a.lo.is_infinite() {
            return b.mul_point(a.lo);
        }
        if b.lo == b.hi {
            return a.mul_point(b.lo);
        }
        if a.lo == a.hi {
            return b.mul_point(a.lo);
        }
        // By the signs of the factors, the products that are the exact minimum and
        // maximum (two of the four, both only when both factors straddle 0). For factors
        // that are not points none of them is `0 * inf`.
        let ((l1, l2), (h1, h2)) = if a.lo >= 0.0 {
            if b.lo >= 0.0 {
                ((a.lo, b.lo), (a.hi, b.hi))
            } else if b.hi <= 0.0 {
                ((a.hi, b.lo), (a.lo, b.hi))
            } else {
                ((a.hi, b.lo), (a.hi, b.hi))
            }
        } else if a.hi <= 0.0 {
            if b.lo >= 0.0 {
                ((a.lo, b.hi), (a.hi, b.lo))
            } else if b.hi <= 0.0 {
                ((a.hi, b.hi), (a.lo, b.lo))
            } else {
                ((a.lo, b.hi), (a.lo, b.lo))
            }
        } else if b.lo >= 0.0 {
            ((a.lo, b.hi), (a.hi, b.hi))
        } else if b.hi <= 0.0 {
            ((a.hi, b.lo), (a.lo, b.lo))
        } else {
            let lo = mul_lo(a.lo, b.hi).min(mul_lo(a.hi, b.lo));
            let hi = mul_hi(a.lo, b.lo).max(mul_hi(a.hi, b.hi));
            return Interval::from_dir(lo, hi);
        };
        Interval::from_dir(mul_lo(l1, l2), mul_hi(h1, h2))
    }
}

impl Div for Interval {
    type Output = Interval;
    fn div(self, rhs: Interval) -> Interval {
        let (a, b) = (self, rhs);
        if b.contains_zero() {
            return Interval::ENTIRE;
        }
        if b.lo == b.hi {
            return a.div_point(b.lo);
        }
        let lo = min4(
            div_lo(a.lo, b.lo),
            div_lo(a.lo, b.hi),
            div_lo(a.hi, b.lo),
            div_lo(a.hi, b.hi),
        );
        let hi = max4(
            div_hi(a.lo, b.lo),
            div_hi(a.lo, b.hi),
            div_hi(a.hi, b.lo),
            div_hi(a.hi, b.hi),
        );
        Interval::from_dir(lo, hi)
    }
}

impl Neg for Interval {
    type Output = Interval;
    fn neg(self) -> Interval {
        Interval {
            lo: -self.hi,
            hi: -self.lo,
        }
    }
}

impl Add<f64> for Interval {
    type Output = Interval;
    fn add(self, c: f64) -> Interval {
        self + Interval::point(c)
    }
}

impl Sub<f64> for Interval {
    type Output = Interval;
    fn sub(self, c: f64) -> Interval {
        self + Interval::point(-c)
    }
}

impl Mul<f64> for Interval {
    type Output = Interval;
    fn mul(self, c: f64) -> Interval {
        self.mul_point(c)
    }
}

impl Div<f64> for Interval {
    type Output = Interval;
    fn div(self, c: f64) -> Interval {
        self.div_point(c)
    }
}

arith_core::impl_f64_lhs_ops!(Interval);

/// The minimum of four bounds (never NaN: the directed helpers widen undefined bounds
/// to the infinite one on their side, and `f64::min` would silently drop a NaN).
#[inline]
fn min4(a: f64, b: f64, c: f64, d: f64) -> f64 {
    a.min(b).min(c.min(d))
}

/// The maximum of four bounds (never NaN, as in [`min4`]).
#[inline]
fn max4(a: f64, b: f64, c: f64, d: f64) -> f64 {
    a.max(b).max(c.max(d))
}

impl Real for Interval {
    fn known(&self) -> arith_core::Known {
        let (lo, hi) = self.bounds();
        arith_core::Known::Range(lo, hi)
    }
    fn from_bounds(lo: f64, hi: f64) -> Option<Self> {
        Some(<Self as Range>::from_interval(lo, hi))
    }
    fn constant(c: f64) -> Self {
        Interval::point(c)
    }

    fn sqr(&self) -> Self {
        self.powi_pos(2)
    }

    fn powi(&self, n: i32) -> Self {
        match n {
            0 => Interval::point(1.0),
            1 => *self,
            n if n > 0 => self.powi_pos(n.unsigned_abs()),
            n => {
                let p = self.powi_pos(n.unsigned_abs());
                if n & 1 == 0 && p.lo >= 0.0 && p.hi > 0.0 {
                    // x^-n for even n is positive wherever it is defined (x != 0): at most
                    // the lower bound survives when the power reaches 0.
                    Interval::from_dir(div_lo(1.0, p.hi), div_hi(1.0, p.lo))
                } else if n & 1 == 0 && p.lo >= 0.0 {
                    // x^-n of exactly 0 takes no real value; `[MAX, inf]` is the limit of
                    // `[1/h^n, inf)` as `h` shrinks, so a narrower operand never gives a
                    // wider result (the whole line here would, against `[0, h]`).
                    Interval {
                        lo: f64::MAX,
                        hi: f64::INFINITY,
                    }
                } else {
                    p.recip()
                }
            }
        }
    }

    fn sqrt(&self) -> Self {
        Interval::from_pair(approx::range_sqrt(self.lo, self.hi))
    }

    fn recip(&self) -> Self {
        if self.contains_zero() {
            return Interval::ENTIRE;
        }
        // 1/x is decreasing on each side of 0.
        Interval::from_dir(div_lo(1.0, self.hi), div_hi(1.0, self.lo))
    }

    fn exp(&self) -> Self {
        Interval::from_pair(approx::range_exp(self.lo, self.hi))
    }

    fn ln(&self) -> Self {
        Interval::from_pair(approx::range_ln(self.lo, self.hi))
    }

    fn sin(&self) -> Self {
        Interval::from_pair(approx::range_sin(self.lo, self.hi))
    }

    fn cos(&self) -> Self {
        Interval::from_pair(approx::range_cos(self.lo, self.hi))
    }

    fn abs(&self) -> Self {
        let (mig, mag) = self.mig_mag();
        Interval { lo: mig, hi: mag }
    }

    fn min(&self, other: &Self) -> Self {
        Interval {
            lo: self.lo.min(other.lo),
            hi: self.hi.min(other.hi),
        }
    }

    fn max(&self, other: &Self) -> Self {
        Interval {
            lo: self.lo.max(other.lo),
            hi: self.hi.max(other.hi),
        }
    }

    fn rsub(self, c: f64) -> Self {
        Interval::point(c) - self
    }

    fn rdiv(self, c: f64) -> Self {
        Interval::point(c) / self
    }
}

impl Range for Interval {
    const NAME: &'static str = "ia";
    /// Intervals have no symbols: any number of inputs is "supported" (none correlated).
    const INPUTS: usize = usize::MAX;

    fn input(_i: usize, lo: f64, hi: f64) -> Self {
        Interval::new(lo, hi)
    }

    fn from_interval(lo: f64, hi: f64) -> Self {
        Interval::new(lo, hi)
    }

    fn bounds(&self) -> (f64, f64) {
        (self.lo, self.hi)
    }
}
