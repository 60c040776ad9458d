//! Value trees: a shape folded by level for shading ([`Shape::specialise_values`]) over
//! a box, and below it a binary tree of overlapping halves of the box, each folded again
//! from its parent on first use. A tile's slice box is a few tenths of the domain wide,
//! so its folded shape still holds every primitive that comes within the level of 0
//! anywhere in it (on 10000 balls, a few thousand instructions), while a group of
//! shading samples spans a few pixels: without the tree each group specialised that
//! long shape over its own box.
//!
//! Each node's box lies inside its parent's, and folding a folded shape again with the
//! same level over a region inside its own keeps its values wherever they lie within
//! the level (see [`Shape::specialise_values`]), so a node's shape serves any samples
//! inside its box exactly as the root's does. The halves overlap (each is 5/8 of its
//! parent along the longest side), so that a box up to a quarter of that side wide
//! always fits one.

use crate::render::tile_shapes::ranges;
use glam::DVec3;
use model_ir::shape::{Aabb, Shape};

/// Below this many instructions a node's shape is not split further: one more fold
/// costs about as much as the evaluations it would save.
pub const MIN_SPLIT_LEN: usize = 64;

/// The deepest a tree goes (each level shrinks one side to 5/8).
pub const MAX_DEPTH: u32 = 24;

/// One node: its box and its shape (`None`: its parent's), its halves once built.
#[derive(Debug)]
struct Node<S> {
    bx: Aabb,
    shape: Option<S>,
    halves: [Option<Box<Node<S>>>; 2],
}

/// A folded shape over a box and its halves (see the module doc).
#[derive(Debug)]
pub struct ValueTree<S> {
    root: Node<S>,
    within: f64,
    /// Folds run, and the instructions their range evaluations ran, not yet counted.
    folds: u64,
    ops: u64,
}

impl<S: Shape> ValueTree<S> {
    /// `base` (whose values hold in `bx`) folded by the level `within` over `bx`.
    pub fn new(base: &S, bx: Aabb, within: f64) -> Self {
        let (mut folds, mut ops) = (0, 0);
        let shape = fold(base, &bx, within, (&mut folds, &mut ops));
        ValueTree {
            root: Node {
                bx,
                shape,
                halves: [None, None],
            },
            within,
            folds,
            ops,
        }
    }

    /// The shape of the smallest node (built where it is not yet) whose box holds
    /// `[lo, hi]`; `base` is the shape the tree was made from. Where the root's box
    /// does not hold it, `base` itself.
    pub fn at<'a>(&'a mut self, base: &'a S, lo: DVec3, hi: DVec3) -> &'a S {
        let inside = |b: &Aabb| b.min.cmple(lo).all() && hi.cmple(b.max).all();
        if !inside(&self.root.bx) {
            return base;
        }
        let ValueTree {
            root,
            within,
            folds,
            ops,
        } = self;
        let (mut node, mut up): (&'a mut Node<S>, &'a S) = (root, base);
        for depth in 0.. {
            let Node {
                bx,
                shape,
                halves: kids,
            } = node;
            let shape: &'a Option<S> = shape;
            let here = shape.as_ref().unwrap_or(up);
            if depth == MAX_DEPTH || here.tape_len().is_none_or(|n| n < MIN_SPLIT_LEN) {
                return here;
            }
            let parts = halves(bx);
            // The half the box lies in (the one on its centre's side first).
            let axis = longest(bx);
            let first = usize::from(lo[axis] + hi[axis] > bx.min[axis] + bx.max[axis]);
            let Some(c) = [first, 1 - first].into_iter().find(|&c| inside(&parts[c])) else {
                return here;
            };
            let kid = kids[c].get_or_insert_with(|| {
                Box::new(Node {
                    bx: parts[c],
                    shape: fold(here, &parts[c], *within, (&mut *folds, &mut *ops)),
                    halves: [None, None],
                })
            });
            (node, up) = (&mut **kid, here);
        }
        unreachable!("the loop returns at MAX_DEPTH")
    }

    /// The folds run and the instructions their range evaluations ran since the last
    /// call.
    pub fn take_counts(&mut self) -> (u64, u64) {
        (
            std::mem::take(&mut self.folds),
            std::mem::take(&mut self.ops),
        )
    }
}

/// `base` folded by the level `within` over `bx` (`None`: no shorter), counted.
fn fold<S: Shape>(
    base: &S,
    bx: &Aabb,
    within: f64,
    (folds, ops): (&mut u64, &mut u64),
) -> Option<S> {
    if !base.specialises_values() {
        return None;
    }
    *folds += 1;
    *ops += base.tape_len().unwrap_or(0) as u64;
    base.specialise_values(&ranges(bx), within)
}

