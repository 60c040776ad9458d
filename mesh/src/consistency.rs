//! Whether a leaf's 8 corner signs tell the topology of the surface inside it, checked
//! on a finer lattice of points: the check that a shell thinner than a cell needs.
//!
//! Dual contouring sees a cell through its corners. A shell a fifth of a cell thick
//! that happens to hold a corner gives that cell a sign change, so it is not probed as
//! an empty-looking leaf, and the mesh shows a small blob around the corner where the
//! shell should pass through. So a leaf with a sign change that the Plantinga–Vegter
//! test does not certify (the gradient turns too much inside it: a crease, two
//! sheets, a small component) is sampled on the lattice of its sub-cells `1, 2, ...`
//! levels down, and the connected components (6-connected) of its inside points and of
//! its outside points are counted. Where the counts differ from those of the 8
//! corners, the surface's topology in the cell is finer than the cell, and the leaf
//! level must reach that sub-level. A crease (two sheets meeting at an edge) keeps the
//! counts and costs no refinement.

use super::grid::{inside_batch, Grid};
use model_ir::shape::{Aabb, Shape};

/// How many levels below the leaf the lattice goes at most (`9^3` points).
pub const MAX_LEVELS: u32 = 3;

/// The first sub-level (`1..=levels`) at which the lattice of cell `c` at `level`
/// shows other inside/outside component counts than its corners, if any, and the
/// points evaluated.
pub fn finer_topology<S: Shape>(
    shape: &S,
    domain: &Aabb,
    grid: &Grid,
    level: u32,
    c: [u32; 3],
    levels: u32,
) -> (Option<u32>, u64) {
    let levels = levels.min(MAX_LEVELS);
    if levels == 0 {
        return (None, 0);
    }
    let n = 1usize << levels;
    let base = c.map(|x| x << levels);
    let fine = level + levels;
    // Signs on the (n + 1)^3 lattice, evaluated a sub-level at a time (the points of
    // sub-level `k` not on a coarser one): a cell whose topology shows at a coarse
    // sub-level costs that sub-level's points only.
    let m = n + 1;
    let mut signs = vec![false; m * m * m];
    let (mut points, mut at, mut got) = (Vec::new(), Vec::new(), Vec::new());
    let mut evals = 0u64;
    let mut coarse = None;
    for k in 0..=levels {
        let step = 1usize << (levels - k);
        let coarser = step << 1;
        points.clear();
        at.clear();
        for z in (0..m).step_by(step) {
            for y in (0..m).step_by(step) {
                for x in (0..m).step_by(step) {
                    if k > 0 && x % coarser == 0 && y % coarser == 0 && z % coarser == 0 {
                        continue;
                    }
                    at.push(x + y * m + z * m * m);
                    let q = [x, y, z].map(|v| v as u32);
                    points.push(grid.point(fine, [0, 1, 2].map(|a| base[a] + q[a])));
                }
            }
        }
        inside_batch(shape, domain, &points, &mut got);
        evals += got.len() as u64;
        for (&i, &g) in at.iter().zip(&got) {
            signs[i] = g;
        }
        let here = counts(&signs, m, step);
        match coarse {
            None => coarse = Some(here),
            Some(c) if c != here => return (Some(k), evals),
            Some(_) => {}
        }
    }
    (None, evals)
}

/// The numbers of 6-connected components of inside and of outside points on the
/// sub-lattice of `signs` (a lattice of side `m`) with step `step`, each set as one bit
/// mask per row along x (at most [`MAX_LEVELS`] levels: 9 points a row).
fn counts(signs: &[bool], m: usize, step: usize) -> (usize, usize) {
    let s = (m - 1) / step + 1;
    let full = (1u16 << s) - 1;
    let (mut ins, mut outs) = ([0u16; ROWS], [0u16; ROWS]);
    for z in 0..s {
        for y in 0..s {
            let row = (0..s).fold(0u16, |r, x| {
                r | (signs[(x + y * m + z * m * m) * step] as u16) << x
            });
            ins[y + z * s] = row;
            outs[y + z * s] = !row & full;
        }
    }
    (components(&mut ins, s), components(&mut outs, s))
}

/// Rows of the finest lattice (`9 x 9`).
const ROWS: usize = 81;

