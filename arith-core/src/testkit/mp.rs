//! Multi-precision reference values: rigorous enclosures of a real value computed with
//! `astro-float` in directed rounding.
//!
//! An [`Mp`] is a tiny interval `[lo, hi]` of `BigFloat`s (256 bits by default) that is
//! *guaranteed* to hold the exact real value of an operation chain at a point, with the
//! workspace's extended definitions (`sqrt(x) = sqrt(max(x, 0))`, `ln(x <= 0) = -inf`,
//! `x^0 = 1`). astro-float rounds every operation and function correctly, so lower
//! bounds are rounded toward `-inf` and upper bounds toward `+inf`; exact chains (sums
//! and products of a few `f64`s) stay exact points, so tight-but-correct bounds of an
//! arithmetic under test never fail a check by accident.
//!
//! `None` means "undefined at this point": a divisor (or `recip`, or a negative `powi`
//! argument) whose enclosure holds 0, or an indeterminate form such as `inf - inf` or
//! `0 * inf` (reachable through `ln(0) = -inf`). Checks skip such points.

use astro_float::{BigFloat, Consts, RoundingMode, INF_NEG, INF_POS};
use core::cell::RefCell;

/// Default working precision of reference values, in bits.
pub const PREC: usize = 256;

thread_local! {
    /// Constants cache (pi, ln 2, ...) reused by every function evaluation on a thread.
    static CONSTS: RefCell<Consts> =
        RefCell::new(Consts::new().expect("astro-float constants cache"));
}

const DN: RoundingMode = RoundingMode::Down;
const UP: RoundingMode = RoundingMode::Up;

/// Where a reference value lies relative to the bounds of a computed range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The exact value certainly lies inside `[lo, hi]`.
    Inside,
    /// The exact value certainly lies outside `[lo, hi]`: the range is unsound.
    Outside,
    /// The reference enclosure overlaps a bound: undecided at this precision.
    Unsure,
}

/// A rigorous multi-precision enclosure `[lo, hi]` of one real (or `±inf`) value.
#[derive(Clone, Debug)]
pub struct Mp {
    lo: BigFloat,
    hi: BigFloat,
    p: usize,
}

/// An `f64` as a `BigFloat`, infinities included (exact).
pub fn big(x: f64, p: usize) -> BigFloat {
    if x == f64::INFINITY {
        INF_POS
    } else if x == f64::NEG_INFINITY {
        INF_NEG
    } else if x != 0.0 && x.abs() < f64::MIN_POSITIVE {
        // astro-float 0.9 converts subnormal f64s wrongly (off by a factor 2): scale
        // into the normal range exactly, convert, and scale back exactly.
        let scaled = BigFloat::from_f64(x * TWO_P64, p);
        scaled.mul(
            &BigFloat::from_f64(1.0 / TWO_P64, p),
            p,
            RoundingMode::ToEven,
        )
    } else {
        BigFloat::from_f64(x, p)
    }
}

/// `2^64`, an exact scale for subnormal conversion.
const TWO_P64: f64 = 18_446_744_073_709_551_616.0;

fn zero(p: usize) -> BigFloat {
    BigFloat::from_f64(0.0, p)
}

fn lt(a: &BigFloat, b: &BigFloat) -> bool {
    matches!(a.cmp(b), Some(c) if c < 0)
}

fn le(a: &BigFloat, b: &BigFloat) -> bool {
    matches!(a.cmp(b), Some(c) if c <= 0)
}

fn min2(a: BigFloat, b: BigFloat) -> BigFloat {
    if lt(&b, &a) {
        b
    } else {
        a
    }
}

fn max2(a: BigFloat, b: BigFloat) -> BigFloat {
    if lt(&a, &b) {
        b
    } else {
        a
    }
}

impl Mp {
    /// The exact point `x` at the default precision; `None` for NaN.
    pub fn point(x: f64) -> Option<Mp> {
        Mp::point_p(x, PREC)
    }

    /// The exact point `x` at precision `p` bits; `None` for NaN.
    pub fn point_p(x: f64, p: usize) -> Option<Mp> {
        if x.is_nan() {
            return None;
        }
        let b = big(x, p);
        Some(Mp {
            lo: b.clone(),
            hi: b,
            p,
        })
    }

    /// Builds `[lo, hi]`, `None` if either end is NaN (an indeterminate form).
    fn make(lo: BigFloat, hi: BigFloat, p: usize) -> Option<Mp> {
        if lo.is_nan() || hi.is_nan() {
            None
        } else {
            Some(Mp { lo, hi, p })
        }
    }

    /// The working precision in bits.
    pub fn prec(&self) -> usize {
        self.p
    }

