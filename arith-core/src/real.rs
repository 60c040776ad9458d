//! The two traits every model and arithmetic is written against.

use crate::branch::Step;
use crate::lanes;
use core::fmt::Debug;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// The operations a model is written with.
///
/// Implemented by `f64` (point evaluation, plain IEEE round-to-nearest, no enclosure
/// guarantee) and by every [`Range`] (sound enclosures). Generic model code takes
/// `R: Real` and so serves points, every arithmetic and operation counting alike.
///
/// `f64` operands are accepted on the right of `+ - * /`; each concrete type also
/// implements them with `f64` on the left (`2.0 * x`), but generic code cannot name
/// those impls without extra bounds, so it writes `x * 2.0` or [`Real::rsub`].
pub trait Real:
    Sized
    + Clone
    + Debug
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
    /// The exact constant `c` (a degenerate range `[c, c]`).
    fn constant(c: f64) -> Self;
    /// `x^2`. Affine arithmetics implement it as one non-affine operation, never wider
    /// than `x * x`.
    fn sqr(&self) -> Self;
    /// `x^n` for an integer `n` (negative `n` means `recip(x^|n|)`, `x^0 = 1`).
    fn powi(&self, n: i32) -> Self;
    /// Square root on the reals extended by `sqrt(x) = sqrt(max(x, 0))`, the paper's
    /// reading: the part of a range below 0 is clipped, and a range wholly below 0 gives
    /// exactly `0`.
    fn sqrt(&self) -> Self;
    /// `sqrt(x^2 + y^2)`, the root of the R-functions. Affine arithmetics override it:
    /// the affine range of `x^2 + y^2` often dips below 0 (and then `sqrt` takes its
    /// loose approximation across 0), while the argument is known to be at least
    /// `mig(x)^2 + mig(y)^2 >= 0` ([`crate::approx::sum_sq_floor`]).
    fn hypot(&self, other: &Self) -> Self {
        (self.sqr() + other.sqr()).sqrt()
    }
    /// `1 / x`.
    fn recip(&self) -> Self;
    /// `e^x`.
    fn exp(&self) -> Self;
    /// Natural logarithm; `ln(x) = -inf` for `x <= 0`.
    fn ln(&self) -> Self;
    /// Sine.
    fn sin(&self) -> Self;
    /// Cosine.
    fn cos(&self) -> Self;
    /// `|x|`.
    fn abs(&self) -> Self;
    /// `min(x, y)`.
    fn min(&self, other: &Self) -> Self;
    /// `max(x, y)`.
    fn max(&self, other: &Self) -> Self;
    /// `c - x` (an `f64` on the left, in generic code).
    fn rsub(self, c: f64) -> Self {
        -self + c
    }
    /// `c / x` (an `f64` on the left, in generic code).
    fn rdiv(self, c: f64) -> Self {
        self.recip() * c
    }
    /// What the value says about itself to generic code: a point, the bounds of a sound
    /// range, or nothing (the default: operation counters, packs). Every [`Range`]
    /// returns [`Known::Range`] of its [`Range::bounds`] (the test kit checks it).
    fn known(&self) -> Known {
        Known::Unknown
    }
    /// A value enclosing `[lo, hi]` where the type holds ranges (every [`Range`]:
    /// [`Range::from_interval`]); `None` for points and other types (the default).
    fn from_bounds(lo: f64, hi: f64) -> Option<Self> {
        let _ = (lo, hi);
        None
    }
    /// The step `d > 0` ([`Step::Pos`]) or `d >= 0` of `self`: 1 or 0, the range
    /// `[0, 1]` where a range straddles 0 ([`crate::branch`]).
    fn step(&self, s: Step) -> Self {
        crate::branch::step(s, self)
    }
    /// `t` where the truth value `self` is 1, `e` where it is 0, the hull of both where
    /// a range leaves it undecided ([`crate::branch`]).
    fn select(&self, t: Self, e: Self) -> Self {
        crate::branch::select(self, t, e)
    }
}

/// What a value of a generic [`Real`] type is known to be ([`Real::known`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Known {
    /// An `f64` point.
    Point(f64),
    /// A sound range with these bounds.
    Range(f64, f64),
    /// A type that says nothing about its values.
    Unknown,
}

