//! Forward-mode dual numbers over any [`Real`]: a value and its gradient with respect to
//! three inputs. Over a range type, one evaluation of a model on a box encloses its
//! gradient there (a Lipschitz bound); over `f64` it gives the exact gradient at a point
//! (normals). `min`/`max` take the gradient of the side that is decided over the whole
//! range, and the hull of both gradients where neither is.
//!
//! Dual-number crates (`num-dual`) are written over `f32`/`f64` components only; this
//! one needs ranges as components, so it is written here, once.

use crate::branch::{self, Step};
use crate::{Known, Real};
use core::ops::{Add, Div, Mul, Neg, Sub};

/// The whole line for sound ranges (`1/0`, by the [`crate::Range`] contract), `+inf`
/// for points.
fn whole_line<R: Real>() -> R {
    R::constant(0.0).recip()
}

/// A forward-mode dual number: a value and its gradient with respect to three inputs,
/// over any [`Real`]. With `R` a range, evaluating a model over `Dual<R>` on a box gives
/// an enclosure of its gradient there, hence a Lipschitz bound.
#[derive(Clone, Debug, PartialEq)]
pub struct Dual<R> {
    /// The value.
    pub v: R,
    /// The gradient with respect to the three inputs.
    pub g: [R; 3],
}

impl<R: Real> Dual<R> {
    /// The `k`-th input variable with value `v`.
    pub fn var(v: R, k: usize) -> Self {
        Dual {
            v,
            g: core::array::from_fn(|j| R::constant(if j == k { 1.0 } else { 0.0 })),
        }
    }
    fn map_g(&self, f: impl Fn(&R) -> R) -> [R; 3] {
        core::array::from_fn(|j| f(&self.g[j]))
    }
    /// Value `v`, gradient `g * dv` (the chain rule for a unary function with derivative `dv`).
    fn chain(&self, v: R, dv: R) -> Self {
        Dual {
            v,
            g: self.map_g(|g| g.clone() * dv.clone()),
        }
    }
}

/// `a / h` for `|a| <= h`, kept in `[-1, 1]`: the ratio itself where it is known to be
/// there, the range's intersection with `[-1, 1]` for ranges, and `0` for points where
/// `h = 0` (a generalised derivative of `hypot` at the origin).
fn unit_ratio<R: Real>(a: &R, h: &R) -> R {
    let q = a.clone() / h.clone();
    match q.known() {
        Known::Point(v) if (-1.0..=1.0).contains(&v) => q,
        Known::Point(v) if v.is_nan() => R::constant(0.0),
        Known::Point(v) => R::constant(v.clamp(-1.0, 1.0)),
        Known::Range(lo, hi) if -1.0 <= lo && hi <= 1.0 => q,
        Known::Range(lo, hi) => {
            let (lo, hi) = (lo.max(-1.0), hi.min(1.0));
            let (lo, hi) = if lo <= hi { (lo, hi) } else { (-1.0, 1.0) };
            R::from_bounds(lo, hi).unwrap_or(q)
        }
        Known::Unknown => q,
    }
}

/// `a ∪ b` as one value: the hull for known ranges, either one for points (a valid
/// one-sided derivative), the whole line otherwise.
fn hull<R: Real>(a: &R, b: &R) -> R {
    match (a.known(), b.known()) {
        (Known::Point(_), Known::Point(_)) => a.clone(),
        (Known::Range(a0, a1), Known::Range(b0, b1)) => {
            R::from_bounds(a0.min(b0), a1.max(b1)).unwrap_or_else(whole_line)
        }
        _ => whole_line(),
    }
}

/// Which side of `min(a, b)` is taken: `Some(true)` for `a`, `Some(false)` for `b`,
/// `None` when undecided (overlapping ranges, unknown types).
fn min_side<R: Real>(a: &R, b: &R) -> Option<bool> {
    match (a.known(), b.known()) {
        (Known::Point(x), Known::Point(y)) => Some(x <= y),
        (Known::Range(a0, a1), Known::Range(b0, b1)) => {
            if a1 <= b0 {
                Some(true)
            } else if b1 <= a0 {
                Some(false)
            } else {
                None
            }
        }
        _ => None,
    }
}

fn pick<R: Real>(a: &Dual<R>, b: &Dual<R>, side: Option<bool>, v: R) -> Dual<R> {
    match side {
        Some(true) => Dual { v, g: a.g.clone() },
        Some(false) => Dual { v, g: b.g.clone() },
        None => Dual {
            v,
            g: core::array::from_fn(|j| hull(&a.g[j], &b.g[j])),
        },
    }
}

