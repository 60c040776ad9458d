//! Conventional Lipschitz ray casting of a whole image, one ray per pixel centre, with
//! one of the casters of [`crate::search::lipschitz`]: the baseline the previewer is
//! measured against (Gamito and Maddock 2007, Table 1) and the reference its final image
//! must equal. It is a driver (a camera and a loop over pixels) over those searches, so
//! it lives with the renderers rather than in `search/`.

use crate::search::lipschitz::{
    clip_to_box, local_trace, overshoot_trace, sphere_trace, Bounded, LocalCounts,
};
use crate::search::ray::{first_root, Precision, RayParams, RayStats, Start};
use model_ir::arith::ArithKind;
use model_ir::camera::Camera;
use model_ir::shape::{Aabb, Shape, View};

/// Which conventional ray caster.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Caster {
    /// `t += |f| / λ`.
    Standard,
    /// Steps enlarged by this factor, with step-back.
    Overshoot(f64),
    /// [`local_trace`] with this overshooting factor (1 for plain steps).
    Local(f64),
    /// Algorithm 1 ([`first_root`]) in this arithmetic, with `eps` as its absolute
    /// precision and argument pruning (no Lipschitz bound used): the reference of the
    /// previewer's range test.
    Range(ArithKind),
}

/// A conventional Lipschitz ray casting of the whole image (one ray per pixel centre):
/// the depth of each pixel (`+inf` for a miss) and the evaluation counts.
#[allow(clippy::too_many_arguments)]
pub fn raycast<S: Shape + ?Sized>(
    shape: &S,
    domain: Aabb,
    view: View,
    w: u32,
    h: u32,
    lambda: f64,
    eps: f64,
    caster: Caster,
) -> Result<(Vec<f64>, LocalCounts), String> {
    let cam = Camera::try_new(view, w, h)?;
    let b = Bounded {
        shape,
        domain,
        lambda,
    };
    let mut depth = Vec::with_capacity(w as usize * h as usize);
    let mut counts = LocalCounts::default();
    for j in 0..h {
        for i in 0..w {
            let (o, d) = cam.ray(i, j);
            let t = match clip_to_box(o, d, &domain) {
                None => None,
                Some((t0, t1)) => {
                    let c = match caster {
                        Caster::Standard => sphere_trace(&b, o, d, t0, t1, eps),
                        Caster::Overshoot(k) => overshoot_trace(&b, o, d, t0, t1, eps, k),
                        Caster::Local(k) => {
                            let mut c = LocalCounts::default();
                            let t = local_trace(&b, o, d, t0, t1, eps, k, &mut c);
                            counts.range_evals += c.range_evals;
                            crate::search::lipschitz::Cast { t, evals: c.evals }
                        }
                        Caster::Range(kind) => {
                            let params = RayParams {
                                precision: Precision { abs: eps, rel: 0.0 },
                                pruning: true,
                            };
                            let mut st = RayStats::default();
                            let start = Start::whole(t0, t1);
                            let t = model_ir::with_arith!(kind, A => first_root::<A, S>(
                                shape, o, d, start, &params, &mut st
                            ));
                            counts.range_evals += st.range_evals;
                            crate::search::lipschitz::Cast {
                                t,
                                evals: st.point_evals,
                            }
                        }
                    };
                    counts.evals += c.evals;
                    c.t
                }
            };
            depth.push(t.unwrap_or(f64::INFINITY));
        }
    }
    Ok((depth, counts))
}
