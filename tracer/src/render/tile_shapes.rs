//! Tile shapes: the shape specialised ([`Shape::specialise`]) down a quadtree of the
//! image before any tile is traced, so that each tile starts from a shape that keeps
//! only what its own rays can meet. Without it every tile's culling starts from the
//! whole tape, and a scene of many primitives pays the whole tape's length once per
//! tile and depth slice; down the quadtree each level starts from its parent's much
//! shorter shape.
//!
//! A node's region is the box of its pixels' rays in each of [`TILE_SLICES`] slices of
//! the domain's depth ([`Culler::slice_boxes`]: the same slices at every level, so a
//! child's boxes lie in its parent's). Each node keeps two things:
//!
//! - a **search** shape over the union of its slice boxes, with the sign of the whole
//!   shape there: every ray of the tile inside the domain, and every cell and segment
//!   culling tests, lies in that union, so it serves root finding and culling;
//! - per slice, a **value** shape with the whole shape's value at every point of the
//!   slice box widened by the shading pad (the exact rule alone, nothing folded by
//!   sign), for shading: a group of shading samples whose box lies inside one of these
//!   boxes (checked, see [`TileShapes::slice_for`]) is shaded from it, as it would be
//!   from the whole shape, where the shape folded by level does not serve (see
//!   [`crate::render::value_tree`]).
//!
//! Search shapes are built for every node before the tiles are traced; value shapes
//! only when shading first asks for one (and then its ancestors' for that slice), since
//! most slices of most tiles hold no hit: on a scene of 10000 balls at 512x512, 197 of
//! the 1024 leaf slices are shaded from.

use crate::search::cull::Culler;
use arith_core::Range;
use arith_ia::Interval;
use glam::DVec3;
use model_ir::shape::{Aabb, Shape};
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, OnceLock};

/// Depth slices of a node's region: more make the union of the boxes hug the rays (a
/// box of a long oblique bundle spans much of the domain) and cost one more range
/// evaluation per node.
pub const TILE_SLICES: usize = 16;

/// One tile's shapes (see the module doc); `None` stands for the whole shape.
#[derive(Debug)]
pub struct TileShapes<S> {
    /// For root finding and culling in the tile.
    pub search: Option<Arc<S>>,
    /// The value shapes of the tile's own node (none where the tile has none).
    values: Option<Arc<ValueNode<S>>>,
}

/// A quadtree node's value shapes, each built on first use from its parent's.
#[derive(Debug)]
struct ValueNode<S> {
    parent: Option<Arc<ValueNode<S>>>,
    /// Per slice: the widened box (`None`: the slice has no points).
    boxes: Vec<Option<Aabb>>,
    /// Per slice: the value shape once built (`None` inside: the whole shape's).
    shapes: Vec<OnceLock<Option<Arc<S>>>>,
    /// Range evaluations spent on value shapes, shared by the whole tree.
    evals: Arc<AtomicU64>,
}

impl<S: Shape> ValueNode<S> {
    /// Slice `k`'s value shape (`None`: the whole shape `root`'s values).
    fn shape(&self, root: &S, k: usize) -> Option<&Arc<S>> {
        self.shapes[k]
            .get_or_init(|| {
                let up = self.parent.as_ref().and_then(|p| p.shape(root, k)).cloned();
                let Some(b) = self.boxes[k] else {
                    return up;
                };
                let base = up.as_deref().unwrap_or(root);
                if !base.specialises_values() {
                    return up;
                }
                self.evals.fetch_add(1, Ordering::Relaxed);
                base.specialise_values(&ranges(&b), f64::INFINITY)
                    .map(Arc::new)
                    .or(up)
            })
            .as_ref()
    }
}

impl<S: Shape> TileShapes<S> {
    /// The slice whose widened box holds the box `[lo, hi]`, if one does.
    pub fn slice_for(&self, lo: DVec3, hi: DVec3) -> Option<usize> {
        self.values.as_ref()?.boxes.iter().position(|b| {
            b.as_ref()
                .is_some_and(|b| b.min.cmple(lo).all() && hi.cmple(b.max).all())
        })
    }

    /// Slice `k`'s widened box (`None`: the slice has no points).
    pub fn slice_box(&self, k: usize) -> Option<&Aabb> {
        self.values.as_ref()?.boxes.get(k)?.as_ref()
    }

    /// Slice `k`'s widened box and its shape with the values of the whole shape `root`
    /// there (`None`: `root`'s own), built on first use.
    pub fn slice<'a>(&'a self, root: &S, k: usize) -> Option<(&'a Aabb, Option<&'a S>)> {
        let node = self.values.as_ref()?;
        let b = node.boxes.get(k)?.as_ref()?;
        Some((b, node.shape(root, k).map(|s| &**s)))
    }

    /// Slice `k`'s shape with the values of the whole shape `root` there (`root`
    /// itself where there is none), built on first use.
    pub fn values_in<'a>(&'a self, root: &'a S, k: usize) -> &'a S {
        self.slice(root, k).and_then(|s| s.1).unwrap_or(root)
    }

    /// The number of slices.
    pub fn slices(&self) -> usize {
        self.values.as_ref().map_or(0, |v| v.boxes.len())
    }
}

