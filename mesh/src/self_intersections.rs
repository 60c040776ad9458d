//! Self-intersections of a triangle mesh, counted over a bounding volume hierarchy.
//!
//! A small AABB tree (median splits along the longest axis of the centroids' box) is
//! built over the triangles and traversed against itself, each pair of subtrees whose
//! boxes overlap compared once (in parallel near the root), down to the pairs of
//! triangles whose boxes overlap, each tested once. A hand-written tree rather than `bvh` or
//! `parry3d`: this is all the mesher needs, and it keeps their dependency trees out of
//! the build.
//!
//! Pair tests, in `f64` (not exact predicates: a pair that touches within rounding
//! may go either way):
//! - no shared vertex: the triangles intersect when an edge of one crosses the other
//!   (exact for triangles that are not coplanar; coplanar overlapping pairs are not
//!   counted);
//! - one shared vertex `v`: the planes meet in a line through `v`, and each triangle
//!   meets it in a segment from `v`; the triangles overlap beyond `v` when that segment
//!   leaves one triangle through the far edge, which then crosses the other triangle:
//!   the far edge of either crossing the other is the test;
//! - two shared vertices (a shared edge): they intersect only when folded onto each
//!   other, coplanar with the other vertices on the same side of the edge.

use crate::triangles::Mesh;
use glam::DVec3;
use rayon::prelude::*;

/// Triangles per leaf of the tree.
const LEAF: usize = 4;

/// Subtrees over more triangles than this build their halves in parallel.
const PARALLEL_BUILD: usize = 4096;

/// Levels of the tree whose halves are compared in parallel.
const PARALLEL_LEVELS: u32 = 8;

/// The number of intersecting pairs of triangles of `mesh`.
pub fn count(mesh: &Mesh) -> u64 {
    let tris: Vec<[DVec3; 3]> = mesh
        .triangles
        .par_iter()
        .map(|t| t.map(|i| DVec3::from(mesh.vertices[i as usize])))
        .collect();
    let boxes: Vec<(DVec3, DVec3)> = tris.par_iter().map(tri_box).collect();
    let bvh = Bvh::build(&boxes);
    if bvh.nodes.is_empty() {
        return 0;
    }
    let test = |i: usize, j: usize| {
        let (i, j) = (i.min(j), i.max(j));
        (overlap(&boxes[i], &boxes[j])
            && intersect(&mesh.triangles[i], &tris[i], &mesh.triangles[j], &tris[j])) as u64
    };
    bvh.pairs(0, 0, PARALLEL_LEVELS, &test)
}

fn tri_box(t: &[DVec3; 3]) -> (DVec3, DVec3) {
    (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]))
}

fn overlap(a: &(DVec3, DVec3), b: &(DVec3, DVec3)) -> bool {
    a.0.cmple(b.1).all() && b.0.cmple(a.1).all()
}

/// A node: its box and either two children or a range of `order`.
struct Node {
    bounds: (DVec3, DVec3),
    /// Children's indices, or `(start, end)` of `order` for a leaf.
    kids: (usize, usize),
    leaf: bool,
}

struct Bvh {
    nodes: Vec<Node>,
    order: Vec<usize>,
}

impl Bvh {
    fn build(boxes: &[(DVec3, DVec3)]) -> Bvh {
        let mut order: Vec<usize> = (0..boxes.len()).collect();
        let centres: Vec<DVec3> = boxes.par_iter().map(|b| (b.0 + b.1) * 0.5).collect();
        let nodes = if boxes.is_empty() {
            Vec::new()
        } else {
            subtree(&(boxes, &centres), &mut order, 0)
        };
        Bvh { nodes, order }
    }

    /// The sum of `test(i, j)` over the pairs of distinct triangles, one of node `a`
    /// and one of node `b` (both of it where `a == b`), whose nodes' boxes overlap:
    /// every pair once (a dual traversal of the tree, so each pair of subtrees is
    /// compared once, where a query per triangle would compare it from both sides).
    /// The first `par` levels run their halves in parallel.
    fn pairs<F: Fn(usize, usize) -> u64 + Sync>(
        &self,
        a: usize,
        b: usize,
        par: u32,
        test: &F,
    ) -> u64 {
        let (na, nb) = (&self.nodes[a], &self.nodes[b]);
        let join = |x: &(dyn Fn() -> u64 + Sync), y: &(dyn Fn() -> u64 + Sync)| {
            if par > 0 {
                let (p, q) = rayon::join(x, y);
                p + q
            } else {
                x() + y()
            }
        };
        let down = par.saturating_sub(1);
        if a == b {
            if na.leaf {
                let s = &self.order[na.kids.0..na.kids.1];
                return (0..s.len())
                    .flat_map(|i| (i + 1..s.len()).map(move |j| (i, j)))
                    .map(|(i, j)| test(s[i], s[j]))
                    .sum();
            }
            let (l, r) = na.kids;
            return join(
                &|| {
                    join(&|| self.pairs(l, l, down, test), &|| {
                        self.pairs(r, r, down, test)
                    })
                },
                &|| self.pairs(l, r, down, test),
            );
        }
        if !overlap(&na.bounds, &nb.bounds) {
            return 0;
        }
        match (na.leaf, nb.leaf) {
            (true, true) => {
                let (sa, sb) = (
                    &self.order[na.kids.0..na.kids.1],
                    &self.order[nb.kids.0..nb.kids.1],
                );
                sa.iter()
                    .flat_map(|&i| sb.iter().map(move |&j| (i, j)))
                    .map(|(i, j)| test(i, j))
                    .sum()
            }
            (false, _) => {
                let (l, r) = na.kids;
                join(&|| self.pairs(l, b, down, test), &|| {
                    self.pairs(r, b, down, test)
                })
            }
            (true, false) => {
                let (l, r) = nb.kids;
                join(&|| self.pairs(a, l, down, test), &|| {
                    self.pairs(a, r, down, test)
                })
            }
        }
    }
}

