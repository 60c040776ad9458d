//! `tracer`: reliable ray casting of implicit surfaces from the command line.
//!
//! `tracer render`, `tracer range`, `tracer list`, `tracer preview` (see `--help`).
//! User errors print one line on stderr and exit with code 2. Ctrl-C stops `render` and
//! `preview` early: what was computed is written, and the exit code is 130.

use arith_core::{Arithmetic, Range};
use clap::{Parser, Subcommand};
use glam::DVec3;
use std::path::PathBuf;
use std::process::ExitCode;
use tracer::arith::ArithKind;
use tracer::render::output::{check_outputs, write_depth, write_png};
use tracer::render::{render_kind, RenderOptions};
use tracer::shape::{check_domain, Aabb, Shape};

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
    Render(RenderArgs),
    /// Print the range of a formula over a box in each arithmetic.
    Range(RangeArgs),
    /// List the models with their domain and default view.
    List,
    /// Progressive refinement previewer (Lipschitz cone tracing).
    Preview(tracer::progressive::PreviewArgs),
}

#[derive(clap::Args, Debug)]
struct RenderArgs {
    /// Model name (see `tracer list`); or give --expr.
    model: Option<String>,
    /// A formula over x, y, z (f >= 0 inside), e.g. "1 - x^2 - y^2 - z^2"; its domain
    /// defaults to [-2, 2]^3 (see --domain), its view frames the domain.
    #[arg(long)]
    expr: Option<String>,
    /// Arithmetic: ia, aa, raa, revaa.
    #[arg(long, default_value = "revaa")]
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
    /// Eye position X,Y,Z.
    #[arg(long, allow_hyphen_values = true)]
    eye: Option<String>,
    /// Point looked at X,Y,Z.
    #[arg(long = "look-at", allow_hyphen_values = true)]
    look_at: Option<String>,
    /// Up vector X,Y,Z (default 0,1,0).
    #[arg(long, allow_hyphen_values = true)]
    up: Option<String>,
    /// Vertical field of view in degrees.
    #[arg(long, allow_hyphen_values = true)]
    fov: Option<String>,
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
    /// Trace shadow rays towards the light.
    #[arg(long)]
    shadows: bool,
}

#[derive(clap::Args, Debug)]
struct RangeArgs {
    /// A formula over x, y, z.
    #[arg(long)]
    expr: String,
    /// The box XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX.
    #[arg(long = "box", allow_hyphen_values = true)]
    bbox: String,
    /// Arithmetic: ia, aa, raa, revaa or all.
    #[arg(long, default_value = "all")]
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
            tracer::progressive::run_preview(a)
        }
    };
    match res {
        // Stopped by Ctrl-C after writing what was computed.
        Ok(()) if tracer::interrupt::requested() => ExitCode::from(tracer::interrupt::EXIT_CODE),
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            // One line, whatever the message held.
            eprintln!("error: {}", msg.replace('\n', " "));
            ExitCode::from(2)
        }
    }
}

/// Parses `n` comma-separated finite numbers for `flag`.
fn parse_list(flag: &str, s: &str, n: usize) -> Result<Vec<f64>, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != n {
        return Err(format!(
            "{flag} '{s}': expected {n} comma-separated numbers, got {}",
            parts.len()
        ));
    }
    parts
        .iter()
        .map(|p| match p.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(format!("{flag} '{s}': '{p}' is not a finite number")),
        })
        .collect()
}

fn parse_vec3(flag: &str, s: &str) -> Result<DVec3, String> {
    let v = parse_list(flag, s, 3)?;
    Ok(DVec3::new(v[0], v[1], v[2]))
}

fn parse_box(flag: &str, s: &str) -> Result<Aabb, String> {
    let v = parse_list(flag, s, 6)?;
    let b = Aabb::new(DVec3::new(v[0], v[1], v[2]), DVec3::new(v[3], v[4], v[5]));
    if !(b.min.cmplt(b.max).all()) {
        return Err(format!(
            "{flag} '{s}': each minimum must be below its maximum"
        ));
    }
    Ok(b)
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let max = tracer::camera::MAX_SIDE;
    let err =
        || format!("--size '{s}': expected WxH with positive integers up to {max}, e.g. 640x480");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(err)?;
    let w: u32 = w.trim().parse().map_err(|_| err())?;
    let h: u32 = h.trim().parse().map_err(|_| err())?;
    tracer::camera::check_size(w, h).map_err(|_| err())?;
    Ok((w, h))
}