    /// The enclosure in decimal, for failure messages.
    pub fn describe(&self) -> String {
        format!("[{}, {}]", self.lo, self.hi)
    }

    /// Whether the enclosure may hold 0.
    fn holds_zero(&self) -> bool {
        let z = zero(self.p);
        le(&self.lo, &z) && le(&z, &self.hi)
    }

    /// `self + o`.
    pub fn add(&self, o: &Mp) -> Option<Mp> {
        Mp::make(
            self.lo.add(&o.lo, self.p, DN),
            self.hi.add(&o.hi, self.p, UP),
            self.p,
        )
    }

    /// `self - o`.
    pub fn sub(&self, o: &Mp) -> Option<Mp> {
        self.add(&o.neg())
    }

    /// `-self`.
    pub fn neg(&self) -> Mp {
        Mp {
            lo: self.hi.neg(),
            hi: self.lo.neg(),
            p: self.p,
        }
    }

    /// `self * o` (`None` for `0 * inf`).
    pub fn mul(&self, o: &Mp) -> Option<Mp> {
        let p = self.p;
        let corners = [
            (&self.lo, &o.lo),
            (&self.lo, &o.hi),
            (&self.hi, &o.lo),
            (&self.hi, &o.hi),
        ];
        let mut lo: Option<BigFloat> = None;
        let mut hi: Option<BigFloat> = None;
        for (a, b) in corners {
            let l = a.mul(b, p, DN);
            let h = a.mul(b, p, UP);
            if l.is_nan() || h.is_nan() {
                return None;
            }
            lo = Some(match lo {
                None => l,
                Some(x) => min2(x, l),
            });
            hi = Some(match hi {
                None => h,
                Some(x) => max2(x, h),
            });
        }
        Mp::make(lo?, hi?, p)
    }

    /// `self / o`; `None` when `o` may be 0.
    pub fn div(&self, o: &Mp) -> Option<Mp> {
        self.mul(&o.recip()?)
    }

    /// `1 / self`; `None` when `self` may be 0.
    pub fn recip(&self) -> Option<Mp> {
        if self.holds_zero() {
            return None;
        }
        let one = BigFloat::from_f64(1.0, self.p);
        // 1/x is decreasing on each side of 0 (1/inf = 0 is exact).
        Mp::make(
            one.div(&self.hi, self.p, DN),
            one.div(&self.lo, self.p, UP),
            self.p,
        )
    }

    /// `|self|`.
    pub fn abs(&self) -> Mp {
        let z = zero(self.p);
        if le(&z, &self.lo) {
            self.clone()
        } else if le(&self.hi, &z) {
            self.neg()
        } else {
            Mp {
                lo: z,
                hi: max2(self.lo.neg(), self.hi.clone()),
                p: self.p,
            }
        }
    }

    /// `self^2`.
    pub fn sqr(&self) -> Option<Mp> {
        self.powi(2)
    }

    /// `self^n` (`x^0 = 1`; negative `n` is `1 / x^|n|`, undefined where `x` may be 0).
    pub fn powi(&self, n: i32) -> Option<Mp> {
        let p = self.p;
        if n == 0 {
            return Mp::point_p(1.0, p);
        }
        let m = n.unsigned_abs() as usize;
        let pw = |x: &BigFloat, rm: RoundingMode| -> BigFloat {
            if x.is_inf() {
                if x.is_inf_neg() && m & 1 == 1 {
                    INF_NEG
                } else {
                    INF_POS
                }
            } else {
                x.powi(m, p, rm)
            }
        };
        let pos = if m & 1 == 0 {
            // Even power: increasing in |x|.
            let a = self.abs();
            Mp::make(pw(&a.lo, DN), pw(&a.hi, UP), p)?
        } else {
            // Odd power: increasing.
            Mp::make(pw(&self.lo, DN), pw(&self.hi, UP), p)?
        };
        if n > 0 {
            Some(pos)
        } else {
            pos.recip()
        }
    }

    /// `sqrt(max(self, 0))`.
    pub fn sqrt(&self) -> Option<Mp> {
        let p = self.p;
        let z = zero(p);
        let f = |x: &BigFloat, rm: RoundingMode| -> BigFloat {
            if le(x, &z) {
                zero(p)
            } else if x.is_inf_pos() {
                INF_POS
            } else {
                x.sqrt(p, rm)
            }
        };
        Mp::make(f(&self.lo, DN), f(&self.hi, UP), p)
    }

