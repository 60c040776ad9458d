//! `tracer`: reliable ray casting of implicit surfaces from the command line.
//!
//! `tracer render`, `tracer range`, `tracer list`, `tracer preview`, `tracer view`,
//! `tracer mesh` (see `--help`), and
//! `tracer completions SHELL`, `tracer man` for the shell and the manual.
//! User errors print one line on stderr and exit with code 2. Ctrl-C stops `render` and
//! `preview` early: what was computed is written, and the exit code is 130.

use arith_core::{Arithmetic, Range};
use clap::{CommandFactory, Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;
use tracer::arith::ArithKind;
use tracer::cli::{model_source, parse_positive, parse_size, ModelArgs, ViewArgs};
use tracer::render::output::{check_outputs, write_depth, write_png};
use tracer::render::{render_kind, RenderOptions};
use tracer::shape::{Aabb, Shape};

#[derive(Parser, Debug)]
#[command(
    name = "tracer",
    version,
    about = "Reliable ray casting of implicit surfaces (FRep: f >= 0 inside)"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand, Debug)]
enum Cmd {
    /// Render a model or a formula to a PNG (and optionally a depth map).
    #[command(after_long_help = tracer::models::formula::SYNTAX)]
    Render(RenderArgs),
    /// Print the range of a formula over a box in each arithmetic.
    #[command(after_long_help = tracer::models::formula::SYNTAX)]
    Range(RangeArgs),
    /// List the models with their domain and default view.
    List,
    /// Progressive refinement previewer (cone tracing with Lipschitz bounds or a range
    /// arithmetic).
    ///
    /// In the window: drag with the left mouse button to set a region of interest (it
    /// is refined first, outlined in white), right-click to cancel it; drag with the
    /// right button to orbit, turn the mouse wheel to zoom (each starts over); a model
    /// file is read again when it changes; Esc or closing the window stops refinement
    /// and writes --out.
    #[command(after_long_help = tracer::models::formula::SYNTAX)]
    Preview(tracer::cli::preview::PreviewArgs),
    /// Real-time window on the GPU renderer (a build with the `gpu` feature).
    ///
    /// The model is searched on the GPU as by `render --device gpu` whenever the view
    /// changes: drag with a mouse button or press the arrow keys to orbit, turn the wheel
    /// or press + / - to zoom, R to go back to the starting view; Esc or closing the
    /// window stops and writes the last frame to --out.
    #[command(after_long_help = tracer::models::formula::SYNTAX)]
    View(tracer::cli::gpu_window::ViewWindowArgs),
    /// Mesh a model or a formula: an octree pruned by range arithmetic, dual contouring
    /// with vertices kept in their cells; writes .obj, .ply or .stl.
    ///
    /// The mesh is closed (clipped to the domain), wound outward, one vertex per piece
    /// of surface in a cell; thin features below a cell are searched for down to
    /// --max-depth. --stats reports watertightness, manifoldness, the Euler
    /// characteristic, the share of cells whose topology is certified (Plantinga and
    /// Vegter) and self-intersecting triangle pairs.
    #[command(after_long_help = tracer::models::formula::SYNTAX)]
    Mesh(tracer::cli::mesh::MeshArgs),
    /// Print a shell completion script: bash, zsh, fish, elvish or powershell.
    Completions {
        /// The shell.
        shell: String,
    },
    /// Print the manual page (roff), e.g. `tracer man > tracer.1`.
    Man,
}

