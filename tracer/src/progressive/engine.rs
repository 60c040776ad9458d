//! The progressive refinement engine (Gamito and Maddock 2007, Section 3): a queue of
//! square image samples, each traced as one cone ([`crate::search::cone`]), painted at
//! the distance the cone reached and split by the [`Plan`] into child cones that start
//! where it stopped (eq. 8, or our guaranteed [`ChildStart::Radial`]), down to single
//! pixels finished by the overshooting ray caster; a region of interest ([`Rect`]) moves
//! its samples to a secondary queue refined first (Section 3.4).

use super::image::{pack, SharedImage};
use super::plan::Plan;
use crate::render::shade::{self, Light, Material, BACKGROUND};
use crate::search::cone::{trace_cone, trace_cone_local, ConeEnd};
use crate::search::cone_range::trace_cone_range;
use crate::search::lipschitz::{
    box_distance, clip_to_box, local_trace, overshoot_trace, Bounded, LocalCounts,
};
use crate::search::ray::{first_root, Precision, RayParams, RayStats, Start};
use glam::DVec3;
use model_ir::arith::ArithKind;
use model_ir::camera::Camera;
use model_ir::shape::{Aabb, Shape, View};
use std::collections::VecDeque;
use std::sync::Arc;
use tracer_kit::bspline_filter::{Filter, Kernel};

/// How a child cone's starting distance is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ChildStart {
    /// Eq. (8): `t0 = t_M / (d_child . d_parent)`, the plane orthogonal to the parent axis
    /// at `t_M`. The parent cleared its cone between two such planes; ancestors cleared
    /// theirs between planes orthogonal to *their* axes, so between tilted planes a thin
    /// wedge of a child cone can be left unchecked (second order in the aperture).
    Paper,
    /// Our guaranteed variant (default): every sample carries a radius `R` such that each
    /// ray of its pyramid is clear of the surface closer than `R` to the eye. A cone
    /// starts at `t0 = R cos α` (all its points of axial distance below `t0` are closer
    /// than `R`), clears the axial range `[t0, t_M]`, and its children inherit
    /// `R' = max(R, t_M)` (a point of the cone closer than `t_M` either has axial
    /// distance in `[t0, t_M]` or is closer than `R`). Terminal rays start at `R`.
    #[default]
    Radial,
}

/// The bound mode `tracer preview` uses unless told otherwise (measured in
/// `bench-suite progressive`; see the README's previewer section): local bounds where
/// they pay, the global bound elsewhere.
pub const DEFAULT_BOUND: Bound = Bound::Auto;

/// Sub-boxes per axis of [`Bound::Auto`]'s probe.
pub const AUTO_PROBE_SPLITS: usize = 8;
/// [`Bound::Auto`] takes local bounds when the median gradient bound over the probe's
/// sub-boxes is below this share of the global bound.
pub const AUTO_LOCAL_SHARE: f64 = 0.5;

/// [`Bound::Auto`]'s choice: local bounds when the gradient bounds over
/// [`AUTO_PROBE_SPLITS`]^3 sub-boxes of the domain are mostly well below the global bound
/// `lambda` (their median below [`AUTO_LOCAL_SHARE`] of it), else the global bound: where
/// the gradient is about as steep everywhere (noise), a segment's bound is no smaller
/// and only costs its range evaluation (measured: 2x slower on the hypertexture).
pub fn auto_bound<S: Shape + ?Sized>(shape: &S, domain: &Aabb, lambda: f64) -> Bound {
    let n = AUTO_PROBE_SPLITS;
    let size = (domain.max - domain.min) / n as f64;
    let mut v = Vec::with_capacity(n * n * n);
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let lo = domain.min + size * DVec3::new(i as f64, j as f64, k as f64);
                let b = Aabb::new(lo, lo + size);
                v.push(model_ir::gradient_bound::gradient_bound_on_box(shape, &b));
            }
        }
    }
    v.sort_by(f64::total_cmp);
    if v[v.len() / 2] < AUTO_LOCAL_SHARE * lambda {
        Bound::Local
    } else {
        Bound::Lipschitz
    }
}

