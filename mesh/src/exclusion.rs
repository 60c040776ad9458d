//! The tests a probe runs on a cell before splitting it, cheapest first: each either
//! proves that the cell holds no zero of `f` (it is then left, as a cell whose range
//! excludes 0), or certifies it ([`super::certificate`]), or leaves it open.
//!
//! The arithmetic's cell range is loose where `f` is built from `min`, `max` and `abs`
//! of simple primitives (the walls and flat faces of CSG): an affine form of `max(a, b)`
//! with overlapping arguments spans both. Two enclosures that are sound for every
//! shape, and tight exactly there, come first:
//! - **interval arithmetic** over the cell: `min`, `max` and `abs` of intervals are
//!   exact, so on a tape of such operations over linear or quadratic primitives the
//!   interval range is as tight as the arithmetic's, often tighter;
//! - the **mean value form** `f(c) + ∇f(cell) · (p - c)`: by the mean value theorem
//!   (Lebourg's, for the piecewise smooth `f` of `min`/`max`/`abs`, whose generalised
//!   gradients the dual numbers' hull of both branches encloses), every value of `f` on
//!   the cell lies within `Σ_i max|∂f/∂x_i| h_i / 2` of its value at the centre `c`.
//!   Its width shrinks with the square of the cell's size faster than the function's
//!   own variation, so a cell beside a surface that merely touches it is excluded a
//!   level or two below the leaf instead of at the maximum depth;
//! - the **monotone reduction**: along an axis where the gradient's range has one
//!   sign, `f` is largest on one face of the cell and smallest on the opposite one,
//!   so the range of `f` over the cell lies between its lowest value on the one face
//!   and its highest on the other (each face a box of one dimension less, pinned on
//!   every such axis: a corner where all three are). Exact on the flat faces and walls
//!   of CSG, where the mean value form is not: a plane a hair outside a cell keeps its
//!   centre's value within the form's spread at every level, so without it every
//!   sub-cell along the plane stays open down to the maximum depth.
//!
//! The gradient's ranges come from the same evaluation over `Dual<A::Cell>` that the
//! Plantinga–Vegter certificate needs, so the certificate costs nothing more. The
//! value at the centre is enclosed in interval arithmetic at a point (sound after
//! rounding), and the bound is rounded up.

use super::certificate::{cell_gradient, inner_product_lower_bound, narrowed_gradient};
use super::grid::{cell_inputs, Clipped};
use arith_core::round::{add_up, mul_up};
use arith_core::{Arithmetic, Range};
use model_ir::arith::arith_ia::Interval;
use model_ir::shape::{Aabb, Shape};

/// What the tests say about a cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// No zero of `f` in the cell: a range excludes 0.
    Excluded(Test),
    /// The Plantinga–Vegter certificate holds: any surface in the cell is one sheet
    /// without folds.
    Certified,
    /// Nothing is proved: the cell is split (or counted unresolved).
    Open,
}

/// The test that excluded a cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Test {
    /// Interval arithmetic over the cell.
    Interval,
    /// The arithmetic's cell form (the value part of the dual evaluation).
    Range,
    /// The mean value form around the cell's centre.
    MeanValue,
    /// Interval arithmetic over the faces where `f` is largest and smallest, along
    /// the axes where it is monotone.
    Monotone,
}

/// Whether the interval range of `shape` clipped to `domain` over the box `b` excludes
/// 0 (the cheapest of the tests).
pub fn interval_excludes<S: Shape>(shape: &S, domain: &Aabb, b: &Aabb) -> bool {
    let f = Clipped {
        inner: shape,
        domain: *domain,
    };
    let [x, y, z] = cell_inputs::<Interval>(b);
    !f.eval(x, y, z).contains_zero()
}

/// The tests that need the gradient, on the box `b` of `shape` clipped to `domain`:
/// the arithmetic's range, the mean value form and the certificate, from one
/// evaluation over `Dual<A::Cell>`.
pub fn gradient_verdict<A: Arithmetic, S: Shape>(shape: &S, domain: &Aabb, b: &Aabb) -> Verdict {
    let d = cell_gradient::<A, S>(shape, domain, b);
    if !d.v.contains_zero() {
        return Verdict::Excluded(Test::Range);
    }
    let g = d.g.map(|r| r.bounds());
    let f = Clipped {
        inner: shape,
        domain: *domain,
    };
    if mean_value_excludes(&f, b, &g) {
        return Verdict::Excluded(Test::MeanValue);
    }
    if monotone_excludes(&f, b, &narrowed_gradient(shape, domain, b, &g)) {
        return Verdict::Excluded(Test::Monotone);
    }
    if inner_product_lower_bound(&g) > 0.0 {
        Verdict::Certified
    } else {
        Verdict::Open
    }
}

