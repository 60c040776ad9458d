//! Where the surface crosses a cell edge: root isolation with the arithmetic's ray form
//! over the edge, not sampling.
//!
//! The edge is one input symbol (the ray form, [`Arithmetic::Ray`]) and `f` is
//! evaluated over it as a dual number, so one evaluation encloses both `f` and its
//! derivative along the edge. A segment whose range of `f` excludes 0 holds no root; a
//! segment whose range of the derivative excludes 0 is monotone and holds exactly one
//! root when its ends differ in sign, none otherwise (so is one whose derivative in
//! interval arithmetic has one sign, 0 allowed): the root is *isolated* and then
//! refined on point values (regula falsi with the Illinois rule, safeguarded by
//! bisection, so the bracket of a sign change shrinks at least by half every other
//! step; superlinearly where `f` is smooth). Other segments are split, down to a minimum
//! width. So every root where `f` changes sign is found, however close they lie to each
//! other (a sampling search misses pairs closer than its step), and the number of
//! sign-changing roots on the edge is known: more than one means the grid is too coarse
//! there (counted in the statistics).

use super::branches::{branches, Branch};
use super::grid::Clipped;
use arith_core::dual::Dual;
use arith_core::{Arithmetic, Range, Real};
use glam::DVec3;
use model_ir::arith::arith_ia::Interval;
use model_ir::shape::{Aabb, Shape};
use std::any::TypeId;

/// Segments narrower than this share of the edge are not split further.
const MIN_SHARE: f64 = 1.0 / (1u64 << 24) as f64;
/// At most this many range evaluations per edge (then the bracketing root is kept).
const MAX_EVALS: u32 = 400;
/// Refinement stops once the bracket is narrower than this share of the edge.
const REFINE_SHARE: f64 = 1.0 / (1u64 << 44) as f64;
/// At most this many point evaluations refine one root (bisection alone needs 44).
const REFINE_STEPS: u32 = 88;

/// Tie tolerance of [`branches`], in edge lengths: sheets within about this distance
/// of the crossing may meet it in one of the edge's cells.
pub const TIE_CELLS: f64 = 2.0;

/// A root of `f` on an edge, with the surface's normal there.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossing {
    /// The point where the sign changes.
    pub p: DVec3,
    /// The unit outward normal (towards `f < 0`) from the gradient at `p`.
    pub n: DVec3,
    /// The other branches of `f` at `p` where `min`/`max` arguments are nearly tied
    /// (the other sheets of a crease or corner near the crossing; empty elsewhere).
    pub others: Vec<Branch>,
    /// Sign-changing roots found on the edge (odd; 1 for a well-resolved edge).
    pub roots: u32,
    /// Range evaluations spent.
    pub evals: u32,
}

/// Finds the crossing on the edge from `a` (`inside` at `a`) along `axis` over length
/// `len`, of `shape` clipped to `domain`, with the other branches tied there when
/// `with_branches`. The ends must differ in sign.
pub fn crossing<A: Arithmetic, S: Shape>(
    shape: &S,
    domain: &Aabb,
    a: DVec3,
    axis: usize,
    len: f64,
    with_branches: bool,
) -> Crossing {
    let f = Clipped {
        inner: shape,
        domain: *domain,
    };
    let edge = Edge { f: &f, a, axis };
    let (roots, evals) = edge.isolate::<A>(len);
    // The first root (there is at least one: the ends differ in sign); if isolation
    // gave up on every segment, the bracket of the whole edge.
    let t = roots
        .first()
        .copied()
        .unwrap_or_else(|| edge.refine(0.0, len, len));
    let p = edge.at(t);
    let others = if with_branches {
        let mut b = branches(&f, p, TIE_CELLS * len);
        b.remove(0);
        b
    } else {
        Vec::new()
    };
    Crossing {
        p,
        n: normal(&f, p, axis, edge.inside(0.0)),
        others,
        roots: roots.len().max(1) as u32,
        evals,
    }
}