/// The linear part of an affine form on its first input symbol:
/// the value lies in `f0 + f1 * eps1 + [-e, e]` for some `eps1 ∈ [-1, 1]` that is the
/// first input's own noise symbol. Used by argument pruning (Algorithm 1, Section 4.1.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Linear {
    /// Centre.
    pub f0: f64,
    /// Coefficient of the first input symbol.
    pub f1: f64,
    /// Radius of everything else (other symbols, accumulated error), rounded up, `>= 0`.
    pub e: f64,
}

/// `x0 + Σ xs[i] eps_i ± e` over the first `K` inputs: see [`Range::affine_part`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AffinePart<const K: usize> {
    /// Centre.
    pub x0: f64,
    /// Coefficients of the first `K` input symbols.
    pub xs: [f64; K],
    /// Radius of everything else (other symbols, accumulated error), rounded up, `>= 0`.
    pub e: f64,
}

/// A sound enclosure: a [`Real`] whose every value encloses the real function's values.
///
/// # Contract
///
/// Let `F` be a composition of [`Real`] operations applied to inputs created by
/// [`Range::input`], [`Range::from_interval`] and [`Real::constant`]. For every choice of
/// real input points inside their ranges, the real value of `F` at those points (with
/// the extended definitions of [`Real::sqrt`] and [`Real::ln`]) lies in
/// [`Range::bounds`] of the computed range, after every `f64` rounding.
///
/// Domain edges and overflow widen, never narrow:
/// - `sqrt` of a range partly below 0 works on the part at or above 0; wholly below 0
///   gives `[0, 0]`.
/// - `ln` of a range reaching 0 or below has lower bound `-inf` (affine forms become the
///   whole line).
/// - `recip` (and `/`) of a range holding 0 gives the whole line `(-inf, +inf)`.
/// - Overflow gives infinite bounds.
/// - Bounds are never NaN, so [`Range::contains_zero`] never answers "no" by accident.
pub trait Range: Real {
    /// Short lower-case name used on command lines and in tables: `ia`, `aa`, ...
    const NAME: &'static str;
    /// How many independent inputs get their own noise symbol. An input with a larger
    /// index is still enclosed soundly, but without correlation.
    const INPUTS: usize;

    /// The `i`-th independent input, ranging over `[lo, hi]` (`lo <= hi`, finite).
    /// Inputs with distinct `i` are independent; the same `i` used twice in one
    /// evaluation denotes the same variable.
    fn input(i: usize, lo: f64, hi: f64) -> Self;
    /// A value only known to lie in `[lo, hi]`, independent of every other value
    /// (affine forms give it a fresh symbol or error term).
    fn from_interval(lo: f64, hi: f64) -> Self;
    /// `c0 + Σ cs[i] eps_i ± err`: an affine function of the inputs `0..cs.len()`, each
    /// `eps_i ∈ [-1, 1]` standing for input `i` as [`Range::input`] over `[-1, 1]` makes
    /// it, plus an independent error of at most `err` (`err >= 0`). The numbers are taken
    /// as exact; a non-finite one gives an unbounded range. Lets a caller build inputs
    /// that are correlated through shared symbols (a frustum's points as functions of
    /// depth and two pixel coordinates) without paying for the operations that would
    /// compute them; the default does exactly that, with the operations.
    fn from_affine(c0: f64, cs: &[f64], err: f64) -> Self {
        if !(c0.is_finite() && err.is_finite() && cs.iter().all(|c| c.is_finite())) {
            return Self::from_interval(f64::NEG_INFINITY, f64::INFINITY);
        }
        let mut r = Self::from_interval(-err.abs(), err.abs()) + c0;
        for (i, &c) in cs.iter().enumerate() {
            r = r + Self::input(i, -1.0, 1.0) * c;
        }
        r
    }
    /// The enclosure `[lo, hi]`; never NaN; `-inf`/`+inf` when unbounded.
    fn bounds(&self) -> (f64, f64);
    /// Whether `0 ∈ bounds()`.
    fn contains_zero(&self) -> bool {
        let (lo, hi) = self.bounds();
        // Written so that a NaN bound (which would break the contract) answers "yes".
        !(lo > 0.0 || hi < 0.0)
    }
    /// The linear part on the first input symbol, for argument pruning. `None` for
    /// arithmetics without one (intervals) or for unbounded forms. By default the
    /// [`Range::affine_part`] on that one input.
    fn linear_part(&self) -> Option<Linear> {
        let a = self.affine_part::<1>()?;
        Some(Linear {
            f0: a.x0,
            f1: a.xs[0],
            e: a.e,
        })
    }
    /// The form's centre and coefficients on the inputs `0..K`, every other term (other
    /// symbols, the error part) bounded in `e`: the value lies in
    /// `x0 + Σ xs[i] eps_i ± e` for the inputs' `eps_i` (as in
    /// [`Range::bounds_at_inputs`]). A coefficient on an input without its own symbol is
    /// 0 (that input is in `e`). What a bundle's form says about one ray, or one child:
    /// fixing some inputs is then the caller's arithmetic. `None` for arithmetics without
    /// symbols (the default) and for unbounded forms.
    fn affine_part<const K: usize>(&self) -> Option<AffinePart<K>> {
        None
    }
    /// The enclosure after fixing the input symbols at `eps[i] ∈ [-1, 1]` (input `i`
    /// fixed at the point `mid_i + rad_i * eps[i]`), leaving every symbol created by an
    /// operation free. Sound (outward rounded). Arithmetics without symbols return
    /// [`Range::bounds`]; this is what the joint-inclusion property tests check.
    fn bounds_at_inputs(&self, eps: &[f64]) -> (f64, f64) {
        let _ = eps;
        self.bounds()
    }
}

