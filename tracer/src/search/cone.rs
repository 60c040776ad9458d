//! Lipschitz cone tracing (Gamito and Maddock 2007, Section 3.1, eqs. 3-6 and Fig. 3):
//! a cone of rays from the eye is cleared of the surface, step by step along its axis,
//! with the unbounding radius of a Lipschitz bound, so that one search answers for every
//! pixel of a square image sample. [`trace_cone`] is the paper's algorithm with one
//! global bound; [`trace_cone_local`] cuts the cone into segments with a bound of their
//! own. The progressive previewer's engine issues the cones, one per image sample.

use super::lipschitz::Bounded;
use glam::DVec3;
use model_ir::shape::{Aabb, Shape};

/// How far cone tracing got (Section 3.1, Fig. 3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConeEnd {
    /// Condition (4) fails at `t0`: the sample must be subdivided without tracing.
    Blocked,
    /// The cone is clear of the surface up to axial distance `t_M`.
    Reached(f64),
    /// The cone is clear up to `t_inf`: no surface in it.
    Escaped,
}

/// Cone tracing exactly as Fig. 3, with the unbounding radius `ε_i` of
/// [`Bounded::radius`], condition (4) `ε_i > t_i tan α`, the offsets (5) and condition
/// (6) `t_{i+1} - t_i < Δt⁻_{i+1} + Δt⁺_i`, which must *hold* for the step to be taken
/// (the text's reading; the figure prints the test with the opposite outcome).
// `!(a > b)` on purpose: a NaN radius must fail condition (4).
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn trace_cone<S: Shape + ?Sized>(
    b: &Bounded<S>,
    o: DVec3,
    d: DVec3,
    tan_a: f64,
    t0: f64,
    t_inf: f64,
    evals: &mut u64,
) -> ConeEnd {
    let cos2 = 1.0 / (1.0 + tan_a * tan_a);
    let sin2 = tan_a * tan_a * cos2;
    // δ of eq. (5c), well defined under condition (4).
    let delta = |e: f64, t: f64| (e * e * cos2 - t * t * sin2).max(0.0).sqrt();
    let mut ti = t0;
    let mut ei = b.radius(o + d * ti, evals);
    if !(ei > ti * tan_a) {
        return ConeEnd::Blocked;
    }
    let mut dplus = delta(ei, ti) - ti * sin2;
    let mut guard = 0u64;
    while ti < t_inf {
        guard += 1;
        let tn = ti + ei;
        let en = b.radius(o + d * tn, evals);
        let stop = if !(en > tn * tan_a) || guard > 10_000_000 {
            true // condition (4)
        } else {
            let dn = delta(en, tn);
            let (dminus_n, dplus_n) = (dn + tn * sin2, dn - tn * sin2);
            if tn - ti < dminus_n + dplus {
                ti = tn;
                ei = en;
                dplus = dplus_n;
                false
            } else {
                true // condition (6) does not hold
            }
        };
        if stop {
            let tm = ti + dplus;
            return if tm >= t_inf {
                ConeEnd::Escaped
            } else {
                ConeEnd::Reached(tm)
            };
        }
    }
    ConeEnd::Escaped
}

/// The axis-aligned box around the part of a cone (apex `o`, unit axis `d`, `tan α`)
/// between axial distances `ta` and `tb`: the frustum is the convex hull of its two end
/// discs, and a disc of radius `ρ` orthogonal to `d` spans `ρ sqrt(1 - d_k^2)` along axis k.
pub(crate) fn frustum_box(o: DVec3, d: DVec3, tan_a: f64, ta: f64, tb: f64) -> Aabb {
    let ext = DVec3::new(
        (1.0 - d.x * d.x).max(0.0).sqrt(),
        (1.0 - d.y * d.y).max(0.0).sqrt(),
        (1.0 - d.z * d.z).max(0.0).sqrt(),
    );
    let (ca, cb) = (o + d * ta, o + d * tb);
    let (ea, eb) = (ext * (ta * tan_a), ext * (tb * tan_a));
    // A relative margin for rounding.
    let pad = DVec3::splat(1e-9 * (1.0 + o.abs().max_element() + tb.abs()));
    Aabb::new((ca - ea).min(cb - eb) - pad, (ca + ea).max(cb + eb) + pad)
}