    /// `e^self`.
    pub fn exp(&self) -> Option<Mp> {
        let p = self.p;
        let f = |x: &BigFloat, rm: RoundingMode| -> BigFloat {
            if x.is_inf_neg() {
                zero(p)
            } else if x.is_inf_pos() {
                INF_POS
            } else {
                CONSTS.with(|c| x.exp(p, rm, &mut c.borrow_mut()))
            }
        };
        Mp::make(f(&self.lo, DN), f(&self.hi, UP), p)
    }

    /// `ln(self)`, `-inf` for arguments `<= 0`.
    pub fn ln(&self) -> Option<Mp> {
        let p = self.p;
        let z = zero(p);
        let f = |x: &BigFloat, rm: RoundingMode| -> BigFloat {
            if le(x, &z) {
                INF_NEG
            } else if x.is_inf_pos() {
                INF_POS
            } else {
                CONSTS.with(|c| x.ln(p, rm, &mut c.borrow_mut()))
            }
        };
        Mp::make(f(&self.lo, DN), f(&self.hi, UP), p)
    }

    /// `sin(self)`.
    pub fn sin(&self) -> Option<Mp> {
        self.trig(false)
    }

    /// `cos(self)`.
    pub fn cos(&self) -> Option<Mp> {
        self.trig(true)
    }

    /// `sin` or `cos` of the enclosure: the hull of the end values when the function is
    /// provably monotone in between (derivative of one strict sign at both ends and a
    /// width below 3 < pi, so no critical point fits inside), else `[-1, 1]`.
    fn trig(&self, cos: bool) -> Option<Mp> {
        let p = self.p;
        let whole = Mp::make(BigFloat::from_f64(-1.0, p), BigFloat::from_f64(1.0, p), p);
        if self.lo.is_inf() || self.hi.is_inf() {
            return whole;
        }
        let f = |x: &BigFloat, rm: RoundingMode, c: bool| -> BigFloat {
            CONSTS.with(|cc| {
                let cc = &mut cc.borrow_mut();
                if c {
                    x.cos(p, rm, cc)
                } else {
                    x.sin(p, rm, cc)
                }
            })
        };
        let same = matches!(self.lo.cmp(&self.hi), Some(0));
        if !same {
            let width = self.hi.sub(&self.lo, p, UP);
            if !lt(&width, &BigFloat::from_f64(3.0, p)) {
                return whole;
            }
            // Derivative of sin is cos, of cos is -sin: only its sign matters.
            let sign = |x: &BigFloat| -> i32 {
                let (l, h) = (f(x, DN, !cos), f(x, UP, !cos));
                let z = zero(p);
                if lt(&z, &l) {
                    1
                } else if lt(&h, &z) {
                    -1
                } else {
                    0
                }
            };
            let (s0, s1) = (sign(&self.lo), sign(&self.hi));
            if s0 == 0 || s0 != s1 {
                return whole;
            }
        }
        let (a_lo, a_hi) = (f(&self.lo, DN, cos), f(&self.lo, UP, cos));
        let (b_lo, b_hi) = (f(&self.hi, DN, cos), f(&self.hi, UP, cos));
        Mp::make(min2(a_lo, b_lo), max2(a_hi, b_hi), p)
    }

    /// `min(self, o)`.
    pub fn min(&self, o: &Mp) -> Mp {
        Mp {
            lo: min2(self.lo.clone(), o.lo.clone()),
            hi: min2(self.hi.clone(), o.hi.clone()),
            p: self.p,
        }
    }

    /// `max(self, o)`.
    pub fn max(&self, o: &Mp) -> Mp {
        Mp {
            lo: max2(self.lo.clone(), o.lo.clone()),
            hi: max2(self.hi.clone(), o.hi.clone()),
            p: self.p,
        }
    }

