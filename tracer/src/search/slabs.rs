//! Image-space tiles by depth slabs: the default search of `tracer render`.
//!
//! An image tile's rays are cut by depth (along `forward`) into slabs, and each
//! tile-slab, the box of its rays' points at those depths ([`Culler::box_of`]), is put
//! to one interval evaluation; the tile-slabs of one level go to the lane kernel in one
//! batch ([`Shape::eval_batch`]). Front to back, a tile-slab whose range excludes 0
//! holds no root of any of its rays and is skipped; one that does not is specialised to
//! its box from that same evaluation's trace ([`Shape::eval_boxes_traced`],
//! [`Shape::specialise_traced`]: no second evaluation, no shared cache) and split into
//! sub-tiles and sub-slabs
//! ([`LEVEL_SPLITS`]), down to leaf tiles whose rays are searched by Algorithm 1
//! ([`super::ray::first_roots_until`], in the render's arithmetic and with its argument pruning) on
//! their piece inside the leaf's slab only. A pixel whose root is found takes no part
//! in deeper slabs, and a tile whose pixels all have theirs visits no deeper slab
//! (occlusion, as fidget's voxel renderer does).
//!
//! Sound: every point of a pixel's ray inside the domain lies in one of the image
//! tile's slabs (they cover the domain's depths, margin included), and the box of a
//! tile-slab holds every point of its rays at its depths (the box is the bundle's, from
//! the corner pixels' rays, widened by a margin far above the rounding), so a skipped
//! tile-slab holds no root of its rays; a specialised shape has the whole shape's sign
//! everywhere in its box, where it is used; and each pixel's pieces are searched in
//! depth order, each after every earlier piece was proved root-free, so the first root
//! found is the first root, within the precision, as Algorithm 1 on the whole ray finds
//! it.

use super::cull::{CullStats, Culler};
use super::ray::{clip_with, Lockstep, RayJob, RayParams, RayStats, Start};
use arith_core::{Arithmetic, Range};
use arith_ia::Interval;
use model_ir::camera::Camera;
use model_ir::shape::{Aabb, Shape};
use model_ir::shape_batch::Batch;
use model_ir::Trace;

/// Below an image tile, each level splits a tile-slab's tile into `n x n` sub-tiles
/// and its slab into `n` sub-slabs (so a tile-slab stays about as deep as it is wide):
/// 64-pixel tiles, then 16, then 8-pixel leaves, as fidget's renderer; the last split,
/// to 4-pixel leaves, only for shapes longer than [`LONG_TAPE`] there.
pub const LEVEL_SPLITS: [u32; 3] = [4, 2, 2];

/// A tile-slab whose shape is longer than this (or is not a tape) takes the last split
/// of [`LEVEL_SPLITS`]: its rays' searches cost more than the interval tests of the
/// smaller boxes that spare some of them (fidget's bear: 27% less CPU, 40% fewer range
/// evaluations along rays; on the colonnade, whose 8-pixel tapes are about 14
/// instructions long, the split costs 18% more).
pub const LONG_TAPE: usize = 64;

/// Tile-slabs down to this level specialise their shape (0: the image tile's slabs);
/// deeper ones search with their parent's. Read from each level's own evaluation, a
/// specialisation costs a backward and a forward pass over the parent: the 8-pixel
/// level pays for itself on long scenes (10000 balls at 256x256, perspective: mean
/// tape per range evaluation 964 -> 307, CPU -30%) and is within noise on fidget's
/// models.
pub const SPECIALISE_LEVELS: usize = 3;

/// The level of the tile-slabs whose hits make a [`HitGroup`] (1: the image tile's
/// slabs' sub-tile-slabs).
pub const GROUP_LEVEL: usize = 1;

/// Tile-slabs the cell-form test ([`Search::cell_test`]) is tried on in an image tile
/// before its share of exclusions decides whether it goes on.
pub const CELL_TEST_TRIAL: u64 = 32;

/// The share of the tile-slabs it is given that the cell-form test must exclude to go
/// on being tried.
pub const CELL_TEST_SHARE: f64 = 0.125;

/// An image tile cut into more slabs than this first tests at most this many runs of
/// consecutive slabs, each specialising the shape for its slabs
/// ([`Search::slab_runs`]).
pub const SLAB_RUN: usize = 8;

