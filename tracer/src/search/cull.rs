//! Algorithm 2: screen-space cell culling. A cell of pixels is a bundle of rays, tested
//! in the arithmetic's cell form with three independent inputs (the depth along `forward`
//! and the two pixel coordinates, `x, y, z` built on them with [`Range::from_affine`]; the
//! paper's single shared symbol is unsound for a box). A cell whose range excludes 0 is
//! dropped, otherwise its depth range is narrowed slice by slice ([`Culler::traverse`]) and
//! it is split in four; its last form tells each child and each ray where their roots can
//! be. The derivation, the margins and the choices are in `docs/algorithm-2-culling.md`.
//!
//! A bundle's points are `O(u, v) + s D(u, v)`, both affine in the pixel coordinates:
//! a pinhole has one origin (the eye) and directions that vary, an orthographic view
//! ([`Camera::ortho`]) one direction (`forward`) and origins that vary on the image
//! plane through the eye, so in both `s` is the depth along `forward`. The box of a
//! slice is spanned by the corner origins and directions, the frustum form is exact
//! for the orthographic bundle (no product terms).

use crate::search::ray::{Pruner, Start};
use crate::search::windows::{Refine, Windows};
use arith_core::pack::LANES;
use arith_core::round::{up_finite, ETA, U};
use arith_core::{Arithmetic, Range};
use glam::DVec3;
use model_ir::camera::Camera;
use model_ir::shape::{Aabb, Shape};
use model_ir::shape_batch::{Batch, Groups};
use std::sync::Arc;

/// Counters of the culling pass.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CullStats {
    /// Cells whose box was evaluated.
    pub cells_tested: u64,
    /// Cells dropped (range without 0, or bundle outside the domain).
    pub cells_culled: u64,
    /// Pixels inside dropped cells (no ray traced for them).
    pub pixels_culled: u64,
    /// Cells whose region was evaluated to specialise the shape ([`Shape::specialise`]).
    pub cells_specialised: u64,
    /// Instructions run by the cells' range evaluations ([`Shape::tape_len`]; 0 for
    /// shapes that are not tapes).
    pub cell_ops: u64,
}

impl std::ops::AddAssign for CullStats {
    fn add_assign(&mut self, o: Self) {
        self.cells_tested += o.cells_tested;
        self.cells_culled += o.cells_culled;
        self.pixels_culled += o.pixels_culled;
        self.cells_specialised += o.cells_specialised;
        self.cell_ops += o.cell_ops;
    }
}

/// A cell smaller than this many pixels is traced ray by ray without a test of its own
/// (from its parent's form): a cell whose parent was not dropped is rarely dropped
/// itself, and a 3-input cell test costs about as much as three ray evaluations
/// (measured with the frustum forms, decocube and Mitchell at 1024²: 4 and 64 both
/// 15-40% slower than 16).
pub const MIN_CELL_PIXELS: u32 = 16;

/// A cell's bundle of rays: directions (un-normalised, see [`Camera::raw_dir`]) and
/// origins ([`Camera::origin_at`]), `D = dc + u u' + v v'`, `O = oc + ou u' + ov v'`.
#[derive(Clone, Copy, Debug)]
struct Bundle {
    dmin: DVec3,
    dmax: DVec3,
    dc: DVec3,
    u: DVec3,
    v: DVec3,
    omin: DVec3,
    omax: DVec3,
    oc: DVec3,
    ou: DVec3,
    ov: DVec3,
    /// The cell's width per unit depth.
    width: f64,
    /// Centre and inverse half-extent of the pixel centres: `u = (px - xc) / hx` (`0` for
    /// a single column: `U` is then 0 too).
    xc: f64,
    ihx: f64,
    yc: f64,
    ihy: f64,
}

impl Bundle {
    /// Pixel column `i`'s coordinate `u` in `[-1, 1]` (two roundings).
    #[inline(always)]
    fn u_of(&self, i: u32) -> f64 {
        (i as f64 + 0.5 - self.xc) * self.ihx
    }

    /// Pixel row `j`'s coordinate `v` in `[-1, 1]` (two roundings).
    #[inline(always)]
    fn v_of(&self, j: u32) -> f64 {
        (j as f64 + 0.5 - self.yc) * self.ihy
    }
}

/// The depths of a slice that its test could not prove root-free, and its frustum form
/// with the slice it was computed on (`None` for a box test); only the last one a
/// narrowing keeps becomes a [`Fit`].
type Kept<R> = ((f64, f64), Option<(R, (f64, f64))>);

/// A bundle's range over the slice of depths `s` in its frustum form (see
/// [`Culler::frustum`]), as `c0 + cs eps0 + cu u + cv v ± e` (eps0 the depth symbol, `u`,
/// `v` the pixel coordinates): see [`Culler::fit_start`].
#[derive(Clone, Copy, Debug)]
struct Fit {
    s: (f64, f64),
    /// Pruning of the slice `s` along the depth symbol (slope `cs`).
    pruner: Pruner,
    c0: f64,
    cu: f64,
    cv: f64,
    /// `e` plus the rounding of `c0 + cu u + cv v` for computed `u`, `v` in `[-1, 1]`.
    e: f64,
}

impl Fit {
    fn new<R: Range>(f: &R, s: (f64, f64)) -> Option<Fit> {
        let a = f.affine_part::<3>()?;
        let [cs, cu, cv] = a.xs;
        // `g = c0 + cu u + cv v` in four roundings: off by <= 4U (|c0| + |cu| + |cv|) +
        // 2 ETA; `u`, `v` themselves (two roundings each, |u|, |v| <= 1) move it by
        // <= 2.01U (|cu| + |cv|) more.
        let mag = a.x0.abs() + cu.abs() + cv.abs();
        let e = up_finite(a.e + (8.0 * U * mag + 4.0 * ETA));
        if !e.is_finite() {
            return None;
        }
        Some(Fit {
            s,
            pruner: Pruner::new(s.0, s.1, cs)?,
            c0: a.x0,
            cu,
            cv,
            e,
        })
    }
}

/// Everything a traversal needs besides the shape.
#[derive(Clone, Copy, Debug)]
pub struct Culler {
    cam: Camera,
    /// The domain widened by the margin.
    domain: Aabb,
    margin: f64,
    /// Depth range of the whole domain (`s >= 0`).
    s_range: (f64, f64),
    /// A pixel's angular size (a cell's width per unit depth, for beam narrowing).
    pixel_angle: f64,
    /// Whether kept cells specialise the shape to their region.
    specialise: bool,
}

