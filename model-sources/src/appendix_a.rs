//! The revised-affine paper's Appendix A models, written once, generic over [`Real`], so
//! the same code serves point evaluation (shading) and every range arithmetic.
//!
//! R-function operators: `&` = [`intersect`], `|` = [`union`], `\` = [`subtract`]
//! (`f >= 0` inside). Domains were chosen by sampling each function on a grid and adding
//! a margin around the solid; views frame the solid in a three-quarter view.

use super::{AnyShape, Model};
use arith_core::rfunc::{
    blend_intersect, blend_union, hf_blend_intersect, hf_blend_union, intersect, subtract, union,
};
use arith_core::Real;
use glam::DVec3;
use model_ir::shape::{Aabb, Shape, View};

/// A model of Appendix A (plus our "sphere with trimming", which the paper only cites).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PaperModel {
    /// Mitchell's quartic.
    Mitchell,
    /// The Bretzel (pretzel).
    Bretzel,
    /// The decocube.
    Decocube,
    /// A CSG construction of a box, a sphere and cylinders with R-functions.
    Csg,
    /// A spherical shell trimmed by a procedural band (our model).
    SphereTrimming,
    /// A sphere with sine noise, read as the authors' code has it (per-axis terms).
    SphereNoise,
    /// The sphere with sine noise exactly as Appendix A prints it.
    SphereNoisePrinted,
    /// CSG with blending union and intersection, HyperFun's `hfBlendUni`/`hfBlendInt`.
    CsgBlending,
    /// CSG with blending as Appendix A prints it, read literally.
    CsgBlendingPrinted,
    /// Hair: thin sine-modulated strands.
    Hair,
    /// A hemispherical shell with a sine microstructure.
    SphereMicrostructure,
    /// Virtual Shikki: a sake set on a table, the HyperFun program `data/shikki.hf` of this crate.
    Shikki,
}

impl PaperModel {
    /// Every model, in the order of the paper's Table 1.
    pub const ALL: [PaperModel; 12] = [
        PaperModel::Mitchell,
        PaperModel::Bretzel,
        PaperModel::Decocube,
        PaperModel::Csg,
        PaperModel::SphereTrimming,
        PaperModel::SphereNoise,
        PaperModel::SphereNoisePrinted,
        PaperModel::CsgBlending,
        PaperModel::CsgBlendingPrinted,
        PaperModel::Hair,
        PaperModel::SphereMicrostructure,
        PaperModel::Shikki,
    ];

