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
//! These are the defaults of [`Real::step`] and [`Real::select`], written against what
//! a value says about itself ([`Real::known`]) and hulls built with
//! [`Real::from_bounds`]. A type that says nothing about itself gets `1 / 0`, the whole
//! line for sound ranges. Dual numbers ([`crate::dual::Dual`]) override both: the
//! value follows the rules above and the gradient is that of the branch taken; where a
//! step or a selection is undecided over a range the function may jump there, so the
//! gradient is the whole line (no Lipschitz bound can be claimed across a jump).

use crate::{Known, Real};

/// Which step: `d > 0` (strict) or `d >= 0`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Step {
    /// `d > 0`.
    Pos,
    /// `d >= 0`.
    NonNeg,
}

impl Step {
    /// The step at a point (NaN is 0, as every IEEE comparison with NaN is false).
    pub fn at(self, d: f64) -> f64 {
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
    pub fn over(self, lo: f64, hi: f64) -> Option<f64> {
        match self {
            Step::Pos if lo > 0.0 => Some(1.0),
            Step::Pos if hi <= 0.0 => Some(0.0),
            Step::NonNeg if lo >= 0.0 => Some(1.0),
            Step::NonNeg if hi < 0.0 => Some(0.0),
            _ => None,
        }
    }
}

/// The whole line for sound ranges (`1/0`, by the [`crate::Range`] contract), `+inf`
/// for points.
pub fn unknown_value<R: Real>() -> R {
    R::constant(0.0).recip()
}

/// Whether a step or selection over values of this kind was decided.
pub fn decided(k: Known) -> bool {
    match k {
        Known::Point(_) => true,
        Known::Range(lo, hi) => lo == hi,
        Known::Unknown => false,
    }
}

/// The step of `d` (the default of [`Real::step`]; see the module doc).
pub fn step<R: Real>(s: Step, d: &R) -> R {
    match d.known() {
        Known::Point(v) => R::constant(s.at(v)),
        Known::Range(lo, hi) => match s.over(lo, hi) {
            Some(v) => R::constant(v),
            None => R::from_bounds(0.0, 1.0).unwrap_or_else(unknown_value),
        },
        Known::Unknown => unknown_value(),
    }
}

/// The hull of two values: a range enclosing both (the whole line where they say
/// nothing about themselves).
pub fn hull<R: Real>(a: &R, b: &R) -> R {
    match (a.known(), b.known()) {
        (Known::Range(a0, a1), Known::Range(b0, b1)) => {
            R::from_bounds(a0.min(b0), a1.max(b1)).unwrap_or_else(unknown_value)
        }
        // Two points of a type without ranges: no value encloses both.
        _ => unknown_value(),
    }
}

/// Which branch a truth value known as `k` picks: `Some(true)` for the first, `None`
/// where undecided.
pub fn side(k: Known) -> Option<bool> {
    match k {
        Known::Point(v) => Some(v > 0.5),
        Known::Range(lo, _) if lo > 0.5 => Some(true),
        Known::Range(_, hi) if hi < 0.5 => Some(false),
        _ => None,
    }
}

/// `t` where the truth value `c` is 1, `e` where it is 0 (the default of
/// [`Real::select`]; see the module doc).
pub fn select<R: Real>(c: &R, t: R, e: R) -> R {
    match (c.known(), side(c.known())) {
        (_, Some(true)) => t,
        (_, Some(false)) => e,
        (Known::Range(..), None) => hull(&t, &e),
        _ => unknown_value(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dual::Dual;

    #[test]
    fn steps_at_points() {
        assert_eq!(step(Step::Pos, &0.0f64), 0.0);
        assert_eq!(step(Step::NonNeg, &0.0f64), 1.0);
        assert_eq!(step(Step::Pos, &f64::NAN), 0.0);
        assert_eq!(step(Step::NonNeg, &f64::NAN), 0.0);
        assert_eq!(Step::Pos.over(0.0, 1.0), None);
        assert_eq!(Step::NonNeg.over(0.0, 1.0), Some(1.0));
        assert_eq!(Step::Pos.over(-1.0, 0.0), Some(0.0));
        assert_eq!(Step::NonNeg.over(-1.0, 0.0), None);
    }

    #[test]
    fn select_at_points() {
        assert_eq!(select(&1.0f64, 2.0, 5.0), 2.0);
        assert_eq!(select(&0.0f64, 2.0, 5.0), 5.0);
    }

    #[test]
    fn duals_at_points_take_the_branch() {
        let x = Dual::var(0.5f64, 0);
        let s = x.step(Step::Pos);
        assert_eq!((s.v, s.g), (1.0, [0.0; 3]));
        let t = s.select(x.clone() * 2.0, x.clone() * 3.0);
        assert_eq!((t.v, t.g[0]), (1.0, 2.0));
    }
}
