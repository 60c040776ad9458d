//! Shading a tile's hits: normals and the sign check from six point samples around
//! each hit ([`shade::samples`]), evaluated a group of neighbouring hits at a time in
//! one batch ([`Samples`]), on the shortest shape that gives the whole shape's values
//! there, then lit ([`shade::shade`]) with optional shadow rays.
//!
//! Hits come in the order of their rays, which come cell by cell, so neighbouring hits
//! are neighbours in the list. A *group* is up to [`SHADE_GROUP`] of them whose
//! samples fit in a box [`SHADE_BOX`] steps wide (a depth jump starts a new one); its
//! normals come from the shape specialised to that box, with the whole shape's values
//! there ([`Shape::specialise_values`]). Where the tile has value shapes and a level, a
//! group inside one of its slices first tries the shape folded by level of the smallest
//! box of that slice's value tree ([`ValueTree`]) that holds it: its samples' values
//! are the whole shape's when they lie within the level, checked hit by hit, else they
//! are evaluated again on the slice's exact value shape (built then). Without a level a
//! group starts from the slice's exact shape, and outside every slice from its
//! *block*'s ([`SHADE_BLOCK`] hits; specialised over the box of the block's samples
//! when first needed).

use super::shade::{self, Samples};
use super::tile_shapes::{self, TileShapes};
use super::types::{RenderStats, TileCtx, TileOut};
use super::value_tree::ValueTree;
use crate::search::ray::{clip, first_root, Precision, RayJob, RayParams, RayStats, Start};
use crate::search::tile_rays::TileRays;
use arith_core::Arithmetic;
use arith_ia::Interval;
use glam::DVec3;
use model_ir::shape::{Aabb, Shape};

/// The least step of the normals' central differences, per unit of the domain's
/// diagonal (the step is otherwise the precision at the hit).
pub(super) const SHADING_STEP: f64 = 1e-7;

/// Hits shaded with one shape specialised to the box of their samples: more share one
/// evaluation of the whole shape over the box, fewer make the box (and the shape) small.
const SHADE_GROUP: usize = 16;

/// Hits whose shape for shading is specialised once, for their groups to start from.
const SHADE_BLOCK: usize = 256;

/// The widest box (in sample steps) a group of hits is shaded in.
pub(super) const SHADE_BOX: f64 = 16.0;

/// Hits of a tile whose samples set its shading level (see [`probe_level`]).
const LEVEL_PROBES: usize = 8;

/// How far above the largest sample value of the probed hits the level lies.
const LEVEL_MARGIN: f64 = 4.0;

/// The box of the shading samples ([`shade::samples`]) of some hits: exactly the least
/// and greatest of their rounded coordinates, so every sample lies in it.
#[derive(Clone, Copy)]
struct SampleBox {
    lo: DVec3,
    hi: DVec3,
}

impl SampleBox {
    const EMPTY: SampleBox = SampleBox {
        lo: DVec3::INFINITY,
        hi: DVec3::NEG_INFINITY,
    };

    /// This box and the samples of a hit at `p` with step `h`.
    fn with(self, (p, h): (DVec3, f64)) -> SampleBox {
        shade::samples(p, h).iter().fold(self, |b, &q| SampleBox {
            lo: b.lo.min(q),
            hi: b.hi.max(q),
        })
    }

    /// Its sides as intervals.
    fn ranges(&self) -> [Interval; 3] {
        tile_shapes::ranges(&Aabb::new(self.lo, self.hi))
    }
}

/// A tile's shading: what its groups share.
struct Shader<'a, S> {
    ctx: &'a TileCtx<'a, S>,
    rays: &'a TileRays<S>,
    /// The tile's value shapes, where shading folds by value.
    tiled: Option<&'a TileShapes<S>>,
    by_values: bool,
    /// The tile's level (`inf`: none).
    within: f64,
    samples: Samples,
    /// The current group's samples, `(point, step)` per hit, their values, and the
    /// hits whose values are evaluated again on the exact shape.
    at: Vec<(DVec3, f64)>,
    values: Vec<[f64; 6]>,
    again: Vec<usize>,
}

/// One group's shapes: the exact one where already known (else the slice's, built
/// when a sample needs it) and the one folded by the level.
struct GroupShapes<'g, S> {
    exact: Option<&'g S>,
    slice: Option<(&'g TileShapes<S>, usize)>,
    fast: Option<&'g S>,
}