/// Narrowings in flight at once in [`Culler::traverse`] (a multiple of [`LANES`]).
pub const CULL_SLOTS: usize = 8 * LANES;

/// Most box evaluations of one beam narrowing pass (each direction); past it the
/// narrowing stops where it is (sound: only proved slices are cut away).
const NARROW_BUDGET: u32 = 48;
/// Depth of the narrowing stack.
const NARROW_STACK: usize = 48;
/// Slices of depth a cell's region is specialised over with the cell (a power of
/// two): each gets a window of its own ([`Windows`]), and the hull of their ranges is
/// far tighter than one range over the whole depth (a quadratic's affine error grows
/// with the square of the slice's depth). Measured against 8 at 512x512, with the slices'
/// finer windows: 4 is 31% slower on 10000 balls and 4% faster on the Shikki scene,
/// 16 is 5% and 11% slower.
const SPECIALISE_SLICES: usize = 8;

impl Culler {
    /// A culler for the camera's view of `domain`.
    pub fn new(cam: &Camera, domain: &Aabb) -> Self {
        // The image plane's extent, for an orthographic view.
        let plane = cam
            .ortho
            .map_or(0.0, |w| w * (1.0 + cam.height as f64 / cam.width as f64));
        let scale = (domain.max - domain.min).length()
            + (cam.eye - domain.min).length()
            + (cam.eye - domain.max).length()
            + plane;
        // Rounding of corners, clip and the normalised directions is ~1e-15 relative.
        let margin = scale * 1e-9 + 1e-300;
        let domain = Aabb::new(
            domain.min - DVec3::splat(margin),
            domain.max + DVec3::splat(margin),
        );
        let (mut s0, mut s1) = depth_range(cam, &domain);
        s0 = (s0 - margin).max(0.0);
        s1 += margin;
        // Orthographic: a pixel is as wide at every depth; a slice that deep at the far
        // end of the domain is not split further (this only steers the narrowing).
        let pixel_angle = if cam.ortho.is_some() {
            cam.pixel_size() / s1.max(f64::MIN_POSITIVE)
        } else {
            cam.pixel_angle()
        };
        Culler {
            cam: *cam,
            domain,
            margin,
            s_range: (s0, s1),
            pixel_angle,
            specialise: true,
        }
    }

    /// This culler with region specialisation on or off (on by default): every cell
    /// that is kept specialises its shape ([`Shape::specialise`]) to the region its
    /// children and rays search, and they search with that shape.
    pub fn specialising(mut self, on: bool) -> Self {
        self.specialise = on;
        self
    }

    /// The depths (along `forward`) of the domain's points, margin included: every
    /// ray's piece inside the domain lies in this range.
    pub fn depth_range(&self) -> (f64, f64) {
        self.s_range
    }

    /// A pixel's width per unit of depth (for an orthographic view, its width at the
    /// far end of the domain, divided by that depth).
    pub fn pixel_width_per_depth(&self) -> f64 {
        self.pixel_angle
    }

    /// The componentwise least and greatest ray directions (un-normalised, see
    /// [`Camera::raw_dir`]) of the pixel centres of `[i0, i1) x [j0, j1)`: the four corner
    /// directions bound all others, `raw_dir` being affine in the pixel coordinates.
    pub fn bundle_dirs(&self, i0: u32, j0: u32, i1: u32, j1: u32) -> (DVec3, DVec3) {
        let (x0, x1) = (i0 as f64 + 0.5, i1 as f64 - 0.5);
        let (y0, y1) = (j0 as f64 + 0.5, j1 as f64 - 0.5);
        let a = self.cam.raw_dir(x0, y0);
        let b = self.cam.raw_dir(x1, y0);
        let c = self.cam.raw_dir(x0, y1);
        let d = self.cam.raw_dir(x1, y1);
        (a.min(b).min(c.min(d)), a.max(b).max(c.max(d)))
    }

    /// The componentwise least and greatest ray origins ([`Camera::origin_at`]) of the
    /// pixel centres of `[i0, i1) x [j0, j1)`, from the four corners likewise.
    pub fn bundle_origins(&self, i0: u32, j0: u32, i1: u32, j1: u32) -> (DVec3, DVec3) {
        let (x0, x1) = (i0 as f64 + 0.5, i1 as f64 - 0.5);
        let (y0, y1) = (j0 as f64 + 0.5, j1 as f64 - 0.5);
        let a = self.cam.origin_at(x0, y0);
        let b = self.cam.origin_at(x1, y0);
        let c = self.cam.origin_at(x0, y1);
        let d = self.cam.origin_at(x1, y1);
        (a.min(b).min(c.min(d)), a.max(b).max(c.max(d)))
    }

    /// The cell's directions: their bounds, and `D = Dc + U u + V v` over the pixel
    /// centres (`u, v in [-1, 1]`).
    fn bundle(&self, i0: u32, j0: u32, i1: u32, j1: u32) -> Bundle {
        let (dmin, dmax) = self.bundle_dirs(i0, j0, i1, j1);
        let (x0, x1) = (i0 as f64 + 0.5, i1 as f64 - 0.5);
        let (y0, y1) = (j0 as f64 + 0.5, j1 as f64 - 0.5);
        let (xc, yc) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let dc = self.cam.raw_dir(xc, yc);
        let u = 0.5 * (self.cam.raw_dir(x1, yc) - self.cam.raw_dir(x0, yc));
        let v = 0.5 * (self.cam.raw_dir(xc, y1) - self.cam.raw_dir(xc, y0));
        let (omin, omax) = self.bundle_origins(i0, j0, i1, j1);
        let oc = self.cam.origin_at(xc, yc);
        let ou = 0.5 * (self.cam.origin_at(x1, yc) - self.cam.origin_at(x0, yc));
        let ov = 0.5 * (self.cam.origin_at(xc, y1) - self.cam.origin_at(xc, y0));
        Bundle {
            dmin,
            dmax,
            dc,
            u,
            v,
            omin,
            omax,
            oc,
            ou,
            ov,
            width: (i1 - i0).max(j1 - j0) as f64 * self.pixel_angle,
            xc,
            ihx: if x1 > x0 { 2.0 / (x1 - x0) } else { 0.0 },
            yc,
            ihy: if y1 > y0 { 2.0 / (y1 - y0) } else { 0.0 },
        }
    }

