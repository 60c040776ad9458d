//! The mesher against ground truth: the topology of analytic shapes (Euler
//! characteristic `2 - 2g` per component, components), closed consistently wound
//! manifolds, no degenerate or intersecting triangles, vertices on the surface, sharp
//! corners kept, the enclosed volume, a shell thinner than a cell, every arithmetic,
//! and options that never panic.

use arith_core::Real;
use glam::DVec3;
use model_ir::arith::ArithKind;
use model_ir::shape::{Aabb, Shape};
use proptest::prelude::*;
use tracer_mesh::grid::Grid;
use tracer_mesh::{mesh_kind, Mesh, MeshOptions, MeshResult};

fn run<S: Shape>(shape: &S, domain: Aabb, depth: u32) -> MeshResult {
    let opts = MeshOptions::new(domain, depth);
    mesh_kind(ArithKind::Revaa, shape, &opts).expect("mesh")
}

/// A closed, consistently wound 2-manifold without degenerate or intersecting
/// triangles, with Euler characteristic `euler` and `components` components.
fn assert_closed(res: &MeshResult, euler: i64, components: u64) {
    let t = res.stats.topology;
    assert!(t.faces > 0, "empty mesh");
    assert_eq!(t.boundary_edges, 0, "{t:?}");
    assert_eq!(t.non_manifold_edges, 0, "{t:?}");
    assert_eq!(t.misoriented_edges, 0, "{t:?}");
    assert_eq!(t.non_manifold_vertices, 0, "{t:?}");
    assert_eq!(t.degenerate, 0, "{t:?}");
    assert_eq!((t.euler, t.components), (euler, components), "{t:?}");
    assert_eq!(res.stats.self_intersections, Some(0));
}

/// The volume the mesh encloses (divergence theorem; positive for outward winding).
fn volume(m: &Mesh) -> f64 {
    m.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| DVec3::from(m.vertices[i as usize]));
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// The largest `|f| / |grad f|` over the vertices (a first-order distance).
fn max_distance<S: Shape>(shape: &S, m: &Mesh) -> f64 {
    m.vertices
        .iter()
        .map(|v| {
            let d = shape.eval(
                arith_core::dual::Dual::var(v[0], 0),
                arith_core::dual::Dual::var(v[1], 1),
                arith_core::dual::Dual::var(v[2], 2),
            );
            d.v.abs() / DVec3::from(d.g).length()
        })
        .fold(0.0, f64::max)
}

fn cell(domain: &Aabb, depth: u32) -> f64 {
    Grid::new(domain, depth).cell_size(depth)
}

struct Ball {
    c: DVec3,
    r: f64,
}
impl Shape for Ball {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        ((x - self.c.x).sqr() + (y - self.c.y).sqr() + (z - self.c.z).sqr()).rsub(self.r * self.r)
    }
}

/// A torus of radii `big` and `small` around the y axis.
struct Torus {
    big: f64,
    small: f64,
}
impl Shape for Torus {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        let ring = (x.sqr() + z.sqr()).sqrt().rsub(self.big);
        (ring.sqr() + y.sqr()).rsub(self.small * self.small)
    }
}

/// The cube `[-a, a]^3`.
struct Cube(f64);
impl Shape for Cube {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        x.abs()
            .rsub(self.0)
            .min(&y.abs().rsub(self.0))
            .min(&z.abs().rsub(self.0))
    }
}

#[test]
fn a_sphere_is_a_sphere() {
    let ball = Ball {
        c: DVec3::new(0.03, -0.02, 0.01),
        r: 0.8,
    };
    let d = Aabb::cube(1.0);
    let res = run(&ball, d, 5);
    assert_closed(&res, 2, 1);
    // Outward winding: the enclosed volume is positive, and close to the ball's.
    let v = volume(&res.mesh);
    let exact = 4.0 / 3.0 * std::f64::consts::PI * 0.8f64.powi(3);
    assert!((v - exact).abs() < 0.02 * exact, "volume {v} vs {exact}");
    // Vertices within a small share of a cell of the surface.
    let h = cell(&d, 5);
    let dist = max_distance(&ball, &res.mesh);
    assert!(dist < 0.1 * h, "vertex {dist} from the sphere, cell {h}");
    // Every surface cell of a sphere this fine is certified by Plantinga-Vegter.
    assert_eq!(res.stats.certified_share(), Some(1.0));
}

#[test]
fn a_torus_has_euler_characteristic_0() {
    let t = Torus {
        big: 0.6,
        small: 0.25,
    };
    let res = run(&t, Aabb::cube(1.0), 5);
    assert_closed(&res, 0, 1);
}

#[test]
fn a_cube_with_a_hole_has_euler_characteristic_0_and_keeps_its_corners() {
    struct Holed;
    impl Shape for Holed {
        fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
            // A cylinder of radius 0.25 along z removed from the cube [-0.6, 0.6]^3.
            let hole = (x.sqr() + y.sqr()) - 0.0625;
            Cube(0.6).eval(x, y, z).min(&hole)
        }
    }
    let d = Aabb::cube(1.0);
    let res = run(&Holed, d, 5);
    assert_closed(&res, 0, 1);
    let h = cell(&d, 5);
    for i in 0..8 {
        let corner = DVec3::new(
            if i & 1 == 0 { -0.6 } else { 0.6 },
            if i & 2 == 0 { -0.6 } else { 0.6 },
            if i & 4 == 0 { -0.6 } else { 0.6 },
        );
        let nearest = res
            .mesh
            .vertices
            .iter()
            .map(|v| (DVec3::from(*v) - corner).length())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 0.1 * h,
            "corner {corner}: nearest vertex {nearest}, cell {h}"
        );
    }
}

