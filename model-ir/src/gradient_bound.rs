//! Lipschitz bounds of a shape from the range of its gradient: one evaluation over
//! [`Dual`]`<Interval>` on a box encloses `grad f` there, and the maximum over sub-boxes
//! bounds `|grad f|` over the domain. Used by models that carry no bound of their own and
//! by the previewer.

use crate::shape::{Aabb, Shape};
use arith_core::dual::Dual;
use arith_core::round::{add_up, mul_up, up};
use arith_core::Range;
use glam::DVec3;

/// An upper bound of `|grad f|` over the box `b`, from one evaluation over
/// `Dual<Interval>`: `sqrt(sum_k max(|lo_k|, |hi_k|)^2)`, rounded up (`+inf` when the
/// enclosure is unbounded).
pub fn gradient_bound_on_box<S: Shape + ?Sized>(s: &S, b: &Aabb) -> f64 {
    use arith_ia::Interval;
    let x = Dual::var(Interval::input(0, b.min.x, b.max.x), 0);
    let y = Dual::var(Interval::input(1, b.min.y, b.max.y), 1);
    let z = Dual::var(Interval::input(2, b.min.z, b.max.z), 2);
    let f = s.eval(x, y, z);
    let mut acc = 0.0f64;
    for g in &f.g {
        let (lo, hi) = g.bounds();
        let m = lo.abs().max(hi.abs());
        if !m.is_finite() {
            return f64::INFINITY;
        }
        acc = add_up(acc, mul_up(m, m));
    }
    up(acc.sqrt())
}

/// An automatic Lipschitz bound of `f` over `b`: the maximum of
/// [`gradient_bound_on_box`] over `n^3` sub-boxes. Sound for continuous, piecewise smooth
/// `f` (a segment between two points of the convex box crosses sub-boxes, in each of
/// which the gradient's norm is bounded).
pub fn auto_lipschitz<S: Shape + ?Sized>(s: &S, b: &Aabb, n: usize) -> f64 {
    let n = n.max(1);
    let size = (b.max - b.min) / n as f64;
    let mut best = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let lo = b.min + size * DVec3::new(i as f64, j as f64, k as f64);
                // The last sub-box ends exactly at the domain's corner.
                let hi = DVec3::new(
                    if i + 1 == n { b.max.x } else { lo.x + size.x },
                    if j + 1 == n { b.max.y } else { lo.y + size.y },
                    if k + 1 == n { b.max.z } else { lo.z + size.z },
                );
                let sub = Aabb::new(lo, hi.max(lo));
                best = best.max(gradient_bound_on_box(s, &sub));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::Real;

    struct Sphere;
    impl Shape for Sphere {
        fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
            (x.sqr() + y.sqr() + z.sqr()).sqrt().rsub(1.0)
        }
    }

    #[test]
    fn auto_bound_of_the_unit_sphere_function_is_at_least_one() {
        // |grad| = 1 away from the origin; the box holding the origin gives infinity.
        let l = auto_lipschitz(&Sphere, &Aabb::new(DVec3::splat(0.5), DVec3::splat(1.5)), 2);
        assert!((1.0..3.5).contains(&l), "{l}");
    }

    /// R-function intersection of two balls: `hypot` has a kink where both operands are
    /// 0, yet the bound is finite (the chain rule through `sqrt` would divide by a range
    /// reaching 0) and at least the gradient's norm at sampled points.
    #[test]
    fn r_function_bound_is_finite_and_above_the_gradient() {
        struct Lens;
        impl Shape for Lens {
            fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
                let a = (x.clone() - 0.5).sqr() + y.sqr() + z.sqr();
                let b = (x + 0.5).sqr() + y.sqr() + z.sqr();
                arith_core::rfunc::intersect(a.rsub(1.0), b.rsub(1.0))
            }
        }
        let dom = Aabb::cube(1.5);
        let l = auto_lipschitz(&Lens, &dom, 8);
        assert!(l.is_finite(), "{l}");
        for i in 0..=20 {
            for j in 0..=20 {
                let p = DVec3::new(-1.5 + 0.15 * i as f64, -1.5 + 0.15 * j as f64, 0.1);
                let d = Lens.eval(Dual::var(p.x, 0), Dual::var(p.y, 1), Dual::var(p.z, 2));
                let n = (d.g[0].powi(2) + d.g[1].powi(2) + d.g[2].powi(2)).sqrt();
                assert!(n <= l, "|grad| {n} above the bound {l} at {p}");
            }
        }
    }
}