/// How cones (and terminal rays) are proved clear of the surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bound {
    /// The paper's: one global Lipschitz bound [`Options::lambda`] (Fig. 3, and the
    /// overshooting ray caster for terminal samples).
    Lipschitz,
    /// Local Lipschitz bounds: per cone segment ([`trace_cone_local`]) and per ray
    /// segment for terminal rays ([`local_trace`]), each capped by the global bound.
    Local,
    /// No Lipschitz bound: each cone segment is tested with this range arithmetic over
    /// the cone's frustum ([`trace_cone_range`]), terminal rays by Algorithm 1
    /// ([`first_root`]) from the radius the cones cleared.
    Range(ArithKind),
    /// [`Bound::Local`] or [`Bound::Lipschitz`], chosen by [`auto_bound`] when the engine
    /// is made.
    Auto,
}

impl Bound {
    /// Command-line name: `lipschitz`, `local`, or `range`.
    pub const fn name(self) -> &'static str {
        match self {
            Bound::Lipschitz => "lipschitz",
            Bound::Local => "local",
            Bound::Range(_) => "range",
            Bound::Auto => "auto",
        }
    }
    /// Whether this mode needs [`Options::lambda`].
    pub fn needs_lambda(self) -> bool {
        !matches!(self, Bound::Range(_))
    }
}

/// Engine options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Lipschitz bound of `f` over the domain.
    pub lambda: f64,
    /// Hit precision: a ray stops where the unbounding radius `|f| / λ` is below it.
    pub eps: f64,
    /// Overshooting factor of the terminal ray caster.
    pub overshoot: f64,
    /// Anti-aliasing: samples are subdivided to `1/aa` of a pixel and filtered into
    /// pixels with [`Options::filter`] (Appendix A).
    pub aa: u32,
    /// The anti-aliasing filter of eq. (A.1) (used when `aa > 1`).
    pub filter: Kernel,
    /// Child cone start rule.
    pub child_start: ChildStart,
    /// How cones and terminal rays are proved clear.
    pub bound: Bound,
}

impl Options {
    /// Defaults for a bound `lambda`: precision `1e-4`, overshoot 1.46, no anti-aliasing,
    /// the global bound only ([`Bound::Lipschitz`]).
    pub fn new(lambda: f64) -> Self {
        Options {
            lambda,
            eps: 1e-4,
            overshoot: crate::search::lipschitz::DEFAULT_OVERSHOOT,
            aa: 1,
            filter: Kernel::default(),
            child_start: ChildStart::Radial,
            bound: Bound::Lipschitz,
        }
    }

    /// Defaults for the range test with arithmetic `kind` ([`Bound::Range`]): no
    /// Lipschitz bound needed.
    pub fn range(kind: ArithKind) -> Self {
        Options {
            bound: Bound::Range(kind),
            ..Options::new(f64::NAN)
        }
    }
}

/// A rectangle of pixels `[x0, x1) x [y0, y1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    /// Left edge (inclusive).
    pub x0: u32,
    /// Top edge (inclusive).
    pub y0: u32,
    /// Right edge (exclusive).
    pub x1: u32,
    /// Bottom edge (exclusive).
    pub y1: u32,
}

impl Rect {
    /// The rectangle spanned by two corners (in any order), `x1`/`y1` inclusive.
    pub fn from_corners(a: (u32, u32), b: (u32, u32)) -> Rect {
        Rect {
            x0: a.0.min(b.0),
            y0: a.1.min(b.1),
            x1: a.0.max(b.0) + 1,
            y1: a.1.max(b.1) + 1,
        }
    }
    fn scaled(&self, k: u32) -> Rect {
        Rect {
            x0: self.x0 * k,
            y0: self.y0 * k,
            x1: self.x1 * k,
            y1: self.y1 * k,
        }
    }
    fn intersects(&self, s: &Sample) -> bool {
        s.x < self.x1 && s.x + s.n > self.x0 && s.y < self.y1 && s.y + s.n > self.y0
    }
}

