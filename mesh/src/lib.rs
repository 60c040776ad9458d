//! Meshes of implicit surfaces: an octree search pruned by range arithmetic, then dual
//! contouring with vertices constrained to their cells, in any arithmetic and for any
//! [`Shape`] (`tracer mesh` on the command line).
//!
//! The octree's cells and their corners are laid out by [`grid`], below every step.
//!
//! The steps, one module each:
//! - [`octree`]: cells whose range of `f` (the arithmetic's cell form) excludes 0 are
//!   dropped; a leaf whose range holds 0 while its corners agree is probed below the
//!   leaf level for thin features, within a budget, and the leaf level is raised where
//!   one is found (within a work limit, [`RISE_WORK`], and a smaller one,
//!   [`PARTIAL_RISE_WORK`], for a rise short of that level); [`exclusion`]: the tighter
//!   tests a probe puts each sub-cell to first (interval arithmetic, the mean value
//!   form, the monotone reduction);
//! - [`edge_roots`]: each sign-changing edge's crossing by range-based root isolation,
//!   the normal from dual numbers;
//! - [`branches`]: every `min`/`max` branch's plane where branches tie at a crossing
//!   (the sheets of a crease or corner);
//! - [`patches`]: the pieces of surface in a cell (one vertex each, Manifold Dual
//!   Contouring's clustering), [`qef`]: each vertex from its planes, minimised over
//!   the cell's box;
//! - [`merge`]: groups of cells collapsed into one vertex where the planes allow it and
//!   the mesh stays a manifold (fewer triangles on flat parts);
//! - [`dual_contour`]: a quad (two triangles) per sign-changing edge, wound outward;
//! - [`certificate`]: the Plantinga–Vegter topology test per surface cell, and
//!   [`consistency`]: a finer lattice where it fails, for shells thinner than a cell;
//! - [`topology`] and [`self_intersections`]: what the result is (watertight,
//!   manifold, Euler characteristic, intersecting triangle pairs over a BVH);
//! - [`output`]: OBJ, binary PLY and binary STL, written atomically; [`triangles`]: the
//!   mesh itself; [`progress`]: one progress measure over the whole job.
//!
//! The shape is meshed clipped to its domain (`min(f, box)`), so the mesh is closed;
//! where the surface leaves the domain it is capped by the domain's faces. The leaf
//! level is uniform: when a probe finds a feature that needs a finer level, the whole
//! search runs again at that level (crack-free, at the cost of more triangles
//! everywhere). `docs/meshing.md` holds the derivations and what is and is not
//! guaranteed.
//!
//! ## Example
//!
//! ```
//! use model_ir::arith::ArithKind;
//! use model_ir::arith_core::Real;
//! use tracer_mesh::{mesh_kind, MeshOptions};
//! use model_ir::shape::{Aabb, Shape};
//!
//! /// A torus of radii 1 and 0.4 around the y axis (`f >= 0` inside).
//! struct Torus;
//! impl Shape for Torus {
//!     fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
//!         let ring = (x.sqr() + z.sqr()).sqrt().rsub(1.0);
//!         (ring.sqr() + y.sqr()).rsub(0.16)
//!     }
//! }
//!
//! let opts = MeshOptions::new(Aabb::cube(1.5), 5);
//! let m = mesh_kind(ArithKind::Revaa, &Torus, &opts)?;
//! let t = m.mesh.topology();
//! assert!(t.manifold());
//! assert_eq!(t.euler, 0); // a torus: genus 1
//! assert_eq!(m.stats.self_intersections, Some(0));
//! # Ok::<(), tracer_mesh::MeshError>(())
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod branches;
pub mod cell_tape;
pub mod certificate;
pub mod consistency;
pub mod dual_contour;
pub mod edge_roots;
pub mod exclusion;
pub mod grid;
pub mod merge;
pub mod octree;
pub mod output;
pub mod patches;
pub mod progress;
pub mod qef;
pub mod self_intersections;
pub mod topology;
pub mod triangles;

use arith_core::Arithmetic;
use model_ir::arith::ArithKind;
use model_ir::shape::{check_domain, Aabb, Shape};
use progress::Meter;
use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
pub use topology::Topology;
use tracer_kit::progress::Progress;
pub use triangles::Mesh;

