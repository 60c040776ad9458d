//! # model-sources: the models and model readers of reliable implicit-surface rendering
//!
//! Model sources and their one registry: every command that takes a model (`render`,
//! `range`, `preview`, the benches) looks it up here ([`load`]), so a model that
//! `tracer list` shows, or a model file, works everywhere. Each source turns its input
//! into an [`AnyShape`] with a domain box and a default view: [`appendix_a`] (the
//! revised-affine paper's models), [`gamito_maddock`] (the progressive-refinement paper's
//! models, with [`noise`]), [`formula`] (formulas parsed from text into a tape) and the
//! model files of [`FORMATS`]: formula files (`.expr`), fidget tapes ([`vm`], `.vm`)
//! and HyperFun programs ([`hyperfun`], `.hf`, compiled onto the same tape), each read
//! by one parse function. A file's [`header`] may state its domain and view.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod appendix_a;
pub mod formula;
pub mod gamito_maddock;
pub mod header;
pub mod hyperfun;
pub mod noise;
pub mod vm;

pub use appendix_a::PaperModel;
pub use gamito_maddock::GmModel;

use arith_core::Real;
use arith_ia::Interval;
use model_ir::shape::{Aabb, Shape, View};
use model_ir::{Tape, Trace};
use std::path::Path;

/// Every kind of shape a model source produces; one `match` per evaluation is negligible
/// next to the arithmetic, and it keeps each renderer monomorphised once per arithmetic.
#[derive(Clone, Debug)]
pub enum AnyShape {
    /// A model of the revised-affine paper's Appendix A.
    Paper(PaperModel),
    /// A model of the progressive-refinement paper.
    Gm(GmModel),
    /// A formula parsed from text.
    Expr(formula::Tape),
}

impl AnyShape {
    /// The function as text that `--expr` accepts and that gives the same values, where
    /// the source has one (the noise models have none).
    pub fn formula(&self) -> Option<String> {
        match self {
            AnyShape::Paper(m) => m.formula().map(str::to_string),
            AnyShape::Gm(m) => m.formula(),
            AnyShape::Expr(t) => Some(formula::ToFormula::to_formula(t)),
        }
    }
}

impl Shape for AnyShape {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        match self {
            AnyShape::Paper(m) => m.eval(x, y, z),
            AnyShape::Gm(m) => m.eval(x, y, z),
            AnyShape::Expr(t) => t.eval(x, y, z),
        }
    }

    fn eval_batch<R: Real>(&self, x: &[R], y: &[R], z: &[R], out: &mut Vec<R>) {
        match self {
            AnyShape::Paper(m) => m.eval_batch(x, y, z, out),
            AnyShape::Gm(m) => m.eval_batch(x, y, z, out),
            AnyShape::Expr(t) => Shape::eval_batch(t, x, y, z, out),
        }
    }

    fn packs(&self) -> bool {
        match self {
            AnyShape::Paper(m) => m.packs(),
            AnyShape::Gm(m) => m.packs(),
            AnyShape::Expr(t) => t.packs(),
        }
    }

    fn specialises(&self) -> bool {
        matches!(self, AnyShape::Expr(t) if t.specialises())
    }

    fn specialises_values(&self) -> bool {
        matches!(self, AnyShape::Expr(t) if t.specialises_values())
    }

    fn tape_len(&self) -> Option<usize> {
        match self {
            AnyShape::Expr(t) => Some(t.len()),
            _ => None,
        }
    }

    fn specialise<R: arith_core::Range>(&self, regions: &[[R; 3]]) -> Option<Self> {
        match self {
            AnyShape::Expr(t) => t.specialise(regions).map(AnyShape::Expr),
            _ => None,
        }
    }

    fn eval_boxes_traced(
        &self,
        x: &[Interval],
        y: &[Interval],
        z: &[Interval],
        out: &mut Vec<Interval>,
        trace: &mut Trace,
    ) {
        match self {
            AnyShape::Expr(t) => t.eval_boxes_traced(x, y, z, out, trace),
            _ => {
                trace.clear();
                self.eval_batch(x, y, z, out)
            }
        }
    }

    fn specialise_traced(&self, trace: &mut Trace, lane: usize) -> Option<Self> {
        match self {
            AnyShape::Expr(t) => t.specialise_traced(trace, lane).map(AnyShape::Expr),
            _ => None,
        }
    }

    fn specialise_groups<R: arith_core::Range>(
        &self,
        regions: &[[R; 3]],
        groups: &[(usize, usize)],
    ) -> (Vec<Self>, Vec<Option<usize>>) {
        match self {
            AnyShape::Expr(t) => {
                let (tapes, which) = t.specialise_groups(regions, groups);
                (tapes.into_iter().map(AnyShape::Expr).collect(), which)
            }
            _ => (Vec::new(), vec![None; groups.len()]),
        }
    }

    fn specialise_values<R: arith_core::Range>(
        &self,
        region: &[R; 3],
        within: f64,
    ) -> Option<Self> {
        match self {
            AnyShape::Expr(t) => t.specialise_values(region, within).map(AnyShape::Expr),
            _ => None,
        }
    }
}

