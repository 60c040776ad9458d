//! Dual contouring over the leaves the octree search kept, all at one level: each edge
//! of the grid whose ends differ in sign gives a quad joining the vertices of the four
//! cells around it (two triangles), wound so that its normal points outside (`f < 0`).
//!
//! A cell has one vertex per piece of the surface inside it ([`super::patches`]), each
//! from the QEF of its crossings ([`super::qef`]), constrained to the cell within the
//! domain (shrunk by a hair, so the vertices of neighbouring cells never coincide). The crossings come
//! from root isolation on the edges ([`super::edge_roots`]), the signs from point
//! values at the corners. Every value is read through the value tape of a cell that
//! holds the point ([`super::cell_tape`]): the whole shape's value, bit for bit, from a
//! formula cut down to the cell; each corner and edge is evaluated once, by the first
//! cell that reads it. Cells that the search dropped cannot touch a sign-changing
//! edge (a cell whose corners differ in sign has 0 in its range); should one be missing
//! all the same (a model that is not continuous), it is added here, so each quad has
//! its four cells and the mesh stays closed.

use super::cell_tape::{first_reader, tape, CellTape};
use super::edge_roots::{crossing, Crossing};
use super::grid::{corner_of, edge_between, edge_corners, face_corners, inside, key, unkey, Grid};
use super::merge::{merge, Clustered};
use super::patches::{pieces, NONE};
use super::qef::Qef;
use crate::progress::Meter;
use crate::triangles::Mesh;
use arith_core::Arithmetic;
use glam::DVec3;
use model_ir::shape::{Aabb, Shape};
use rayon::prelude::*;
use rustc_hash::FxHashSet;
use std::sync::atomic::{AtomicBool, Ordering};

/// Vertices stay this share of a cell inside their cell's faces.
pub const MARGIN: f64 = 1e-4;

/// Counters of the contouring.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ContourStats {
    /// Cells contoured.
    pub cells: u64,
    /// Cells added because a sign-changing edge needed them.
    pub added_cells: u64,
    /// Cells holding more than one piece of the surface.
    pub multi_piece_cells: u64,
    /// Vertices removed by merging cells.
    pub merged_vertices: u64,
    /// Sign-changing edges.
    pub crossings: u64,
    /// Edges with more than one sign-changing root (the grid is coarse there).
    pub multi_root_edges: u64,
    /// Range evaluations of root isolation.
    pub edge_evals: u64,
    /// Corner points evaluated.
    pub corners: u64,
}

/// The fixed inputs of the contouring.
pub struct Contour<'a, S> {
    /// The shape (unclipped).
    pub shape: &'a S,
    /// The domain it is clipped to.
    pub domain: Aabb,
    /// The cube.
    pub grid: Grid,
    /// The level of the cells.
    pub level: u32,
    /// Find the other branches' planes at crossings ([`super::branches`]).
    pub branch_planes: bool,
    /// Merge cells whose vertices fit their planes within this distance
    /// ([`super::merge`]); `None`: no merging.
    pub merge_error: Option<f64>,
    /// Stops the work when set.
    pub cancel: Option<&'a AtomicBool>,
}

/// Cells (sorted keys) with their corner masks and value tapes.
struct Cells<S> {
    keys: Vec<u64>,
    masks: Vec<u8>,
    tapes: Vec<CellTape<S>>,
}

impl<S> Cells<S> {
    fn index(&self, c: [u32; 3]) -> Option<usize> {
        self.keys.binary_search(&key(c)).ok()
    }
}

