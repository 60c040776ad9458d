//! One 3-D render with fidget's own pipeline: the `.vm` text read by
//! `Context::from_text`, compiled by the JIT, rasterised by `fidget::raster::voxel`
//! with the frame of fidget's CLI demo (`render3d --isometric`), then shaded with
//! fidget's normal denoising and shading effects.
//!
//! The frame: identity rotation, no perspective, world `[-1, 1]^3` seen along `-z`
//! with `+y` up, the model scaled by `1/scale` as the demo's `--scale` does. Voxel
//! `(i, j, k)` of an `N^3` render samples world `x = -1 + 2i/N`, `y = 1 - 2(j+1)/N`,
//! `z = -1 + 2k/N` (fidget's `VoxelSize::screen_to_world`), and a pixel is a hit when
//! some voxel of its column has `f < 0` (or an interval proves the column's tile
//! inside).

use fidget::context::Context;
use fidget::jit::JitShape;
use fidget::raster::{effects, voxel};
use fidget::render::{ThreadPool, VoxelSize};
use fidget::shape::BoundShape;
use std::time::{Duration, Instant};

/// What one render produced.
pub struct Rendered {
    /// Shaded image, RGB, row-major from the top row; background black.
    pub rgb: Vec<u8>,
    /// 1 where fidget reports a surface (depth above 0), row-major.
    pub mask: Vec<u8>,
    /// Per pixel, the distance in model units from the view box's front face (model
    /// `z = 1/scale`) to the surface, taken halfway between the last outside and the
    /// first inside voxel of the column; `+inf` on a miss. Row-major.
    pub depth: Vec<f32>,
    /// Time to build the JIT shape.
    pub jit: Duration,
    /// Time of `voxel::render` alone.
    pub render: Duration,
    /// Time of denoising and shading.
    pub shade: Duration,
}

/// Renders the `.vm` tape `text` at `size x size` pixels (and `size` voxels deep),
/// the model scaled by `1/scale` (fidget's `--scale`).
pub fn render(text: &str, size: u32, scale: f32) -> Result<Rendered, String> {
    let (ctx, root) = Context::from_text(text.as_bytes()).map_err(|e| format!("{e}"))?;
    let t = Instant::now();
    let shape = JitShape::new(&ctx, root).map_err(|e| format!("JIT: {e}"))?;
    let jit = t.elapsed();
    let shape = BoundShape::try_from(shape).map_err(|e| format!("variables: {e}"))?;

    let s = 1.0 / scale;
    let cfg = voxel::RenderConfig {
        image_size: VoxelSize::from(size),
        world_to_model: nalgebra::Scale3::new(s, s, s).to_homogeneous(),
    };
    let t = Instant::now();
    let image =
        voxel::render(shape, &cfg, &voxel::EvalConfig::default()).ok_or("render was cancelled")?;
    let render = t.elapsed();

    let t = Instant::now();
    let threads = Some(&ThreadPool::Global);
    let denoised = effects::denoise_normals(&image, threads);
    let color = effects::apply_shading(&denoised, false, threads);
    let shade = t.elapsed();

    let mask: Vec<u8> = image.iter().map(|p| u8::from(p.depth > 0)).collect();
    let n = size as f32;
    let depth = image
        .iter()
        .map(|p| match p.depth {
            0 => f32::INFINITY,
            // Voxel k = depth - 1 is inside; its sample is at world z = -1 + 2k/N.
            d => (2.0 - (2 * d - 1) as f32 / n) / scale,
        })
        .collect();
    let rgb = color
        .iter()
        .zip(&mask)
        .flat_map(|(c, &m)| if m == 1 { *c } else { [0; 3] })
        .collect();
    Ok(Rendered {
        rgb,
        mask,
        depth,
        jit,
        render,
        shade,
    })
}

#[cfg(test)]
mod tests {
    use super::render;

    /// A sphere of radius 0.5 centred at the origin (fidget's sign: negative inside).
    const SPHERE: &str = "_x var-x\n_y var-y\n_z var-z\n_a square _x\n_b square _y\n\
                          _c square _z\n_s add _a _b\n_t add _s _c\n_r const 0.25\n\
                          _o sub _t _r\n";

    #[test]
    fn sphere_covers_its_disc_and_scale_shrinks_it() {
        let n = 64u32;
        let r = render(SPHERE, n, 1.0).unwrap();
        let hits = r.mask.iter().filter(|&&m| m == 1).count() as f64;
        // The disc of radius 0.5 covers pi/16 of the [-1, 1]^2 view.
        let want = std::f64::consts::PI / 16.0 * f64::from(n * n);
        assert!((hits - want).abs() < 0.05 * want, "{hits} vs {want}");
        // Centre pixel hit, corner pixel missed.
        let c = (n / 2 * n + n / 2) as usize;
        assert_eq!((r.mask[c], r.mask[0]), (1, 0));
        // Half the scale: a quarter of the area.
        let half = render(SPHERE, n, 0.5).unwrap();
        let h = half.mask.iter().filter(|&&m| m == 1).count() as f64;
        assert!((h - want / 4.0).abs() < 0.1 * want / 4.0, "{h}");
        // The sphere's front at the centre is 0.5 behind the face z = 1, within a voxel.
        assert!((r.depth[c] - 0.5).abs() <= 2.0 / n as f32, "{}", r.depth[c]);
        assert_eq!(r.depth[0], f32::INFINITY);
    }

    #[test]
    fn every_bundled_model_reads_and_shows_a_surface() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
        let mut seen = 0;
        for e in std::fs::read_dir(&dir).unwrap() {
            let path = e.unwrap().path();
            if path.extension().and_then(|x| x.to_str()) != Some("vm") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            crate::vm_check::check(&text).unwrap();
            let r = render(&text, 32, 1.0).unwrap();
            let hits = r.mask.iter().filter(|&&m| m == 1).count();
            assert!(hits > 0, "{}: no surface", path.display());
            seen += 1;
        }
        assert!(seen >= 3, "{seen} models in {}", dir.display());
    }

    #[test]
    fn a_miss_is_black() {
        let r = render(SPHERE, 32, 1.0).unwrap();
        assert_eq!(&r.rgb[..3], &[0, 0, 0]);
        assert_eq!(r.rgb.len(), 32 * 32 * 3);
    }
}