/// The axis of `b`'s longest side.
fn longest(b: &Aabb) -> usize {
    let d = b.max - b.min;
    if d.x >= d.y && d.x >= d.z {
        0
    } else if d.y >= d.z {
        1
    } else {
        2
    }
}

/// The two overlapping halves of `b` along its longest side, each 5/8 of it, inside
/// `b` whatever the rounding.
fn halves(b: &Aabb) -> [Aabb; 2] {
    let k = longest(b);
    let w = (b.max[k] - b.min[k]) * 0.625;
    let (mut lower, mut upper) = (*b, *b);
    lower.max[k] = (b.min[k] + w).min(b.max[k]);
    upper.min[k] = (b.max[k] - w).max(b.min[k]);
    [lower, upper]
}

#[cfg(test)]
mod tests {
    use super::*;
    use model_sources::formula::parse;

    /// A row of balls along x, 0.5 apart, radius 0.1 (`f >= 0` inside).
    fn row(n: usize) -> model_sources::formula::Tape {
        let balls: Vec<String> = (0..n)
            .map(|i| format!("(0.01 - (x - {})^2 - y^2 - z^2)", i as f64 * 0.5))
            .collect();
        let mut e = balls[0].clone();
        for b in &balls[1..] {
            e = format!("max({e}, {b})");
        }
        parse(&e).unwrap()
    }

    #[test]
    fn halves_lie_inside_and_hold_any_quarter() {
        let b = Aabb::new(DVec3::new(-1.0, 0.0, 0.3), DVec3::new(2.0, 0.5, 0.4));
        let [l, u] = halves(&b);
        for h in [l, u] {
            assert!(b.min.cmple(h.min).all() && h.max.cmple(b.max).all());
        }
        assert_eq!(l.max.x - l.min.x, 3.0 * 0.625);
        // A box a quarter of the side wide anywhere along it fits one half.
        for i in 0..=300 {
            let x0 = -1.0 + 2.25 * i as f64 / 300.0;
            let (lo, hi) = (x0, x0 + 0.75);
            assert!(
                [l, u].iter().any(|h| h.min.x <= lo && hi <= h.max.x),
                "{lo}"
            );
        }
    }

    #[test]
    fn a_small_box_gets_a_short_shape_with_the_same_values() {
        let t = row(40);
        let bx = Aabb::new(DVec3::new(-0.5, -0.5, -0.5), DVec3::new(20.0, 0.5, 0.5));
        let within = 0.02;
        let mut tree = ValueTree::new(&t, bx, within);
        let root_len = tree.root.shape.as_ref().map_or(t.len(), |s| s.len());
        // Around the ball at x = 7.
        let (lo, hi) = (DVec3::new(6.95, -0.05, -0.05), DVec3::new(7.05, 0.05, 0.05));
        let s = tree.at(&t, lo, hi);
        assert!(s.len() * 4 < root_len, "{} of {root_len}", s.len());
        for i in 0..=20 {
            let p = lo + (hi - lo) * (i as f64 / 20.0);
            let (v, w) = (s.eval(p.x, p.y, p.z), t.eval(p.x, p.y, p.z));
            if v.abs() < within {
                assert_eq!(v, w, "at {p}");
            }
        }
        let (folds, _) = tree.take_counts();
        assert!(folds > 1);
        // Built once: asking again folds nothing.
        tree.at(&t, lo, hi);
        assert_eq!(tree.take_counts().0, 0);
        // Outside the root's box: the base shape.
        let far = DVec3::new(30.0, 0.0, 0.0);
        assert_eq!(tree.at(&t, far, far).len(), t.len());
    }

    #[test]
    fn an_r_function_union_is_never_folded() {
        // The value rules fold only through `min` and `max`: a union of balls by `|`
        // has none, and each fold would run the whole tape for nothing.
        let balls: Vec<String> = (0..40)
            .map(|i| format!("(0.01 - (x - {})^2 - y^2 - z^2)", i as f64 * 0.5))
            .collect();
        let t = parse(&balls.join(" | ")).unwrap();
        assert!(t.specialises() && !t.specialises_values());
        assert!(row(40).specialises_values());
        let bx = Aabb::new(DVec3::new(-0.5, -0.5, -0.5), DVec3::new(20.0, 0.5, 0.5));
        let mut tree = ValueTree::new(&t, bx, 0.02);
        let (lo, hi) = (DVec3::new(6.95, -0.05, -0.05), DVec3::new(7.05, 0.05, 0.05));
        assert_eq!(tree.at(&t, lo, hi).len(), t.len());
        assert_eq!(tree.take_counts(), (0, 0));
    }
}