    /// Command-line name.
    pub fn name(self) -> &'static str {
        match self {
            PaperModel::Mitchell => "mitchell",
            PaperModel::Bretzel => "bretzel",
            PaperModel::Decocube => "decocube",
            PaperModel::Csg => "csg",
            PaperModel::SphereTrimming => "sphere-trimming",
            PaperModel::SphereNoise => "sphere-noise",
            PaperModel::SphereNoisePrinted => "sphere-noise-printed",
            PaperModel::CsgBlending => "csg-blending",
            PaperModel::CsgBlendingPrinted => "csg-blending-printed",
            PaperModel::Hair => "hair",
            PaperModel::SphereMicrostructure => "sphere-microstructure",
            PaperModel::Shikki => "shikki",
        }
    }

    /// The paper's Table 1 resolution.
    pub fn table1_size(self) -> (u32, u32) {
        match self {
            PaperModel::Mitchell | PaperModel::Bretzel | PaperModel::Decocube => (1280, 1024),
            PaperModel::SphereTrimming => (1024, 768),
            PaperModel::SphereNoise | PaperModel::SphereNoisePrinted => (800, 600),
            PaperModel::Shikki => (320, 240),
            PaperModel::Csg
            | PaperModel::CsgBlending
            | PaperModel::CsgBlendingPrinted
            | PaperModel::Hair
            | PaperModel::SphereMicrostructure => (640, 480),
        }
    }

    fn description(self) -> &'static str {
        match self {
            PaperModel::Mitchell => "20(x^2+y^2+z^2) - 4(x^4+(y^2+z^2)^2) - 17x^2(y^2+z^2) - 17",
            PaperModel::Bretzel => "2 - 60z^2 - (x^2(1.21-x^2)^2(3.8-x^2)^3 - 10y^2)^2",
            PaperModel::Decocube => {
                "0.02 - ((x^2+y^2-0.82)^2+(z^2-1)^2)((y^2+z^2-0.82)^2+(x^2-1)^2)((x^2+z^2-0.82)^2+(y^2-1)^2)"
            }
            PaperModel::Csg => "b | (s & ((c1\\c2)|(c3\\c4)) \\ c5): box, sphere and four cylinders",
            PaperModel::SphereTrimming => "((1-r^2) \\ (0.94-r^2)) & (0.3 - |gyroid(5x,5y,5z)|): shell trimmed to thin ribbons",
            PaperModel::SphereNoise => "81 - x^2 - y^2 - z^2 + product of three per-axis sine-noise factors (the authors' code)",
            PaperModel::SphereNoisePrinted => "81 - x^2 - y^2 - z^2 + product of three sine-noise factors (as printed)",
            PaperModel::CsgBlending => "(((c1 vb c2) ^b s) vb b) ^b (-c3) with vb = hfBlendUni, ^b = hfBlendInt (0.5, 1, 1)",
            PaperModel::CsgBlendingPrinted => "(((c1 vb c2) ^b s) vb b) ^b (-c3) with the paper's blends, read literally",
            PaperModel::Hair => "o | ((hair pattern - 10) & (o + 2) & y): ellipsoid head with procedural hair",
            PaperModel::SphereMicrostructure => "((ball & lattice of bars) | shell) & (-z)",
            PaperModel::Shikki => "stand | cup | sake pot | table: the HyperFun program data/shikki.hf",
        }
    }

    /// The function in the formula language of `--expr` (see [`super::formula`]), written
    /// to evaluate in the same order as the Rust below, so that at points it gives the
    /// same values bit for bit (`tracer list` prints it); `None` for the models that have
    /// no such text.
    pub fn formula(self) -> Option<&'static str> {
        Some(match self {
            PaperModel::Mitchell => {
                "x2 = x^2; yz = y^2 + z^2; (x2 + yz) * 20 - (x2^2 + yz^2) * 4 - x2 * yz * 17 - 17"
            }
            PaperModel::Bretzel => {
                "x2 = x^2; a = (1.21 - x2)^2; b = (3.8 - x2)^3; inner = x2 * a * b - y^2 * 10; \
                 2 - z^2 * 60 - inner^2"
            }
            PaperModel::Decocube => {
                "x2 = x^2; y2 = y^2; z2 = z^2; \
                 p1 = (x2 + y2 - 0.82)^2 + (z2 - 1)^2; p2 = (y2 + z2 - 0.82)^2 + (x2 - 1)^2; \
                 p3 = (x2 + z2 - 0.82)^2 + (y2 - 1)^2; 0.02 - p1 * p2 * p3"
            }
            PaperModel::Csg => {
                "x2 = x^2; y2 = y^2; z2 = z^2; b = (0.36 - x2) & (0.36 - y2) & (0.36 - z2); \
                 s = 0.7056 - (x2 + y2 + z2); yz = y2 + z2; xz = x2 + z2; \
                 c1 = 0.09 - yz; c2 = 0.04 - yz; c3 = 0.09 - xz; c4 = 0.04 - xz; \
                 c5 = 0.25 - (x2 + y2); b | ((s & ((c1 \\ c2) | (c3 \\ c4))) \\ c5)"
            }
            PaperModel::SphereTrimming => {
                "r2 = x^2 + y^2 + z^2; shell = (1 - r2) \\ (0.94 - r2); \
                 x5 = x * 5; y5 = y * 5; z5 = z * 5; \
                 g = sin(x5) * cos(y5) + sin(y5) * cos(z5) + sin(z5) * cos(x5); \
                 shell & (0.3 - abs(g))"
            }
            PaperModel::SphereNoisePrinted => {
                "sx = sin(x * 1.5); sy = sin(y * 1.5); w = sin(x * 1.111 + sx * 1.1); \
                 f1 = sx * 3.8 + w * 1.624; f2 = sy * 3.8 + w * 1.299; f3 = sy * 3.8 + w * 2.598; \
                 81 - (x^2 + y^2 + z^2) + f1 * f2 * f3"
            }
            PaperModel::CsgBlendingPrinted => {
                "x2 = x^2; y2 = y^2; z2 = z^2; b = (0.36 - x2) & (0.36 - y2) & (0.36 - z2); \
                 s = 0.7056 - (x2 + y2 + z2); \
                 c1 = 0.09 - (y2 + z2); c2 = 0.09 - (x2 + z2); c3 = 0.25 - (x2 + y2); \
                 q1 = c1^2 + c2^2; i1 = c1 + c2 - sqrt(q1 + 1 / (q1 + 1) * 0.5); \
                 q2 = i1^2 + s^2; u1 = i1 + s + sqrt(q2 + 1 / (q2 + 1) * 0.5); \
                 q3 = u1^2 + b^2; i2 = u1 + b - sqrt(q3 + 1 / (q3 + 1) * 0.5); \
                 m = -c3; q4 = i2^2 + m^2; i2 + m + sqrt(q4 + 1 / (q4 + 1) * 0.5)"
            }
            PaperModel::Hair => {
                "x2 = x^2; y2 = y^2; z2 = z^2; \
                 o1 = 1 - (x2 * 0.0625 + y2 * 0.027777777777777776 + z2 * 0.0625); \
                 o2 = 1 - (x2 / 1.6129 + (y + 2.5)^2 / 2.25 + (z - 3)^2 / 1.6129); \
                 o = o1 | o2; k = 9 / sqrt(x2 + y2 + z2); \
                 xk = x * k; sx = sin(xk * 1.8); fx = sx * 1.8 + (sin(xk * 1.33) * 1.538 + sx * 1.4); \
                 yk = y * k; sy = sin(yk * 1.8); fy = sy * 1.8 + (sin(yk * 1.33) * 1.538 + sy * 1.4); \
                 zk = z * k; sz = sin(zk * 1.8); fz = sz * 1.8 + (sin(zk * 1.33) * 1.538 + sz * 1.4); \
                 pattern = fx * fy * fz - 10; o | ((pattern & (o + 2)) & y)"
            }
            PaperModel::SphereMicrostructure => {
                "r2 = x^2 + y^2 + z^2; ball = 1 - r2; \
                 sx = sin(x * 20) - 0.9; sy = sin(y * 20) - 0.9; sz = sin(z * 20) - 0.9; \
                 lattice = (sy & sz) | (sx & sz) | (sx & sy); shell = ball \\ (0.75 - r2); \
                 ((ball & lattice) | shell) & -z"
            }
            PaperModel::SphereNoise => {
                "sx = sin(x * 1.5); sy = sin(y * 1.5); sz = sin(z * 1.5); \
                 fx = sx * 3.8 + sin(x * 1.111 + sz * 1.1) * 1.624; \
                 fy = sy * 3.8 + sin(y * 1.111 + sx * 1.1) * 1.299; \
                 fz = sz * 3.8 + sin(z * 1.111 + sy * 1.1) * 2.598; \
                 81 - (x^2 + y^2 + z^2) + fx * fy * fz"
            }
            PaperModel::CsgBlending => {
                "x2 = x^2; y2 = y^2; z2 = z^2; b = (0.36 - x2) & (0.36 - y2) & (0.36 - z2); \
                 s = 0.7056 - (x2 + y2 + z2); \
                 c1 = 0.09 - (y2 + z2); c2 = 0.09 - (x2 + z2); c3 = 0.25 - (x2 + y2); \
                 f1 = hf_blend_union(c1, c2, 0.5, 1, 1); f2 = hf_blend_intersect(f1, s, 0.5, 1, 1); \
                 f3 = hf_blend_union(f2, b, 0.5, 1, 1); hf_blend_intersect(f3, -c3, 0.5, 1, 1)"
            }
            // A HyperFun program: its formula is its tape's (`AnyShape::formula`).
            PaperModel::Shikki => return None,
        })
    }

    /// Domain box: the function is considered inside it only.
    pub fn domain(self) -> Aabb {
        match self {
            PaperModel::Mitchell => Aabb::cube(2.05),
            PaperModel::Bretzel => {
                Aabb::new(DVec3::new(-2.2, -1.2, -0.4), DVec3::new(2.2, 1.2, 0.4))
            }
            PaperModel::Decocube => Aabb::cube(1.2),
            PaperModel::Csg => Aabb::cube(0.9),
            PaperModel::SphereTrimming => Aabb::cube(1.05),
            PaperModel::SphereNoise => Aabb::cube(15.0),
            PaperModel::SphereNoisePrinted => Aabb::new(
                DVec3::new(-13.0, -13.5, -16.5),
                DVec3::new(12.0, 15.0, 16.5),
            ),
            PaperModel::CsgBlending => Aabb::cube(1.15),
            PaperModel::CsgBlendingPrinted => Aabb::cube(1.0),
            PaperModel::Shikki => {
                Aabb::new(DVec3::new(-20.5, -4.5, -13.0), DVec3::new(20.5, 17.5, 13.0))
            }
            PaperModel::Hair => Aabb::new(DVec3::new(-7.0, -6.2, -7.0), DVec3::new(7.0, 10.5, 7.0)),
            PaperModel::SphereMicrostructure => Aabb::new(
                DVec3::new(-1.05, -1.05, -1.05),
                DVec3::new(1.05, 1.05, 0.05),
            ),
        }
    }

    /// Default camera framing the solid like the paper's figures (three-quarter views,
    /// y up; the microstructure sphere is seen from its cut face at `z = 0`).
    pub fn view(self) -> View {
        // (look-at, direction to the eye, radius to frame)
        let (c, d, r) = match self {
            PaperModel::Mitchell => (DVec3::ZERO, DVec3::new(1.0, 0.8, 1.6), 2.0),
            PaperModel::Bretzel => (DVec3::ZERO, DVec3::new(0.25, 0.9, 1.4), 2.05),
            PaperModel::Decocube => (DVec3::ZERO, DVec3::new(1.0, 0.8, 1.6), 1.25),
            PaperModel::Csg => (DVec3::ZERO, DVec3::new(1.0, 0.8, 1.6), 0.95),
            PaperModel::SphereTrimming => (DVec3::ZERO, DVec3::new(0.6, 0.5, 1.6), 1.0),
            PaperModel::SphereNoise => (DVec3::ZERO, DVec3::new(0.7, 0.5, 1.6), 15.0),
            PaperModel::SphereNoisePrinted => {
                (DVec3::new(0.0, 0.5, 0.0), DVec3::new(0.7, 0.5, 1.6), 15.0)
            }
            PaperModel::CsgBlending => (DVec3::ZERO, DVec3::new(1.0, 0.8, 1.6), 1.1),
            PaperModel::CsgBlendingPrinted => (DVec3::ZERO, DVec3::new(1.0, 0.8, 1.6), 1.2),
            PaperModel::Shikki => (DVec3::new(0.0, 4.0, 0.0), DVec3::new(0.35, 0.55, 1.6), 21.0),
            PaperModel::Hair => (DVec3::new(0.0, 2.0, 0.0), DVec3::new(0.8, 0.35, 1.6), 9.0),
            PaperModel::SphereMicrostructure => {
                (DVec3::new(0.0, 0.0, -0.3), DVec3::new(0.6, 0.7, 1.6), 1.05)
            }
        };
        let fov_deg: f64 = 35.0;
        let dist = r / (fov_deg.to_radians() * 0.5).sin() * 1.05;
        View {
            eye: c + d.normalize() * dist,
            look_at: c,
            up: DVec3::Y,
            fov_deg,
            ortho: None,
        }
    }

    /// The model with its domain and default view.
    pub fn model(self) -> Model {
        Model {
            name: self.name().to_string(),
            description: self.description().to_string(),
            // Virtual Shikki as its tape, so that region specialisation applies.
            shape: match (self, shikki_tape()) {
                (PaperModel::Shikki, Some(t)) => AnyShape::Expr(t.clone()),
                _ => AnyShape::Paper(self),
            },
            domain: self.domain(),
            view: self.view(),
            lipschitz: None,
        }
    }
}

