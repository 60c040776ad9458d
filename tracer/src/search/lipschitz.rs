//! Lipschitz ray casting: Hart's sphere tracing, its overshooting variant and the
//! local-bound caster (bounds over each segment from [`Dual`]`<Interval>`).
//!
//! A Lipschitz bound `λ` of `f` over a convex domain guarantees that the ball of radius
//! `|f(x)| / λ` around `x` holds no root of `f` inside the domain: for `y` in both,
//! `|f(y)| >= |f(x)| - λ |x - y| > 0`.

use arith_core::dual::Dual;
use arith_core::round::up;
use arith_core::{Range, Real};
use glam::DVec3;
use model_ir::shape::{Aabb, Shape};

/// The default overshooting factor (the paper's "46%", after Worley and Hart).
pub const DEFAULT_OVERSHOOT: f64 = 1.46;

/// The parameter interval `[t0, t1]` where the ray `o + t d` (`t >= 0`) is inside `b`.
/// Not widened like [`crate::search::ray::clip`]: that would move every Lipschitz sample.
pub fn clip_to_box(o: DVec3, d: DVec3, b: &Aabb) -> Option<(f64, f64)> {
    let mut t0 = 0.0f64;
    let mut t1 = f64::INFINITY;
    for k in 0..3 {
        let (lo, hi, ok, dk) = (b.min[k], b.max[k], o[k], d[k]);
        if dk == 0.0 {
            if ok < lo || ok > hi {
                return None;
            }
        } else {
            let (a, c) = ((lo - ok) / dk, (hi - ok) / dk);
            let (a, c) = if a < c { (a, c) } else { (c, a) };
            t0 = t0.max(a);
            t1 = t1.min(c);
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// Euclidean distance from `p` to the box (0 inside).
pub fn box_distance(p: DVec3, b: &Aabb) -> f64 {
    (b.min - p).max(p - b.max).max(DVec3::ZERO).length()
}

/// The closest point of the box to `p`.
pub fn box_project(p: DVec3, b: &Aabb) -> DVec3 {
    p.clamp(b.min, b.max)
}

/// A shape restricted to its domain box with a Lipschitz bound: the unbounding radius
/// used by every Lipschitz tracer, counting point evaluations.
pub struct Bounded<'a, S: Shape + ?Sized> {
    /// The function.
    pub shape: &'a S,
    /// Where the function is considered: outside it there is no surface.
    pub domain: Aabb,
    /// A Lipschitz bound of the function over `domain`.
    pub lambda: f64,
}

impl<S: Shape + ?Sized> Bounded<'_, S> {
    /// A radius around `c` holding no surface point of the domain:
    /// `max(dist(c, box), |f(P c)| / λ)` with `P` the projection onto the box.
    ///
    /// Points nearer than `dist(c, box)` are outside the domain. For `y` in the box,
    /// `|y - P c| <= |y - c|` (projection onto a convex set is non-expansive and fixes
    /// `y`), so `|y - c| < |f(P c)|/λ` puts `y` in the unbounding ball of `P c`.
    #[inline]
    pub fn radius(&self, c: DVec3, evals: &mut u64) -> f64 {
        *evals += 1;
        let q = box_project(c, &self.domain);
        let f = self.shape.eval(q.x, q.y, q.z);
        let r = if f.is_nan() {
            0.0
        } else {
            f.abs() / self.lambda
        };
        r.max(box_distance(c, &self.domain))
    }
}

/// Result of a ray cast.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cast {
    /// Parameter of the hit (`|f| / λ < eps` there, no root before it), `None` on a miss.
    pub t: Option<f64>,
    /// Point evaluations of `f`.
    pub evals: u64,
}

/// Hart's sphere tracing from `t0` to `t1`: `t += |f| / λ`; a hit where `|f| / λ < eps`.
pub fn sphere_trace<S: Shape + ?Sized>(
    b: &Bounded<S>,
    o: DVec3,
    d: DVec3,
    t0: f64,
    t1: f64,
    eps: f64,
) -> Cast {
    let mut evals = 0;
    let mut t = t0;
    while t <= t1 {
        let r = b.radius(o + d * t, &mut evals);
        if r < eps {
            return Cast { t: Some(t), evals };
        }
        t += r;
    }
    Cast { t: None, evals }
}

/// Sphere tracing with steps enlarged by `k` (> 1): from `t` with radius `r` it tries
/// `t' = t + k r`; the step is kept when the two unbounding balls overlap
/// (`r + r' > k r`, so `[t, t']` is covered), otherwise it steps back to the plain step
/// `t + r`. Every accepted step is guaranteed, so it finds the same first root as
/// [`sphere_trace`].
pub fn overshoot_trace<S: Shape + ?Sized>(
    b: &Bounded<S>,
    o: DVec3,
    d: DVec3,
    t0: f64,
    t1: f64,
    eps: f64,
    k: f64,
) -> Cast {
    let mut evals = 0;
    let mut t = t0;
    if t > t1 {
        return Cast { t: None, evals };
    }
    let mut r = b.radius(o + d * t, &mut evals);
    loop {
        if r < eps {
            return Cast { t: Some(t), evals };
        }
        let big = k * r;
        let tt = t + big;
        let mut accepted = false;
        if tt <= t1 {
            let rr = b.radius(o + d * tt, &mut evals);
            if r + rr > big {
                t = tt;
                r = rr;
                accepted = true;
            }
        }
        if !accepted {
            t += r;
            if t > t1 {
                return Cast { t: None, evals };
            }
            r = b.radius(o + d * t, &mut evals);
        }
    }
}