fn parse_positive(flag: &str, s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        _ => Err(format!("{flag} '{s}': expected a positive number")),
    }
}

fn cmd_render(a: &RenderArgs) -> Result<(), String> {
    let kind: ArithKind = a.arith.parse().map_err(|e| format!("--arith: {e}"))?;
    let (width, height) = parse_size(&a.size)?;
    let domain_override = a
        .domain
        .as_deref()
        .map(|s| parse_box("--domain", s))
        .transpose()?;
    let domain_err = |e: String| format!("--domain '{}': {e}", a.domain.as_deref().unwrap_or(""));
    if let Some(b) = &domain_override {
        check_domain(b).map_err(domain_err)?;
    }
    enum Target {
        Model(Box<tracer::models::Model>),
        Expr(tracer::models::formula::Tape),
    }
    let (target, name, domain, mut view) = match (&a.model, &a.expr) {
        (Some(_), Some(_)) => return Err("give either a MODEL or --expr, not both".into()),
        (None, None) => {
            return Err("give a MODEL name (see `tracer list`) or --expr FORMULA".into())
        }
        (Some(m), None) => {
            let model = tracer::models::find(m)?;
            let domain = domain_override.unwrap_or(model.domain);
            let view = model.view;
            let name = model.name.clone();
            (Target::Model(Box::new(model)), name, domain, view)
        }
        (None, Some(f)) => {
            let tape = tracer::models::formula::parse(f).map_err(|e| format!("--expr: {e}"))?;
            let domain = domain_override.unwrap_or(Aabb::cube(2.0));
            let view = tracer::camera::frame_box(&domain).map_err(domain_err)?;
            (Target::Expr(tape), "expr".to_string(), domain, view)
        }
    };
    if let Some(s) = &a.eye {
        view.eye = parse_vec3("--eye", s)?;
    }
    if let Some(s) = &a.look_at {
        view.look_at = parse_vec3("--look-at", s)?;
    }
    if let Some(s) = &a.up {
        view.up = parse_vec3("--up", s)?;
    }
    if let Some(s) = &a.fov {
        let f = parse_positive("--fov", s)?;
        if f >= 180.0 {
            return Err(format!("--fov '{s}': must be below 180 degrees"));
        }
        view.fov_deg = f;
    }
    tracer::camera::Camera::try_new(view, width, height).map_err(|e| format!("camera: {e}"))?;
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

    let mut opts = RenderOptions::for_view(view, domain, width, height);
    opts.eps = eps;
    opts.culling = !a.no_culling;
    opts.pruning = !a.no_pruning;
    opts.shadows = a.shadows;
    opts.progress = true;
    // Ctrl-C stops starting tiles; the finished ones are written below.
    opts.cancel = Some(tracer::interrupt::cancel_flag());
    let res = match &target {
        Target::Model(m) => render_kind(kind, &m.shape, &opts)?,
        Target::Expr(t) => render_kind(kind, t, &opts)?,
    };
    write_png(&out, width, height, &res.rgb).map_err(|e| format!("--out: {e}"))?;
    if let Some(d) = &a.depth {
        write_depth(d, width, height, &res.depth).map_err(|e| format!("--depth: {e}"))?;
    }
    if res.stats.cut {
        eprintln!(
            "interrupted: {} of {} tiles done; the partial image{} written (unfinished tiles \
             are background, depth +inf)",
            res.stats.tiles_done,
            res.stats.tiles_total,
            if a.depth.is_some() {
                " and depth were"
            } else {
                " was"
            }
        );
    }
    tracer::out!(
        "{name} {width}x{height} arith={kind} culling={} pruning={} shadows={}",
        opts.culling,
        opts.pruning,
        opts.shadows
    );
    tracer::out!("{}", res.stats);
    tracer::out!("wrote {}", out.display());
    if let Some(d) = &a.depth {
        tracer::out!("wrote {}", d.display());
    }
    Ok(())
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
    let tape = tracer::models::formula::parse(&a.expr).map_err(|e| format!("--expr: {e}"))?;
    let b = parse_box("--box", &a.bbox)?;
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
                tracer::with_arith!(k, A => range_over::<A, _>(&tape, &b)),
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
            tracer::out!("{:<6} [{lo:e}, {hi:e}]", k.name());
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
