//! The mesher's geometry: the cube of cells over the domain, cell and corner keys, the
//! numbering of a cell's 8 corners, 12 edges and 6 faces, the domain clip, and what every
//! step asks of a cell: its inputs to range arithmetic ([`cell_inputs`]) and the signs
//! of its corners ([`inside`], [`corner_mask`]).
//!
//! The cube is centred on the domain and has `2^depth` cells along each side, one cell
//! wider than the domain's longest side: the domain reaches half a cell short of the
//! cube's faces, so every corner of the outermost layer of cells lies outside the
//! domain. The shape is meshed clipped to its domain ([`Clipped`], `min(f, box)`), so
//! those corners are outside and the mesh is closed even where the surface leaves the
//! domain (it is capped by the domain's faces).
//!
//! Corners and cells are addressed by integer coordinates at one level, packed 21 bits
//! per axis into a `u64` key ([`key`]), which bounds the depth at [`MAX_DEPTH`].

use arith_core::{Range, Real};
use glam::DVec3;
use model_ir::shape::{Aabb, Shape};

/// The deepest level the keys can address (corner coordinates up to `2^20`).
pub const MAX_DEPTH: u32 = 20;

/// The cube of cells: its lowest corner and its side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// The cube's corner with the smallest coordinates.
    pub origin: DVec3,
    /// The cube's side.
    pub side: f64,
}

impl Grid {
    /// The cube over `domain` for `depth`: centred on it, `2^depth` cells along each
    /// side, one cell longer than the domain's longest side.
    pub fn new(domain: &Aabb, depth: u32) -> Grid {
        let n = (1u64 << depth) as f64;
        let longest = (domain.max - domain.min).max_element();
        let side = longest * n / (n - 1.0).max(1.0);
        let centre = (domain.min + domain.max) * 0.5;
        Grid {
            origin: centre - DVec3::splat(side * 0.5),
            side,
        }
    }

    /// The side of a cell at `level`.
    pub fn cell_size(&self, level: u32) -> f64 {
        self.side / (1u64 << level) as f64
    }

    /// The point of corner `c` (integer coordinates at `level`).
    pub fn point(&self, level: u32, c: [u32; 3]) -> DVec3 {
        let h = self.cell_size(level);
        self.origin + DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64) * h
    }

    /// The box of cell `c` at `level`.
    pub fn cell_box(&self, level: u32, c: [u32; 3]) -> Aabb {
        let lo = self.point(level, c);
        Aabb::new(lo, self.point(level, [c[0] + 1, c[1] + 1, c[2] + 1]))
    }
}

/// Packs integer coordinates (each below `2^21`) into one key.
pub fn key(c: [u32; 3]) -> u64 {
    c[0] as u64 | (c[1] as u64) << 21 | (c[2] as u64) << 42
}

/// The coordinates a [`key`] packs.
pub fn unkey(k: u64) -> [u32; 3] {
    let m = (1u64 << 21) - 1;
    [(k & m) as u32, (k >> 21 & m) as u32, (k >> 42 & m) as u32]
}

/// Offset of corner `i` (0..8) of a cell: bit 0 is x, bit 1 is y, bit 2 is z.
pub fn corner_offset(i: usize) -> [u32; 3] {
    [(i & 1) as u32, (i >> 1 & 1) as u32, (i >> 2 & 1) as u32]
}

/// The corner `c + corner_offset(i)`.
pub fn corner_of(c: [u32; 3], i: usize) -> [u32; 3] {
    let o = corner_offset(i);
    [c[0] + o[0], c[1] + o[1], c[2] + o[2]]
}

/// The two axes other than `a`, in increasing order.
pub fn other_axes(a: usize) -> (usize, usize) {
    match a {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// The index (0..12) of the cell edge between corners `c1` and `c2` (which differ in
/// one bit): `4 * axis + (bit of the lower other axis) + 2 * (bit of the higher one)`.
pub fn edge_between(c1: usize, c2: usize) -> usize {
    let axis = (c1 ^ c2).trailing_zeros() as usize;
    let lo = c1.min(c2);
    let (b, c) = other_axes(axis);
    4 * axis + (lo >> b & 1) + 2 * (lo >> c & 1)
}

/// The corners `(lower, upper)` of cell edge `e` (0..12), the upper one a step along
/// the edge's axis `e / 4`.
pub fn edge_corners(e: usize) -> (usize, usize) {
    let axis = e / 4;
    let (b, c) = other_axes(axis);
    let lo = (e & 1) << b | (e >> 1 & 1) << c;
    (lo, lo | 1 << axis)
}

/// The corners of face `(axis, side)` in cyclic order around it.
pub fn face_corners(axis: usize, side: usize) -> [usize; 4] {
    let (b, c) = other_axes(axis);
    let base = side << axis;
    [base, base | 1 << b, base | 1 << b | 1 << c, base | 1 << c]
}

/// A shape clipped to a box: `min(f, x - xmin, xmax - x, ...)`, inside where both are.
/// The mesher meshes this, so the mesh closes along the domain's faces.
pub struct Clipped<'a, S> {
    /// The shape.
    pub inner: &'a S,
    /// The box it is clipped to.
    pub domain: Aabb,
}

impl<S> Clipped<'_, S> {
    /// The distance-like value of the domain's walls, `>= 0` inside the domain.
    fn walls<R: Real>(&self, x: &R, y: &R, z: &R) -> R {
        let (lo, hi) = (self.domain.min, self.domain.max);
        (x.clone() - lo.x)
            .min(&x.clone().rsub(hi.x))
            .min(&(y.clone() - lo.y).min(&y.clone().rsub(hi.y)))
            .min(&(z.clone() - lo.z).min(&z.clone().rsub(hi.z)))
    }
}

