//! The reliable tracer: tiles in parallel (rayon), each tile traversed by cell culling
//! ([`crate::search::cull`]) and its remaining pixels traced by Algorithm 1
//! ([`crate::search::ray`]), shaded ([`shade`]), with optional shadow rays through the
//! same reliable intersection, written by `tracer_kit::output`. Monomorphised once per
//! arithmetic and shape; the per-ray path does not allocate for `Copy` arithmetics.
//! The types it takes and gives are in [`types`].

pub mod auto_arith;
pub mod downsample;
pub mod shade;
mod shade_groups;
mod shade_hits;
pub mod tile_shapes;
pub mod types;
pub mod value_tree;

pub use types::{RenderOptions, RenderResult, RenderStats, Search};

use crate::search::cull::{CullStats, Culler};
use crate::search::ray::{first_roots_until, RayJob, RayParams};
use crate::search::slabs;
use crate::search::tile_rays::{tile_rays, TileRays};
use crate::search::windows::Windows;
use arith_core::Arithmetic;
use glam::DVec3;
use model_ir::arith::ArithKind;
use model_ir::camera::Camera;
use model_ir::shape::{check_domain, Shape};
use rayon::prelude::*;
use shade::Light;
use shade_hits::{shade_hits, SHADE_BOX, SHADING_STEP};
use std::sync::atomic::Ordering;
use std::time::Instant;
use tile_shapes::{tile_shapes, TileShapes};
use types::{TileCtx, TileOut};

/// Renders `shape` in the arithmetic `A`. Errors, before allocating anything, on a
/// degenerate view, size ([`model_ir::camera::check_size`]), precision or domain.
pub fn render<A: Arithmetic, S: Shape>(
    shape: &S,
    opts: &RenderOptions,
) -> Result<RenderResult, String> {
    render_tiles(shape, opts, &|t: &Tiles<'_, S>| {
        t.run(&(0..t.len()).collect::<Vec<_>>(), render_tile::<A, S>)
    })
}

/// What renders one tile: the render's shared context, the tile's specialised shapes,
/// its pixels `[i0, i1) x [j0, j1)` and when to stop.
pub(crate) type TileFn<S> = fn(
    &TileCtx<'_, S>,
    Option<&TileShapes<S>>,
    (u32, u32, u32, u32),
    &(dyn Fn() -> bool + Sync),
) -> TileOut;

/// A render's tiles, ready to run.
pub(crate) struct Tiles<'a, S> {
    ctx: TileCtx<'a, S>,
    rects: &'a [(u32, u32, u32, u32)],
    per_tile: &'a [TileShapes<S>],
    stop: &'a (dyn Fn() -> bool + Sync),
}

impl<S: Shape> Tiles<'_, S> {
    /// How many tiles the image has.
    pub(crate) fn len(&self) -> usize {
        self.rects.len()
    }

    /// Runs `tile_fn` on the tiles `which` in parallel, in that order (`None`: not
    /// started, the render being stopped), each counted done on the progress bar.
    pub(crate) fn run(&self, which: &[usize], tile_fn: TileFn<S>) -> Vec<Option<TileOut>> {
        which
            .par_iter()
            .map(|&k| {
                if (self.stop)() {
                    return None;
                }
                let out = tile_fn(&self.ctx, self.per_tile.get(k), self.rects[k], self.stop);
                if let Some(p) = &self.ctx.opts.progress {
                    p.tile_done();
                }
                Some(out)
            })
            .collect()
    }
}