/// Whether a derivative's range `d` has one sign, 0 allowed: a weakly monotone `f`
/// changes sign once at most (`f >= 0` holds on an upper or lower part of the
/// segment). Where a crease crosses the edge and one of its sheets is level along it,
/// the derivative is the hull of that sheet's exact 0 and the other's slope: interval
/// arithmetic keeps that 0 at the range's end, where an affine form's rounding leaves
/// a hair below it (the segment would be split down to the minimum width). NaN has no
/// sign.
fn weakly_monotone(d: &Interval) -> bool {
    let (lo, hi) = d.bounds();
    lo >= 0.0 || hi <= 0.0
}

/// One edge of a shape: `a + t e_axis`.
struct Edge<'a, S> {
    f: &'a S,
    a: DVec3,
    axis: usize,
}

impl<S: Shape> Edge<'_, S> {
    fn at(&self, t: f64) -> DVec3 {
        let mut p = self.a;
        p[self.axis] += t;
        p
    }

    fn value(&self, t: f64) -> f64 {
        let p = self.at(t);
        self.f.eval(p.x, p.y, p.z)
    }

    fn inside(&self, t: f64) -> bool {
        // NaN counts as outside, as any value below 0.
        self.value(t) >= 0.0
    }

    /// `f` and its derivative along the edge over `[t0, t1]`.
    fn range<R: Range>(&self, t0: f64, t1: f64) -> Dual<R> {
        let s = R::input(0, self.a[self.axis] + t0, self.a[self.axis] + t1);
        let mut xyz: [Dual<R>; 3] = core::array::from_fn(|k| Dual::constant(0.0) + self.a[k]);
        xyz[self.axis] = Dual {
            v: s,
            g: core::array::from_fn(|k| R::constant((k == self.axis) as u8 as f64)),
        };
        let [x, y, z] = xyz;
        self.f.eval(x, y, z)
    }

    /// The sign-changing roots on `[0, len]` in increasing order, and the range
    /// evaluations spent.
    fn isolate<A: Arithmetic>(&self, len: f64) -> (Vec<f64>, u32) {
        let min_w = len * MIN_SHARE;
        let mut roots = Vec::new();
        let mut evals = 0;
        let mut todo = vec![(0.0, len, self.inside(0.0), self.inside(len))];
        while let Some((t0, t1, s0, s1)) = todo.pop() {
            if evals >= MAX_EVALS {
                if s0 != s1 {
                    roots.push(self.refine(t0, t1, len));
                }
                continue;
            }
            // Interval arithmetic first, the cheapest: where its range excludes 0 or its
            // derivative has one sign (0 allowed), the segment is decided; else the
            // arithmetic's tighter range.
            evals += 1;
            let ia = self.range::<Interval>(t0, t1);
            let one = if !ia.v.contains_zero() {
                continue;
            } else if weakly_monotone(&ia.g[self.axis]) || t1 - t0 <= min_w {
                true
            } else if TypeId::of::<A::Ray>() == TypeId::of::<Interval>() {
                false
            } else {
                evals += 1;
                let r = self.range::<A::Ray>(t0, t1);
                if !r.v.contains_zero() {
                    continue;
                }
                !r.g[self.axis].contains_zero()
            };
            if one {
                // Monotone: one root where the ends differ, none where they agree.
                if s0 != s1 {
                    roots.push(self.refine(t0, t1, len));
                }
                continue;
            }
            let tm = 0.5 * (t0 + t1);
            let sm = self.inside(tm);
            // Left half on top: roots come out in increasing order.
            todo.push((tm, t1, sm, s1));
            todo.push((t0, tm, s0, sm));
        }
        (roots, evals)
    }

    /// A point of sign change in `[t0, t1]` (whose ends differ in sign), within
    /// [`REFINE_SHARE`] of the edge's length `len`: the bracket is kept around a sign
    /// change (inside at one end, outside at the other) and cut at the regula falsi
    /// point of the values at its ends, the value kept at an end twice in a row halved
    /// (the Illinois rule); a cut that does not halve the bracket is followed by a
    /// bisection, as is a step the values cannot give (NaN, infinite, equal values).
    fn refine(&self, mut t0: f64, mut t1: f64, len: f64) -> f64 {
        let tol = len * REFINE_SHARE;
        let (mut f0, mut f1) = (self.value(t0), self.value(t1));
        let s0 = f0 >= 0.0;
        let (mut bisect, mut kept) = (false, 0i8);
        for _ in 0..REFINE_STEPS {
            let w = t1 - t0;
            if w <= tol {
                break;
            }
            let mut tm = t0 - f0 * w / (f1 - f0);
            if bisect || !(tm > t0 && tm < t1) {
                tm = 0.5 * (t0 + t1);
                if tm <= t0 || tm >= t1 {
                    break;
                }
            }
            let fm = self.value(tm);
            if (fm >= 0.0) == s0 {
                t0 = tm;
                f0 = fm;
                // t1 kept again: halve its value.
                if kept == 1 {
                    f1 *= 0.5;
                }
                kept = 1;
            } else {
                t1 = tm;
                f1 = fm;
                if kept == -1 {
                    f0 *= 0.5;
                }
                kept = -1;
            }
            bisect = !bisect && t1 - t0 > 0.5 * w;
        }
        0.5 * (t0 + t1)
    }
}