    /// The box enclosing every point inside the domain of the rays through the centres
    /// of pixels `[i0, i1) x [j0, j1)` whose depth lies in `s_range`, and the tightened
    /// depth range; `None` when the bundle does not meet the domain.
    pub fn bundle_box(
        &self,
        i0: u32,
        j0: u32,
        i1: u32,
        j1: u32,
        s_range: (f64, f64),
    ) -> Option<(Aabb, (f64, f64))> {
        self.box_of(
            self.bundle_dirs(i0, j0, i1, j1),
            self.bundle_origins(i0, j0, i1, j1),
            s_range,
        )
    }

    /// The boxes of [`Culler::bundle_box`] for the `k` equal slices of the domain's whole
    /// depth range (the same slices for every cell, so a cell's boxes lie inside its
    /// parent's), `None` for a slice whose points miss the domain.
    pub fn slice_boxes(
        &self,
        (i0, j0, i1, j1): (u32, u32, u32, u32),
        k: usize,
    ) -> Vec<Option<Aabb>> {
        let dirs = self.bundle_dirs(i0, j0, i1, j1);
        let origins = self.bundle_origins(i0, j0, i1, j1);
        let (a, b) = self.s_range;
        let edge = |i: usize| match i {
            0 => a,
            i if i == k => b,
            i => a + (b - a) * i as f64 / k as f64,
        };
        (0..k)
            .map(|i| Some(self.box_of(dirs, origins, (edge(i), edge(i + 1)))?.0))
            .collect()
    }