impl<S: Shape> Contour<'_, S> {
    fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }

    /// The shape that cell `i` of `cells` reads values through.
    fn tape<'s>(&'s self, cells: &'s Cells<S>, i: u32) -> &'s S {
        tape(self.shape, &cells.tapes[i as usize])
    }

    /// The mesh of `cells` (leaves at `level`, each with its value tape in `tapes`);
    /// `None` when cancelled.
    pub fn run<A: Arithmetic>(
        &self,
        cells: &[[u32; 3]],
        tapes: &[CellTape<S>],
        meter: &Meter,
    ) -> Option<(Mesh, ContourStats)> {
        let mut stats = ContourStats::default();
        let cells = self.close_cells(cells, tapes, &mut stats)?;
        let (edges, readers) = sign_changing_edges(&cells);
        stats.cells = cells.keys.len() as u64;
        stats.crossings = edges.len() as u64;
        let chunks = (edges.len() + cells.keys.len()) as u64 / CHUNK + 2;
        meter.add_total(chunks);
        let crossings = self.crossings::<A>(&cells, &edges, &readers, meter)?;
        for c in &crossings {
            stats.edge_evals += c.evals as u64;
            stats.multi_root_edges += (c.roots > 1) as u64;
        }
        let (pieces, vertices) = self.vertices(&cells, &edges, &crossings, meter)?;
        if self.cancelled() {
            return None;
        }
        stats.multi_piece_cells = pieces.iter().filter(|p| p.1 > 1).count() as u64;
        let triangles = self.quads(&cells, &edges, &readers, &pieces, &vertices.pos);
        meter.tick(1);
        let (vertices, triangles) = match self.merge_error {
            Some(e) => {
                let m = Clustered {
                    vertices: vertices.pos,
                    triangles,
                    cells: vertices.cells,
                    qefs: vertices.qefs,
                };
                let (v, t, removed) = merge(m, self.level, e, |l, c| self.vertex_box(l, c));
                stats.merged_vertices = removed;
                (v, t)
            }
            None => (vertices.pos, triangles),
        };
        let mesh = Mesh {
            vertices: vertices.iter().map(|v| v.to_array()).collect(),
            triangles,
        };
        Some((mesh, stats))
    }

    /// The corner mask of each cell, adding the cells that a sign-changing edge needs
    /// (and, in turn, those that the added cells' edges need; they read values through
    /// the whole shape).
    fn close_cells(
        &self,
        cells: &[[u32; 3]],
        tapes: &[CellTape<S>],
        stats: &mut ContourStats,
    ) -> Option<Cells<S>> {
        let mut order: Vec<(u64, u32)> = cells
            .iter()
            .enumerate()
            .map(|(i, &c)| (key(c), i as u32))
            .collect();
        first_reader(&mut order);
        let mut keys: Vec<u64> = order.iter().map(|o| o.0).collect();
        let mut tapes: Vec<CellTape<S>> =
            order.iter().map(|o| tapes[o.1 as usize].clone()).collect();
        let n = 1u32 << self.level;
        loop {
            if self.cancelled() {
                return None;
            }
            let masks = self.masks(&keys, &tapes, &mut stats.corners);
            let cells = Cells { keys, masks, tapes };
            let mut missing: Vec<u64> = cells
                .keys
                .par_iter()
                .zip(&cells.masks)
                .flat_map_iter(|(&k, &m)| edges_of(k, m))
                .flat_map_iter(|(lo, axis)| around(unkey(lo), axis as usize, n))
                .filter(|c| cells.index(*c).is_none())
                .map(key)
                .collect();
            if missing.is_empty() {
                return Some(cells);
            }
            missing.par_sort_unstable();
            missing.dedup();
            stats.added_cells += missing.len() as u64;
            let mut all: Vec<(u64, CellTape<S>)> =
                cells.keys.into_iter().zip(cells.tapes).collect();
            all.extend(missing.into_iter().map(|k| (k, None)));
            all.par_sort_unstable_by_key(|a| a.0);
            (keys, tapes) = all.into_iter().unzip();
        }
    }

    /// The corner masks of the cells `keys` (with their `tapes`), each corner
    /// evaluated once, through the tape of the first cell that holds it.
    fn masks(&self, keys: &[u64], tapes: &[CellTape<S>], corners: &mut u64) -> Vec<u8> {
        let mut all: Vec<(u64, u32)> = keys
            .par_iter()
            .enumerate()
            .flat_map_iter(|(j, &k)| (0..8).map(move |i| (key(corner_of(unkey(k), i)), j as u32)))
            .collect();
        all.par_sort_unstable();
        all.dedup_by_key(|a| a.0);
        *corners += all.len() as u64;
        let signs: Vec<bool> = all
            .par_iter()
            .map(|&(k, j)| self.inside_at(tape(self.shape, &tapes[j as usize]), unkey(k)))
            .collect();
        keys.par_iter()
            .map(|&k| {
                (0..8).fold(0u8, |m, i| {
                    let c = key(corner_of(unkey(k), i));
                    let j = all.binary_search_by_key(&c, |a| a.0).unwrap_or(0);
                    m | (signs[j] as u8) << i
                })
            })
            .collect()
    }

    /// Whether corner `c` is inside, read through `shape` (a tape valid there).
    fn inside_at(&self, shape: &S, c: [u32; 3]) -> bool {
        inside(shape, &self.domain, self.grid.point(self.level, c))
    }

    /// The crossing of each edge, in the order of `edges`, each through the tape of
    /// its cell in `readers`.
    fn crossings<A: Arithmetic>(
        &self,
        cells: &Cells<S>,
        edges: &[(u64, u8)],
        readers: &[u32],
        meter: &Meter,
    ) -> Option<Vec<Crossing>> {
        let h = self.grid.cell_size(self.level);
        let out: Vec<Option<Vec<Crossing>>> = edges
            .par_chunks(CHUNK as usize)
            .zip(readers.par_chunks(CHUNK as usize))
            .map(|(chunk, readers)| {
                if self.cancelled() {
                    return None;
                }
                let v = chunk
                    .iter()
                    .zip(readers)
                    .map(|(&(lo, axis), &r)| {
                        let a = self.grid.point(self.level, unkey(lo));
                        crossing::<A, S>(
                            self.tape(cells, r),
                            &self.domain,
                            a,
                            axis as usize,
                            h,
                            self.branch_planes,
                        )
                    })
                    .collect();
                meter.tick(1);
                Some(v)
            })
            .collect();
        out.into_iter()
            .collect::<Option<Vec<_>>>()
            .map(|v| v.concat())
    }

    /// Each cell's pieces (the vertex index of each local edge's piece, `u32::MAX`
    /// for none, and the number of pieces) and every vertex.
    fn vertices(
        &self,
        cells: &Cells<S>,
        edges: &[(u64, u8)],
        crossings: &[Crossing],
        meter: &Meter,
    ) -> Option<(Vec<PieceIndex>, Vertices)> {
        let flipped = self.flip_faces(cells);
        let flipped = &flipped;
        let chunks: Vec<Option<Vec<CellPieces>>> = cells
            .keys
            .par_chunks(CHUNK as usize)
            .zip(cells.masks.par_chunks(CHUNK as usize))
            .enumerate()
            .map(|(n, (ks, ms))| {
                if self.cancelled() {
                    return None;
                }
                let first = n * CHUNK as usize;
                let v = ks
                    .iter()
                    .zip(ms)
                    .enumerate()
                    .map(|(i, (&k, &m))| {
                        let s = self.tape(cells, (first + i) as u32);
                        self.cell_vertices(s, unkey(k), m, flipped, edges, crossings)
                    })
                    .collect();
                meter.tick(1);
                Some(v)
            })
            .collect();
        let mut pieces = Vec::with_capacity(cells.keys.len());
        let mut vertices = Vertices::default();
        for (cell, c) in chunks
            .into_iter()
            .collect::<Option<Vec<_>>>()?
            .into_iter()
            .flatten()
            .zip(&cells.keys)
        {
            pieces.push((shift(cell.piece, vertices.pos.len() as u32), cell.count));
            let n = cell.vertices.len();
            vertices.pos.extend(cell.vertices);
            vertices.qefs.extend(cell.qefs);
            vertices.cells.extend(std::iter::repeat_n(unkey(*c), n));
        }
        Some((pieces, vertices))
    }

    /// The ambiguous faces whose decision is flipped: where both cells beside a face
    /// join its two segments into one piece, the pair of their vertices would be the
    /// side of four triangles (a non-manifold edge); pairing the face's crossings the
    /// other way separates them. A few rounds, as a flip changes two cells' pieces.
    fn flip_faces(&self, cells: &Cells<S>) -> Flipped {
        let mut flipped = Flipped::default();
        for _ in 0..FLIP_ROUNDS {
            let found = self.conflicts(cells, &flipped);
            if found.is_empty() {
                break;
            }
            for f in found {
                if !flipped.insert(f) {
                    flipped.remove(&f);
                }
            }
        }
        flipped
    }

    /// The ambiguous faces (each seen from its lower cell) whose two cells both join
    /// the face's two segments into one piece.
    fn conflicts(&self, cells: &Cells<S>, flipped: &Flipped) -> Vec<(u64, u8)> {
        cells
            .keys
            .par_iter()
            .zip(&cells.masks)
            .enumerate()
            .flat_map_iter(|(i, (&k, &m))| {
                let c = unkey(k);
                let (piece, _) = self.cell_pieces(self.tape(cells, i as u32), c, m, flipped);
                let mut out = Vec::new();
                for axis in 0..3 {
                    if !ambiguous(m, axis, 1) || !joined(&piece, axis, 1) {
                        continue;
                    }
                    let mut n = c;
                    n[axis] += 1;
                    let Some(j) = cells.index(n) else { continue };
                    let s = self.tape(cells, j as u32);
                    let (np, _) = self.cell_pieces(s, n, cells.masks[j], flipped);
                    if joined(&np, axis, 0) {
                        out.push(face_key(c, axis, 1));
                    }
                }
                out
            })
            .collect()
    }

    /// The pieces of cell `c` (with its tape `shape`) with the face decisions of
    /// `flipped`.
    fn cell_pieces(&self, shape: &S, c: [u32; 3], mask: u8, flipped: &Flipped) -> ([u8; 12], u8) {
        pieces(mask, |axis, side| {
            self.face_centre_inside(shape, c, axis, side)
                ^ flipped.contains(&face_key(c, axis, side))
        })
    }

    /// The pieces of cell `c` (with its tape `shape`) and their vertices.
    fn cell_vertices(
        &self,
        shape: &S,
        c: [u32; 3],
        mask: u8,
        flipped: &Flipped,
        edges: &[(u64, u8)],
        crossings: &[Crossing],
    ) -> CellPieces {
        let (piece, count) = self.cell_pieces(shape, c, mask, flipped);
        let mut qefs = vec![Qef::default(); count as usize];
        let cell = self.grid.cell_box(self.level, c);
        for e in 0..12 {
            if piece[e] == NONE {
                continue;
            }
            let (lo, _) = edge_corners(e);
            let g = (key(corner_of(c, lo)), (e / 4) as u8);
            if let Ok(i) = edges.binary_search(&g) {
                add_crossing(&mut qefs[piece[e] as usize], &crossings[i], &cell);
            }
        }
        let (lo, hi) = self.vertex_box(self.level, c);
        CellPieces {
            piece,
            count,
            vertices: qefs.iter().map(|q| q.solve(lo, hi)).collect(),
            qefs,
        }
    }

    /// Where the vertices of cell `c` at `level` may go: the cell within the domain
    /// (the clipped shape's surface lies in the domain), shrunk by [`MARGIN`] of a
    /// leaf cell.
    fn vertex_box(&self, level: u32, c: [u32; 3]) -> (DVec3, DVec3) {
        let b = self.grid.cell_box(level, c);
        let m = MARGIN * self.grid.cell_size(self.level);
        let (mut lo, mut hi) = (b.min.max(self.domain.min), b.max.min(self.domain.max));
        for k in 0..3 {
            if lo[k].partial_cmp(&hi[k]).is_none_or(|o| o.is_gt()) {
                // Not in the domain at all (cannot happen for a cell with crossings).
                (lo[k], hi[k]) = (b.min[k], b.max[k]);
            }
            if hi[k] - lo[k] > 2.0 * m {
                (lo[k], hi[k]) = (lo[k] + m, hi[k] - m);
            } else {
                let mid = 0.5 * (lo[k] + hi[k]);
                (lo[k], hi[k]) = (mid, mid);
            }
        }
        (lo, hi)
    }

    /// Whether the centre of face `(axis, side)` of cell `c` (with its tape `shape`)
    /// is inside.
    fn face_centre_inside(&self, shape: &S, c: [u32; 3], axis: usize, side: usize) -> bool {
        let b = self.grid.cell_box(self.level, c);
        let mut p = (b.min + b.max) * 0.5;
        p[axis] = if side == 0 { b.min[axis] } else { b.max[axis] };
        inside(shape, &self.domain, p)
    }

    /// Two triangles per sign-changing edge.
    fn quads(
        &self,
        cells: &Cells<S>,
        edges: &[(u64, u8)],
        readers: &[u32],
        pieces: &[([u32; 12], u8)],
        vertices: &[DVec3],
    ) -> Vec<[u32; 3]> {
        let n = 1u32 << self.level;
        edges
            .par_iter()
            .zip(readers)
            .flat_map_iter(|(&(lo, axis), &r)| {
                let axis = axis as usize;
                let lo_c = unkey(lo);
                let lower_inside = self.inside_at(self.tape(cells, r), lo_c);
                let quad: Vec<u32> = around(lo_c, axis, n)
                    .map(|cell| {
                        let i = cells.index(cell).expect("closed cells");
                        let local_lo = local_corner(cell, lo_c);
                        pieces[i].0[edge_between(local_lo, local_lo | 1 << axis)]
                    })
                    .collect();
                // Never short: the outermost corners are outside, so no sign-changing
                // edge lies on the cube's faces.
                let &[a, b, c, d] = quad.as_slice() else {
                    return Vec::new();
                };
                let mut q = [a, b, c, d];
                if !lower_inside {
                    q.reverse();
                }
                let mut dir = DVec3::ZERO;
                dir[axis] = if lower_inside { 1.0 } else { -1.0 };
                split(q, vertices, dir).to_vec()
            })
            .collect()
    }
}