/// What to mesh and how.
#[derive(Clone, Debug)]
pub struct MeshOptions {
    /// The box meshed (the shape is clipped to it).
    pub domain: Aabb,
    /// `2^depth` cells along the domain's longest side (at least [`MIN_DEPTH`]).
    pub depth: u32,
    /// How deep probes for thin features go, and the finest leaf level they may
    /// ask for (at least `depth`, at most [`grid::MAX_DEPTH`]).
    pub max_depth: u32,
    /// Evaluate the Plantinga–Vegter certificate of each surface cell.
    pub certify: bool,
    /// Count self-intersecting triangle pairs after meshing.
    pub check_self_intersections: bool,
    /// Give the QEF the planes of every `min`/`max` branch tied at a crossing
    /// ([`branches`]), so creases and corners of CSG are kept (off: one plane per
    /// crossing, as fidget's mesher).
    pub branch_planes: bool,
    /// Merge groups of cells into one vertex where it fits their planes within this
    /// share of a leaf cell and keeps the mesh a manifold ([`merge`]); `None`: no
    /// merging, one vertex per piece of surface per leaf.
    pub merge: Option<f64>,
    /// Refuse (with [`MeshError::TooLarge`]) a depth whose estimated memory
    /// ([`estimate_bytes`]) exceeds this many bytes, and keep the leaf level that thin
    /// features ask for within it (`MeshStats::level_wanted` then says so).
    pub memory_limit: Option<u64>,
    /// Progress reports (units: octree subtrees and chunks of edges and cells).
    pub progress: Option<Arc<dyn Progress>>,
    /// Stop (with [`MeshError::Cancelled`]) once this flag is set.
    pub cancel: Option<Arc<AtomicBool>>,
}

/// The shallowest depth accepted.
pub const MIN_DEPTH: u32 = 2;

/// The default largest distance of a merged vertex from its cells' planes, in leaf
/// cells.
pub const DEFAULT_MERGE_ERROR: f64 = 0.01;

/// Extra levels that probes go below the depth by default.
pub const DEFAULT_EXTRA_DEPTH: u32 = 4;

/// The share of the progress bar left that each octree search takes.
const SEARCH_SHARE: f64 = 0.4;

/// The share of the progress bar left that the contouring takes.
const CONTOUR_SHARE: f64 = 0.85;

/// The leaf level rises for thin features only while the contouring's estimated work,
/// surface cells times the shape's instructions per evaluation, stays within this
/// (seconds: a rotated cube's rise from level 5 to 9, about 560,000 surface cells of
/// a 30-instruction formula, takes some 6 s on two cores): small meshes of short
/// formulas refine freely, long tapes keep the depth asked for and report what they
/// leave.
pub const RISE_WORK: u64 = 1 << 24;

/// The work limit of a rise short of the level the features ask for
/// ([`RISE_WORK`] is that of a rise to it): the uniform rise multiplies the whole
/// mesh's work by four a level while the deepest features stay unresolved, so it is
/// held to a sixteenth of the limit, the cost of two levels fewer.
pub const PARTIAL_RISE_WORK: u64 = RISE_WORK >> 4;

/// The instructions per evaluation assumed for a shape that is not a tape.
pub const SHAPE_INSTRUCTIONS: u64 = 32;

impl MeshOptions {
    /// Options for `domain` at `depth`: probes to `depth + 4` (at most
    /// [`grid::MAX_DEPTH`]), certificate and self-intersection check on, no limit.
    pub fn new(domain: Aabb, depth: u32) -> Self {
        MeshOptions {
            domain,
            depth,
            max_depth: (depth + DEFAULT_EXTRA_DEPTH).min(grid::MAX_DEPTH),
            certify: true,
            check_self_intersections: true,
            branch_planes: true,
            merge: Some(DEFAULT_MERGE_ERROR),
            memory_limit: None,
            progress: None,
            cancel: None,
        }
    }

