//! Engine tests for the progressive refinement previewer (headless).

use glam::DVec3;
use model_ir::shape::{Aabb, Shape, View};
use model_sources::gamito_maddock::GmModel;
use model_sources::Model;
use tracer::progressive::*;
use tracer::search::cone::{trace_cone, ConeEnd};
use tracer::search::lipschitz::Bounded;

fn model(name: &str) -> Model {
    model_sources::gamito_maddock::all()
        .into_iter()
        .find(|m| m.name == name)
        .unwrap()
}

/// Every bound mode: the global Lipschitz bound, local bounds and the range test with
/// each arithmetic of the one list.
fn bound_modes() -> Vec<Bound> {
    let mut v = vec![Bound::Lipschitz, Bound::Local];
    v.extend(model_ir::arith::ArithKind::ALL.map(Bound::Range));
    v
}

/// Whether the ray of pixel `k` never crosses the surface inside the domain (dense
/// sampling finds no sign change of `f`): a near miss, where a Lipschitz caster's "hit"
/// (a point with `|f| / λ < eps`) and a miss are both within its contract.
fn never_crosses(m: &Model, w: u32, h: u32, k: usize) -> bool {
    let cam = model_ir::camera::Camera::new(m.view, w, h);
    let (o, d) = cam.ray(k as u32 % w, k as u32 / w);
    let Some((t0, t1)) = tracer::search::lipschitz::clip_to_box(o, d, &m.domain) else {
        return true;
    };
    let f = |t: f64| {
        let p = o + d * t;
        m.eval(p.x, p.y, p.z)
    };
    let s0 = f(t0).signum();
    let n = 20_000;
    (0..=n).all(|i| f(t0 + (t1 - t0) * i as f64 / n as f64).signum() == s0)
}

/// The final image of every bound mode equals a conventional ray caster's, pixel for
/// pixel in hit mask:
/// - the global Lipschitz bound: the standard Lipschitz caster's, and its depth within
///   `k eps` (k the overshooting factor);
/// - the range test in each arithmetic: Algorithm 1's over the whole ray in the same
///   arithmetic and precision, and its depth within `eps`;
/// - local bounds: the standard Lipschitz caster's, except at near misses (rays that
///   never cross the surface, checked by dense sampling), where the local hit test
///   `|f| / λ_segment < eps` is stricter than the global one; those are few.
///
/// Why `k eps`: near a simple root at `t*` with slope `s <= λ` along the ray, the
/// standard caster stops at its first point with `r = |f|/λ < eps`, whose predecessor had
/// `r >= eps`, so its distance to the root lies in `[(eps - eps s/λ) λ/s, eps λ/s)`, i.e.
/// within `eps` of `eps λ/s`; the overshooting caster's last step is at most `k r`, so
/// its distance lies within `k eps` of the same value. A 1% allowance covers the
/// curvature of `f` over the last step (second order in `eps`).
#[test]
fn final_image_of_every_bound_mode_equals_the_conventional_ray_caster() {
    let cases: &[(&str, u32, u32)] = &[
        ("mitchell-gm", 32, 32),
        ("mitchell-gm", 37, 24),
        ("mitchell-gm", 30, 20),
        ("hypertexture-1", 32, 32),
        ("hypertexture-1", 37, 24),
        ("hypertexture-2", 24, 18),
        ("blobby", 20, 16),
        ("landscape", 30, 20),
        // Prime sides: a padded plan, its samples cropped to the image.
        ("mitchell-gm", 31, 29),
    ];
    for &(name, w, h) in cases {
        let m = model(name);
        let lambda = m.lipschitz.unwrap();
        let eps = Options::new(lambda).eps;
        let cast = |c| {
            raycast(&m, m.domain, m.view, w, h, lambda, eps, c)
                .unwrap()
                .0
        };
        let standard = cast(Caster::Standard);
        for bound in bound_modes() {
            let reference = match bound {
                Bound::Range(kind) => cast(Caster::Range(kind)),
                _ => standard.clone(),
            };
            for cs in [ChildStart::Radial, ChildStart::Paper] {
                let mut opts = Options::new(lambda);
                opts.child_start = cs;
                opts.bound = bound;
                let mut e = Engine::new(m.clone(), m.domain, m.view, w, h, opts).unwrap();
                e.run();
                assert!(e.is_done());
                let (mut hits, mut near_misses) = (0, 0);
                for (k, (a, b)) in e.depth().iter().zip(&reference).enumerate() {
                    let at = format!("{name} {w}x{h} {bound:?} {cs:?} pixel {k}");
                    assert!(!a.is_nan(), "{at}: never finished");
                    if a.is_finite() != b.is_finite() {
                        assert!(
                            bound == Bound::Local && never_crosses(&m, w, h, k),
                            "{at}: hit mask differs ({a} vs {b})"
                        );
                        near_misses += 1;
                        continue;
                    }
                    if a.is_finite() {
                        hits += 1;
                        let tol = match bound {
                            Bound::Lipschitz => opts.overshoot * eps * 1.01,
                            Bound::Range(_) => eps,
                            // Closer to the root than the global caster: never before it.
                            Bound::Local | Bound::Auto => f64::INFINITY,
                        };
                        assert!(
                            (a - b).abs() <= tol && *a >= b - opts.overshoot * eps * 1.01,
                            "{at}: depth {a} vs {b}"
                        );
                    }
                }
                // The case is not vacuous: it has hits and misses.
                assert!(hits > 0 && hits < (w * h) as usize, "{name}: {hits} hits");
                assert!(
                    near_misses * 100 <= (w * h) as usize,
                    "{name} {bound:?}: {near_misses} near misses"
                );
            }
        }
    }
}