/// Adds a crossing's plane to `q`, and the planes of its other branches whose crease
/// with it passes through the cell (a sharp feature in the cell that the cell's edges
/// may not all see).
fn add_crossing(q: &mut Qef, x: &Crossing, cell: &Aabb) {
    q.add(x.p, x.n);
    for b in &x.others {
        if b.crease_meets(x.p, x.n, cell.min, cell.max) {
            let (p, n) = b.plane(x.p);
            q.add_plane(p, n);
        }
    }
}

/// The pieces of one cell: the piece of each local edge ([`NONE`]: none), their
/// number, and a vertex per piece.
struct CellPieces {
    piece: [u8; 12],
    count: u8,
    vertices: Vec<DVec3>,
    qefs: Vec<Qef>,
}

/// A cell's pieces: the vertex index of each local edge's piece (`u32::MAX` for
/// none) and the number of pieces.
type PieceIndex = ([u32; 12], u8);

/// Every vertex with its leaf cell and its QEF.
#[derive(Default)]
struct Vertices {
    pos: Vec<DVec3>,
    cells: Vec<[u32; 3]>,
    qefs: Vec<Qef>,
}

/// Faces whose ambiguity decision is flipped: (key of the lower corner, normal axis).
type Flipped = FxHashSet<(u64, u8)>;