/// A shape with everything needed to render it without further flags.
#[derive(Clone, Debug)]
pub struct Model {
    /// Name used on the command line (`mitchell`, `decocube`, ...).
    pub name: String,
    /// One-line description (the formula or its source).
    pub description: String,
    /// The defining function.
    pub shape: AnyShape,
    /// The function is only considered inside this box (rays are clipped to it).
    pub domain: Aabb,
    /// Default camera framing the model like the papers' figures.
    pub view: View,
    /// A Lipschitz bound of `f` over `domain`, where one is known.
    pub lipschitz: Option<f64>,
}

impl Model {
    /// The model as a tape of the model IR: a formula's own tape, or the generic code of
    /// a built-in model recorded ([`Tape::record`]). Errors for models whose code looks
    /// at the type of its values (procedural noise), which no tape can express.
    ///
    /// ```
    /// use model_ir::shape::Shape;
    /// let m = model_sources::find("mitchell").unwrap();
    /// let t = m.tape().unwrap();
    /// assert_eq!(t.eval(0.3_f64, 0.2, 0.1), m.shape.eval(0.3_f64, 0.2, 0.1));
    /// ```
    pub fn tape(&self) -> Result<Tape, String> {
        match &self.shape {
            AnyShape::Expr(t) => Ok(t.clone()),
            s if !s.packs() => Err(format!(
                "model '{}' uses procedural noise, which a tape cannot express",
                self.name
            )),
            s => Ok(Tape::record(|x, y, z| s.eval(x, y, z))),
        }
    }

    /// A model of the formula `text` (see [`formula`]) over `domain` (default
    /// `[-2, 2]^3`), viewed by [`model_ir::camera::frame_box`] of the domain. Errors: the
    /// formula's parse error, or a domain too large to frame.
    pub fn formula(text: &str, domain: Option<Aabb>) -> Result<Model, String> {
        let tape = formula::parse(text).map_err(|e| e.to_string())?;
        let domain = domain.unwrap_or(Aabb::cube(2.0));
        let view = model_ir::camera::frame_box(&domain)?;
        Ok(Model {
            name: "expr".into(),
            description: text.trim().to_string(),
            shape: AnyShape::Expr(tape),
            domain,
            view,
            lipschitz: None,
        })
    }

    /// A model of the HyperFun program `text` (see [`hyperfun`]; its `my_model`, else
    /// its first body) over `domain`, by default HyperFun's `[-10, 10]^3` (the `hfp`
    /// polygonizer's default box), viewed by [`model_ir::camera::frame_box`] of the domain.
    /// Errors: the program's error (line and column), or a domain too large to frame.
    pub fn hyperfun(text: &str, domain: Option<Aabb>) -> Result<Model, String> {
        let tape = hyperfun::parse_hyperfun(text).map_err(|e| e.to_string())?;
        let domain = domain.unwrap_or(Aabb::cube(hyperfun::DEFAULT_DOMAIN));
        let view = model_ir::camera::frame_box(&domain)?;
        Ok(Model {
            name: "hyperfun".into(),
            description: "a HyperFun program".into(),
            shape: AnyShape::Expr(tape),
            domain,
            view,
            lipschitz: None,
        })
    }
}

/// A model file format: how its files are named and read. Adding a format is one
/// entry of [`FORMATS`] with its parse function.
#[derive(Clone, Copy, Debug)]
pub struct Format {
    /// Its `--format` name.
    pub name: &'static str,
    /// File name extensions (without the dot) that select it.
    pub extensions: &'static [&'static str],
    /// What it is, for `--help` and messages.
    pub about: &'static str,
    /// The comment mark of its [`header`] lines (`""`: no header).
    pub comment: &'static str,
    /// Reads a file's text (`path` names it in messages, `file:line:column: ...`) into
    /// a model with the format's default domain and a view framing it.
    pub parse: fn(&str, &str) -> Result<Model, String>,
}

/// Every model file format.
pub const FORMATS: [Format; 3] = [
    Format {
        name: "expr",
        extensions: &["expr"],
        about: "formula in the language of --expr",
        comment: "#",
        parse: formula_file,
    },
    Format {
        name: "vm",
        extensions: &["vm"],
        about: "fidget SSA tape, negated (fidget is < 0 inside)",
        comment: "#",
        parse: vm_file,
    },
    Format {
        name: "hf",
        extensions: &["hf"],
        about: "HyperFun program",
        comment: "--",
        parse: hf_file,
    },
];

