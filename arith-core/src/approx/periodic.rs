//! What the affine approximations of `sin` and `cos` ([`super::trig`]) and their
//! interval ranges ([`super::interval`]) share: which function, its value and slope
//! enclosed at a point, and the conservative test of whether an argument range may
//! hold an extremum or an inflection.

use crate::round::libm_enclose;

/// Largest argument magnitude for which `sin`/`cos` get more than `[-1, 1]`.
pub(super) const TRIG_MAX_ARG: f64 = 1.0e7;

/// Safety margin (in periods) of [`may_contain`]; float errors are below `1e-9` there.
const PERIOD_EPS: f64 = 1.0e-6;

/// Conservatively: whether `[a, b]` (finite, `|a|, |b| <= TRIG_MAX_ARG`) may contain a
/// point `offset + k*period` (`k` integer). The float quotient `(x - offset)/period` is
/// within `1e-9` of the exact one at these magnitudes; `PERIOD_EPS` covers that with room.
pub(super) fn may_contain(a: f64, b: f64, offset: f64, period: f64) -> bool {
    let u = (a - offset) / period - PERIOD_EPS;
    let v = (b - offset) / period + PERIOD_EPS;
    u.ceil() <= v.floor()
}

/// `sin` or `cos`.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Trig {
    Sin,
    Cos,
}

impl Trig {
    pub(super) fn f(self, x: f64) -> (f64, f64) {
        match self {
            Trig::Sin => libm_enclose(x.sin()),
            Trig::Cos => libm_enclose(x.cos()),
        }
    }
    pub(super) fn df(self, x: f64) -> (f64, f64) {
        match self {
            Trig::Sin => libm_enclose(x.cos()),
            Trig::Cos => {
                let (lo, hi) = libm_enclose(x.sin());
                (-hi, -lo)
            }
        }
    }
}