#[derive(clap::Args, Debug)]
struct RenderArgs {
    #[command(flatten)]
    src: ModelArgs,
    /// Arithmetic.
    #[arg(long, default_value = "auto", help = render_arith_help())]
    arith: String,
    /// Image size WxH.
    #[arg(long, default_value = "640x480", allow_hyphen_values = true)]
    size: String,
    /// Output PNG (default: <model>.png).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Depth map: .npy (float32, shape (H, W)) or .exr (one float32 channel Z); +inf on a miss.
    #[arg(long)]
    depth: Option<PathBuf>,
    #[command(flatten)]
    view: ViewArgs,
    /// Domain box XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX.
    #[arg(long, allow_hyphen_values = true)]
    domain: Option<String>,
    /// Absolute precision of roots along rays (default: a quarter pixel footprint).
    #[arg(long, allow_hyphen_values = true)]
    eps: Option<String>,
    /// Disable cell culling (Algorithm 2).
    #[arg(long)]
    no_culling: bool,
    /// Disable argument pruning.
    #[arg(long)]
    no_pruning: bool,
    /// Disable region specialisation (formula, .vm and HyperFun models: each culling
    /// cell searches a tape shortened for its region).
    #[arg(long)]
    no_specialise: bool,
    /// Trace shadow rays towards the light.
    #[arg(long)]
    shadows: bool,
    /// No progress bar.
    #[arg(long, short)]
    quiet: bool,
    /// Worker threads (default: one per core).
    #[arg(long, allow_hyphen_values = true)]
    threads: Option<String>,
    /// Statistics: text (default), or json (one object on stdout, nothing else there).
    #[arg(long, default_value = "text", allow_hyphen_values = true)]
    stats: String,
    /// Anti-aliasing: render N x N rays per pixel and filter them into the pixel with
    /// --filter (the previewer's Appendix A filter); the depth map keeps each pixel's
    /// nearest sub-pixel depth.
    #[arg(long, default_value_t = 1)]
    aa: u32,
    /// Anti-aliasing filter (with --aa above 1): a B-spline of degree 0 to 3: box, tent,
    /// quadratic or cubic.
    #[arg(long, default_value = "quadratic", allow_hyphen_values = true)]
    filter: String,
    /// Where to trace: cpu, or gpu (wgpu compute shaders in f32 IA, RAA* or RevAA with
    /// outward rounding; needs a build with the `gpu` feature and a Vulkan, Metal or
    /// DX12 driver; no --shadows).
    #[arg(long, default_value = "cpu", allow_hyphen_values = true)]
    device: String,
}

/// `render --arith`'s help text: `auto` and the arithmetics of the one list.
fn render_arith_help() -> String {
    format!(
        "Arithmetic: auto (a probe of {side} pixels across renders in revaa and hull and \
         keeps revaa unless its ranges draw false walls there; revaa on the GPU), or one \
         of {}",
        ArithKind::names(),
        side = tracer::render::auto_arith::PROBE_SIDE
    )
}

/// The `--arith` help text, listing the arithmetics of the one list.
fn arith_help(all: bool) -> String {
    let names = ArithKind::names();
    if all {
        format!("Arithmetic: {names}, or all")
    } else {
        format!("Arithmetic: {names}")
    }
}

#[derive(clap::Args, Debug)]
struct RangeArgs {
    #[command(flatten)]
    src: ModelArgs,
    /// The box XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX (default: the model's domain; [-2, 2]^3 for
    /// a formula).
    #[arg(long = "box", allow_hyphen_values = true)]
    bbox: Option<String>,
    #[arg(long, default_value = "all", help = arith_help(true))]
    arith: String,
    /// Print JSON: [{"arith": "revaa", "lo": .., "hi": ..}, ...] (null for an infinite bound).
    #[arg(long)]
    json: bool,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let res = match &cli.cmd {
        Cmd::Render(a) => cmd_render(a),
        Cmd::Range(a) => cmd_range(a),
        Cmd::List => {
            cmd_list();
            Ok(())
        }
        Cmd::Preview(a) => {
            tracer::interrupt::install();
            tracer::cli::run_preview(a)
        }
        Cmd::View(a) => {
            tracer::interrupt::install();
            tracer::cli::gpu_window::run_view(a)
        }
        Cmd::Mesh(a) => tracer::cli::mesh::run_mesh(a),
        Cmd::Completions { shell } => cmd_completions(shell),
        Cmd::Man => cmd_man(),
    };
    match res {
        // Stopped by Ctrl-C after writing what was computed.
        Ok(()) if tracer::interrupt::requested() => ExitCode::from(tracer::interrupt::exit_code()),
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            // One line, whatever the message held.
            eprintln!("error: {}", msg.replace('\n', " "));
            ExitCode::from(2)
        }
    }
}

/// `--device gpu`'s refusals, before any work.
#[cfg(feature = "gpu")]
fn check_gpu_flags(a: &RenderArgs, kind: ArithKind) -> Result<(), String> {
    tracer::gpu::gpu_arith(kind).map_err(|e| format!("--arith with --device gpu: {e}"))?;
    if a.shadows {
        return Err("--shadows: not supported with --device gpu".into());
    }
    Ok(())
}

#[cfg(not(feature = "gpu"))]
fn check_gpu_flags(_: &RenderArgs, _: ArithKind) -> Result<(), String> {
    Err(
        "--device gpu: this tracer was built without the GPU renderer; build it with \
         `cargo build --release -p tracer --features gpu`"
            .into(),
    )
}