/// The boxes' sides as intervals.
pub fn ranges(b: &Aabb) -> [Interval; 3] {
    core::array::from_fn(|k| Interval::from_interval(b.min[k], b.max[k]))
}

/// A tile's corner and its shapes.
type Leaf<S> = ((u32, u32), TileShapes<S>);

/// The shapes of every tile of `tiles` (rectangles of side `tile` on a grid from the
/// image's origin, as the renderer cuts them), in that order; the number of range
/// evaluations spent on the search shapes; and the counter of those the value shapes
/// take as they are built. `pad` is how far the value boxes reach past the slice
/// boxes: at least the size of a group of shading samples.
pub fn tile_shapes<S: Shape>(
    shape: &S,
    culler: &Culler,
    (width, height): (u32, u32),
    tile: u32,
    tiles: &[(u32, u32, u32, u32)],
    pad: f64,
) -> (Vec<TileShapes<S>>, u64, Arc<AtomicU64>) {
    let cols = width.div_ceil(tile);
    let rows = height.div_ceil(tile);
    let mut leaves = Vec::with_capacity(tiles.len());
    let counter = Arc::new(AtomicU64::new(0));
    let tree = Tree {
        shape,
        culler,
        tile,
        size: (width, height),
        pad,
        counter: &counter,
    };
    let evals = tree.visit((0, 0, cols, rows), None, None, &mut leaves);
    let mut by_corner: HashMap<(u32, u32), TileShapes<S>> = leaves.into_iter().collect();
    let out = tiles
        .iter()
        .map(|&(i0, j0, _, _)| {
            by_corner.remove(&(i0, j0)).unwrap_or(TileShapes {
                search: None,
                values: None,
            })
        })
        .collect();
    (out, evals, counter)
}

/// What every node of the quadtree shares.
struct Tree<'a, S> {
    shape: &'a S,
    culler: &'a Culler,
    tile: u32,
    size: (u32, u32),
    pad: f64,
    counter: &'a Arc<AtomicU64>,
}

impl<S: Shape> Tree<'_, S> {
    /// The node of tiles `[c0, c1) x [r0, r1)` (in tile units) from its parent's
    /// shapes: pushes its leaves and gives the range evaluations spent on search shapes.
    fn visit(
        &self,
        (c0, r0, c1, r1): (u32, u32, u32, u32),
        search: Option<&Arc<S>>,
        values: Option<&Arc<ValueNode<S>>>,
        leaves: &mut Vec<Leaf<S>>,
    ) -> u64 {
        let (width, height) = self.size;
        let rect = (
            c0 * self.tile,
            r0 * self.tile,
            (c1 * self.tile).min(width),
            (r1 * self.tile).min(height),
        );
        let boxes = self.culler.slice_boxes(rect, TILE_SLICES);
        let regions: Vec<[Interval; 3]> = boxes.iter().flatten().map(ranges).collect();
        let mut evals = 0u64;
        let base = search.map_or(self.shape, |s| &**s);
        let search = if regions.is_empty() || !base.specialises() {
            search.cloned()
        } else {
            evals += regions.len() as u64;
            base.specialise(&regions)
                .map(Arc::new)
                .or_else(|| search.cloned())
        };
        let pad = DVec3::splat(self.pad);
        let boxes: Vec<Option<Aabb>> = boxes
            .iter()
            .map(|b| b.map(|b| Aabb::new(b.min - pad, b.max + pad)))
            .collect();
        let node = Arc::new(ValueNode {
            parent: values.cloned(),
            shapes: boxes.iter().map(|_| OnceLock::new()).collect(),
            boxes,
            evals: self.counter.clone(),
        });
        if c1 - c0 <= 1 && r1 - r0 <= 1 {
            leaves.push((
                (rect.0, rect.1),
                TileShapes {
                    search,
                    values: Some(node),
                },
            ));
            return evals;
        }
        let (cm, rm) = (c0 + (c1 - c0).div_ceil(2), r0 + (r1 - r0).div_ceil(2));
        let quads: Vec<(u32, u32, u32, u32)> = [(c0, cm), (cm, c1)]
            .into_iter()
            .flat_map(|(a0, a1)| [(r0, rm), (rm, r1)].map(|(b0, b1)| (a0, b0, a1, b1)))
            .filter(|&(a0, b0, a1, b1)| a0 < a1 && b0 < b1)
            .collect();
        let parts: Vec<(u64, Vec<Leaf<S>>)> = quads
            .into_par_iter()
            .map(|q| {
                let mut mine = Vec::new();
                let e = self.visit(q, search.as_ref(), Some(&node), &mut mine);
                (e, mine)
            })
            .collect();
        for (e, mine) in parts {
            evals += e;
            leaves.extend(mine);
        }
        evals
    }
}