/// A square sample of `n x n` (virtual) pixels at `(x, y)`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Sample {
    x: u32,
    y: u32,
    n: u32,
    /// Number of splits applied since the top level.
    level: usize,
    /// [`ChildStart::Radial`]: the clear radius `R`; [`ChildStart::Paper`]: the parent's `t_M`.
    start: f64,
    /// [`ChildStart::Paper`]: the parent's axis (the sample's own for top-level samples).
    parent_dir: DVec3,
    top: bool,
}

/// Counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Samples processed (the paper's "iterations").
    pub iterations: u64,
    /// Point evaluations of `f` by cone tracing and ray casting.
    pub evals: u64,
    /// Point evaluations of `f` for normals (6 per shaded sample).
    pub shading_evals: u64,
    /// Range evaluations (`Dual<Interval>`) for local Lipschitz bounds.
    pub range_evals: u64,
}

/// What one [`Engine::step`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// The queues are empty: the image is final.
    Done,
    /// One sample was processed. `level_started`: the first sample of a deeper level
    /// (from the primary queue) was taken, i.e. the previous level is complete.
    /// `roi_finished`: the region of interest became fully refined.
    Processed {
        /// The level whose first sample was just taken, if one was.
        level_started: Option<usize>,
        /// Whether the region of interest became fully refined.
        roi_finished: bool,
    },
}

/// The progressive refinement renderer for one shape and image.
pub struct Engine<S: Shape> {
    shape: S,
    bounded_domain: Aabb,
    opts: Options,
    cam: Camera,
    light: Light,
    material: Material,
    width: u32,
    height: u32,
    /// Virtual (anti-aliasing) resolution.
    vw: u32,
    vh: u32,
    plan: Plan,
    queue: VecDeque<Sample>,
    roi_queue: VecDeque<Sample>,
    roi: Option<Rect>,
    /// Clear radius of every ray from the eye: the distance to the domain.
    r_near: f64,
    /// Farthest distance from the eye to the domain.
    t_far: f64,
    vcolour: Vec<[u8; 3]>,
    /// Virtual pixels painted at least once, and how many.
    painted: Vec<bool>,
    painted_count: usize,
    depth: Vec<f64>,
    done: Vec<bool>,
    image: Arc<SharedImage>,
    filter: Filter,
    stats: Stats,
    primary_level: usize,
}

