//! The reliable tracer: tiles in parallel (rayon), each tile traversed by cell culling
//! ([`crate::search::cull`]) and its remaining pixels traced by Algorithm 1
//! ([`crate::search::ray`]), shaded ([`shade`]), with optional shadow rays through the
//! same reliable intersection, written by [`output`]. Monomorphised once per arithmetic
//! and shape; the per-ray path does not allocate for `Copy` arithmetics.

pub mod auto_arith;
pub mod bspline_filter;
pub mod output;
pub mod shade;
mod shade_hits;
pub mod tile_shapes;
pub mod value_tree;

use crate::arith::ArithKind;
use crate::camera::Camera;
use crate::models::Model;
use crate::search::cull::{CullStats, Culler};
use crate::search::ray::{clip_with, first_roots_until, Precision, RayJob, RayParams, Start};
use crate::search::windows::Windows;
use crate::shape::{check_domain, Aabb, Shape, View};
use arith_core::Arithmetic;
use glam::DVec3;
use rayon::prelude::*;
use shade::{Light, Material};
use shade_hits::{shade_hits, SHADE_BOX, SHADING_STEP};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use tile_shapes::{tile_shapes, TileShapes};

/// Follows a render's progress: told the number of tiles, then each finished tile (from
/// any of the worker threads), then the end.
pub trait Progress: Send + Sync + std::fmt::Debug {
    /// The render has `tiles` tiles to do.
    fn start(&self, tiles: u64);
    /// One more tile is done.
    fn tile_done(&self);
    /// No more tiles will be done (all of them, or the render was stopped).
    fn finish(&self);
}

/// What to render and how.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The camera placement.
    pub view: View,
    /// Rays are clipped to this box; the function is not looked at outside it.
    pub domain: Aabb,
    /// Absolute precision of the roots along the ray (`--eps`). `None`: a quarter of a
    /// pixel's footprint at the root's distance, floored at `1e-7` of the domain diagonal.
    pub eps: Option<f64>,
    /// Algorithm 2 (screen-space cell culling).
    pub culling: bool,
    /// Argument pruning in Algorithm 1.
    pub pruning: bool,
    /// Region specialisation ([`Shape::specialise`]): each cell culling keeps searches,
    /// and hands its rays, the shape specialised to its region. Only with `culling`;
    /// no effect on shapes that do not specialise (the built-in models).
    pub specialise: bool,
    /// Shadow rays towards the light.
    pub shadows: bool,
    /// Surface reflectance.
    pub material: Material,
    /// Colour of pixels that miss, RGB.
    pub background: [u8; 3],
    /// Told the number of tiles and each finished tile (a progress bar, say).
    pub progress: Option<Arc<dyn Progress>>,
    /// Stop starting new tiles after this instant (the result says it was cut).
    pub deadline: Option<Instant>,
    /// Stop starting new tiles once this flag is set.
    pub cancel: Option<Arc<AtomicBool>>,
    /// Tile side in pixels (the unit of parallel work and of the culling quadtree's root).
    pub tile: u32,
}

impl RenderOptions {
    /// The model's domain and view, culling and pruning on, no shadows.
    pub fn new(model: &Model, width: u32, height: u32) -> Self {
        Self::for_view(model.view, model.domain, width, height)
    }

    /// A view and a domain, culling and pruning on, no shadows.
    pub fn for_view(view: View, domain: Aabb, width: u32, height: u32) -> Self {
        RenderOptions {
            width,
            height,
            view,
            domain,
            eps: None,
            culling: true,
            pruning: true,
            specialise: true,
            shadows: false,
            material: Material::default(),
            background: shade::BACKGROUND,
            progress: None,
            deadline: None,
            cancel: None,
            tile: 64,
        }
    }

    /// The precision actually used along primary rays (see [`RenderOptions::eps`]).
    pub fn precision(&self, cam: &Camera) -> Precision {
        match self.eps {
            Some(e) => Precision { abs: e, rel: 0.0 },
            None => Precision {
                abs: 1e-7 * (self.domain.max - self.domain.min).length() + 0.25 * cam.pixel_size(),
                rel: 0.25 * cam.pixel_angle(),
            },
        }
    }
}