impl Shape for PaperModel {
    #[inline]
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        match self {
            PaperModel::Mitchell => mitchell(x, y, z),
            PaperModel::Bretzel => bretzel(x, y, z),
            PaperModel::Decocube => decocube(x, y, z),
            PaperModel::Csg => csg(x, y, z),
            PaperModel::SphereTrimming => sphere_trimming(x, y, z),
            PaperModel::SphereNoise => sphere_noise(x, y, z),
            PaperModel::SphereNoisePrinted => sphere_noise_printed(x, y, z),
            PaperModel::CsgBlending => csg_blending(x, y, z),
            PaperModel::CsgBlendingPrinted => csg_blending_printed(x, y, z),
            PaperModel::Hair => hair(x, y, z),
            PaperModel::SphereMicrostructure => sphere_microstructure(x, y, z),
            PaperModel::Shikki => match shikki_tape() {
                Some(t) => t.eval(x, y, z),
                None => R::constant(-1.0),
            },
        }
    }

    fn packs(&self) -> bool {
        // The scene's conditionals look at their values (see `formula::Tape::packs`).
        !matches!(self, PaperModel::Shikki)
    }
}

/// The HyperFun source of Virtual Shikki, shipped as `data/shikki.hf` of this crate.
pub const SHIKKI_HF: &str = include_str!("../data/shikki.hf");

