//! Each cell's own shape for point values: the shape specialised to the cell by the
//! *value-exact* rule ([`Shape::specialise_values`] with no level: decided `min`/`max`
//! only), derived from its parent cell's down the octree, and handed from a leaf to
//! everything that reads values in it: its corner signs, its finer lattice, its edges'
//! root isolation, normals and branch planes, its face centres and its certificate.
//! Deep in a CSG scene a leaf's tape holds the one or two primitives near it, where the
//! whole formula holds hundreds.
//!
//! Why value-exact and not the shorter sign-only tape of the range tests
//! ([`Shape::specialise`]): corners, edges and faces are shared by several cells, each
//! reading them through its own tape. A value-exact tape runs, at every point of its
//! region, the very instructions the whole shape runs on the same operands, and drops
//! only `min`/`max` operands that the other one beats everywhere in the region (their
//! ranges enclose the rounded values, so the same operand wins after rounding too): its
//! value is the whole shape's bit for bit, whichever cell's tape reads a point. A
//! sign-only tape keeps the sign in real arithmetic but its values differ (normals and
//! QEF planes would depend on the cell), and rounding can flip a sign it only argues
//! about over the reals (a product underflowing to `-0`).
//!
//! The region is the cell's box grown by [`GROW`] of its side on every side, so points
//! computed along an edge (`a + t`) that land an ulp past the cell's corner lie in it.

use super::grid::cell_inputs;
use model_ir::arith::arith_ia::Interval;
use model_ir::shape::{Aabb, Shape};
use std::sync::Arc;

/// A cell's shape for point values: `None` for the whole shape, else one specialised to
/// a region holding the cell (shared by the cells below it that specialise no further).
pub type CellTape<S> = Option<Arc<S>>;

/// How far beyond its box a cell's tape holds, in cell sides.
pub const GROW: f64 = 1e-6;

/// The shape that `t` stands for.
pub fn tape<'a, S>(whole: &'a S, t: &'a CellTape<S>) -> &'a S {
    t.as_deref().unwrap_or(whole)
}

/// The tape of the cell `b` below a cell whose tape is `parent`: `parent`'s specialised
/// to `b` (grown by [`GROW`]) where that shortens it, else `parent` itself.
pub fn specialise_to<S: Shape>(whole: &S, parent: &CellTape<S>, b: &Aabb) -> CellTape<S> {
    let p = tape(whole, parent);
    if !p.specialises_values() {
        return parent.clone();
    }
    let g = (b.max - b.min) * GROW;
    let region = cell_inputs::<Interval>(&Aabb::new(b.min - g, b.max + g));
    match p.specialise_values(&region, f64::INFINITY) {
        Some(s) => Some(Arc::new(s)),
        None => parent.clone(),
    }
}

/// For items (edges, corners) each read by several cells: `pairs` of (item, cell index)
/// sorted, each item kept once with the first cell that reads it (the same one on every
/// run).
pub fn first_reader<K: Ord + Copy>(pairs: &mut Vec<(K, u32)>) {
    pairs.sort_unstable();
    pairs.dedup_by_key(|p| p.0);
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::Real;
    use glam::DVec3;
    use model_ir::Tape;

    /// A row of balls (`max` of each), one at every integer x.
    fn balls<R: Real>(x: R, y: R, z: R) -> R {
        let ball = |c: f64| ((x.clone() - c).sqr() + y.sqr() + z.sqr()).rsub(0.16);
        (0..8).fold(ball(0.0), |f, c| f.max(&ball(c as f64)))
    }

    #[test]
    fn a_cell_tape_is_shorter_and_gives_the_same_bits() {
        let t = Tape::record(balls);
        let b = Aabb::new(DVec3::new(2.7, -0.5, -0.5), DVec3::new(3.2, 0.5, 0.5));
        let s = specialise_to(&t, &None, &b);
        let s = tape(&t, &s);
        assert!(s.len() * 3 < t.len(), "{} of {}", s.len(), t.len());
        for i in 0..=10 {
            let p = b.min + (b.max - b.min) * (i as f64 / 10.0);
            let (v, w) = (t.eval(p.x, p.y, p.z), s.eval(p.x, p.y, p.z));
            assert_eq!(v.to_bits(), w.to_bits(), "at {p}");
        }
        // And again below it, from its own tape.
        let c = Aabb::new(DVec3::new(2.7, -0.5, -0.5), DVec3::new(2.9, 0.0, 0.0));
        let parent = Some(Arc::new(s.clone()));
        let k = specialise_to(&t, &parent, &c);
        let k = tape(&t, &k);
        assert!(k.len() <= s.len());
        assert_eq!(
            k.eval(2.8, -0.1, -0.2).to_bits(),
            t.eval(2.8, -0.1, -0.2).to_bits()
        );
    }

    #[test]
    fn the_first_reader_is_kept() {
        let mut v = vec![(5u64, 3), (2, 9), (5, 1), (2, 4)];
        first_reader(&mut v);
        assert_eq!(v, [(2, 4), (5, 1)]);
    }
}
