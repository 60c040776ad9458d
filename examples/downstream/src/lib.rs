//! A downstream user of `tracer` with no other dependency and without the `cli` feature:
//! a shape written once, its range in every arithmetic of the one list through
//! `tracer::with_arith!`, and a small render. It exists to prove that the exported
//! macros and re-exports compile outside the workspace's own crates.

#![forbid(unsafe_code)]

use tracer::arith::ArithKind;
use tracer::arith_core::{Arithmetic, Range, Real};
use tracer::glam::DVec3;
use tracer::render::{render_kind, RenderOptions};
use tracer::shape::{Aabb, Shape, View};

/// The unit ball, `1 - x^2 - y^2 - z^2 >= 0` inside.
pub struct Ball;

impl Shape for Ball {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        (x.sqr() + y.sqr() + z.sqr()).rsub(1.0)
    }
}

/// The range of [`Ball`] over `b` in arithmetic `kind`.
pub fn ball_range(kind: ArithKind, b: &Aabb) -> (f64, f64) {
    fn over<A: Arithmetic>(b: &Aabb) -> (f64, f64) {
        let x = <A::Cell as Range>::input(0, b.min.x, b.max.x);
        let y = <A::Cell as Range>::input(1, b.min.y, b.max.y);
        let z = <A::Cell as Range>::input(2, b.min.z, b.max.z);
        Ball.eval(x, y, z).bounds()
    }
    tracer::with_arith!(kind, A => over::<A>(b))
}

/// How many pixels of a `w x h` render of [`Ball`] hit it, in arithmetic `kind`.
pub fn ball_hits(kind: ArithKind, w: u32, h: u32) -> Result<usize, String> {
    let view = View {
        eye: DVec3::new(0.0, 0.0, 4.0),
        look_at: DVec3::ZERO,
        up: DVec3::Y,
        fov_deg: 40.0,
        ortho: None,
    };
    let opts = RenderOptions::for_view(view, Aabb::cube(1.5), w, h);
    let res = render_kind(kind, &Ball, &opts)?;
    Ok(res.depth.iter().filter(|d| d.is_finite()).count())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_arithmetic_encloses_the_ball_and_renders_it() {
        let b = Aabb::new(DVec3::new(0.5, -0.1, 0.0), DVec3::new(0.6, 0.1, 0.2));
        let hits: Vec<usize> = ArithKind::ALL
            .into_iter()
            .map(|k| {
                let (lo, hi) = ball_range(k, &b);
                // The exact range is [1 - 0.36 - 0.01 - 0.04, 1 - 0.25] = [0.59, 0.75].
                assert!(lo <= 0.59 && 0.75 <= hi, "{k}: [{lo}, {hi}]");
                ball_hits(k, 24, 24).unwrap()
            })
            .collect();
        assert!(hits[0] > 100, "{hits:?}");
        assert!(hits.iter().all(|&h| h == hits[0]), "{hits:?}");
    }
}