/// Shades the tile's `hits` (ray, distance), writing their pixels' colour and depth.
/// `shape` is the tile's search shape, `mine` its value shapes.
pub(super) fn shade_hits<A: Arithmetic, S: Shape>(
    ctx: &TileCtx<'_, S>,
    shape: &S,
    mine: Option<&TileShapes<S>>,
    rays: &TileRays<S>,
    hits: &mut [(usize, f64)],
    out: &mut TileOut,
) {
    hits.sort_unstable_by_key(|h| h.0);
    let by_values = ctx.opts.specialise && ctx.root.specialises_values();
    let tiled = mine.filter(|m| by_values && m.slices() > 0);
    let mut sh = Shader {
        ctx,
        rays,
        tiled,
        by_values,
        within: f64::INFINITY,
        samples: Samples::default(),
        at: Vec::with_capacity(SHADE_GROUP),
        values: Vec::with_capacity(SHADE_GROUP),
        again: Vec::with_capacity(SHADE_GROUP),
    };
    if tiled.is_some() {
        let probes = hits.iter().take(LEVEL_PROBES).map(|h| sh.sample_at(h));
        sh.within = probe_level(shape, probes);
    }
    let mut trees: Vec<Option<ValueTree<S>>> =
        (0..tiled.map_or(0, |m| m.slices())).map(|_| None).collect();
    let block_len = if by_values { SHADE_BLOCK } else { 1 };
    for block in hits.chunks(block_len) {
        sh.block::<A>(block, &mut trees, out);
    }
    for t in trees.iter_mut().flatten() {
        let (folds, ops) = t.take_counts();
        out.stats.shade_evals += folds;
        out.stats.range_ops += ops;
    }
}

impl<'a, S: Shape> Shader<'a, S> {
    /// The sample point and step of a hit.
    fn sample_at(&self, &(ray, t): &(usize, f64)) -> (DVec3, f64) {
        let RayJob { o, d, .. } = self.rays.jobs[ray];
        let step = self.ctx.params.precision.at(t);
        (o + d * t, step.max(self.ctx.scale * SHADING_STEP))
    }

    /// `base` folded by value over the box `b` (see [`Shape::specialise_values`]).
    fn values_over(base: &S, b: &SampleBox, within: f64, st: &mut RenderStats) -> Option<S> {
        st.shade_evals += 1;
        st.range_ops += base.tape_len().unwrap_or(0) as u64;
        base.specialise_values(&b.ranges(), within)
    }

    /// Shades a block of hits, group by group.
    fn block<A: Arithmetic>(
        &mut self,
        block: &[(usize, f64)],
        trees: &mut [Option<ValueTree<S>>],
        out: &mut TileOut,
    ) {
        let root = self.ctx.root;
        let mut block_shape: Option<Option<S>> = None;
        let mut rest = block;
        while !rest.is_empty() {
            let b = self.next_group(rest);
            let (group, next) = rest.split_at(self.at.len());
            rest = next;
            let slice = self.tiled.and_then(|m| Some((m, m.slice_for(b.lo, b.hi)?)));
            let (exact, level): (Option<&S>, Option<&S>) = match slice {
                Some((m, k)) if self.within < f64::INFINITY => {
                    let tree = trees[k].get_or_insert_with(|| {
                        let bx = m.slice_box(k).expect("slice_for gives slices with points");
                        ValueTree::new(root, *bx, self.within)
                    });
                    (None, Some(tree.at(root, b.lo, b.hi)))
                }
                Some((m, k)) => (Some(m.values_in(root, k)), None),
                None if self.by_values => {
                    let whole = block_shape.get_or_insert_with(|| {
                        let mut bb = SampleBox::EMPTY;
                        block
                            .iter()
                            .for_each(|hit| bb = bb.with(self.sample_at(hit)));
                        Self::values_over(root, &bb, f64::INFINITY, &mut out.stats)
                    });
                    (Some(whole.as_ref().unwrap_or(root)), None)
                }
                None => (Some(root), None),
            };
            let folded = level.map(|l| (l, Self::values_over(l, &b, self.within, &mut out.stats)));
            let fast = folded.as_ref().map(|(l, f)| f.as_ref().unwrap_or(l));
            let shapes = GroupShapes { exact, slice, fast };
            self.group::<A>(group, &b, shapes, out);
        }
    }

    /// Takes the next group from the front of `rest` into `self.at`: up to
    /// [`SHADE_GROUP`] hits whose samples fit in a box [`SHADE_BOX`] steps wide (a depth
    /// jump starts a new one). Returns the box of their samples.
    fn next_group(&mut self, rest: &[(usize, f64)]) -> SampleBox {
        let mut b = SampleBox::EMPTY;
        self.at.clear();
        for hit in rest.iter().take(SHADE_GROUP) {
            let (p, h) = self.sample_at(hit);
            let wider = b.with((p, h));
            if !self.at.is_empty() && (wider.hi - wider.lo).max_element() > SHADE_BOX * h {
                break;
            }
            b = wider;
            self.at.push((p, h));
        }
        b
    }