#[test]
fn a_sphere_with_two_handles_has_euler_characteristic_minus_2() {
    struct TwoHoles;
    impl Shape for TwoHoles {
        fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
            // A flattened ellipsoid pierced along y by two cylinders of radius 0.25.
            let e = ((x.clone() * (1.0 / 0.9)).sqr()
                + (y.clone() * (1.0 / 0.3)).sqr()
                + (z.clone() * (1.0 / 0.6)).sqr())
            .rsub(1.0);
            let h1 = (x.clone() - 0.42).sqr() + z.clone().sqr() - 0.04;
            let h2 = (x + 0.42).sqr() + z.sqr() - 0.04;
            e.min(&h1).min(&h2)
        }
    }
    let res = run(&TwoHoles, Aabb::cube(1.0), 5);
    assert_closed(&res, -2, 1);
}

#[test]
fn separated_spheres_give_as_many_components() {
    struct Three;
    impl Shape for Three {
        fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
            let ball = |c: DVec3| Ball { c, r: 0.2 }.eval(x.clone(), y.clone(), z.clone());
            ball(DVec3::new(-0.6, 0.0, 0.0))
                .max(&ball(DVec3::new(0.1, 0.5, 0.0)))
                .max(&ball(DVec3::new(0.4, -0.4, 0.3)))
        }
    }
    let res = run(&Three, Aabb::cube(1.0), 5);
    assert_closed(&res, 6, 3);
}

#[test]
fn a_shell_a_fifth_of_a_cell_thick_keeps_both_sheets() {
    let d = Aabb::cube(1.0);
    let depth = 3;
    let t = cell(&d, depth) / 5.0;
    struct Shell(f64);
    impl Shape for Shell {
        fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
            let r = (x.sqr() + y.sqr() + z.sqr()).sqrt();
            (r - 0.7).abs().rsub(self.0 / 2.0)
        }
    }
    let res = run(&Shell(t), d, depth);
    assert!(
        res.stats.level > depth,
        "the leaf level rose: {:?}",
        res.stats
    );
    // Two spheres: the shell's outer and inner sheets.
    assert_closed(&res, 4, 2);
    // The peers' behaviour, without looking below the depth: the corners that fall in
    // the shell give blobs, not the two sheets.
    let mut flat = MeshOptions::new(d, depth);
    flat.max_depth = depth;
    let res = mesh_kind(ArithKind::Revaa, &Shell(t), &flat).unwrap();
    let t = res.stats.topology;
    assert_ne!((t.euler, t.components), (4, 2), "{t:?}");
}

#[test]
fn every_arithmetic_meshes_a_torus_alike() {
    let t = Torus {
        big: 0.6,
        small: 0.3,
    };
    for kind in ArithKind::ALL {
        let opts = MeshOptions::new(Aabb::cube(1.0), 4);
        let res = mesh_kind(kind, &t, &opts).unwrap();
        assert_closed(&res, 0, 1);
        assert!(res.stats.cells_pruned > 0, "{kind}");
    }
}

#[test]
fn a_surface_leaving_the_domain_is_capped() {
    // A ball of radius 1.2 in [-1, 1]^3: the domain's faces close it.
    let ball = Ball {
        c: DVec3::ZERO,
        r: 1.2,
    };
    let res = run(&ball, Aabb::cube(1.0), 4);
    assert_closed(&res, 2, 1);
    for v in &res.mesh.vertices {
        assert!(
            v.iter().all(|c| c.abs() <= 1.0 + 1e-9),
            "{v:?} outside the domain"
        );
    }
}

#[test]
fn cancelling_stops_with_an_error() {
    let mut opts = MeshOptions::new(Aabb::cube(1.0), 6);
    let flag = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(true));
    opts.cancel = Some(flag);
    let ball = Ball {
        c: DVec3::ZERO,
        r: 0.5,
    };
    let r = mesh_kind(ArithKind::Ia, &ball, &opts);
    assert_eq!(r.err(), Some(tracer_mesh::MeshError::Cancelled));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Options never panic: they are meshed or refused with a message.
    #[test]
    fn options_never_panic(
        depth in 0u32..40,
        extra in 0u32..40,
        lo in prop::array::uniform3(-1e300f64..1e300),
        size in prop::array::uniform3(prop_oneof![Just(0.0), Just(f64::INFINITY), Just(f64::NAN), 1e-300f64..1e300]),
        limit in prop::option::of(0u64..u64::MAX),
    ) {
        let min = DVec3::from(lo);
        let domain = Aabb::new(min, min + DVec3::from(size));
        let mut opts = MeshOptions::new(domain, depth);
        opts.max_depth = depth.saturating_add(extra);
        opts.memory_limit = limit;
        if opts.check().is_ok() {
            // Only cheap ones are run.
            prop_assume!(depth <= 4 && opts.max_depth <= 6);
            let ball = Ball { c: (domain.min + domain.max) * 0.5, r: (domain.max - domain.min).min_element() / 3.0 };
            let r = mesh_kind(ArithKind::Ia, &ball, &opts);
            prop_assert!(r.is_ok(), "{:?}", r.err());
        }
    }
}
