//! Progressive refinement previewer (Gamito and Maddock 2007): Lipschitz cone tracing
//! over a queue of square image samples, subdivided by the prime factors of the image
//! size, finished per pixel by the overshooting Lipschitz ray caster, with regions of
//! interest, a live window and a headless mode.
//!
//! - [`engine`]: the renderer ([`Engine`]), cone tracing ([`trace_cone`]), the
//!   conventional ray casters over a whole image ([`raycast`]).
//! - [`window`]: the two-thread live preview.

pub mod engine;
pub mod window;

pub use engine::{
    prime_factors_desc, raycast, trace_cone, trace_cone_local, Caster, ChildStart, ConeEnd, Engine,
    Options, Plan, Rect, SharedImage, Stats, Step,
};

use crate::models::Model;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `tracer preview`.
#[derive(clap::Args, Debug, Clone)]
pub struct PreviewArgs {
    /// Model name (see `tracer list`).
    pub model: String,
    /// Image width in pixels.
    #[arg(long, default_value_t = 800)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 800)]
    pub height: u32,
    /// Override the model's Lipschitz bound.
    #[arg(long)]
    pub lambda: Option<f64>,
    /// Hit precision (a ray stops where |f|/lambda is below it).
    #[arg(long, default_value_t = 1e-4)]
    pub eps: f64,
    /// Overshooting factor of the terminal ray caster.
    #[arg(long, default_value_t = crate::search::lipschitz::DEFAULT_OVERSHOOT)]
    pub overshoot: f64,
    /// Anti-aliasing: subdivide to 1/N of a pixel and box-filter (Appendix A with a box filter).
    #[arg(long, default_value_t = 1)]
    pub aa: u32,
    /// Start child cones as eq. (8) of the paper instead of the guaranteed radial rule.
    #[arg(long)]
    pub paper_child_start: bool,
    /// Local Lipschitz bounds per cone and ray segment (past the paper).
    #[arg(long)]
    pub local: bool,
    /// No window: refine to completion (or Ctrl-C), printing each level transition.
    #[arg(long)]
    pub headless: bool,
    /// Write a PNG at every level transition into this directory (headless).
    #[arg(long)]
    pub snapshots: Option<PathBuf>,
    /// Write the image here at completion, or when stopped early.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Window frame rate.
    #[arg(long, default_value_t = 30)]
    pub fps: u32,
    /// Close the window by itself after this many seconds (for tests and demos).
    #[arg(long)]
    pub stop_after: Option<f64>,
}

/// Finds a model by name among every model the tracer knows.
pub fn find_model(name: &str) -> Result<Model, String> {
    crate::models::progressive::all()
        .into_iter()
        .find(|m| m.name.eq_ignore_ascii_case(name))
        .ok_or_else(|| format!("unknown model '{name}' (see `tracer list`)"))
}

/// Builds the engine options for `args` and `model`.
pub fn options_for(args: &PreviewArgs, model: &Model) -> Result<Options, String> {
    let lambda = match (args.lambda, model.lipschitz) {
        (Some(l), _) => l,
        (None, Some(l)) => l,
        (None, None) => {
            return Err(format!(
                "model '{}' has no known Lipschitz bound: pass --lambda",
                model.name
            ))
        }
    };
    let mut o = Options::new(lambda);
    o.eps = args.eps;
    o.overshoot = args.overshoot;
    o.aa = args.aa;
    o.local = args.local;
    if args.paper_child_start {
        o.child_start = ChildStart::Paper;
    }
    Ok(o)
}

/// Writes the shared image as a PNG.
pub fn write_png(img: &SharedImage, path: &Path) -> Result<(), String> {
    if let Some(dir) = path.parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)
                .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        }
    }
    img.to_rgb()
        .save(path)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// Runs `tracer preview`.
pub fn run_preview(args: &PreviewArgs) -> Result<(), String> {
    let model = find_model(&args.model)?;
    let opts = options_for(args, &model)?;
    let engine = Engine::new(
        model.clone(),
        model.domain,
        model.view,
        args.width,
        args.height,
        opts,
    )?;
    if args.headless {
        run_headless(engine, args)
    } else {
        window::run_window(engine, args)
    }
}