/// Cone tracing with local Lipschitz bounds (past the paper): the cone is cut into
/// axial segments `[ta, tb]`; in each, `λ` is the gradient bound over the box around
/// that frustum, intersected with the domain ([`model_ir::gradient_bound::gradient_bound_on_box`],
/// capped by the global bound), and Fig. 3 runs inside it with the offsets (5) clipped
/// to the segment (a ball certifies only the part of the cone inside the box, where its
/// `λ` holds). The next segment starts at the cleared frontier. Segment lengths adapt
/// as in [`crate::search::lipschitz::local_trace`].
// `!(a > b)` on purpose: a NaN radius must fail condition (4).
#[allow(clippy::neg_cmp_op_on_partial_ord, clippy::too_many_arguments)]
pub fn trace_cone_local<S: Shape + ?Sized>(
    b: &Bounded<S>,
    o: DVec3,
    d: DVec3,
    tan_a: f64,
    t0: f64,
    t_inf: f64,
    evals: &mut u64,
    range_evals: &mut u64,
) -> ConeEnd {
    let cos2 = 1.0 / (1.0 + tan_a * tan_a);
    let sin2 = tan_a * tan_a * cos2;
    let delta = |e: f64, t: f64| (e * e * cos2 - t * t * sin2).max(0.0).sqrt();
    let mut ta = t0;
    let mut len = ((t_inf - t0) * 0.125).max(1e-6);
    let mut first = true;
    let mut guard = 0u64;
    while ta < t_inf {
        let tb = (ta + len).min(t_inf);
        let bx = frustum_box(o, d, tan_a, ta, tb);
        let clipped = Aabb::new(bx.min.max(b.domain.min), bx.max.min(b.domain.max));
        let lam = if clipped.min.cmple(clipped.max).all() {
            *range_evals += 1;
            model_ir::gradient_bound::gradient_bound_on_box(b.shape, &clipped).min(b.lambda)
        } else {
            b.lambda // the frustum misses the domain: any bound serves
        };
        let lb = Bounded {
            shape: b.shape,
            domain: b.domain,
            lambda: lam.max(f64::MIN_POSITIVE),
        };
        let mut ti = ta;
        let mut ei = lb.radius(o + d * ti, evals);
        if !(ei > ti * tan_a) {
            return if first {
                ConeEnd::Blocked
            } else {
                ConeEnd::Reached(ta)
            };
        }
        first = false;
        let mut dplus = (delta(ei, ti) - ti * sin2).min(tb - ti);
        let mut steps = 0u32;
        let frontier = loop {
            guard += 1;
            steps += 1;
            let tn = ti + ei;
            if tn > tb || guard > 10_000_000 {
                break ti + dplus;
            }
            let en = lb.radius(o + d * tn, evals);
            if !(en > tn * tan_a) {
                let tm = ti + dplus;
                return if tm >= t_inf {
                    ConeEnd::Escaped
                } else {
                    ConeEnd::Reached(tm)
                };
            }
            let dn = delta(en, tn);
            let (dminus_n, dplus_n) =
                ((dn + tn * sin2).min(tn - ta), (dn - tn * sin2).min(tb - tn));
            if tn - ti < dminus_n + dplus {
                ti = tn;
                ei = en;
                dplus = dplus_n;
            } else {
                let tm = ti + dplus;
                return if tm >= t_inf {
                    ConeEnd::Escaped
                } else {
                    ConeEnd::Reached(tm)
                };
            }
        };
        if frontier >= t_inf {
            return ConeEnd::Escaped;
        }
        if !(frontier > ta) || guard > 10_000_000 {
            return ConeEnd::Reached(frontier.max(ta));
        }
        if steps <= 2 {
            len *= 2.0;
        } else if steps > 8 {
            len *= 0.5;
        }
        ta = frontier;
    }
    ConeEnd::Escaped
}