#[cfg(feature = "gpu")]
fn render_gpu(
    kind: ArithKind,
    model: &tracer::models::Model,
    opts: &RenderOptions,
) -> Result<tracer::render::RenderResult, String> {
    let gpu = tracer::gpu::tracer_gpu::Gpu::new().map_err(|e| format!("--device gpu: {e}"))?;
    tracer::gpu::render(&gpu, kind, model, opts).map_err(|e| format!("--device gpu: {e}"))
}

#[cfg(not(feature = "gpu"))]
fn render_gpu(
    _: ArithKind,
    _: &tracer::models::Model,
    _: &RenderOptions,
) -> Result<tracer::render::RenderResult, String> {
    unreachable!("check_gpu_flags refuses --device gpu without the gpu feature")
}

fn cmd_render(a: &RenderArgs) -> Result<(), String> {
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
    tracer::cli::set_threads(a.threads.as_deref())?;
    let model = model_source(&a.src, a.domain.as_deref().map(|d| ("--domain", d)))?;
    let (name, domain) = (model.name.clone(), model.domain);
    let view = a.view.apply(model.view)?;
    let kernel: tracer::render::bspline_filter::Kernel =
        a.filter.parse().map_err(|e| format!("--filter: {e}"))?;
    if a.aa == 0 || a.aa > 16 {
        return Err(format!("--aa {}: must be in 1..=16", a.aa));
    }
    let (vw, vh) = (width as u64 * a.aa as u64, height as u64 * a.aa as u64);
    let max = tracer::camera::MAX_SIDE as u64;
    if vw > max || vh > max {
        return Err(format!(
            "--aa {}: {width}x{height} at {0} rays per pixel side is {vw}x{vh} rays; each \
             side must be at most {max}",
            a.aa
        ));
    }
    let (vw, vh) = (vw as u32, vh as u32);
    tracer::camera::Camera::try_new(view, vw, vh).map_err(|e| format!("camera: {e}"))?;
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

    let mut opts = RenderOptions::for_view(view, domain, vw, vh);
    opts.eps = eps;
    opts.culling = !a.no_culling;
    opts.pruning = !a.no_pruning;
    opts.specialise = !a.no_specialise;
    opts.shadows = a.shadows;
    if !a.quiet {
        opts.progress = Some(std::sync::Arc::new(tracer::cli::Bar::new()));
    }
    // Ctrl-C stops starting tiles; the finished ones are written below.
    opts.cancel = Some(tracer::interrupt::cancel_flag());
    let kind = if auto && !gpu {
        let c = tracer::render::auto_arith::choose(&model.shape, &opts)?;
        if !a.quiet {
            let hull = c
                .unconfirmed
                .1
                .map_or("not probed".into(), |u| u.to_string());
            eprintln!(
                "--arith auto: {} (probe {}x{}: {} hits, unconfirmed revaa {}, hull {hull})",
                c.kind, c.size.0, c.size.1, c.hits, c.unconfirmed.0
            );
        }
        c.kind
    } else {
        kind
    };
    let res = if gpu {
        render_gpu(kind, &model, &opts)?
    } else {
        render_kind(kind, &model.shape, &opts)?
    };
    let res = if a.aa > 1 {
        use tracer::render::bspline_filter::{downsample_render, Filter};
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
        let j = tracer::cli::stats_json(&name, width, height, kind.name(), &res.stats);
        tracer::out!("{j}");
    } else {
        tracer::out!(
            "{name} {width}x{height} arith={kind} culling={} pruning={} shadows={}",
            opts.culling,
            opts.pruning,
            opts.shadows
        );
        tracer::out!("{}", res.stats);
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
        tracer::out!("wrote {}", out.display());
        if let Some(d) = &a.depth {
            tracer::out!("wrote {}", d.display());
        }
    }
    Ok(())
}

/// Writes `bytes` to stdout (a closed stdout ends the process quietly, as `out!`).
fn write_stdout(bytes: &[u8]) -> Result<(), String> {
    use std::io::Write as _;
    let mut o = std::io::stdout().lock();
    match o.write_all(bytes).and_then(|()| o.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        r => r.map_err(|e| format!("cannot write to stdout: {e}")),
    }
}