    /// [`Culler::bundle_box`] from the bundle's direction and origin bounds. The points
    /// `o + d s` (`s >= 0`) are extreme in each coordinate at `omin` or `omax`, `dmin` or
    /// `dmax` and at `s0` or `s1`; rounding is monotone, so this is exactly the box of
    /// the rounded corner points (the origins' rounding is within the margin).
    /// The depth range is then cut to the box's (further rounds of box and depth range
    /// tightened little once cells are tested in their frustum form).
    #[inline]
    pub(crate) fn box_of(
        &self,
        (dmin, dmax): (DVec3, DVec3),
        (omin, omax): (DVec3, DVec3),
        s_range: (f64, f64),
    ) -> Option<(Aabb, (f64, f64))> {
        // Rays start at the eye: every point of a bundle has depth `s >= 0`.
        let (s0, s1) = (s_range.0.max(0.0), s_range.1);
        if s0.partial_cmp(&s1).is_none_or(|o| o.is_gt()) {
            return None;
        }
        let m = DVec3::splat(self.margin);
        let lo = omin + (dmin * s0).min(dmin * s1);
        let hi = omax + (dmax * s0).max(dmax * s1);
        let lo = (lo - m).max(self.domain.min);
        let hi = (hi + m).min(self.domain.max);
        if !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z) {
            return None;
        }
        let b = Aabb::new(lo, hi);
        let (b0, b1) = depth_range(&self.cam, &b);
        let (s0, s1) = (s0.max(b0 - self.margin), s1.min(b1 + self.margin));
        // Empty: no point of the bundle at these depths lies in the domain.
        (s0 <= s1).then_some((b, (s0, s1)))
    }

    /// Visits the cell `[i0, i1) x [j0, j1)`: calls `trace(i, j, start)` for every pixel
    /// whose ray must be traced, skipping the pixels of dropped cells. `start` is in
    /// depth along `forward` (margin included): the ray is proved root-free outside
    /// `[t0, t1]` and inside `(split, resume)`, and its first root is most likely before
    /// `split` (a ray's range over the whole `[t0, t1]` spans both sides of a closed
    /// surface and needs many halvings before it says anything). From its cell's form
    /// (see the module doc) `[t0, split]` is where the ray's roots in the cell's slice
    /// can be, or, without one, the first two slices its cell could not prove root-free.
    ///
    /// Cells waiting for their narrowing are kept on a stack, and up to [`CULL_SLOTS`]
    /// are narrowed at once: each step evaluates the slices asked for by every narrowing
    /// in flight, those on one shape in one batch ([`Batch`]: in
    /// [`Arithmetic::CellPack`]s, each lane exactly the scalar cell form's range; form by
    /// form for a shape that does not [pack](Shape::packs)), and a finished narrowing's
    /// slot takes the next cell. A cell depends only on its parent's narrowing, so the
    /// cells dropped and the depths handed to rays are those of a depth-first visit;
    /// only the order in which rays are handed out differs.
    pub fn traverse<
        A: Arithmetic,
        S: Shape,
        F: FnMut(u32, u32, Start, Option<&Arc<Windows<S>>>),
    >(
        &self,
        shape: &S,
        rect: (u32, u32, u32, u32),
        stats: &mut CullStats,
        trace: &mut F,
    ) {
        let s = self.s_range;
        let start = Start::whole(s.0, s.1);
        struct Slot<R, S> {
            cell: Cell<S>,
            bundle: Bundle,
            narrowing: Narrowing<R>,
            forms: [R; 3],
        }
        let mut todo = Vec::with_capacity(64);
        self.enqueue(rect, s, start, None, None, &mut todo, trace);
        let mut slots: Vec<Option<Slot<A::Cell, S>>> = (0..CULL_SLOTS).map(|_| None).collect();
        let mut ranges: Vec<Option<A::Cell>> = (0..CULL_SLOTS).map(|_| None).collect();
        let mut groups = Groups::default();
        let mut batch = Batch::<A::CellPack>::default();
        let specialise = self.specialise && shape.specialises();
        loop {
            for slot in slots.iter_mut() {
                while slot.is_none() {
                    let Some(cell) = todo.pop() else { break };
                    let (i0, j0, i1, j1) = cell.rect;
                    let bundle = self.bundle(i0, j0, i1, j1);
                    let mut narrowing = Narrowing::new(bundle.width, cell.s_range, cell.start);
                    match narrowing.run(self, &bundle, stats, None) {
                        Step::Eval(forms) => {
                            *slot = Some(Slot {
                                cell,
                                bundle,
                                narrowing,
                                forms,
                            })
                        }
                        Step::Done(res) => self.narrowed::<A, S, F>(
                            shape, specialise, cell, &bundle, res, &mut todo, stats, trace,
                        ),
                    }
                }
            }
            // Each cell's slice on its own shape: its windows' shape at the depths under
            // test (siblings share their parent's windows), or the tile's.
            let shapes: [Option<&S>; CULL_SLOTS] = core::array::from_fn(|k| {
                let slot = slots[k].as_ref()?;
                let (t0, t1) = slot.narrowing.t;
                Some(match &slot.cell.shape {
                    Some(w) => w.at(shape, t0, t1),
                    None => shape,
                })
            });
            groups.regroup(&shapes);
            if groups.is_empty() {
                return;
            }
            let forms = |k: usize| slots[k].as_ref().expect("a grouped slot").forms.clone();
            for group in groups.iter() {
                let sh = shapes[group[0]].expect("a grouped slot has a shape");
                batch.eval(sh, group, forms, &mut ranges);
                stats.cell_ops += (group.len() * sh.tape_len().unwrap_or(0)) as u64;
            }
            for (k, f) in ranges.iter_mut().enumerate() {
                let (Some(slot), Some(f)) = (&mut slots[k], f.take()) else {
                    continue;
                };
                match slot.narrowing.feed(f, self, &slot.bundle, stats) {
                    Step::Eval(forms) => slot.forms = forms,
                    Step::Done(res) => {
                        let Slot { cell, bundle, .. } = slots[k].take().expect("an active slot");
                        self.narrowed::<A, S, F>(
                            shape, specialise, cell, &bundle, res, &mut todo, stats, trace,
                        );
                    }
                }
            }
        }
    }

    /// A cell whose narrowing ended with `res` (`None`: dropped): its four children are
    /// queued, those too small to be tested hand their rays out at once. With
    /// `specialise`, they get the cell's shape specialised to the region they search:
    /// the cell's bundle at the depths left to them, widened by twice the margin
    /// (rays search up to one margin beyond).
    #[allow(clippy::too_many_arguments)]
    fn narrowed<A: Arithmetic, S: Shape, F: FnMut(u32, u32, Start, Option<&Arc<Windows<S>>>)>(
        &self,
        root: &S,
        specialise: bool,
        cell: Cell<S>,
        bundle: &Bundle,
        res: Option<((f64, f64), Option<Fit>)>,
        todo: &mut Vec<Cell<S>>,
        stats: &mut CullStats,
        trace: &mut F,
    ) {
        let (i0, j0, i1, j1) = cell.rect;
        let (w, h) = (i1 - i0, j1 - j0);
        // The fine windows this cell's narrowing built, counted before it may be dropped.
        if let Some(w) = &cell.shape {
            let (evals, ops) = w.take_counts();
            stats.cells_specialised += evals;
            stats.cell_ops += ops;
        }
        let Some(((first, first_end), fit)) = res else {
            stats.cells_culled += 1;
            stats.pixels_culled += (w * h) as u64;
            return;
        };
        let parent = fit.as_ref().map(|f| (bundle, f));
        let s = (first, cell.s_range.1);
        let mut local = cell.shape;
        if specialise {
            // Segments stay a margin inside the region (rays search up to one margin
            // beyond the depths handed out), and windows half a margin inside theirs.
            let m = self.margin;
            let base = local.as_ref().and_then(|w| w.whole());
            let built = Windows::build::<A::Cell>(
                root,
                base,
                (s.0 - 2.0 * m, s.1 + 2.0 * m),
                SPECIALISE_SLICES,
                0.5 * m,
                |lo, hi| Some(self.region::<A::Cell>(bundle, (lo, hi))?.0),
                Some(self.refine::<A::Cell, S>(bundle)),
            );
            if let Some((windows, evaluated)) = built {
                let current = base.map_or(root, |b| &**b);
                stats.cells_specialised += evaluated as u64;
                stats.cell_ops += (evaluated * current.tape_len().unwrap_or(0)) as u64;
                local = Some(Arc::new(windows));
            }
        }
        let plain = Start {
            t0: first,
            split: first_end,
            resume: first_end,
            step: 0.0,
            t1: s.1,
        };
        let (im, jm) = (i0 + w.div_ceil(2), j0 + h.div_ceil(2));
        for (a0, a1) in [(i0, im), (im, i1)] {
            for (c0, c1) in [(j0, jm), (jm, j1)] {
                if a0 < a1 && c0 < c1 {
                    let rect = (a0, c0, a1, c1);
                    let start = parent
                        .and_then(|(b, fit)| self.fit_start(b, fit, rect, s))
                        .unwrap_or(plain);
                    self.enqueue(rect, s, start, parent, local.clone(), todo, trace);
                }
            }
        }
    }

    /// The refinement of a cell's [`Windows`]: a shape specialised to the bundle's
    /// points at the depths given.
    fn refine<R: Range, S: Shape>(&self, bundle: &Bundle) -> Box<Refine<S>> {
        let (culler, bundle) = (*self, *bundle);
        Box::new(move |shape: &S, lo, hi| {
            let (region, _) = culler.region::<R>(&bundle, (lo, hi))?;
            let ops = shape.tape_len().unwrap_or(0);
            Some((
                shape
                    .specialise(std::slice::from_ref(&region))
                    .map(Arc::new),
                ops,
            ))
        })
    }

    /// The inputs of a range over the bundle's points at the depths `s`: its frustum
    /// form (arithmetics with symbols), or its box; with the depths tightened to the
    /// box; `None` where they miss the domain.
    fn region<R: Range>(&self, bundle: &Bundle, s: (f64, f64)) -> Option<([R; 3], (f64, f64))> {
        let (b, t) = self.box_of((bundle.dmin, bundle.dmax), (bundle.omin, bundle.omax), s)?;
        let forms = if R::INPUTS >= 3 {
            self.frustum::<R>(bundle, t.0, t.1)
        } else {
            [
                R::input(0, b.min.x, b.max.x),
                R::input(1, b.min.y, b.max.y),
                R::input(2, b.min.z, b.max.z),
            ]
        };
        Some((forms, t))
    }

    /// Queues the cell `rect` for its narrowing, or, when it is too small to be tested,
    /// hands out its rays (each started from its own share of the parent's form where
    /// there is one).
    #[allow(clippy::too_many_arguments)]
    fn enqueue<S, F: FnMut(u32, u32, Start, Option<&Arc<Windows<S>>>)>(
        &self,
        rect: (u32, u32, u32, u32),
        s_range: (f64, f64),
        start: Start,
        parent: Option<(&Bundle, &Fit)>,
        shape: Option<Arc<Windows<S>>>,
        todo: &mut Vec<Cell<S>>,
        trace: &mut F,
    ) {
        let (i0, j0, i1, j1) = rect;
        let (w, h) = (i1.saturating_sub(i0), j1.saturating_sub(j0));
        if w == 0 || h == 0 {
            return;
        }
        if w * h >= MIN_CELL_PIXELS {
            todo.push(Cell {
                rect,
                s_range,
                start,
                shape,
            });
            return;
        }
        // The ray's first piece: two slices deep (the slice is the cell's nearest
        // surface; this ray's root is often just past it, and a piece that holds the
        // root is resolved by pruning in one evaluation, while proving the slice empty
        // first costs one more). Measured: 18-22% fewer ray evaluations on Mitchell and
        // the decocube, 10% on the noisy sphere, CSG within 1%.
        let split = (start.split + (start.split - s_range.0)).min(s_range.1);
        let plain = Start {
            t0: s_range.0,
            split,
            resume: split,
            step: 0.0,
            t1: s_range.1,
        };
        for j in j0..j1 {
            for i in i0..i1 {
                // Better: the ray's own share of its cell's form.
                let st = parent
                    .and_then(|(b, fit)| self.fit_start(b, fit, (i, j, i + 1, j + 1), s_range))
                    .unwrap_or(plain);
                let split = st.split + self.margin;
                trace(
                    i,
                    j,
                    Start {
                        t0: st.t0 - self.margin,
                        split,
                        resume: (st.resume - self.margin).max(split),
                        step: st.step,
                        t1: s_range.1 + self.margin,
                    },
                    shape.as_ref(),
                );
            }
        }
    }

    /// The points `eye + s D(u, v)` of the bundle's frustum between the depths `[s0, s1]`
    /// as affine forms in three independent inputs: depth `s = m + r eps0` and the pixel
    /// coordinates `u = eps1`, `v = eps2` (`D` is affine in them: `D = Dc + U u + V v`).
    /// The product `s D` gives `eye + m Dc + r Dc eps0 + m U eps1 + m V eps2` plus the
    /// terms `r U eps0 eps1 + r V eps0 eps2`, bounded by `r (|U| + |V|)` in the error,
    /// which also holds the rounding of every coefficient and of `D`, and the culling
    /// margin. A ray's rounded, normalised direction puts its points off the exact
    /// frustum line by far less than that margin; along the line, its points sit at a
    /// depth a few ulps of `|D|^2 s` from the one the forms give them, which every form
    /// of every cell shares and the depths handed to rays absorb in their margins.
    /// Unlike the box, the forms follow the frustum's slant, and pruning their depth
    /// symbol narrows the depth range of the whole bundle at once.
    ///
    /// With origins `O = Oc + Ou u + Ov v` (orthographic views) the forms gain the
    /// affine terms `Ou eps1 + Ov eps2` (exact: no product with the depth), and the
    /// rounding allowance counts the origins' magnitude.
    fn frustum<R: Range>(&self, bundle: &Bundle, s0: f64, s1: f64) -> [R; 3] {
        let (m, r, emr) = arith_core::affine_round::mid_rad(s0, s1);
        let (dc, u, v) = (bundle.dc, bundle.u, bundle.v);
        let (oc, ou, ov) = (bundle.oc, bundle.ou, bundle.ov);
        let dn = (dc.abs() + u.abs() + v.abs()).max_element();
        core::array::from_fn(|k| {
            let (dk, uk, vk) = (dc[k], u[k], v[k]);
            let on = oc[k].abs() + ou[k].abs() + ov[k].abs();
            let round = 64.0 * f64::EPSILON * (on + (m.abs() + r) * dn);
            let err = r * (uk.abs() + vk.abs()) + emr * dn + round + self.margin;
            R::from_affine(
                oc[k] + m * dk,
                &[r * dk, m * uk + ou[k], m * vk + ov[k]],
                err,
            )
        })
    }

    /// Where the rays through the pixels `rect` (inside the cell of `b`) are searched,
    /// from the cell's last form: with the pixel coordinates `u`, `v` fixed, the form is
    /// affine in the depth symbol alone, and pruning it proves the part of the slice in
    /// front of (or all of) those rays' possible roots root-free, without an evaluation.
    /// Over a rectangle of pixels the form's constant part ranges between its values at
    /// the corners (it is affine in `u`, `v`), so pruning with that range covers every
    /// ray of the rectangle. `None` when the form says nothing.
    #[inline(always)]
    fn fit_start(
        &self,
        b: &Bundle,
        fit: &Fit,
        (i0, j0, i1, j1): (u32, u32, u32, u32),
        s_range: (f64, f64),
    ) -> Option<Start> {
        let (u, v) = (|i| b.u_of(i), |j| b.v_of(j));
        let (f0, e) = if i1 - i0 == 1 && j1 - j0 == 1 {
            (fit.c0 + fit.cu * u(i0) + fit.cv * v(j0), fit.e)
        } else {
            // Over the rectangle `g` is between its values at the corners, each within
            // `fit.e` of the computed one; `[lo - e, hi + e]` is within `f0 ± e'`, `f0`
            // rounded (off by <= U |f0|).
            let (pu, qu) = (fit.cu * u(i0), fit.cu * u(i1 - 1));
            let (pv, qv) = (fit.cv * v(j0), fit.cv * v(j1 - 1));
            let lo = fit.c0 + pu.min(qu) + pv.min(qv);
            let hi = fit.c0 + pu.max(qu) + pv.max(qv);
            let f0 = 0.5 * lo + 0.5 * hi;
            let half = up_finite(0.5 * hi - 0.5 * lo);
            (f0, up_finite(up_finite(half + fit.e) + 2.0 * U * f0.abs()))
        };
        let (t0, t1) = fit.s;
        // The cell's form was tight on its slice: pieces that long.
        let step = (t1 - t0).max(b.width * t1);
        // No root in the slice (or none left past the range's start).
        let start = match fit.pruner.prune(f0, e)?.filter(|&(_, c)| c >= s_range.0) {
            None => {
                let s0 = t1.max(s_range.0);
                let split = (s0 + step).min(s_range.1);
                Start {
                    t0: s0,
                    split,
                    resume: split,
                    step,
                    t1: s_range.1,
                }
            }
            // The form says next to nothing about these rays (R-function models, whose
            // forms are loose): the plain start (measured: 6% fewer ray evaluations on
            // hair and the microstructure, the others within 1%).
            Some((a, c)) if c - a > 0.9 * (t1 - t0) => return None,
            // Roots in the slice lie in `[a, c]`: none in `(c, t1]` either.
            Some((a, c)) => Start {
                t0: a.max(s_range.0),
                split: c.min(s_range.1),
                resume: t1.min(s_range.1),
                step,
                t1: s_range.1,
            },
        };
        (start.t0 <= start.split).then_some(start)
    }
}