/// Refines to completion without a window, writing a snapshot at every level transition.
pub fn run_headless<S: crate::shape::Shape>(
    mut engine: Engine<S>,
    args: &PreviewArgs,
) -> Result<(), String> {
    let start = Instant::now();
    let plan = engine.plan().clone();
    println!(
        "plan: {}x{} top-level samples of {} px, splits {:?}, lambda {}",
        plan.u,
        plan.v,
        plan.size,
        plan.splits,
        engine.options().lambda
    );
    // Wall time of refinement only: the snapshots' PNG writing is left out.
    let mut io = std::time::Duration::ZERO;
    let mut snap = |engine: &Engine<S>, level: usize| -> Result<(), String> {
        let s = engine.stats();
        println!(
            "level {level} complete: {} iterations, {} evaluations, {:.3} s",
            s.iterations,
            s.evals,
            (start.elapsed() - io).as_secs_f64()
        );
        if let Some(dir) = &args.snapshots {
            let t = Instant::now();
            write_png(&engine.image(), &dir.join(format!("level-{level:02}.png")))?;
            io += t.elapsed();
        }
        Ok(())
    };
    // A snapshot is taken when every sample of a level is processed and before any of
    // the next, as the paper's Figs. 5-7.
    let mut level = 0;
    // Ctrl-C (see [`crate::interrupt`], installed by the CLI) stops refinement; the image
    // refined so far is still written to `--out` below.
    let mut interrupted = false;
    while !engine.is_done() {
        if crate::interrupt::requested() {
            interrupted = true;
            break;
        }
        if let Some(l) = engine.next_level() {
            if l > level {
                snap(&engine, level)?;
                level = l;
            }
        }
        engine.step();
    }
    let s = engine.stats();
    if interrupted {
        eprintln!(
            "interrupted: {} iterations, {} evaluations, {:.3} s; writing the image refined so far",
            s.iterations,
            s.evals,
            (start.elapsed() - io).as_secs_f64()
        );
        if let Some(out) = &args.out {
            write_png(&engine.image(), out)?;
        }
        return Ok(());
    }
    println!(
        "done: {} iterations, {} evaluations (+{} for normals, {} range), {:.3} s",
        s.iterations,
        s.evals,
        s.shading_evals,
        s.range_evals,
        (start.elapsed() - io).as_secs_f64()
    );
    if let Some(dir) = &args.snapshots {
        write_png(&engine.image(), &dir.join("final.png"))?;
    }
    if let Some(out) = &args.out {
        write_png(&engine.image(), out)?;
    }
    Ok(())
}

/// One row of the previewer benchmark (the paper's Table 1 and Fig. 9).
#[derive(Clone, Debug, PartialEq)]
pub struct BenchRow {
    pub model: String,
    /// `previewer`, `previewer-local`, `overshoot-rc`, `standard-rc`, `local-rc`.
    pub method: &'static str,
    /// Wall time to the final image, seconds.
    pub seconds: f64,
    /// Point evaluations of `f` (tracing only; normals excluded, as for the ray casters).
    pub evals: u64,
    /// Range evaluations (`Dual<Interval>`) for local Lipschitz bounds.
    pub range_evals: u64,
    /// Previewer only: wall time until every pixel was painted once (first full frame).
    pub first_frame_s: Option<f64>,
    /// Previewer only: samples processed.
    pub iterations: Option<u64>,
}

/// Times the previewer (global and local Lipschitz bounds) and the overshooting,
/// standard and local ray casters on each model at `width x height`, with each model's
/// own bound and precision `1e-4`. The ray casters shade nothing; the previewer's times
/// include its shading of every sample (its extra cost, as in the paper).
pub fn bench_table(models: &[Model], width: u32, height: u32) -> Result<Vec<BenchRow>, String> {
    let mut rows = Vec::new();
    for m in models {
        let lambda = m
            .lipschitz
            .ok_or_else(|| format!("model '{}' has no Lipschitz bound", m.name))?;
        for (method, local) in [("previewer", false), ("previewer-local", true)] {
            let mut opts = Options::new(lambda);
            opts.local = local;
            let start = Instant::now();
            let mut e = Engine::new(m.clone(), m.domain, m.view, width, height, opts)?;
            let mut first = None;
            while e.step() != Step::Done {
                if first.is_none() && e.fully_painted() {
                    first = Some(start.elapsed().as_secs_f64());
                }
            }
            let s = e.stats();
            rows.push(BenchRow {
                model: m.name.clone(),
                method,
                seconds: start.elapsed().as_secs_f64(),
                evals: s.evals,
                range_evals: s.range_evals,
                first_frame_s: first,
                iterations: Some(s.iterations),
            });
        }
        let eps = Options::new(lambda).eps;
        for (method, caster) in [
            (
                "overshoot-rc",
                Caster::Overshoot(crate::search::lipschitz::DEFAULT_OVERSHOOT),
            ),
            ("standard-rc", Caster::Standard),
            (
                "local-rc",
                Caster::Local(crate::search::lipschitz::DEFAULT_OVERSHOOT),
            ),
        ] {
            let start = Instant::now();
            let (_, c) = raycast(m, m.domain, m.view, width, height, lambda, eps, caster)?;
            rows.push(BenchRow {
                model: m.name.clone(),
                method,
                seconds: start.elapsed().as_secs_f64(),
                evals: c.evals,
                range_evals: c.range_evals,
                first_frame_s: None,
                iterations: None,
            });
        }
    }
    Ok(rows)
}
