//! Comparisons and conditional selection, sound over every range arithmetic.
//!
//! A comparison is a step function of one value, `d > 0` or `d >= 0`, whose result is
//! 1 or 0. Over a range the step is decided when the whole range lies on one side of 0,
//! and is the range `[0, 1]` when it straddles 0. A selection `select(c, t, e)` takes
//! `t` where the truth value `c` is 1 and `e` where it is 0: over a range it is decided
//! when `c`'s range lies above or below 1/2 (a real truth value is exactly 0 or 1, so
//! that threshold is never close), and otherwise it is the hull of both branches,
//! which encloses whichever one each point takes.
//!
//! Generic code tells points from ranges by [`Real::known`] and builds hulls with
//! [`Real::from_bounds`]. Dual numbers ([`Dual`]) say nothing about themselves; they are
//! recognised by their concrete type (over `f64` and over the ray and cell forms of every
//! arithmetic in [`crate::arith::ArithKind`]): the value follows the rules above and the
//! gradient is that of the branch taken. Where a step or a selection is undecided over a
//! range the function may jump there, so the gradient is the whole line (no Lipschitz
//! bound can be claimed across a jump). Any other type gets `1 / 0`, the whole line for
//! sound ranges.

use crate::models::noise::{cast, unknown_value};
use arith_core::dual::Dual;
use arith_core::{Arithmetic, Known, Real};
use std::any::{Any, TypeId};

/// Which step: `d > 0` (strict) or `d >= 0`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Step {
    /// `d > 0`.
    Pos,
    /// `d >= 0`.
    NonNeg,
}

impl Step {
    /// The step at a point (NaN is 0, as every IEEE comparison with NaN is false).
    pub(crate) fn at(self, d: f64) -> f64 {
        let holds = match self {
            Step::Pos => d > 0.0,
            Step::NonNeg => d >= 0.0,
        };
        if holds {
            1.0
        } else {
            0.0
        }
    }

    /// The step over `[lo, hi]`: `Some(0 or 1)` where decided, `None` where not.
    fn over(self, lo: f64, hi: f64) -> Option<f64> {
        match self {
            Step::Pos if lo > 0.0 => Some(1.0),
            Step::Pos if hi <= 0.0 => Some(0.0),
            Step::NonNeg if lo >= 0.0 => Some(1.0),
            Step::NonNeg if hi < 0.0 => Some(0.0),
            _ => None,
        }
    }
}

/// Calls `$m!(T)` for `f64` and the ray and cell form of every arithmetic.
macro_rules! for_each_component {
    ($m:ident) => {
        $m!(f64);
        for kind in $crate::arith::ArithKind::ALL {
            $crate::with_arith!(kind, A => {
                $m!(<A as Arithmetic>::Ray);
                $m!(<A as Arithmetic>::Cell);
            });
        }
    };
}

/// Whether a step or selection over values of this kind was decided.
fn decided(k: Known) -> bool {
    match k {
        Known::Point(_) => true,
        Known::Range(lo, hi) => lo == hi,
        Known::Unknown => false,
    }
}

/// The step of `d` over any [`Real`] (see the module doc).
pub(crate) fn step<R: Real>(s: Step, d: &R) -> R {
    match d.known() {
        Known::Point(v) => return R::constant(s.at(v)),
        Known::Range(lo, hi) => {
            return match s.over(lo, hi) {
                Some(v) => R::constant(v),
                None => R::from_bounds(0.0, 1.0).unwrap_or_else(unknown_value),
            }
        }
        Known::Unknown => {}
    }
    macro_rules! try_dual {
        ($t:ty) => {
            if TypeId::of::<R>() == TypeId::of::<Dual<$t>>() {
                if let Some(dd) = (d as &dyn Any).downcast_ref::<Dual<$t>>() {
                    let v: $t = step(s, &dd.v);
                    let g = if decided(v.known()) {
                        <$t as Real>::constant(0.0)
                    } else {
                        unknown_value()
                    };
                    let out = Dual {
                        v,
                        g: [g.clone(), g.clone(), g],
                    };
                    if let Some(out) = cast::<Dual<$t>, R>(out) {
                        return out;
                    }
                }
            }
        };
    }
    for_each_component!(try_dual);
    unknown_value()
}

/// The hull of two values: a range enclosing both (the whole line where they say
/// nothing about themselves).
fn hull<R: Real>(a: &R, b: &R) -> R {
    match (a.known(), b.known()) {
        (Known::Range(a0, a1), Known::Range(b0, b1)) => {
            R::from_bounds(a0.min(b0), a1.max(b1)).unwrap_or_else(unknown_value)
        }
        // Two points of a type without ranges: no value encloses both.
        _ => unknown_value(),
    }
}

