//! Every branch gradient of a shape at a point where its `min`/`max` branches are
//! (nearly) tied: the planes of the sheets that meet at a sharp feature (a crease or a
//! corner of CSG), as libfive's feature evaluator gives them to its QEF.
//!
//! Dual contouring places a vertex where the planes of its crossings meet. One
//! gradient per crossing is the plane of the sheet the crossing lies on; where a crease
//! runs through a cell but the cell's edges happen to cross only one of its sheets, the
//! other sheet's plane is missing and the vertex lands beside the crease (the mesh
//! chamfers it). The shape is any [`Shape`], written against [`Real`], so the branches
//! are found by evaluating it over [`Tied`], a dual number whose `min` and `max` take
//! the side that a *choice mask* says wherever their two arguments lie within a
//! tolerance of each other (a tie), and the usual side elsewhere. The ties are numbered
//! in the order the evaluation meets them; every combination of choices of the first
//! [`MAX_TIES`] ties is evaluated, and each gives the value and gradient of one
//! branch. `abs`, `step` and `select` are not enumerated (their kinks lie on the
//! surface only for degenerate models).
//!
//! The choices live in a thread-local script, since [`Real`] values are created without
//! a context (constants); one evaluation runs on one thread from start to end.

use arith_core::branch::Step;
use arith_core::dual::Dual;
use arith_core::{Known, Real};
use core::ops::{Add, Div, Mul, Neg, Sub};
use glam::DVec3;
use model_ir::shape::Shape;
use std::cell::Cell;

/// Ties enumerated at most (so at most `2^MAX_TIES` evaluations, branches).
pub const MAX_TIES: u32 = 3;

/// One branch of the shape at a point: its value and gradient there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Branch {
    /// The branch's value at the point (0 on its own sheet).
    pub v: f64,
    /// Its gradient.
    pub g: DVec3,
}

impl Branch {
    /// The branch's sheet near `p` (its first-order zero set), as a point on it and its
    /// unit outward normal (towards `f < 0`).
    pub fn plane(&self, p: DVec3) -> (DVec3, DVec3) {
        let len2 = self.g.length_squared();
        (p - self.g * (self.v / len2), -self.g / len2.sqrt())
    }