/// Work and time counters of one render.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Wall time of the render.
    pub wall: Duration,
    /// Primary rays traced (pixels not dropped by culling).
    pub rays: u64,
    /// Shadow rays traced.
    pub shadow_rays: u64,
    /// Range evaluations along rays (primary and shadow).
    pub range_evals: u64,
    /// Range evaluations along primary rays of pixels that hit.
    pub range_evals_hit: u64,
    /// Range evaluations of culling cells (narrowing and specialisation).
    pub cell_evals: u64,
    /// Range evaluations over the boxes of shading samples (the normals' tapes
    /// specialised there).
    pub shade_evals: u64,
    /// Instructions run by all range evaluations, on rays, cells and shading boxes, for
    /// shapes that are tapes ([`Shape::tape_len`]; 0 otherwise): with the three counts
    /// of evaluations, the mean tape length that specialisation brings down.
    pub range_ops: u64,
    /// Point evaluations (normals).
    pub point_evals: u64,
    /// Cells proved empty by culling.
    pub cells_culled: u64,
    /// Pixels inside culled cells (no ray traced).
    pub pixels_culled: u64,
    /// Segments proved root-free by argument pruning alone.
    pub pruned_empty: u64,
    /// Pixels whose ray hit the surface.
    pub hits: u64,
    /// Hit pixels whose root no sign change confirms: the six samples of `f` at the
    /// normal's step around the root (which the normal is computed from, so the check
    /// costs no evaluation) have one strict sign or are NaN; a sign change among them
    /// proves a surface point within that step. The search reports unconfirmed roots
    /// where a segment at the precision still has a range holding 0: tangent roots,
    /// features thinner than the precision, or a function whose ranges hold 0
    /// everywhere (infinite or NaN values).
    pub unconfirmed: u64,
    /// Whether the render stopped early (deadline or cancel): the pixels it did not finish are background.
    pub cut: bool,
    /// Tiles rendered.
    pub tiles_done: u64,
    /// Tiles in the image.
    pub tiles_total: u64,
}

impl RenderStats {
    /// Mean tape length of a range evaluation (rays and cells; 0 for shapes that are not
    /// tapes).
    pub fn mean_tape_len(&self) -> f64 {
        let evals = self.range_evals + self.cell_evals + self.shade_evals;
        if evals == 0 {
            0.0
        } else {
            self.range_ops as f64 / evals as f64
        }
    }

    /// Mean number of range evaluations per hit pixel (primary rays).
    pub fn mean_evals_per_hit(&self) -> f64 {
        if self.hits == 0 {
            0.0
        } else {
            self.range_evals_hit as f64 / self.hits as f64
        }
    }
}

impl std::fmt::Display for RenderStats {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "wall time:            {:.3} s{}",
            self.wall.as_secs_f64(),
            if self.cut { " (cut short)" } else { "" }
        )?;
        writeln!(
            f,
            "rays:                 {} primary, {} shadow",
            self.rays, self.shadow_rays
        )?;
        writeln!(
            f,
            "range evaluations:    {} on rays, {} on cells, {} on shading boxes",
            self.range_evals, self.cell_evals, self.shade_evals
        )?;
        writeln!(f, "point evaluations:    {}", self.point_evals)?;
        writeln!(
            f,
            "cells culled:         {} ({} pixels)",
            self.cells_culled, self.pixels_culled
        )?;
        writeln!(f, "hit pixels:           {}", self.hits)?;
        writeln!(f, "unconfirmed hits:     {}", self.unconfirmed)?;
        write!(f, "range evals per hit:  {:.2}", self.mean_evals_per_hit())?;
        if self.range_ops > 0 {
            write!(f, "\nmean tape length:     {:.1}", self.mean_tape_len())?;
        }
        Ok(())
    }
}

/// An image with its depth and hit mask, row-major, row 0 at the top.
#[derive(Clone, Debug)]
pub struct RenderResult {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// RGB, 3 bytes per pixel.
    pub rgb: Vec<u8>,
    /// Distance from the eye along the normalised ray to the first root; `+inf` for a miss.
    pub depth: Vec<f32>,
    /// Whether each pixel's ray hit the surface.
    pub hit: Vec<bool>,
    /// The render's counters.
    pub stats: RenderStats,
}