    /// Where the exact value lies relative to `[lo, hi]` (infinite bounds allowed: a
    /// value `-inf` is inside only when `lo == -inf`). NaN bounds are always
    /// [`Verdict::Outside`]: they break the [`crate::Range`] contract.
    pub fn verdict(&self, lo: f64, hi: f64) -> Verdict {
        if lo.is_nan() || hi.is_nan() {
            return Verdict::Outside;
        }
        let (blo, bhi) = (big(lo, 64), big(hi, 64));
        if lt(&self.hi, &blo) || lt(&bhi, &self.lo) {
            Verdict::Outside
        } else if le(&blo, &self.lo) && le(&self.hi, &bhi) {
            Verdict::Inside
        } else {
            Verdict::Unsure
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directed_rounding_brackets_thirds_and_e() {
        let third = Mp::point(1.0)
            .unwrap()
            .div(&Mp::point(3.0).unwrap())
            .unwrap();
        assert!(lt(&third.lo, &third.hi), "1/3 is not a binary float");
        // Multiplying back brackets 1 strictly.
        let back = third.mul(&Mp::point(3.0).unwrap()).unwrap();
        assert_eq!(back.verdict(1.0, 1.0), Verdict::Unsure);
        assert_eq!(
            back.verdict(1.0f64.next_down(), 1.0f64.next_up()),
            Verdict::Inside
        );
        let e = Mp::point(1.0).unwrap().exp().unwrap();
        assert_eq!(
            e.verdict(core::f64::consts::E, core::f64::consts::E.next_up()),
            Verdict::Inside
        );
        assert_eq!(e.verdict(2.7182818284590455, 3.0), Verdict::Outside);
    }

    #[test]
    fn subnormals_convert_exactly() {
        let tiny = Mp::point(f64::from_bits(1)).unwrap();
        // 2^-1074 * 2^1000 * 2^74 == 1 exactly.
        let one = tiny.mul(&Mp::point(2f64.powi(1000)).unwrap()).unwrap();
        let one = one.mul(&Mp::point(2f64.powi(74)).unwrap()).unwrap();
        assert_eq!(one.verdict(1.0, 1.0), Verdict::Inside);
        let s = 1.9434059944139155e-308;
        let r = Mp::point(s)
            .unwrap()
            .mul(&Mp::point(2f64.powi(1000)).unwrap())
            .unwrap();
        assert_eq!(
            r.verdict(s * 2f64.powi(1000), s * 2f64.powi(1000)),
            Verdict::Inside
        );
        assert_eq!(Mp::point(s).unwrap().verdict(s, s), Verdict::Inside);
        assert_eq!(
            Mp::point(s).unwrap().verdict(s.next_up(), 1.0),
            Verdict::Outside
        );
    }

    #[test]
    fn exact_chains_stay_points() {
        let x = Mp::point(1.5).unwrap();
        let y = x.powi(3).unwrap().add(&Mp::point(0.25).unwrap()).unwrap();
        assert_eq!(y.verdict(3.625, 3.625), Verdict::Inside);
        assert_eq!(y.verdict(3.625f64.next_up(), 4.0), Verdict::Outside);
    }

    #[test]
    fn extended_definitions() {
        let neg = Mp::point(-2.0).unwrap();
        assert_eq!(neg.sqrt().unwrap().verdict(0.0, 0.0), Verdict::Inside);
        let l = Mp::point(0.0).unwrap().ln().unwrap();
        assert_eq!(l.verdict(f64::NEG_INFINITY, 0.0), Verdict::Inside);
        assert_eq!(l.verdict(-1e308, 0.0), Verdict::Outside);
        // ln(0) - ln(0) = -inf + inf: undefined.
        assert!(l.sub(&l).is_none());
        assert!(Mp::point(0.0).unwrap().recip().is_none());
        assert!(Mp::point(0.0).unwrap().powi(-2).is_none());
        assert_eq!(
            Mp::point(0.0).unwrap().powi(0).unwrap().verdict(1.0, 1.0),
            Verdict::Inside
        );
        // exp overflows f64 but not the reference: an f64 bound MAX is too small.
        let big_e = Mp::point(710.0).unwrap().exp().unwrap();
        assert_eq!(big_e.verdict(0.0, f64::MAX), Verdict::Outside);
        assert_eq!(big_e.verdict(f64::MAX, f64::INFINITY), Verdict::Inside);
    }

    #[test]
    fn trig_known_values() {
        // sin(1e22) = -0.8522008497671888... (a classic argument-reduction test).
        let s = Mp::point(1e22).unwrap().sin().unwrap();
        assert_eq!(
            s.verdict(-0.852200849767189, -0.8522008497671887),
            Verdict::Inside
        );
        // Huge arguments (values from mpmath at 3000 bits).
        let s = Mp::point(2f64.powi(1000)).unwrap().sin().unwrap();
        assert_eq!(
            s.verdict(-0.15920170308624245, -0.15920170308624242),
            Verdict::Inside
        );
        assert_eq!(s.verdict(-0.1592017030862424, 1.0), Verdict::Outside);
        let c = Mp::point(f64::MAX).unwrap().cos().unwrap();
        assert_eq!(
            c.verdict(-0.99998768942656, -0.9999876894265598),
            Verdict::Inside
        );
        let c = Mp::point(0.0).unwrap().cos().unwrap();
        assert_eq!(c.verdict(1.0, 1.0), Verdict::Inside);
        // A non-degenerate enclosure around pi/2 must include the maximum 1.
        let around = Mp {
            lo: big(1.5, PREC),
            hi: big(1.6, PREC),
            p: PREC,
        };
        assert_ne!(around.sin().unwrap().verdict(0.0, 0.9999), Verdict::Inside);
    }
}
