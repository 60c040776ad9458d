//! `tracer render`: its arguments, the refusals before any work (flags, sizes, output
//! paths, `--device gpu` without the GPU renderer), the render with a progress bar and
//! Ctrl-C (the finished tiles are written), `--aa` filtering, and the statistics as
//! text or JSON.

use crate::args::{model_source, parse_positive, parse_size, set_threads, ModelArgs, ViewArgs};
use crate::bar::Bar;
use crate::stats_json::{json_string, stats_json};
use model_ir::arith::ArithKind;
use model_sources::Model;
use std::path::PathBuf;
use tracer::render::downsample::downsample_render;
use tracer::render::{render_kind, RenderOptions, RenderResult, RenderStats, Search};
use tracer_kit::bspline_filter::Filter;
use tracer_kit::out;
use tracer_kit::output::{check_outputs, write_depth, write_png};

/// Arguments of `tracer render`.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// The model.
    #[command(flatten)]
    pub src: ModelArgs,
    /// Arithmetic.
    #[arg(long, default_value = "auto", help = render_arith_help())]
    pub arith: String,
    /// Image size WxH.
    #[arg(long, default_value = "640x480", allow_hyphen_values = true)]
    pub size: String,
    /// Output PNG (default: <model>.png).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Depth map: .npy (float32, shape (H, W)) or .exr (one float32 channel Z); +inf on a miss.
    #[arg(long)]
    pub depth: Option<PathBuf>,
    /// The camera.
    #[command(flatten)]
    pub view: ViewArgs,
    /// Domain box XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX.
    #[arg(long, allow_hyphen_values = true)]
    pub domain: Option<String>,
    /// Absolute precision of roots along rays (default: a quarter pixel footprint).
    #[arg(long, allow_hyphen_values = true)]
    pub eps: Option<String>,
    /// How each pixel's first root is searched for: slabs (image tiles by depth slabs,
    /// each one interval evaluation, down to Algorithm 1 on short pieces of the rays),
    /// paper (Algorithm 2's cell culling, then Algorithm 1 on each ray, as the
    /// revised-affine paper; for its counts), or auto (slabs for formula, .vm and
    /// HyperFun models, whose tapes specialise; paper for the built-in models). Both
    /// find the same first roots.
    #[arg(long, default_value = "auto", allow_hyphen_values = true)]
    pub search: String,
    /// Disable cell culling (Algorithm 2, with --search paper).
    #[arg(long)]
    pub no_culling: bool,
    /// Disable argument pruning.
    #[arg(long)]
    pub no_pruning: bool,
    /// Disable region specialisation (formula, .vm and HyperFun models: each culling
    /// cell searches a tape shortened for its region).
    #[arg(long)]
    pub no_specialise: bool,
    /// Trace shadow rays towards the light.
    #[arg(long)]
    pub shadows: bool,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
    /// Worker threads (default: one per core).
    #[arg(long, allow_hyphen_values = true)]
    pub threads: Option<String>,
    /// Statistics: text (default), or json (one object on stdout, nothing else there).
    #[arg(long, default_value = "text", allow_hyphen_values = true)]
    pub stats: String,
    /// Anti-aliasing: render N x N rays per pixel and filter them into the pixel with
    /// --filter (the previewer's Appendix A filter); the depth map keeps each pixel's
    /// nearest sub-pixel depth.
    #[arg(long, default_value_t = 1)]
    pub aa: u32,
    /// Anti-aliasing filter (with --aa above 1): a B-spline of degree 0 to 3: box, tent,
    /// quadratic or cubic.
    #[arg(long, default_value = "quadratic", allow_hyphen_values = true)]
    pub filter: String,
    /// Where to trace: cpu, or gpu (wgpu compute shaders in f32 IA, RAA* or RevAA with
    /// outward rounding; needs a build with the `gpu` feature and a Vulkan, Metal or
    /// DX12 driver; no --shadows).
    #[arg(long, default_value = "cpu", allow_hyphen_values = true)]
    pub device: String,
}

