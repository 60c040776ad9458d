//! # arith-hull: revised affine forms that carry an interval hull
//!
//! [`Hull<N>`] is a revised affine form ([`arith_revaa::RevAa<N>`]) together with an
//! [`arith_ia::Interval`], both sound enclosures of the same real value. Its
//! [`Range::bounds`] are their intersection, so a result is never wider than the
//! interval part, and the affine part keeps the correlations that intervals lose.
//!
//! The two parts help each other where either alone fails:
//!
//! - **Half-lines.** An affine form cannot hold `[0.49, inf)`: one unbounded operand makes
//!   it the whole line. The interval part keeps the half-line through `max`, `min`,
//!   `exp`, `ln`, `recip` and `sqrt`, and as soon as the interval is bounded again the
//!   affine part is rebuilt from it (a fresh error term), so
//!   `exp(-30*max(1 - x, 1/(x - 0.5))) - 0.5` over `x ∈ [0.49, 0.51]` stays bounded below 0.
//! - **Domain edges.** `ln((...)^2 + 0.5)`: the affine range of the argument may dip below
//!   0 though the argument is at least 0.5. Each non-affine operation fits its
//!   approximation on the intersection of the operand's affine range and its interval.
//! - **Dependency.** `x - x`, products of correlated factors and long polynomials are the
//!   affine part's; the intersection takes whichever is tighter per value.
//!
//! # Soundness of fitting on the intersection
//!
//! For every point `p` of the inputs, the real value `x(p)` lies in the affine part's
//! range `[A, B]` and in the interval `[c, d]` (both parts are sound), so in
//! `[a, b] = [A, B] ∩ [c, d]`. An approximation `f(t) ∈ alpha*t + zeta ± delta` valid for
//! every `t ∈ [a, b]` (from [`arith_core::approx`], the one source every arithmetic uses)
//! therefore holds at `t = x(p)`; and the affine form stands for `x(p)` at that point's
//! symbol values, so `alpha * form + zeta ± delta` (with its rounding errors in the error
//! term, [`arith_core::reduced::Reduced::apply`]) encloses `f(x(p))`. The form may take
//! values outside `[a, b]` at other symbol values; those are not values of `x`, and the
//! result keeps its meaning only through the values that are.
//!
//! An empty intersection cannot come from two sound enclosures of a value that exists:
//! only from rounding at their touching ends. The operations then use the union of the
//! two ranges instead, which holds the value whatever went wrong.
//!
//! Each operation fits on the intersection where it leaves out more than a quarter of the
//! affine range (a narrower cut changes the fit by little and costs a second one); there
//! it also computes revised affine arithmetic's own result (fitted on the affine range)
//! and keeps the one of smaller radius (both are sound), so the affine part does not
//! widen through a steep fit extrapolated over a wide form. Elsewhere the affine part is
//! revised affine arithmetic's own result.
//!
//! ```
//! use arith_core::{Range, Real};
//! use arith_hull::Hull;
//!
//! let x = Hull::<1>::input(0, 0.49, 0.51);
//! let f = (-((x.rsub(1.0)).max(&(x - 0.5).recip()) * 30.0)).exp() - 0.5;
//! let (lo, hi) = f.bounds();
//! assert!(lo >= -0.5 && hi < 0.0, "[{lo}, {hi}]");
//! // The affine part alone is the whole line here; intervals alone agree with the hull.
//! let y = arith_revaa::RevAa::<1>::input(0, 0.49, 0.51);
//! let g = (-((y.rsub(1.0)).max(&(y - 0.5).recip()) * 30.0)).exp() - 0.5;
//! assert_eq!(g.bounds(), (f64::NEG_INFINITY, f64::INFINITY));
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

use arith_core::approx::{self, Approx};
use arith_core::{AffinePart, Arithmetic, Known, Range, Real};
use arith_ia::Interval;
use arith_revaa::RevAa;
use core::ops::{Add, Div, Mul, Neg, Sub};

mod pack;
pub use pack::HullX4;

/// A revised affine form with `N` input symbols and an interval hull of the same value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hull<const N: usize> {
    /// The affine part (the whole line when it knows nothing).
    pub affine: RevAa<N>,
    /// The interval part.
    pub interval: Interval,
}

