//! `tracer mesh`: its arguments, the refusals before any work (flags, an unknown
//! extension, an unwritable path, a depth beyond the machine's memory), the run with a
//! progress bar and Ctrl-C, and the statistics as text or JSON.
//!
//! Errors are one line, exit code 2, as `render`'s. Ctrl-C stops within a moment
//! (the mesher polls the flag per cell subtree and per chunk of edges): no file is
//! written (the mesh goes to a temporary file renamed into place), the exit code is
//! 130.

use crate::stats_json::{json_string, stats_json};
use model_ir::arith::ArithKind;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use tracer_mesh::{
    mesh_kind, output, MeshError, MeshOptions, MeshResult, MeshStats, DEFAULT_EXTRA_DEPTH,
};

/// The default `--depth`.
pub const DEFAULT_DEPTH: u32 = 6;

/// Arguments of `tracer mesh`.
#[derive(clap::Args, Debug, Clone)]
pub struct MeshArgs {
    /// The model: see `tracer render --help`.
    #[command(flatten)]
    pub src: crate::args::ModelArgs,
    /// Output mesh: .obj, .ply (binary, indexed) or .stl (binary) (default:
    /// <model>.stl).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// 2^N cells along the domain's longest side.
    #[arg(long, default_value = "6", allow_hyphen_values = true)]
    pub depth: String,
    /// How deep to look below --depth for features thinner than a cell (leaves whose
    /// range holds 0 while their corners agree); the leaf level rises to where one is
    /// found (default: --depth + 4).
    #[arg(long, allow_hyphen_values = true)]
    pub max_depth: Option<String>,
    /// Arithmetic.
    #[arg(long, default_value = "revaa", allow_hyphen_values = true, help = arith_help())]
    pub arith: String,
    /// Domain box XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX (default: the model's; [-2, 2]^3 for a
    /// formula). The mesh is clipped to it and closed by its faces.
    #[arg(long, allow_hyphen_values = true)]
    pub domain: Option<String>,
    /// Worker threads (default: one per core).
    #[arg(long, allow_hyphen_values = true)]
    pub threads: Option<String>,
    /// Statistics: text (default), or json (one object on stdout, nothing else there).
    #[arg(long, default_value = "text", allow_hyphen_values = true)]
    pub stats: String,
    /// Skip the self-intersection check (a BVH over the triangles after meshing). It is
    /// on by default: about a tenth of the time of a small mesh of a short formula
    /// (the tanglecube at depth 6), under 1% on long formulas.
    #[arg(long)]
    pub no_check: bool,
    /// Keep one vertex per piece of surface per leaf cell: do not merge cells where
    /// one vertex fits their planes (more triangles on flat parts).
    #[arg(long)]
    pub no_merge: bool,
    /// One plane per edge crossing: leave out the other min/max branches' planes at
    /// creases and corners (as fidget; sharp features get chamfered).
    #[arg(long)]
    pub no_branch_planes: bool,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
}

fn arith_help() -> String {
    format!("Arithmetic: {}", ArithKind::names())
}

/// Parses a depth flag: a whole number.
pub fn parse_depth(flag: &str, s: &str) -> Result<u32, String> {
    let max = tracer_mesh::grid::MAX_DEPTH;
    match s.trim().parse::<u32>() {
        Ok(n) if (tracer_mesh::MIN_DEPTH..=max).contains(&n) => Ok(n),
        _ => Err(format!(
            "{flag} '{s}': expected a whole number from {} to {max}",
            tracer_mesh::MIN_DEPTH
        )),
    }
}

/// The memory available to this process (`MemAvailable` of `/proc/meminfo`), where
/// known.
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib.saturating_mul(1024))
}

/// Everything `tracer mesh` decided before the work: the options and where to write.
#[derive(Debug)]
pub struct Plan {
    /// The model's name.
    pub name: String,
    /// The model.
    pub model: model_sources::Model,
    /// The arithmetic.
    pub kind: ArithKind,
    /// The mesher's options.
    pub opts: MeshOptions,
    /// The output path.
    pub out: PathBuf,
    /// `--stats json`.
    pub json: bool,
}