/// One arithmetic as a family of forms: what the tracer, the tests and the benches
/// iterate over. Rays use the shortest form; cells use three independent inputs.
pub trait Arithmetic: Send + Sync + 'static {
    /// Lower-case name (`ia`, `aa`, `raa`, `revaa`).
    const NAME: &'static str;
    /// Display label as in the paper's tables (`IA`, `AA`, `RAA*`, `RevAA`).
    const LABEL: &'static str;
    /// Form for a ray: one input (`t`).
    type Ray: Range;
    /// Form for a 3-D cell: three independent inputs (`x`, `y`, `z`).
    type Cell: Range;
    /// Four ray forms evaluated together ([`crate::pack`]): a SIMD form where the
    /// arithmetic has one, else `Lanes<Self::Ray>`.
    type RayPack: crate::pack::Pack<Lane = Self::Ray>;
    /// Four cell forms evaluated together, as [`Arithmetic::RayPack`].
    type CellPack: crate::pack::Pack<Lane = Self::Cell>;
}

impl Real for f64 {
    fn constant(c: f64) -> Self {
        c
    }
    fn sqr(&self) -> Self {
        self * self
    }
    fn powi(&self, n: i32) -> Self {
        f64::powi(*self, n)
    }
    /// The root of `x` where `x > 0`, else `+0` (NaN, negative numbers and both
    /// zeros), so that every evaluation path gives the same bits.
    fn sqrt(&self) -> Self {
        f64::sqrt(if *self > 0.0 { *self } else { 0.0 })
    }
    fn recip(&self) -> Self {
        1.0 / self
    }
    /// The lanes' `exp` ([`lanes::exp_f64`], within 9 ulp-units) for
    /// `|x| <= EXP_MAX_ARG`, so that a point evaluated alone and in lanes gives the
    /// same bits; libm's beyond.
    fn exp(&self) -> Self {
        let x = *self;
        if x.abs() <= lanes::EXP_MAX_ARG {
            lanes::exp_f64(x)
        } else {
            f64::exp(x)
        }
    }
    /// `-inf` for `x <= 0`; the lanes' `ln` ([`lanes::ln_f64`]) for positive normal
    /// `x` (see [`Real::exp`] for `f64`); libm's elsewhere (subnormal, infinite, NaN).
    fn ln(&self) -> Self {
        let x = *self;
        if x <= 0.0 {
            f64::NEG_INFINITY
        } else if (f64::MIN_POSITIVE..f64::INFINITY).contains(&x) {
            lanes::ln_f64(x)
        } else {
            f64::ln(x)
        }
    }
    /// The lanes' `sin` ([`lanes::sin_f64`]) for `|x| <= TRIG_MAX_ARG` (see
    /// [`Real::exp`] for `f64`); libm's beyond.
    fn sin(&self) -> Self {
        let x = *self;
        if x.abs() <= lanes::TRIG_MAX_ARG {
            lanes::sin_f64(x)
        } else {
            f64::sin(x)
        }
    }
    /// The lanes' `cos` ([`lanes::cos_f64`]) for `|x| <= TRIG_MAX_ARG`; libm's beyond.
    fn cos(&self) -> Self {
        let x = *self;
        if x.abs() <= lanes::TRIG_MAX_ARG {
            lanes::cos_f64(x)
        } else {
            f64::cos(x)
        }
    }
    fn abs(&self) -> Self {
        f64::abs(*self)
    }
    /// `f64::min`, but `min(-0, +0) = -0` in either order (as IEEE 754-2019's
    /// `minimum`): `f64::min` returns either zero, even by operand order, so a model
    /// rewritten with its operands swapped could change a bit.
    fn min(&self, other: &Self) -> Self {
        let (a, b) = (*self, *other);
        if a == b {
            // Equal values have equal bits but for the zeros' signs: keep a set sign.
            f64::from_bits(a.to_bits() | b.to_bits())
        } else {
            f64::min(a, b)
        }
    }
    /// `f64::max`, but `max(-0, +0) = +0` in either order (see [`Real::min`]).
    fn max(&self, other: &Self) -> Self {
        let (a, b) = (*self, *other);
        if a == b {
            f64::from_bits(a.to_bits() & b.to_bits())
        } else {
            f64::max(a, b)
        }
    }
    fn rsub(self, c: f64) -> Self {
        c - self
    }
    fn known(&self) -> Known {
        Known::Point(*self)
    }
    fn rdiv(self, c: f64) -> Self {
        c / self
    }
}