/// The render's frame around its tiles: the checks, the tiles' specialised shapes, the
/// tiles run by `schedule` (one output per tile, in order), and the image and counters
/// put together.
pub(crate) fn render_tiles<S: Shape>(
    shape: &S,
    opts: &RenderOptions,
    schedule: &dyn Fn(&Tiles<'_, S>) -> Vec<Option<TileOut>>,
) -> Result<RenderResult, String> {
    let start = Instant::now();
    let cam = checked_camera(opts)?;
    let resolved;
    let opts = if opts.search == Search::Auto {
        let search = opts.search.resolve(shape, opts.specialise);
        resolved = RenderOptions {
            search,
            ..opts.clone()
        };
        &resolved
    } else {
        opts
    };
    let dom = opts.domain;
    let precision = opts.precision(&cam);
    let params = RayParams {
        precision,
        pruning: opts.pruning,
    };
    let light = Light::for_camera(&cam);
    let culler = Culler::new(&cam, &dom).specialising(opts.specialise);
    let scale = (dom.max - dom.min).length();
    let tile = opts.tile.max(1);
    let mut tiles = Vec::new();
    for j0 in (0..opts.height).step_by(tile as usize) {
        for i0 in (0..opts.width).step_by(tile as usize) {
            tiles.push((
                i0,
                j0,
                (i0 + tile).min(opts.width),
                (j0 + tile).min(opts.height),
            ));
        }
    }
    // A group of shading samples lies within `pad` of one of its hits (it is at most
    // SHADE_BOX steps wide, plus a step each side), the step being largest at the
    // farthest point of the domain from the eye (or the image plane); the tiles' value
    // shapes hold that far around their rays (a group outside them is checked).
    let far = (0..8)
        .map(|k| {
            let c = DVec3::new(
                if k & 1 == 0 { dom.min.x } else { dom.max.x },
                if k & 2 == 0 { dom.min.y } else { dom.max.y },
                if k & 4 == 0 { dom.min.z } else { dom.max.z },
            );
            (c - cam.eye).length()
        })
        .fold(0.0, f64::max)
        + cam.ortho.unwrap_or(0.0) * (1.0 + opts.height as f64 / opts.width as f64);
    let step = precision.at(far).max(scale * SHADING_STEP);
    let pad = (SHADE_BOX + 4.0) * step;
    // The slab search specialises its tile-slabs itself.
    let quadtree = opts.search == Search::Paper && opts.specialise && shape.specialises();
    let (per_tile, tile_evals, value_evals) = if quadtree {
        tile_shapes(shape, &culler, (opts.width, opts.height), tile, &tiles, pad)
    } else {
        (Vec::new(), 0, Default::default())
    };
    if let Some(p) = &opts.progress {
        p.start(tiles.len() as u64);
    }
    let stop = || {
        opts.deadline.is_some_and(|d| Instant::now() >= d)
            || opts
                .cancel
                .as_ref()
                .is_some_and(|c| c.load(Ordering::Relaxed))
    };

    let ctx = TileCtx {
        root: shape,
        opts,
        cam: &cam,
        culler: &culler,
        params: &params,
        light: &light,
        scale,
        shade_pad: 2.0 * step,
    };
    let outs = schedule(&Tiles {
        ctx,
        rects: &tiles,
        per_tile: &per_tile,
        stop: &stop,
    });
    if let Some(p) = &opts.progress {
        p.finish();
    }

    let cells = tile_evals + value_evals.load(Ordering::Relaxed);
    Ok(assemble(opts, &tiles, outs, cells, start))
}

/// The image of `tiles`' outputs (background where a tile was not run), with their
/// counters summed (`cells` range evaluations made before the tiles ran).
fn assemble(
    opts: &RenderOptions,
    tiles: &[(u32, u32, u32, u32)],
    outs: Vec<Option<TileOut>>,
    cells: u64,
    start: Instant,
) -> RenderResult {
    let (w, h) = (opts.width as usize, opts.height as usize);
    // Every pixel is written below: by its tile, or as background where a tile was cut.
    let mut rgb = vec![0u8; w * h * 3];
    let mut depth = vec![0.0f32; w * h];
    let mut stats = RenderStats {
        tiles_total: tiles.len() as u64,
        cell_evals: cells,
        ..Default::default()
    };
    for (&(i0, j0, i1, j1), out) in tiles.iter().zip(outs) {
        let tw = (i1 - i0) as usize;
        for j in j0..j1 {
            let dst = j as usize * w + i0 as usize;
            let (d, c) = (&mut depth[dst..dst + tw], &mut rgb[dst * 3..(dst + tw) * 3]);
            match &out {
                Some(out) => {
                    let src = (j - j0) as usize * tw;
                    d.copy_from_slice(&out.depth[src..src + tw]);
                    c.copy_from_slice(&out.rgb[src * 3..(src + tw) * 3]);
                }
                None => {
                    d.fill(f32::INFINITY);
                    for px in c.chunks_exact_mut(3) {
                        px.copy_from_slice(&opts.background);
                    }
                }
            }
        }
        let Some(out) = out else {
            stats.cut = true;
            continue;
        };
        stats.cut |= out.cut;
        stats += out.stats;
        stats.tiles_done += u64::from(!out.cut);
    }
    stats.wall = start.elapsed();
    RenderResult::of_image(opts, rgb, depth, stats)
}

/// The camera of `opts`, after checking its view, size, precision and domain (the
/// errors every renderer gives before any work).
pub fn checked_camera(opts: &RenderOptions) -> Result<Camera, String> {
    let cam = Camera::try_new(opts.view, opts.width, opts.height)?;
    if let Some(e) = opts.eps {
        if !(e > 0.0 && e.is_finite()) {
            return Err(format!("precision {e} must be positive and finite"));
        }
    }
    check_domain(&opts.domain).map_err(|e| format!("domain box: {e}"))?;
    Ok(cam)
}

/// [`render`] with the arithmetic chosen at run time.
pub fn render_kind<S: Shape>(
    kind: ArithKind,
    shape: &S,
    opts: &RenderOptions,
) -> Result<RenderResult, String> {
    model_ir::with_arith!(kind, A => render::<A, S>(shape, opts))
}

/// Renders the tile `rect` (pixels `[i0, i1) x [j0, j1)`) in the arithmetic `A`:
/// culling hands out its rays ([`cull_tile`]), which are searched ([`search_rays`]) and
/// the hits shaded ([`shade_hits`]). `mine` are the tile's specialised shapes.
fn render_tile<A: Arithmetic, S: Shape>(
    ctx: &TileCtx<'_, S>,
    mine: Option<&TileShapes<S>>,
    rect: (u32, u32, u32, u32),
    stop: &(dyn Fn() -> bool + Sync),
) -> TileOut {
    let (rays, cs, mut out) = trace_tile::<A, S>(ctx, mine, rect, stop);
    end_tile(&rays, cs, &mut out);
    out
}

/// The tile `rect` culled, searched and shaded in `A`: its rays, the culling counters
/// and its output (see [`render_tile`], which then adds the counters).
pub(crate) fn trace_tile<A: Arithmetic, S: Shape>(
    ctx: &TileCtx<'_, S>,
    mine: Option<&TileShapes<S>>,
    rect: (u32, u32, u32, u32),
    stop: &(dyn Fn() -> bool + Sync),
) -> (TileRays<S>, CullStats, TileOut) {
    if ctx.opts.search == Search::Slabs {
        return slab_tile::<A, S>(ctx, rect, stop);
    }
    let shape = tile_shape(ctx, mine);
    let (rays, cs, mut out) = cull_tile::<A, S>(ctx, shape, rect);
    let mut hits = search_rays::<A, S>(ctx, shape, &rays, &rays.jobs, stop, &mut out);
    shade_hits::<A, S>(ctx, shape, mine, &rays, &mut hits, &mut out);
    (rays, cs, out)
}

/// [`trace_tile`] by the slab search ([`slabs::search_tile`]): every ray of the tile
/// with one job (its whole piece in the domain), its hits shaded.
fn slab_tile<A: Arithmetic, S: Shape>(
    ctx: &TileCtx<'_, S>,
    rect: (u32, u32, u32, u32),
    stop: &(dyn Fn() -> bool + Sync),
) -> (TileRays<S>, CullStats, TileOut) {
    let (i0, j0, i1, j1) = rect;
    let mut out = TileOut::background(ctx.opts, ((i1 - i0) * (j1 - j0)) as usize);
    let (opts, root) = (ctx.opts, ctx.root);
    let t = slabs::search_tile::<A, S>(
        ctx.culler,
        ctx.cam,
        &opts.domain,
        root,
        ctx.params,
        rect,
        opts.specialise,
        None,
        stop,
    );
    out.stats.rays += t.jobs.len() as u64;
    count_slab_search(&t, &mut out);
    shade_groups::shade_groups::<A, S>(ctx, &t, &mut out);
    let rays = TileRays {
        traced: t.jobs.len() as u64,
        jobs: t.jobs,
        pixel_of: t.pixel_of,
        locals: Vec::new(),
    };
    (rays, t.cells, out)
}

/// The shape a tile searches: its specialised search shape, else the whole one.
pub(crate) fn tile_shape<'s, S: Shape>(
    ctx: &TileCtx<'s, S>,
    mine: Option<&'s TileShapes<S>>,
) -> &'s S {
    mine.and_then(|m| m.search.as_deref()).unwrap_or(ctx.root)
}