/// Which branch the truth value `c` picks over `[lo, hi]`: `Some(true)` for the first.
fn side(lo: f64, hi: f64) -> Option<bool> {
    if lo > 0.5 {
        Some(true)
    } else if hi < 0.5 {
        Some(false)
    } else {
        None
    }
}

/// `t` where the truth value `c` is 1, `e` where it is 0, over any [`Real`] (see the
/// module doc).
pub(crate) fn select<R: Real>(c: &R, t: R, e: R) -> R {
    match c.known() {
        Known::Point(v) => return if v > 0.5 { t } else { e },
        Known::Range(lo, hi) => {
            return match side(lo, hi) {
                Some(true) => t,
                Some(false) => e,
                None => hull(&t, &e),
            }
        }
        Known::Unknown => {}
    }
    macro_rules! try_dual {
        ($t:ty) => {
            if TypeId::of::<R>() == TypeId::of::<Dual<$t>>() {
                if let Some(dc) = (c as &dyn Any).downcast_ref::<Dual<$t>>() {
                    let pick = match dc.v.known() {
                        Known::Point(v) => Some(v > 0.5),
                        Known::Range(lo, hi) => side(lo, hi),
                        Known::Unknown => None,
                    };
                    match pick {
                        Some(true) => return t,
                        Some(false) => return e,
                        None => {
                            let d = |v: &R| (v as &dyn Any).downcast_ref::<Dual<$t>>().cloned();
                            if let (Some(dt), Some(de)) = (d(&t), d(&e)) {
                                let g: $t = unknown_value();
                                let out = Dual {
                                    v: hull(&dt.v, &de.v),
                                    g: [g.clone(), g.clone(), g],
                                };
                                if let Some(out) = cast::<Dual<$t>, R>(out) {
                                    return out;
                                }
                            }
                        }
                    }
                }
            }
        };
    }
    for_each_component!(try_dual);
    unknown_value()
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::Range;
    use arith_ia::Interval;

    #[test]
    fn steps_over_points_and_ranges() {
        assert_eq!(step(Step::Pos, &0.0f64), 0.0);
        assert_eq!(step(Step::NonNeg, &0.0f64), 1.0);
        assert_eq!(step(Step::Pos, &f64::NAN), 0.0);
        let r = |lo, hi| Interval::new(lo, hi);
        assert_eq!(step(Step::Pos, &r(0.0, 1.0)).bounds(), (0.0, 1.0));
        assert_eq!(step(Step::NonNeg, &r(0.0, 1.0)).bounds(), (1.0, 1.0));
        assert_eq!(step(Step::Pos, &r(-1.0, 0.0)).bounds(), (0.0, 0.0));
        assert_eq!(step(Step::NonNeg, &r(-1.0, 0.0)).bounds(), (0.0, 1.0));
    }

    #[test]
    fn select_decides_or_takes_the_hull() {
        let r = |lo, hi| Interval::new(lo, hi);
        assert_eq!(
            select(&r(1.0, 1.0), r(2.0, 3.0), r(5.0, 6.0)).bounds(),
            (2.0, 3.0)
        );
        assert_eq!(
            select(&r(0.0, 0.0), r(2.0, 3.0), r(5.0, 6.0)).bounds(),
            (5.0, 6.0)
        );
        assert_eq!(
            select(&r(0.0, 1.0), r(2.0, 3.0), r(5.0, 6.0)).bounds(),
            (2.0, 6.0)
        );
        assert_eq!(select(&1.0f64, 2.0, 5.0), 2.0);
        assert_eq!(select(&0.0f64, 2.0, 5.0), 5.0);
    }

    #[test]
    fn duals_take_the_branch_or_an_unbounded_gradient() {
        let x = Dual::var(0.5f64, 0);
        let s = step(Step::Pos, &x);
        assert_eq!((s.v, s.g), (1.0, [0.0; 3]));
        let t = select(&s, x.clone() * 2.0, x.clone() * 3.0);
        assert_eq!((t.v, t.g[0]), (1.0, 2.0));
        let xi = Dual::var(Interval::new(-1.0, 1.0), 0);
        let si = step(Step::Pos, &xi);
        assert_eq!(si.v.bounds(), (0.0, 1.0));
        assert_eq!(si.g[0].bounds(), (f64::NEG_INFINITY, f64::INFINITY));
        let ti = select(&si, xi.clone() * 2.0, xi.clone() * 3.0);
        assert_eq!(ti.v.bounds(), (-3.0, 3.0));
        assert_eq!(ti.g[1].bounds(), (f64::NEG_INFINITY, f64::INFINITY));
    }
}