/// The most slabs an image tile's depth is cut into.
pub const MAX_SLABS: usize = 512;

/// The depth at which slab `k` of `n` equal slabs of `[s0, s1]` starts (`k = n`: `s1`),
/// the ends exact.
fn slab_edge((s0, s1): (f64, f64), n: u32, k: u32) -> f64 {
    match k {
        0 => s0,
        k if k == n => s1,
        k => s0 + (s1 - s0) * k as f64 / n as f64,
    }
}

/// A tile `[i0, i1) x [j0, j1)` of pixels.
pub type Rect = (u32, u32, u32, u32);

/// What the search of one image tile gives.
#[derive(Default)]
pub struct SlabTile {
    /// One job per pixel whose ray meets the domain: its whole piece inside it.
    pub jobs: Vec<RayJob>,
    /// The pixel (index in the tile, row-major) of each job.
    pub pixel_of: Vec<usize>,
    /// The first roots found, as `(job, distance)`.
    pub hits: Vec<(usize, f64)>,
    /// The ray searches' counters, summed.
    pub rays: RayStats,
    /// The range evaluations of the rays that hit, summed over their pieces.
    pub hit_evals: u64,
    /// The tile-slabs' counters: tested, excluded (culled), specialised.
    pub cells: CullStats,
    /// Whether `stop` ended the search early (the pixels left are misses).
    pub cut: bool,
    /// The hits by the tile-slab of [`GROUP_LEVEL`] they were found in (each group's
    /// hits are contiguous in `hits`, groups in order).
    pub groups: Vec<HitGroup>,
    /// The boxes of the image tile's slabs the groups lie in.
    pub parents: Vec<Aabb>,
}

/// The hits found in one tile-slab: `hits[start..end]` of [`SlabTile::hits`], every
/// one inside `region` (its box), which lies inside `parents[parent]`.
#[derive(Clone, Copy, Debug)]
pub struct HitGroup {
    /// Its first hit's index in [`SlabTile::hits`].
    pub start: usize,
    /// One past its last hit's.
    pub end: usize,
    /// The box of the tile-slab the hits were found in.
    pub region: Aabb,
    /// The index in [`SlabTile::parents`] of the image tile's slab it lies in.
    pub parent: usize,
}

/// What a [`Search`] is generic over without holding it: its arithmetic and shape.
type Marker<A, S> = core::marker::PhantomData<(A, fn(&S))>;

/// One image tile's search in progress.
struct Search<'a, A: Arithmetic, S> {
    culler: &'a Culler,
    params: &'a RayParams,
    specialise: bool,
    stop: &'a (dyn Fn() -> bool + Sync),
    rect: Rect,
    /// Tile width in pixels and the leaves' side.
    tw: usize,
    leaf: u32,
    /// Per pixel: its job, or `u32::MAX` (no ray in the domain, or its root found).
    open: Vec<u32>,
    /// Per leaf block of the tile: its pixels still searched.
    left: Vec<u32>,
    blocks_w: usize,
    /// Per job: `1 / (d . forward)`, and the range evaluations of its pieces so far.
    ic: Vec<f64>,
    evals: Vec<u64>,
    out: SlabTile,
    /// Per level: the boxes of its tile-slabs and their ranges.
    levels: Vec<Boxes>,
    /// The image tile's runs of slabs ([`Search::slab_runs`]), per depth of runs.
    runs: Vec<Boxes>,
    leaf_jobs: Vec<RayJob>,
    leaf_of: Vec<u32>,
    lockstep: Lockstep<A>,
    /// The second test, in the arithmetic's cell form: its batch, group and ranges,
    /// and how many tile-slabs it was tried on and excluded in this tile.
    cell_batch: Batch<A::CellPack>,
    cell_group: Vec<usize>,
    cell_out: Vec<Option<A::Cell>>,
    cell_tries: u64,
    cell_wins: u64,
    _arith: Marker<A, S>,
}

/// The tile-slabs of one visit: their sub-tile and slab, and the boxes' sides.
#[derive(Default)]
struct Boxes {
    which: Vec<(Rect, (f64, f64), Option<Aabb>)>,
    x: Vec<Interval>,
    y: Vec<Interval>,
    z: Vec<Interval>,
    range: Vec<Interval>,
    /// Per range: whether the tile-slab may hold a root (neither test excluded it).
    keep: Vec<bool>,
    /// What the interval evaluation recorded for specialising each tile-slab.
    trace: Trace,
}

