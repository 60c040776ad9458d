//! The GPU renderer: a model of the registry as a tape of the model IR ([`Model::tape`],
//! from which [`crate::codegen`] generates its shaders), its rays and culling cells
//! prepared in `f64` exactly as the CPU renderer's ([`Camera::ray`],
//! [`tracer::search::ray::clip`]), searched on the device by the [`crate::engine`] and
//! shaded by [`tracer::render::shade`], giving the same [`RenderResult`] as
//! [`tracer::render::render`].

use crate::{Bundle, Cells, Frame, Gpu, GpuArith, Status, Tracer};
use glam::DVec3;
use model_ir::arith::ArithKind;
use model_ir::camera::Camera;
use model_ir::Tape;
use model_sources::Model;
use std::time::Instant;
use tracer::render::shade::{self, Light};
use tracer::render::{RenderOptions, RenderResult, RenderStats};
use tracer::search::ray::clip;

/// Side of the culling pass's screen cells, in pixels.
pub const CELL: u32 = 8;

/// The GPU arithmetic of `kind`; an error naming the ones the GPU has.
pub fn gpu_arith(kind: ArithKind) -> Result<GpuArith, String> {
    GpuArith::from_name(kind.name()).ok_or_else(|| {
        format!(
            "arithmetic '{}' has no GPU form (the GPU renders in ia, raa or revaa)",
            kind.name()
        )
    })
}

/// The frame of `opts` for the GPU: each pixel's `f64` ray clipped to the domain, the
/// precision, and with culling one bundle per `CELL x CELL` cell.
pub fn frame(opts: &RenderOptions) -> Result<(Frame, Camera), String> {
    let cam = tracer::render::checked_camera(opts)?;
    let dom = opts.domain;
    let precision = opts.precision(&cam);
    let scale = (dom.max - dom.min).length();
    let mut rays = Vec::with_capacity((opts.width * opts.height) as usize);
    for j in 0..opts.height {
        for i in 0..opts.width {
            let (o, d) = cam.ray(i, j);
            let (s0, s1) = clip(o, d, &dom, 0.0).unwrap_or((1.0, 0.0));
            rays.push(Bundle {
                origin: o.to_array(),
                origin_rad: [0.0; 3],
                dir: d.to_array(),
                dir_rad: [0.0; 3],
                s0,
                s1,
            });
        }
    }
    let cells = opts.culling.then(|| cells(&cam, opts));
    Ok((
        Frame {
            width: opts.width,
            height: opts.height,
            rays,
            // f32 resolves about 2^-20 of the scene: a floor on the precision.
            eps_abs: precision.abs.max(scale * 1e-6),
            eps_rel: precision.rel,
            normal_h: scale * 1e-4,
            pruning: opts.pruning,
            cells,
        },
        cam,
    ))
}

/// The culling cells: the raw directions `forward + dx right + dy up` of a cell's
/// pixels (an orthographic view's: `forward` alone) and their origins (the eye; an
/// orthographic view's image-plane points), each as a centre and a radius (both are
/// affine in the pixel coordinates, so the corners bound them), over the depths along
/// `forward` of the domain's corners. `s` is then the depth along `forward` (the raw
/// direction's `forward` component is 1), widened for the rounding of the set-up.
fn cells(cam: &Camera, opts: &RenderOptions) -> Cells {
    let dom = opts.domain;
    let corners = (0..8).map(|k| {
        DVec3::new(
            if k & 1 == 0 { dom.min.x } else { dom.max.x },
            if k & 2 == 0 { dom.min.y } else { dom.max.y },
            if k & 4 == 0 { dom.min.z } else { dom.max.z },
        )
    });
    let depths: Vec<f64> = corners.map(|c| (c - cam.eye).dot(cam.forward)).collect();
    let lo = depths
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min)
        .max(0.0);
    let hi = depths.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (s0, s1) = (lo * (1.0 - 1e-9), hi * (1.0 + 1e-9) + 1e-300);
    let cells_x = opts.width.div_ceil(CELL);
    let rows = opts.height.div_ceil(CELL);
    let mut bundles = Vec::with_capacity((cells_x * rows) as usize);
    for cy in 0..rows {
        for cx in 0..cells_x {
            let (x0, y0) = ((cx * CELL) as f64, (cy * CELL) as f64);
            let x1 = ((cx + 1) * CELL).min(opts.width) as f64;
            let y1 = ((cy + 1) * CELL).min(opts.height) as f64;
            let corners = [(x0, y0), (x1, y1), (x0, y1), (x1, y0)];
            let (dir, dir_rad) = centre_radius(corners.map(|(x, y)| cam.raw_dir(x, y)));
            let (origin, origin_rad) = centre_radius(corners.map(|(x, y)| cam.origin_at(x, y)));
            bundles.push(Bundle {
                origin: origin.to_array(),
                origin_rad: origin_rad.to_array(),
                dir: dir.to_array(),
                dir_rad: dir_rad.to_array(),
                s0,
                s1,
            });
        }
    }
    Cells {
        cell: CELL,
        cells_x,
        bundles,
    }
}

