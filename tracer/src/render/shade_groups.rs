//! Shading the slab search's hits ([`crate::search::slabs`]) group by group: the hits
//! of one tile-slab share one shape with the whole shape's values around them
//! ([`Shape::specialise_values`] over the tile-slab's box widened by the samples' step,
//! from the value shape of the image tile's slab it lies in, itself from the whole
//! shape), on which the six samples of all of them ([`super::shade::samples`]: the normal and
//! the sign check) are evaluated in one batch, then lit ([`super::shade::shade`]) with
//! optional shadow rays.
//!
//! A value shape holds only in its box: a hit whose samples leave the group's box
//! (never, unless rounding put the hit a margin outside its tile-slab) is sampled on
//! the whole shape.

use super::shade::Samples;
use super::shade_hits::{write_hit, SHADING_STEP};
use super::tile_shapes::ranges;
use super::types::{TileCtx, TileOut};
use crate::search::slabs::SlabTile;
use arith_core::Arithmetic;
use glam::DVec3;
use model_ir::shape::{Aabb, Shape};

/// Shades the hits of `t` (a tile's slab search) into `out`, noting the unconfirmed
/// ones' jobs in `out.unconfirmed_rays`.
pub(super) fn shade_groups<A: Arithmetic, S: Shape>(
    ctx: &TileCtx<'_, S>,
    t: &SlabTile,
    out: &mut TileOut,
) {
    let root = ctx.root;
    let by_values = ctx.opts.specialise && root.specialises_values();
    let pad = DVec3::splat(ctx.shade_pad);
    let widen = |b: &Aabb| Aabb::new(b.min - pad, b.max + pad);
    let mut parent: Option<(usize, Option<S>)> = None;
    let mut samples = Samples::default();
    let mut at: Vec<(DVec3, f64)> = Vec::new();
    let mut values: Vec<[f64; 6]> = Vec::new();
    for g in &t.groups {
        let hits = &t.hits[g.start..g.end];
        let region = widen(&g.region);
        let shape = if by_values {
            if parent.as_ref().is_none_or(|p| p.0 != g.parent) {
                let b = widen(&t.parents[g.parent]);
                out.stats.shade_evals += 1;
                out.stats.range_ops += root.tape_len().unwrap_or(0) as u64;
                parent = Some((g.parent, root.specialise_values(&ranges(&b), f64::INFINITY)));
            }
            let up = parent.as_ref().and_then(|p| p.1.as_ref()).unwrap_or(root);
            out.stats.shade_evals += 1;
            out.stats.range_ops += up.tape_len().unwrap_or(0) as u64;
            up.specialise_values(&ranges(&region), f64::INFINITY)
        } else {
            None
        };
        let parent_shape = parent.as_ref().and_then(|p| p.1.as_ref());
        let shape = shape.as_ref().or(parent_shape).unwrap_or(root);
        at.clear();
        at.extend(hits.iter().map(|&(job, d)| {
            let r = &t.jobs[job];
            let step = ctx.params.precision.at(d);
            (r.o + r.d * d, step.max(ctx.scale * SHADING_STEP))
        }));
        out.stats.point_evals += 6 * hits.len() as u64;
        values.clear();
        let inside = |&(p, h): &(DVec3, f64)| {
            let h = DVec3::splat(h);
            region.min.cmple(p - h).all() && (p + h).cmple(region.max).all()
        };
        if at.iter().all(inside) {
            values.extend(samples.values(shape, at.iter().copied()));
        } else {
            values.extend(samples.values(root, at.iter().copied()));
        }
        for ((&(job, d), &(p, step)), s) in hits.iter().zip(&at).zip(&values) {
            let ray = (job, t.pixel_of[job], t.jobs[job].d);
            write_hit::<A, S>(ctx, ray, (d, p, step), s, out);
        }
    }
}