impl RenderResult {
    /// The result of an image of `opts`'s size: its hit mask is where `depth` is finite.
    pub(crate) fn of_image(
        opts: &RenderOptions,
        rgb: Vec<u8>,
        depth: Vec<f32>,
        stats: RenderStats,
    ) -> Self {
        let hit = depth.iter().map(|d| d.is_finite()).collect();
        RenderResult {
            width: opts.width,
            height: opts.height,
            rgb,
            depth,
            hit,
            stats,
        }
    }
}

struct TileOut {
    rgb: Vec<u8>,
    depth: Vec<f32>,
    stats: RenderStats,
    /// Stopped before its last rays: those pixels are background.
    cut: bool,
}

impl TileOut {
    /// `n` pixels of background.
    fn background(opts: &RenderOptions, n: usize) -> Self {
        TileOut {
            rgb: opts.background.repeat(n),
            depth: vec![f32::INFINITY; n],
            stats: RenderStats::default(),
            cut: false,
        }
    }
}

/// What every tile of a render shares.
struct TileCtx<'a, S> {
    /// The whole shape (shading and shadows reach outside a tile's rays).
    root: &'a S,
    opts: &'a RenderOptions,
    cam: &'a Camera,
    culler: &'a Culler,
    params: &'a RayParams,
    light: &'a Light,
    /// The domain's diagonal.
    scale: f64,
}

/// The rays of a tile left to search after culling.
struct TileRays<S> {
    jobs: Vec<RayJob>,
    /// The pixel (index in the tile) of each job.
    pixel_of: Vec<usize>,
    /// The cells' depth windows the jobs refer to (job shape `k` is `locals[k - 1]`).
    locals: Vec<Arc<Windows<S>>>,
    /// Rays culling handed out (some then miss the domain).
    traced: u64,
}

/// Renders `shape` in the arithmetic `A`. Errors, before allocating anything, on a
/// degenerate view, size ([`crate::camera::check_size`]), precision or domain.
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
        let s = out.stats;
        stats.rays += s.rays;
        stats.shadow_rays += s.shadow_rays;
        stats.range_evals += s.range_evals;
        stats.range_evals_hit += s.range_evals_hit;
        stats.cell_evals += s.cell_evals;
        stats.range_ops += s.range_ops;
        stats.shade_evals += s.shade_evals;
        stats.point_evals += s.point_evals;
        stats.cells_culled += s.cells_culled;
        stats.pixels_culled += s.pixels_culled;
        stats.pruned_empty += s.pruned_empty;
        stats.hits += s.hits;
        stats.unconfirmed += s.unconfirmed;
        stats.tiles_done += u64::from(!out.cut);
    }
    stats.wall = start.elapsed();
    Ok(RenderResult::of_image(opts, rgb, depth, stats))
}

/// The camera of `opts`, after checking its view, size, precision and domain (the
/// errors every renderer gives before any work).
pub(crate) fn checked_camera(opts: &RenderOptions) -> Result<Camera, String> {
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
    crate::with_arith!(kind, A => render::<A, S>(shape, opts))
}

/// Renders the tile `rect` (pixels `[i0, i1) x [j0, j1)`): culling hands out the rays
/// to search ([`tile_rays`]), which are searched in lock-step ([`first_roots_until`],
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
    let rays = tile_rays::<A, S>(ctx, shape, rect, &mut cs);
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

/// The rays of the tile `rect` that culling leaves to search (every ray of the tile
/// without culling), each clipped to the domain and to the depths culling left it, in
/// the order culling hands them out (cell by cell). Rays are set up four at a time
/// ([`Camera::rays4`]).
fn tile_rays<A: Arithmetic, S: Shape>(
    ctx: &TileCtx<'_, S>,
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
    if ctx.opts.culling {
        ctx.culler.traverse::<A, S, _>(shape, rect, cs, &mut trace);
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
        let set = ctx.cam.rays4(core::array::from_fn(|l| {
            (chunk[l.min(last)].0, chunk[l.min(last)].1)
        }));
        for (&(i, j, depths, local), &(d, inv, c, ic)) in chunk.iter().zip(&set) {
            let o = ctx.cam.origin_at(i as f64 + 0.5, j as f64 + 0.5);
            let domain = &ctx.opts.domain;
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