/// The hull arithmetic as a family: one symbol on a ray, three in a cell.
#[derive(Clone, Copy, Debug, Default)]
pub struct HullArith;

impl Arithmetic for HullArith {
    const NAME: &'static str = "hull";
    const LABEL: &'static str = "Hull";
    type Ray = Hull<1>;
    type Cell = Hull<3>;
    type RayPack = HullX4<1>;
    type CellPack = HullX4<3>;
}

/// `[a, b] ∩ [c, d]`, or their union where rounding made them disjoint.
#[inline(always)]
fn meet((al, ah): (f64, f64), i: &Interval) -> (f64, f64) {
    let lo = al.max(i.lo);
    let hi = ah.min(i.hi);
    if lo <= hi {
        (lo, hi)
    } else {
        (al.min(i.lo), ah.max(i.hi))
    }
}

impl<const N: usize> Hull<N> {
    /// The pair as it is, except that an affine part that knows nothing is rebuilt from a
    /// bounded interval part (a fresh error term): affine forms cannot hold a half-line,
    /// so this is where they come back once the interval closes.
    #[inline(always)]
    pub fn new(affine: RevAa<N>, interval: Interval) -> Self {
        if affine.e.is_finite() && affine.x0.is_finite() {
            Hull { affine, interval }
        } else if interval.lo.is_finite() && interval.hi.is_finite() {
            Hull {
                affine: RevAa::from_interval(interval.lo, interval.hi),
                interval,
            }
        } else {
            Hull {
                affine: RevAa::UNBOUNDED,
                interval,
            }
        }
    }

    /// The pair with its interval part cut to the range both parts agree on: what a
    /// decided `min` or `max` passes on, so that its interval part stays within plain
    /// intervals' result, which takes the other operand's bounds where their intervals
    /// overlap.
    #[inline(always)]
    fn narrowed(&self) -> Self {
        let ((lo, hi), _) = self.ranges();
        Hull {
            affine: self.affine,
            interval: Interval::new(lo, hi),
        }
    }

    /// The range both parts agree on (see [`meet`]) and the affine part's own.
    #[inline(always)]
    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let own = self.affine.bounds();
        (meet(own, &self.interval), own)
    }

    /// A non-affine operation: the interval part is `ia` of the intersection; the affine
    /// part is revised affine arithmetic's own result (`own`) where the intersection is
    /// the affine range, else the narrower of `own` and the shared approximation `fit` on
    /// the intersection (the crate doc's argument).
    #[inline(always)]
    fn unary(
        &self,
        own: impl FnOnce(&RevAa<N>) -> RevAa<N>,
        fit: impl FnOnce(f64, f64) -> Approx,
        ia: impl FnOnce(&Interval) -> Interval,
    ) -> Self {
        let ((lo, hi), (al, ah)) = self.ranges();
        let interval = ia(&Interval::new(lo, hi));
        let affine = if !(al.is_finite() && ah.is_finite()) {
            // Nothing to fit: `new` rebuilds the form from a bounded interval.
            RevAa::UNBOUNDED
        } else if cuts_a_quarter((lo, hi), (al, ah)) {
            narrower(own(&self.affine), self.affine.apply(fit(lo, hi)))
        } else {
            own(&self.affine)
        };
        Self::new(affine, interval)
    }

    /// [`Real::hypot`] from the squares' sum `s = x.sqr() + y.sqr()` and revised affine
    /// arithmetic's fused `hypot` of the affine parts, `own` (the SIMD pack forms both in
    /// lanes).
    #[inline(always)]
    fn hypot_of_sum(&self, other: &Self, s: Self, own: RevAa<N>) -> Self {
        let ((xl, xh), _) = self.ranges();
        let ((yl, yh), _) = other.ranges();
        let floor = approx::sum_sq_floor((xl, xh), (yl, yh));
        let ((lo, hi), (al, ah)) = s.ranges();
        // A floor above the upper bound can only come from rounding: then no cut.
        let lo = if floor <= hi { lo.max(floor) } else { lo };
        let interval = Interval::new(lo, hi).sqrt();
        let affine = if al.is_finite() && ah.is_finite() && cuts_a_quarter((lo, hi), (al, ah)) {
            narrower(own, s.affine.apply(approx::sqrt(lo, hi)))
        } else {
            own
        };
        Self::new(affine, interval)
    }
}

