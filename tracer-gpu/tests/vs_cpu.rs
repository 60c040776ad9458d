//! The GPU against the CPU tracer and against analytic ground truth, at 64x64 (lavapipe
//! in CI). Every pixel the CPU proves hit (its ray shows a sign change of f around the
//! CPU's depth) is a GPU hit; every GPU-confirmed hit (a sign change proved for the
//! whole bundle, so on the CPU's ray too) is a CPU hit; where both are proved the
//! depths agree within the two precisions. The analytic scenes of the CPU's ground
//! truth tests (sphere, R-function box, a shell 1e-5 thin, a tangent touch with no sign
//! change) are hit wherever the analytic ray meets them.
mod common;

use arith_core::Real;
use glam::DVec3;
use model_ir::arith::ArithKind;
use model_ir::camera::Camera;
use model_ir::shape::{Aabb, Shape, View};
use model_sources::formula::Tape;
use tracer::render::{render_kind, RenderOptions};
use tracer::search::ray::clip;
use tracer_gpu::{GpuArith, Status, Tracer};

const N: u32 = 64;

fn gpu_kinds() -> Vec<ArithKind> {
    ArithKind::ALL
        .into_iter()
        .filter(|k| GpuArith::from_name(k.name()).is_some())
        .collect()
}

#[test]
fn gpu_hits_every_pixel_the_cpu_proves_and_agrees_on_depth() {
    let Some(gpu) = common::gpu() else { return };
    let mut models: Vec<_> = ["mitchell", "bretzel", "csg"]
        .into_iter()
        .map(|name| model_sources::find(name).unwrap())
        .collect();
    // Conditionals (a step, a select, an undecided hull across x = 0).
    models.push(model_sources::Model::formula(CONDITIONAL, None).unwrap());
    // The formula language's blends and R-functions, fused when converted.
    models.push(model_sources::Model::formula(BLENDS, None).unwrap());
    for model in &models {
        let name = &model.name;
        let program = model.tape().unwrap();
        for kind in gpu_kinds() {
            for culling in [false, true] {
                let mut opts = RenderOptions::new(model, N, N);
                opts.culling = culling;
                let cpu = render_kind(kind, &model.shape, &opts).unwrap();
                let (frame, cam) = tracer_gpu::render::frame(&opts).unwrap();
                let tracer =
                    Tracer::new(gpu, &program, GpuArith::from_name(kind.name()).unwrap()).unwrap();
                let out = tracer.render(&frame).unwrap();
                let prec = opts.precision(&cam);
                let (mut proved, mut both) = (0, 0);
                for j in 0..N {
                    for i in 0..N {
                        let k = (j * N + i) as usize;
                        let tag = format!("{name} {kind} culling={culling} pixel ({i},{j})");
                        let (o, d) = cam.ray(i, j);
                        let st = out.status[k];
                        if st == Status::Hit {
                            assert!(cpu.hit[k], "{tag}: GPU proved a root the CPU missed");
                        }
                        if !cpu.hit[k] {
                            continue;
                        }
                        let t = cpu.depth[k] as f64;
                        let h = 2.0 * prec.at(t) + 1e-6 * t;
                        let f = |s: f64| {
                            let p = o + d * s;
                            model.shape.eval(p.x, p.y, p.z)
                        };
                        if f(t - h) * f(t + h) >= 0.0 {
                            continue;
                        }
                        proved += 1;
                        assert!(
                            st.is_hit(),
                            "{tag}: CPU hit at {t} (sign change) missed: {st:?}"
                        );
                        if st == Status::Hit {
                            both += 1;
                            let tg = out.depth[k] as f64;
                            let tol = h + frame.eps_abs + frame.eps_rel * t + 1e-5 * t;
                            assert!((tg - t).abs() <= tol, "{tag}: depth {tg} vs CPU {t}");
                        }
                    }
                }
                assert!(
                    proved > 300 && both * 10 > proved * 9,
                    "{name}: {proved} / {both}"
                );
            }
        }
    }
}

const CONDITIONAL: &str =
    "if(x > 0, 1.6 - x^2 - y^2 - z^2, if(y >= 0.2, 1.2 - x^2 - y^2 - z^2, 1 - x^2 - y^2 - z^2))";

const BLENDS: &str = "blend_union(2.2 - x^2 - y^2 - z^2, 0.3 - (x - 1.2)^2 - y^2) \\ \
    blend_intersect(0.6 - x^2 - (z - 1.2)^2, y + 0.3) | (0.1 - x^2 - (y + 1)^2 - z^2)";

