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
//!   slice box widened by [`TileShapes::pad`] (the exact rule alone, nothing folded by
//!   sign), for shading: a group of shading samples whose box lies inside one of these
//!   boxes (checked, see [`TileShapes::values_for`]) is shaded from it, as it would be
//!   from the whole shape.

use crate::search::cull::Culler;
use crate::shape::{Aabb, Shape};
use arith_core::Range;
use arith_ia::Interval;
use glam::DVec3;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::Arc;

/// Depth slices of a node's region: more make the union of the boxes hug the rays (a
/// box of a long oblique bundle spans much of the domain) and cost one more range
/// evaluation per node.
pub const TILE_SLICES: usize = 16;

/// One tile's shapes (see the module doc); `None` stands for the whole shape.
#[derive(Debug)]
pub struct TileShapes<S> {
    /// For root finding and culling in the tile.
    pub search: Option<Arc<S>>,
    /// Per slice: the widened box and its value shape.
    values: Vec<Option<(Aabb, Option<Arc<S>>)>>,
}

impl<S> TileShapes<S> {
    /// The slice whose widened box holds the box `[lo, hi]`, if one does.
    pub fn slice_for(&self, lo: DVec3, hi: DVec3) -> Option<usize> {
        self.values.iter().position(|v| {
            v.as_ref()
                .is_some_and(|(b, _)| b.min.cmple(lo).all() && hi.cmple(b.max).all())
        })
    }

    /// Slice `k`'s widened box and its shape with the whole shape's values there
    /// (`None`: the whole shape's).
    pub fn slice(&self, k: usize) -> Option<(&Aabb, Option<&S>)> {
        self.values.get(k)?.as_ref().map(|(b, s)| (b, s.as_deref()))
    }

    /// The number of slices.
    pub fn slices(&self) -> usize {
        self.values.len()
    }
}

/// The boxes' sides as intervals.
pub fn ranges(b: &Aabb) -> [Interval; 3] {
    core::array::from_fn(|k| Interval::from_interval(b.min[k], b.max[k]))
}

/// A tile's corner and its shapes.
type Leaf<S> = ((u32, u32), TileShapes<S>);

/// A quadtree node's shapes while the tree is built: `None` where the whole shape's.
struct Node<S> {
    search: Option<Arc<S>>,
    values: Vec<Option<Arc<S>>>,
}

/// The shapes of every tile of `tiles` (rectangles of side `tile` on a grid from the
/// image's origin, as the renderer cuts them), in that order, and the number of range
/// evaluations spent. `pad` is how far the value boxes reach past the slice boxes: at
/// least the size of a group of shading samples.
pub fn tile_shapes<S: Shape>(
    shape: &S,
    culler: &Culler,
    (width, height): (u32, u32),
    tile: u32,
    tiles: &[(u32, u32, u32, u32)],
    pad: f64,
) -> (Vec<TileShapes<S>>, u64) {
    let root = Node {
        search: None,
        values: vec![None; TILE_SLICES],
    };
    let cols = width.div_ceil(tile);
    let rows = height.div_ceil(tile);
    let mut leaves = Vec::with_capacity(tiles.len());
    let evals = visit(
        shape,
        culler,
        tile,
        (width, height),
        (0, 0, cols, rows),
        &root,
        pad,
        &mut leaves,
    );
    let mut by_corner: HashMap<(u32, u32), TileShapes<S>> = leaves.into_iter().collect();
    let out = tiles
        .iter()
        .map(|&(i0, j0, _, _)| {
            by_corner.remove(&(i0, j0)).unwrap_or(TileShapes {
                search: None,
                values: Vec::new(),
            })
        })
        .collect();
    (out, evals)
}

/// The node of tiles `[c0, c1) x [r0, r1)` (in tile units) from its parent's shapes:
/// pushes its leaves and gives the range evaluations spent.
#[allow(clippy::too_many_arguments)]
fn visit<S: Shape>(
    shape: &S,
    culler: &Culler,
    tile: u32,
    (width, height): (u32, u32),
    (c0, r0, c1, r1): (u32, u32, u32, u32),
    parent: &Node<S>,
    pad: f64,
    leaves: &mut Vec<Leaf<S>>,
) -> u64 {
    let rect = (
        c0 * tile,
        r0 * tile,
        (c1 * tile).min(width),
        (r1 * tile).min(height),
    );
    let boxes = culler.slice_boxes(rect, TILE_SLICES);
    let regions: Vec<[Interval; 3]> = boxes.iter().flatten().map(ranges).collect();
    let mut evals = 0u64;
    let base = parent.search.as_deref().unwrap_or(shape);
    let search = if regions.is_empty() || !base.specialises() {
        parent.search.clone()
    } else {
        evals += regions.len() as u64;
        base.specialise(&regions)
            .map(Arc::new)
            .or_else(|| parent.search.clone())
    };
    let widened: Vec<Option<Aabb>> = boxes
        .iter()
        .map(|b| b.map(|b| Aabb::new(b.min - DVec3::splat(pad), b.max + DVec3::splat(pad))))
        .collect();
    let values: Vec<Option<Arc<S>>> = widened
        .iter()
        .zip(&parent.values)
        .map(|(b, up)| {
            let b = b.as_ref()?;
            let base = up.as_deref().unwrap_or(shape);
            if !base.specialises() {
                return up.clone();
            }
            evals += 1;
            base.specialise_values(&ranges(b), f64::INFINITY)
                .map(Arc::new)
                .or_else(|| up.clone())
        })
        .collect();
    let node = Node { search, values };
    if c1 - c0 <= 1 && r1 - r0 <= 1 {
        leaves.push((
            (rect.0, rect.1),
            TileShapes {
                search: node.search,
                values: widened
                    .into_iter()
                    .zip(node.values)
                    .map(|(b, s)| Some((b?, s)))
                    .collect(),
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
            let e = visit(
                shape,
                culler,
                tile,
                (width, height),
                q,
                &node,
                pad,
                &mut mine,
            );
            (e, mine)
        })
        .collect();
    for (e, mine) in parts {
        evals += e;
        leaves.extend(mine);
    }
    evals
}