/// Whether the intersection `m` leaves out more than a quarter of the affine range `a`:
/// only then is a second fit worth its cost (a fit on a range a few ulps narrower, as
/// every input's interval is against its form's rounded range, gives the same form).
#[inline(always)]
fn cuts_a_quarter(m: (f64, f64), a: (f64, f64)) -> bool {
    (m.0 - a.0) + (a.1 - m.1) > 0.25 * (a.1 - a.0)
}

/// The form of smaller radius (the first on a tie or NaN).
#[inline(always)]
fn narrower<const N: usize>(a: RevAa<N>, b: RevAa<N>) -> RevAa<N> {
    if b.rad_dir() < a.rad_dir() {
        b
    } else {
        a
    }
}

impl<const N: usize> Add for Hull<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, y: Self) -> Self {
        Self::new(self.affine + y.affine, self.interval + y.interval)
    }
}

impl<const N: usize> Sub for Hull<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, y: Self) -> Self {
        Self::new(self.affine - y.affine, self.interval - y.interval)
    }
}

impl<const N: usize> Mul for Hull<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, y: Self) -> Self {
        Self::new(self.affine * y.affine, self.interval * y.interval)
    }
}

impl<const N: usize> Div for Hull<N> {
    type Output = Self;
    /// `x * recip(y)` in the affine part, `x / y` in the interval part.
    #[inline(always)]
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, y: Self) -> Self {
        let r = y.recip();
        let (ym, _) = y.ranges();
        Self::new(
            self.affine * r.affine,
            self.interval / Interval::new(ym.0, ym.1),
        )
    }
}

impl<const N: usize> Neg for Hull<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Hull {
            affine: -self.affine,
            interval: -self.interval,
        }
    }
}

macro_rules! with_f64 {
    ($tr:ident, $f:ident) => {
        impl<const N: usize> $tr<f64> for Hull<N> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, c: f64) -> Self {
                Self::new(self.affine.$f(c), self.interval.$f(c))
            }
        }
    };
}
with_f64!(Add, add);
with_f64!(Sub, sub);
with_f64!(Mul, mul);
with_f64!(Div, div);

arith_core::impl_f64_lhs_ops!(<const N: usize> Hull<N>);

impl<const N: usize> Real for Hull<N> {
    fn known(&self) -> Known {
        let (lo, hi) = self.bounds();
        Known::Range(lo, hi)
    }
    fn from_bounds(lo: f64, hi: f64) -> Option<Self> {
        Some(<Self as Range>::from_interval(lo, hi))
    }
    fn constant(c: f64) -> Self {
        Self::new(RevAa::constant(c), Interval::constant(c))
    }

    /// `c * recip(x)` in the affine part, `c / x` (one rounding) in the interval part.
    fn rdiv(self, c: f64) -> Self {
        let ((lo, hi), _) = self.ranges();
        Self::new(
            self.recip().affine * c,
            Interval::point(c) / Interval::new(lo, hi),
        )
    }

    fn sqr(&self) -> Self {
        self.unary(RevAa::sqr, approx::sqr, Interval::sqr)
    }

    fn powi(&self, n: i32) -> Self {
        match n {
            0 => Self::constant(1.0),
            1 => *self,
            2 => self.sqr(),
            n if n > 2 => self.unary(
                |a| a.powi(n),
                |lo, hi| approx::powi(lo, hi, n),
                |i| i.powi(n),
            ),
            n => match n.checked_neg() {
                Some(m) => {
                    // The interval part also straight from the intersection, where even
                    // negative powers keep their sign (`recip` of the power reaching 0 is
                    // the whole line).
                    let ((lo, hi), _) = self.ranges();
                    let r = self.powi(m).recip();
                    let i = Interval::new(lo, hi).powi(n);
                    Self::new(r.affine, meet_intervals(r.interval, i))
                }
                None => Self::new(RevAa::UNBOUNDED, Interval::ENTIRE),
            },
        }
    }

    fn sqrt(&self) -> Self {
        self.unary(RevAa::sqrt, approx::sqrt, Interval::sqrt)
    }