struct Ball;
impl Shape for Ball {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        (x.sqr() + y.sqr() + z.sqr()).rsub(1.0)
    }
}
const SHELL: f64 = 1e-5;
struct Shell;
impl Shape for Shell {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        (x.sqr() + y.sqr() + z.sqr() - 1.0)
            .sqr()
            .rsub(SHELL * SHELL)
    }
}
struct Touch;
impl Shape for Touch {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        -(x.sqr() + y.sqr() + z.sqr() - 1.0).sqr()
    }
}
const B: f64 = 0.6;
struct RBox;
impl Shape for RBox {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        use arith_core::rfunc::intersect;
        intersect(
            intersect(x.sqr().rsub(B * B), y.sqr().rsub(B * B)),
            z.sqr().rsub(B * B),
        )
    }
}

fn sphere_hit(o: DVec3, d: DVec3, r: f64) -> (f64, f64) {
    let b = o.dot(d);
    let disc = b * b - (o.length_squared() - r * r);
    (disc, -b - disc.max(0.0).sqrt())
}

fn box_hit(o: DVec3, d: DVec3, b: f64) -> (f64, f64) {
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        let (a, c) = ((-b - o[k]) / d[k], (b - o[k]) / d[k]);
        t0 = t0.max(a.min(c));
        t1 = t1.min(a.max(c));
    }
    (t1 - t0, t0)
}

fn check<S: Shape>(
    name: &str,
    shape: &S,
    analytic: impl Fn(DVec3, DVec3) -> (f64, f64),
    depth_check: bool,
) {
    let Some(gpu) = common::gpu() else { return };
    let pinhole = View {
        eye: DVec3::new(0.7, 0.9, 3.4),
        look_at: DVec3::new(0.05, -0.03, 0.0),
        up: DVec3::Y,
        fov_deg: 40.0,
        ortho: None,
    };
    // Parallel rays from the image plane, across a little more than the domain.
    let parallel = View {
        ortho: Some(3.3),
        ..pinhole
    };
    let dom = Aabb::cube(1.5);
    let program = Tape::record(|x, y, z| shape.eval(x, y, z));
    for (view, kind) in [pinhole, parallel]
        .into_iter()
        .flat_map(|v| gpu_kinds().into_iter().map(move |k| (v, k)))
    {
        let cam = Camera::new(view, N, N);
        let camera = if view.ortho.is_some() {
            "ortho"
        } else {
            "pinhole"
        };
        for (culling, pruning) in [(false, false), (true, true), (false, true)] {
            let mut opts = RenderOptions::for_view(view, dom, N, N);
            opts.culling = culling;
            opts.pruning = pruning;
            let (frame, _) = tracer_gpu::render::frame(&opts).unwrap();
            let t = Tracer::new(gpu, &program, GpuArith::from_name(kind.name()).unwrap()).unwrap();
            let out = t.render(&frame).unwrap();
            let mut hits = 0;
            for j in 0..N {
                for i in 0..N {
                    let k = (j * N + i) as usize;
                    let (o, d) = cam.ray(i, j);
                    let (margin, t_true) = analytic(o, d);
                    if margin > 1e-9 && clip(o, d, &dom, 0.0).is_some() {
                        hits += 1;
                        let tag = format!(
                            "{name} {camera} {kind} culling={culling} pruning={pruning} ({i},{j})"
                        );
                        assert!(
                            out.status[k].is_hit(),
                            "{tag}: analytic hit at {t_true} missed"
                        );
                        if depth_check && margin > 1e-2 && out.status[k] == Status::Hit {
                            // A confirmed hit: the root is within the precision.
                            let tol = frame.eps_abs + frame.eps_rel * t_true + 1e-5 * t_true;
                            {
                                let tg = out.depth[k] as f64;
                                assert!(
                                    (tg - t_true).abs() <= tol,
                                    "{tag}: depth {tg} vs {t_true}"
                                );
                            }
                        }
                    }
                }
            }
            assert!(hits > 500, "{name}: {hits} analytic hits");
        }
    }
}

#[test]
fn analytic_sphere() {
    check("sphere", &Ball, |o, d| sphere_hit(o, d, 1.0), true);
}

#[test]
fn analytic_box() {
    check("box", &RBox, |o, d| box_hit(o, d, B), true);
}

#[test]
fn analytic_thin_shell() {
    check(
        "shell",
        &Shell,
        |o, d| sphere_hit(o, d, (1.0 + SHELL).sqrt()),
        false,
    );
}

#[test]
fn analytic_tangent_touch() {
    check("touch", &Touch, |o, d| sphere_hit(o, d, 1.0), false);
}