impl<S> Clipped<'_, S> {
    /// `f`, the inner shape's value (or range) at `(x, y, z)`, clipped as
    /// [`Clipped::eval`] clips it.
    pub fn clip<R: Real>(&self, f: R, x: &R, y: &R, z: &R) -> R {
        f.min(&self.walls(x, y, z))
    }
}

impl<S: Shape> Shape for Clipped<'_, S> {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        let walls = self.walls(&x, &y, &z);
        self.inner.eval(x, y, z).min(&walls)
    }

    /// The inner shape's batch (instruction-major for a tape), each lane then clipped
    /// exactly as [`Clipped::eval`] clips it.
    fn eval_batch<R: Real>(&self, x: &[R], y: &[R], z: &[R], out: &mut Vec<R>) {
        self.inner.eval_batch(x, y, z, out);
        for (((f, x), y), z) in out.iter_mut().zip(x).zip(y).zip(z) {
            *f = f.min(&self.walls(x, y, z));
        }
    }

    fn packs(&self) -> bool {
        self.inner.packs()
    }
}

/// The three independent inputs of a box (symbols 0, 1, 2), as culling's cells.
pub fn cell_inputs<R: Range>(b: &Aabb) -> [R; 3] {
    [
        R::input(0, b.min.x, b.max.x),
        R::input(1, b.min.y, b.max.y),
        R::input(2, b.min.z, b.max.z),
    ]
}

/// Whether `shape` clipped to `domain` is inside (`f >= 0`) at `p`.
pub fn inside<S: Shape>(shape: &S, domain: &Aabb, p: glam::DVec3) -> bool {
    let clipped = Clipped {
        inner: shape,
        domain: *domain,
    };
    // NaN counts as outside, as any value below 0.
    clipped.eval(p.x, p.y, p.z) >= 0.0
}

/// Whether `shape` clipped to `domain` is inside at each of `points`, into `out`
/// (cleared first): [`inside`] at each, from one batch evaluation ([`Shape::eval_batch`],
/// bit for bit the values one at a time give).
pub fn inside_batch<S: Shape>(shape: &S, domain: &Aabb, points: &[DVec3], out: &mut Vec<bool>) {
    let clipped = Clipped {
        inner: shape,
        domain: *domain,
    };
    SCRATCH.with_borrow_mut(|(x, y, z, f)| {
        x.clear();
        y.clear();
        z.clear();
        for p in points {
            x.push(p.x);
            y.push(p.y);
            z.push(p.z);
        }
        clipped.eval_batch(x, y, z, f);
        out.clear();
        // NaN counts as outside, as any value below 0.
        out.extend(f.iter().map(|&v| v >= 0.0));
    });
}

type Lanes = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>);

thread_local! {
    /// The inputs and values of [`inside_batch`], reused per thread.
    static SCRATCH: std::cell::RefCell<Lanes> = std::cell::RefCell::default();
}

/// The corner mask of cell `c` at `level` (bit `i`: corner `i` inside).
pub fn corner_mask<S: Shape>(shape: &S, domain: &Aabb, g: &Grid, level: u32, c: [u32; 3]) -> u8 {
    let points: [DVec3; 8] = core::array::from_fn(|i| g.point(level, corner_of(c, i)));
    let mut signs = Vec::with_capacity(8);
    inside_batch(shape, domain, &points, &mut signs);
    signs
        .iter()
        .enumerate()
        .fold(0u8, |m, (i, &s)| m | (s as u8) << i)
}

/// Whether a corner mask has a sign change.
pub fn crosses(mask: u8) -> bool {
    mask != 0 && mask != 0xff
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edges_and_corners_agree() {
        for e in 0..12 {
            let (a, b) = edge_corners(e);
            assert_eq!(edge_between(a, b), e);
            assert_eq!(edge_between(b, a), e);
            assert_eq!((a ^ b).count_ones(), 1);
            assert_eq!((a ^ b).trailing_zeros() as usize, e / 4);
        }
        for axis in 0..3 {
            for side in 0..2 {
                let f = face_corners(axis, side);
                for k in 0..4 {
                    assert_eq!((f[k] ^ f[(k + 1) % 4]).count_ones(), 1);
                    assert_eq!(f[k] >> axis & 1, side);
                }
            }
        }
    }

    #[test]
    fn keys_round_trip() {
        for c in [[0, 0, 0], [1 << 20, 3, 7], [5, 1 << 20, (1 << 20) - 1]] {
            assert_eq!(unkey(key(c)), c);
        }
    }

    #[test]
    fn the_domain_stays_half_a_cell_inside_the_cube() {
        let d = Aabb::new(DVec3::new(-1.0, -2.0, 0.0), DVec3::new(1.0, 2.0, 0.5));
        for depth in 1..8 {
            let g = Grid::new(&d, depth);
            let h = g.cell_size(depth);
            assert!((g.origin.y - (d.min.y - h / 2.0)).abs() < 1e-12);
            assert!((g.origin.y + g.side - (d.max.y + h / 2.0)).abs() < 1e-12);
            assert!(g.origin.x < d.min.x && g.origin.z < d.min.z);
        }
    }
}