/// The nodes of the tree over `order` (positions `base..` of the whole order), its
/// root first, children's indices into the returned nodes: the halves of subtrees
/// over more than [`PARALLEL_BUILD`] triangles are built in parallel.
fn subtree(boxes: &Boxes, order: &mut [usize], base: usize) -> Vec<Node> {
    if order.len() <= PARALLEL_BUILD {
        let mut nodes = Vec::with_capacity(2 * order.len() / LEAF + 1);
        split(boxes, order, base, &mut nodes);
        return nodes;
    }
    let (bounds, mid) = partition(boxes, order);
    let (lo, hi) = order.split_at_mut(mid);
    let (l, r) = rayon::join(
        || subtree(boxes, lo, base),
        || subtree(boxes, hi, base + mid),
    );
    let mut nodes = Vec::with_capacity(1 + l.len() + r.len());
    nodes.push(Node {
        bounds,
        kids: (1, 1 + l.len()),
        leaf: false,
    });
    let right = nodes[0].kids.1;
    for (part, by) in [(l, 1), (r, right)] {
        nodes.extend(part.into_iter().map(|mut n| {
            if !n.leaf {
                n.kids = (n.kids.0 + by, n.kids.1 + by);
            }
            n
        }));
    }
    nodes
}

/// Builds the node over `order` (positions `base..` of the whole order) into `nodes`,
/// returning its index.
fn split(boxes: &Boxes, order: &mut [usize], base: usize, nodes: &mut Vec<Node>) -> usize {
    let id = nodes.len();
    if order.len() <= LEAF {
        nodes.push(Node {
            bounds: bounds(boxes, order),
            kids: (base, base + order.len()),
            leaf: true,
        });
        return id;
    }
    let (bounds, mid) = partition(boxes, order);
    nodes.push(Node {
        bounds,
        kids: (0, 0),
        leaf: false,
    });
    let (lo, hi) = order.split_at_mut(mid);
    let l = split(boxes, lo, base, nodes);
    let r = split(boxes, hi, base + mid, nodes);
    nodes[id].kids = (l, r);
    id
}

/// The triangles' boxes and the boxes' centres.
type Boxes<'a> = (&'a [(DVec3, DVec3)], &'a [DVec3]);

/// The box around the triangles of `order`.
fn bounds(boxes: &Boxes, order: &[usize]) -> (DVec3, DVec3) {
    order
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &i| {
            (lo.min(boxes.0[i].0), hi.max(boxes.0[i].1))
        })
}

/// The box around the triangles of `order`, and `order` split at its middle along the
/// longest axis of their centres' box (the lower half first): returns the middle.
fn partition(boxes: &Boxes, order: &mut [usize]) -> ((DVec3, DVec3), usize) {
    let (b, c) = *boxes;
    let inf = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    let (bounds, (clo, chi)) = order.iter().fold((inf, inf), |(bb, cb), &i| {
        (
            (bb.0.min(b[i].0), bb.1.max(b[i].1)),
            (cb.0.min(c[i]), cb.1.max(c[i])),
        )
    });
    let axis = (chi - clo).max_position();
    let mid = order.len() / 2;
    order.select_nth_unstable_by(mid, |&p, &q| c[p][axis].total_cmp(&c[q][axis]));
    (bounds, mid)
}

/// Whether triangles `a` and `b` (indices `ia`, `ib`) intersect other than in the
/// vertices and edge they share.
fn intersect(ia: &[u32; 3], a: &[DVec3; 3], ib: &[u32; 3], b: &[DVec3; 3]) -> bool {
    let mut shared = [(0, 0); 9];
    let mut n = 0;
    for (i, va) in ia.iter().enumerate() {
        for (j, vb) in ib.iter().enumerate() {
            if va == vb {
                shared[n] = (i, j);
                n += 1;
            }
        }
    }
    let shared = &shared[..n];
    match shared.len() {
        0 => {
            !one_side(a, b)
                && !one_side(b, a)
                && (0..3).any(|k| {
                    segment_hits(a[k], a[(k + 1) % 3], b) || segment_hits(b[k], b[(k + 1) % 3], a)
                })
        }
        1 => {
            let (i, j) = shared[0];
            let far_a = (a[(i + 1) % 3], a[(i + 2) % 3]);
            let far_b = (b[(j + 1) % 3], b[(j + 2) % 3]);
            segment_hits_strictly(far_a.0, far_a.1, b, b[j])
                || segment_hits_strictly(far_b.0, far_b.1, a, a[i])
        }
        2 => folded(a, b, shared),
        _ => true,
    }
}