/// Virtual Shikki compiled once; `None` only if the shipped file did not compile, which
/// a test rules out.
pub fn shikki_tape() -> Option<&'static super::formula::Tape> {
    static TAPE: std::sync::OnceLock<Option<super::formula::Tape>> = std::sync::OnceLock::new();
    TAPE.get_or_init(|| super::hyperfun::parse_hyperfun(SHIKKI_HF).ok())
        .as_ref()
}

/// Mitchell: `f = 20(x^2+y^2+z^2) - 4(x^4+(y^2+z^2)^2) - 17x^2(y^2+z^2) - 17`.
pub fn mitchell<R: Real>(x: R, y: R, z: R) -> R {
    let x2 = x.sqr();
    let yz = y.sqr() + z.sqr();
    (x2.clone() + yz.clone()) * 20.0 - (x2.sqr() + yz.sqr()) * 4.0 - x2 * yz * 17.0 - 17.0
}

/// Bretzel: `f = 2 - 60z^2 - (x^2(1.21-x^2)^2(3.8-x^2)^3 - 10y^2)^2`.
pub fn bretzel<R: Real>(x: R, y: R, z: R) -> R {
    let x2 = x.sqr();
    let a = x2.clone().rsub(1.21).sqr();
    let b = x2.clone().rsub(3.8).powi(3);
    let inner = x2 * a * b - y.sqr() * 10.0;
    (z.sqr() * 60.0).rsub(2.0) - inner.sqr()
}

