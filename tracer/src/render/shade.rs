//! Shading: normals by central finite differences of the point function, Lambert plus
//! Blinn-Phong with one directional light, and the background colour for misses.

use glam::DVec3;
use model_ir::camera::Camera;
use model_ir::shape::Shape;

/// Colour of pixels whose ray misses the surface.
pub const BACKGROUND: [u8; 3] = [40, 44, 52];

/// One directional light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Unit vector from the surface *towards* the light.
    pub dir: DVec3,
}

impl Light {
    /// A light above, to the left of and behind the viewer, so that the visible side of
    /// a model is lit with some relief.
    pub fn for_camera(cam: &Camera) -> Self {
        Light {
            dir: (-cam.forward + cam.up * 0.8 - cam.right * 0.5).normalize(),
        }
    }
}

/// Surface reflectance, RGB components in `[0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Base colour, RGB in `[0, 1]`.
    pub colour: [f64; 3],
    /// Ambient weight.
    pub ambient: f64,
    /// Diffuse (Lambert) weight.
    pub diffuse: f64,
    /// Specular (Blinn-Phong) weight.
    pub specular: f64,
    /// Specular exponent.
    pub shininess: f64,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            colour: [0.85, 0.62, 0.35],
            ambient: 0.12,
            diffuse: 0.8,
            specular: 0.35,
            shininess: 40.0,
        }
    }
}

/// The outward unit normal at `p`: `-grad f / |grad f|` (FRep: `f >= 0` inside), with
/// the gradient by central differences of step `h`. Where the gradient vanishes or is
/// not finite (a singular point, a tangent double root), returns `None`.
pub fn normal<S: Shape + ?Sized>(shape: &S, p: DVec3, h: f64) -> Option<DVec3> {
    normal_and_sign_change(shape, p, h).0
}

/// The six points `p ± h e_k` where [`normal_and_sign_change`] samples the shape.
#[inline]
pub fn samples(p: DVec3, h: f64) -> [DVec3; 6] {
    [
        p + DVec3::X * h,
        p - DVec3::X * h,
        p + DVec3::Y * h,
        p - DVec3::Y * h,
        p + DVec3::Z * h,
        p - DVec3::Z * h,
    ]
}

/// [`normal`], and whether its six samples `f(p ± h e_k)` hold a sign change (some
/// `<= 0` and some `>= 0`, none NaN): then `f` has a root within `h` of `p` on an axis
/// segment through it, since `f` is continuous.
pub fn normal_and_sign_change<S: Shape + ?Sized>(
    shape: &S,
    p: DVec3,
    h: f64,
) -> (Option<DVec3>, bool) {
    normal_of_samples(&sample_values(shape, p, h))
}

/// The shape's values at the [`samples`] of `p` with step `h`.
#[inline]
pub fn sample_values<S: Shape + ?Sized>(shape: &S, p: DVec3, h: f64) -> [f64; 6] {
    samples(p, h).map(|q| shape.eval::<f64>(q.x, q.y, q.z))
}

/// Buffers for evaluating the [`samples`] of many points in one batch
/// ([`Shape::eval_batch`]: for a tape, each instruction over every sample before the
/// next), reused from one batch to the next.
#[derive(Default)]
pub struct Samples {
    xyz: [Vec<f64>; 3],
    values: Vec<f64>,
}

impl Samples {
    /// The shape's values at the samples of each `(p, h)` of `at` (point, step), in
    /// order: each exactly [`sample_values`] of it.
    pub fn values<'s, S: Shape + ?Sized>(
        &'s mut self,
        shape: &S,
        at: impl IntoIterator<Item = (DVec3, f64)>,
    ) -> impl ExactSizeIterator<Item = [f64; 6]> + 's {
        self.values.clear();
        if shape.tape_len().is_none() {
            // Not a tape: its batch would go point by point anyway, without the staging.
            for (p, h) in at {
                self.values.extend(sample_values(shape, p, h));
            }
        } else {
            for v in &mut self.xyz {
                v.clear();
            }
            for (p, h) in at {
                for q in samples(p, h) {
                    self.xyz[0].push(q.x);
                    self.xyz[1].push(q.y);
                    self.xyz[2].push(q.z);
                }
            }
            let [x, y, z] = &self.xyz;
            shape.eval_batch(x, y, z, &mut self.values);
        }
        self.values
            .chunks_exact(6)
            .map(|c| c.try_into().expect("six samples a point"))
    }
}