    /// `Ok` when the options can be meshed: a valid domain, `MIN_DEPTH <= depth <=
    /// max_depth <= MAX_DEPTH`, and the depth's estimate within the memory limit.
    pub fn check(&self) -> Result<(), MeshError> {
        check_domain(&self.domain).map_err(MeshError::Options)?;
        let max = grid::MAX_DEPTH;
        if !(MIN_DEPTH..=max).contains(&self.depth) {
            return Err(MeshError::Options(format!(
                "depth {}: must be in {MIN_DEPTH}..={max}",
                self.depth
            )));
        }
        if !(self.depth..=max).contains(&self.max_depth) {
            return Err(MeshError::Options(format!(
                "max depth {}: must be in {}..={max} (at least the depth)",
                self.max_depth, self.depth
            )));
        }
        self.check_memory(self.depth, estimate_bytes(self.depth))
    }

    fn check_memory(&self, level: u32, bytes: u64) -> Result<(), MeshError> {
        match self.memory_limit {
            Some(limit) if bytes > limit => Err(MeshError::TooLarge {
                level,
                bytes,
                limit,
            }),
            _ => Ok(()),
        }
    }
}

/// Bytes per surface cell (cell keys and masks, corners, edges and their crossings,
/// vertices, triangles, the topology check's maps), measured with some headroom.
pub const BYTES_PER_CELL: u64 = 800;

/// The memory a mesh at leaf level `depth` is estimated to need: a surface crossing
/// `24 * 4^depth` cells (six times a sphere filling the domain) at [`BYTES_PER_CELL`].
pub fn estimate_bytes(depth: u32) -> u64 {
    24u64
        .saturating_mul(1u64 << (2 * depth.min(31)))
        .saturating_mul(BYTES_PER_CELL)
}

/// Why there is no mesh.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MeshError {
    /// Invalid options (the message says which).
    Options(String),
    /// The depth needs more memory than the limit.
    TooLarge {
        /// The leaf level asked for.
        level: u32,
        /// Its estimate in bytes.
        bytes: u64,
        /// The limit in bytes.
        limit: u64,
    },
    /// The cancel flag was set.
    Cancelled,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::Options(m) => f.write_str(m),
            MeshError::TooLarge {
                level,
                bytes,
                limit,
            } => write!(
                f,
                "a mesh at depth {level} needs about {:.1} GiB, more than the {:.1} GiB \
                 available",
                *bytes as f64 / GIB,
                *limit as f64 / GIB
            ),
            MeshError::Cancelled => f.write_str("cancelled"),
        }
    }
}

const GIB: f64 = (1u64 << 30) as f64;

impl std::error::Error for MeshError {}

impl From<MeshError> for String {
    fn from(e: MeshError) -> String {
        e.to_string()
    }
}

/// Counters of one meshing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshStats {
    /// Wall time of the whole meshing.
    pub wall: Duration,
    /// Wall time of the checks after meshing (topology and self-intersections).
    pub check_wall: Duration,
    /// The depth asked for.
    pub depth: u32,
    /// The leaf level used: the depth, or deeper where probes found thin features.
    pub level: u32,
    /// The deepest leaf level that thin features asked for (above `level` where the
    /// memory limit held it back; 0 when none asked).
    pub level_wanted: u32,
    /// Leaves with a sign change whose finer lattice showed another topology than
    /// their corners (summed over the searches).
    pub finer_cells: u64,
    /// The deepest level probes could go to.
    pub max_depth: u32,
    /// Octree cells whose range was evaluated (all searches, probes included).
    pub cells_visited: u64,
    /// Cells dropped because their range excluded 0.
    pub cells_pruned: u64,
    /// Cells evaluated by probes below the leaf level.
    pub cells_probed: u64,
    /// Cells whose shape was specialised.
    pub cells_specialised: u64,
    /// Cells below the leaf level where the mesher cannot say whether surface is
    /// there: probes that reached the maximum depth with 0 still in the range and no
    /// sign change, sub-cells and finer lattices that the probe budget left, and
    /// leaves whose features need a finer leaf level than the budget allowed.
    pub unresolved_at_max_depth: u64,
    /// The box around the unresolved cells (`None` when there are none).
    pub unresolved_box: Option<Aabb>,
    /// Cells that interval arithmetic, the mean value form or the monotone reduction
    /// excluded ([`exclusion`]): leaves whose arithmetic's range held 0, and sub-cells
    /// of probes (interval arithmetic, the cheapest, is tried before the arithmetic's
    /// range there).
    pub cells_excluded: u64,
    /// Leaves with a sign change (the cells contoured).
    pub surface_cells: u64,
    /// Surface cells holding several pieces of surface (one vertex each).
    pub multi_piece_cells: u64,
    /// Vertices removed by merging cells.
    pub merged_vertices: u64,
    /// Sign-changing edges.
    pub crossings: u64,
    /// Edges with several sign-changing roots (finer than the grid).
    pub multi_root_edges: u64,
    /// Range evaluations of root isolation on edges.
    pub edge_evals: u64,
    /// Point evaluations (corner signs).
    pub point_evals: u64,
    /// Surface cells certified by the Plantinga–Vegter test (`None`: not evaluated).
    pub certified_cells: Option<u64>,
    /// The mesh's topology.
    pub topology: Topology,
    /// Intersecting triangle pairs (`None`: not checked).
    pub self_intersections: Option<u64>,
}

