//! `tracer preview`: its arguments, the engine options they give, and the headless run
//! (every level's snapshot, Ctrl-C keeping the image refined so far); the window is in
//! [`super::window`].

use super::window;
use crate::lipschitz_bound::auto_lipschitz;
use crate::models::Model;
use crate::progressive::{write_png, ChildStart, Engine, Options};
use std::path::PathBuf;
use std::time::Instant;

/// Sub-boxes per axis of the automatic Lipschitz bound of a model that has none.
pub const AUTO_LIPSCHITZ_SPLITS: usize = 16;

/// Arguments of `tracer preview`.
#[derive(clap::Args, Debug, Clone)]
pub struct PreviewArgs {
    /// The model: see `tracer render --help`.
    #[command(flatten)]
    pub src: super::ModelArgs,
    /// Domain box XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX (default: the model's; [-2, 2]^3 for a
    /// formula).
    #[arg(long, allow_hyphen_values = true)]
    pub domain: Option<String>,
    /// Image size WxH, as for `tracer render` (default 800x800).
    #[arg(long, allow_hyphen_values = true)]
    pub size: Option<String>,
    /// Orthographic camera WIDTH model units across the image instead of the pinhole
    /// (cones become cylinders of parallel rays), as for `tracer render --ortho`.
    #[arg(long, allow_hyphen_values = true, value_name = "WIDTH")]
    pub ortho: Option<String>,
    /// Image width in pixels (or give --size).
    #[arg(long, default_value_t = 800, conflicts_with = "size")]
    pub width: u32,
    /// Image height in pixels (or give --size).
    #[arg(long, default_value_t = 800, conflicts_with = "size")]
    pub height: u32,
    /// Worker threads (default: one per core).
    #[arg(long, allow_hyphen_values = true)]
    pub threads: Option<String>,
    /// Lipschitz bound of f over the domain (default: the model's own, or one computed
    /// from the range of its gradient over 16^3 sub-boxes).
    #[arg(long, allow_hyphen_values = true)]
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

impl PreviewArgs {
    /// The image size: `--size`, or `--width` and `--height` (800 each by default).
    pub fn image_size(&self) -> Result<(u32, u32), String> {
        match &self.size {
            Some(s) => super::parse_size("--size", s),
            // Checked by `Engine::new`.
            None => Ok((self.width, self.height)),
        }
    }

    /// The model's name, or the formula, for a window title.
    pub fn title(&self) -> &str {
        self.src.title()
    }
}

/// Refuses, before any work, a run that would write nothing (`--headless` with neither
/// `--out` nor `--snapshots`), `--snapshots` without `--headless` (the window keeps no
/// snapshots), an `--out` that is not a writable `.png`, and a `--snapshots` that is
/// not a folder or cannot be made one.
fn check_paths(args: &PreviewArgs) -> Result<(), String> {
    if args.headless && args.out.is_none() && args.snapshots.is_none() {
        return Err("--headless: give --out FILE or --snapshots DIR, or nothing is written".into());
    }
    if let Some(dir) = &args.snapshots {
        if !args.headless {
            return Err(format!(
                "--snapshots '{}': snapshots are written with --headless only",
                dir.display()
            ));
        }
        if dir.exists() && !dir.is_dir() {
            return Err(format!(
                "--snapshots '{}': is a file, not a folder",
                dir.display()
            ));
        }
        std::fs::create_dir_all(dir).map_err(|e| {
            format!(
                "--snapshots '{}': cannot create the folder: {e}",
                dir.display()
            )
        })?;
    }
    if let Some(out) = &args.out {
        crate::render::output::check_outputs(out, None)?;
    }
    Ok(())
}

/// Builds the engine options for `args` and `model`.
pub fn options_for(args: &PreviewArgs, model: &Model) -> Result<Options, String> {
    let lambda = match (args.lambda, model.lipschitz) {
        (Some(l), _) => l,
        (None, Some(l)) => l,
        (None, None) => {
            let l = auto_lipschitz(model, &model.domain, AUTO_LIPSCHITZ_SPLITS);
            if !l.is_finite() {
                return Err(format!(
                    "model '{}': its gradient is unbounded on the domain (a sqrt or ln \
                     at 0, a division by 0), so no Lipschitz bound can be computed: pass \
                     --lambda or a smaller --domain",
                    model.name
                ));
            }
            l
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

/// Runs `tracer preview`.
pub fn run_preview(args: &PreviewArgs) -> Result<(), String> {
    let (width, height) = args.image_size()?;
    super::set_threads(args.threads.as_deref())?;
    let mut model =
        super::model_source(&args.src, args.domain.as_deref().map(|d| ("--domain", d)))?;
    if let Some(s) = &args.ortho {
        model.view.ortho = Some(super::parse_ortho(s)?);
    }
    check_paths(args)?;
    let opts = options_for(args, &model)?;
    let engine = Engine::new(model.clone(), model.domain, model.view, width, height, opts)?;
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
    crate::say!(
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
        crate::say!(
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
    crate::say!(
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