/// Decocube: `f = 0.02 - ((x^2+y^2-0.82)^2+(z^2-1)^2)((y^2+z^2-0.82)^2+(x^2-1)^2)((x^2+z^2-0.82)^2+(y^2-1)^2)`.
pub fn decocube<R: Real>(x: R, y: R, z: R) -> R {
    let (x2, y2, z2) = (x.sqr(), y.sqr(), z.sqr());
    let p1 = (x2.clone() + y2.clone() - 0.82).sqr() + (z2.clone() - 1.0).sqr();
    let p2 = (y2.clone() + z2.clone() - 0.82).sqr() + (x2.clone() - 1.0).sqr();
    let p3 = (x2 + z2 - 0.82).sqr() + (y2 - 1.0).sqr();
    (p1 * p2 * p3).rsub(0.02)
}

/// `(0.36 - x^2) & (0.36 - y^2) & (0.36 - z^2)`: the box `[-0.6, 0.6]^3` of CSG models.
fn csg_box<R: Real>(x2: &R, y2: &R, z2: &R) -> R {
    intersect(
        intersect(x2.clone().rsub(0.36), y2.clone().rsub(0.36)),
        z2.clone().rsub(0.36),
    )
}

/// CSG: `f = b | (s & ((c1 \ c2) | (c3 \ c4)) \ c5)`, where
/// `b = (0.36-x^2) & (0.36-y^2) & (0.36-z^2)`, `s = 0.7056-x^2-y^2-z^2`,
/// `c1 = 0.09-y^2-z^2`, `c2 = 0.04-y^2-z^2`, `c3 = 0.09-x^2-z^2`, `c4 = 0.04-x^2-z^2`,
/// `c5 = 0.25-x^2-y^2`. `&` and `\` bind equally, left to right: `(s & ...) \ c5`.
pub fn csg<R: Real>(x: R, y: R, z: R) -> R {
    let (x2, y2, z2) = (x.sqr(), y.sqr(), z.sqr());
    let b = csg_box(&x2, &y2, &z2);
    let s = (x2.clone() + y2.clone() + z2.clone()).rsub(0.7056);
    let yz = y2.clone() + z2.clone();
    let xz = x2.clone() + z2;
    let c1 = yz.clone().rsub(0.09);
    let c2 = yz.rsub(0.04);
    let c3 = xz.clone().rsub(0.09);
    let c4 = xz.rsub(0.04);
    let c5 = (x2 + y2).rsub(0.25);
    let tubes = union(subtract(c1, c2), subtract(c3, c4));
    union(b, subtract(intersect(s, tubes), c5))
}