/// A prime or awkward size still refines progressively: the sample grid is padded to a
/// side of small prime factors and cropped (eq. 7 alone gives no levels at all).
#[test]
fn prime_sizes_get_a_padded_plan_with_several_levels() {
    let p = Plan::for_image(797, 797);
    assert_eq!(Plan::new(797, 797).splits, vec![797]);
    assert_eq!((p.u, p.v, p.padded), (1, 1, true), "{p:?}");
    assert!(p.size >= 797 && p.splits.len() >= 7, "{p:?}");
    assert!(p.splits.iter().all(|&s| s <= 5));
    assert_eq!(p.splits.iter().product::<u32>(), p.size);
    let p = Plan::for_image(37, 24);
    assert!(p.padded && p.splits.len() >= 3, "{p:?}");
    assert!(p.u * p.size >= 37 && p.v * p.size >= 24);
    // Sizes eq. (7) serves well keep the paper's plan.
    assert_eq!(Plan::for_image(800, 600), Plan::new(800, 600));
    assert_eq!(Plan::for_image(800, 800), Plan::new(800, 800));
    // The engine at a prime size passes through several levels, and every pixel ends.
    let m = model("mitchell-gm");
    let mut e = Engine::new(
        m.clone(),
        m.domain,
        m.view,
        61,
        59,
        Options::new(m.lipschitz.unwrap()),
    )
    .unwrap();
    let mut levels = 0;
    while let Step::Processed { level_started, .. } = e.step() {
        levels += level_started.is_some() as usize;
    }
    assert!(levels >= 3, "{levels} level transitions");
    assert!((0..59).all(|j| (0..61).all(|i| e.pixel_done(i, j))));
    assert!(e.depth().iter().all(|d| !d.is_nan()));
}

#[test]
fn prime_factor_plan_follows_eq_7() {
    let p = Plan::new(800, 600);
    assert_eq!((p.u, p.v, p.size), (4, 3, 200));
    assert_eq!(p.splits, vec![5, 5, 2, 2, 2]);
    let p = Plan::new(37, 24);
    assert_eq!((p.u, p.v, p.size), (37, 24, 1));
    assert!(p.splits.is_empty());
    assert_eq!(Plan::new(64, 64).splits, vec![2; 6]);
    assert_eq!(prime_factors_desc(360), vec![5, 3, 3, 2, 2, 2]);
}