/// Rounds of face flips at most.
const FLIP_ROUNDS: usize = 4;

/// The global key of face `(axis, side)` of cell `c`.
fn face_key(c: [u32; 3], axis: usize, side: usize) -> (u64, u8) {
    let mut k = c;
    k[axis] += side as u32;
    (key(k), axis as u8)
}

/// Whether the corners of face `(axis, side)` alternate in sign.
fn ambiguous(mask: u8, axis: usize, side: usize) -> bool {
    let cs = face_corners(axis, side).map(|c| mask >> c & 1);
    cs[0] == cs[2] && cs[1] == cs[3] && cs[0] != cs[1]
}

/// Whether the four edges of face `(axis, side)` all belong to one piece.
fn joined(piece: &[u8; 12], axis: usize, side: usize) -> bool {
    let cs = face_corners(axis, side);
    let p = piece[edge_between(cs[0], cs[1])];
    p != NONE && (1..4).all(|k| piece[edge_between(cs[k], cs[(k + 1) % 4])] == p)
}

/// Units of work per progress tick.
const CHUNK: u64 = 4096;

/// Adds `first` to each piece index (as `u32`), keeping [`NONE`] as `u32::MAX`.
fn shift(p: [u8; 12], first: u32) -> [u32; 12] {
    p.map(|x| {
        if x == NONE {
            u32::MAX
        } else {
            first + x as u32
        }
    })
}