/// A cell waiting for its narrowing: its pixels, the depths left to it, where its
/// narrowing starts (in depth, without the margins handed to rays) and its shape
/// specialised to its parent's region (`None`: the whole shape).
struct Cell<S> {
    rect: (u32, u32, u32, u32),
    s_range: (f64, f64),
    start: Start,
    shape: Option<Arc<Windows<S>>>,
}

/// The next step of a [`Narrowing`].
enum Step<R> {
    /// The cell's range over these inputs is needed (pass it to [`Narrowing::feed`]).
    Eval([R; 3]),
    /// The narrowing is over: the first slice not proved root-free and the [`Fit`] of
    /// its last form, or `None` when every slice is (the cell is dropped).
    Done(Option<((f64, f64), Option<Fit>)>),
}

/// Beam narrowing of the depth range of a cell's bundle, as a state machine that asks
/// for one slice's range at a time (so that four cells are narrowed in one packed
/// evaluation, see [`Culler::traverse`]). Slices of depth are tested front to back,
/// halving a slice whose range holds 0 until it is about as deep as the cell is wide (a
/// thinner slice is no tighter). Sound whatever the budget: a depth is cut away only
/// when its slice was proved root-free.
///
/// Like a ray, the narrowing marches: `[s.0, split]` first (the parent's first non-empty
/// slice, or this cell's share of the parent's form, where its surface most likely
/// starts), then pieces [`crate::search::ray::MARCH_GROWTH`] times as deep as the slice last
/// proved empty; halving the whole rest from the front costs an evaluation per halving
/// before anything is proved.
///
/// A slice is tested in the cell form over the frustum's points on it
/// ([`Culler::frustum`]), or, for arithmetics without symbols, over its box
/// ([`Culler::box_of`]); a slice whose bundle misses the domain is proved without an
/// evaluation. Where the frustum form's range holds 0, argument pruning along its depth
/// symbol still proves the depths outside the pruned interval root-free.
struct Narrowing<R> {
    /// The cell's width per unit depth: a slice about that deep is not split further.
    width: f64,
    s: (f64, f64),
    /// The slice under test, and its depths tightened to its box.
    cur: (f64, f64),
    t: (f64, f64),
    rest: f64,
    first_step: f64,
    budget: u32,
    stack: [(f64, f64); NARROW_STACK],
    sp: usize,
    /// The last slice's form and the depths it was computed on.
    last: Option<(R, (f64, f64))>,
}