/// A unit-radius sphere at distance `D` on the cone axis: no point of the sphere lies in
/// the cone before axial distance `D - 1`, so `t_M <= D - 1`.
#[test]
fn cone_tracing_stops_before_the_surface_and_escapes_past_it() {
    struct Ball;
    impl Shape for Ball {
        fn eval<R: arith_core::Real>(&self, x: R, y: R, z: R) -> R {
            (x.sqr() + y.sqr() + z.sqr()).sqrt().rsub(1.0)
        }
    }
    let b = Bounded {
        shape: &Ball,
        domain: Aabb::cube(1.5),
        lambda: 1.0,
    };
    let o = DVec3::new(0.0, 0.0, -5.0);
    let mut evals = 0;
    for tan_a in [0.001, 0.01, 0.05] {
        match trace_cone(&b, o, DVec3::Z, tan_a, 0.0, 20.0, &mut evals) {
            ConeEnd::Reached(tm) => {
                assert!(tm <= 4.0, "tan {tan_a}: t_M {tm}");
                // Thinner cones get closer.
                assert!(tm > 4.0 - 60.0 * tan_a, "tan {tan_a}: t_M {tm}");
            }
            e => panic!("{e:?}"),
        }
    }
    assert!(evals > 0);
    // An axis passing 1.3 from the centre with a thin cone misses the ball entirely.
    let o2 = DVec3::new(1.3, 0.0, -5.0);
    assert_eq!(
        trace_cone(&b, o2, DVec3::Z, 0.01, 0.0, 20.0, &mut evals),
        ConeEnd::Escaped
    );
    // Condition (4) fails at t0 when the first sphere cannot hold the cone's section.
    assert_eq!(
        trace_cone(&b, o, DVec3::Z, 0.5, 3.9, 20.0, &mut evals),
        ConeEnd::Blocked
    );
}

fn hyper64() -> Engine<Model> {
    let m = model("hypertexture-1");
    Engine::new(
        m.clone(),
        m.domain,
        m.view,
        64,
        64,
        Options::new(m.lipschitz.unwrap()),
    )
    .unwrap()
}

#[test]
fn region_of_interest_refines_only_its_samples_first() {
    let mut e = hyper64();
    for _ in 0..30 {
        e.step();
    }
    let roi = Rect {
        x0: 10,
        y0: 20,
        x1: 30,
        y1: 34,
    };
    e.set_roi(roi).unwrap();
    assert!(e.queue_lens().1 > 0);
    let mut finished = false;
    for _ in 0..100_000 {
        if let Step::Processed {
            roi_finished: true, ..
        } = e.step()
        {
            finished = true;
            break;
        }
    }
    assert!(finished);
    assert_eq!(e.roi(), None);
    for j in 0..64 {
        for i in 0..64 {
            let inside = (roi.x0..roi.x1).contains(&i) && (roi.y0..roi.y1).contains(&j);
            if inside {
                assert!(e.pixel_done(i, j), "ROI pixel ({i},{j}) not final");
            }
        }
    }
    let outside_done = (0..64)
        .flat_map(|j| (0..64).map(move |i| (i, j)))
        .filter(|&(i, j)| {
            !((roi.x0..roi.x1).contains(&i) && (roi.y0..roi.y1).contains(&j)) && e.pixel_done(i, j)
        })
        .count();
    assert!(
        outside_done < 64 * 64 - 20 * 14,
        "outside the ROI nearly nothing should be final yet ({outside_done})"
    );
    assert!(!e.is_done());
    e.run();
    assert!((0..64).all(|j| (0..64).all(|i| e.pixel_done(i, j))));
}