/// The rays culling (in `A`) leaves to search in the tile `rect`
/// ([`tile_rays`](crate::search::tile_rays)), its counters, and the tile's output, all
/// background so far.
pub(crate) fn cull_tile<A: Arithmetic, S: Shape>(
    ctx: &TileCtx<'_, S>,
    shape: &S,
    rect: (u32, u32, u32, u32),
) -> (TileRays<S>, CullStats, TileOut) {
    let (i0, j0, i1, j1) = rect;
    let mut out = TileOut::background(ctx.opts, ((i1 - i0) * (j1 - j0)) as usize);
    let mut cs = CullStats::default();
    let culler = ctx.opts.culling.then_some(ctx.culler);
    let rays = tile_rays::<A, S>(culler, ctx.cam, &ctx.opts.domain, shape, rect, &mut cs);
    out.stats.rays += rays.traced;
    (rays, cs, out)
}

/// The first roots of `jobs` (some of `rays`' jobs) in the arithmetic `A`, searched in
/// lock-step ([`first_roots_until`]), as `(job, distance)`; counted in `out`, which is
/// marked cut when `stop` ended the search early (the rays left are background).
pub(crate) fn search_rays<A: Arithmetic, S: Shape>(
    ctx: &TileCtx<'_, S>,
    shape: &S,
    rays: &TileRays<S>,
    jobs: &[RayJob],
    stop: &(dyn Fn() -> bool + Sync),
    out: &mut TileOut,
) -> Vec<(usize, f64)> {
    let windows: Vec<&Windows<S>> = rays.locals.iter().map(|l| &**l).collect();
    let mut hits: Vec<(usize, f64)> = Vec::new();
    let st = &mut out.stats;
    let all = first_roots_until::<A, S>(shape, &windows, ctx.params, jobs, stop, |ray, hit, rs| {
        st.add_rays(&rs);
        if let Some(t) = hit {
            st.hits += 1;
            st.range_evals_hit += rs.range_evals;
            hits.push((ray, t));
        }
    });
    out.cut |= !all;
    hits
}