/// The outcome of a narrowing: see [`Step::Done`].
type Narrowed = Option<((f64, f64), Option<Fit>)>;

impl<R: Range> Narrowing<R> {
    fn new(width: f64, s: (f64, f64), start: Start) -> Self {
        // Nothing before `start.t0` (the parent proved it).
        let s = (start.t0.max(s.0), s.1);
        let mut n = Narrowing {
            width,
            s,
            cur: s,
            t: s,
            rest: s.1,
            first_step: 0.0,
            budget: NARROW_BUDGET,
            stack: [(0.0, 0.0); NARROW_STACK],
            sp: 0,
            last: None,
        };
        if s.0 < start.split && start.split < s.1 {
            n.cur = (s.0, start.split);
            n.rest = start.resume.clamp(start.split, s.1);
            n.first_step = start.step;
        }
        n
    }

    /// Goes on with `f`, the range over the inputs last asked for.
    fn feed(&mut self, f: R, c: &Culler, bundle: &Bundle, stats: &mut CullStats) -> Step<R> {
        let (cur, (t0, t1)) = (self.cur, self.t);
        let kept = if R::INPUTS < 3 {
            f.contains_zero().then_some((cur, None))
        } else if !f.contains_zero() {
            None
        } else {
            let kept = match crate::search::ray::prune(&f, t0, t1) {
                Some(None) => None,
                Some(Some((a, b))) => Some((a.max(cur.0), b.min(cur.1))),
                None => Some(cur),
            };
            // Kept unless certainly empty (a NaN end keeps it: sound).
            kept.filter(|k| k.0.partial_cmp(&k.1).is_none_or(|o| o.is_le()))
                .map(|k| (k, Some((f, (t0, t1)))))
        };
        self.run(c, bundle, stats, Some(kept))
    }

    /// Runs until a slice's range is needed or the narrowing is over; `kept` is the
    /// outcome of the slice just tested (`None` at the start): the depths it could not
    /// prove root-free with its form (`None`: it proved all of them).
    fn run(
        &mut self,
        c: &Culler,
        bundle: &Bundle,
        stats: &mut CullStats,
        mut kept: Option<Option<Kept<R>>>,
    ) -> Step<R> {
        loop {
            if let Some(k) = kept.take() {
                if let Some(done) = self.after(k, c) {
                    return Step::Done(done);
                }
            }
            if self.budget == 0 {
                // Sound: only what was proved is cut away.
                return Step::Done(Some(((self.cur.0, self.s.1), None)));
            }
            self.budget -= 1;
            stats.cells_tested += 1;
            let Some((forms, t)) = c.region::<R>(bundle, self.cur) else {
                kept = Some(None);
                continue;
            };
            self.t = t;
            return Step::Eval(forms);
        }
    }

