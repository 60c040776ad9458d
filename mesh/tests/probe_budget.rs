//! Probes below the depth stay within their budget: a CSG model meshes with the
//! default options within a number of probed cells bounded by the mesh's size, and a
//! shape with more thin features than the budget can look into still gives a closed
//! mesh, with the cells left unresolved counted and boxed. Counts, never times.

use arith_core::Real;
use glam::DVec3;
use model_ir::arith::ArithKind;
use model_ir::shape::{Aabb, Shape};
use tracer_mesh::octree::{PROBE_FLOOR, PROBE_PER_CELL};
use tracer_mesh::{mesh_kind, MeshOptions, MeshResult, RISE_WORK, SHAPE_INSTRUCTIONS};

/// Subtrees the search hands to threads (level 3 of the octree).
const TASKS: u64 = 512;

/// Closed, consistently wound, manifold.
fn assert_closed(res: &MeshResult) {
    let t = res.stats.topology;
    assert!(t.faces > 0, "empty mesh");
    assert!(t.manifold(), "{t:?}");
    assert_eq!(t.degenerate, 0, "{t:?}");
}

/// The most sub-cells the probes of a meshing may evaluate: per search, each task's
/// floor and its share per surface cell (the last search's cells bound every
/// earlier, coarser one's).
fn probe_bound(res: &MeshResult) -> u64 {
    let s = &res.stats;
    let searches = (s.level - s.depth + 1) as u64;
    searches * (TASKS * PROBE_FLOOR + PROBE_PER_CELL * s.surface_cells)
}

#[test]
fn a_csg_model_meshes_with_the_default_options_within_its_budget() {
    let m = model_sources::find("csg").expect("csg model");
    let depth = 5;
    let opts = MeshOptions::new(m.domain, depth);
    assert_eq!(opts.max_depth, depth + 4);
    let res = mesh_kind(ArithKind::Revaa, &m.shape, &opts).expect("mesh");
    assert_closed(&res);
    let s = res.stats;
    assert!(s.cells_probed <= probe_bound(&res), "{s:?}");
    // The leaf level rose only within the work budget.
    let cost = m.shape.tape_len().map_or(SHAPE_INSTRUCTIONS, |n| n as u64);
    assert!(
        s.level == depth || s.surface_cells * cost <= 2 * RISE_WORK,
        "{s:?}"
    );
}

/// A ball, and beside it a lattice of blobs a few hundredths of a cell across, one
/// in every leaf of a box at depth 5, too small for probes to find even at the
/// maximum depth.
struct Blobs {
    /// The lattice's spacing (a leaf cell).
    a: f64,
}

impl Shape for Blobs {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        let ball = ((x.clone() + 0.5).sqr() + (y.clone() + 0.5).sqr() + (z.clone() + 0.5).sqr())
            .rsub(0.09);
        let k = std::f64::consts::PI / self.a;
        // Blobs at the lattice points n * a + a / 3 (off the grid's corners).
        let wave = |v: R| ((v - self.a / 3.0) * k).sin().sqr();
        let blobs = (wave(x.clone()) + wave(y.clone()) + wave(z.clone())).rsub(1e-4);
        let region = (x - 0.5)
            .abs()
            .max(&(y - 0.5).abs())
            .max(&(z - 0.5).abs())
            .rsub(0.25);
        ball.max(&blobs.min(&region))
    }
}

#[test]
fn thin_features_beyond_the_budget_leave_a_closed_mesh_and_a_boxed_count() {
    let domain = Aabb::cube(1.0);
    let depth = 5;
    let a = tracer_mesh::grid::Grid::new(&domain, depth).cell_size(depth);
    let opts = MeshOptions::new(domain, depth);
    let res = mesh_kind(ArithKind::Revaa, &Blobs { a }, &opts).expect("mesh");
    assert_closed(&res);
    let s = res.stats;
    assert_eq!(s.topology.components, 1, "the ball alone: {s:?}");
    assert!(s.unresolved_at_max_depth > 0, "{s:?}");
    assert!(s.cells_probed <= probe_bound(&res), "{s:?}");
    // The box around the unresolved cells reaches the blobs.
    let b = s.unresolved_box.expect("a box around the unresolved cells");
    let (lo, hi) = (DVec3::splat(0.25), DVec3::splat(0.75));
    assert!(
        b.max.cmpge(lo).all() && b.min.cmple(hi).all(),
        "{b:?} misses the blobs' box"
    );
}
