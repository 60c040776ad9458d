//! Depth windows: a cell's shape specialised ([`Shape::specialise`]) to slices of the
//! depths its rays search, so that a segment near the front of the cell runs a tape
//! that keeps only what lies near the front. A cell's region runs from its first
//! surface to the back of the domain; one tape for all of it keeps everything along
//! the line of sight, while a ray's search spends most of its evaluations in the
//! slice that holds its first root.
//!
//! The windows are the slices and the whole range, built with the cell, and below
//! each slice a binary tree of its halves, quarters, ..., down to [`FINEST`] parts of
//! the range, each specialised from its parent's shape on first use, so that the fine
//! windows cost only where segments search them (most lie near the first surface). A segment (of a ray or of a
//! child cell's narrowing) uses the narrowest window whose depths contain it; one that
//! fits none uses the whole shape. Each window's depths lie inside the region its
//! shape was derived for (by half the culling margin at each end, far more than the
//! rounding of a ray's depth), so a shape is only ever used where it has the sign of
//! the whole one.

use arith_core::Range;
use model_ir::shape::Shape;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, OnceLock};

/// One window: its shape holds for segments whose depths lie in `[lo, hi]`.
#[derive(Debug)]
struct Window<S: ?Sized> {
    lo: f64,
    hi: f64,
    /// `None`: the whole shape.
    shape: Option<Arc<S>>,
}

/// Specialises a shape to the region of the depths `[lo, hi]`: the shorter shape and
/// the instructions the range evaluation ran, or `None` where it has no points.
pub type Refine<S> = dyn Fn(&S, f64, f64) -> Option<(Option<Arc<S>>, usize)> + Send + Sync;

/// The finest windows are one part in `FINEST` of a cell's depths.
pub const FINEST: usize = 128;

/// The slices' finer windows, built on first use: per slice a binary tree of halves,
/// down to [`FINEST`] parts of the range, each node specialised from its parent's
/// shape.
struct Fine<S: ?Sized> {
    /// The first slice's near depth, and a slice's depth.
    a: f64,
    step: f64,
    /// How far inside a window's depths segments stay.
    slack: f64,
    /// Levels of halving below each slice.
    levels: u32,
    slices: Vec<Slice<S>>,
    refine: Box<Refine<S>>,
    /// Regions evaluated and instructions run by the builds, not yet counted.
    evals: AtomicU64,
    ops: AtomicU64,
}

/// One slice of [`Fine`].
struct Slice<S: ?Sized> {
    /// `None`: the whole shape.
    shape: Option<Arc<S>>,
    /// In heap order from 2: node `n` of level `l` is part `n - 2^l` of `2^l`, its
    /// parent is `n / 2`. Allocated when a segment first reaches below the slice (most
    /// slices never see one).
    nodes: OnceLock<Box<[Node<S>]>>,
}

/// A fine window's shape, built on first use (`None`: its parent's).
type Node<S> = OnceLock<Option<Arc<S>>>;

/// A cell's shape specialised to depth windows (see the module doc): the shape over the
/// whole range, which the cell's children specialise further, and the narrower ones.
pub struct Windows<S: ?Sized> {
    /// Narrowest first, the whole range last.
    list: Vec<Window<S>>,
    fine: Option<Fine<S>>,
}

impl<S: ?Sized> std::fmt::Debug for Windows<S> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Windows")
            .field("windows", &self.list.len())
            .field("fine", &self.fine.is_some())
            .finish()
    }
}