fn cmd_completions(shell: &str) -> Result<(), String> {
    use clap_complete::Shell;
    let sh = match shell.to_ascii_lowercase().as_str() {
        "bash" => Shell::Bash,
        "zsh" => Shell::Zsh,
        "fish" => Shell::Fish,
        "elvish" => Shell::Elvish,
        "powershell" => Shell::PowerShell,
        _ => {
            return Err(format!(
                "completions: unknown shell '{shell}' (bash, zsh, fish, elvish or powershell)"
            ))
        }
    };
    let mut buf = Vec::new();
    clap_complete::generate(sh, &mut Cli::command(), "tracer", &mut buf);
    write_stdout(&buf)
}

fn cmd_man() -> Result<(), String> {
    let mut buf = Vec::new();
    clap_mangen::Man::new(Cli::command())
        .render(&mut buf)
        .map_err(|e| format!("man: {e}"))?;
    // The page opens with its `.TH` title, as man(7) has it; the rendering puts the
    // definition of the apostrophe string (used only further down) before it.
    let page = String::from_utf8_lossy(&buf);
    let lines: Vec<&str> = page.lines().collect();
    let mut out = String::with_capacity(page.len() + 1);
    if let Some(k) = lines.iter().position(|l| l.starts_with(".TH")) {
        for l in std::iter::once(&lines[k])
            .chain(&lines[..k])
            .chain(&lines[k + 1..])
        {
            out.push_str(l);
            out.push('\n');
        }
    } else {
        out.push_str(&page);
    }
    write_stdout(out.as_bytes())
}

fn range_over<A: Arithmetic, S: Shape>(shape: &S, b: &Aabb) -> (f64, f64) {
    let x = <A::Cell as Range>::input(0, b.min.x, b.max.x);
    let y = <A::Cell as Range>::input(1, b.min.y, b.max.y);
    let z = <A::Cell as Range>::input(2, b.min.z, b.max.z);
    shape.eval(x, y, z).bounds()
}

fn json_num(v: f64) -> String {
    if v.is_finite() {
        format!("{v:?}")
    } else {
        "null".into()
    }
}

fn cmd_range(a: &RangeArgs) -> Result<(), String> {
    let model = model_source(&a.src, a.bbox.as_deref().map(|b| ("--box", b)))?;
    let b = model.domain;
    let kinds: Vec<ArithKind> = if a.arith.eq_ignore_ascii_case("all") {
        ArithKind::ALL.to_vec()
    } else {
        vec![a
            .arith
            .parse()
            .map_err(|e| format!("--arith: {e} or all"))?]
    };
    let rows: Vec<(ArithKind, (f64, f64))> = kinds
        .iter()
        .map(|&k| {
            (
                k,
                tracer::with_arith!(k, A => range_over::<A, _>(&model.shape, &b)),
            )
        })
        .collect();
    if a.json {
        let items: Vec<String> = rows
            .iter()
            .map(|(k, (lo, hi))| {
                format!(
                    "{{\"arith\": \"{}\", \"lo\": {}, \"hi\": {}}}",
                    k.name(),
                    json_num(*lo),
                    json_num(*hi)
                )
            })
            .collect();
        tracer::out!("[{}]", items.join(", "));
    } else {
        for (k, (lo, hi)) in rows {
            // Shortest decimals that read back as the same doubles.
            tracer::out!("{:<6} [{lo:?}, {hi:?}]", k.name());
        }
    }
    Ok(())
}

fn cmd_list() {
    for m in tracer::models::all() {
        let v = m.view;
        let d = m.domain;
        tracer::out!("{}", m.name);
        tracer::out!("    {}", m.description);
        match m.shape.formula() {
            // One line: bindings separated by '; ' (as --expr takes them).
            Some(f) => tracer::out!("    formula {}", f.replace('\n', " ")),
            None => tracer::out!("    formula (none: uses noise, which formulas lack)"),
        }
        tracer::out!(
            "    domain {},{},{},{},{},{}",
            d.min.x,
            d.min.y,
            d.min.z,
            d.max.x,
            d.max.y,
            d.max.z
        );
        tracer::out!(
            "    view   --eye {:.3},{:.3},{:.3} --look-at {},{},{} --up {},{},{} --fov {}",
            v.eye.x,
            v.eye.y,
            v.eye.z,
            v.look_at.x,
            v.look_at.y,
            v.look_at.z,
            v.up.x,
            v.up.y,
            v.up.z,
            v.fov_deg
        );
    }
}