/// CSG with blending in the standard reading: `f = (((c1 vb c2) ^b s) vb b) ^b (-c3)` with
/// `vb` HyperFun's blending union `hfBlendUni` and `^b` its blending intersection
/// `hfBlendInt` (`f1 | f2` or `f1 & f2` plus `a0 / (1 + (f1/a1)^2 + (f2/a2)^2)`), with the
/// printed formula's `a0 = 0.5`, `a1 = a2 = 1`; `b`, `s`, `c1`, `c2`, `c3` as in
/// [`csg_blending_printed`]. Read so, `∨` is a union and `∧` an intersection as in logic
/// (two blended tubes, clipped by the ball, blended onto the box, a vertical hole cut
/// out), and the solid is bounded; the printed text calls the minus form "blending
/// intersection" and writes the displacement inside the square root, which
/// [`csg_blending_printed`] keeps.
pub fn csg_blending<R: Real>(x: R, y: R, z: R) -> R {
    let (x2, y2, z2) = (x.sqr(), y.sqr(), z.sqr());
    let b = csg_box(&x2, &y2, &z2);
    let s = (x2.clone() + y2.clone() + z2.clone()).rsub(0.7056);
    let c1 = (y2.clone() + z2.clone()).rsub(0.09);
    let c2 = (x2.clone() + z2).rsub(0.09);
    let c3 = (x2 + y2).rsub(0.25);
    let (a0, a1, a2) = (0.5, 1.0, 1.0);
    let f = hf_blend_union(c1, c2, a0, a1, a2);
    let f = hf_blend_intersect(f, s, a0, a1, a2);
    let f = hf_blend_union(f, b, a0, a1, a2);
    hf_blend_intersect(f, -c3, a0, a1, a2)
}

/// CSG with blending as printed: `f = (((c1 vb c2) ^b s) vb b) ^b (-c3)`, where `b` and `s` are as in
/// [`csg`], `c1 = 0.09-y^2-z^2`, `c2 = 0.09-x^2-z^2`, `c3 = 0.25-x^2-y^2`, and, as the
/// paper defines them, `f1 vb f2 = f1 + f2 - sqrt(f1^2 + f2^2 + 0.5/(1 + f1^2 + f2^2))`
/// ("blending intersection", [`blend_intersect`]) and `f1 ^b f2` the same with `+`
/// ("blending union", [`blend_union`]).
///
/// Transcribed literally. Note: the blend offset `sqrt(0.5/(1+...)) ~ 0.7` dominates these
/// small fields, so the literal solid also fills most of the domain outside the cylinder
/// `x^2+y^2 <= 0.25`, and swapping the two blends everywhere leaves it empty (we checked
/// all 16 choices of blend per operator on a grid: only intersection, union, union,
/// intersection in order of application is bounded); the domain box clips it, so rays
/// enter the domain inside the solid and the picture shows the boundaries of the holes
/// (the cylinder and the blended voids) rather than a closed object.
pub fn csg_blending_printed<R: Real>(x: R, y: R, z: R) -> R {
    let (x2, y2, z2) = (x.sqr(), y.sqr(), z.sqr());
    let b = csg_box(&x2, &y2, &z2);
    let s = (x2.clone() + y2.clone() + z2.clone()).rsub(0.7056);
    let c1 = (y2.clone() + z2.clone()).rsub(0.09);
    let c2 = (x2.clone() + z2).rsub(0.09);
    let c3 = (x2 + y2).rsub(0.25);
    blend_union(
        blend_intersect(blend_union(blend_intersect(c1, c2), s), b),
        -c3,
    )
}

/// Sphere with noise as the authors' code computes it (HyperFun's Gardner-series noise
/// `hfNoiseG` with amplitude 3.8, frequency 1.5 and phase 1.1, as the public OpenCL
/// transcription of their scenes has it): every factor has its own axis, and each
/// inner sine is phase-shifted by the sine of the previous axis,
///
/// ```text
/// f = 81 - x^2 - y^2 - z^2 + (3.8 sin(1.5x) + 1.624 sin(1.111x + 1.1 sin(1.5z)))
///     * (3.8 sin(1.5y) + 1.299 sin(1.111y + 1.1 sin(1.5x)))
///     * (3.8 sin(1.5z) + 2.598 sin(1.111z + 1.1 sin(1.5y)))
/// ```
///
/// with the printed constants (`1.624 = 0.5 * 3.8/1.17`, `1.111 = 1.5/1.35`, ...). Its
/// operation count is the paper's, 36 / 11 / 5.
pub fn sphere_noise<R: Real>(x: R, y: R, z: R) -> R {
    let sx = (x.clone() * 1.5).sin();
    let sy = (y.clone() * 1.5).sin();
    let sz = (z.clone() * 1.5).sin();
    let fx = sx.clone() * 3.8 + (x.clone() * 1.111 + sz.clone() * 1.1).sin() * 1.624;
    let fy = sy.clone() * 3.8 + (y.clone() * 1.111 + sx * 1.1).sin() * 1.299;
    let fz = sz * 3.8 + (z.clone() * 1.111 + sy * 1.1).sin() * 2.598;
    (x.sqr() + y.sqr() + z.sqr()).rsub(81.0) + fx * fy * fz
}

