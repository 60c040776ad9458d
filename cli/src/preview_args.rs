//! `tracer preview`'s arguments: their checks, the engine options and the engine they
//! give, and where images are written.

use model_ir::arith::ArithKind;
use model_ir::gradient_bound::auto_lipschitz;
use model_sources::Model;
use std::path::{Path, PathBuf};
use tracer::progressive::SharedImage;
use tracer::progressive::{write_png, Bound, ChildStart, Engine, Options, Rect};

/// Sub-boxes per axis of the automatic Lipschitz bound of a model that has none.
pub const AUTO_LIPSCHITZ_SPLITS: usize = 16;

fn arith_help() -> String {
    format!("Arithmetic of --bound range: {}", ArithKind::names())
}

/// Arguments of `tracer preview`.
#[derive(clap::Args, Debug, Clone)]
pub struct PreviewArgs {
    /// The model: see `tracer render --help`.
    #[command(flatten)]
    pub src: crate::args::ModelArgs,
    /// Domain box XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX (default: the model's; [-2, 2]^3 for a
    /// formula).
    #[arg(long, allow_hyphen_values = true)]
    pub domain: Option<String>,
    /// Image size WxH, as for `tracer render` (default 800x800).
    #[arg(long, allow_hyphen_values = true)]
    pub size: Option<String>,
    /// The camera: as for `tracer render` (with --ortho, cones become cylinders of
    /// parallel rays).
    #[command(flatten)]
    pub view: crate::args::ViewArgs,
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
    #[arg(long, default_value_t = tracer::search::lipschitz::DEFAULT_OVERSHOOT)]
    pub overshoot: f64,
    /// Anti-aliasing: subdivide samples to 1/N of a pixel and filter them into pixels
    /// with --filter (Appendix A, eq. A.1).
    #[arg(long, default_value_t = 1)]
    pub aa: u32,
    /// Anti-aliasing filter (with --aa above 1): a B-spline of degree 0 to 3: box, tent,
    /// quadratic or cubic.
    #[arg(long, default_value = "quadratic", allow_hyphen_values = true)]
    pub filter: String,
    /// Start child cones as eq. (8) of the paper instead of the guaranteed radial rule.
    #[arg(long)]
    pub paper_child_start: bool,
    /// How cones and terminal rays are proved clear of the surface: `lipschitz` (the
    /// paper's one global bound), `local` (a bound per cone and ray segment from the
    /// range of the gradient over it), `auto` (local where the gradient's bounds over
    /// 8^3 sub-boxes are mostly below half the global one, else lipschitz), or `range`
    /// (each cone segment tested with the --arith range arithmetic over its frustum,
    /// terminal rays by Algorithm 1: no Lipschitz bound needed).
    #[arg(long, default_value = tracer::progressive::DEFAULT_BOUND.name(), allow_hyphen_values = true)]
    pub bound: String,
    /// Arithmetic of `--bound range`.
    #[arg(long, default_value = "revaa", help = arith_help())]
    pub arith: String,
    /// No window: refine to completion (or Ctrl-C), printing each level transition.
    #[arg(long)]
    pub headless: bool,
    /// Write a PNG at every level transition into this directory (headless).
    #[arg(long)]
    pub snapshots: Option<PathBuf>,
    /// Write the image here at completion, or when stopped early.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// A region of interest X0,Y0,X1,Y1 (pixel corners, inclusive), refined first from
    /// the start of level --roi-level on (Section 3.4; in the window, drag with the left
    /// button instead). Headless with --snapshots, `roi-set.png` and `roi-done.png` are
    /// written when it is set and when it is fully refined (the paper's Fig. 10).
    #[arg(long, allow_hyphen_values = true)]
    pub roi: Option<String>,
    /// The level at whose start --roi is set.
    #[arg(long, default_value_t = 0)]
    pub roi_level: usize,
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
            Some(s) => crate::args::parse_size("--size", s),
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
        tracer_kit::output::check_outputs(out, None)?;
    }
    Ok(())
}

/// The `--bound` and `--arith` flags as a [`Bound`].
pub fn parse_bound(bound: &str, arith: &str) -> Result<Bound, String> {
    match bound.to_ascii_lowercase().as_str() {
        "lipschitz" => Ok(Bound::Lipschitz),
        "local" => Ok(Bound::Local),
        "auto" => Ok(Bound::Auto),
        "range" => Ok(Bound::Range(
            arith.parse().map_err(|e| format!("--arith: {e}"))?,
        )),
        _ => Err(format!(
            "--bound '{bound}': expected lipschitz, local, auto or range"
        )),
    }
}

