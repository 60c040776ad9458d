//! The progressive-refinement paper's models (Gamito and Maddock 2007, Section 4).
//!
//! FRep sign convention throughout: `f >= 0` inside. The paper writes Mitchell's surface
//! (eq. 9), the blobby model (eq. 10) and the hypertextures (eqs. 11, 12) with the
//! opposite sign (negative inside); here each is negated.
use super::{AnyShape, Model};
use crate::noise::{eval_field, Cellular, Field3, Perlin, SparseConvolution, SplitMix64};
use arith_core::{Known, Real};
use glam::DVec3;
use model_ir::gradient_bound::auto_lipschitz;
use model_ir::shape::{Aabb, Shape, View};
use std::sync::OnceLock;

/// A model of the progressive-refinement paper.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GmModel {
    /// Mitchell's quartic (eq. 9), negated.
    Mitchell,
    /// 60 compactly supported radial basis functions with the outside modification.
    Blobby,
    /// The hypertextured sphere with `L` noise layers (eq. 12; `L = 1` is eq. 11).
    Hypertexture(u8),
    /// A landscape of gradient, sparse convolution and cellular noise.
    Landscape,
}

/// Seed of the blobby model's basis functions.
pub const BLOBBY_SEED: u64 = 0x5EED_B10B;
/// Number of basis functions of the blobby model (as in the paper).
pub const BLOBS: usize = 60;
/// Seed of the hypertexture's and the landscape's gradient noise permutation.
pub const NOISE_SEED: u64 = 2002;

/// One compactly supported basis function `s p(|x - c| / R)`.
#[derive(Clone, Copy, Debug)]
pub struct Blob {
    /// Centre of the support sphere.
    pub centre: DVec3,
    /// Radius of the support sphere.
    pub radius: f64,
    /// Weight `s` of the basis function.
    pub strength: f64,
}

/// The blobby model's 60 basis functions, generated from [`BLOBBY_SEED`] (the paper's
/// Dali figure data is not public): centres along a loose figure-like column.
pub fn blobs() -> &'static [Blob] {
    static B: OnceLock<Vec<Blob>> = OnceLock::new();
    B.get_or_init(|| {
        let mut rng = SplitMix64(BLOBBY_SEED);
        (0..BLOBS)
            .map(|i| {
                let h = -1.2 + 2.4 * (i as f64 + rng.next_f64()) / BLOBS as f64;
                let w = 0.55 * (1.0 - 0.4 * (h * 1.3).sin().abs());
                let centre = DVec3::new(rng.range(-w, w), h, rng.range(-0.35, 0.35));
                Blob {
                    centre,
                    radius: rng.range(0.3, 0.55),
                    strength: rng.range(0.6, 1.0),
                }
            })
            .collect()
    })
}

/// The blobby function at a point, the same formula as the generic one with the work
/// skipped where a basis function cannot contribute (the paper's clipping against the
/// support spheres): outside a support its term is 0, and the distance term is 0 as soon
/// as one support contains the point.
fn blobby_point(p: DVec3) -> f64 {
    let mut sum = -0.5;
    let mut inside = false;
    let mut outside = f64::INFINITY;
    for b in blobs() {
        let q = (p - b.centre).length_squared();
        let r2 = b.radius * b.radius;
        if q < r2 {
            let u = q * (-1.0 / r2) + 1.0;
            sum += u * u * u * b.strength;
            inside = true;
        } else if !inside {
            outside = outside.min(q.sqrt() - b.radius);
        }
    }
    if inside {
        sum
    } else {
        sum - outside
    }
}

/// Over a box of inputs (known ranges, or `Dual` numbers over intervals), the basis
/// functions that can matter there: those whose support meets the box (the others add
/// exactly 0), plus those whose distance term may be the minimum (a blob whose distance
/// over the box is surely above another's largest cannot be the minimum anywhere in it).
/// Dropping the rest changes no value, only the work (the paper's clipping of cones
/// against the supports, and its "localised" evaluation). `None` for points and
/// unknown types (keep all).
fn relevant_blobs<R: Real>(x: &R, y: &R, z: &R) -> Option<Vec<bool>> {
    use arith_core::dual::Dual;
    use std::any::Any;
    let bounds = |v: &R| match v.known() {
        Known::Range(lo, hi) => Some((lo, hi)),
        _ => (v as &dyn Any)
            .downcast_ref::<Dual<arith_ia::Interval>>()
            .map(|d| (d.v.lo, d.v.hi)),
    };
    let (bx, by, bz) = (bounds(x)?, bounds(y)?, bounds(z)?);
    let lo = DVec3::new(bx.0, by.0, bz.0);
    let hi = DVec3::new(bx.1, by.1, bz.1);
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    // Nearest and farthest distances from each centre to the box, with a relative margin
    // for rounding (the decisions only need to be conservative).
    let near_far = |c: DVec3| {
        let near = (lo - c).max(c - hi).max(DVec3::ZERO).length();
        let far = (c - lo).abs().max((hi - c).abs()).length();
        (near * (1.0 - 1e-9), far * (1.0 + 1e-9))
    };
    let bl = blobs();
    let nf: Vec<(f64, f64)> = bl.iter().map(|b| near_far(b.centre)).collect();
    let u = bl
        .iter()
        .zip(&nf)
        .map(|(b, (_, far))| (far - b.radius).max(0.0))
        .fold(f64::INFINITY, f64::min);
    Some(
        bl.iter()
            .zip(&nf)
            .map(|(b, (near, _))| *near < b.radius * (1.0 + 1e-9) || near - b.radius <= u)
            .collect(),
    )
}