/// The 6-connected components of the points in `left` (row `y + z s` of a lattice of
/// side `s`, bit `x`), which it empties: each component is claimed from a seed, a run
/// along its row at a time, then the runs its claimed runs touch in the four
/// neighbouring rows.
fn components(left: &mut [u16; ROWS], s: usize) -> usize {
    let mut n = 0;
    let mut claimed = [0u16; ROWS];
    let mut todo = Vec::with_capacity(ROWS);
    for r0 in 0..s * s {
        while left[r0] != 0 {
            n += 1;
            let seed = left[r0] & left[r0].wrapping_neg();
            let run = run_of(seed, left[r0]);
            left[r0] &= !run;
            claimed[r0] = run;
            todo.push(r0);
            while let Some(r) = todo.pop() {
                let c = std::mem::take(&mut claimed[r]);
                let (y, z) = (r % s, r / s);
                let near = [
                    (y > 0).then(|| r - 1),
                    (y + 1 < s).then_some(r + 1),
                    (z > 0).then(|| r - s),
                    (z + 1 < s).then_some(r + s),
                ];
                for q in near.into_iter().flatten() {
                    let touch = c & left[q];
                    if touch != 0 {
                        let g = run_of(touch, left[q]);
                        left[q] &= !g;
                        claimed[q] |= g;
                        todo.push(q);
                    }
                }
            }
        }
    }
    n
}

/// The runs of consecutive bits of `mask` that hold a bit of `seed`.
fn run_of(seed: u16, mask: u16) -> u16 {
    let mut g = seed & mask;
    loop {
        let next = (g | g << 1 | g >> 1) & mask;
        if next == g {
            return g;
        }
        g = next;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::Real;

    /// A slab `|x - x0| <= t / 2`.
    struct Slab(f64, f64);
    impl Shape for Slab {
        fn eval<R: Real>(&self, x: R, _y: R, _z: R) -> R {
            (x - self.0).abs().rsub(self.1 / 2.0)
        }
    }

    /// A half-space `x <= x0`.
    struct Half(f64);
    impl Shape for Half {
        fn eval<R: Real>(&self, x: R, _y: R, _z: R) -> R {
            x.rsub(self.0)
        }
    }

    #[test]
    fn components_are_counted_on_each_sub_lattice() {
        // A 5^3 lattice: inside at two opposite corners of it, and on a wall x = 2
        // broken at its centre point.
        let m = 5;
        let mut signs = vec![false; m * m * m];
        let idx = |x: usize, y: usize, z: usize| x + y * m + z * m * m;
        signs[idx(0, 0, 0)] = true;
        signs[idx(4, 4, 4)] = true;
        assert_eq!(counts(&signs, m, 1), (2, 1));
        assert_eq!(counts(&signs, m, 4), (2, 1));
        // A full wall at x = 2 splits the outside in two at steps 1 and 2 (its points
        // are on both sub-lattices; at step 2 it also touches both corners), not at
        // step 4 (which skips it).
        for y in 0..m {
            for z in 0..m {
                signs[idx(2, y, z)] = true;
            }
        }
        assert_eq!(counts(&signs, m, 1), (3, 2));
        assert_eq!(counts(&signs, m, 2), (1, 2));
        assert_eq!(counts(&signs, m, 4), (2, 1));
    }

    #[test]
    fn a_thin_slab_through_a_cell_is_finer_than_its_corners() {
        let domain = Aabb::cube(1.0);
        let g = Grid::new(&domain, 3);
        // Cell (3, 3, 3), inside the domain: a slab a fifth of it thick, off its middle.
        let h = g.cell_size(3);
        let x0 = g.point(3, [3, 3, 3]).x + 0.51 * h;
        let (k, evals) = finer_topology(&Slab(x0, h / 5.0), &domain, &g, 3, [3, 3, 3], 3);
        assert_eq!(k, Some(1), "slab not seen");
        // Seen on the first sub-level's 3^3 points: the finer ones are not evaluated.
        assert_eq!(evals, 27);
        // A plane through the cell: the corners tell it all, on every sub-level.
        let (k, evals) = finer_topology(&Half(x0), &domain, &g, 3, [3, 3, 3], 3);
        assert_eq!(k, None);
        assert_eq!(evals, 729);
    }
}