impl MeshStats {
    /// Every counter under its field name (in `--stats json` and Python's stats), in
    /// this order; times and the unresolved cells' box are not counters.
    pub fn counters(&self) -> [(&'static str, u64); 26] {
        let (s, t) = (self, &self.topology);
        [
            ("depth", s.depth as u64),
            ("level", s.level as u64),
            ("level_wanted", s.level_wanted as u64),
            ("finer_cells", s.finer_cells),
            ("max_depth", s.max_depth as u64),
            ("cells_visited", s.cells_visited),
            ("cells_pruned", s.cells_pruned),
            ("cells_probed", s.cells_probed),
            ("cells_specialised", s.cells_specialised),
            ("cells_excluded", s.cells_excluded),
            ("unresolved_at_max_depth", s.unresolved_at_max_depth),
            ("surface_cells", s.surface_cells),
            ("multi_piece_cells", s.multi_piece_cells),
            ("merged_vertices", s.merged_vertices),
            ("crossings", s.crossings),
            ("multi_root_edges", s.multi_root_edges),
            ("edge_evals", s.edge_evals),
            ("point_evals", s.point_evals),
            ("vertices", t.vertices),
            ("triangles", t.faces),
            ("components", t.components),
            ("boundary_edges", t.boundary_edges),
            ("non_manifold_edges", t.non_manifold_edges),
            ("non_manifold_vertices", t.non_manifold_vertices),
            ("misoriented_edges", t.misoriented_edges),
            ("degenerate_triangles", t.degenerate),
        ]
    }
    /// The share of surface cells certified, in `[0, 1]`.
    pub fn certified_share(&self) -> Option<f64> {
        let c = self.certified_cells?;
        Some(if self.surface_cells == 0 {
            1.0
        } else {
            c as f64 / self.surface_cells as f64
        })
    }
}

impl fmt::Display for MeshStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let t = &self.topology;
        let yes = |b: bool| if b { "yes" } else { "no" };
        writeln!(
            f,
            "wall time          {:.3} s ({:.3} s of checks)",
            self.wall.as_secs_f64(),
            self.check_wall.as_secs_f64()
        )?;
        writeln!(
            f,
            "levels             depth {}, leaf level {}, probes to {}",
            self.depth, self.level, self.max_depth
        )?;
        writeln!(
            f,
            "octree cells       {} visited, {} pruned, {} probed, {} excluded by tighter tests, {} specialised",
            self.cells_visited,
            self.cells_pruned,
            self.cells_probed,
            self.cells_excluded,
            self.cells_specialised
        )?;
        writeln!(
            f,
            "unresolved         {} cells{}; {} leaves finer than their corners{}",
            self.unresolved_at_max_depth,
            self.unresolved_box
                .map_or(String::new(), |b| format!(" in {}", box_text(&b))),
            self.finer_cells,
            if self.level_wanted > self.level {
                format!("; level {} wanted, held back by memory", self.level_wanted)
            } else {
                String::new()
            }
        )?;
        writeln!(
            f,
            "surface cells      {} ({} with several pieces); {} vertices merged away",
            self.surface_cells, self.multi_piece_cells, self.merged_vertices
        )?;
        writeln!(
            f,
            "edges              {} crossings, {} with several roots, {} range evaluations",
            self.crossings, self.multi_root_edges, self.edge_evals
        )?;
        if let (Some(c), Some(s)) = (self.certified_cells, self.certified_share()) {
            writeln!(f, "certified cells    {c} ({:.1}%)", 100.0 * s)?;
        }
        writeln!(
            f,
            "mesh               {} vertices, {} triangles, {} components, Euler characteristic {}",
            t.vertices, t.faces, t.components, t.euler
        )?;
        writeln!(
            f,
            "watertight         {} ({} boundary edges)",
            yes(t.watertight()),
            t.boundary_edges
        )?;
        writeln!(
            f,
            "manifold           {} ({} non-manifold edges, {} pinched vertices, {} misoriented edges)",
            yes(t.manifold()),
            t.non_manifold_edges,
            t.non_manifold_vertices,
            t.misoriented_edges
        )?;
        writeln!(f, "degenerate         {} triangles", t.degenerate)?;
        match self.self_intersections {
            Some(n) => write!(f, "self-intersections {n} triangle pairs"),
            None => write!(f, "self-intersections not checked"),
        }
    }
}