fn perlin() -> &'static Perlin {
    static P: OnceLock<Perlin> = OnceLock::new();
    P.get_or_init(|| Perlin::new(NOISE_SEED))
}
fn sparse() -> &'static SparseConvolution {
    static S: OnceLock<SparseConvolution> = OnceLock::new();
    S.get_or_init(|| SparseConvolution::new(NOISE_SEED + 1))
}
fn cellular() -> &'static Cellular {
    static C: OnceLock<Cellular> = OnceLock::new();
    C.get_or_init(|| Cellular::new(NOISE_SEED + 2))
}

/// Layers of the hypertexture allowed on the command line.
pub const MAX_LAYERS: u8 = 5;
/// The layer weights `2^(-0.8 i)` and frequencies `2^(i+2)` of eq. 12.
fn layer(i: u8) -> (f64, f64) {
    (2f64.powf(-0.8 * i as f64), 2f64.powi(i as i32 + 2))
}

/// Landscape terms: (amplitude, frequency, y-offset of the 2-D slice) for gradient,
/// sparse convolution and cellular noise.
const LAND_PERLIN: (f64, f64, f64) = (0.5, 0.8, 0.37);
const LAND_SPARSE: (f64, f64, f64) = (0.04, 1.5, 0.5);
const LAND_CELL: (f64, f64, f64) = (0.35, 0.7, 0.21);
/// Base level of the landscape.
const LAND_BASE: f64 = -0.45;

fn noise_at<F: Field3, R: Real>(f: &F, x: &R, z: &R, (a, s, y0): (f64, f64, f64)) -> R {
    let y = R::constant(y0);
    eval_field(f, &(x.clone() * s), &y, &(z.clone() * s)) * a
}

impl Shape for GmModel {
    /// The noise and blob models look at their arguments' types (points, known ranges,
    /// duals); Mitchell's quartic is plain arithmetic.
    fn packs(&self) -> bool {
        matches!(self, GmModel::Mitchell)
    }

    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        match *self {
            GmModel::Mitchell => {
                let (x2, y2, z2) = (x.sqr(), y.sqr(), z.sqr());
                let yz = y2 + z2;
                let quartic = (x2.sqr() + yz.sqr()) * 4.0 + x2.clone() * yz.clone() * 17.0
                    - (x2 + yz) * 20.0
                    + 17.0;
                -quartic
            }
            GmModel::Blobby => {
                if let (Known::Point(px), Known::Point(py), Known::Point(pz)) =
                    (x.known(), y.known(), z.known())
                {
                    return R::constant(blobby_point(DVec3::new(px, py, pz)));
                }
                let mut sum = R::constant(-0.5);
                let mut outside: Option<R> = None;
                let relevant = relevant_blobs(&x, &y, &z);
                for b in blobs()
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| relevant.as_ref().is_none_or(|r| r[*i]))
                    .map(|(_, b)| b)
                {
                    let q = (x.clone() - b.centre.x).sqr()
                        + (y.clone() - b.centre.y).sqr()
                        + (z.clone() - b.centre.z).sqr();
                    let r2 = b.radius * b.radius;
                    // p(r) = (1 - r^2)^3 on [0, 1], 0 beyond: p(0) = 1, p(1) = 0.
                    let u = (q.clone() * (-1.0 / r2) + 1.0).max(&R::constant(0.0));
                    sum = sum + u.powi(3) * b.strength;
                    // Distance outside this support (0 inside it).
                    let d = q.max(&R::constant(r2)).sqrt() - b.radius;
                    outside = Some(match outside {
                        None => d,
                        Some(o) => o.min(&d),
                    });
                }
                // The paper's outside modification: where no support reaches, the value
                // falls off with the distance to the nearest support (continuous at its
                // boundary, where both terms give -0.5).
                sum - outside.unwrap_or_else(|| R::constant(0.0))
            }
            GmModel::Hypertexture(l) => {
                let r = (x.clone().sqr() + y.clone().sqr() + z.clone().sqr()).sqrt();
                let mut f = r.rsub(1.0);
                for i in 0..l {
                    let (w, s) = layer(i);
                    let n = eval_field(
                        perlin(),
                        &(x.clone() * s),
                        &(y.clone() * s),
                        &(z.clone() * s),
                    );
                    f = f - n * (0.8 * w);
                }
                f
            }
            GmModel::Landscape => {
                let h = noise_at(perlin(), &x, &z, LAND_PERLIN)
                    + noise_at(sparse(), &x, &z, LAND_SPARSE)
                    + noise_at(cellular(), &x, &z, LAND_CELL)
                    + LAND_BASE;
                h - y
            }
        }
    }
}