/// `render --arith`'s help text: `auto` and the arithmetics of the one list.
fn render_arith_help() -> String {
    format!(
        "Arithmetic: auto (revaa, the rays of hits it cannot confirm searched again in \
         hull, which removes false walls; revaa on the GPU), or one of {}",
        ArithKind::names(),
    )
}

/// `--device gpu`'s refusals, before any work.
#[cfg(feature = "gpu")]
fn check_gpu_flags(a: &RenderArgs, kind: ArithKind) -> Result<(), String> {
    tracer_gpu::render::gpu_arith(kind).map_err(|e| format!("--arith with --device gpu: {e}"))?;
    if a.shadows {
        return Err("--shadows: not supported with --device gpu".into());
    }
    Ok(())
}

#[cfg(not(feature = "gpu"))]
fn check_gpu_flags(_: &RenderArgs, _: ArithKind) -> Result<(), String> {
    Err(
        "--device gpu: this tracer was built without the GPU renderer; build it with \
         `cargo build --release -p tracer-cli --features gpu`"
            .into(),
    )
}

#[cfg(feature = "gpu")]
fn render_gpu(
    kind: ArithKind,
    model: &Model,
    opts: &RenderOptions,
) -> Result<RenderResult, String> {
    let gpu = tracer_gpu::Gpu::new().map_err(|e| format!("--device gpu: {e}"))?;
    tracer_gpu::render::render(&gpu, kind, model, opts).map_err(|e| format!("--device gpu: {e}"))
}

#[cfg(not(feature = "gpu"))]
fn render_gpu(_: ArithKind, _: &Model, _: &RenderOptions) -> Result<RenderResult, String> {
    unreachable!("check_gpu_flags refuses --device gpu without the gpu feature")
}