/// The sign-changing edges of a cell (key of the lower corner, axis).
fn edges_of(k: u64, mask: u8) -> impl Iterator<Item = (u64, u8)> {
    let c = unkey(k);
    (0..12).filter_map(move |e| {
        let (a, b) = edge_corners(e);
        ((mask >> a & 1) != (mask >> b & 1)).then(|| (key(corner_of(c, a)), (e / 4) as u8))
    })
}

/// Every sign-changing edge of the cells, sorted, and the first cell holding each (whose
/// tape reads its values).
fn sign_changing_edges<S: Sync>(cells: &Cells<S>) -> (Vec<(u64, u8)>, Vec<u32>) {
    let mut v: Vec<((u64, u8), u32)> = cells
        .keys
        .par_iter()
        .zip(&cells.masks)
        .enumerate()
        .flat_map_iter(|(i, (&k, &m))| edges_of(k, m).map(move |e| (e, i as u32)))
        .collect();
    v.par_sort_unstable();
    v.dedup_by_key(|e| e.0);
    v.into_iter().unzip()
}

/// The cells around the edge from corner `lo` along `axis`, counter-clockwise seen
/// from the edge's upper end (`(u, v)` offsets `(-1,-1), (0,-1), (0,0), (-1,0)` with
/// `(axis, u, v)` right-handed); those outside the grid of `n` cells are left out.
fn around(lo: [u32; 3], axis: usize, n: u32) -> impl Iterator<Item = [u32; 3]> {
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    [(-1i64, -1i64), (0, -1), (0, 0), (-1, 0)]
        .into_iter()
        .filter_map(move |(du, dv)| {
            let mut c = lo.map(|x| x as i64);
            c[u] += du;
            c[v] += dv;
            c.iter()
                .all(|&x| x >= 0 && x < n as i64)
                .then(|| c.map(|x| x as u32))
        })
}

/// The local index of corner `corner` in cell `cell` (it must be one of its corners).
fn local_corner(cell: [u32; 3], corner: [u32; 3]) -> usize {
    (0..3).fold(0, |i, k| i | ((corner[k] - cell[k]) as usize) << k)
}

/// Splits quad `q` (counter-clockwise around `dir`) along the diagonal whose two
/// triangles face `dir` best.
fn split(q: [u32; 4], vertices: &[DVec3], dir: DVec3) -> [[u32; 3]; 2] {
    let p = q.map(|i| vertices[i as usize]);
    let facing = |a: usize, b: usize, c: usize| {
        let n = (p[b] - p[a]).cross(p[c] - p[a]);
        n.dot(dir) / n.length().max(f64::MIN_POSITIVE)
    };
    let ac = facing(0, 1, 2).min(facing(0, 2, 3));
    let bd = facing(0, 1, 3).min(facing(1, 2, 3));
    if ac >= bd {
        [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
    } else {
        [[q[0], q[1], q[3]], [q[1], q[2], q[3]]]
    }
}