/// Builds the engine options for `args` and `model`. A Lipschitz mode on a model whose
/// gradient is unbounded on the domain (no `--lambda`, none of its own) falls back to
/// the range test, which needs no bound, with a note on stderr.
pub fn options_for(args: &PreviewArgs, model: &Model) -> Result<Options, String> {
    let mut bound = parse_bound(&args.bound, &args.arith)?;
    let lambda = match (bound, args.lambda, model.lipschitz) {
        (_, Some(l), _) | (_, None, Some(l)) => l,
        (Bound::Range(_), None, None) => f64::NAN,
        (_, None, None) => {
            let l = auto_lipschitz(model, &model.domain, AUTO_LIPSCHITZ_SPLITS);
            if !l.is_finite() {
                let kind: ArithKind = args.arith.parse().map_err(|e| format!("--arith: {e}"))?;
                eprintln!(
                    "note: model '{}': its gradient is unbounded on the domain (a sqrt or ln \
                     at 0, a division by 0), so no Lipschitz bound exists there: using \
                     --bound range --arith {kind} instead (or pass --lambda, or a smaller \
                     --domain)",
                    model.name
                );
                bound = Bound::Range(kind);
            }
            l
        }
    };
    let mut o = Options::new(lambda);
    o.eps = args.eps;
    o.overshoot = args.overshoot;
    o.aa = args.aa;
    o.filter = args.filter.parse().map_err(|e| format!("--filter: {e}"))?;
    o.bound = bound;
    if args.paper_child_start {
        o.child_start = ChildStart::Paper;
    }
    Ok(o)
}

/// Writes the image to `out` (`flag` names it in messages); when that fails (a full disk,
/// a folder removed meanwhile) the computed image is not lost: it goes to a file in the
/// temporary folder, and the error line says where.
pub fn save_image(img: &SharedImage, out: &Path, flag: &str) -> Result<(), String> {
    let Err(e) = write_png(img, out) else {
        return Ok(());
    };
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let keep =
        std::env::temp_dir().join(format!("tracer-preview-{}-{nanos}.png", std::process::id()));
    match write_png(img, &keep) {
        Ok(()) => Err(format!(
            "{flag} '{}': {e}; the image is kept in {}",
            out.display(),
            keep.display()
        )),
        Err(e2) => Err(format!(
            "{flag} '{}': {e}; keeping it in {} failed too: {e2}",
            out.display(),
            keep.display()
        )),
    }
}

/// The `--roi` flag as a rectangle of the `w x h` image.
pub fn parse_roi(s: &str, w: u32, h: u32) -> Result<Rect, String> {
    let v = crate::args::parse_list("--roi", s, 4)?;
    if v.iter().any(|x| x.fract() != 0.0 || *x < 0.0) {
        return Err(format!(
            "--roi '{s}': the corners must be whole pixel numbers"
        ));
    }
    let (x0, y0, x1, y1) = (v[0] as u32, v[1] as u32, v[2] as u32, v[3] as u32);
    if x0.max(x1) >= w || y0.max(y1) >= h {
        return Err(format!("--roi '{s}': outside the {w}x{h} image"));
    }
    Ok(Rect::from_corners((x0, y0), (x1, y1)))
}

/// What `tracer preview` runs on: the engine, the model and the region of interest,
/// every flag and path checked.
pub fn prepare(args: &PreviewArgs) -> Result<(Engine<Model>, Model, Option<Rect>), String> {
    let (width, height) = args.image_size()?;
    crate::args::set_threads(args.threads.as_deref())?;
    let mut model =
        crate::args::model_source(&args.src, args.domain.as_deref().map(|d| ("--domain", d)))?;
    model.view = args.view.apply(model.view)?;
    let roi = args
        .roi
        .as_deref()
        .map(|s| parse_roi(s, width, height))
        .transpose()?;
    check_paths(args)?;
    let opts = options_for(args, &model)?;
    let engine = Engine::new(model.clone(), model.domain, model.view, width, height, opts)?;
    Ok((engine, model, roi))
}
