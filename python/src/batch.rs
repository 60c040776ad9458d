//! Batched evaluation over many points or boxes, the work behind `Shape.eval` and
//! `Shape.eval_boxes`: the inputs (rows of `x, y, z`, as numpy lays out an `(N, 3)`
//! array) are cut into chunks, the chunks spread over rayon's workers, and each chunk
//! evaluated by one [`Shape::eval_batch`] call (a tape runs each instruction over the
//! whole chunk). Free of Python, so the Rust benchmark of the binding's overhead runs
//! exactly this code.

use crate::toolkit::{with_arith, ArithKind, Arithmetic, Range, Shape};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Points per [`Shape::eval_batch`] call: long enough to spread the per-instruction
/// cost, short enough for the tape's registers to stay in the cache.
pub const POINT_CHUNK: usize = 1024;
/// Boxes per [`Shape::eval_batch`] call (each form is several `f64`s, some allocate).
pub const BOX_CHUNK: usize = 256;

/// `out[k] = f(xyz[3k], xyz[3k + 1], xyz[3k + 2])` in `f64`, skipping the chunks not yet
/// started once `cancel` is set. `xyz.len() == 3 * out.len()`.
pub fn eval_points<S: Shape>(shape: &S, xyz: &[f64], out: &mut [f64], cancel: &AtomicBool) {
    assert_eq!(
        xyz.len(),
        3 * out.len(),
        "eval_points: 3 coordinates per point"
    );
    out.par_chunks_mut(POINT_CHUNK)
        .zip(xyz.par_chunks(3 * POINT_CHUNK))
        .for_each_init(Lanes::<f64>::default, |lanes, (out, xyz)| {
            if cancel.load(Ordering::Relaxed) {
                return;
            }
            lanes.clear();
            for p in xyz.chunks_exact(3) {
                lanes.push(p[0], p[1], p[2]);
            }
            lanes.eval(shape);
            out.copy_from_slice(&lanes.out);
        });
}

/// `out[2k], out[2k + 1]` = the bounds of `f` over the box `lo[3k..3k + 3]` to
/// `hi[3k..3k + 3]` in the arithmetic `A` (its cell form, one input symbol per axis).
/// Every box must be finite with `lo <= hi`. Chunks not yet started once `cancel` is set
/// are skipped.
pub fn eval_boxes<A: Arithmetic, S: Shape>(
    shape: &S,
    lo: &[f64],
    hi: &[f64],
    out: &mut [f64],
    cancel: &AtomicBool,
) {
    assert!(
        lo.len() == hi.len() && 2 * lo.len() == 3 * out.len(),
        "eval_boxes: 3 coordinates per corner, 2 bounds per box"
    );
    out.par_chunks_mut(2 * BOX_CHUNK)
        .zip(lo.par_chunks(3 * BOX_CHUNK))
        .zip(hi.par_chunks(3 * BOX_CHUNK))
        .for_each_init(Lanes::<A::Cell>::default, |lanes, ((out, lo), hi)| {
            if cancel.load(Ordering::Relaxed) {
                return;
            }
            lanes.clear();
            for (a, b) in lo.chunks_exact(3).zip(hi.chunks_exact(3)) {
                lanes.push(
                    A::Cell::input(0, a[0], b[0]),
                    A::Cell::input(1, a[1], b[1]),
                    A::Cell::input(2, a[2], b[2]),
                );
            }
            lanes.eval(shape);
            for (o, r) in out.chunks_exact_mut(2).zip(&lanes.out) {
                (o[0], o[1]) = r.bounds();
            }
        });
}

/// [`eval_boxes`] in the arithmetic `kind`.
pub fn eval_boxes_kind<S: Shape>(
    kind: ArithKind,
    shape: &S,
    lo: &[f64],
    hi: &[f64],
    out: &mut [f64],
    cancel: &AtomicBool,
) {
    with_arith!(kind, A => eval_boxes::<A, S>(shape, lo, hi, out, cancel))
}

/// The inputs and output of one [`Shape::eval_batch`] call, reused across chunks.
struct Lanes<R> {
    x: Vec<R>,
    y: Vec<R>,
    z: Vec<R>,
    out: Vec<R>,
}

impl<R> Default for Lanes<R> {
    fn default() -> Self {
        Lanes {
            x: Vec::new(),
            y: Vec::new(),
            z: Vec::new(),
            out: Vec::new(),
        }
    }
}

impl<R: crate::toolkit::Real> Lanes<R> {
    fn clear(&mut self) {
        self.x.clear();
        self.y.clear();
        self.z.clear();
    }

    fn push(&mut self, x: R, y: R, z: R) {
        self.x.push(x);
        self.y.push(y);
        self.z.push(z);
    }

    fn eval<S: Shape>(&mut self, shape: &S) {
        shape.eval_batch(&self.x, &self.y, &self.z, &mut self.out);
    }
}
