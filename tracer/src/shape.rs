//! Shapes (functions written once, generic over [`Real`]) and models (a shape with its
//! domain box, default view and, where known, a Lipschitz bound).
//!
//! FRep sign convention: `f >= 0` inside, `f = 0` on the surface.

use arith_core::Real;
use glam::DVec3;

/// A defining function `f(x, y, z)`, evaluable at points (`f64`), over every
/// [`arith_core::Range`], over operation counters and over dual numbers alike.
pub trait Shape: Send + Sync {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R;

    /// Whether [`Shape::eval`] over a pack of four forms ([`arith_core::pack`]) gives,
    /// lane by lane, what it gives over each form alone: true for code written with the
    /// [`Real`] operations only. A shape that looks at the concrete type of its arguments
    /// (noise over ranges, see [`crate::noise`]) does not know the pack types and says
    /// false; the tracer then evaluates its forms one at a time.
    fn packs(&self) -> bool {
        true
    }
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: DVec3,
    pub max: DVec3,
}

impl Aabb {
    pub fn new(min: DVec3, max: DVec3) -> Self {
        Aabb { min, max }
    }
    /// The cube `[-r, r]^3`.
    pub fn cube(r: f64) -> Self {
        Aabb {
            min: DVec3::splat(-r),
            max: DVec3::splat(r),
        }
    }
}

/// A pinhole camera placement (see [`crate::camera`] for the ray formula).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    pub eye: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    /// Vertical field of view in degrees.
    pub fov_deg: f64,
}

/// Every kind of shape the CLI can render; one `match` per evaluation is negligible next
/// to the arithmetic, and it keeps the renderer monomorphised once per arithmetic only.
#[derive(Clone, Debug)]
pub enum AnyShape {
    /// A model of the revised-affine paper's Appendix A.
    Paper(crate::models::PaperModel),
    /// A model of the progressive-refinement paper.
    Gm(crate::gm_models::GmModel),
    /// A formula parsed from text.
    Expr(crate::expr::Tape),
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
    pub shape: AnyShape,
    /// The function is only considered inside this box (rays are clipped to it).
    pub domain: Aabb,
    /// Default camera framing the model like the papers' figures.
    pub view: View,
    /// A Lipschitz bound of `f` over `domain`, where one is known.
    pub lipschitz: Option<f64>,
}

impl Shape for Model {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        self.shape.eval(x, y, z)
    }

    fn packs(&self) -> bool {
        self.shape.packs()
    }
}