/// A box as `[x0, x1] x [y0, y1] x [z0, z1]`, four significant digits.
pub fn box_text(b: &Aabb) -> String {
    let (lo, hi) = (b.min, b.max);
    format!(
        "[{:.4}, {:.4}] x [{:.4}, {:.4}] x [{:.4}, {:.4}]",
        lo.x, hi.x, lo.y, hi.y, lo.z, hi.z
    )
}

/// A mesh and how it was made.
#[derive(Clone, Debug, Default)]
pub struct MeshResult {
    /// The mesh.
    pub mesh: Mesh,
    /// The counters.
    pub stats: MeshStats,
}

/// Meshes `shape` over `opts.domain` in the arithmetic `A`.
///
/// Errors: invalid options, a leaf level over the memory limit, or cancellation.
pub fn mesh<A: Arithmetic, S: Shape>(
    shape: &S,
    opts: &MeshOptions,
) -> Result<MeshResult, MeshError> {
    opts.check()?;
    let start = Instant::now();
    let meter = Meter::new(opts.progress.clone());
    let res = run::<A, S>(shape, opts, &meter);
    meter.finish();
    let mut res = res?;
    res.stats.wall = start.elapsed();
    Ok(res)
}

/// [`mesh`] with the arithmetic chosen at run time.
pub fn mesh_kind<S: Shape>(
    kind: ArithKind,
    shape: &S,
    opts: &MeshOptions,
) -> Result<MeshResult, MeshError> {
    model_ir::with_arith!(kind, A => mesh::<A, S>(shape, opts))
}

fn run<A: Arithmetic, S: Shape>(
    shape: &S,
    opts: &MeshOptions,
    meter: &Meter,
) -> Result<MeshResult, MeshError> {
    let cancel = opts.cancel.as_deref();
    let mut stats = MeshStats {
        depth: opts.depth,
        max_depth: opts.max_depth,
        ..MeshStats::default()
    };
    let (level, cells, tapes, certified) = search::<A, S>(shape, opts, meter, &mut stats)?;
    let grid = grid::Grid::new(&opts.domain, level);
    let contour = dual_contour::Contour {
        shape,
        domain: opts.domain,
        grid,
        level,
        branch_planes: opts.branch_planes,
        merge_error: opts.merge.map(|e| e * grid.cell_size(level)),
        cancel,
    };
    meter.phase("contouring", CONTOUR_SHARE, 0);
    let (mesh, c) = contour
        .run::<A>(&cells, &tapes, meter)
        .ok_or(MeshError::Cancelled)?;
    stats.level = level;
    stats.surface_cells = c.cells;
    stats.multi_piece_cells = c.multi_piece_cells;
    stats.merged_vertices = c.merged_vertices;
    stats.crossings = c.crossings;
    stats.multi_root_edges = c.multi_root_edges;
    stats.edge_evals = c.edge_evals;
    stats.point_evals += c.corners;
    if opts.certify {
        // The search certified every surface cell on its way.
        stats.certified_cells = Some(certified.iter().filter(|&&c| c).count() as u64);
    }
    if cancelled(cancel) {
        return Err(MeshError::Cancelled);
    }
    meter.phase("checks", 1.0, 1);
    let checks = Instant::now();
    // The topology is sequential: it runs beside the parallel pair count.
    let (topology, pairs) = rayon::join(
        || mesh.topology(),
        || {
            opts.check_self_intersections
                .then(|| mesh.self_intersections())
        },
    );
    stats.topology = topology;
    stats.self_intersections = pairs;
    stats.check_wall = checks.elapsed();
    meter.tick(1);
    if cancelled(cancel) {
        return Err(MeshError::Cancelled);
    }
    Ok(MeshResult { mesh, stats })
}