/// The first roots of the rays `again` (indices into `rays`, the tile `rect`'s) searched
/// again in `A`, as `(ray, distance)`, counted in `out` (marked cut when `stop` ended
/// the search early): by the render's search, from the depths culling left them (the
/// paper's) or tile-slab by tile-slab over these pixels alone (the slab search).
pub(crate) fn search_again<A: Arithmetic, S: Shape>(
    ctx: &TileCtx<'_, S>,
    shape: &S,
    rays: &TileRays<S>,
    rect: (u32, u32, u32, u32),
    again: &[usize],
    stop: &(dyn Fn() -> bool + Sync),
    out: &mut TileOut,
) -> Vec<(usize, f64)> {
    if ctx.opts.search == Search::Paper {
        let jobs: Vec<RayJob> = again.iter().map(|&r| rays.jobs[r]).collect();
        let mut hits = search_rays::<A, S>(ctx, shape, rays, &jobs, stop, out);
        for h in &mut hits {
            h.0 = again[h.0];
        }
        return hits;
    }
    let pixels: Vec<usize> = again.iter().map(|&r| rays.pixel_of[r]).collect();
    let opts = ctx.opts;
    let t = slabs::search_tile::<A, S>(
        ctx.culler,
        ctx.cam,
        &opts.domain,
        ctx.root,
        ctx.params,
        rect,
        opts.specialise,
        Some(&pixels),
        stop,
    );
    out.stats.range_ops += t.cells.cell_ops;
    out.stats.cell_evals += t.cells.cells_tested + t.cells.cells_specialised;
    count_slab_search(&t, out);
    let ray_of: std::collections::HashMap<usize, usize> =
        again.iter().map(|&r| (rays.pixel_of[r], r)).collect();
    t.hits
        .iter()
        .map(|&(job, d)| (ray_of[&t.pixel_of[job]], d))
        .collect()
}

/// Adds a slab search's ray counters and hits to `out` (cut where it was).
fn count_slab_search(t: &slabs::SlabTile, out: &mut TileOut) {
    let st = &mut out.stats;
    st.add_rays(&t.rays);
    st.hits += t.hits.len() as u64;
    st.range_evals_hit += t.hit_evals;
    out.cut |= t.cut;
}

/// Adds the culling counters and the fine depth windows the rays built to `out`.
pub(crate) fn end_tile<S: Shape>(rays: &TileRays<S>, mut cs: CullStats, out: &mut TileOut) {
    for l in &rays.locals {
        let (evals, ops) = l.take_counts();
        cs.cells_specialised += evals;
        cs.cell_ops += ops;
    }
    let st = &mut out.stats;
    st.cell_evals = cs.cells_tested + cs.cells_specialised;
    st.range_ops += cs.cell_ops;
    st.cells_culled = cs.cells_culled;
    st.pixels_culled = cs.pixels_culled;
}