impl<S: ?Sized> Windows<S> {
    /// The shape for the segment at depths `[s0, s1]`: the narrowest window's that
    /// contains it, else the whole shape `root`.
    #[inline]
    pub fn at<'a>(&'a self, root: &'a S, s0: f64, s1: f64) -> &'a S {
        if let Some(f) = &self.fine {
            if let Some(s) = f.at(root, s0, s1) {
                return s;
            }
        }
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

    /// The regions evaluated and instructions run by the fine windows built since the
    /// last call.
    pub fn take_counts(&self) -> (u64, u64) {
        self.fine.as_ref().map_or((0, 0), |f| {
            (
                f.evals.swap(0, Ordering::Relaxed),
                f.ops.swap(0, Ordering::Relaxed),
            )
        })
    }
}

impl<S: ?Sized> Fine<S> {
    /// The finest window below a slice that contains `[s0, s1]`, built where it is
    /// not yet; `None` where no slice contains it.
    fn at<'a>(&'a self, root: &'a S, s0: f64, s1: f64) -> Option<&'a S> {
        let x = (s0 - self.a) / self.step;
        if x.is_nan() || x < 0.0 {
            return None;
        }
        let i = x as usize;
        let slice = self.slices.get(i)?;
        let lo = self.a + self.step * i as f64;
        if !(lo + self.slack <= s0 && s1 <= lo + self.step - self.slack) {
            return None;
        }
        let mut shape = slice.shape.as_deref().unwrap_or(root);
        let count = (1usize << (self.levels + 1)).saturating_sub(2);
        let nodes = || {
            slice
                .nodes
                .get_or_init(|| (0..count).map(|_| OnceLock::new()).collect())
        };
        // Down the halves while one holds the segment.
        let mut n = 1usize;
        let (mut p, mut w) = (lo, self.step);
        for _ in 0..self.levels {
            w *= 0.5;
            let (c, q) = if s0 >= p + w {
                (2 * n + 1, p + w)
            } else {
                (2 * n, p)
            };
            if !(q + self.slack <= s0 && s1 <= q + w - self.slack) {
                break;
            }
            let parent = shape;
            let node = nodes()[c - 2].get_or_init(|| match (self.refine)(parent, q, q + w) {
                Some((s, ops)) => {
                    self.evals.fetch_add(1, Ordering::Relaxed);
                    self.ops.fetch_add(ops as u64, Ordering::Relaxed);
                    s
                }
                None => None,
            });
            // Unchanged from the parent (or without points): the parent's shape serves.
            if let Some(s) = node {
                shape = s;
            }
            (n, p) = (c, q);
        }
        Some(shape)
    }
}

impl<S: Shape> Windows<S> {
    /// `base` (the whole shape where `None`) specialised to the `k` slices of `[a, b]`
    /// (`k` a power of two) and to all of it, with the slices' finer windows to be
    /// built by `refine` (none where `None`). `region(lo, hi)` gives the inputs of a
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
        refine: Option<Box<Refine<S>>>,
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
        // The slices, then the whole range. (Their unions, pairs and fours, would
        // serve segments across a slice's edge, but cost more to build than they save
        // on long tapes: measured, 10000 balls 17% slower, the Shikki scene 8% faster.)
        let spans: Vec<(usize, usize)> = (0..k).map(|i| (i, i + 1)).chain([(0, k)]).collect();
        let groups: Vec<(usize, usize)> =
            spans.iter().map(|&(i, j)| (before[i], before[j])).collect();
        let current = base.map_or(root, |b| &**b);
        let (shapes, which) = current.specialise_groups(&regions, &groups);
        let shapes: Vec<Arc<S>> = shapes.into_iter().map(Arc::new).collect();
        let shape_of = |g: usize| match which[g] {
            Some(s) => Some(shapes[s].clone()),
            None => base.cloned(),
        };
        // A slice whose shape is the whole range's is left out: the whole one serves
        // its segments alike (and packs with them). With fine windows, every slice is
        // left out: `Fine::at` serves each segment that fits one.
        let with_fine = refine.is_some();
        let parent = |g: usize| {
            let (i, j) = spans[g];
            spans
                .iter()
                .position(|&(p, q)| q - p > j - i && p <= i && j <= q)
        };
        let list = (0..spans.len())
            .filter(|&g| {
                if with_fine {
                    g == k
                } else {
                    parent(g).is_none_or(|p| which[p] != which[g])
                }
            })
            .map(|g| {
                let (i, j) = spans[g];
                Window {
                    lo: edge(i) + slack,
                    hi: edge(j) - slack,
                    shape: shape_of(g),
                }
            })
            .collect();
        // The slices come first among the spans.
        let levels = (FINEST / k).max(1).trailing_zeros();
        let fine = refine.map(|refine| Fine {
            a,
            levels,
            step: (b - a) / k as f64,
            slack,
            slices: (0..k)
                .map(|g| Slice {
                    shape: shape_of(g),
                    nodes: OnceLock::new(),
                })
                .collect(),
            refine,
            evals: AtomicU64::new(0),
            ops: AtomicU64::new(0),
        });
        Some((Windows { list, fine }, regions.len()))
    }
}