/// The format named `name` (`--format`).
pub fn format(name: &str) -> Result<&'static Format, String> {
    FORMATS
        .iter()
        .find(|f| f.name.eq_ignore_ascii_case(name))
        .ok_or_else(|| {
            let names: Vec<&str> = FORMATS.iter().map(|f| f.name).collect();
            format!(
                "unknown format '{name}' (expected one of: {})",
                names.join(", ")
            )
        })
}

/// The format a file name's extension selects.
pub fn format_of(path: &str) -> Option<&'static Format> {
    let ext = Path::new(path).extension()?.to_str()?;
    FORMATS
        .iter()
        .find(|f| f.extensions.iter().any(|e| e.eq_ignore_ascii_case(ext)))
}

/// The model name of a file: its stem (`models/shikki.hf` is `shikki`).
fn file_stem(path: &str) -> String {
    Path::new(path)
        .file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty())
        .unwrap_or("model")
        .to_string()
}

/// Default domain of a formula: `[-2, 2]^3`.
pub const FORMULA_DOMAIN: f64 = 2.0;

fn formula_file(text: &str, path: &str) -> Result<Model, String> {
    let tape = formula::parse(text)
        .map_err(|e| format!("{path}:{}:{}: {}", e.line, e.column, e.message))?;
    let domain = Aabb::cube(FORMULA_DOMAIN);
    Ok(Model {
        name: file_stem(path),
        description: format!("formula file {path} ({} instructions)", tape.len()),
        shape: AnyShape::Expr(tape),
        domain,
        view: model_ir::camera::frame_box(&domain)?,
        lipschitz: None,
    })
}

fn vm_file(text: &str, path: &str) -> Result<Model, String> {
    let tape = vm::parse(text).map_err(|e| format!("{path}:{e}"))?;
    let domain = Aabb::cube(vm::DEFAULT_DOMAIN);
    Ok(Model {
        name: file_stem(path),
        description: format!("fidget tape {path}, negated ({} instructions)", tape.len()),
        shape: AnyShape::Expr(tape),
        domain,
        view: model_ir::camera::frame_box(&domain)?,
        lipschitz: None,
    })
}

fn hf_file(text: &str, path: &str) -> Result<Model, String> {
    let tape = hyperfun::parse_hyperfun(text)
        .map_err(|e| format!("{path}:{}:{}: {}", e.line, e.column, e.message))?;
    let domain = Aabb::cube(hyperfun::DEFAULT_DOMAIN);
    Ok(Model {
        name: file_stem(path),
        description: format!("HyperFun program {path} ({} instructions)", tape.len()),
        shape: AnyShape::Expr(tape),
        domain,
        view: model_ir::camera::frame_box(&domain)?,
        lipschitz: None,
    })
}

/// The name standing for standard input in [`load`].
pub const STDIN: &str = "-";

