//! The range-arithmetic cone test (past both papers): a cone of rays from the eye is
//! cleared of the surface segment by segment, each segment tested with a [`Range`]
//! arithmetic over the cone's frustum, exactly as Algorithm 2 tests a cell of pixels
//! ([`crate::search::cull`]): a segment whose range excludes 0 holds no surface point,
//! and no Lipschitz constant is needed. The forms have three independent symbols (the
//! axial distance and two lateral coordinates), so affine arithmetics also prune the
//! segment along its depth symbol, clearing its front without another evaluation.

use super::cone::{frustum_box, ConeEnd};
use super::ray::{Pruner, MARCH_GROWTH};
use arith_core::round::{up_finite, ETA, U};
use arith_core::{Arithmetic, Range};
use glam::DVec3;
use model_ir::shape::{Aabb, Shape};

/// Two unit vectors orthogonal to the unit `d` and to each other.
fn lateral_axes(d: DVec3) -> (DVec3, DVec3) {
    let a = if d.x.abs() < 0.6 { DVec3::X } else { DVec3::Y };
    let e1 = d.cross(a).normalize();
    let e2 = d.cross(e1).normalize();
    (e1, e2)
}

/// The points of the round cone (apex `o`, unit axis `d`, aperture `tan α`) at axial
/// distances `[s0, s1]` as affine forms in three independent inputs: the axial distance
/// `s = m + r eps0` and the lateral coordinates `u = eps1`, `v = eps2` of
/// `o + s (d + tan α (u e1 + v e2))`. A point of the cone at axial distance `s` is within
/// `s tan α` of the axis in the plane orthogonal to `d`, so its coordinates along `e1`,
/// `e2` are within `s tan α` too: the square `u, v in [-1, 1]` covers the cone's disc
/// (`tan α` is widened by `1e-9` for the rounding of `e1`, `e2`). The product terms
/// `r tan α eps0 (u e1 + v e2)` and the rounding of every coefficient go into the
/// error, as in [`crate::search::cull`]'s frustum forms.
pub fn cone_frustum<R: Range>(o: DVec3, d: DVec3, tan_a: f64, s0: f64, s1: f64) -> [R; 3] {
    let (e1, e2) = lateral_axes(d);
    let w = tan_a * (1.0 + 1e-9);
    let (uu, vv) = (e1 * w, e2 * w);
    let (m, r, emr) = arith_core::affine_round::mid_rad(s0, s1);
    let dn = (d.abs() + uu.abs() + vv.abs()).max_element();
    core::array::from_fn(|k| {
        let (dk, uk, vk) = (d[k], uu[k], vv[k]);
        let round = 64.0 * f64::EPSILON * (o[k].abs() + (m.abs() + r) * dn) + 4.0 * ETA;
        let err = r * (uk.abs() + vk.abs()) + emr * dn + round;
        R::from_affine(o[k] + m * dk, &[r * dk, m * uk, m * vk], up_finite(err))
    })
}

/// What the range test says about one segment `[ta, tb]` of a cone.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Verdict {
    /// No surface point in the segment.
    Empty,
    /// Surface points can only be at axial distances in `[a, b]` (`ta <= a`).
    Maybe(f64, f64),
}

/// Tests the cone's segment `[ta, tb]` in the arithmetic's cell form: the range excludes
/// 0, or its affine part along the depth symbol (the lateral terms and the rest bounded
/// in its error, for every `u`, `v`) prunes the segment to where roots can be.
fn test_segment<A: Arithmetic, S: Shape + ?Sized>(
    shape: &S,
    o: DVec3,
    d: DVec3,
    tan_a: f64,
    (ta, tb): (f64, f64),
) -> Verdict {
    let [x, y, z] = cone_frustum::<A::Cell>(o, d, tan_a, ta, tb);
    let f = shape.eval(x, y, z);
    if !f.contains_zero() {
        return Verdict::Empty;
    }
    let Some(a) = f.affine_part::<3>() else {
        return Verdict::Maybe(ta, tb);
    };
    let [cs, cu, cv] = a.xs;
    // `f in c0 + cs eps0 + (cu u + cv v ± e)`: the bracket within `±(|cu| + |cv| + e)`,
    // that sum rounded up (plus a few ulps of the magnitudes, as in culling's `Fit`).
    let mag = a.x0.abs() + cu.abs() + cv.abs();
    let e = up_finite(up_finite(a.e + cu.abs() + cv.abs()) + (8.0 * U * mag + 4.0 * ETA));
    match Pruner::new(ta, tb, cs).and_then(|p| p.prune(a.x0, e)) {
        Some(None) => Verdict::Empty,
        Some(Some((p0, p1))) => Verdict::Maybe(p0.max(ta), p1.min(tb)),
        None => Verdict::Maybe(ta, tb),
    }
}

/// Cone tracing with the range test: from `t0`, segments of the cone are tested front to
/// back ([`test_segment`]); a segment proved empty is cleared and the next one is
/// [`MARCH_GROWTH`] times longer; one that may hold surface is halved from its front
/// until it is about as long as the cone is wide there (a thinner frustum is no tighter),
/// and there the cone stops. Segments whose frustum's box misses `domain` are cleared
/// without an evaluation (the surface is only considered inside the domain). Returns
/// what [`crate::search::cone::trace_cone`] returns: `Blocked` when nothing past `t0`
/// could be cleared, `Reached(t_M)` with `[t0, t_M]` clear, `Escaped` past `t_inf`.
// `!(len > 0.0)` on purpose: a NaN length must end the march.
#[allow(clippy::too_many_arguments, clippy::neg_cmp_op_on_partial_ord)]
pub fn trace_cone_range<A: Arithmetic, S: Shape + ?Sized>(
    shape: &S,
    domain: &Aabb,
    o: DVec3,
    d: DVec3,
    tan_a: f64,
    t0: f64,
    t_inf: f64,
    range_evals: &mut u64,
) -> ConeEnd {
    let mut ta = t0;
    let mut len = ((t_inf - t0) * 0.125).max(1e-9 * (1.0 + t_inf.abs()));
    let mut guard = 0u32;
    while ta < t_inf {
        guard += 1;
        let tb = (ta + len).min(t_inf);
        let bx = frustum_box(o, d, tan_a, ta, tb);
        let meets = bx.min.cmple(domain.max).all() && domain.min.cmple(bx.max).all();
        let verdict = if meets {
            *range_evals += 1;
            test_segment::<A, S>(shape, o, d, tan_a, (ta, tb))
        } else {
            Verdict::Empty
        };
        // A slice thinner than the cone's width there gives ranges no tighter.
        let thin = (tb - ta) <= (2.0 * tb * tan_a).max(1e-12 * (1.0 + tb.abs()));
        match verdict {
            Verdict::Empty => {
                len = (tb - ta) * MARCH_GROWTH;
                ta = tb;
            }
            Verdict::Maybe(a, _) if a > ta => {
                // The front `[ta, a)` is proved clear by pruning.
                ta = a;
                len = (tb - a) * 0.5;
            }
            Verdict::Maybe(..) if !thin && guard < 100_000 => len = (tb - ta) * 0.5,
            Verdict::Maybe(..) => {
                return if ta > t0 {
                    ConeEnd::Reached(ta)
                } else {
                    ConeEnd::Blocked
                };
            }
        }
        if !(len > 0.0) || ta + len == ta {
            return if ta > t0 {
                ConeEnd::Reached(ta)
            } else {
                ConeEnd::Blocked
            };
        }
    }
    ConeEnd::Escaped
}