impl<R: Real> Add for Dual<R> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Dual {
            v: self.v + o.v,
            g: core::array::from_fn(|j| self.g[j].clone() + o.g[j].clone()),
        }
    }
}
impl<R: Real> Sub for Dual<R> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Dual {
            v: self.v - o.v,
            g: core::array::from_fn(|j| self.g[j].clone() - o.g[j].clone()),
        }
    }
}
impl<R: Real> Mul for Dual<R> {
    type Output = Self;
    #[allow(clippy::suspicious_arithmetic_impl)] // the product rule
    fn mul(self, o: Self) -> Self {
        let g = core::array::from_fn(|j| {
            self.g[j].clone() * o.v.clone() + o.g[j].clone() * self.v.clone()
        });
        Dual { v: self.v * o.v, g }
    }
}
impl<R: Real> Div for Dual<R> {
    type Output = Self;
    #[allow(clippy::suspicious_arithmetic_impl)] // the quotient rule
    fn div(self, o: Self) -> Self {
        let q = self.v.clone() / o.v.clone();
        let g = core::array::from_fn(|j| {
            (self.g[j].clone() - o.g[j].clone() * q.clone()) / o.v.clone()
        });
        Dual { v: q, g }
    }
}
impl<R: Real> Neg for Dual<R> {
    type Output = Self;
    fn neg(self) -> Self {
        Dual {
            v: -self.v,
            g: self.g.map(|g| -g),
        }
    }
}
impl<R: Real> Add<f64> for Dual<R> {
    type Output = Self;
    fn add(self, c: f64) -> Self {
        Dual {
            v: self.v + c,
            g: self.g,
        }
    }
}
impl<R: Real> Sub<f64> for Dual<R> {
    type Output = Self;
    fn sub(self, c: f64) -> Self {
        Dual {
            v: self.v - c,
            g: self.g,
        }
    }
}
impl<R: Real> Mul<f64> for Dual<R> {
    type Output = Self;
    fn mul(self, c: f64) -> Self {
        Dual {
            v: self.v * c,
            g: self.g.map(|g| g * c),
        }
    }
}
impl<R: Real> Div<f64> for Dual<R> {
    type Output = Self;
    fn div(self, c: f64) -> Self {
        Dual {
            v: self.v / c,
            g: self.g.map(|g| g / c),
        }
    }
}

impl<R: Real> Real for Dual<R> {
    fn constant(c: f64) -> Self {
        Dual {
            v: R::constant(c),
            g: core::array::from_fn(|_| R::constant(0.0)),
        }
    }
    fn sqr(&self) -> Self {
        self.chain(self.v.sqr(), self.v.clone() * 2.0)
    }
    fn powi(&self, n: i32) -> Self {
        if n == 0 {
            return Self::constant(1.0);
        }
        self.chain(self.v.powi(n), self.v.powi(n - 1) * n as f64)
    }
    fn sqrt(&self) -> Self {
        // d sqrt(x) = 1 / (2 sqrt x); over a range reaching 0 this is unbounded (sound).
        let s = self.v.sqrt();
        self.chain(s.clone(), (s * 2.0).recip())
    }
    fn hypot(&self, o: &Self) -> Self {
        // d hypot(a, b) = (a/h) da + (b/h) db with h = hypot(a, b), and |a|, |b| <= h:
        // each ratio lies in [-1, 1], also where h = 0 (every value there is a generalised
        // gradient of the kink). The gradient stays bounded where the chain rule through
        // `sqrt(a^2 + b^2)` divides by a range reaching 0.
        let h = self.v.hypot(&o.v);
        let (ra, rb) = (unit_ratio(&self.v, &h), unit_ratio(&o.v, &h));
        Dual {
            g: core::array::from_fn(|k| {
                ra.clone() * self.g[k].clone() + rb.clone() * o.g[k].clone()
            }),
            v: h,
        }
    }
    fn recip(&self) -> Self {
        let r = self.v.recip();
        self.chain(r.clone(), -r.sqr())
    }
    fn exp(&self) -> Self {
        let e = self.v.exp();
        self.chain(e.clone(), e)
    }
    fn ln(&self) -> Self {
        self.chain(self.v.ln(), self.v.recip())
    }
    fn sin(&self) -> Self {
        self.chain(self.v.sin(), self.v.cos())
    }
    fn cos(&self) -> Self {
        self.chain(self.v.cos(), -self.v.sin())
    }
    fn abs(&self) -> Self {
        // |x| = max(x, -x).
        self.max(&-self.clone())
    }
    fn min(&self, o: &Self) -> Self {
        pick(self, o, min_side(&self.v, &o.v), self.v.min(&o.v))
    }
    fn max(&self, o: &Self) -> Self {
        pick(
            self,
            o,
            min_side(&self.v, &o.v).map(|a_is_min| !a_is_min),
            self.v.max(&o.v),
        )
    }
    fn step(&self, s: Step) -> Self {
        // The step is constant on either side of its jump: a zero gradient where it is
        // decided, the whole line where the range may straddle the jump.
        let v = self.v.step(s);
        let g = if branch::decided(v.known()) {
            R::constant(0.0)
        } else {
            branch::unknown_value()
        };
        Dual {
            v,
            g: [g.clone(), g.clone(), g],
        }
    }
    fn select(&self, t: Self, e: Self) -> Self {
        match branch::side(self.v.known()) {
            Some(true) => t,
            Some(false) => e,
            None => {
                let g: R = branch::unknown_value();
                Dual {
                    v: branch::hull(&t.v, &e.v),
                    g: [g.clone(), g.clone(), g],
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hypot_gradient_is_bounded_at_the_origin() {
        // Over points: the exact gradient away from 0, a bounded one at 0.
        let (x, y) = (Dual::var(3.0, 0), Dual::var(4.0, 1));
        let h = x.hypot(&y);
        assert!((h.v - 5.0).abs() < 1e-15 && (h.g[0] - 0.6).abs() < 1e-15);
        assert!((h.g[1] - 0.8).abs() < 1e-15 && h.g[2] == 0.0);
        let h0 = Dual::var(0.0, 0).hypot(&Dual::var(0.0, 1));
        assert_eq!((h0.v, h0.g), (0.0, [0.0; 3]));
    }

    #[test]
    fn dual_gradient_of_a_product() {
        // f = x^2 y + sin z: grad = (2xy, x^2, cos z)
        let (x, y, z) = (Dual::var(1.5, 0), Dual::var(-2.0, 1), Dual::var(0.3, 2));
        let f = x.sqr() * y + z.sin();
        assert!((f.g[0] - 2.0 * 1.5 * -2.0).abs() < 1e-12);
        assert!((f.g[1] - 2.25).abs() < 1e-12);
        assert!((f.g[2] - 0.3f64.cos()).abs() < 1e-12);
    }
}