/// Whether the vertices of `b` lie strictly on one side of the plane of `a` (then the
/// triangles do not meet; the signs are those that [`segment_hits`] computes, so only
/// pairs that touch within rounding, which may go either way, can be decided
/// differently).
fn one_side(a: &[DVec3; 3], b: &[DVec3; 3]) -> bool {
    let n = (a[1] - a[0]).cross(a[2] - a[0]);
    let d = b.map(|p| n.dot(p - a[0]));
    d.iter().all(|&v| v > 0.0) || d.iter().all(|&v| v < 0.0)
}

/// Whether the segment `p q` meets the triangle `t` (closed).
fn segment_hits(p: DVec3, q: DVec3, t: &[DVec3; 3]) -> bool {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let (dp, dq) = (n.dot(p - t[0]), n.dot(q - t[0]));
    if (dp > 0.0 && dq > 0.0) || (dp < 0.0 && dq < 0.0) || (dp == 0.0 && dq == 0.0) {
        return false;
    }
    let x = p + (q - p) * (dp / (dp - dq));
    inside_triangle(x, t, n)
}

/// [`segment_hits`], except at the shared vertex `v` of `t`.
fn segment_hits_strictly(p: DVec3, q: DVec3, t: &[DVec3; 3], v: DVec3) -> bool {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let (dp, dq) = (n.dot(p - t[0]), n.dot(q - t[0]));
    if (dp > 0.0 && dq > 0.0) || (dp < 0.0 && dq < 0.0) || (dp == 0.0 && dq == 0.0) {
        return false;
    }
    let x = p + (q - p) * (dp / (dp - dq));
    x != v && inside_triangle(x, t, n)
}

/// Whether `x`, in the plane of `t` with normal `n`, lies in `t` (closed).
fn inside_triangle(x: DVec3, t: &[DVec3; 3], n: DVec3) -> bool {
    (0..3).all(|k| (t[(k + 1) % 3] - t[k]).cross(x - t[k]).dot(n) >= 0.0)
}

/// Whether two triangles sharing an edge are folded onto each other: coplanar, with
/// their third vertices on the same side of the edge.
fn folded(a: &[DVec3; 3], b: &[DVec3; 3], shared: &[(usize, usize)]) -> bool {
    let (i0, i1) = (shared[0].0, shared[1].0);
    let (j0, j1) = (shared[0].1, shared[1].1);
    let ta = a[3 - i0 - i1];
    let tb = b[3 - j0 - j1];
    let (p, q) = (a[i0], a[i1]);
    let na = (q - p).cross(ta - p);
    let nb = (q - p).cross(tb - p);
    let scale = na.length() * nb.length();
    // Coplanar and on the same side: the normals of (p, q, ta) and (p, q, tb) agree.
    scale > 0.0 && na.dot(nb) >= scale * (1.0 - 1e-12)
}

impl Mesh {
    /// Pairs of triangles that intersect other than in shared vertices and edges.
    pub fn self_intersections(&self) -> u64 {
        count(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh(vertices: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Mesh {
        Mesh {
            vertices,
            triangles,
        }
    }

    #[test]
    fn crossing_triangles_are_counted_once() {
        let m = mesh(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.2, 0.2, -0.5],
                [0.2, 0.2, 0.5],
                [0.9, 0.9, 0.0],
            ],
            vec![[0, 1, 2], [3, 4, 5]],
        );
        assert_eq!(count(&m), 1);
    }

    #[test]
    fn neighbours_sharing_an_edge_or_a_vertex_do_not_count() {
        let m = mesh(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [1.0, 1.0, 0.1],
                [-1.0, -1.0, 0.3],
            ],
            vec![[0, 1, 2], [1, 3, 2], [0, 4, 1]],
        );
        assert_eq!(count(&m), 0);
    }

    #[test]
    fn a_fold_and_a_fan_through_a_shared_vertex_count() {
        // (0, 1, 3) folded back onto (0, 1, 2).
        let fold = mesh(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.5, 0.5, 0.0],
            ],
            vec![[0, 1, 2], [1, 0, 3]],
        );
        assert_eq!(count(&fold), 1);
        // A triangle from vertex 0 piercing (0, 1, 2) beyond the vertex.
        let pierce = mesh(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.6, 0.6, -0.5],
                [0.6, 0.6, 0.5],
            ],
            vec![[0, 1, 2], [0, 3, 4]],
        );
        assert_eq!(count(&pierce), 1);
    }
}
