//! Depth windows: a cell's shape specialised ([`Shape::specialise`]) to slices of the
//! depths its rays search, so that a segment near the front of the cell runs a tape
//! that keeps only what lies near the front. A cell's region runs from its first
//! surface to the back of the domain; one tape for all of it keeps everything along
//! the line of sight, while a ray's search spends most of its evaluations in the
//! slice that holds its first root.
//!
//! The windows are the slices and their unions in a binary tree (pairs, fours, ...,
//! the whole range). A segment (of a ray or of a child cell's narrowing) uses the
//! narrowest window whose depths contain it; one that fits none uses the whole shape.
//! Each window's depths lie inside the region its shape was derived for (by half the
//! culling margin at each end, far more than the rounding of a ray's depth), so a
//! shape is only ever used where it has the sign of the whole one.

use crate::shape::Shape;
use arith_core::Range;
use std::sync::Arc;

/// One window: its shape holds for segments whose depths lie in `[lo, hi]`.
#[derive(Debug)]
struct Window<S: ?Sized> {
    lo: f64,
    hi: f64,
    /// `None`: the whole shape.
    shape: Option<Arc<S>>,
}

/// A cell's shape specialised to depth windows (see the module doc): the shape over the
/// whole range, which the cell's children specialise further, and the narrower ones.
#[derive(Debug)]
pub struct Windows<S: ?Sized> {
    /// Narrowest first, the whole range last.
    list: Vec<Window<S>>,
}

impl<S: ?Sized> Windows<S> {
    /// The shape for the segment at depths `[s0, s1]`: the narrowest window's that
    /// contains it, else the whole shape `root`.
    #[inline]
    pub fn at<'a>(&'a self, root: &'a S, s0: f64, s1: f64) -> &'a S {
        for w in &self.list {
            if w.lo <= s0 && s1 <= w.hi {
                return w.shape.as_deref().unwrap_or(root);
            }
        }
        root
    }

    /// The shape specialised to the whole range (`None`: the whole shape), which the
    /// cell's children start from.
    pub fn whole(&self) -> Option<&Arc<S>> {
        self.list.last().and_then(|w| w.shape.as_ref())
    }
}

impl<S: Shape> Windows<S> {
    /// `base` (the whole shape where `None`) specialised to the `k` slices of `[a, b]`
    /// (`k` a power of two) and their unions. `region(lo, hi)` gives the inputs of a
    /// range over the slice's points (`None` where it has none to evaluate), and
    /// `slack` is how far inside each window's slices segments must stay. Returns the
    /// windows and the number of regions evaluated.
    pub fn build<R: Range>(
        root: &S,
        base: Option<&Arc<S>>,
        (a, b): (f64, f64),
        k: usize,
        slack: f64,
        mut region: impl FnMut(f64, f64) -> Option<[R; 3]>,
    ) -> Option<(Windows<S>, usize)> {
        debug_assert!(k.is_power_of_two());
        let edge = |i: usize| match i {
            0 => a,
            i if i == k => b,
            i => a + (b - a) * i as f64 / k as f64,
        };
        // The slices' regions, and per slice how many regions come before it (a slice
        // without points has none).
        let mut regions = Vec::with_capacity(k);
        let mut before = Vec::with_capacity(k + 1);
        for i in 0..k {
            before.push(regions.len());
            if let Some(r) = region(edge(i), edge(i + 1)) {
                regions.push(r);
            }
        }
        before.push(regions.len());
        if regions.is_empty() {
            return None;
        }
        // The tree, narrowest first: slices `[i, i + w)` for widths 1, 2, 4, ..., k.
        let mut spans = Vec::with_capacity(2 * k - 1);
        let mut w = 1;
        while w <= k {
            spans.extend((0..k).step_by(w).map(|i| (i, i + w)));
            w *= 2;
        }
        let groups: Vec<(usize, usize)> =
            spans.iter().map(|&(i, j)| (before[i], before[j])).collect();
        let current = base.map_or(root, |b| &**b);
        let (shapes, which) = current.specialise_groups(&regions, &groups);
        let shapes: Vec<Arc<S>> = shapes.into_iter().map(Arc::new).collect();
        // A window whose shape is that of the window above it is left out: the one
        // above serves its segments alike (and packs with them).
        let parent = |g: usize| {
            let (i, j) = spans[g];
            let w = 2 * (j - i);
            spans
                .iter()
                .position(|&(p, q)| q - p == w && p <= i && j <= q)
        };
        let list = (0..spans.len())
            .filter(|&g| parent(g).is_none_or(|p| which[p] != which[g]))
            .map(|g| {
                let (i, j) = spans[g];
                Window {
                    lo: edge(i) + slack,
                    hi: edge(j) - slack,
                    shape: match which[g] {
                        Some(s) => Some(shapes[s].clone()),
                        None => base.cloned(),
                    },
                }
            })
            .collect();
        Some((Windows { list }, regions.len()))
    }
}