/// Checks every flag and the output path, and estimates the memory, before any work.
pub fn plan(a: &MeshArgs) -> Result<Plan, String> {
    let kind: ArithKind = a.arith.parse().map_err(|e| format!("--arith: {e}"))?;
    let json = match a.stats.as_str() {
        "text" => false,
        "json" => true,
        s => return Err(format!("--stats '{s}': expected text or json")),
    };
    let depth = parse_depth("--depth", &a.depth)?;
    let max_depth = match &a.max_depth {
        Some(s) => {
            let m = parse_depth("--max-depth", s)?;
            if m < depth {
                return Err(format!(
                    "--max-depth '{s}': must be at least --depth ({depth})"
                ));
            }
            m
        }
        None => (depth + DEFAULT_EXTRA_DEPTH).min(tracer_mesh::grid::MAX_DEPTH),
    };
    if let Some(t) = &a.threads {
        crate::args::parse_threads(t)?;
    }
    let mut model =
        crate::args::model_source(&a.src, a.domain.as_deref().map(|d| ("--domain", d)))?;
    // R-functions written out (as `.vm` tapes spell them) become one instruction each:
    // the same value at every point, and sign tapes on which the mesher's range tests
    // see them as the `min`/`max` they agree with in sign.
    if let model_sources::AnyShape::Expr(t) = &model.shape {
        model.shape = model_sources::AnyShape::Expr(t.fuse_hypot().fuse_rfunctions());
    }
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{}.stl", model.name)));
    output::check(&out).map_err(|e| format!("--out {e}"))?;
    let mut opts = MeshOptions::new(model.domain, depth);
    opts.max_depth = max_depth;
    opts.check_self_intersections = !a.no_check;
    if a.no_merge {
        opts.merge = None;
    }
    opts.branch_planes = !a.no_branch_planes;
    opts.memory_limit = available_memory();
    opts.check().map_err(|e| match e {
        MeshError::TooLarge { .. } => format!("--depth {depth}: {e}"),
        e => e.to_string(),
    })?;
    Ok(Plan {
        name: model.name.clone(),
        model,
        kind,
        opts,
        out,
        json,
    })
}

/// Runs `tracer mesh`.
pub fn run_mesh(a: &MeshArgs) -> Result<(), String> {
    let mut p = plan(a)?;
    crate::args::set_threads(a.threads.as_deref())?;
    if !a.quiet {
        p.opts.progress = Some(Arc::new(crate::bar::Bar::phased()));
    }
    p.opts.cancel = Some(tracer_kit::interrupt::cancel_flag());
    let res = match mesh_kind(p.kind, &p.model.shape, &p.opts) {
        Err(MeshError::Cancelled) => {
            eprintln!("interrupted: no mesh written");
            return Ok(());
        }
        r => r?,
    };
    if tracer_kit::interrupt::requested() {
        eprintln!("interrupted: no mesh written");
        return Ok(());
    }
    output::write(&p.out, &res.mesh).map_err(|e| format!("--out {e}"))?;
    report(&p, &res, &p.out);
    Ok(())
}

fn report(p: &Plan, res: &MeshResult, out: &Path) {
    let s = &res.stats;
    warn(s);
    if p.json {
        tracer_kit::out!("{}", stats_json(&mesh_fields(&p.name, p.kind.name(), s)));
        return;
    }
    tracer_kit::out!("{} depth={} arith={}", p.name, s.depth, p.kind);
    tracer_kit::out!("{s}");
    tracer_kit::out!("wrote {}", out.display());
}

/// One warning line on stderr where the mesh may miss thin parts of the surface: how
/// many cells stayed unresolved, where, and why.
fn warn(s: &MeshStats) {
    if s.unresolved_at_max_depth == 0 {
        return;
    }
    let place = s.unresolved_box.map_or(String::new(), |b| {
        format!(" in {}", tracer_mesh::box_text(&b))
    });
    let held = if s.level_wanted > s.level {
        format!(
            "; features there asked for leaf level {}, held at {} by the work and memory \
             budget",
            s.level_wanted, s.level
        )
    } else {
        String::new()
    };
    eprintln!(
        "warning: {} cells stayed unresolved{place} (--max-depth {} or the probe budget \
         reached{held}): surface thinner than a cell may be missing there; a larger --depth \
         resolves more",
        s.unresolved_at_max_depth, s.max_depth
    );
}

/// The fields of a meshing's `--stats json` object.
pub fn mesh_fields(model: &str, arith: &str, s: &MeshStats) -> Vec<(&'static str, String)> {
    let t = &s.topology;
    let opt = |v: Option<u64>| v.map_or("null".to_string(), |v| v.to_string());
    let counters = s.counters();
    let mut fields = vec![
        ("model", json_string(model)),
        ("arith", json_string(arith)),
        ("wall_s", format!("{:?}", s.wall.as_secs_f64())),
        ("check_wall_s", format!("{:?}", s.check_wall.as_secs_f64())),
    ];
    fields.extend(counters.map(|(k, v)| (k, v.to_string())));
    fields.extend([
        ("euler", t.euler.to_string()),
        ("watertight", t.watertight().to_string()),
        ("manifold", t.manifold().to_string()),
        ("certified_cells", opt(s.certified_cells)),
        (
            "certified_share",
            s.certified_share()
                .map_or("null".into(), |v| format!("{v:?}")),
        ),
        ("self_intersections", opt(s.self_intersections)),
        (
            "unresolved_box",
            s.unresolved_box.map_or("null".into(), |b| {
                let v = [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z];
                format!("[{}]", v.map(|x| format!("{x:?}")).join(", "))
            }),
        ),
    ]);
    fields
}
