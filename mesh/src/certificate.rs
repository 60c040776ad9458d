//! The topology certificate of Plantinga and Vegter ("Isotopic approximation of
//! implicit curves and surfaces", 2004), per cell: a cell is certified when 0 is not in
//! its range of `f`, or when the ranges of the gradient over the cell have a strictly
//! positive inner product with themselves: `⟨∇f(p), ∇f(q)⟩ > 0` for every pair of
//! points `p, q` of the cell (the small normal variation condition). Then the surface
//! inside the cell is a graph over some direction, a single disk with no folds, and
//! the piece the mesher builds there has the right topology.
//!
//! The gradient's ranges come from one evaluation over dual numbers in the
//! arithmetic's cell form (`Dual<A::Cell>`, three independent symbols); the inner
//! product's lower bound is interval arithmetic over those ranges with the two factors
//! taken independent (`p` and `q` are), rounded down.

use super::grid::{cell_inputs, Clipped};
use arith_core::dual::Dual;
use arith_core::{Arithmetic, Range};
use model_ir::arith::arith_ia::IaArith;
use model_ir::shape::{Aabb, Shape};

/// The value and gradient of `shape` clipped to `domain` over the cell `b`, in the
/// arithmetic's cell form: what the certificate (and the probes' mean value form)
/// read.
pub fn cell_gradient<A: Arithmetic, S: Shape>(shape: &S, domain: &Aabb, b: &Aabb) -> Dual<A::Cell> {
    let f = Clipped {
        inner: shape,
        domain: *domain,
    };
    let [x, y, z] = cell_inputs::<A::Cell>(b);
    f.eval(Dual::var(x, 0), Dual::var(y, 1), Dual::var(z, 2))
}

/// The gradient's ranges `g` (from any arithmetic's [`cell_gradient`]) narrowed by
/// interval arithmetic's: both enclose every gradient over the cell `b`, so their
/// intersection does. Interval arithmetic keeps the exact 0 and the exact slopes of
/// the flat pieces of CSG (the hull of a wall's `[0, 0]` and another's `[10, 10]` is
/// `[0, 10]`), where an affine form's rounding leaves a hair on both sides of 0: what
/// the sign tests of [`crate::exclusion`] and [`crate::octree::monotone`] read.
pub fn narrowed_gradient<S: Shape>(
    shape: &S,
    domain: &Aabb,
    b: &Aabb,
    g: &[(f64, f64); 3],
) -> [(f64, f64); 3] {
    let ia = cell_gradient::<IaArith, S>(shape, domain, b);
    meet(&ia.g.map(|r| r.bounds()), g)
}

/// The intersection of two enclosures of the same gradient's ranges (NaN on either
/// side stays NaN: no sign test passes on it).
pub fn meet(a: &[(f64, f64); 3], b: &[(f64, f64); 3]) -> [(f64, f64); 3] {
    core::array::from_fn(|k| {
        let ((l0, h0), (l1, h1)) = (a[k], b[k]);
        if l0.is_nan() || h0.is_nan() || l1.is_nan() || h1.is_nan() {
            (f64::NAN, f64::NAN)
        } else {
            (l0.max(l1), h0.min(h1))
        }
    })
}

/// Whether the value `v` and gradient ranges `g` of a cell (in any arithmetic)
/// certify it: 0 is not in `v`, or the inner product's lower bound is positive.
pub fn certifies<R: Range>(v: &R, g: &[(f64, f64); 3]) -> bool {
    !v.contains_zero() || inner_product_lower_bound(g) > 0.0
}

/// Whether the cell `b` of `shape` clipped to `domain` is certified.
pub fn certified<A: Arithmetic, S: Shape>(shape: &S, domain: &Aabb, b: &Aabb) -> bool {
    let d = cell_gradient::<A, S>(shape, domain, b);
    certifies(&d.v, &d.g.map(|r| r.bounds()))
}

/// A lower bound of `⟨u, v⟩` over `u, v` in the box `g` (each component `[lo, hi]`),
/// rounded down (NaN and infinite bounds give `-inf`).
pub fn inner_product_lower_bound(g: &[(f64, f64); 3]) -> f64 {
    let mut sum = 0.0f64;
    for &(lo, hi) in g {
        // min of x * y over x, y in [lo, hi].
        let m = (lo * lo).min(lo * hi).min(hi * hi);
        if m.is_nan() {
            return f64::NEG_INFINITY;
        }
        sum += m;
    }
    // Three products and two sums, each within half an ulp: step down by a few ulps'
    // worth, relative to the largest term.
    let scale: f64 = g
        .iter()
        .map(|&(lo, hi)| lo.abs().max(hi.abs()).powi(2))
        .sum();
    let r = sum - 8.0 * f64::EPSILON * scale;
    if r.is_nan() {
        f64::NEG_INFINITY
    } else {
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::Real;
    use glam::DVec3;
    use model_ir::arith::arith_revaa::RevAaArith;

    struct Ball;
    impl Shape for Ball {
        fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
            (x.sqr() + y.sqr() + z.sqr()).rsub(1.0)
        }
    }

    #[test]
    fn small_cells_on_a_sphere_are_certified_but_not_its_centre() {
        let d = Aabb::cube(2.0);
        let on = Aabb::new(DVec3::new(0.95, -0.05, -0.05), DVec3::new(1.05, 0.05, 0.05));
        assert!(certified::<RevAaArith, _>(&Ball, &d, &on));
        let centre = Aabb::cube(0.1);
        // Every direction of gradient meets here (and 0 is not in its range of f: 1 - r²
        // > 0, so the cell is certified as empty of surface).
        assert!(certified::<RevAaArith, _>(&Ball, &d, &centre));
        let big = Aabb::new(DVec3::new(0.0, -1.1, -0.2), DVec3::new(1.1, 1.1, 0.2));
        assert!(!certified::<RevAaArith, _>(&Ball, &d, &big));
    }

    #[test]
    fn the_bound_is_below_every_product() {
        let g = [(-0.5, 2.0), (1.0, 1.5), (-3.0, -2.0)];
        let lb = inner_product_lower_bound(&g);
        for a in [-0.5, 0.0, 2.0] {
            for b in [-0.5, 2.0] {
                for c in [1.0, 1.5] {
                    for e in [-3.0, -2.0] {
                        let v = a * b + c * c + e * e;
                        assert!(lb <= v);
                    }
                }
            }
        }
        assert!(lb > 0.0);
    }
}