fn cancelled(c: Option<&AtomicBool>) -> bool {
    c.is_some_and(|c| c.load(Ordering::Relaxed))
}

/// The leaf level, its surface cells, their value tapes and certificates.
type Leaves<S> = (u32, Vec<[u32; 3]>, Vec<cell_tape::CellTape<S>>, Vec<bool>);

/// The octree search, raised to the level that thin features need within the memory
/// limit and the work budget ([`RISE_WORK`]): the leaf level and its surface cells.
fn search<A: Arithmetic, S: Shape>(
    shape: &S,
    opts: &MeshOptions,
    meter: &Meter,
    stats: &mut MeshStats,
) -> Result<Leaves<S>, MeshError> {
    let mut level = opts.depth;
    loop {
        let tree = octree::Octree {
            shape,
            domain: opts.domain,
            grid: grid::Grid::new(&opts.domain, level),
            level,
            max_depth: opts.max_depth,
            cancel: opts.cancel.as_deref(),
        };
        meter.phase(
            &format!("search, level {level}"),
            SEARCH_SHARE,
            tree.tasks(),
        );
        let d = tree.search::<A>(&|n| meter.tick(n));
        if d.cancelled {
            return Err(MeshError::Cancelled);
        }
        stats.cells_visited += d.visited;
        stats.cells_pruned += d.pruned;
        stats.cells_probed += d.probed;
        stats.cells_specialised += d.specialised;
        stats.cells_excluded += d.excluded;
        stats.point_evals += d.point_evals;
        stats.finer_cells += d.finer;
        let cells = d.cells.len().max(1) as u64;
        let cost = shape
            .tape_len()
            .map_or(SHAPE_INSTRUCTIONS, |n| n.max(1) as u64);
        // Surface cells grow four-fold per level: the deepest level within the limits.
        let fits = |l: u32, work: u64| {
            let grown = cells.saturating_mul(1u64 << (2 * (l - level)));
            let bytes = grown.saturating_mul(BYTES_PER_CELL);
            opts.memory_limit.is_none_or(|m| bytes <= m) && grown.saturating_mul(cost) <= work
        };
        // The level the features ask for within the work limit; a level short of it
        // (which leaves them unresolved all the same) within a sixteenth of it only.
        let next = if d.needs > level && fits(d.needs, RISE_WORK) {
            Some(d.needs)
        } else {
            (level + 1..d.needs)
                .rev()
                .find(|&l| fits(l, PARTIAL_RISE_WORK))
        };
        if let Some(next) = next {
            stats.level_wanted = stats.level_wanted.max(d.needs);
            level = next;
            continue;
        }
        // Features that need a finer level than the limits allow stay unresolved.
        let grid = grid::Grid::new(&opts.domain, level);
        let held: Vec<Aabb> = d
            .deeper
            .iter()
            .filter(|e| e.0 > level)
            .map(|e| grid.cell_box(level, e.1))
            .collect();
        if !held.is_empty() {
            stats.level_wanted = stats.level_wanted.max(d.needs);
        }
        stats.unresolved_at_max_depth = d.unresolved + held.len() as u64;
        stats.unresolved_box = held
            .into_iter()
            .fold(d.unresolved_box, |u, b| octree::union(u, Some(b)));
        return Ok((level, d.cells, d.tapes, d.certified));
    }
}