/// [`normal_and_sign_change`] from the values at the samples.
pub fn normal_of_samples(s: &[f64; 6]) -> (Option<DVec3>, bool) {
    let g = DVec3::new(s[0] - s[1], s[2] - s[3], s[4] - s[5]);
    let changes =
        s.iter().any(|&v| v <= 0.0) && s.iter().any(|&v| v >= 0.0) && !s.iter().any(|v| v.is_nan());
    let n = -g;
    let l = n.length();
    let n = if l.is_finite() && l > 0.0 {
        Some(n / l)
    } else {
        None
    };
    (n, changes)
}

/// Shades a hit: `normal` the surface normal (either orientation; it is flipped to face
/// the viewer, so thin shells and open sheets are lit on the seen side), `view_dir` the
/// unit ray direction (eye to point), `in_shadow` removes the direct light.
pub fn shade(
    normal: Option<DVec3>,
    view_dir: DVec3,
    light: &Light,
    m: &Material,
    in_shadow: bool,
) -> [u8; 3] {
    let to_eye = -view_dir;
    // No usable normal: light it as if it faced the viewer.
    let mut n = normal.unwrap_or(to_eye);
    if n.dot(to_eye) < 0.0 {
        n = -n;
    }
    let (diff, spec) = if in_shadow {
        (0.0, 0.0)
    } else {
        let diff = n.dot(light.dir).max(0.0);
        let half = (light.dir + to_eye).normalize_or_zero();
        let spec = if diff > 0.0 {
            let c = n.dot(half).max(0.0);
            // powf is a tenth of a render's time on cheap models; integer exponents are
            // the common case.
            if m.shininess.fract() == 0.0 && m.shininess.abs() <= 1024.0 {
                c.powi(m.shininess as i32)
            } else {
                c.powf(m.shininess)
            }
        } else {
            0.0
        };
        (diff, spec)
    };
    let mut out = [0u8; 3];
    for (k, o) in out.iter_mut().enumerate() {
        let c = m.colour[k] * (m.ambient + m.diffuse * diff) + m.specular * spec;
        *o = to_u8(c);
    }
    out
}

/// Gamma-encodes a linear value in `[0, 1]` (clamped) to 8 bits: the first linear value
/// of each 8-bit level, `((k - 0.5) / 255)^2.2`, tabled, and the level found from a
/// second table by one branch-free step: exact, and no `powf` per pixel (a binary search
/// over the 256 levels was 6% of a render). The second table holds the level at the
/// start of each bucket of the value's bits (exponent and top 7 bits of the mantissa,
/// values from 2^-21, below the first level's start, up to 1): a bucket is at most
/// 2^-7 of its values wide, narrower than the levels are apart (at least 0.86% near 1,
/// relatively more below), so at most one level starts inside it (the loop after the
/// step never runs; it is there so that no value could ever get a level too low).
fn to_u8(c: f64) -> u8 {
    /// Bits of the exponent and mantissa kept: the top 7 of the mantissa.
    const SHIFT: u32 = 52 - 7;
    /// Buckets from 2^-21 up to 1.
    const BUCKETS: usize = 21 << 7;
    const BASE: u64 = (1.0f64 / (1u64 << 21) as f64).to_bits() >> SHIFT;
    struct Gamma {
        /// The 256 levels' first values and `+inf` past the last.
        starts: [f64; 257],
        first: [u8; BUCKETS],
    }
    static GAMMA: std::sync::OnceLock<Gamma> = std::sync::OnceLock::new();
    let g = GAMMA.get_or_init(|| {
        let mut levels = [0.0; 256];
        for (k, v) in levels.iter_mut().enumerate().skip(1) {
            *v = ((k as f64 - 0.5) / 255.0).powf(2.2);
        }
        let mut first = [0u8; BUCKETS];
        for (j, f) in first.iter_mut().enumerate() {
            *f = level_by_search(&levels, f64::from_bits((BASE + j as u64) << SHIFT));
        }
        let mut starts = [f64::INFINITY; 257];
        starts[..256].copy_from_slice(&levels);
        Gamma { starts, first }
    });
    // NaN and values at or below 0 are level 0, values at or above 1 level 255.
    if c.is_nan() || c <= 0.0 {
        return 0;
    }
    if c >= 1.0 {
        return 255;
    }
    // Below 2^-21 (a wrapped index): level 0.
    let Some(&k) = g
        .first
        .get(((c.to_bits() >> SHIFT).wrapping_sub(BASE)) as usize)
    else {
        return 0;
    };
    let mut k = k as usize;
    k += usize::from(g.starts[k + 1] <= c);
    while g.starts[k + 1] <= c {
        k += 1;
    }
    k as u8
}