/// A Lipschitz bound of `t -> f(o + t d)` (unit `d`) over `[ta, tb]`: the largest
/// `|df/dt|` enclosed by one evaluation over `Dual<Interval>` (the directional derivative
/// `grad f . d` on the segment), `+inf` when unbounded. Along a ray only this 1-D bound
/// matters, and near a surface it is often far below the global bound.
pub fn ray_lipschitz<S: Shape + ?Sized>(s: &S, o: DVec3, d: DVec3, ta: f64, tb: f64) -> f64 {
    use arith_ia::Interval;
    let t = Interval::input(0, ta, tb);
    let zero = Interval::constant(0.0);
    let mk = |ok: f64, dk: f64| Dual {
        v: t * dk + ok,
        g: [Interval::constant(dk), zero, zero],
    };
    let f = s.eval(mk(o.x, d.x), mk(o.y, d.y), mk(o.z, d.z));
    let (lo, hi) = f.g[0].bounds();
    let m = lo.abs().max(hi.abs());
    if m.is_finite() {
        up(m)
    } else {
        f64::INFINITY
    }
}

/// Counters of [`local_trace`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LocalCounts {
    /// Point evaluations of `f`.
    pub evals: u64,
    /// Range (`Dual<Interval>`) evaluations for segment bounds.
    pub range_evals: u64,
}

/// Ray casting with local Lipschitz bounds: the ray is cut into segments, each with its
/// own bound from [`ray_lipschitz`] (capped by the global `b.lambda`), and traced inside
/// it with steps enlarged by `k` (1 for plain sphere tracing) exactly as
/// [`overshoot_trace`]; a step leaving the segment ends it (the segment is then clear).
/// Segment lengths adapt: doubled after a segment crossed in at most two steps, halved
/// after one needing more than eight. A hit is where `|f| / λ_segment < eps`.
#[allow(clippy::too_many_arguments)]
pub fn local_trace<S: Shape + ?Sized>(
    b: &Bounded<S>,
    o: DVec3,
    d: DVec3,
    t0: f64,
    t1: f64,
    eps: f64,
    k: f64,
    counts: &mut LocalCounts,
) -> Option<f64> {
    let mut ta = t0;
    let mut len = ((t1 - t0) * 0.25).max(16.0 * eps);
    while ta <= t1 {
        let tb = (ta + len).min(t1);
        counts.range_evals += 1;
        let lam = ray_lipschitz(b.shape, o, d, ta, tb).min(b.lambda);
        let radius = |t: f64, counts: &mut LocalCounts| {
            counts.evals += 1;
            let p = box_project(o + d * t, &b.domain);
            let f = b.shape.eval(p.x, p.y, p.z);
            if f.is_nan() {
                0.0
            } else if lam > 0.0 {
                f.abs() / lam
            } else if f == 0.0 {
                0.0
            } else {
                f64::INFINITY
            }
        };
        let mut steps = 0u32;
        let mut t = ta;
        let mut r = radius(t, counts);
        loop {
            if r < eps {
                return Some(t);
            }
            steps += 1;
            let big = k * r;
            let tt = t + big;
            if k > 1.0 && tt < tb {
                let rr = radius(tt, counts);
                if r + rr > big {
                    t = tt;
                    r = rr;
                    continue;
                }
            }
            t += r;
            if t >= tb {
                break;
            }
            r = radius(t, counts);
        }
        if tb >= t1 {
            return None;
        }
        if steps <= 2 {
            len *= 2.0;
        } else if steps > 8 {
            len = (len * 0.5).max(4.0 * eps);
        }
        ta = tb;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Sphere;
    impl Shape for Sphere {
        fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
            (x.sqr() + y.sqr() + z.sqr()).sqrt().rsub(1.0)
        }
    }

    #[test]
    fn casters_agree_on_a_sphere() {
        let b = Bounded {
            shape: &Sphere,
            domain: Aabb::cube(2.0),
            lambda: 1.0,
        };
        let o = DVec3::new(0.2, 0.1, -5.0);
        let d = DVec3::Z;
        let (t0, t1) = clip_to_box(o, d, &b.domain).unwrap();
        let a = sphere_trace(&b, o, d, t0, t1, 1e-6);
        let c = overshoot_trace(&b, o, d, t0, t1, 1e-6, DEFAULT_OVERSHOOT);
        let exact = 5.0 - (1.0f64 - 0.05).sqrt();
        assert!((a.t.unwrap() - exact).abs() < 2e-6);
        assert!((c.t.unwrap() - exact).abs() < 2e-6);
        let miss = sphere_trace(&b, DVec3::new(1.5, 0.0, -5.0), d, t0, t1, 1e-6);
        assert_eq!(miss.t, None);
    }
}