impl<S: Shape> Engine<S> {
    /// An engine rendering `shape` (on `domain`, seen from `view`) at `width x height`.
    pub fn new(
        shape: S,
        domain: Aabb,
        view: View,
        width: u32,
        height: u32,
        mut opts: Options,
    ) -> Result<Self, String> {
        if opts.bound.needs_lambda() && !(opts.lambda.is_finite() && opts.lambda > 0.0) {
            return Err(format!(
                "the Lipschitz bound must be positive and finite, got {}",
                opts.lambda
            ));
        }
        if !(opts.eps.is_finite() && opts.eps > 0.0) {
            return Err(format!("the precision must be positive, got {}", opts.eps));
        }
        if !(opts.overshoot >= 1.0 && opts.overshoot < 2.0) {
            return Err(format!(
                "the overshooting factor must be in [1, 2), got {}",
                opts.overshoot
            ));
        }
        if opts.aa == 0 || opts.aa > 16 {
            return Err(format!("--aa must be in 1..=16, got {}", opts.aa));
        }
        model_ir::camera::check_size(width, height)?;
        model_ir::shape::check_domain(&domain).map_err(|e| format!("domain box: {e}"))?;
        if opts.bound == Bound::Auto {
            opts.bound = auto_bound(&shape, &domain, opts.lambda);
        }
        let (vw, vh) = (width * opts.aa, height * opts.aa);
        if vw > model_ir::camera::MAX_SIDE || vh > model_ir::camera::MAX_SIDE {
            return Err(format!(
                "image size {width}x{height} at --aa {} is {vw}x{vh} samples: each side \
                 must be at most {} samples",
                opts.aa,
                model_ir::camera::MAX_SIDE
            ));
        }
        let cam = Camera::try_new(view, vw, vh)?;
        let plan = Plan::for_image(vw, vh);
        // Orthographic: every ray starts on the image plane and distances are depths
        // along `forward` (the domain's nearest and farthest).
        let ortho = cam.ortho.is_some();
        let depth_of = |p: DVec3| (p - cam.eye).dot(cam.forward);
        let mut r_near = if ortho {
            f64::INFINITY
        } else {
            box_distance(cam.eye, &domain)
        };
        let mut t_far = 0.0f64;
        for c in 0..8 {
            let p = DVec3::new(
                if c & 1 == 0 {
                    domain.min.x
                } else {
                    domain.max.x
                },
                if c & 2 == 0 {
                    domain.min.y
                } else {
                    domain.max.y
                },
                if c & 4 == 0 {
                    domain.min.z
                } else {
                    domain.max.z
                },
            );
            if ortho {
                r_near = r_near.min(depth_of(p));
                t_far = t_far.max(depth_of(p));
            } else {
                t_far = t_far.max((p - cam.eye).length());
            }
        }
        if ortho {
            // A margin for the rounding of the depths.
            r_near = (r_near - 1e-12 * t_far.abs()).max(0.0);
        }
        let t_far = t_far * (1.0 + 1e-12);
        let mut queue = VecDeque::new();
        for j in 0..plan.v {
            for i in 0..plan.u {
                queue.push_back(Sample {
                    x: i * plan.size,
                    y: j * plan.size,
                    n: plan.size,
                    level: 0,
                    start: r_near,
                    parent_dir: DVec3::ZERO,
                    top: true,
                });
            }
        }
        let n = vw as usize * vh as usize;
        Ok(Engine {
            light: Light::for_camera(&cam),
            material: Material::default(),
            shape,
            bounded_domain: domain,
            opts,
            cam,
            width,
            height,
            vw,
            vh,
            plan,
            queue,
            roi_queue: VecDeque::new(),
            roi: None,
            r_near,
            t_far,
            vcolour: vec![BACKGROUND; n],
            painted: vec![false; n],
            painted_count: 0,
            depth: vec![f64::NAN; n],
            done: vec![false; n],
            image: Arc::new(SharedImage::new(width, height, BACKGROUND)),
            filter: Filter::new(opts.filter, opts.aa),
            stats: Stats::default(),
            primary_level: 0,
        })
    }

    /// The subdivision plan (at the anti-aliasing resolution).
    pub fn plan(&self) -> &Plan {
        &self.plan
    }
    /// The shared image buffer (at the output resolution).
    pub fn image(&self) -> Arc<SharedImage> {
        Arc::clone(&self.image)
    }
    /// Counters so far.
    pub fn stats(&self) -> Stats {
        self.stats
    }
    /// Whether every pixel has been painted at least once: a first full-frame preview.
    pub fn fully_painted(&self) -> bool {
        self.painted_count == self.painted.len()
    }
    /// Whether every sample is processed.
    pub fn is_done(&self) -> bool {
        self.queue.is_empty() && self.roi_queue.is_empty()
    }
    /// Samples waiting in the primary and the secondary (ROI) queue.
    pub fn queue_lens(&self) -> (usize, usize) {
        (self.queue.len(), self.roi_queue.len())
    }
    /// The active region of interest.
    pub fn roi(&self) -> Option<Rect> {
        self.roi
    }
    /// Depth of each (virtual) pixel: the hit's ray parameter, `+inf` for a miss, NaN
    /// while not final. Row-major at `aa` times the output resolution.
    pub fn depth(&self) -> &[f64] {
        &self.depth
    }
    /// Whether output pixel `(i, j)` has its final colour.
    pub fn pixel_done(&self, i: u32, j: u32) -> bool {
        let a = self.opts.aa;
        (0..a).all(|dy| (0..a).all(|dx| self.done[((j * a + dy) * self.vw + i * a + dx) as usize]))
    }

    /// The sample's pixels inside the image, `[x, x1) x [y, y1)` (a padded plan's samples
    /// overhang it).
    fn span(&self, s: &Sample) -> (u32, u32) {
        ((s.x + s.n).min(self.vw), (s.y + s.n).min(self.vh))
    }