    /// The march after a slice's test; `Some` when the narrowing is over.
    fn after(&mut self, kept: Option<Kept<R>>, c: &Culler) -> Option<Narrowed> {
        let proved = kept.is_none();
        if let Some((k, fit)) = kept {
            self.last = fit;
            // Pruning proved the rest of `cur` root-free; a slice it shrank a lot is
            // tested again (an affine Newton step) rather than halved.
            let shrunk = k.1 - k.0 < 0.5 * (self.cur.1 - self.cur.0);
            self.cur = k;
            if shrunk {
                return None;
            }
        }
        let (cur, s) = (self.cur, self.s);
        if proved {
            if self.sp > 0 {
                self.sp -= 1;
                self.cur = self.stack[self.sp];
            } else if self.rest < s.1 {
                // As for rays: a little longer than the slice just proved empty. Never
                // thinner than a slice worth testing (progress is certain).
                let rest = self.rest;
                let step = ((cur.1 - cur.0) * crate::search::ray::MARCH_GROWTH)
                    .max(self.width * rest.max(0.0) + c.margin)
                    .max(self.first_step);
                self.first_step = 0.0;
                let end = crate::search::ray::next_piece(rest, s.1, step);
                self.cur = (rest, end);
                self.rest = end;
            } else {
                return Some(None);
            }
            return None;
        }
        let mid = 0.5 * cur.0 + 0.5 * cur.1;
        let small = cur.1 - cur.0 <= self.width * cur.1.max(0.0) + c.margin;
        if small || self.sp == NARROW_STACK || mid <= cur.0 || mid >= cur.1 {
            let fit = self.last.take().and_then(|(f, sl)| Fit::new(&f, sl));
            return Some(Some((cur, fit)));
        }
        self.stack[self.sp] = (mid, cur.1);
        self.sp += 1;
        self.cur = (cur.0, mid);
        None
    }
}