    /// Shades one group: the samples of all its hits in one batch on the folded shape,
    /// those outside the level (or all, without one) in a second batch on the exact one.
    fn group<A: Arithmetic>(
        &mut self,
        group: &[(usize, f64)],
        b: &SampleBox,
        shapes: GroupShapes<'_, S>,
        out: &mut TileOut,
    ) {
        let (root, within) = (self.ctx.root, self.within);
        let n = group.len();
        self.values.clear();
        self.values.resize(n, [f64::NAN; 6]);
        self.again.clear();
        out.stats.point_evals += 6 * n as u64;
        match shapes.fast {
            Some(f) => {
                for (i, s) in self.samples.values(f, self.at.iter().copied()).enumerate() {
                    if s.iter().all(|v| v.abs() < within) {
                        self.values[i] = s;
                    } else {
                        self.again.push(i);
                    }
                }
            }
            None => self.again.extend(0..n),
        }
        if !self.again.is_empty() {
            if shapes.fast.is_some() {
                out.stats.point_evals += 6 * self.again.len() as u64;
            }
            let exact = shapes
                .exact
                .unwrap_or_else(|| shapes.slice.map_or(root, |(m, k)| m.values_in(root, k)));
            let slow = if self.by_values {
                Self::values_over(exact, b, f64::INFINITY, &mut out.stats)
            } else {
                None
            };
            let e = slow.as_ref().unwrap_or(exact);
            let at = self.again.iter().map(|&i| self.at[i]);
            for (&i, s) in self.again.iter().zip(self.samples.values(e, at)) {
                self.values[i] = s;
            }
        }
        for ((&(ray, t), &(p, step)), s) in group.iter().zip(&self.at).zip(&self.values) {
            self.shade_hit::<A>(ray, t, p, step, s, out);
        }
    }

    /// Lights one hit from its samples' values and writes its pixel.
    fn shade_hit<A: Arithmetic>(
        &self,
        ray: usize,
        t: f64,
        p: DVec3,
        step: f64,
        s: &[f64; 6],
        out: &mut TileOut,
    ) {
        let (k, d) = (self.rays.pixel_of[ray], self.rays.jobs[ray].d);
        write_hit::<A, S>(self.ctx, (ray, k, d), (t, p, step), s, out);
    }
}

/// Lights one hit from the values `s` of its samples and writes its pixel `k`: the ray
/// `ray` (direction `d`) meets the surface at distance `t`, at `p`, sampled with step
/// `step`. A hit whose samples hold no sign change is counted unconfirmed and its ray
/// noted in `out`.
pub(super) fn write_hit<A: Arithmetic, S: Shape>(
    ctx: &TileCtx<'_, S>,
    (ray, k, d): (usize, usize, DVec3),
    (t, p, step): (f64, DVec3, f64),
    s: &[f64; 6],
    out: &mut TileOut,
) {
    out.depth[k] = t as f32;
    let (n, confirmed) = shade::normal_of_samples(s);
    if !confirmed {
        out.stats.unconfirmed += 1;
        out.unconfirmed_rays.push(ray);
    }
    let in_shadow = ctx.opts.shadows && shadowed::<A, S>(ctx, p, n, step, &mut out.stats);
    let c = shade::shade(n, d, ctx.light, &ctx.opts.material, in_shadow);
    out.rgb[k * 3..k * 3 + 3].copy_from_slice(&c);
}

/// The level for the tile's folded value shapes: [`LEVEL_MARGIN`] times the largest
/// value at the samples of `probes` (hits, with their sample step) of `shape`, the
/// tile's search shape; `inf` (no folding) where they are all 0 or not finite. Any level
/// is sound (values outside it are evaluated again exactly); one that holds most
/// samples lets the folded shapes be short. The search shape keeps its sign, not its
/// value, but near a root what it keeps is the primitives that make the surface there,
/// which is all a level needs, and it is far shorter than the whole shape (building
/// the tile's exact value shapes to probe them cost a quarter of a 10000-ball render).
fn probe_level<S: Shape>(shape: &S, probes: impl Iterator<Item = (DVec3, f64)>) -> f64 {
    let mut top = 0.0f64;
    for v in Samples::default().values(shape, probes).flatten() {
        if v.is_finite() {
            top = top.max(v.abs());
        }
    }
    if top > 0.0 {
        LEVEL_MARGIN * top
    } else {
        f64::INFINITY
    }
}

/// Whether the segment from just off the surface at `p` (normal `n`, sample step
/// `step`) towards the light holds a root.
pub(super) fn shadowed<A: Arithmetic, S: Shape>(
    ctx: &TileCtx<'_, S>,
    p: DVec3,
    n: Option<DVec3>,
    step: f64,
    st: &mut RenderStats,
) -> bool {
    let (shape, l) = (ctx.root, ctx.light.dir);
    // Leave the surface on the light's side, far enough that the surface itself is not
    // found again.
    let off = (8.0 * step).max(ctx.scale * 1e-4);
    let side = match n {
        Some(n) if n.dot(l) < 0.0 => -n,
        Some(n) => n,
        None => l,
    };
    let start = p + side * off;
    st.shadow_rays += 1;
    let Some((t0, t1)) = clip(start, l, &ctx.opts.domain, off) else {
        return false;
    };
    let mut rs = RayStats::default();
    let sp = RayParams {
        precision: Precision {
            abs: ctx.params.precision.at(0.0).max(step),
            rel: 0.0,
        },
        pruning: ctx.params.pruning,
    };
    let hit = first_root::<A, S>(shape, start, l, Start::whole(t0, t1), &sp, &mut rs).is_some();
    st.range_evals += rs.range_evals;
    st.range_ops += rs.range_evals * shape.tape_len().unwrap_or(0) as u64;
    st.point_evals += rs.point_evals;
    hit
}
