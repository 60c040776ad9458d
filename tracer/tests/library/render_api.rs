//! Renderer features beyond primary hits: shadow rays against an analytic occluder, and
//! the time budget used by the bench suite.

use arith_core::rfunc::union;
use arith_core::Real;
use glam::DVec3;
use model_ir::arith::ArithKind;
use model_ir::camera::Camera;
use model_ir::shape::{Aabb, Shape, View};
use tracer::render::shade::Light;
use tracer::render::{render_kind, RenderOptions};

/// A ball of radius 0.5 centred at `C` resting above the floor `y <= 0`.
struct BallOnFloor;
const C: DVec3 = DVec3::new(0.0, 0.7, 0.0);
impl Shape for BallOnFloor {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        let ball = ((x - C.x).sqr() + (y.clone() - C.y).sqr() + (z - C.z).sqr()).rsub(0.25);
        union(ball, -y)
    }
}

fn opts() -> RenderOptions {
    let view = View {
        eye: DVec3::new(0.4, 3.0, 3.5),
        look_at: DVec3::new(0.0, 0.2, 0.0),
        up: DVec3::Y,
        fov_deg: 45.0,
        ortho: None,
    };
    let domain = Aabb::new(DVec3::new(-2.0, -0.5, -2.0), DVec3::new(2.0, 1.5, 2.0));
    let mut o = RenderOptions::for_view(view, domain, 64, 48);
    o.eps = Some(1e-5);
    o
}

#[test]
fn shadow_rays_match_the_analytic_shadow() {
    let mut o = opts();
    let lit = render_kind(ArithKind::Revaa, &BallOnFloor, &o).unwrap();
    o.shadows = true;
    let sh = render_kind(ArithKind::Revaa, &BallOnFloor, &o).unwrap();
    assert!(sh.stats.shadow_rays > 0);
    let cam = Camera::new(o.view, o.width, o.height);
    let l = Light::for_camera(&cam).dir;
    let (mut shadowed, mut lit_floor) = (0, 0);
    for j in 0..o.height {
        for i in 0..o.width {
            let k = (j * o.width + i) as usize;
            if !sh.hit[k] {
                continue;
            }
            let (eye, d) = cam.ray(i, j);
            let p = eye + d * sh.depth[k] as f64;
            // Floor points only, away from the ball's contact region.
            if p.y.abs() > 1e-3 || (p - DVec3::new(C.x, 0.0, C.z)).length() < 0.2 {
                continue;
            }
            // Does the ray p + s l (s > 0) meet the ball? Clear-cut cases only.
            let oc = p - C;
            let b = oc.dot(l);
            let disc = b * b - (oc.length_squared() - 0.25);
            let differs = lit.rgb[3 * k..3 * k + 3] != sh.rgb[3 * k..3 * k + 3];
            if disc > 1e-2 && b < 0.0 {
                shadowed += 1;
                assert!(
                    differs,
                    "pixel ({i},{j}) at {p:?} should be in the ball's shadow"
                );
            } else if disc < -1e-2 {
                lit_floor += 1;
                assert!(!differs, "pixel ({i},{j}) at {p:?} should be lit");
            }
        }
    }
    assert!(
        shadowed > 20 && lit_floor > 100,
        "{shadowed} shadowed, {lit_floor} lit floor pixels"
    );
}

#[test]
fn deadline_cuts_the_render_short() {
    let mut o = opts();
    o.deadline = Some(std::time::Instant::now());
    let r = render_kind(ArithKind::Revaa, &BallOnFloor, &o).unwrap();
    assert!(r.stats.cut);
    assert!(r.stats.tiles_done < r.stats.tiles_total);
    let full = render_kind(ArithKind::Revaa, &BallOnFloor, &opts()).unwrap();
    assert!(!full.stats.cut && full.stats.tiles_done == full.stats.tiles_total);
}

#[test]
fn degenerate_options_are_errors() {
    let mut o = opts();
    o.eps = Some(0.0);
    assert!(render_kind(ArithKind::Ia, &BallOnFloor, &o).is_err());
    let mut o = opts();
    o.domain = Aabb::new(DVec3::ONE, DVec3::ZERO);
    assert!(render_kind(ArithKind::Ia, &BallOnFloor, &o).is_err());
}

/// The size is checked before any buffer is allocated: a 100000 x 100000 image would
/// need 30 GB of colour alone.
#[test]
fn huge_and_empty_sizes_are_errors() {
    for (w, h) in [(100_000, 100_000), (0, 0), (0, 48), (64, 0), (16_385, 1)] {
        let mut o = opts();
        o.width = w;
        o.height = h;
        // Were the size not checked, the render would skip every tile and then try to
        // allocate the image.
        o.deadline = Some(std::time::Instant::now());
        let e = render_kind(ArithKind::Ia, &BallOnFloor, &o).unwrap_err();
        assert!(
            e.contains(&format!("{w}x{h}")) && e.contains("16384"),
            "{e}"
        );
    }
    let mut o = opts();
    o.width = model_ir::camera::MAX_SIDE;
    o.height = 1;
    o.tile = 1 << 20;
    o.deadline = Some(std::time::Instant::now());
    assert!(render_kind(ArithKind::Ia, &BallOnFloor, &o).is_ok());
}

#[test]
fn overflowing_views_and_domains_are_errors() {
    let mut o = opts();
    o.view.eye = DVec3::splat(1e308);
    let e = render_kind(ArithKind::Ia, &BallOnFloor, &o).unwrap_err();
    assert!(e.contains("too far") && e.contains("1e308"), "{e}");
    let mut o = opts();
    o.domain = Aabb::cube(1e300);
    let e = render_kind(ArithKind::Ia, &BallOnFloor, &o).unwrap_err();
    assert!(e.contains("too large"), "{e}");
}