impl GmModel {
    /// A derived Lipschitz bound over the model's domain.
    ///
    /// - Hypertexture: `|grad (1 - |x|)| = 1`, and layer `i` adds `0.8 · 2^(-0.8 i) ·
    ///   2^(i+2) · L_n` with `L_n` = [`Perlin::LIPSCHITZ`].
    /// - Landscape `f = h(x, z) - y`: `|grad f| = sqrt(1 + |grad h|^2) <= 1 + |grad h|`,
    ///   `|grad h| <= sum a_k s_k L_k` (a 2-D slice of a 3-D field is no steeper).
    /// - Mitchell, blobby: [`auto_lipschitz`] (the gradient enclosed over `16^3` sub-boxes
    ///   with `Dual<Interval>`).
    pub fn lipschitz(&self) -> f64 {
        match *self {
            GmModel::Hypertexture(l) => {
                1.0 + (0..l)
                    .map(|i| 0.8 * layer(i).0 * layer(i).1 * Perlin::LIPSCHITZ)
                    .sum::<f64>()
                    * (1.0 + 1e-12)
            }
            GmModel::Landscape => {
                let t = |(a, s, _): (f64, f64, f64), l: f64| a * s * l;
                let gh = t(LAND_PERLIN, Perlin::LIPSCHITZ)
                    + t(LAND_SPARSE, sparse().lipschitz())
                    + t(LAND_CELL, 1.0);
                (1.0 + gh) * (1.0 + 1e-12)
            }
            GmModel::Mitchell | GmModel::Blobby => {
                static M: OnceLock<f64> = OnceLock::new();
                static B: OnceLock<f64> = OnceLock::new();
                let cell = if *self == GmModel::Mitchell { &M } else { &B };
                *cell.get_or_init(|| auto_lipschitz(self, &self.domain(), 16))
            }
        }
    }

    /// The box the surface lies in.
    pub fn domain(&self) -> Aabb {
        match *self {
            GmModel::Mitchell => Aabb::cube(2.0),
            GmModel::Blobby => {
                let mut lo = DVec3::splat(f64::INFINITY);
                let mut hi = DVec3::splat(f64::NEG_INFINITY);
                for b in blobs() {
                    lo = lo.min(b.centre - DVec3::splat(b.radius));
                    hi = hi.max(b.centre + DVec3::splat(b.radius));
                }
                Aabb::new(lo - DVec3::splat(0.05), hi + DVec3::splat(0.05))
            }
            GmModel::Hypertexture(l) => {
                // |n| <= 1.5, so the surface lies where | |x| - 1 | <= 0.8 · 1.5 · sum w_i.
                let amp: f64 = (0..l).map(|i| layer(i).0).sum::<f64>() * 0.8 * Perlin::BOUND;
                Aabb::cube(1.0 + amp + 0.01)
            }
            GmModel::Landscape => {
                Aabb::new(DVec3::new(-4.0, -2.2, -4.0), DVec3::new(4.0, 2.2, 4.0))
            }
        }
    }

    fn view(&self) -> View {
        match *self {
            GmModel::Mitchell => View {
                eye: DVec3::new(4.5, 3.0, 5.5),
                look_at: DVec3::ZERO,
                up: DVec3::Y,
                fov_deg: 36.0,
                ortho: None,
            },
            GmModel::Blobby => View {
                eye: DVec3::new(1.2, 0.6, 5.5),
                look_at: DVec3::ZERO,
                up: DVec3::Y,
                fov_deg: 40.0,
                ortho: None,
            },
            GmModel::Hypertexture(_) => View {
                eye: DVec3::new(0.0, 0.8, 5.6),
                look_at: DVec3::ZERO,
                up: DVec3::Y,
                fov_deg: 40.0,
                ortho: None,
            },
            GmModel::Landscape => View {
                eye: DVec3::new(0.0, 1.6, 3.9),
                look_at: DVec3::new(0.0, -0.4, 0.0),
                up: DVec3::Y,
                fov_deg: 60.0,
                ortho: None,
            },
        }
    }