/// Sphere with noise, transcribed exactly as printed:
/// `f = 81 - x^2 - y^2 - z^2 + (3.8 sin(1.5x) + sin(1.111x + 1.1 sin(1.5x)) * 1.624)
///    * (3.8 sin(1.5y) + sin(1.111x + 1.1 sin(1.5x)) * 1.299)
///    * (3.8 sin(1.5y) + sin(1.111x + 1.1 sin(1.5x)) * 2.598)`.
///
/// The printed noise depends on `x` and `y` only (its render is a cloud of spindles);
/// [`sphere_noise`] is the reading of the authors' code.
pub fn sphere_noise_printed<R: Real>(x: R, y: R, z: R) -> R {
    let sx = (x.clone() * 1.5).sin();
    let sy = (y.clone() * 1.5).sin();
    let w = (x.clone() * 1.111 + sx.clone() * 1.1).sin();
    let f1 = sx * 3.8 + w.clone() * 1.624;
    let f2 = sy.clone() * 3.8 + w.clone() * 1.299;
    let f3 = sy * 3.8 + w * 2.598;
    (x.sqr() + y.sqr() + z.sqr()).rsub(81.0) + f1 * f2 * f3
}

/// Sphere with microstructure. Printed (parentheses unbalanced):
/// `f = (((1-r^2) & ((sin 20y - 0.9) & (sin 20z - 0.9))) | ((sin 20x - 0.9) & (sin 20z - 0.9)))
///      | ((sin 20x - 0.9) & (sin 20y - 0.9))) | ((1-r^2) \ (0.75-r^2))) & (-z)`.
///
/// Our reading, matching Fig. 5a (a sphere shell holding an internal lattice of thin bars,
/// cut in half by `-z`): the three families of bars are united, the union is clipped by
/// the ball, the shell is added, and the whole is cut by `-z`:
/// `f = (((1-r^2) & (Byz | Bxz | Bxy)) | ((1-r^2) \ (0.75-r^2))) & (-z)` with
/// `Byz = (sin 20y - 0.9) & (sin 20z - 0.9)` etc. Reading the printed grouping literally
/// would leave two bar families unbounded, outside the sphere.
pub fn sphere_microstructure<R: Real>(x: R, y: R, z: R) -> R {
    let r2 = x.sqr() + y.sqr() + z.sqr();
    let ball = r2.clone().rsub(1.0);
    let sx = (x * 20.0).sin() - 0.9;
    let sy = (y * 20.0).sin() - 0.9;
    let sz = (z.clone() * 20.0).sin() - 0.9;
    let lattice = union(
        union(intersect(sy.clone(), sz.clone()), intersect(sx.clone(), sz)),
        intersect(sx, sy),
    );
    let shell = subtract(ball.clone(), r2.rsub(0.75));
    intersect(union(intersect(ball, lattice), shell), -z)
}

/// Hair: `f = o | (((1.8 sin(1.8 x k) + sx)(1.8 sin(1.8 y k) + sy)(1.8 sin(1.8 z k) + sz) - 10) & (o + 2) & y)`,
/// where `k = 9 / sqrt(x^2+y^2+z^2)`,
/// `o = (1 - x^2/16 - y^2/36 - z^2/16) | (1 - x^2/1.6129 - (y+2.5)^2/2.25 - (z-3)^2/1.6129)`,
/// `sx = 1.538 sin(1.33 x k) + 1.4 sin(1.8 x k)` (likewise `sy`, `sz`).
pub fn hair<R: Real>(x: R, y: R, z: R) -> R {
    let (x2, y2, z2) = (x.sqr(), y.sqr(), z.sqr());
    let o1 = (x2.clone() * (1.0 / 16.0) + y2.clone() * (1.0 / 36.0) + z2.clone() * (1.0 / 16.0))
        .rsub(1.0);
    let o2 =
        (x2.clone() / 1.6129 + (y.clone() + 2.5).sqr() / 2.25 + (z.clone() - 3.0).sqr() / 1.6129)
            .rsub(1.0);
    let o = union(o1, o2);
    let k = (x2 + y2 + z2).sqrt().rdiv(9.0);
    let factor = |v: &R| {
        let vk = v.clone() * k.clone();
        let s18 = (vk.clone() * 1.8).sin();
        let s = (vk * 1.33).sin() * 1.538 + s18.clone() * 1.4;
        s18 * 1.8 + s
    };
    let pattern = factor(&x) * factor(&y) * factor(&z) - 10.0;
    union(o.clone(), intersect(intersect(pattern, o + 2.0), y))
}