/// Implements `f64 + T`, `f64 - T`, `f64 * T`, `f64 / T` for a concrete [`Real`] type in
/// terms of its `T op f64` impls, so users of a concrete type can write `2.0 * x`.
/// For a type with a const parameter: `impl_f64_lhs_ops!(<const N: usize> RevAa<N>);`,
/// and one more bounded type parameter:
/// `impl_f64_lhs_ops!(<const N: usize, F: ReducedForm<N>> ReducedX4<N, F>);`
#[macro_export]
macro_rules! impl_f64_lhs_ops {
    (<const $n:ident : $nt:ty, $p:ident : $b:path> $t:ty) => {
        $crate::impl_f64_lhs_ops!(@impl [const $n: $nt, $p: $b] $t);
    };
    (<$(const $n:ident : $nt:ty)?> $t:ty) => {
        $crate::impl_f64_lhs_ops!(@impl [$(const $n: $nt)?] $t);
    };
    (@impl [$($g:tt)*] $t:ty) => {
        impl<$($g)*> ::core::ops::Add<$t> for f64 {
            type Output = $t;
            fn add(self, rhs: $t) -> $t {
                rhs + self
            }
        }
        impl<$($g)*> ::core::ops::Sub<$t> for f64 {
            type Output = $t;
            fn sub(self, rhs: $t) -> $t {
                $crate::Real::rsub(rhs, self)
            }
        }
        impl<$($g)*> ::core::ops::Mul<$t> for f64 {
            type Output = $t;
            fn mul(self, rhs: $t) -> $t {
                rhs * self
            }
        }
        impl<$($g)*> ::core::ops::Div<$t> for f64 {
            type Output = $t;
            fn div(self, rhs: $t) -> $t {
                $crate::Real::rdiv(rhs, self)
            }
        }
    };
    // After the generic arm: a `ty` fragment that fails to parse (`<> T`) is a hard
    // error, so the plain form must not be tried first.
    ($t:ty) => {
        $crate::impl_f64_lhs_ops!(<> $t);
    };
}
