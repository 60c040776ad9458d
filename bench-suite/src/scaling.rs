//! `bench-suite scaling`: how time and range evaluations grow as the resolution doubles,
//! with and without cell culling (Algorithm 2), in one arithmetic.
//!
//! Doubling both sides quadruples the pixels; without culling the ray work should grow
//! about fourfold per step, while the per-ray precision (a fraction of a pixel's
//! footprint) shrinks and adds a few evaluations per hit ray. Culling removes whole cells
//! of empty pixels, so its share grows with resolution.

use crate::table1::{render_once, resolution};
use model_ir::arith::ArithKind;
use model_sources::PaperModel;
use std::fmt::Write as _;
use std::time::Duration;

/// What to run.
#[derive(Clone, Debug)]
pub struct Options {
    /// Models to run.
    pub models: Vec<PaperModel>,
    /// The arithmetic.
    pub kind: ArithKind,
    /// Scale of the first step (fraction of the paper's resolution per axis).
    pub base_scale: f64,
    /// Number of resolutions.
    pub steps: usize,
    /// Time budget per render.
    pub budget: Duration,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            models: vec![PaperModel::Mitchell, PaperModel::SphereNoise],
            kind: ArithKind::Revaa,
            base_scale: 0.0625,
            steps: 4,
            budget: Duration::from_secs(60),
        }
    }
}

/// One measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// The model.
    pub model: PaperModel,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Whether cell culling was on.
    pub culling: bool,
    /// Wall time of the render.
    pub seconds: f64,
    /// Whether the time budget stopped it.
    pub stopped: bool,
    /// Range evaluations on rays.
    pub ray_evals: u64,
    /// Range evaluations on cells.
    pub cell_evals: u64,
    /// Pixels that hit the surface.
    pub hits: u64,
}

/// Runs every step; errors on bad options or a failed render.
pub fn measure(o: &Options) -> Result<Vec<Point>, String> {
    if !(o.base_scale > 0.0 && o.base_scale <= 16.0) {
        return Err(format!("--base-scale {} must be in (0, 16]", o.base_scale));
    }
    if o.steps == 0 || o.steps > 8 {
        return Err(format!("--steps {} must be in 1..=8", o.steps));
    }
    let mut out = Vec::new();
    for &m in &o.models {
        for step in 0..o.steps {
            let (w, h) = resolution(m, false, o.base_scale * (1u32 << step) as f64);
            for culling in [false, true] {
                let r = render_once(m, o.kind, (w, h), o.budget, culling)?;
                out.push(Point {
                    model: m,
                    width: w,
                    height: h,
                    culling,
                    seconds: r.stats.wall.as_secs_f64(),
                    stopped: r.stats.cut,
                    ray_evals: r.stats.range_evals,
                    cell_evals: r.stats.cell_evals,
                    hits: r.stats.hits,
                });
            }
        }
    }
    Ok(out)
}

/// The measurements as Markdown.
pub fn markdown(o: &Options, pts: &[Point]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "## Scaling with resolution ({}, argument pruning on, primary rays)\n\n\
         Each step doubles both sides (4x the pixels). `x prev`: time relative to the previous \
         step with the same culling setting.\n",
        o.kind.label()
    );
    s.push_str(
        "| Model | Resolution | Culling | Seconds | x prev | Ray evals | Cell evals | Evals / pixel | us / pixel |\n\
         |---|---|---|---:|---:|---:|---:|---:|---:|\n",
    );
    for (i, p) in pts.iter().enumerate() {
        let prev = pts[..i]
            .iter()
            .rev()
            .find(|q| q.model == p.model && q.culling == p.culling);
        let ratio = prev.map_or(String::from("-"), |q| {
            format!("{:.2}", p.seconds / q.seconds.max(1e-9))
        });
        let px = p.width as f64 * p.height as f64;
        let _ = writeln!(
            s,
            "| {} | {}x{} | {} | {:.3}{} | {} | {} | {} | {:.1} | {:.2} |",
            p.model.name(),
            p.width,
            p.height,
            if p.culling { "on" } else { "off" },
            p.seconds,
            if p.stopped { " (stopped)" } else { "" },
            ratio,
            p.ray_evals,
            p.cell_evals,
            (p.ray_evals + p.cell_evals) as f64 / px,
            p.seconds * 1e6 / px
        );
    }
    s
}