/// Range of the depth `(p - eye) . forward` over a box (extreme at corners: the corner
/// taking each coordinate's smaller (larger) term; rounding is monotone, so this equals
/// the least (greatest) of the 8 rounded corner depths), `s >= 0`.
fn depth_range(cam: &Camera, b: &Aabb) -> (f64, f64) {
    let p = (b.min - cam.eye) * cam.forward;
    let q = (b.max - cam.eye) * cam.forward;
    let (lo, hi) = (p.min(q), p.max(q));
    ((lo.x + lo.y + lo.z).max(0.0), hi.x + hi.y + hi.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::ray::clip;
    use model_ir::shape::View;

    use arith_core::Real;
    use model_ir::arith::ArithKind;

    /// `1 - r^2` (`touch == false`) or the tangent touch `-(r^2 - 1)^2` (no sign change).
    struct Ball {
        touch: bool,
    }
    impl Shape for Ball {
        fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
            let r2 = x.sqr() + y.sqr() + z.sqr();
            if self.touch {
                -(r2 - 1.0).sqr()
            } else {
                r2.rsub(1.0)
            }
        }
    }

    /// Beam narrowing never cuts a root away: for every arithmetic, every pixel whose
    /// analytic ray meets the unit sphere is traced, and both its roots lie in the depth
    /// range handed to the ray (depth = `t (d . forward)`).
    /// Cells narrowed four at a time hand out the same rays, with the same depths and
    /// counts, as cells narrowed one at a time: every paper and progressive-refinement
    /// model, every arithmetic. (A model whose evaluation looks at its arguments' types
    /// and says it packs would fail here.)
    #[test]
    fn packed_narrowing_is_the_scalar_narrowing() {
        struct OneByOne<'a>(&'a model_sources::Model);
        impl Shape for OneByOne<'_> {
            fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
                self.0.eval(x, y, z)
            }
            fn packs(&self) -> bool {
                false
            }
        }
        // Virtual Shikki evaluates one form at a time anyway (its tape branches).
        let models = model_sources::PaperModel::ALL
            .into_iter()
            .filter(|&m| m != model_sources::PaperModel::Shikki)
            .map(|m| m.model())
            .chain(model_sources::gamito_maddock::all());
        for m in models {
            let (w, h) = (40, 30);
            let cam = Camera::new(m.view, w, h);
            let c = Culler::new(&cam, &m.domain);
            for kind in ArithKind::ALL {
                fn run<S: Shape>(
                    c: &Culler,
                    kind: ArithKind,
                    shape: &S,
                    rect: (u32, u32, u32, u32),
                ) -> (Vec<(u32, u32, Start)>, CullStats) {
                    let mut rays = Vec::new();
                    let mut stats = CullStats::default();
                    let mut trace = |i, j, d, _: Option<&Arc<Windows<S>>>| rays.push((j, i, d));
                    model_ir::with_arith!(kind, A => c.traverse::<A, _, _>(shape, rect, &mut stats, &mut trace));
                    rays.sort_by_key(|r| (r.0, r.1));
                    (rays, stats)
                }
                let packed = run(&c, kind, &m, (0, 0, w, h));
                let alone = run(&c, kind, &OneByOne(&m), (0, 0, w, h));
                assert_eq!(packed, alone, "{} {kind}", m.name);
            }
        }
    }

    #[test]
    fn narrowing_keeps_every_root() {
        let domain = Aabb::cube(1.5);
        let view = View {
            eye: DVec3::new(0.7, 0.9, 3.4),
            look_at: DVec3::new(0.05, -0.03, 0.0),
            up: DVec3::Y,
            fov_deg: 40.0,
            ortho: None,
        };
        let (w, h) = (64, 48);
        // And orthographic: parallel rays from the image plane.
        let ortho = View {
            ortho: Some(2.6),
            ..view
        };
        for view in [view, ortho] {
            let cam = Camera::new(view, w, h);
            let c = Culler::new(&cam, &domain);
            for kind in ArithKind::ALL {
                for touch in [false, true] {
                    let shape = Ball { touch };
                    let mut got = vec![None; (w * h) as usize];
                    let mut stats = CullStats::default();
                    let mut gaps = 0;
                    let mut trace = |i: u32, j: u32, s: Start, _: Option<&Arc<Windows<Ball>>>| {
                        assert!(s.t0 <= s.split && s.split <= s.resume, "{s:?}");
                        assert!(s.resume <= s.t1 && s.step >= 0.0, "{s:?}");
                        gaps += usize::from(s.resume > s.split);
                        got[(j * w + i) as usize] = Some(s);
                    };
                    model_ir::with_arith!(kind, A => c.traverse::<A, _, _>(
                        &shape,
                        (0, 0, w, h),
                        &mut stats,
                        &mut trace,
                    ));
                    assert!(stats.pixels_culled > 0, "{kind}: nothing culled");
                    let mut hits = 0;
                    for j in 0..h {
                        for i in 0..w {
                            let (o, d) = cam.ray(i, j);
                            let b = o.dot(d);
                            let disc = b * b - (o.length_squared() - 1.0);
                            if disc <= 1e-9 {
                                continue;
                            }
                            hits += 1;
                            let tag = format!("{kind} touch={touch} pixel ({i},{j})");
                            let g = got[(j * w + i) as usize]
                                .unwrap_or_else(|| panic!("{tag}: culled but hits"));
                            let f = d.dot(cam.forward);
                            for t in [-b - disc.sqrt(), -b + disc.sqrt()] {
                                let s = t * f;
                                assert!(
                                    g.t0 <= s && s <= g.t1,
                                    "{tag}: root depth {s} not in [{}, {}]",
                                    g.t0,
                                    g.t1
                                );
                                assert!(
                                    !(g.split < s && s < g.resume),
                                    "{tag}: root depth {s} in the gap ({}, {})",
                                    g.split,
                                    g.resume
                                );
                            }
                        }
                    }
                    assert!(hits > 500, "the view should show the sphere ({hits} hits)");
                    if kind != ArithKind::Ia && view.ortho.is_none() {
                        // The rays' shares of their cells' forms were used (about half of
                        // the hit rays skip a gap on the ball, a tenth on the touch; none
                        // in the orthographic view, whose rays start from their cell's
                        // first slice instead).
                        assert!(
                            gaps > hits / 20,
                            "{kind}: only {gaps} rays skip a proved gap"
                        );
                    }
                }
            }
        }
    }

    /// The frustum forms enclose every ray point of the bundle: for each pixel of a cell
    /// and each point of its (normalised, rounded) ray at a depth in the slice, fixing the
    /// depth symbol and the pixel's `u`, `v` leaves the point inside each coordinate's
    /// form; and a pixel's coordinates (as `fit_start` computes them) are in `[-1, 1]`.
    #[test]
    fn frustum_forms_enclose_the_rays() {
        use arith_revaa::RevAa;
        let domain = Aabb::cube(2.0);
        let views = [
            View {
                eye: DVec3::new(2.13, 1.704, 3.408),
                look_at: DVec3::ZERO,
                up: DVec3::Y,
                fov_deg: 35.0,
                ortho: None,
            },
            View {
                eye: DVec3::new(0.1, 0.2, 0.0),
                look_at: DVec3::new(1.0, 0.3, -1.0),
                up: DVec3::Y,
                fov_deg: 100.0,
                ortho: None,
            },
            View {
                eye: DVec3::new(2.13, 1.704, 3.408),
                look_at: DVec3::new(0.2, 0.0, -0.1),
                up: DVec3::Y,
                fov_deg: 35.0,
                ortho: Some(3.5),
            },
        ];
        for v in views {
            let cam = Camera::new(v, 61, 37);
            let c = Culler::new(&cam, &domain);
            for &(i0, j0, i1, j1) in &[
                (0, 0, 61, 37),
                (8, 4, 16, 12),
                (30, 20, 33, 22),
                (5, 5, 6, 7),
            ] {
                let b = c.bundle(i0, j0, i1, j1);
                for (s0, s1) in [(0.5, 0.75), (2.0, 2.0 + 1e-3), (3.0, 6.5)] {
                    let xyz = c.frustum::<RevAa<3>>(&b, s0, s1);
                    let (m, r) = (0.5 * s0 + 0.5 * s1, 0.5 * s1 - 0.5 * s0);
                    for j in j0..j1 {
                        for i in i0..i1 {
                            let (u, w) = (b.u_of(i), b.v_of(j));
                            assert!(u.abs() <= 1.0 && w.abs() <= 1.0, "{u} {w}");
                            let (o, d) = cam.ray(i, j);
                            let f = d.dot(cam.forward);
                            for k in 0..=20 {
                                let s = s0 + (s1 - s0) * k as f64 / 20.0;
                                let p = o + d * (s / f);
                                let eps = [((s - m) / r).clamp(-1.0, 1.0), u, w];
                                for (a, x) in xyz.iter().enumerate() {
                                    let (lo, hi) = x.bounds_at_inputs(&eps);
                                    assert!(
                                        lo <= p[a] && p[a] <= hi,
                                        "pixel ({i},{j}) depth {s}: {} not in [{lo}, {hi}]",
                                        p[a]
                                    );
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    /// Every point of every pixel ray inside the domain lies in its cell's box.
    #[test]
    fn bundle_box_encloses_the_rays() {
        let domain = Aabb::new(DVec3::new(-1.0, -0.5, -2.0), DVec3::new(1.5, 1.0, 0.5));
        let views = [
            View {
                eye: DVec3::new(3.0, 2.0, 4.0),
                look_at: DVec3::ZERO,
                up: DVec3::Y,
                fov_deg: 40.0,
                ortho: None,
            },
            View {
                eye: DVec3::new(0.1, 0.2, 0.0),
                look_at: DVec3::new(1.0, 0.3, -1.0),
                up: DVec3::Y,
                fov_deg: 90.0,
                ortho: None,
            },
            View {
                eye: DVec3::new(3.0, 2.0, 4.0),
                look_at: DVec3::ZERO,
                up: DVec3::Y,
                fov_deg: 40.0,
                ortho: Some(2.5),
            },
        ];
        for v in views {
            let cam = Camera::new(v, 40, 30);
            let c = Culler::new(&cam, &domain);
            for &(i0, j0, i1, j1) in &[
                (0, 0, 40, 30),
                (8, 4, 16, 12),
                (30, 20, 33, 22),
                (5, 5, 6, 7),
            ] {
                let Some((b, _)) = c.bundle_box(i0, j0, i1, j1, c.s_range) else {
                    // Then no ray of the cell meets the domain.
                    for j in j0..j1 {
                        for i in i0..i1 {
                            let (o, d) = cam.ray(i, j);
                            assert!(clip(o, d, &domain, 0.0).is_none());
                        }
                    }
                    continue;
                };
                for j in j0..j1 {
                    for i in i0..i1 {
                        let (o, d) = cam.ray(i, j);
                        if let Some((t0, t1)) = clip(o, d, &domain, 0.0) {
                            for k in 0..=50 {
                                let p = o + d * (t0 + (t1 - t0) * k as f64 / 50.0);
                                assert!(
                                    p.cmpge(b.min).all() && p.cmple(b.max).all(),
                                    "{p:?} not in {b:?}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}