/// The centre of the first two of `corners` (opposite corners of a cell) and a radius
/// reaching all four, widened for the rounding of the set-up (a few ulps of their size).
fn centre_radius(corners: [DVec3; 4]) -> (DVec3, DVec3) {
    let mid = (corners[0] + corners[1]) * 0.5;
    let rad = corners
        .iter()
        .map(|v| (*v - mid).abs())
        .fold(DVec3::ZERO, DVec3::max);
    let scale = corners
        .iter()
        .map(|v| v.abs().max_element())
        .fold(0.0, f64::max);
    (mid, rad + DVec3::splat(scale * 1e-12 + 1e-300))
}

/// Renders `model` on `gpu` in `kind` with `opts` (as [`tracer::render::render`]; the
/// shadows, progress and deadline options are not used). `stats.unconfirmed` counts the
/// hits without a proved sign change.
pub fn render(
    gpu: &Gpu,
    kind: ArithKind,
    model: &Model,
    opts: &RenderOptions,
) -> Result<RenderResult, String> {
    let tape = model
        .tape()
        .map_err(|e| format!("{e} (the GPU renders tapes)"))?;
    render_tape(gpu, kind, &tape, opts)
}

/// [`render`] of a model's tape.
pub fn render_tape(
    gpu: &Gpu,
    kind: ArithKind,
    tape: &Tape,
    opts: &RenderOptions,
) -> Result<RenderResult, String> {
    let tracer = Tracer::new(gpu, tape, gpu_arith(kind)?)?;
    render_with(&tracer, opts)
}

/// [`render`] on a tracer already compiled for the model and arithmetic (the window's
/// frames reuse one).
pub fn render_with(tracer: &Tracer, opts: &RenderOptions) -> Result<RenderResult, String> {
    let start = Instant::now();
    let (frame, cam) = frame(opts)?;
    let out = tracer.render(&frame)?;
    let light = Light::for_camera(&cam);
    let n = (opts.width * opts.height) as usize;
    let mut rgb = opts.background.repeat(n);
    let mut depth = vec![f32::INFINITY; n];
    let mut stats = RenderStats {
        rays: n as u64,
        tiles_total: 1,
        tiles_done: 1,
        cells_culled: out.cells_culled,
        cell_evals: frame.cells.as_ref().map_or(0, |c| c.bundles.len() as u64),
        ..Default::default()
    };
    for k in 0..n {
        let st = out.status[k];
        stats.range_evals += out.evals[k] as u64;
        match st {
            Status::Culled => stats.pixels_culled += 1,
            Status::Miss => {}
            Status::Hit | Status::Unconfirmed => {
                stats.hits += 1;
                stats.range_evals_hit += out.evals[k] as u64;
                if st == Status::Unconfirmed {
                    stats.unconfirmed += 1;
                }
                depth[k] = out.depth[k];
                let nv = out.normal[k];
                let nv = DVec3::new(nv[0] as f64, nv[1] as f64, nv[2] as f64);
                let normal = (nv.length() > 0.5).then_some(nv);
                let d = DVec3::from_array(frame.rays[k].dir);
                let c = shade::shade(normal, d, &light, &opts.material, false);
                rgb[k * 3..k * 3 + 3].copy_from_slice(&c);
            }
        }
    }
    stats.wall = start.elapsed();
    Ok(RenderResult::of_image(opts, rgb, depth, stats))
}