impl Boxes {
    fn clear(&mut self) {
        self.which.clear();
        self.x.clear();
        self.y.clear();
        self.z.clear();
    }

    fn push(&mut self, q: Rect, s: (f64, f64), b: Option<Aabb>) {
        self.which.push((q, s, b));
        if let Some(b) = b {
            self.x.push(Interval::from_interval(b.min.x, b.max.x));
            self.y.push(Interval::from_interval(b.min.y, b.max.y));
            self.z.push(Interval::from_interval(b.min.z, b.max.z));
        }
    }
}

/// Searches the tile `rect` of the image of `cam` (rays clipped to `domain`) for each
/// pixel's first root of `shape`, in the arithmetic `A` (see the module doc). `tile` is
/// the image tile's side, from which the levels' sides follow; `specialise` turns region
/// specialisation on; `stop` ends the search early (the result says so). `only`: the
/// pixels to search (indices in the tile, row-major), `None` for all.
#[allow(clippy::too_many_arguments)]
pub fn search_tile<A: Arithmetic, S: Shape>(
    culler: &Culler,
    cam: &Camera,
    domain: &Aabb,
    shape: &S,
    params: &RayParams,
    rect: Rect,
    specialise: bool,
    only: Option<&[usize]>,
    stop: &(dyn Fn() -> bool + Sync),
) -> SlabTile {
    let (i0, j0, i1, j1) = rect;
    let tw = (i1 - i0) as usize;
    let side = (i1 - i0).max(j1 - j0);
    let leaf = side.div_ceil(LEVEL_SPLITS.iter().product()).max(1);
    let blocks_w = tw.div_ceil(leaf as usize);
    let blocks_h = ((j1 - j0) as usize).div_ceil(leaf as usize);
    let mut s = Search::<A, S> {
        culler,
        params,
        specialise: specialise && shape.specialises(),
        stop,
        rect,
        tw,
        leaf,
        open: vec![u32::MAX; tw * (j1 - j0) as usize],
        left: vec![0; blocks_w * blocks_h],
        blocks_w,
        ic: Vec::new(),
        evals: Vec::new(),
        out: SlabTile::default(),
        levels: (0..=LEVEL_SPLITS.len()).map(|_| Boxes::default()).collect(),
        runs: Vec::new(),
        leaf_jobs: Vec::new(),
        leaf_of: Vec::new(),
        lockstep: Lockstep::default(),
        cell_batch: Batch::default(),
        cell_group: Vec::new(),
        cell_out: Vec::new(),
        cell_tries: 0,
        cell_wins: 0,
        _arith: core::marker::PhantomData,
    };
    let pixels: Vec<(u32, u32)> = match only {
        None => (j0..j1)
            .flat_map(|j| (i0..i1).map(move |i| (i, j)))
            .collect(),
        Some(ps) => ps
            .iter()
            .map(|&p| (i0 + (p % tw) as u32, j0 + (p / tw) as u32))
            .collect(),
    };
    s.set_up_rays(cam, domain, &pixels);
    if !s.out.jobs.is_empty() {
        s.image_tile(shape, side);
    }
    s.out
}

