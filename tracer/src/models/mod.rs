//! Model sources and their one registry: every command that takes a model (`render`,
//! `range`, `preview`, the benches) looks it up here, so a model that `tracer list`
//! shows works everywhere. Each source turns its input into an [`AnyShape`] with a
//! domain box and a default view: [`appendix_a`] (the revised-affine paper's models),
//! [`progressive`] (the progressive-refinement paper's models, with [`noise`]) and
//! [`formula`] (formulas parsed from text into a tape) and [`hyperfun`] (HyperFun
//! programs compiled onto the same tape).

pub mod appendix_a;
pub mod formula;
pub mod hyperfun;
pub mod noise;
pub mod progressive;

pub use appendix_a::PaperModel;
pub use progressive::GmModel;

use crate::shape::{Aabb, Shape, View};
use arith_core::Real;

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

impl Shape for AnyShape {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        match self {
            AnyShape::Paper(m) => m.eval(x, y, z),
            AnyShape::Gm(m) => m.eval(x, y, z),
            AnyShape::Expr(t) => t.eval(x, y, z),
        }
    }

    fn packs(&self) -> bool {
        match self {
            AnyShape::Paper(m) => m.packs(),
            AnyShape::Gm(m) => m.packs(),
            AnyShape::Expr(t) => t.packs(),
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
    /// A model of the formula `text` (see [`formula`]) over `domain` (default
    /// `[-2, 2]^3`), viewed by [`crate::camera::frame_box`] of the domain. Errors: the
    /// formula's parse error, or a domain too large to frame.
    pub fn formula(text: &str, domain: Option<Aabb>) -> Result<Model, String> {
        let tape = formula::parse(text).map_err(|e| e.to_string())?;
        let domain = domain.unwrap_or(Aabb::cube(2.0));
        let view = crate::camera::frame_box(&domain)?;
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
    /// polygonizer's default box), viewed by [`crate::camera::frame_box`] of the domain.
    /// Errors: the program's error (line and column), or a domain too large to frame.
    pub fn hyperfun(text: &str, domain: Option<Aabb>) -> Result<Model, String> {
        let tape = hyperfun::parse_hyperfun(text).map_err(|e| e.to_string())?;
        let domain = domain.unwrap_or(Aabb::cube(10.0));
        let view = crate::camera::frame_box(&domain)?;
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

impl Shape for Model {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        self.shape.eval(x, y, z)
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
    v.extend(progressive::all());
    v
}

/// The model named `name` (case-insensitive); the error lists the valid names. Only the
/// model found is built (some models compute a Lipschitz bound when built).
pub fn find(name: &str) -> Result<Model, String> {
    let is = |n: &str| n.eq_ignore_ascii_case(name);
    if let Some(m) = appendix_a::PaperModel::ALL.iter().find(|m| is(m.name())) {
        return Ok(m.model());
    }
    let gm = progressive::GmModel::all();
    if let Some(m) = gm.iter().find(|m| is(&m.name())) {
        return Ok(m.model());
    }
    let names: Vec<String> = appendix_a::PaperModel::ALL
        .iter()
        .map(|m| m.name().to_string())
        .chain(gm.iter().map(|m| m.name()))
        .collect();
    Err(format!(
        "unknown model '{name}' (expected one of: {})",
        names.join(", ")
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
}