    /// Command-line name (`mitchell-gm`, `blobby`, `hypertexture-3`, ...).
    pub fn name(&self) -> String {
        match *self {
            GmModel::Mitchell => "mitchell-gm".into(),
            GmModel::Blobby => "blobby".into(),
            GmModel::Hypertexture(l) => format!("hypertexture-{l}"),
            GmModel::Landscape => "landscape".into(),
        }
    }

    fn description(&self) -> String {
        match *self {
            GmModel::Mitchell => "-(4(x^4+(y^2+z^2)^2) + 17x^2(y^2+z^2) - 20(x^2+y^2+z^2) + 17) on [-2,2]^3 (Gamito-Maddock eq. 9, negated)".into(),
            GmModel::Blobby => format!("sum of {BLOBS} compact RBFs - 0.5, outside modification (eq. 10, negated; seed {BLOBBY_SEED:#x})"),
            GmModel::Hypertexture(1) => "1 - |x| - 0.8 n(4x), Perlin improved noise (eq. 11, negated)".into(),
            GmModel::Hypertexture(l) => format!("1 - |x| - 0.8 sum_(i<{l}) 2^(-0.8i) n(2^(i+2) x) (eq. 12, negated)"),
            GmModel::Landscape => "h(x,z) - y, h of gradient, sparse convolution and cellular noise".into(),
        }
    }

    /// The function in the formula language of `--expr` (see [`super::formula`]), where
    /// it has one (the noise models have none: noise is not in the language), written to
    /// evaluate in the same order as the generic Rust code.
    pub fn formula(&self) -> Option<String> {
        match *self {
            GmModel::Mitchell => Some(
                "x2 = x^2; yz = y^2 + z^2; \
                 -((x2^2 + yz^2) * 4 + x2 * yz * 17 - (x2 + yz) * 20 + 17)"
                    .into(),
            ),
            GmModel::Blobby => Some(blobby_formula()),
            GmModel::Hypertexture(_) | GmModel::Landscape => None,
        }
    }

    /// This model as a [`Model`].
    pub fn model(self) -> Model {
        Model {
            name: self.name(),
            description: self.description(),
            shape: AnyShape::Gm(self),
            domain: self.domain(),
            view: self.view(),
            lipschitz: Some(self.lipschitz()),
        }
    }

    /// Every model, in the paper's order.
    pub fn all() -> Vec<GmModel> {
        let mut v = vec![GmModel::Mitchell, GmModel::Blobby];
        v.extend((1..=MAX_LAYERS).map(GmModel::Hypertexture));
        v.push(GmModel::Landscape);
        v
    }
}

/// The blobby function as a formula: per blob `q = |p - c|^2`, the sum of
/// `max(1 - q / R^2, 0)^3 s` from -0.5, minus the least `sqrt(max(q, R^2)) - R`.
fn blobby_formula() -> String {
    // Shortest text that reads back as the same double (negative ones parenthesised).
    let lit = |c: f64| {
        if c.is_sign_negative() {
            format!("(-{:?})", -c)
        } else {
            format!("{c:?}")
        }
    };
    let mut f = String::new();
    for (i, b) in blobs().iter().enumerate() {
        let r2 = b.radius * b.radius;
        let c = b.centre;
        f.push_str(&format!(
            "q{i} = (x - {})^2 + (y - {})^2 + (z - {})^2;\n",
            lit(c.x),
            lit(c.y),
            lit(c.z)
        ));
        let term = format!(
            "max(q{i} * {} + 1, 0)^3 * {}",
            lit(-1.0 / r2),
            lit(b.strength)
        );
        let dist = format!("sqrt(max(q{i}, {})) - {}", lit(r2), lit(b.radius));
        if i == 0 {
            f.push_str(&format!("s0 = -0.5 + {term};\no0 = {dist};\n"));
        } else {
            f.push_str(&format!(
                "s{i} = s{} + {term};\no{i} = min(o{}, {dist});\n",
                i - 1,
                i - 1
            ));
        }
    }
    let n = blobs().len() - 1;
    f.push_str(&format!("s{n} - o{n}"));
    f
}

/// The progressive-refinement paper's models, with domains, views and Lipschitz bounds.
pub fn all() -> Vec<Model> {
    GmModel::all().into_iter().map(GmModel::model).collect()
}