#[test]
fn cancelling_a_region_flushes_its_samples_back_and_changes_nothing_final() {
    let mut plain = hyper64();
    plain.run();
    let mut e = hyper64();
    for _ in 0..30 {
        e.step();
    }
    e.set_roi(Rect::from_corners((40, 5), (60, 25))).unwrap();
    for _ in 0..50 {
        e.step();
    }
    let (p, s) = e.queue_lens();
    assert!(s > 0, "the ROI should still have samples");
    e.cancel_roi();
    assert_eq!(e.queue_lens(), (p + s, 0));
    assert_eq!(e.roi(), None);
    e.run();
    assert_eq!(e.depth(), plain.depth());
    assert_eq!(e.image().snapshot(), plain.image().snapshot());
    assert!(e
        .set_roi(Rect {
            x0: 5,
            y0: 5,
            x1: 5,
            y1: 9
        })
        .is_err());
    assert!(e
        .set_roi(Rect {
            x0: 0,
            y0: 0,
            x1: 65,
            y1: 9
        })
        .is_err());
}

#[test]
fn previewer_paints_a_full_frame_early() {
    // After four of the six levels (down to samples of 8x8 pixels) the image already
    // shows the model, while most pixels are not final yet.
    let mut e = hyper64();
    while e.next_level().is_some_and(|l| l < 4) {
        e.step();
    }
    let done = (0..64)
        .flat_map(|j| (0..64).map(move |i| (i, j)))
        .filter(|&(i, j)| e.pixel_done(i, j))
        .count();
    assert!(done < 64 * 64 / 2, "{done}");
    let img = e.image().snapshot();
    let bg = tracer::render::shade::BACKGROUND;
    let bgc = (bg[0] as u32) << 16 | (bg[1] as u32) << 8 | bg[2] as u32;
    assert!(img.iter().any(|&c| c != bgc));
}

#[test]
fn anti_aliasing_box_filters_subpixel_samples() {
    let m = model("mitchell-gm");
    let mut opts = Options::new(m.lipschitz.unwrap());
    opts.aa = 2;
    opts.filter = tracer_kit::bspline_filter::Kernel::Box;
    let mut e = Engine::new(m.clone(), m.domain, m.view, 16, 12, opts).unwrap();
    assert_eq!(e.virtual_size(), (32, 24));
    e.run();
    // The virtual image equals the conventional caster at twice the resolution.
    let (reference, _) = raycast(
        &m,
        m.domain,
        m.view,
        32,
        24,
        opts.lambda,
        opts.eps,
        Caster::Standard,
    )
    .unwrap();
    for (a, b) in e.depth().iter().zip(&reference) {
        assert_eq!(a.is_finite(), b.is_finite());
    }
    // Silhouette pixels mix the surface and the background colour.
    let bg = tracer::render::shade::BACKGROUND;
    let img = e.image().to_rgb();
    let mixed = (0..12)
        .flat_map(|j| (0..16).map(move |i| (i, j)))
        .filter(|&(i, j)| {
            let k = |dx, dy| reference[((2 * j + dy) * 32 + 2 * i + dx) as usize].is_finite();
            let n = [k(0, 0), k(1, 0), k(0, 1), k(1, 1)]
                .iter()
                .filter(|&&h| h)
                .count();
            n > 0 && n < 4 && img.get_pixel(i, j).0 != bg
        });
    assert!(mixed.count() > 0);
}

#[test]
fn bad_options_are_errors() {
    let m = model("mitchell-gm");
    let v: View = m.view;
    for (l, aa) in [(0.0, 1), (f64::NAN, 1), (1.0, 0), (1.0, 99)] {
        let mut o = Options::new(l);
        o.aa = aa;
        assert!(Engine::new(GmModel::Mitchell, m.domain, v, 8, 8, o).is_err());
    }
    assert!(Engine::new(GmModel::Mitchell, m.domain, v, 0, 8, Options::new(1.0)).is_err());
    // Sizes are checked before the buffers are allocated, at the output and at the
    // anti-aliasing resolution.
    let e = Engine::new(
        GmModel::Mitchell,
        m.domain,
        v,
        100_000,
        100_000,
        Options::new(1.0),
    );
    assert!(e.err().unwrap().contains("100000x100000"));
    let mut o = Options::new(1.0);
    o.aa = 16;
    let e = Engine::new(GmModel::Mitchell, m.domain, v, 2000, 2000, o);
    assert!(e.err().unwrap().contains("32000x32000"));
    let e = Engine::new(
        GmModel::Mitchell,
        Aabb::cube(1e300),
        v,
        8,
        8,
        Options::new(1.0),
    );
    assert!(e.err().unwrap().contains("too large"));
    let mut far = v;
    far.eye = DVec3::splat(1e308);
    let e = Engine::new(GmModel::Mitchell, m.domain, far, 8, 8, Options::new(1.0));
    assert!(e.err().unwrap().contains("too far"));
}