    fn bounded(&self) -> Bounded<'_, S> {
        Bounded {
            shape: &self.shape,
            domain: self.bounded_domain,
            lambda: self.opts.lambda,
        }
    }

    /// Sets a region of interest (output pixels): every queued sample meeting it moves to
    /// the secondary queue, which is refined first (Section 3.4). Replaces an active one.
    pub fn set_roi(&mut self, r: Rect) -> Result<(), String> {
        if r.x0 >= r.x1 || r.y0 >= r.y1 || r.x1 > self.width || r.y1 > self.height {
            return Err(format!(
                "region {r:?} is empty or outside the {}x{} image",
                self.width, self.height
            ));
        }
        self.cancel_roi();
        let vr = r.scaled(self.opts.aa);
        let (inside, outside): (VecDeque<_>, VecDeque<_>) =
            self.queue.drain(..).partition(|s| vr.intersects(s));
        self.queue = outside;
        self.roi_queue = inside;
        self.roi = Some(r);
        Ok(())
    }

    /// Cancels the region of interest: its samples return to the primary queue, merged
    /// by level so the queue stays in breadth-first order.
    pub fn cancel_roi(&mut self) {
        self.roi = None;
        if self.roi_queue.is_empty() {
            return;
        }
        let a: Vec<Sample> = self.queue.drain(..).collect();
        let b: Vec<Sample> = self.roi_queue.drain(..).collect();
        let (mut i, mut j) = (0, 0);
        while i < a.len() || j < b.len() {
            if j >= b.len() || (i < a.len() && a[i].level <= b[j].level) {
                self.queue.push_back(a[i]);
                i += 1;
            } else {
                self.queue.push_back(b[j]);
                j += 1;
            }
        }
    }

    /// Processes one sample.
    pub fn step(&mut self) -> Step {
        let mut roi_finished = false;
        let mut level_started = None;
        let from_roi = self.roi.is_some() && !self.roi_queue.is_empty();
        let s = if from_roi {
            self.roi_queue.pop_front()
        } else {
            if self.roi.take().is_some() {
                roi_finished = true;
            }
            let s = self.queue.pop_front();
            if let Some(s) = &s {
                if s.level > self.primary_level {
                    self.primary_level = s.level;
                    level_started = Some(s.level);
                }
            }
            s
        };
        let Some(s) = s else {
            return Step::Done;
        };
        self.stats.iterations += 1;
        if s.n == 1 {
            self.terminal(&s);
        } else {
            self.cone(&s, from_roi);
        }
        if from_roi && self.roi_queue.is_empty() {
            self.roi = None;
            roi_finished = true;
        }
        Step::Processed {
            level_started,
            roi_finished,
        }
    }

    /// Runs to completion.
    pub fn run(&mut self) {
        while self.step() != Step::Done {}
    }

    fn terminal(&mut self, s: &Sample) {
        let (o, d) = self.cam.ray_at(s.x as f64 + 0.5, s.y as f64 + 0.5);
        let mut evals = 0;
        let hit = match clip_to_box(o, d, &self.bounded_domain) {
            None => None,
            Some((t_in, t_out)) => {
                let start = match self.opts.child_start {
                    ChildStart::Radial => s.start,
                    ChildStart::Paper if s.top => self.r_near,
                    ChildStart::Paper => s.start / d.dot(s.parent_dir),
                };
                let (t0, eps, k) = (start.max(t_in), self.opts.eps, self.opts.overshoot);
                match self.opts.bound {
                    // `Auto` is resolved in `Engine::new`.
                    Bound::Local | Bound::Auto => {
                        let mut c = LocalCounts::default();
                        let t = local_trace(&self.bounded(), o, d, t0, t_out, eps, k, &mut c);
                        evals = c.evals;
                        self.stats.range_evals += c.range_evals;
                        t
                    }
                    Bound::Lipschitz => {
                        let c = overshoot_trace(&self.bounded(), o, d, t0, t_out, eps, k);
                        evals = c.evals;
                        c.t
                    }
                    Bound::Range(kind) if t0 <= t_out => {
                        let params = RayParams {
                            precision: Precision { abs: eps, rel: 0.0 },
                            pruning: true,
                        };
                        let mut st = RayStats::default();
                        let start = Start::whole(t0, t_out);
                        let t = model_ir::with_arith!(kind, A => first_root::<A, S>(
                            &self.shape, o, d, start, &params, &mut st
                        ));
                        evals = st.point_evals;
                        self.stats.range_evals += st.range_evals;
                        t
                    }
                    Bound::Range(_) => None,
                }
            }
        };
        self.stats.evals += evals;
        let idx = (s.y * self.vw + s.x) as usize;
        let colour = match hit {
            Some(t) => {
                self.depth[idx] = t;
                self.shade_at(o + d * t, d)
            }
            None => {
                self.depth[idx] = f64::INFINITY;
                BACKGROUND
            }
        };
        self.done[idx] = true;
        self.paint(s, colour);
    }

    fn shade_at(&mut self, p: DVec3, d: DVec3) -> [u8; 3] {
        self.stats.shading_evals += 6;
        let n = shade::normal(&self.shape, p, 1e-5 * (1.0 + p.length()));
        shade::shade(n, d, &self.light, &self.material, false)
    }

    /// The aperture: eq. (3) with the bounding circle of the sample, widened where needed
    /// to the largest angle between the axis and the sample's corner rays (off the image
    /// centre the image plane is oblique to the axis and eq. (3) alone can miss corners).
    fn tan_aperture(&self, s: &Sample, d: DVec3) -> f64 {
        let c = &self.cam;
        let p = c.raw_dir(s.x as f64 + s.n as f64 * 0.5, s.y as f64 + s.n as f64 * 0.5);
        let dl = 2.0 * c.tan_half / c.height as f64;
        let eps = 0.5 * std::f64::consts::SQRT_2 * s.n as f64 * dl;
        let mut t = eps / p.length();
        for (cx, cy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let q = c
                .raw_dir((s.x + cx * s.n) as f64, (s.y + cy * s.n) as f64)
                .normalize();
            let cos = q.dot(d).clamp(-1.0, 1.0);
            let sin = (1.0 - cos * cos).max(0.0).sqrt();
            t = t.max(sin / cos);
        }
        // A relative margin for the rounding of the above.
        t * (1.0 + 1e-9)
    }

    fn cone(&mut self, s: &Sample, from_roi: bool) {
        let (o, d) = self
            .cam
            .ray_at(s.x as f64 + s.n as f64 * 0.5, s.y as f64 + s.n as f64 * 0.5);
        // Orthographic: the sample's rays fill a cylinder of radius `rho` about the axis
        // (the sample's half diagonal). It is traced as the cone of apex `o - L d` with
        // `tan a = rho / L`, which holds it at every depth `t >= 0` (its radius there is
        // `rho (1 + t / L)`) and is barely wider for `L` far beyond the domain; distances
        // along that cone are `L` more than the depths (`shift`). Its points nearer than
        // `start` are in the region its parent cleared (or before the domain).
        let (apex, tan_a, shift, t0) = if self.cam.ortho.is_some() {
            let rho = 0.5 * std::f64::consts::SQRT_2 * s.n as f64 * self.cam.pixel_size();
            let l = 1024.0 * (self.t_far + rho) + 1.0;
            let tan_a = rho / l * (1.0 + 1e-9);
            (o - d * l, tan_a, l, l + s.start)
        } else {
            let tan_a = self.tan_aperture(s, d);
            let cos_a = 1.0 / (1.0 + tan_a * tan_a).sqrt();
            let t0 = match self.opts.child_start {
                ChildStart::Radial => s.start * cos_a,
                ChildStart::Paper if s.top => s.start * cos_a,
                ChildStart::Paper => s.start / d.dot(s.parent_dir),
            };
            (o, tan_a, 0.0, t0)
        };
        let t_far = self.t_far + shift;
        let mut evals = 0;
        let end = if let Bound::Range(kind) = self.opts.bound {
            let mut ranges = 0;
            let dom = self.bounded_domain;
            let e = model_ir::with_arith!(kind, A => trace_cone_range::<A, S>(
                &self.shape, &dom, o, d, tan_a, t0, self.t_far, &mut ranges
            ));
            self.stats.range_evals += ranges;
            e
        } else if self.opts.bound == Bound::Local {
            let mut ranges = 0;
            let e = trace_cone_local(
                &self.bounded(),
                apex,
                d,
                tan_a,
                t0,
                t_far,
                &mut evals,
                &mut ranges,
            );
            self.stats.range_evals += ranges;
            e
        } else {
            trace_cone(&self.bounded(), apex, d, tan_a, t0, t_far, &mut evals)
        };
        let end = match end {
            ConeEnd::Reached(tm) => ConeEnd::Reached(tm - shift),
            e => e,
        };
        self.stats.evals += evals;
        let (start, parent_dir, top) = match end {
            ConeEnd::Escaped => {
                let (x1, y1) = self.span(s);
                for j in s.y..y1 {
                    for i in s.x..x1 {
                        let k = (j * self.vw + i) as usize;
                        self.depth[k] = f64::INFINITY;
                        self.done[k] = true;
                    }
                }
                self.paint(s, BACKGROUND);
                return;
            }
            ConeEnd::Blocked => (s.start, s.parent_dir, s.top),
            ConeEnd::Reached(tm) => {
                let colour = self.shade_at(o + d * tm, d);
                self.paint(s, colour);
                match self.opts.child_start {
                    ChildStart::Radial => (s.start.max(tm), d, false),
                    ChildStart::Paper => (tm, d, false),
                }
            }
        };
        let p = self.plan.splits[s.level];
        let n = s.n / p;
        for cj in 0..p {
            for ci in 0..p {
                let c = Sample {
                    x: s.x + ci * n,
                    y: s.y + cj * n,
                    n,
                    level: s.level + 1,
                    start,
                    parent_dir,
                    top,
                };
                if c.x >= self.vw || c.y >= self.vh {
                    continue; // wholly outside the image (a padded plan)
                }
                match self.roi {
                    Some(r) if from_roi && r.scaled(self.opts.aa).intersects(&c) => {
                        self.roi_queue.push_back(c)
                    }
                    _ => self.queue.push_back(c),
                }
            }
        }
    }

    /// Paints a sample with one colour, then refreshes the output pixels it touches
    /// (with anti-aliasing, filtered by eq. (A.1) over the virtual pixels).
    fn paint(&mut self, s: &Sample, colour: [u8; 3]) {
        let (x1, y1) = self.span(s);
        if self.painted_count < self.painted.len() {
            for j in s.y..y1 {
                for i in s.x..x1 {
                    let k = (j * self.vw + i) as usize;
                    if !self.painted[k] {
                        self.painted[k] = true;
                        self.painted_count += 1;
                    }
                }
            }
        }
        let a = self.opts.aa;
        if a == 1 {
            let c = pack(colour);
            for j in s.y..y1 {
                for i in s.x..x1 {
                    self.vcolour[(j * self.vw + i) as usize] = colour;
                    self.image.set(i, j, c);
                }
            }
            return;
        }
        for j in s.y..y1 {
            for i in s.x..x1 {
                self.vcolour[(j * self.vw + i) as usize] = colour;
            }
        }
        // Eq. (A.1) for every pixel whose filter support meets the sample.
        let (i0, i1) = self.filter.affected(s.x, x1, self.width);
        let (j0, j1) = self.filter.affected(s.y, y1, self.height);
        for oj in j0..j1 {
            for oi in i0..i1 {
                let c = self.filter.pixel(&self.vcolour, self.vw, self.vh, oi, oj);
                self.image.set(oi, oj, pack(c));
            }
        }
    }

    /// The level of the sample the next [`Engine::step`] takes from the primary queue
    /// (`None` while a region of interest is being refined or when done).
    pub fn next_level(&self) -> Option<usize> {
        if self.roi.is_some() && !self.roi_queue.is_empty() {
            return None;
        }
        self.queue.front().map(|s| s.level)
    }
    /// The options.
    pub fn options(&self) -> &Options {
        &self.opts
    }
    /// Output size.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }
    /// Virtual (anti-aliasing) size.
    pub fn virtual_size(&self) -> (u32, u32) {
        (self.vw, self.vh)
    }
}