/// The last level whose first value is at or below `c` (binary search).
fn level_by_search(starts: &[f64; 256], c: f64) -> u8 {
    // NaN lands on 0 (`0.0 <= c` holds for every other value).
    (starts.partition_point(|&v| v <= c).max(1) - 1) as u8
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::Real;

    struct Ball;
    impl Shape for Ball {
        fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
            (x.sqr() + y.sqr() + z.sqr()).rsub(1.0)
        }
    }

    #[test]
    fn gamma_table_matches_the_formula() {
        for k in 0..=10_000 {
            let c = k as f64 / 10_000.0;
            let want = (c.powf(1.0 / 2.2) * 255.0 + 0.5) as u8;
            let got = to_u8(c);
            // The table's boundaries are the formula's, up to the rounding of powf.
            assert!(got.abs_diff(want) <= 1, "{c}: {got} vs {want}");
            if got != want {
                let b = ((got.max(want) as f64 - 0.5) / 255.0).powf(2.2);
                assert!((c - b).abs() < 1e-12, "{c}: {got} vs {want}");
            }
        }
        assert_eq!(
            (to_u8(-1.0), to_u8(0.0), to_u8(1.0), to_u8(2.0)),
            (0, 0, 255, 255)
        );
        assert_eq!(to_u8(f64::NAN), 0);
    }

    /// The two-table lookup gives the binary search's level everywhere.
    #[test]
    fn table_lookup_matches_the_search() {
        let mut starts = [0.0; 256];
        for (k, v) in starts.iter_mut().enumerate().skip(1) {
            *v = ((k as f64 - 0.5) / 255.0).powf(2.2);
        }
        let mut cs: Vec<f64> = (0..=200_000).map(|k| k as f64 / 200_000.0).collect();
        // Every level's boundary and its neighbours, the bucket edges, and tiny values.
        for &v in &starts {
            cs.extend([v.next_down(), v, v.next_up()]);
        }
        cs.extend((0..=4096).map(|j| j as f64 / 4096.0));
        // Every bucket's first value and the value before it.
        let base = (1.0f64 / (1u64 << 21) as f64).to_bits() >> 45;
        for j in 0..=(21u64 << 7) {
            let v = f64::from_bits((base + j) << 45);
            cs.extend([v.next_down(), v]);
        }
        cs.extend([1e-300, 5e-324, 1e-7, 0.999_999_999, 1.0f64.next_down()]);
        for c in cs {
            assert_eq!(to_u8(c), level_by_search(&starts, c), "{c:e}");
        }
        // At most one level starts inside a bucket (after its first value): one step
        // always suffices.
        for j in 0..(21u64 << 7) {
            let (lo, hi) = (
                f64::from_bits((base + j) << 45),
                f64::from_bits((base + j + 1) << 45),
            );
            let inside = starts.iter().filter(|&&v| lo < v && v < hi).count();
            assert!(
                inside <= 1,
                "bucket {j}: {inside} levels start in [{lo:e}, {hi:e})"
            );
        }
        assert!(starts[1] > f64::from_bits(base << 45));
    }

    #[test]
    fn sphere_normal_points_outward() {
        let p = DVec3::new(0.6, 0.0, 0.8);
        let n = normal(&Ball, p, 1e-5).unwrap();
        assert!((n - p).length() < 1e-6, "{n:?}");
    }

    #[test]
    fn lit_side_is_brighter_than_shadowed() {
        let light = Light { dir: DVec3::Z };
        let m = Material::default();
        let view = DVec3::new(0.0, 0.0, -1.0);
        let lit = shade(Some(DVec3::Z), view, &light, &m, false);
        let dark = shade(Some(DVec3::Z), view, &light, &m, true);
        assert!(lit.iter().zip(dark.iter()).all(|(a, b)| a > b));
        // A normal facing away is flipped towards the viewer.
        assert_eq!(shade(Some(-DVec3::Z), view, &light, &m, false), lit);
    }
}
