//! The hand-over from culling (Algorithm 2, [`super::cull`]) to the ray search
//! (Algorithm 1, [`super::ray`]): the rays of a tile that culling leaves, each clipped
//! to the domain and to the depths culling left it ([`start_of`]), as jobs for
//! [`super::ray::first_roots_until`].

use super::cull::{CullStats, Culler};
use super::ray::{clip_with, RayJob, Start};
use super::windows::Windows;
use arith_core::Arithmetic;
use glam::DVec3;
use model_ir::camera::Camera;
use model_ir::shape::{Aabb, Shape};
use std::sync::Arc;

/// The rays of a tile left to search after culling.
pub struct TileRays<S> {
    /// The searches, in the order culling handed them out.
    pub jobs: Vec<RayJob>,
    /// The pixel (index in the tile) of each job.
    pub pixel_of: Vec<usize>,
    /// The cells' depth windows the jobs refer to (job shape `k` is `locals[k - 1]`).
    pub locals: Vec<Arc<Windows<S>>>,
    /// Rays culling handed out (some then miss the domain).
    pub traced: u64,
}

/// The rays of the tile `rect` that culling leaves to search (every ray of the tile
/// without culling), each clipped to the domain and to the depths culling left it, in
/// the order culling hands them out (cell by cell). `culler` is `None` without culling.
/// Rays are set up four at a time ([`Camera::rays4`]).
pub fn tile_rays<A: Arithmetic, S: Shape>(
    culler: Option<&Culler>,
    cam: &Camera,
    domain: &Aabb,
    shape: &S,
    rect: (u32, u32, u32, u32),
    cs: &mut CullStats,
) -> TileRays<S> {
    let (i0, j0, i1, j1) = rect;
    let tw = (i1 - i0) as usize;
    // Each ray's shape: 0 the whole one, `k` its cell's depth windows `locals[k - 1]`
    // (rays come cell by cell, so a new one is pushed only when the cell's changes).
    let mut pending: Vec<(u32, u32, Start, u32)> = Vec::with_capacity(tw * (j1 - j0) as usize);
    let mut locals: Vec<Arc<Windows<S>>> = Vec::new();
    let mut trace = |i: u32, j: u32, depths: Start, local: Option<&Arc<Windows<S>>>| {
        let k = match local {
            None => 0,
            Some(l) => {
                if !locals.last().is_some_and(|last| Arc::ptr_eq(last, l)) {
                    locals.push(l.clone());
                }
                locals.len() as u32
            }
        };
        pending.push((i, j, depths, k));
    };
    if let Some(culler) = culler {
        culler.traverse::<A, S, _>(shape, rect, cs, &mut trace);
    } else {
        for j in j0..j1 {
            for i in i0..i1 {
                trace(i, j, Start::whole(f64::NEG_INFINITY, f64::INFINITY), None);
            }
        }
    }
    let mut rays = TileRays {
        jobs: Vec::with_capacity(pending.len()),
        pixel_of: Vec::with_capacity(pending.len()),
        locals,
        traced: pending.len() as u64,
    };
    for chunk in pending.chunks(4) {
        let last = chunk.len() - 1;
        let set = cam.rays4(core::array::from_fn(|l| {
            (chunk[l.min(last)].0, chunk[l.min(last)].1)
        }));
        for (&(i, j, depths, local), &(d, inv, c, ic)) in chunk.iter().zip(&set) {
            let o = cam.origin_at(i as f64 + 0.5, j as f64 + 0.5);
            if let Some((start, windowed)) = start_of(o, d, inv, c, ic, depths, domain) {
                // A specialised shape holds only in its cell's depth windows.
                let shape = if windowed { local } else { 0 };
                rays.jobs.push(RayJob {
                    o,
                    d,
                    start,
                    shape,
                    depth: c,
                });
                rays.pixel_of
                    .push((j - j0) as usize * tw + (i - i0) as usize);
            }
        }
    }
    rays
}

/// Where to search the ray `o + t d` (`inv = d.recip()`, `c = d . forward`,
/// `ic = 1 / c`): its piece inside the domain, narrowed to what culling left of it
/// (`depths`, in depth along `forward`), and whether it was (else it is the whole
/// piece in the domain). `None` when nothing is left.
#[allow(clippy::too_many_arguments)]
fn start_of(
    o: DVec3,
    d: DVec3,
    inv: DVec3,
    c: f64,
    ic: f64,
    depths: Start,
    domain: &Aabb,
) -> Option<(Start, bool)> {
    let (t0, t1) = clip_with(o, d, inv, domain, 0.0)?;
    // Culling proved the ray root-free outside the depths `[s0, s1]` and inside
    // `(split, resume)` (margin included); depth is `t (d . forward)`. Widened (the
    // gap narrowed) by far more than the rounding.
    let Start {
        t0: s0,
        split,
        resume,
        step,
        t1: s1,
    } = depths;
    let windowed = c > 0.5 && s0.is_finite() && s1.is_finite();
    let (t0, t1, split, resume, step) = if windowed {
        let (a, b) = (s0 * ic, s1 * ic);
        let m = (a.abs() + b.abs()) * 1e-12;
        let split = split * ic;
        let resume = (resume * ic - m).max(split);
        (t0.max(a - m), t1.min(b + m), split, resume, step * ic)
    } else {
        (t0, t1, t1, t1, 0.0)
    };
    if t0 > t1 {
        return None;
    }
    Some((
        Start {
            t0,
            split,
            resume,
            step,
            t1,
        },
        windowed,
    ))
}