    /// Whether this branch's sheet meets the plane through `p` with unit normal `n`
    /// (the crossing's own sheet) along a line that passes through the box `[lo, hi]`:
    /// a crease in the box. Parallel sheets have no crease.
    pub fn crease_meets(&self, p: DVec3, n: DVec3, lo: DVec3, hi: DVec3) -> bool {
        let (q, u) = self.plane(p);
        let d = n.cross(u);
        let det = d.length_squared();
        // NaN (a degenerate gradient) has no crease either.
        if det.is_nan() || det <= 1e-12 {
            return false;
        }
        // The line's point p + a n + b u with n.(x - p) = 0 and u.(x - p) = u.(q - p).
        let c = u.dot(q - p);
        let nu = n.dot(u);
        let x0 = p + n * (-nu * c / det) + u * (c / det);
        let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
        for k in 0..3 {
            if d[k].abs() < 1e-300 {
                if x0[k] < lo[k] || x0[k] > hi[k] {
                    return false;
                }
                continue;
            }
            let (a, b) = ((lo[k] - x0[k]) / d[k], (hi[k] - x0[k]) / d[k]);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        t0 <= t1
    }
}

/// The branches of `shape` at `p`: first the one that the shape takes there (what a
/// plain `Dual<f64>` evaluation gives, whatever it is), then those reached by taking
/// the other side of `min`/`max` instructions whose arguments differ by at most `tol`
/// times the larger of their gradients' lengths (a distance: a sheet within about
/// `tol` of `p`). Those others are left out where their gradient is zero or not
/// finite, and so are repeats.
pub fn branches<S: Shape>(shape: &S, p: DVec3, tol: f64) -> Vec<Branch> {
    let (first, ties) = eval_with(shape, p, tol, 0);
    let mut out: Vec<Branch> = vec![first];
    let mut push = |b: Branch| {
        let ok = b.v.is_finite() && b.g.is_finite() && b.g.length() > 0.0;
        if ok && !out.iter().any(|o| same(o, &b, tol)) {
            out.push(b);
        }
    };
    for mask in 1..1u32 << ties.min(MAX_TIES) {
        push(eval_with(shape, p, tol, mask).0);
    }
    out
}

/// Whether two branches are the same plane near the point (within a part in `10^9`).
fn same(a: &Branch, b: &Branch, tol: f64) -> bool {
    let scale = a.g.length().max(b.g.length());
    (a.g - b.g).length() <= 1e-9 * scale && (a.v - b.v).abs() <= 1e-9 * scale * tol.max(1.0)
}

/// The shape at `p` with the ties' choices of `mask`, and the number of ties met.
fn eval_with<S: Shape>(shape: &S, p: DVec3, tol: f64, mask: u32) -> (Branch, u32) {
    let saved = SCRIPT.with(|s| s.replace(Script { tol, mask, seen: 0 }));
    let t = |v: f64, k: usize| Tied(Dual::var(v, k));
    let d = shape.eval(t(p.x, 0), t(p.y, 1), t(p.z, 2)).0;
    let seen = SCRIPT.with(|s| s.replace(saved)).seen;
    (
        Branch {
            v: d.v,
            g: DVec3::from(d.g),
        },
        seen,
    )
}

/// The choices of one evaluation.
#[derive(Clone, Copy, Debug)]
struct Script {
    /// The tie tolerance (a distance).
    tol: f64,
    /// Bit `i` set: the `i`-th tie takes the side not taken by a plain evaluation.
    mask: u32,
    /// Ties met so far.
    seen: u32,
}

thread_local! {
    static SCRIPT: Cell<Script> = const { Cell::new(Script { tol: 0.0, mask: 0, seen: 0 }) };
}

/// A dual number over `f64` whose `min` and `max` follow the thread's [`Script`] at
/// ties; every other operation is `Dual<f64>`'s.
#[derive(Clone, Debug, PartialEq)]
pub struct Tied(pub Dual<f64>);

impl Tied {
    /// `min` (`want_min`) or `max` of `self` and `o`, with the side swapped at a tie
    /// whose bit is set.
    fn choose(&self, o: &Self, want_min: bool) -> Self {
        let plain = self.0.v <= o.0.v; // `self` is the min (as `Dual` decides)
        let self_side = plain == want_min;
        let flip = SCRIPT.with(|s| {
            let mut sc = s.get();
            let scale = grad_len(&self.0).max(grad_len(&o.0));
            let gap = (self.0.v - o.0.v).abs();
            if !(scale.is_finite() && gap <= sc.tol * scale) {
                return false;
            }
            let i = sc.seen;
            sc.seen += 1;
            s.set(sc);
            i < 32 && sc.mask >> i & 1 == 1
        });
        let take_self = self_side != flip;
        let v = if want_min {
            self.0.v.min(o.0.v)
        } else {
            self.0.v.max(o.0.v)
        };
        let taken = if take_self { self } else { o };
        // The value of the branch taken (at a flipped tie, not the min/max itself).
        let v = if flip { taken.0.v } else { v };
        Tied(Dual { v, g: taken.0.g })
    }
}

fn grad_len(d: &Dual<f64>) -> f64 {
    DVec3::from(d.g).length()
}

macro_rules! binop {
    ($tr:ident, $f:ident) => {
        impl $tr for Tied {
            type Output = Tied;
            fn $f(self, o: Tied) -> Tied {
                Tied(self.0.$f(o.0))
            }
        }
        impl $tr<f64> for Tied {
            type Output = Tied;
            fn $f(self, c: f64) -> Tied {
                Tied(self.0.$f(c))
            }
        }
    };
}
binop!(Add, add);
binop!(Sub, sub);
binop!(Mul, mul);
binop!(Div, div);

impl Neg for Tied {
    type Output = Tied;
    fn neg(self) -> Tied {
        Tied(-self.0)
    }
}

arith_core::impl_f64_lhs_ops!(Tied);

impl Real for Tied {
    fn constant(c: f64) -> Self {
        Tied(Dual::constant(c))
    }
    fn sqr(&self) -> Self {
        Tied(self.0.sqr())
    }
    fn powi(&self, n: i32) -> Self {
        Tied(self.0.powi(n))
    }
    fn sqrt(&self) -> Self {
        Tied(self.0.sqrt())
    }
    fn hypot(&self, o: &Self) -> Self {
        Tied(self.0.hypot(&o.0))
    }
    fn recip(&self) -> Self {
        Tied(self.0.recip())
    }
    fn exp(&self) -> Self {
        Tied(self.0.exp())
    }
    fn ln(&self) -> Self {
        Tied(self.0.ln())
    }
    fn sin(&self) -> Self {
        Tied(self.0.sin())
    }
    fn cos(&self) -> Self {
        Tied(self.0.cos())
    }
    fn abs(&self) -> Self {
        Tied(self.0.abs())
    }
    fn min(&self, o: &Self) -> Self {
        self.choose(o, true)
    }
    fn max(&self, o: &Self) -> Self {
        self.choose(o, false)
    }
    fn rsub(self, c: f64) -> Self {
        Tied(self.0.rsub(c))
    }
    fn rdiv(self, c: f64) -> Self {
        Tied(self.0.rdiv(c))
    }
    fn known(&self) -> Known {
        self.0.known()
    }
    fn from_bounds(lo: f64, hi: f64) -> Option<Self> {
        <Dual<f64> as Real>::from_bounds(lo, hi).map(Tied)
    }
    fn step(&self, s: Step) -> Self {
        Tied(self.0.step(s))
    }
    fn select(&self, t: Self, e: Self) -> Self {
        Tied(self.0.select(t.0, e.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The corner of `min(x, y, z)`-style half-spaces: `min(0.3 - x, 0.3 - y, 0.3 - z)`.
    struct Corner;
    impl Shape for Corner {
        fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
            x.rsub(0.3).min(&y.rsub(0.3)).min(&z.rsub(0.3))
        }
    }

    #[test]
    fn a_corner_gives_its_three_planes() {
        let b = branches(&Corner, DVec3::new(0.3, 0.29, 0.28), 0.05);
        let gs: Vec<DVec3> = b.iter().map(|b| b.g).collect();
        assert_eq!(gs.len(), 3, "{b:?}");
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            assert!(gs.contains(&-axis), "{gs:?}");
        }
        // The first is the branch taken (x: 0.3 - x = 0 is the least).
        assert_eq!(b[0].g, -DVec3::X);
        // Each branch's value is its own: 0.3 - y = 0.01 at the point.
        let y = b.iter().find(|b| b.g == -DVec3::Y).expect("y branch");
        assert!((y.v - 0.01).abs() < 1e-15);
    }

    #[test]
    fn a_crease_is_seen_in_the_boxes_it_crosses() {
        // At (0.3, 0.29, 0.1) the sheet x = 0.3 meets y = 0.3 along x = y = 0.3.
        let p = DVec3::new(0.3, 0.29, 0.1);
        let b = branches(&Corner, p, 0.05);
        let y = b.iter().find(|b| b.g == -DVec3::Y).expect("y branch");
        let n = DVec3::X;
        assert!(y.crease_meets(p, n, DVec3::splat(0.25), DVec3::splat(0.35)));
        assert!(!y.crease_meets(p, n, DVec3::splat(0.31), DVec3::splat(0.4)));
        let (q, u) = y.plane(p);
        assert!((q.y - 0.3).abs() < 1e-15 && u == DVec3::Y, "{q} {u}");
    }

    #[test]
    fn far_branches_are_not_ties() {
        let b = branches(&Corner, DVec3::new(0.3, 0.0, 0.0), 0.05);
        assert_eq!(b.len(), 1);
        assert_eq!(b[0].g, -DVec3::X);
    }

    #[test]
    fn the_script_is_restored() {
        let _ = branches(&Corner, DVec3::splat(0.3), 1.0);
        SCRIPT.with(|s| assert_eq!((s.get().mask, s.get().seen), (0, 0)));
    }
}
