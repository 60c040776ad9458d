//! The flags the commands share and the parsing of flag values into the library's
//! types, with one-line errors naming the flag: the model a command's flags select
//! ([`ModelArgs`], [`model_source`]), the view ([`ViewArgs`]), sizes, boxes, numbers
//! and the worker threads.

use glam::DVec3;
use model_ir::shape::Aabb;
use model_sources::Model;

/// The flags that choose a model, shared by `render`, `range` and `preview`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct ModelArgs {
    /// The model: a built-in name (see `tracer list`), a model file (`.expr` formula,
    /// `.vm` fidget tape, `.hf` HyperFun; see --format), or `-` for a formula on
    /// standard input. Or give --expr or --expr-file.
    pub model: Option<String>,
    /// A formula over x, y, z (f >= 0 inside), e.g. "1 - x^2 - y^2 - z^2"; its domain
    /// defaults to [-2, 2]^3, its view frames the domain. The language is listed at the
    /// end of `--help`.
    #[arg(long, allow_hyphen_values = true)]
    pub expr: Option<String>,
    /// A formula file (the language of --expr, with optional `# domain:` and `# view:`
    /// header lines); `-` reads standard input. The same as MODEL with --format expr.
    #[arg(long, allow_hyphen_values = true)]
    pub expr_file: Option<String>,
    /// The model file's format: expr (formula), vm (fidget SSA tape; fidget's f < 0
    /// inside is negated to ours, f >= 0 inside) or hf (HyperFun). Default: from the
    /// file's extension (.expr, .vm, .hf); expr for `-`.
    #[arg(long, allow_hyphen_values = true)]
    pub format: Option<String>,
}

impl ModelArgs {
    /// What names the model, for a window title: the name or path, or the formula.
    pub fn title(&self) -> &str {
        self.model
            .as_deref()
            .or(self.expr_file.as_deref())
            .or(self.expr.as_deref())
            .unwrap_or_default()
    }
}

/// The model that the flags of `src` and a domain flag (`(flag, value)`: `--domain`,
/// `--box`) select, from the one registry ([`model_sources::load`]): a built-in name, a
/// model file or standard input, or a formula (domain `[-2, 2]^3` unless the flag gives
/// one, framed by [`model_ir::camera::frame_box`]). A file's header may state its domain
/// and view; the flag overrides the domain, and the view then frames the new domain
/// unless the header states one. Files are read (and a missing one refused) here,
/// before any work.
pub fn model_source(src: &ModelArgs, domain: Option<(&str, &str)>) -> Result<Model, String> {
    let domain = match domain {
        Some((flag, s)) => {
            let b = parse_box(flag, s)?;
            // Formulas and files frame their view from the domain (built-ins keep theirs).
            let builtin = src
                .model
                .as_deref()
                .is_some_and(|m| src.format.is_none() && model_sources::is_builtin(m));
            if !builtin {
                model_ir::camera::frame_box(&b).map_err(|e| format!("{flag} '{s}': {e}"))?;
            }
            Some(b)
        }
        None => None,
    };
    let format = src
        .format
        .as_deref()
        .map(|f| model_sources::format(f).map_err(|e| format!("--format: {e}")))
        .transpose()?;
    let given = [
        src.model.is_some(),
        src.expr.is_some(),
        src.expr_file.is_some(),
    ];
    match given.iter().filter(|&&g| g).count() {
        0 => {
            return Err(
                "give a MODEL (a name from `tracer list`, a model file, or - for stdin), \
                 --expr FORMULA or --expr-file FILE"
                    .into(),
            )
        }
        1 => {}
        _ => return Err("give one of MODEL, --expr and --expr-file, not several".into()),
    }
    if let Some(f) = &src.expr {
        if format.is_some() {
            return Err("--format applies to MODEL files, not to --expr".into());
        }
        return Model::formula(f, domain).map_err(|e| format!("--expr: {e}"));
    }
    if let Some(f) = &src.expr_file {
        if format.is_some_and(|f| f.name != "expr") {
            return Err("--expr-file reads formula files: leave out --format".into());
        }
        let expr = model_sources::format("expr")?;
        return model_sources::load("--expr-file", f, Some(expr), domain);
    }
    let m = src.model.as_deref().unwrap_or_default();
    model_sources::load("MODEL", m, format, domain)
}