/// Reads model text from `spec` (a path, or [`STDIN`]); `what` names the argument in
/// the one-line error.
pub fn read_source(what: &str, spec: &str) -> Result<String, String> {
    let bytes = if spec == STDIN {
        use std::io::Read as _;
        let mut buf = Vec::new();
        std::io::stdin()
            .read_to_end(&mut buf)
            .map_err(|e| format!("{what} '-': cannot read standard input: {e}"))?;
        buf
    } else {
        let p = Path::new(spec);
        if p.is_dir() {
            return Err(format!("{what} '{spec}': is a folder, not a model file"));
        }
        std::fs::read(p).map_err(|e| format!("{what} '{spec}': cannot read the file: {e}"))?
    };
    String::from_utf8(bytes).map_err(|e| {
        format!(
            "{what} '{spec}': not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        )
    })
}

/// The model of `text` in `format` (`path` names it in messages): the format's parse,
/// then the domain (`domain`, else the header's `domain:`, else the format's default)
/// and the view (the header's `view:` fields over the view that frames the domain, or
/// the format's own view where neither the domain nor a view is stated).
pub fn from_text(
    text: &str,
    path: &str,
    format: &Format,
    domain: Option<Aabb>,
) -> Result<Model, String> {
    let mut model = (format.parse)(text, path)?;
    let h = if format.comment.is_empty() {
        header::Header::default()
    } else {
        header::Header::parse(text, format.comment, path)?
    };
    let dom = domain.or(h.domain);
    if let Some(d) = dom {
        model.domain = d;
    }
    if dom.is_some() || !h.view.is_empty() {
        let base = model_ir::camera::frame_box(&model.domain)
            .map_err(|e| format!("{path}: domain: {e}"))?;
        model.view = h.view.apply(base);
    }
    Ok(model)
}

/// The model `spec` names: a built-in name ([`find`]), or a model file's path, or
/// [`STDIN`] (a formula unless `format` says otherwise). A file's format is `format`,
/// else the one its extension selects. `domain` replaces the model's domain (a file's
/// view then frames it, unless its header states one; a built-in keeps its view).
/// `what` names the argument in one-line errors (`MODEL`, `--models`).
pub fn load(
    what: &str,
    spec: &str,
    format: Option<&Format>,
    domain: Option<Aabb>,
) -> Result<Model, String> {
    if spec != STDIN && format.is_none() {
        let builtin = find(spec);
        if builtin.is_ok() || !looks_like_path(spec) {
            let mut m = builtin.map_err(|e| {
                let exts: Vec<String> = FORMATS
                    .iter()
                    .flat_map(|f| f.extensions.iter().map(|e| format!(".{e}")))
                    .collect();
                format!("{what}: {e}, or a model file ({})", exts.join(", "))
            })?;
            if let Some(d) = domain {
                m.domain = d;
            }
            return Ok(m);
        }
    }
    let fmt = match format {
        Some(f) => f,
        None if spec == STDIN => &FORMATS[0],
        None => format_of(spec).ok_or_else(|| {
            let names: Vec<&str> = FORMATS.iter().map(|f| f.name).collect();
            format!(
                "{what} '{spec}': cannot tell the format from the file name: give --format {}",
                names.join("|")
            )
        })?,
    };
    let text = read_source(what, spec)?;
    let path = if spec == STDIN { "<stdin>" } else { spec };
    let mut m = from_text(&text, path, fmt, domain)?;
    if spec == STDIN {
        m.name = "stdin".into();
    }
    Ok(m)
}

/// Whether `spec` is meant as a path: it has a folder part or an extension, or names
/// an existing file.
fn looks_like_path(spec: &str) -> bool {
    spec.contains(['/', '\\']) || Path::new(spec).extension().is_some() || Path::new(spec).is_file()
}

impl Shape for Model {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        self.shape.eval(x, y, z)
    }

    fn eval_batch<R: Real>(&self, x: &[R], y: &[R], z: &[R], out: &mut Vec<R>) {
        self.shape.eval_batch(x, y, z, out)
    }

    fn packs(&self) -> bool {
        self.shape.packs()
    }
}

/// Every model the CLI knows: the paper's, then the progressive-refinement paper's.
pub fn all() -> Vec<Model> {
    let mut v: Vec<Model> = appendix_a::PaperModel::ALL
        .iter()
        .map(|m| m.model())
        .collect();
    v.extend(gamito_maddock::all());
    v
}

/// The names of the built-in models, without building them.
pub fn builtin_names() -> Vec<String> {
    appendix_a::PaperModel::ALL
        .iter()
        .map(|m| m.name().to_string())
        .chain(gamito_maddock::GmModel::all().iter().map(|m| m.name()))
        .collect()
}

/// Whether `name` is a built-in model's (case-insensitive).
pub fn is_builtin(name: &str) -> bool {
    builtin_names().iter().any(|n| n.eq_ignore_ascii_case(name))
}

/// The model named `name` (case-insensitive); the error lists the valid names. Only the
/// model found is built (some models compute a Lipschitz bound when built).
pub fn find(name: &str) -> Result<Model, String> {
    let is = |n: &str| n.eq_ignore_ascii_case(name);
    if let Some(m) = appendix_a::PaperModel::ALL.iter().find(|m| is(m.name())) {
        return Ok(m.model());
    }
    let gm = gamito_maddock::GmModel::all();
    if let Some(m) = gm.iter().find(|m| is(&m.name())) {
        return Ok(m.model());
    }
    Err(format!(
        "unknown model '{name}' (expected one of: {})",
        builtin_names().join(", ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_found() {
        let all = all();
        for m in &all {
            assert_eq!(find(&m.name).unwrap().name, m.name);
            assert_eq!(all.iter().filter(|o| o.name == m.name).count(), 1);
        }
        let e = find("nope").unwrap_err();
        assert!(e.contains("mitchell") && e.contains("nope"));
    }

    /// A model's tape computes what the model computes, bit for bit at points: the
    /// recording performs the model's own operations.
    #[test]
    fn tapes_match_the_models_at_points() {
        for m in all() {
            let Ok(t) = m.tape() else {
                assert!(!m.shape.packs(), "{} failed to record", m.name);
                continue;
            };
            for &(x, y, z) in &[(0.3, -0.2, 0.1), (1.1, 0.7, -0.4), (-0.9, 0.05, 0.6)] {
                let (a, b) = (t.eval(x, y, z), m.shape.eval(x, y, z));
                assert!(
                    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                    "{}: {a} vs {b}",
                    m.name
                );
            }
        }
    }
}