/// The automatic choice takes local bounds on Mitchell's quartic (its gradient is steep
/// only near the domain's corners) and the global bound on the noise hypertexture (as
/// steep everywhere), as measured in `bench-suite progressive`.
#[test]
fn auto_bound_picks_local_bounds_where_they_pay() {
    for (name, want) in [
        ("mitchell-gm", Bound::Local),
        ("blobby", Bound::Local),
        ("hypertexture-1", Bound::Lipschitz),
    ] {
        let m = model(name);
        assert_eq!(
            auto_bound(&m, &m.domain, m.lipschitz.unwrap()),
            want,
            "{name}"
        );
        let mut o = Options::new(m.lipschitz.unwrap());
        o.bound = Bound::Auto;
        let e = Engine::new(m.clone(), m.domain, m.view, 8, 8, o).unwrap();
        assert_eq!(e.options().bound, want);
    }
}

/// With local (per ray segment) Lipschitz bounds the hit test `|f| / λ_segment < eps` is
/// stricter than the global one, so near misses (rays passing within `eps λ / |grad f|`
/// of the surface without crossing it) may be classified differently from the global
/// caster; what must hold is the guarantee: no sign change of `f` before the reported
/// depth (checked by dense sampling), a near-surface point at each hit, and a miss only
/// where the ray never crosses the surface.
#[test]
fn local_bounds_keep_the_guarantee_and_save_evaluations() {
    let cam_check = |name: &str, w: u32, h: u32| {
        let m = model(name);
        let mut opts = Options::new(m.lipschitz.unwrap());
        opts.bound = Bound::Local;
        let mut e = Engine::new(m.clone(), m.domain, m.view, w, h, opts).unwrap();
        e.run();
        let mut global =
            Engine::new(m.clone(), m.domain, m.view, w, h, Options::new(opts.lambda)).unwrap();
        global.run();
        assert!(
            e.stats().evals < global.stats().evals,
            "{name}: local bounds should save point evaluations"
        );
        assert!(e.stats().range_evals > 0);
        let cam = model_ir::camera::Camera::new(m.view, w, h);
        let f = |p: DVec3| m.eval(p.x, p.y, p.z);
        for (k, &depth) in e.depth().iter().enumerate() {
            let (o, d) = cam.ray(k as u32 % w, k as u32 / w);
            let Some((t0, t1)) = tracer::search::lipschitz::clip_to_box(o, d, &m.domain) else {
                assert!(depth.is_infinite());
                continue;
            };
            let end = if depth.is_finite() { depth } else { t1 };
            let s0 = f(o + d * t0).signum();
            let n = 4000;
            for i in 0..=n {
                let t = t0 + (end - t0) * i as f64 / n as f64;
                let v = f(o + d * t);
                assert!(
                    v.signum() == s0 || v.abs() < opts.eps * opts.lambda,
                    "{name} pixel {k}: f changes sign at {t} before {depth}"
                );
            }
            if depth.is_finite() {
                assert!(
                    f(o + d * depth).abs() < opts.eps * opts.lambda,
                    "{name} pixel {k}: hit is not near the surface"
                );
            }
        }
    };
    cam_check("mitchell-gm", 32, 24);
    cam_check("blobby", 16, 12);
}