impl<A: Arithmetic, S: Shape> Search<'_, A, S> {
    /// The rays of `pixels`, clipped to the domain, as jobs (four at a time,
    /// [`Camera::rays4`]).
    fn set_up_rays(&mut self, cam: &Camera, domain: &Aabb, pixels: &[(u32, u32)]) {
        let (i0, j0, _, _) = self.rect;
        for chunk in pixels.chunks(4) {
            let last = chunk.len() - 1;
            let set = cam.rays4(core::array::from_fn(|l| chunk[l.min(last)]));
            for (&(i, j), &(d, inv, c, ic)) in chunk.iter().zip(&set) {
                let o = cam.origin_at(i as f64 + 0.5, j as f64 + 0.5);
                let Some((t0, t1)) = clip_with(o, d, inv, domain, 0.0) else {
                    continue;
                };
                let k = (j - j0) as usize * self.tw + (i - i0) as usize;
                self.open[k] = self.out.jobs.len() as u32;
                let b = self.block_of(i, j);
                self.left[b] += 1;
                self.out.jobs.push(RayJob {
                    o,
                    d,
                    start: Start::whole(t0, t1),
                    shape: 0,
                    depth: c,
                });
                self.out.pixel_of.push(k);
                self.ic.push(ic);
                self.evals.push(0);
            }
        }
    }

    fn block_of(&self, i: u32, j: u32) -> usize {
        let (i0, j0, _, _) = self.rect;
        ((j - j0) / self.leaf) as usize * self.blocks_w + ((i - i0) / self.leaf) as usize
    }

    /// Whether a pixel of `q` (a union of leaf blocks) is still searched.
    fn any_open(&self, (a0, b0, a1, b1): Rect) -> bool {
        let l = self.leaf;
        let (i0, j0, _, _) = self.rect;
        let (bi0, bi1) = ((a0 - i0) / l, (a1 - i0).div_ceil(l));
        (((b0 - j0) / l)..(b1 - j0).div_ceil(l)).any(|bj| {
            let row = bj as usize * self.blocks_w;
            self.left[row + bi0 as usize..row + bi1 as usize]
                .iter()
                .any(|&n| n > 0)
        })
    }

    /// The image tile's slabs, each about as deep as the tile is wide at the far end of
    /// the domain, front to back.
    fn image_tile(&mut self, shape: &S, side: u32) {
        let (s0, s1) = self.culler.depth_range();
        let width = side as f64 * self.culler.pixel_width_per_depth() * s1;
        let n = if width > 0.0 && (s1 - s0).is_finite() {
            ((s1 - s0) / width).ceil().clamp(1.0, MAX_SLABS as f64) as u32
        } else {
            1
        };
        let rect = self.rect;
        if self.specialise && n as usize > SLAB_RUN {
            self.slab_runs(0, shape, (s0, s1), n);
        } else {
            self.visit(0, &[rect], (s0, s1), n, shape);
        }
    }

    /// The image tile's `n` slabs of `[s0, s1]` in at most [`SLAB_RUN`] runs of
    /// consecutive slabs (a power of [`SLAB_RUN`] each), front to back: each run's box is one interval evaluation, and
    /// the slabs of a run not excluded are visited with the shape specialised to it
    /// (read from that evaluation), in runs again (`depth` + 1) while a run holds more
    /// than [`SLAB_RUN`] slabs. So no slab of the image tile evaluates the whole shape
    /// (a union of 2000 balls at 1024x1024: 60% fewer instructions evaluated).
    fn slab_runs(&mut self, depth: usize, shape: &S, (s0, s1): (f64, f64), n: u32) {
        if self.runs.len() <= depth {
            self.runs.resize_with(depth + 1, Boxes::default);
        }
        let mut bx = std::mem::take(&mut self.runs[depth]);
        bx.clear();
        let q = self.rect;
        let edge = |k: u32| slab_edge((s0, s1), n, k);
        let (a0, b0, a1, b1) = q;
        let dirs = self.culler.bundle_dirs(a0, b0, a1, b1);
        let origins = self.culler.bundle_origins(a0, b0, a1, b1);
        // Runs of a power of SLAB_RUN slabs, at most SLAB_RUN of them.
        let mut run = SLAB_RUN as u32;
        while run * (SLAB_RUN as u32) < n {
            run *= SLAB_RUN as u32;
        }
        for k in (0..n).step_by(run as usize) {
            let s = (edge(k), edge((k + run).min(n)));
            bx.push(q, s, self.culler.box_of(dirs, origins, s).map(|b| b.0));
        }
        shape.eval_boxes_traced(&bx.x, &bx.y, &bx.z, &mut bx.range, &mut bx.trace);
        let tested = bx.range.len() as u64;
        self.out.cells.cells_tested += tested;
        self.out.cells.cell_ops += tested * shape.tape_len().unwrap_or(0) as u64;
        let mut r = 0;
        for (g, &(_, s, b)) in bx.which.iter().enumerate() {
            if b.is_none() {
                continue;
            }
            r += 1;
            if self.out.cut || !self.any_open(q) {
                continue;
            }
            if !bx.range[r - 1].contains_zero() {
                self.out.cells.cells_culled += 1;
                continue;
            }
            self.out.cells.cells_specialised += 1;
            let spec = shape.specialise_traced(&mut bx.trace, r - 1);
            let here = spec.as_ref().unwrap_or(shape);
            match (n - g as u32 * run).min(run) {
                m if m as usize > SLAB_RUN => self.slab_runs(depth + 1, here, s, m),
                m => self.visit(0, &[q], s, m, here),
            }
        }
        self.runs[depth] = bx;
    }

    /// The tile-slabs of the tiles `subs` by the `n` slabs of `slab`, at `level`: each
    /// tile's slabs front to back, each not excluded specialised and split further (or
    /// its rays searched, at the leaves).
    fn visit(&mut self, level: usize, subs: &[Rect], (sa, sb): (f64, f64), n: u32, shape: &S) {
        let mut bx = std::mem::take(&mut self.levels[level]);
        bx.clear();
        let edge = |k: u32| slab_edge((sa, sb), n, k);
        for &q in subs {
            if !self.any_open(q) {
                continue;
            }
            let (a0, b0, a1, b1) = q;
            let dirs = self.culler.bundle_dirs(a0, b0, a1, b1);
            let origins = self.culler.bundle_origins(a0, b0, a1, b1);
            for k in 0..n {
                let s = (edge(k), edge(k + 1));
                let b = self.culler.box_of(dirs, origins, s).map(|b| b.0);
                bx.push(q, s, b);
            }
        }
        let traced = self.specialise && level < SPECIALISE_LEVELS;
        if traced {
            shape.eval_boxes_traced(&bx.x, &bx.y, &bx.z, &mut bx.range, &mut bx.trace);
        } else {
            shape.eval_batch(&bx.x, &bx.y, &bx.z, &mut bx.range);
        }
        let tested = bx.range.len() as u64;
        self.out.cells.cells_tested += tested;
        self.out.cells.cell_ops += tested * shape.tape_len().unwrap_or(0) as u64;
        self.cell_test(shape, &mut bx);
        let mut r = 0;
        for &(q, s, b) in &bx.which {
            if self.out.cut || !self.any_open(q) {
                r += usize::from(b.is_some());
                continue;
            }
            let Some(b) = b else { continue };
            r += 1;
            if !bx.keep[r - 1] {
                self.out.cells.cells_culled += 1;
                continue;
            }
            if (self.stop)() {
                self.out.cut = true;
                continue;
            }
            let spec = traced
                .then(|| {
                    self.out.cells.cells_specialised += 1;
                    shape.specialise_traced(&mut bx.trace, r - 1)
                })
                .flatten();
            let here = spec.as_ref().unwrap_or(shape);
            let first = self.out.hits.len();
            if level + 1 == GROUP_LEVEL {
                self.out.parents.push(b);
            }
            let short =
                level + 1 == LEVEL_SPLITS.len() && here.tape_len().is_some_and(|n| n <= LONG_TAPE);
            match LEVEL_SPLITS.get(level).filter(|_| !short) {
                Some(&m) => {
                    let quads = self.split(q, m);
                    self.visit(level + 1, &quads, s, m, here);
                }
                None => self.search_leaf(q, s, here),
            }
            if level == GROUP_LEVEL && self.out.hits.len() > first {
                self.out.groups.push(HitGroup {
                    start: first,
                    end: self.out.hits.len(),
                    region: b,
                    parent: self.out.parents.len() - 1,
                });
            }
        }
        self.levels[level] = bx;
    }

    /// Which tile-slabs of `bx` may hold a root: those whose interval range holds 0,
    /// less those the arithmetic's cell form (each side of the box its own input)
    /// excludes. The cell form is tighter where intervals lose the dependency between
    /// terms (polynomials), no tighter on `min`/`max` of simple primitives, and costs
    /// several interval evaluations: it is tried while it excludes at least
    /// [`CELL_TEST_SHARE`] of the tile-slabs it is given in this image tile (after
    /// [`CELL_TEST_TRIAL`] of them), which depends on the tile alone.
    fn cell_test(&mut self, shape: &S, bx: &mut Boxes) {
        bx.keep.clear();
        bx.keep.extend(bx.range.iter().map(|r| r.contains_zero()));
        let worth = self.cell_tries < CELL_TEST_TRIAL
            || self.cell_wins as f64 >= CELL_TEST_SHARE * self.cell_tries as f64;
        if A::NAME == Interval::NAME || !worth {
            return;
        }
        self.cell_group.clear();
        self.cell_group
            .extend((0..bx.keep.len()).filter(|&k| bx.keep[k]));
        if self.cell_group.is_empty() {
            return;
        }
        self.cell_out.clear();
        self.cell_out.resize(bx.keep.len(), None);
        let input = |k: usize| {
            let side = |i: usize, v: &Interval| {
                let (lo, hi) = v.bounds();
                A::Cell::input(i, lo, hi)
            };
            [side(0, &bx.x[k]), side(1, &bx.y[k]), side(2, &bx.z[k])]
        };
        self.cell_batch
            .eval(shape, &self.cell_group, input, &mut self.cell_out);
        let n = self.cell_group.len() as u64;
        self.cell_tries += n;
        self.out.cells.cells_tested += n;
        self.out.cells.cell_ops += n * shape.tape_len().unwrap_or(0) as u64;
        for &k in &self.cell_group {
            if self.cell_out[k]
                .as_ref()
                .is_some_and(|f| !f.contains_zero())
            {
                bx.keep[k] = false;
                self.cell_wins += 1;
            }
        }
    }

    /// The sub-tiles of `q` `m` times smaller (whole leaf blocks, clipped to `q`).
    fn split(&self, (a0, b0, a1, b1): Rect, m: u32) -> Vec<Rect> {
        let side = ((a1 - a0).max(b1 - b0).div_ceil(m)).next_multiple_of(self.leaf);
        let mut out = Vec::with_capacity((m * m) as usize);
        for b in (b0..b1).step_by(side as usize) {
            for a in (a0..a1).step_by(side as usize) {
                out.push((a, b, (a + side).min(a1), (b + side).min(b1)));
            }
        }
        out
    }

    /// Algorithm 1 on the piece of each ray of `q` still searched that lies in the
    /// slab `[sa, sb]` (depths, margin added), with `shape`.
    fn search_leaf(&mut self, q: Rect, (sa, sb): (f64, f64), shape: &S) {
        let (i0, j0, _, _) = self.rect;
        let (a0, b0, a1, b1) = q;
        let mut jobs = std::mem::take(&mut self.leaf_jobs);
        let mut of = std::mem::take(&mut self.leaf_of);
        jobs.clear();
        of.clear();
        for j in b0..b1 {
            for i in a0..a1 {
                let job = self.open[(j - j0) as usize * self.tw + (i - i0) as usize];
                if job == u32::MAX {
                    continue;
                }
                let r = self.out.jobs[job as usize];
                let ic = self.ic[job as usize];
                // The slab's depths in `t` (depth = t (d . forward)), widened by far
                // more than the rounding; the box holds these points (its margin).
                let (a, b) = (sa * ic, sb * ic);
                let m = (a.abs() + b.abs()) * 1e-12;
                let (t0, t1) = (r.start.t0.max(a - m), r.start.t1.min(b + m));
                if t0 > t1 {
                    continue;
                }
                jobs.push(RayJob {
                    start: Start::whole(t0, t1),
                    ..r
                });
                of.push(job);
            }
        }
        let (open, left, evals) = (&mut self.open, &mut self.left, &mut self.evals);
        let (hits, rays, hit_evals) = (
            &mut self.out.hits,
            &mut self.out.rays,
            &mut self.out.hit_evals,
        );
        let (tw, leaf, blocks_w) = (self.tw, self.leaf, self.blocks_w);
        let pixel_of = &self.out.pixel_of;
        let (stop, params) = (self.stop, self.params);
        let all = self
            .lockstep
            .run(shape, &[], params, &jobs, stop, |k, hit, rs| {
                *rays += rs;
                let job = of[k] as usize;
                evals[job] += rs.range_evals;
                let Some(t) = hit else { return };
                hits.push((job, t));
                *hit_evals += evals[job];
                let p = pixel_of[job];
                open[p] = u32::MAX;
                let (i, j) = ((p % tw) as u32, (p / tw) as u32);
                left[(j / leaf) as usize * blocks_w + (i / leaf) as usize] -= 1;
            });
        self.out.cut |= !all;
        self.leaf_jobs = jobs;
        self.leaf_of = of;
    }
}
