//! The reliable tracer: tiles in parallel (rayon), each tile traversed by cell culling
//! ([`crate::search::cull`]) and its remaining pixels traced by Algorithm 1
//! ([`crate::search::ray`]), shaded ([`shade`]), with optional shadow rays through the
//! same reliable intersection, written by `tracer_kit::output`. Monomorphised once per
//! arithmetic and shape; the per-ray path does not allocate for `Copy` arithmetics.
//! The types it takes and gives are in [`types`].

pub mod auto_arith;
pub mod downsample;
pub mod shade;
mod shade_hits;
pub mod tile_shapes;
pub mod types;
pub mod value_tree;

pub use types::{RenderOptions, RenderResult, RenderStats};

use crate::search::cull::{CullStats, Culler};
use crate::search::ray::{first_roots_until, RayParams};
use crate::search::tile_rays::tile_rays;
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
    let start = Instant::now();
    let cam = checked_camera(opts)?;
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
    let (per_tile, tile_evals, value_evals) = if opts.specialise && shape.specialises() {
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
    };
    let outs: Vec<Option<TileOut>> = tiles
        .par_iter()
        .enumerate()
        .map(|(k, &rect)| {
            if stop() {
                return None;
            }
            let out = render_tile::<A, S>(&ctx, per_tile.get(k), rect, &stop);
            if let Some(p) = &opts.progress {
                p.tile_done();
            }
            Some(out)
        })
        .collect();
    if let Some(p) = &opts.progress {
        p.finish();
    }

    let (w, h) = (opts.width as usize, opts.height as usize);
    // Every pixel is written below: by its tile, or as background where a tile was cut.
    let mut rgb = vec![0u8; w * h * 3];
    let mut depth = vec![0.0f32; w * h];
    let mut stats = RenderStats {
        tiles_total: tiles.len() as u64,
        cell_evals: tile_evals + value_evals.load(std::sync::atomic::Ordering::Relaxed),
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
    Ok(RenderResult::of_image(opts, rgb, depth, stats))
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

/// Renders the tile `rect` (pixels `[i0, i1) x [j0, j1)`): culling hands out the rays
/// to search ([`tile_rays`](crate::search::tile_rays)), which are searched in lock-step ([`first_roots_until`],
/// stopping early, keeping what it found, when `stop` says so; the rays left are
/// background), and the hits shaded ([`shade_hits`]). `mine` are the tile's
/// specialised shapes.
fn render_tile<A: Arithmetic, S: Shape>(
    ctx: &TileCtx<'_, S>,
    mine: Option<&TileShapes<S>>,
    rect: (u32, u32, u32, u32),
    stop: &(dyn Fn() -> bool + Sync),
) -> TileOut {
    let shape = mine.and_then(|m| m.search.as_deref()).unwrap_or(ctx.root);
    let (i0, j0, i1, j1) = rect;
    let mut out = TileOut::background(ctx.opts, ((i1 - i0) * (j1 - j0)) as usize);
    let mut cs = CullStats::default();
    let culler = ctx.opts.culling.then_some(ctx.culler);
    let rays = tile_rays::<A, S>(culler, ctx.cam, &ctx.opts.domain, shape, rect, &mut cs);
    let st = &mut out.stats;
    st.rays += rays.traced;
    let windows: Vec<&Windows<S>> = rays.locals.iter().map(|l| &**l).collect();
    let mut hits: Vec<(usize, f64)> = Vec::new();
    let all = first_roots_until::<A, S>(
        shape,
        &windows,
        ctx.params,
        &rays.jobs,
        stop,
        |ray, hit, rs| {
            st.range_evals += rs.range_evals;
            st.range_ops += rs.range_ops;
            st.pruned_empty += rs.pruned_empty;
            st.point_evals += rs.point_evals;
            if let Some(t) = hit {
                st.hits += 1;
                st.range_evals_hit += rs.range_evals;
                hits.push((ray, t));
            }
        },
    );
    out.cut = !all;
    shade_hits::<A, S>(ctx, shape, mine, &rays, &mut hits, &mut out);
    // The fine depth windows the rays built.
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
    out
}