/// The camera flags, shared by `render` and `preview`: each one given replaces that part
/// of the model's default view.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct ViewArgs {
    /// Eye position X,Y,Z.
    #[arg(long, allow_hyphen_values = true)]
    pub eye: Option<String>,
    /// Point looked at X,Y,Z.
    #[arg(long = "look-at", allow_hyphen_values = true)]
    pub look_at: Option<String>,
    /// Up vector X,Y,Z (default 0,1,0).
    #[arg(long, allow_hyphen_values = true)]
    pub up: Option<String>,
    /// Vertical field of view in degrees.
    #[arg(long, allow_hyphen_values = true)]
    pub fov: Option<String>,
    /// Orthographic camera WIDTH model units across the image (parallel rays along the
    /// view direction, starting on the image plane through the eye) instead of the
    /// pinhole; --fov is then unused.
    #[arg(long, allow_hyphen_values = true, value_name = "WIDTH")]
    pub ortho: Option<String>,
}

impl ViewArgs {
    /// `view` with the given flags applied; an error names the flag and its value.
    pub fn apply(&self, mut view: model_ir::shape::View) -> Result<model_ir::shape::View, String> {
        if let Some(s) = &self.eye {
            view.eye = parse_vec3("--eye", s)?;
        }
        if let Some(s) = &self.look_at {
            view.look_at = parse_vec3("--look-at", s)?;
        }
        if let Some(s) = &self.up {
            view.up = parse_vec3("--up", s)?;
        }
        if let Some(s) = &self.fov {
            let f = parse_positive("--fov", s)?;
            if f >= 180.0 {
                return Err(format!("--fov '{s}': must be below 180 degrees"));
            }
            view.fov_deg = f;
        }
        if let Some(s) = &self.ortho {
            view.ortho = Some(parse_ortho(s)?);
        }
        Ok(view)
    }
}

/// Parses `--ortho WIDTH`: the view width of an orthographic camera in model units.
pub fn parse_ortho(s: &str) -> Result<f64, String> {
    parse_positive("--ortho", s)
}

/// Parses `n` comma-separated finite numbers for `flag`.
pub fn parse_list(flag: &str, s: &str, n: usize) -> Result<Vec<f64>, String> {
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

/// Parses `X,Y,Z` for `flag`.
pub fn parse_vec3(flag: &str, s: &str) -> Result<DVec3, String> {
    let v = parse_list(flag, s, 3)?;
    Ok(DVec3::new(v[0], v[1], v[2]))
}

/// Parses `XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX` for `flag`: a box the renderers can work in.
pub fn parse_box(flag: &str, s: &str) -> Result<Aabb, String> {
    let v = parse_list(flag, s, 6)?;
    let b = Aabb::new(DVec3::new(v[0], v[1], v[2]), DVec3::new(v[3], v[4], v[5]));
    model_ir::shape::check_domain(&b).map_err(|e| format!("{flag} '{s}': {e}"))?;
    Ok(b)
}

/// Parses `WxH` for `flag`, each side within [`model_ir::camera::check_size`].
pub fn parse_size(flag: &str, s: &str) -> Result<(u32, u32), String> {
    let max = model_ir::camera::MAX_SIDE;
    let err =
        || format!("{flag} '{s}': expected WxH with positive integers up to {max}, e.g. 640x480");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(err)?;
    let w: u32 = w.trim().parse().map_err(|_| err())?;
    let h: u32 = h.trim().parse().map_err(|_| err())?;
    model_ir::camera::check_size(w, h).map_err(|_| err())?;
    Ok((w, h))
}

/// Most worker threads `--threads` accepts.
pub const MAX_THREADS: usize = 1024;

/// Parses `--threads N`, `1 <= N <= MAX_THREADS`.
pub fn parse_threads(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n) if (1..=MAX_THREADS).contains(&n) => Ok(n),
        _ => Err(format!(
            "--threads '{s}': expected a whole number of threads from 1 to {MAX_THREADS}"
        )),
    }
}

/// Builds rayon's global pool with `--threads` threads, if given (before any parallel
/// work: the pool is built once per process).
pub fn set_threads(threads: Option<&str>) -> Result<(), String> {
    let Some(s) = threads else {
        return Ok(());
    };
    let n = parse_threads(s)?;
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build_global()
        .map_err(|e| format!("--threads {n}: {e}"))
}

/// Parses a finite number above 0 for `flag`.
pub fn parse_positive(flag: &str, s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        _ => Err(format!("{flag} '{s}': expected a positive number")),
    }
}