    /// The squares' sum in both parts, then `sqrt` on its intersection cut at the floor
    /// `mig(x)^2 + mig(y)^2` of the operands' intersections
    /// ([`approx::sum_sq_floor`]); revised affine arithmetic's fused `hypot` is the
    /// affine candidate it is compared with.
    fn hypot(&self, other: &Self) -> Self {
        let s = self.sqr() + other.sqr();
        self.hypot_of_sum(other, s, self.affine.hypot(&other.affine))
    }

    fn recip(&self) -> Self {
        self.unary(RevAa::recip, approx::recip, Interval::recip)
    }

    fn exp(&self) -> Self {
        self.unary(RevAa::exp, approx::exp, Interval::exp)
    }

    fn ln(&self) -> Self {
        self.unary(RevAa::ln, approx::ln, Interval::ln)
    }

    fn sin(&self) -> Self {
        self.unary(RevAa::sin, approx::sin, Interval::sin)
    }

    fn cos(&self) -> Self {
        self.unary(RevAa::cos, approx::cos, Interval::cos)
    }

    /// Exact (`x` or `-x`) where the intersection has a sign, else as any non-affine
    /// operation.
    fn abs(&self) -> Self {
        let ((lo, hi), _) = self.ranges();
        if lo >= 0.0 {
            Hull {
                affine: self.affine,
                interval: Interval::new(lo, hi),
            }
        } else if hi <= 0.0 {
            Hull {
                affine: -self.affine,
                interval: Interval::new(-hi, -lo),
            }
        } else {
            self.unary(RevAa::abs, approx::abs, Interval::abs)
        }
    }

    /// The lower operand (its interval part cut to its range) when the ranges do not
    /// overlap; else `(x+y)/2 - |x-y|/2` in the affine part and the interval minimum of
    /// the intersections.
    fn min(&self, other: &Self) -> Self {
        let ((xl, xh), _) = self.ranges();
        let ((yl, yh), _) = other.ranges();
        if xh <= yl {
            self.narrowed()
        } else if yh <= xl {
            other.narrowed()
        } else {
            let d = (*self - *other).abs();
            let affine = ((self.affine + other.affine) - d.affine) * 0.5;
            let interval = Interval::new(xl, xh).min(&Interval::new(yl, yh));
            Self::new(affine, interval)
        }
    }

    /// The higher operand (its interval part cut to its range) when the ranges do not
    /// overlap; else `(x+y)/2 + |x-y|/2` in the affine part and the interval maximum of
    /// the intersections.
    fn max(&self, other: &Self) -> Self {
        let ((xl, xh), _) = self.ranges();
        let ((yl, yh), _) = other.ranges();
        if xh <= yl {
            other.narrowed()
        } else if yh <= xl {
            self.narrowed()
        } else {
            let d = (*self - *other).abs();
            let affine = ((self.affine + other.affine) + d.affine) * 0.5;
            let interval = Interval::new(xl, xh).max(&Interval::new(yl, yh));
            Self::new(affine, interval)
        }
    }
}

/// `a ∩ b` of two enclosures of one value (their union where rounding made them
/// disjoint).
fn meet_intervals(a: Interval, b: Interval) -> Interval {
    let (lo, hi) = meet((a.lo, a.hi), &b);
    Interval::new(lo, hi)
}

impl<const N: usize> Range for Hull<N> {
    const NAME: &'static str = HullArith::NAME;
    const INPUTS: usize = N;

    fn input(i: usize, lo: f64, hi: f64) -> Self {
        Self::new(RevAa::input(i, lo, hi), Interval::input(i, lo, hi))
    }

    fn from_interval(lo: f64, hi: f64) -> Self {
        Self::new(RevAa::from_interval(lo, hi), Interval::new(lo, hi))
    }

    fn from_affine(c0: f64, cs: &[f64], err: f64) -> Self {
        let affine = RevAa::from_affine(c0, cs, err);
        let (lo, hi) = affine.bounds();
        Self::new(affine, Interval::new(lo, hi))
    }

    fn bounds(&self) -> (f64, f64) {
        self.ranges().0
    }

    fn affine_part<const K: usize>(&self) -> Option<AffinePart<K>> {
        self.affine.affine_part()
    }

    fn bounds_at_inputs(&self, eps: &[f64]) -> (f64, f64) {
        meet(self.affine.bounds_at_inputs(eps), &self.interval)
    }
}