/// Sphere with trimming (our design, in the spirit of \[PP04\] "Trimming implicit surfaces"):
/// a thin spherical shell `(1 - r^2) \ (0.94 - r^2)` (thickness about 0.03) trimmed by the
/// procedural gyroid band `0.3 - |sin 5x cos 5y + sin 5y cos 5z + sin 5z cos 5x|`, which
/// leaves a lattice of thin ribbons on the sphere:
/// `f = ((1 - r^2) \ (0.94 - r^2)) & (0.3 - |g|)`.
pub fn sphere_trimming<R: Real>(x: R, y: R, z: R) -> R {
    let r2 = x.sqr() + y.sqr() + z.sqr();
    let shell = subtract(r2.clone().rsub(1.0), r2.rsub(0.94));
    let (x5, y5, z5) = (x * 5.0, y * 5.0, z * 5.0);
    let g = x5.sin() * y5.cos() + y5.sin() * z5.cos() + z5.sin() * x5.cos();
    intersect(shell, g.abs().rsub(0.3))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_points_have_the_right_sign() {
        // Mitchell: on the x axis the roots are x^2 = (20 ± sqrt(128)) / 8.
        let r = ((20.0 - 128f64.sqrt()) / 8.0).sqrt();
        assert!(mitchell(r, 0.0, 0.0).abs() < 1e-12);
        assert!(mitchell(1.5, 0.0, 0.0) > 0.0 && mitchell(0.0, 0.0, 0.0) < 0.0);
        // Decocube: f(0,0,0) = 0.02 - (0.82^2+1)^3.
        assert!((decocube(0.0, 0.0, 0.0) - (0.02 - (0.82f64.powi(2) + 1.0).powi(3))).abs() < 1e-12);
        // CSG: inside the box, outside far away, hole along z removed from the sphere part.
        assert!(csg(0.5, 0.5, 0.5) > 0.0 && csg(0.0, 0.0, 0.0) > 0.0 && csg(0.9, 0.9, 0.9) < 0.0);
        // Microstructure: the shell at r = 0.95 below z = 0 is solid; above z = 0 nothing.
        assert!(sphere_microstructure(0.0, 0.0, -0.95) > 0.0);
        assert!(sphere_microstructure(0.0, 0.0, 0.5) < 0.0);
        assert!(sphere_trimming(0.0, 0.0, 0.0) < 0.0);
        assert!(sphere_noise(0.0, 0.0, 0.0) > 0.0 && sphere_noise(0.0, 0.0, 16.0) < 0.0);
        assert!(hair(0.1, 0.2, 0.1) > 0.0 && hair(0.0, 0.0, 6.9) < 0.0);
        assert!(bretzel(0.0, 0.0, 0.0) > 0.0 && bretzel(0.0, 0.0, 0.3) < 0.0);
    }

    #[test]
    fn shikki_compiles_and_branches() {
        let t = shikki_tape().expect("data/shikki.hf compiles");
        assert!(t.has_branches() && !PaperModel::Shikki.packs());
        // Inside the table top and the pot's body; outside high above the scene.
        assert!(PaperModel::Shikki.eval(0.0, -0.75, 0.0) > 0.0);
        assert!(PaperModel::Shikki.eval(11.0, 4.5, 0.0) > 0.0);
        assert!(PaperModel::Shikki.eval(0.0, 30.0, 0.0) < 0.0);
    }

    #[test]
    fn every_model_has_a_surface_in_its_domain() {
        // Sample a grid: both signs must occur, so each domain contains a surface.
        for m in PaperModel::ALL {
            let d = m.domain();
            let (mut pos, mut neg) = (false, false);
            let n = 24;
            for i in 0..=n {
                for j in 0..=n {
                    for k in 0..=n {
                        let t = DVec3::new(i as f64, j as f64, k as f64) / n as f64;
                        let p = d.min + (d.max - d.min) * t;
                        let v = m.eval(p.x, p.y, p.z);
                        pos |= v > 0.0;
                        neg |= v < 0.0;
                    }
                }
            }
            assert!(pos && neg, "{}", m.name());
        }
    }
}