/// The unit outward normal at `p`: minus the normalised gradient of `f` (`f >= 0`
/// inside). Where the gradient is zero or not finite, the edge's direction, pointing
/// from the inside end to the outside end (`lower_inside`: the end at the lower
/// coordinate is inside).
pub fn normal<S: Shape>(f: &S, p: DVec3, axis: usize, lower_inside: bool) -> DVec3 {
    let d = f.eval(Dual::var(p.x, 0), Dual::var(p.y, 1), Dual::var(p.z, 2));
    let g = -DVec3::from(d.g);
    let len = g.length();
    if len.is_finite() && len > 0.0 {
        return g / len;
    }
    let mut e = DVec3::ZERO;
    e[axis] = if lower_inside { 1.0 } else { -1.0 };
    e
}

#[cfg(test)]
mod tests {
    use super::*;
    use model_ir::arith::arith_revaa::RevAaArith;

    /// Three parallel planes x = 0.1, 0.2, 0.3 (a sign change at each).
    struct Layers;
    impl Shape for Layers {
        fn eval<R: Real>(&self, x: R, _y: R, _z: R) -> R {
            (x.clone() - 0.1) * (x.clone() - 0.2) * (x - 0.3)
        }
    }

    #[test]
    fn a_crease_with_a_level_sheet_is_isolated_at_once() {
        // Along the edge y = 0.1 the sheet 0.3 - y is level: the min's derivative is
        // the hull of -1 and 0, which holds 0, yet f only falls.
        struct Crease;
        impl Shape for Crease {
            fn eval<R: Real>(&self, x: R, y: R, _z: R) -> R {
                x.rsub(0.5).min(&y.rsub(0.3))
            }
        }
        let domain = Aabb::cube(2.0);
        let c =
            crossing::<RevAaArith, _>(&Crease, &domain, DVec3::new(0.0, 0.1, 0.5), 0, 1.0, false);
        assert_eq!(c.roots, 1);
        assert!((c.p.x - 0.5).abs() < 1e-12, "{c:?}");
        assert!(c.evals <= 2, "{c:?}");
    }

    #[test]
    fn every_root_of_an_edge_is_found() {
        let domain = Aabb::cube(2.0);
        let c =
            crossing::<RevAaArith, _>(&Layers, &domain, DVec3::new(0.0, 0.5, 0.5), 0, 1.0, true);
        assert_eq!(c.roots, 3);
        assert!((c.p.x - 0.1).abs() < 1e-12, "{c:?}");
        // f < 0 at x = 0, rising through 0.1: the outside is towards -x.
        assert!((c.n - DVec3::new(-1.0, 0.0, 0.0)).length() < 1e-12, "{c:?}");
    }

    #[test]
    fn two_close_roots_beside_one_crossing_are_seen() {
        // (x - 0.5) ((x - 0.7)^2 - 1e-6): roots 0.5, 0.699, 0.701 on [0, 1].
        struct Close;
        impl Shape for Close {
            fn eval<R: Real>(&self, x: R, _y: R, _z: R) -> R {
                (x.clone() - 0.5) * ((x - 0.7).sqr() - 1e-6)
            }
        }
        let domain = Aabb::cube(2.0);
        let c = crossing::<RevAaArith, _>(&Close, &domain, DVec3::ZERO, 0, 1.0, true);
        assert_eq!(c.roots, 3);
    }
}