/// Runs `tracer render`: the refusals before any work, the render (on the CPU or the
/// GPU), anti-aliasing, the files and the statistics.
pub fn run_render(a: &RenderArgs) -> Result<(), String> {
    let auto = a.arith == "auto";
    let kind: ArithKind = if auto {
        ArithKind::Revaa
    } else {
        a.arith
            .parse()
            .map_err(|e| format!("--arith: {e} (or auto)"))?
    };
    let gpu = match a.device.as_str() {
        "cpu" => false,
        "gpu" => true,
        s => return Err(format!("--device '{s}': expected cpu or gpu")),
    };
    if gpu {
        check_gpu_flags(a, kind)?;
    }
    let (width, height) = parse_size("--size", &a.size)?;
    let json = match a.stats.as_str() {
        "text" => false,
        "json" => true,
        s => return Err(format!("--stats '{s}': expected text or json")),
    };
    set_threads(a.threads.as_deref())?;
    let model = model_source(&a.src, a.domain.as_deref().map(|d| ("--domain", d)))?;
    let (name, domain) = (model.name.clone(), model.domain);
    let view = a.view.apply(model.view)?;
    let kernel: tracer_kit::bspline_filter::Kernel =
        a.filter.parse().map_err(|e| format!("--filter: {e}"))?;
    if a.aa == 0 || a.aa > 16 {
        return Err(format!("--aa {}: must be in 1..=16", a.aa));
    }
    let (vw, vh) = (width as u64 * a.aa as u64, height as u64 * a.aa as u64);
    let max = model_ir::camera::MAX_SIDE as u64;
    if vw > max || vh > max {
        return Err(format!(
            "--aa {}: {width}x{height} at {0} rays per pixel side is {vw}x{vh} rays; each \
             side must be at most {max}",
            a.aa
        ));
    }
    let (vw, vh) = (vw as u32, vh as u32);
    model_ir::camera::Camera::try_new(view, vw, vh).map_err(|e| format!("camera: {e}"))?;
    let eps = a
        .eps
        .as_deref()
        .map(|s| parse_positive("--eps", s))
        .transpose()?;
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{name}.png")));
    // Fail on a refused or unwritable output before a long render.
    check_outputs(&out, a.depth.as_deref())?;

    let search: Search = a.search.parse().map_err(|e| format!("--search: {e}"))?;
    let mut opts = RenderOptions::for_view(view, domain, vw, vh);
    opts.search = search;
    opts.eps = eps;
    opts.culling = !a.no_culling;
    opts.pruning = !a.no_pruning;
    opts.specialise = !a.no_specialise;
    opts.shadows = a.shadows;
    if !a.quiet {
        opts.progress = Some(std::sync::Arc::new(Bar::new()));
    }
    // Ctrl-C stops starting tiles; the finished ones are written below.
    opts.cancel = Some(tracer_kit::interrupt::cancel_flag());
    let res = if gpu {
        render_gpu(kind, &model, &opts)?
    } else if auto {
        tracer::render::auto_arith::render_auto(&model.shape, &opts)?
    } else {
        render_kind(kind, &model.shape, &opts)?
    };
    let arith_name = if auto && !gpu { "auto" } else { kind.name() };
    let search = search.resolve(&model.shape, opts.specialise);
    let res = if a.aa > 1 {
        downsample_render(&res, width, height, &Filter::new(kernel, a.aa))
    } else {
        res
    };
    write_png(&out, width, height, &res.rgb).map_err(|e| format!("--out: {e}"))?;
    if let Some(d) = &a.depth {
        write_depth(d, width, height, &res.depth).map_err(|e| format!("--depth: {e}"))?;
    }
    if res.stats.cut {
        let what = if a.depth.is_some() {
            "image and depth were written (unfinished pixels are background, depth +inf)"
        } else {
            "image was written (unfinished pixels are background)"
        };
        eprintln!(
            "interrupted: {} of {} tiles done; the partial {what}",
            res.stats.tiles_done, res.stats.tiles_total,
        );
    }
    if json {
        let run = (arith_name, search);
        let j = stats_json(&render_fields(&name, width, height, run, &res.stats));
        out!("{j}");
    } else {
        out!(
            "{name} {width}x{height} arith={arith_name} search={} culling={} pruning={} \
             shadows={}",
            search.name(),
            opts.culling,
            opts.pruning,
            opts.shadows
        );
        out!("{}", res.stats);
    }
    let (hits, unconfirmed) = (res.stats.hits, res.stats.unconfirmed);
    if unconfirmed * 4 > hits {
        eprintln!(
            "warning: {unconfirmed} of {hits} hit pixels are unconfirmed (no sign change of f \
             within the precision): f may be infinite or NaN on a region (a division by \
             0, ln of values <= 0) or touch 0 without crossing it"
        );
    }
    if !json {
        out!("wrote {}", out.display());
        if let Some(d) = &a.depth {
            out!("wrote {}", d.display());
        }
    }
    Ok(())
}

/// The fields of a render's `--stats json` object: every counter of
/// [`RenderStats`] under its field name, `wall_s` for the wall time, and the render's
/// model, size, arithmetic and search.
pub fn render_fields(
    model: &str,
    width: u32,
    height: u32,
    (arith, search): (&str, Search),
    s: &RenderStats,
) -> Vec<(&'static str, String)> {
    let counters = s.counters();
    let mut fields = vec![
        ("model", json_string(model)),
        ("width", width.to_string()),
        ("height", height.to_string()),
        ("arith", json_string(arith)),
        ("search", json_string(search.name())),
        ("wall_s", format!("{:?}", s.wall.as_secs_f64())),
        ("cut", s.cut.to_string()),
    ];
    fields.extend(counters.map(|(k, v)| (k, v.to_string())));
    fields.push((
        "mean_evals_per_hit",
        format!("{:?}", s.mean_evals_per_hit()),
    ));
    fields
}