/// Whether the mean value form excludes 0: `|f(p) - f(c)| <= Σ_i max|g_i| h_i / 2` for
/// every `p` of the box `b`, `g` enclosing the gradient over it.
fn mean_value_excludes<S: Shape>(f: &S, b: &Aabb, g: &[(f64, f64); 3]) -> bool {
    let c = (b.min + b.max) * 0.5;
    let half = [
        (b.max.x - c.x).max(c.x - b.min.x),
        (b.max.y - c.y).max(c.y - b.min.y),
        (b.max.z - c.z).max(c.z - b.min.z),
    ];
    let mut spread = 0.0f64;
    for (&(lo, hi), h) in g.iter().zip(half) {
        let m = lo.abs().max(hi.abs());
        if !m.is_finite() {
            return false;
        }
        spread = add_up(spread, mul_up(m, h));
    }
    let point = |v: f64, k: usize| Interval::input(k, v, v);
    let (lo, hi) = f.eval(point(c.x, 0), point(c.y, 1), point(c.z, 2)).bounds();
    // Written so that NaN answers "not excluded".
    lo - spread > 0.0 || hi + spread < 0.0
}

/// Whether the monotone reduction excludes 0 from `f` over the box `b`, `g` enclosing
/// the gradient over it (every generalised gradient, for the piecewise smooth `f` of
/// `min`/`max`/`abs`).
///
/// Why it is sound: let axis `i` have `g_i` within `[0, ∞)`. For `p` in `b`, move its
/// `i`-th coordinate up to `b.max[i]`: the segment stays in the box, and by the mean
/// value theorem (Lebourg's, for the Lipschitz `f` whose generalised gradients `g`
/// encloses) `f` changes by `ζ_i t` with `ζ_i >= 0` and `t >= 0`, so it does not fall.
/// Doing so on every such axis (down to `b.min[i]` where `g_i` lies within
/// `(-∞, 0]`) takes `p` to a point `q` of the box `top` (those coordinates pinned)
/// with `f(p) <= f(q)`; moving the other way, to a point of `bottom` with
/// `f(p) >= f(q')`. So `f(b)` lies within `[min f(bottom), max f(top)]`, and interval
/// arithmetic over both boxes (degenerate along the pinned axes, a point where all
/// three are) encloses that hull. Where `f` is not Lipschitz (a root reaching 0) the
/// gradient's range is unbounded and no axis is pinned; NaN pins nothing and excludes
/// nothing.
fn monotone_excludes<S: Shape>(f: &S, b: &Aabb, g: &[(f64, f64); 3]) -> bool {
    let (mut top, mut bottom) = (*b, *b);
    let mut pinned = false;
    for (i, &(lo, hi)) in g.iter().enumerate() {
        if lo >= 0.0 {
            top.min[i] = b.max[i];
            bottom.max[i] = b.min[i];
        } else if hi <= 0.0 {
            top.max[i] = b.min[i];
            bottom.min[i] = b.max[i];
        } else {
            continue;
        }
        pinned = true;
    }
    if !pinned {
        return false;
    }
    let bounds = |r: &Aabb| {
        let [x, y, z] = cell_inputs::<Interval>(r);
        f.eval(x, y, z).bounds()
    };
    // Written so that NaN answers "not excluded".
    bounds(&top).1 < 0.0 || bounds(&bottom).0 > 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::Real;
    use glam::DVec3;
    use model_ir::arith::arith_revaa::RevAaArith;

    /// `max(|x|, |y|, |z|) <= 1`: a cube of side 2 (`f >= 0` inside).
    struct Cube;
    impl Shape for Cube {
        fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
            x.abs().max(&y.abs()).max(&z.abs()).rsub(1.0)
        }
    }

    #[test]
    fn cells_beside_a_cube_s_edge_are_excluded_where_the_affine_range_is_not() {
        let d = Aabb::cube(2.0);
        let clipped = Clipped {
            inner: &Cube,
            domain: d,
        };
        // Boxes outside the cube across its edge x = y = 1, where the arguments of
        // the max overlap: the affine max spans both, the interval max is exact.
        let mut loose = 0;
        for i in 0..10 {
            let lo = DVec3::new(1.01, 0.7 + 0.05 * i as f64, -0.2);
            let b = Aabb::new(lo, lo + DVec3::new(0.3, 0.4, 0.4));
            assert!(interval_excludes(&Cube, &d, &b), "{b:?}");
            let [x, y, z] = cell_inputs::<<RevAaArith as Arithmetic>::Cell>(&b);
            loose += clipped.eval(x, y, z).contains_zero() as u32;
        }
        assert!(loose > 0, "the affine range excluded every box");
    }

    #[test]
    fn a_cell_beside_a_sphere_is_excluded_and_one_across_it_is_not() {
        struct Ball;
        impl Shape for Ball {
            fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
                (x.sqr() + y.sqr() + z.sqr()).rsub(1.0)
            }
        }
        let d = Aabb::cube(2.0);
        // Just outside the sphere, beside it.
        let c = DVec3::new(1.02, 0.0, 0.0);
        let b = Aabb::new(c - 0.01, c + 0.01);
        assert!(matches!(
            gradient_verdict::<RevAaArith, _>(&Ball, &d, &b),
            Verdict::Excluded(_)
        ));
        // Across it: never excluded, whatever the test.
        let c = DVec3::new(1.0, 0.0, 0.0);
        let b = Aabb::new(c - 0.01, c + 0.01);
        assert!(!interval_excludes(&Ball, &d, &b));
        assert!(!matches!(
            gradient_verdict::<RevAaArith, _>(&Ball, &d, &b),
            Verdict::Excluded(_)
        ));
    }

    #[test]
    fn a_cell_beside_two_walls_is_excluded_by_monotonicity_alone() {
        // Outside the edge x = z = 1 of two walls, each written with a term that is 0
        // but that interval arithmetic widens (`y - y`): the min of the two walls ties
        // across the box, so its gradient is the hull of both walls' and the mean value
        // form's spread exceeds the centre's value; f falls along x and z.
        struct Walls;
        impl Shape for Walls {
            fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
                let zero = (y.clone() - y) * 0.5;
                (z.rsub(1.0) - zero.clone()).min(&(x.rsub(1.0) - zero))
            }
        }
        let d = Aabb::cube(4.0);
        let f = Clipped {
            inner: &Walls,
            domain: d,
        };
        let b = Aabb::new(DVec3::new(1.001, 0.0, 1.001), DVec3::new(1.1, 0.5, 1.1));
        assert!(!interval_excludes(&Walls, &d, &b));
        let g = cell_gradient::<RevAaArith, _>(&Walls, &d, &b)
            .g
            .map(|r| r.bounds());
        assert!(!mean_value_excludes(&f, &b, &g), "{g:?}");
        // Interval arithmetic keeps the hull of 0 and -1 from reaching above 0.
        let g = narrowed_gradient(&Walls, &d, &b, &g);
        assert!(monotone_excludes(&f, &b, &g), "{g:?}");
        // A box the walls cross is not excluded, whatever the gradient says.
        let across = Aabb::new(DVec3::new(0.99, 0.0, 0.99), DVec3::new(1.1, 0.5, 1.1));
        let g = cell_gradient::<RevAaArith, _>(&Walls, &d, &across)
            .g
            .map(|r| r.bounds());
        assert!(!monotone_excludes(&f, &across, &g));
    }

    #[test]
    fn an_excluded_cell_holds_one_sign_at_every_sample() {
        // A saddle and a crease: over boxes swept across their zero sets, whatever a
        // test excludes has no sign change on a lattice of 6^3 points.
        struct Saddle;
        impl Shape for Saddle {
            fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
                (x.clone() * y - 0.3).min(&(z - 0.2).abs().rsub(0.5))
            }
        }
        let d = Aabb::cube(2.0);
        let clipped = Clipped {
            inner: &Saddle,
            domain: d,
        };
        let (mut excluded, mut open) = (0, 0);
        for i in 0..12 {
            for j in 0..12 {
                for size in [0.02, 0.05, 0.2] {
                    let z = 0.3 + 0.1 * ((i * j) % 5) as f64;
                    let lo = DVec3::new(-1.0 + 0.17 * i as f64, -1.0 + 0.17 * j as f64, z);
                    let b = Aabb::new(lo, lo + size);
                    let v = gradient_verdict::<RevAaArith, _>(&Saddle, &d, &b);
                    if !matches!(v, Verdict::Excluded(_)) && !interval_excludes(&Saddle, &d, &b) {
                        open += 1;
                        continue;
                    }
                    excluded += 1;
                    let mut signs = [false; 2];
                    for k in 0..216 {
                        let t = DVec3::new((k % 6) as f64, (k / 6 % 6) as f64, (k / 36) as f64);
                        let p = b.min + (b.max - b.min) * t / 5.0;
                        signs[(clipped.eval(p.x, p.y, p.z) >= 0.0) as usize] = true;
                    }
                    assert!(!(signs[0] && signs[1]), "{b:?}: {v:?}");
                }
            }
        }
        assert!(excluded > 0 && open > 0, "{excluded} excluded, {open} open");
    }
}
