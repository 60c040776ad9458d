//! Shapes: a defining function written once, generic over [`Real`], so points, every
//! range arithmetic, operation counters and dual numbers run the same code; the box it
//! is considered in ([`Aabb`]) and a camera placement ([`View`]). The bottom of the
//! tracer: it knows no model source, search or renderer.
//!
//! FRep sign convention: `f >= 0` inside, `f = 0` on the surface.

use crate::specialise::Trace;
use arith_core::{Range, Real};
use arith_ia::Interval;
use glam::DVec3;

/// A defining function `f(x, y, z)`, evaluable at points (`f64`), over every
/// [`arith_core::Range`], over operation counters and over dual numbers alike.
pub trait Shape: Send + Sync {
    /// `f(x, y, z)`: `>= 0` inside, `0` on the surface.
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R;

    /// [`Shape::eval`] on every lane `l` of the inputs, `(x[l], y[l], z[l])`, into `out`
    /// (cleared first), each lane exactly what `eval` gives on it. The default evaluates
    /// the lanes one by one; tapes run each instruction over all lanes at once
    /// (`model_ir::Tape::eval_batch`).
    fn eval_batch<R: Real>(&self, x: &[R], y: &[R], z: &[R], out: &mut Vec<R>) {
        out.clear();
        out.extend(
            x.iter()
                .zip(y)
                .zip(z)
                .map(|((x, y), z)| self.eval(x.clone(), y.clone(), z.clone())),
        );
    }

    /// Whether [`Shape::eval`] over a pack of four forms ([`arith_core::pack`]) gives,
    /// lane by lane, what it gives over each form alone: true for code written with the
    /// [`Real`] operations only. A shape that looks at the concrete type of its arguments
    /// (noise over ranges, see `model_sources::noise`) does not know the pack types and says
    /// false; the tracer then evaluates its forms one at a time.
    fn packs(&self) -> bool {
        true
    }

    /// Whether [`Shape::specialise`] can ever return a shape (callers skip the range
    /// evaluation it needs otherwise). False unless the shape overrides it.
    fn specialises(&self) -> bool {
        false
    }

    /// Whether [`Shape::specialise_values`] can ever return a shape (callers skip the
    /// range evaluation it needs otherwise). False unless the shape overrides it.
    fn specialises_values(&self) -> bool {
        false
    }

    /// The number of instructions one evaluation runs, for a shape that is a tape
    /// (counted in `tracer::render::RenderStats::range_ops`); `None` otherwise.
    fn tape_len(&self) -> Option<usize> {
        None
    }

    /// A shape for the union of the regions that the ranges `[x, y, z]` of `regions`
    /// enclose that has, at every point there, the same sign as this one (so the same
    /// zero set and first roots) and is cheaper to evaluate; `None` where there is none
    /// (the default). Several small regions give a tighter account of their union than
    /// one range over all of it. Its values
    /// are not this shape's, and it means nothing outside the region: callers use it
    /// for range tests and root finding inside the region only, and shade with the
    /// whole shape. Formula tapes implement it ([`crate::Tape::specialise`]).
    fn specialise<R: Range>(&self, regions: &[[R; 3]]) -> Option<Self>
    where
        Self: Sized,
    {
        let _ = regions;
        None
    }

    /// [`Shape::specialise`] for several unions of regions at once: `groups[g] = (i, j)`
    /// is the union of `regions[i..j]`. Gives the distinct shapes built and, per group,
    /// the index of its shape among them (`None`: this shape unchanged). An
    /// implementation evaluates each region once and lets groups with the same outcome
    /// share a shape; this default specialises group by group.
    fn specialise_groups<R: Range>(
        &self,
        regions: &[[R; 3]],
        groups: &[(usize, usize)],
    ) -> (Vec<Self>, Vec<Option<usize>>)
    where
        Self: Sized,
    {
        let mut shapes = Vec::new();
        let which = groups
            .iter()
            .map(|&(i, j)| {
                let s = self.specialise(regions.get(i..j)?)?;
                shapes.push(s);
                Some(shapes.len() - 1)
            })
            .collect();
        (shapes, which)
    }

    /// [`Shape::eval_batch`] over the boxes `(x[l], y[l], z[l])`, recording into
    /// `trace` what [`Shape::specialise_traced`] needs to specialise the shape to any of
    /// them without evaluating it again. The default records nothing.
    fn eval_boxes_traced(
        &self,
        x: &[Interval],
        y: &[Interval],
        z: &[Interval],
        out: &mut Vec<Interval>,
        trace: &mut Trace,
    ) {
        trace.clear();
        self.eval_batch(x, y, z, out);
    }

    /// [`Shape::specialise`] to box `lane` of the evaluation that `trace` recorded
    /// ([`Shape::eval_boxes_traced`] on this shape), read from the trace: `None` where
    /// there is none (the default). Tapes implement it ([`crate::Tape::specialise_traced`]).
    fn specialise_traced(&self, trace: &mut Trace, lane: usize) -> Option<Self>
    where
        Self: Sized,
    {
        let _ = (trace, lane);
        None
    }

    /// A shape with the same *value* as this one (not only the same sign) at every
    /// point of the region that the ranges `[x, y, z]` enclose where its own value lies
    /// strictly inside `(-within, within)` (everywhere for `within = inf`), and cheaper
    /// to evaluate: fit for shading there. `None` where there is none (the default).
    fn specialise_values<R: Range>(&self, region: &[R; 3], within: f64) -> Option<Self>
    where
        Self: Sized,
    {
        let _ = (region, within);
        None
    }
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The corner with the smallest coordinates.
    pub min: DVec3,
    /// The corner with the largest coordinates.
    pub max: DVec3,
}

impl Aabb {
    /// The box with corners `min` and `max`.
    pub fn new(min: DVec3, max: DVec3) -> Self {
        Aabb { min, max }
    }
    /// The cube `[-r, r]^3`.
    pub fn cube(r: f64) -> Self {
        Aabb {
            min: DVec3::splat(-r),
            max: DVec3::splat(r),
        }
    }
}

/// `Ok` for a box the renderers can work in: finite, `min < max` on every axis, and a
/// diagonal whose length does not overflow (precisions and margins scale with it).
pub fn check_domain(b: &Aabb) -> Result<(), String> {
    if !(b.min.is_finite() && b.max.is_finite()) {
        return Err("the box must be finite".into());
    }
    if !b.min.cmplt(b.max).all() {
        return Err("each minimum must be below its maximum".into());
    }
    if !(b.max - b.min).length().is_finite() {
        return Err("the box is too large: the length of its diagonal overflows".into());
    }
    Ok(())
}

/// A camera placement: a pinhole, or orthographic with `ortho` (see [`crate::camera`]
/// for the ray formulas).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Eye position.
    pub eye: DVec3,
    /// The point at the centre of the image.
    pub look_at: DVec3,
    /// Up direction (need not be orthogonal to the viewing direction).
    pub up: DVec3,
    /// Vertical field of view in degrees (of a pinhole view; unused with `ortho`).
    pub fov_deg: f64,
    /// `Some(width)`: an orthographic view `width` model units across the image, its
    /// rays parallel to the viewing direction, starting on the image plane through the
    /// eye; `None`: a pinhole at the eye.
    pub ortho: Option<f64>,
}
