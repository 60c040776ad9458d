//! Algorithm 1: reliable ray-surface intersection. On a segment of the ray the function's
//! range in the ray form (one input, `t`) excludes 0, or the segment is pruned with the
//! form's linear part and halved, first half first; a segment shorter than the precision
//! whose range holds 0 is the root, so no root is ever missed. The search is a state
//! machine ([`RaySearch`]) asking for one range at a time, so [`first_roots`] searches
//! many rays in lock-step, their segments evaluated in batches of
//! [`Arithmetic::RayPack`]s. The paper's loop, our two departures
//! from it (sign-change shortcut, marching from the cell's slice) and their measured effect
//! are in `docs/algorithm-1-ray.md`.

use crate::search::windows::Windows;
use arith_core::pack::LANES;
use arith_core::round::ETA;
use arith_core::{Arithmetic, Range};
use glam::DVec3;
use model_ir::shape::{Aabb, Shape};
use model_ir::shape_batch::{Batch, Groups};

/// When to stop subdividing: a segment `[t0, t1]` is resolved once
/// `t1 - t0 <= abs + rel * max(t0, 0)`.
///
/// `rel` ties the precision to a pixel's footprint at that distance (the renderer uses a
/// quarter of a pixel's angular size); `abs` is a floor tied to the domain size (or the
/// user's `--eps T`, then `rel = 0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Precision {
    /// Absolute part of the precision.
    pub abs: f64,
    /// Relative part, per unit of distance from the eye.
    pub rel: f64,
}

impl Precision {
    /// Largest resolved segment length at distance `t`.
    #[inline]
    pub fn at(&self, t: f64) -> f64 {
        self.abs + self.rel * t.max(0.0)
    }
}

/// Options of one intersection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayParams {
    /// When a segment is resolved.
    pub precision: Precision,
    /// Argument pruning with the linear part of the form (no effect for IA).
    pub pruning: bool,
}

/// Work counters; summed over rays by the renderer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayStats {
    /// Range evaluations (one per segment tested).
    pub range_evals: u64,
    /// Segments pruned to nothing by argument pruning (proved root-free).
    pub pruned_empty: u64,
    /// Point evaluations (sign checks at the ends of resolved segments).
    pub point_evals: u64,
    /// Instructions run by the range evaluations, for shapes that are tapes
    /// ([`Shape::tape_len`]; counted by [`first_roots`]).
    pub range_ops: u64,
}

impl std::ops::AddAssign for RayStats {
    fn add_assign(&mut self, o: Self) {
        self.range_evals += o.range_evals;
        self.pruned_empty += o.pruned_empty;
        self.point_evals += o.point_evals;
        self.range_ops += o.range_ops;
    }
}

/// The parameter interval `[t0, t1]` (with `t0 >= tmin`) where the ray `o + t d` lies in
/// `domain` (slab test), widened outward by a few ulps so rounding never cuts off a piece
/// of the ray inside the box. `None` when the ray misses the box.
pub fn clip(o: DVec3, d: DVec3, domain: &Aabb, tmin: f64) -> Option<(f64, f64)> {
    clip_with(o, d, d.recip(), domain, tmin)
}

/// [`clip`] with `inv == d.recip()` given (computed for several rays at once).
#[inline]
pub fn clip_with(o: DVec3, d: DVec3, inv: DVec3, domain: &Aabb, tmin: f64) -> Option<(f64, f64)> {
    let mut t0 = f64::NEG_INFINITY;
    let mut t1 = f64::INFINITY;
    // One division per axis: `(lo - o) * (1/d)` is off by at most ~3 ulps, as covered.
    for k in 0..3 {
        let (ok, dk, lo, hi) = (o[k], d[k], domain.min[k], domain.max[k]);
        if dk == 0.0 {
            if ok < lo || ok > hi {
                return None;
            }
            continue;
        }
        let (a, b) = if inv[k].is_finite() {
            ((lo - ok) * inv[k], (hi - ok) * inv[k])
        } else {
            ((lo - ok) / dk, (hi - ok) / dk)
        };
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        t0 = t0.max(a);
        t1 = t1.min(b);
    }
    if !(t0.is_finite() && t1.is_finite()) {
        return None;
    }
    // Each quotient is off by at most a few ulps (and by an ETA or two when tiny, or
    // when `1/d` is subnormal); widen by more than that.
    let m = (t0.abs() + t1.abs()) * 8.0 * f64::EPSILON + ETA;
    let (t0, t1) = ((t0 - m).max(tmin), t1 + m);
    if t0 <= t1 {
        Some((t0, t1))
    } else {
        None
    }
}

/// The function's range on the segment `[t0, t1]` of the ray, in the ray form.
#[inline]
pub fn range_on_segment<R: Range, S: Shape + ?Sized>(
    shape: &S,
    o: DVec3,
    d: DVec3,
    t0: f64,
    t1: f64,
) -> R {
    let [x, y, z] = ray_inputs(o, d, t0, t1);
    shape.eval(x, y, z)
}

/// The coordinates `o + t d` of the segment `[t0, t1]` of the ray, in the ray form.
#[inline]
pub fn ray_inputs<R: Range>(o: DVec3, d: DVec3, t0: f64, t1: f64) -> [R; 3] {
    let t = R::input(0, t0, t1);
    let x = t.clone() * d.x + o.x;
    let y = t.clone() * d.y + o.y;
    let z = t * d.z + o.z;
    [x, y, z]
}

/// Sound argument pruning (Section 4.1.2). With `t = m + r eps` (`m`, `r` the midpoint
/// and radius of `[t0, t1]`) and `f in f0 + f1 eps ± e`, a root needs
/// `|f0 + f1 eps| <= e`, i.e. `eps` between `(-e - f0)/f1` and `(e - f0)/f1`: the paper's
/// `t' = t0 - t1 f0/f1 ± e t1/f1`. The result is widened by a margin far above both the
/// rounding of these few operations and how the arithmetic itself rounded `m` and `r`
/// (its `input` puts that error into `e`, a few ulps of `|m| + r`), so no root is ever
/// pruned away. Returns the pruned segment, `Some(None)` when it is empty (no root),
/// `None` when pruning does not apply (no linear part, `f1` zero, non-finite values).
#[inline]
pub fn prune<R: Range>(f: &R, t0: f64, t1: f64) -> Option<Option<(f64, f64)>> {
    let lin = f.linear_part()?;
    Pruner::new(t0, t1, lin.f1)?.prune(lin.f0, lin.e)
}

/// Argument pruning of `[t0, t1]` along a linear part of slope `f1`, set up once for any
/// number of constant parts `f0 ± e` (a bundle's rays share the slope of its form).
///
/// Rounding, in units of `U = 2^-53`: each `eps` bound is three roundings off (the sum,
/// `1/f1`, the product), at most `3.1 U` of itself (`1/f1` is normal, checked). Where it
/// matters, a bound `lo` at most 2 (when the exact `lo` is above 2 the root would lie
/// past `m + 2r > t1`, and the computed `p0` does too, so the segment is empty either
/// way; a bound below -1 is clamped to -1, which only widens), `r lo` is off by
/// `6.2 U r` from that and by `2 U r` more, `m + r lo` by `U (|m| + 2r)` more, and the
/// margin's subtraction by about as much again: in all under `13 U (|m| + r)`, plus an
/// `ETA` or two where results are subnormal, against a margin of
/// `32 U (|m| + r) + 4 ETA` (the rest of it for the arithmetic's own `m`, `r`, off by at
/// most `U (|m| + r)`). Plain round-to-nearest operations instead of
/// directed steps, and no division: pruning sits on every ray's and cell's critical path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pruner {
    t0: f64,
    t1: f64,
    m: f64,
    r: f64,
    margin: f64,
    inv: f64,
}

impl Pruner {
    /// `None` when pruning does not apply: `f1` zero, not finite, or with a subnormal
    /// reciprocal (`|f1| > 2^1022`).
    #[inline]
    pub fn new(t0: f64, t1: f64, f1: f64) -> Option<Pruner> {
        let inv = 1.0 / f1;
        if !(f1.is_finite() && inv.is_normal()) {
            return None;
        }
        let m = 0.5 * t0 + 0.5 * t1;
        let r = 0.5 * t1 - 0.5 * t0;
        let margin = (m.abs() + r) * (16.0 * f64::EPSILON) + 4.0 * ETA;
        Some(Pruner {
            t0,
            t1,
            m,
            r,
            margin,
            inv,
        })
    }

    /// The pruned segment for the constant part `f0 ± e`, `Some(None)` when it is empty
    /// (no root), `None` when pruning does not apply (non-finite values).
    #[inline]
    pub fn prune(&self, f0: f64, e: f64) -> Option<Option<(f64, f64)>> {
        if !(f0.is_finite() && e.is_finite()) {
            return None;
        }
        let q0 = (-e - f0) * self.inv;
        let q1 = (e - f0) * self.inv;
        let (lo, hi) = if self.inv > 0.0 { (q0, q1) } else { (q1, q0) };
        if !(lo.is_finite() && hi.is_finite()) {
            return None;
        }
        let lo = lo.max(-1.0);
        let hi = hi.min(1.0);
        let p0 = (self.m + self.r * lo) - self.margin;
        let p1 = (self.m + self.r * hi) + self.margin;
        if !(p0.is_finite() && p1.is_finite()) {
            return None;
        }
        let n0 = self.t0.max(p0);
        let n1 = self.t1.min(p1);
        if n0 > n1 {
            Some(None)
        } else {
            Some(Some((n0, n1)))
        }
    }
}

/// A segment of length `<= eps` whose ends show no sign change is reported only once it
/// is `REFINE` times shorter still (and its own range still holds 0). Reliable either way;
/// this makes spurious hits (an overestimated range next to a near miss) so rare that
/// hit masks do not depend on culling or pruning, at a few extra evaluations on
/// silhouettes, tangent roots and thin features only. 2^-10 was not enough once rays
/// march from culling's first slice (IA kept an unconfirmed hit 1e-6 long where
/// `|f| > 0.016`, found with one segmentation and not another); 2^-30 costs no measurable
/// evaluations on the paper's models.
pub const REFINE: f64 = 1.0 / (1u64 << 30) as f64;

/// Whether `[fa, fb]` holds 0 (a sign change or a zero at an end).
#[inline]
fn opposite(fa: f64, fb: f64) -> bool {
    (fa <= 0.0 && fb >= 0.0) || (fa >= 0.0 && fb <= 0.0)
}

/// `f` at the point `o + t d`.
#[inline]
fn point_on_ray<S: Shape + ?Sized>(shape: &S, o: DVec3, d: DVec3, t: f64) -> f64 {
    let p = o + d * t;
    shape.eval(p.x, p.y, p.z)
}

/// Each piece of the march after `[t0, split]` is this much longer than the segment last
/// proved root-free (measured: 1.5 beat 1.25, 2 and 3 over Mitchell, the decocube, CSG,
/// the noisy sphere, hair and the microstructure).
pub const MARCH_GROWTH: f64 = 1.5;

/// The end of the next piece of a march from `rest` towards `end` whose step is `step`:
/// the whole rest when that is less than one and a half steps away (or the step is lost
/// to rounding), so no sliver is left over.
#[inline]
pub(crate) fn next_piece(rest: f64, end: f64, step: f64) -> f64 {
    if rest + 1.5 * step >= end || rest + step <= rest {
        end
    } else {
        rest + step
    }
}

/// How much longer than the precision a ray's first piece may be for its first
/// precision's length to be tried by a sign change before any range evaluation.
pub const SHORT_PIECES: f64 = 3.0;

/// Depth of the explicit subdivision stack. Halving stops at the precision (whose floor
/// is positive) or at floating-point resolution, long before this; should it ever fill,
/// the segment at hand is reported as a root (a hit, never a miss).
const STACK: usize = 128;

/// Where the search of a ray starts, in the ray's parameter (`t`; culling hands rays
/// the same in depth along `forward`, see [`crate::search::cull`]): `[t0, t1]` is
/// searched, `[t0, split]` first (any `split` is sound; one outside `(t0, t1)` is
/// ignored). The caller may know more: `(split, resume)` proved root-free, then the
/// search goes on at `resume` after `[t0, split]` (`resume == split` when it knows
/// nothing), and a length on which the function's ranges are known to be tight: the
/// march's first piece after `[t0, split]` is at least `step` long (`0`: none known).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Start {
    /// Start of the searched segment.
    pub t0: f64,
    /// End of the part searched first.
    pub split: f64,
    /// Where the search goes on after `[t0, split]`.
    pub resume: f64,
    /// Least length of the march's first piece after `[t0, split]` (`0`: none known).
    pub step: f64,
    /// End of the searched segment.
    pub t1: f64,
}

impl Start {
    /// The whole of `[t0, t1]`, nothing known about it.
    #[inline]
    pub const fn whole(t0: f64, t1: f64) -> Start {
        Start {
            t0,
            split: t1,
            resume: t1,
            step: 0.0,
            t1,
        }
    }
}

/// The first root of `shape` on the ray `o + t d` searched as `start` says (Algorithm 1,
/// first root only), in the arithmetic `A`'s ray form: [`RaySearch`] driven by one loop.
/// Allocates only when a segment has to be halved.
pub fn first_root<A: Arithmetic, S: Shape + ?Sized>(
    shape: &S,
    o: DVec3,
    d: DVec3,
    start: Start,
    params: &RayParams,
    stats: &mut RayStats,
) -> Option<f64> {
    let ray = RayCtx {
        shape,
        windows: None,
        depth: 1.0,
        o,
        d,
        params,
    };
    let mut stack = Vec::new();
    let (mut search, mut next) = RaySearch::start(&ray, start, stats, &mut stack);
    loop {
        match next {
            Next::Eval(a, b) => {
                let f: A::Ray = range_on_segment(shape, o, d, a, b);
                next = search.feed(&f, &ray, stats, &mut stack);
            }
            Next::Points(ts, n) => {
                next = search.signs(points_on(&ray, ts, n), stats, &mut stack);
            }
            Next::Done(hit) => return hit,
        }
    }
}

/// What a [`RaySearch`] needs of its ray between range evaluations: the shape (for the
/// sign checks at points), the ray `o + t d` and the search options.
#[derive(Clone, Copy)]
pub struct RayCtx<'a, S: ?Sized> {
    /// The shape.
    pub shape: &'a S,
    /// The shape specialised to depth windows along the ray, where there are some.
    pub windows: Option<&'a Windows<S>>,
    /// The depth the windows are in per unit of `t`.
    pub depth: f64,
    /// The ray's origin.
    pub o: DVec3,
    /// The ray's direction.
    pub d: DVec3,
    /// The search options.
    pub params: &'a RayParams,
}

impl<'a, S: ?Sized> RayCtx<'a, S> {
    /// The shape to use on the segment `[a, b]` of the ray (`a <= b`).
    #[inline]
    pub fn shape_on(&self, a: f64, b: f64) -> &'a S {
        match self.windows {
            Some(w) => w.at(self.shape, a * self.depth, b * self.depth),
            None => self.shape,
        }
    }
}

/// The next step of a [`RaySearch`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Next {
    /// The range of the function on the segment `[a, b]` of the ray is needed (pass it
    /// to [`RaySearch::feed`]).
    Eval(f64, f64),
    /// The values of the function at the points of the ray at the first `n` of these
    /// parameters are needed, for a sign check (pass them to [`RaySearch::signs`]).
    Points([f64; 2], usize),
    /// The search is over: the first root, or `None` for no root.
    Done(Option<f64>),
}

/// The sign check a [`RaySearch`] waits for.
#[derive(Clone, Copy, Debug)]
enum Check {
    /// The values at the ends of the resolved segment `[a, b]` (`shrunk`: pruned from a
    /// longer one).
    Ends { a: f64, b: f64, shrunk: bool },
    /// The value one segment's length past it, the value at `b` being `fb`.
    Past {
        a: f64,
        b: f64,
        shrunk: bool,
        fb: f64,
    },
}

/// Algorithm 1 on one ray as a state machine that asks for one segment's range at a
/// time ([`first_root`] is its plain loop): a renderer can then evaluate the
/// segments of four rays in one packed evaluation ([`arith_core::pack`]) and feed each
/// its own lane. Whoever evaluates, each segment's range is the one the ray form gives,
/// so the roots found are the same.
#[derive(Clone, Copy, Debug)]
pub struct RaySearch {
    /// The segment whose range was last asked for.
    a: f64,
    b: f64,
    /// Where the march goes on once the stack is empty.
    rest: f64,
    t1: f64,
    first_step: f64,
    /// The sign check asked for by the last [`Next::Points`].
    check: Option<Check>,
}

impl RaySearch {
    /// Starts the search of `start` (the stack, lent by the caller, is emptied). A ray
    /// may be resolved at once, by a sign change over its first piece.
    #[inline]
    pub fn start<S: Shape + ?Sized>(
        ray: &RayCtx<'_, S>,
        start: Start,
        stats: &mut RayStats,
        stack: &mut Vec<(f64, f64)>,
    ) -> (RaySearch, Next) {
        let Start {
            t0,
            split,
            resume,
            step,
            t1,
        } = start;
        let mut s = RaySearch {
            a: t0,
            b: t1,
            rest: t1,
            t1,
            first_step: step,
            check: None,
        };
        if t0.partial_cmp(&t1).is_none_or(|o| o.is_gt()) {
            return (s, Next::Done(None));
        }
        stack.clear();
        // March: `[t0, split]` first, then pieces each `MARCH_GROWTH` times longer than
        // the last segment proved root-free (a piece proved in one evaluation is cheap;
        // one range over the whole rest is loose).
        if t0 < split && split < t1 {
            s.b = split;
            s.rest = resume.clamp(split, t1);
            // A first piece already within the precision (a cell's form pruned for this
            // ray) with a sign change at its ends holds the first root: nothing before
            // `t0`. A piece up to SHORT_PIECES times longer: the same for its first
            // precision's length.
            let eps = ray.params.precision.at(t0);
            if split - t0 <= SHORT_PIECES * eps {
                let c = (t0 + eps).min(split);
                stats.point_evals += 2;
                let fa: f64 = point_on_ray(ray.shape_on(t0, t0), ray.o, ray.d, t0);
                let fc: f64 = point_on_ray(ray.shape_on(c, c), ray.o, ray.d, c);
                if opposite(fa, fc) && c > t0 {
                    return (s, Next::Done(Some(0.5 * t0 + 0.5 * c)));
                }
            }
        }
        (s, Next::Eval(s.a, s.b))
    }

    /// Goes on with `f`, the range on the segment last asked for.
    #[inline]
    pub fn feed<R: Range, S: Shape + ?Sized>(
        &mut self,
        f: &R,
        ray: &RayCtx<'_, S>,
        stats: &mut RayStats,
        stack: &mut Vec<(f64, f64)>,
    ) -> Next {
        let params = ray.params;
        let (mut a, mut b, t1) = (self.a, self.b, self.t1);
        stats.range_evals += 1;
        let mut keep = f.contains_zero();
        // Pruning shrank the segment a lot: test the pruned segment itself (an affine
        // Newton step; it converges fast) rather than split it, unless it is resolved.
        let mut shrunk = false;
        if keep && params.pruning {
            match prune(f, a, b) {
                Some(None) => {
                    stats.pruned_empty += 1;
                    keep = false;
                }
                Some(Some((na, nb))) => {
                    shrunk = nb - na < 0.5 * (b - a);
                    a = na;
                    b = nb;
                }
                None => {}
            }
        }
        if keep {
            let eps = params.precision.at(a);
            // A segment is reported without a sign change only if its own range holds 0
            // (not one pruned from a longer segment's range): then whether such a pixel
            // hits does not depend on pruning.
            if b - a <= eps * REFINE && !shrunk {
                return self.halve(a, b, shrunk, true, stack);
            }
            if b - a <= eps {
                // Everything before `a` is proved root-free, so a sign change at the ends
                // certifies the first root within the precision (see `signs`).
                stats.point_evals += 2;
                self.check = Some(Check::Ends { a, b, shrunk });
                return Next::Points([a, b], 2);
            }
            return self.halve(a, b, shrunk, false, stack);
        } else if let Some(next) = stack.pop() {
            (a, b) = next;
        } else {
            let rest = self.rest;
            if rest >= t1 {
                return Next::Done(None);
            }
            // `[a, b]` was just proved root-free: the next piece is a little longer than
            // that (a piece that had to be halved says the function's ranges are only
            // tight enough on pieces about that long), and never shorter than the
            // precision (a proved segment can be a single point, pruned to one, and a
            // zero step would never end).
            let step = ((b - a) * MARCH_GROWTH)
                .max(params.precision.at(rest))
                .max(self.first_step);
            self.first_step = 0.0;
            a = rest;
            b = next_piece(rest, t1, step);
            self.rest = b;
        }
        self.a = a;
        self.b = b;
        Next::Eval(a, b)
    }

    /// Goes on with `v`, the values asked for by the last [`Next::Points`] (the first
    /// `n` of them). A resolved segment `[a, b]` (everything before `a` proved
    /// root-free) with a sign change at its ends holds the first root within the
    /// precision. Without one (tangent root, feature thinner than the segment, or an
    /// overestimated range near a miss) the search keeps halving down to
    /// `eps * REFINE` before reporting, unless the next segment of the same length
    /// certifies a root by a sign change (an overestimated range just before a
    /// crossing, common with IA): then `b` is within one segment of the first root.
    pub fn signs(
        &mut self,
        v: [f64; 2],
        stats: &mut RayStats,
        stack: &mut Vec<(f64, f64)>,
    ) -> Next {
        match self.check.take() {
            Some(Check::Ends { a, b, shrunk }) => {
                let (fa, fb) = (v[0], v[1]);
                if opposite(fa, fb) {
                    return self.halve(a, b, shrunk, true, stack);
                }
                let c = (b + (b - a)).min(self.t1);
                if c > b {
                    stats.point_evals += 1;
                    self.check = Some(Check::Past { a, b, shrunk, fb });
                    return Next::Points([c, c], 1);
                }
                self.halve(a, b, shrunk, false, stack)
            }
            Some(Check::Past { a, b, shrunk, fb }) => {
                if opposite(fb, v[0]) {
                    return Next::Done(Some(b));
                }
                self.halve(a, b, shrunk, false, stack)
            }
            None => unreachable!("RaySearch::signs without a sign check asked for"),
        }
    }

    /// The segment `[a, b]` whose range holds 0: reported at its middle where
    /// `resolved` (or it can be halved no further), else its first half asked for (the
    /// second stacked), or, where pruning `shrunk` it, itself again.
    fn halve(
        &mut self,
        a: f64,
        mut b: f64,
        shrunk: bool,
        resolved: bool,
        stack: &mut Vec<(f64, f64)>,
    ) -> Next {
        let mid = 0.5 * a + 0.5 * b;
        if resolved || mid <= a || mid >= b || stack.len() == STACK {
            return Next::Done(Some(mid));
        }
        if !shrunk {
            stack.push((mid, b));
            b = mid;
        }
        self.a = a;
        self.b = b;
        Next::Eval(a, b)
    }
}

/// The values of `ray`'s function at the first `n` of the parameters `ts`, as
/// [`RaySearch::signs`] takes them.
fn points_on<S: Shape + ?Sized>(ray: &RayCtx<'_, S>, ts: [f64; 2], n: usize) -> [f64; 2] {
    let at = |t: f64| point_on_ray(ray.shape_on(t, t), ray.o, ray.d, t);
    [at(ts[0]), if n > 1 { at(ts[1]) } else { f64::NAN }]
}

/// One ray for [`first_roots`]: `o + t d` searched as `start` says.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayJob {
    /// The ray's origin.
    pub o: DVec3,
    /// The ray's direction.
    pub d: DVec3,
    /// Where its search starts.
    pub start: Start,
    /// Its shape: `0` the whole one, `k` the depth windows `windows[k - 1]` given to
    /// [`first_roots`] (a cell's, valid on this ray's segment).
    pub shape: u32,
    /// The depth (that the windows are in) per unit of `t`.
    pub depth: f64,
}

/// [`first_root`] for many rays, [`SLOTS`] at a time in lock-step: each step evaluates
/// the segment asked for by every search in flight, those on one shape together in one
/// batched evaluation ([`Shape::eval_batch`]) of [`Arithmetic::RayPack`]s, four rays a
/// pack (of single ray forms where the shape does not [pack](Shape::packs)), and a
/// finished search's slot takes the next ray. Calls `done(index, first root, counters)`
/// once per ray, in the order the rays finish. The roots are those of [`first_root`],
/// ray by ray: each lane of a batch is the scalar ray form's range, and no lane reads
/// another's. Each segment is evaluated with its ray's shape: `shape`, or the narrowest
/// of its windows (`windows[ray.shape - 1]`) that holds the segment.
pub fn first_roots<A: Arithmetic, S: Shape + ?Sized>(
    shape: &S,
    windows: &[&Windows<S>],
    params: &RayParams,
    rays: &[RayJob],
    done: impl FnMut(usize, Option<f64>, RayStats),
) {
    first_roots_until::<A, S>(shape, windows, params, rays, || false, done);
}

/// Evaluation steps of [`first_roots_until`] between two calls of its `stop`.
const STOP_EVERY: u32 = 64;

/// Searches in flight at once in [`first_roots_until`] (a multiple of [`LANES`]).
pub const SLOTS: usize = 8 * LANES;

/// A search in flight.
struct Slot {
    ray: usize,
    search: RaySearch,
    /// What it waits for: [`Next::Eval`] or [`Next::Points`].
    next: Next,
    stats: RayStats,
}

/// [`first_roots`] that gives up once `stop()` returns true (asked every
/// [`STOP_EVERY`] evaluation steps: one ray of a loose arithmetic on a long tape can
/// take seconds). The rays not finished by then are not reported to `done`. Returns
/// whether every ray was.
pub fn first_roots_until<A: Arithmetic, S: Shape + ?Sized>(
    shape: &S,
    windows: &[&Windows<S>],
    params: &RayParams,
    rays: &[RayJob],
    stop: impl Fn() -> bool,
    done: impl FnMut(usize, Option<f64>, RayStats),
) -> bool {
    Lockstep::<A>::default().run(shape, windows, params, rays, stop, done)
}

/// The buffers of [`first_roots_until`] (searches in flight, their stacks and ranges,
/// the batch), kept from one call of [`Lockstep::run`] to the next by a caller that
/// searches many small sets of rays.
pub struct Lockstep<A: Arithmetic> {
    slots: Vec<Option<Slot>>,
    stacks: Vec<Vec<(f64, f64)>>,
    ranges: Vec<Option<A::Ray>>,
    groups: Groups,
    batch: Batch<A::RayPack>,
    probes: Box<Probes>,
}

impl<A: Arithmetic> Default for Lockstep<A> {
    fn default() -> Self {
        Lockstep {
            slots: (0..SLOTS).map(|_| None).collect(),
            stacks: (0..SLOTS).map(|_| Vec::with_capacity(64)).collect(),
            ranges: (0..SLOTS).map(|_| None).collect(),
            groups: Groups::default(),
            batch: Batch::default(),
            probes: Box::default(),
        }
    }
}

impl<A: Arithmetic> Lockstep<A> {
    /// [`first_roots_until`] with these buffers.
    pub fn run<S: Shape + ?Sized>(
        &mut self,
        shape: &S,
        windows: &[&Windows<S>],
        params: &RayParams,
        rays: &[RayJob],
        stop: impl Fn() -> bool,
        done: impl FnMut(usize, Option<f64>, RayStats),
    ) -> bool {
        let Lockstep {
            slots,
            stacks,
            ranges,
            groups,
            batch,
            probes,
        } = self;
        slots.iter_mut().for_each(|s| *s = None);
        lockstep::<A, S>(
            shape,
            windows,
            params,
            rays,
            (slots, stacks, ranges, groups, batch, probes),
            stop,
            done,
        )
    }
}

/// The buffers [`lockstep`] works in.
type Buffers<'b, A> = (
    &'b mut [Option<Slot>],
    &'b mut [Vec<(f64, f64)>],
    &'b mut [Option<<A as Arithmetic>::Ray>],
    &'b mut Groups,
    &'b mut Batch<<A as Arithmetic>::RayPack>,
    &'b mut Probes,
);

/// The loop of [`first_roots_until`], in `buffers` (every slot empty).
fn lockstep<A: Arithmetic, S: Shape + ?Sized>(
    shape: &S,
    windows: &[&Windows<S>],
    params: &RayParams,
    rays: &[RayJob],
    (slots, stacks, ranges, groups, batch, probes): Buffers<'_, A>,
    stop: impl Fn() -> bool,
    mut done: impl FnMut(usize, Option<f64>, RayStats),
) -> bool {
    let ctx = |r: &RayJob| RayCtx {
        shape,
        windows: r.shape.checked_sub(1).map(|k| windows[k as usize]),
        depth: r.depth,
        o: r.o,
        d: r.d,
        params,
    };
    let mut queue = 0..rays.len();
    let mut steps = 0u32;
    loop {
        steps = steps.wrapping_add(1);
        if steps.is_multiple_of(STOP_EVERY) && stop() {
            return false;
        }
        for (slot, stack) in slots.iter_mut().zip(stacks.iter_mut()) {
            while slot.is_none() {
                let Some(ray) = queue.next() else { break };
                let mut stats = RayStats::default();
                let (search, next) =
                    RaySearch::start(&ctx(&rays[ray]), rays[ray].start, &mut stats, stack);
                match next {
                    Next::Done(hit) => done(ray, hit, stats),
                    next => {
                        *slot = Some(Slot {
                            ray,
                            search,
                            next,
                            stats,
                        })
                    }
                }
            }
        }
        if slots.iter().all(Option::is_none) {
            return true;
        }
        probes.check(slots, |k| ctx(&rays[k]));
        for k in 0..SLOTS {
            let Some(s) = slots[k].as_mut() else { continue };
            let Next::Points(..) = s.next else { continue };
            let next = s
                .search
                .signs(probes.values[k], &mut s.stats, &mut stacks[k]);
            settle(&mut slots[k], next, &mut done);
        }
        let shapes: [Option<&S>; SLOTS] = core::array::from_fn(|k| match slots[k].as_ref()? {
            Slot {
                ray,
                next: Next::Eval(a, b),
                ..
            } => Some(ctx(&rays[*ray]).shape_on(*a, *b)),
            _ => None,
        });
        groups.regroup(&shapes);
        let inputs = |k: usize| match slots[k].as_ref() {
            Some(Slot {
                ray,
                next: Next::Eval(a, b),
                ..
            }) => ray_inputs::<A::Ray>(rays[*ray].o, rays[*ray].d, *a, *b),
            _ => unreachable!("a grouped slot waits for a range"),
        };
        for group in groups.iter() {
            let sh = shapes[group[0]].expect("a grouped slot has a shape");
            batch.eval(sh, group, inputs, ranges);
        }
        for k in 0..SLOTS {
            let (Some(s), Some(f)) = (slots[k].as_mut(), ranges[k].take()) else {
                continue;
            };
            s.stats.range_ops += shapes[k].and_then(Shape::tape_len).unwrap_or(0) as u64;
            let next = s
                .search
                .feed(&f, &ctx(&rays[s.ray]), &mut s.stats, &mut stacks[k]);
            settle(&mut slots[k], next, &mut done);
        }
    }
}

/// A slot's search goes on with `next`: done (reported, the slot freed) or waiting.
fn settle(
    slot: &mut Option<Slot>,
    next: Next,
    done: &mut impl FnMut(usize, Option<f64>, RayStats),
) {
    match (slot.as_mut(), next) {
        (Some(s), Next::Done(hit)) => {
            done(s.ray, hit, s.stats);
            *slot = None;
        }
        (Some(s), next) => s.next = next,
        (None, _) => {}
    }
}

/// The sign checks of the searches in flight, evaluated together: every point asked
/// for by a [`Next::Points`], one batched point evaluation per shape
/// ([`Shape::eval_batch`] over `f64`, each lane what [`Shape::eval`] gives).
pub(crate) struct Probes {
    /// Per slot, the values asked for.
    values: [[f64; 2]; SLOTS],
    /// The points of one shape's batch, their slot and index, and their values.
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    owner: Vec<(usize, usize)>,
    out: Vec<f64>,
    groups: Groups,
}

impl Default for Probes {
    fn default() -> Self {
        Probes {
            values: [[f64::NAN; 2]; SLOTS],
            x: Vec::new(),
            y: Vec::new(),
            z: Vec::new(),
            owner: Vec::new(),
            out: Vec::new(),
            groups: Groups::default(),
        }
    }
}

impl Probes {
    /// Evaluates the points every slot waiting on [`Next::Points`] asks for into
    /// `values`; `ctx(ray)` is the ray's context.
    fn check<'s, S: Shape + ?Sized + 's>(
        &mut self,
        slots: &[Option<Slot>],
        ctx: impl Fn(usize) -> RayCtx<'s, S>,
    ) {
        let mut shapes: [Option<&'s S>; 2 * SLOTS] = [None; 2 * SLOTS];
        let mut at = [(0usize, 0usize, DVec3::ZERO); 2 * SLOTS];
        let mut m = 0;
        for (k, slot) in slots.iter().enumerate() {
            let Some(Slot {
                ray,
                next: Next::Points(ts, n),
                ..
            }) = slot
            else {
                continue;
            };
            let c = ctx(*ray);
            for (i, &t) in ts.iter().enumerate().take(*n) {
                shapes[m] = Some(c.shape_on(t, t));
                at[m] = (k, i, c.o + c.d * t);
                m += 1;
            }
        }
        if m == 0 {
            return;
        }
        self.groups.regroup(&shapes[..m]);
        for group in self.groups.iter() {
            let sh = shapes[group[0]].expect("a grouped point has a shape");
            self.x.clear();
            self.y.clear();
            self.z.clear();
            self.owner.clear();
            for &p in group {
                let (k, i, q) = at[p];
                self.x.push(q.x);
                self.y.push(q.y);
                self.z.push(q.z);
                self.owner.push((k, i));
            }
            sh.eval_batch(&self.x, &self.y, &self.z, &mut self.out);
            for (&(k, i), &v) in self.owner.iter().zip(&self.out) {
                self.values[k][i] = v;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::Real;

    struct Neg;
    impl Shape for Neg {
        fn eval<R: Real>(&self, x: R, _y: R, _z: R) -> R {
            x * 0.0 - 1.0
        }
    }

    /// A march that starts from a piece one ulp long (or a proved point) still crosses
    /// the segment in a few pieces: each is at least the precision long.
    #[test]
    fn march_from_a_tiny_piece_ends_quickly() {
        let params = RayParams {
            precision: Precision {
                abs: 1e-3,
                rel: 0.0,
            },
            pruning: true,
        };
        for split in [1.0f64.next_up(), 1.0 + 1e-12] {
            let mut stats = RayStats::default();
            let start = Start {
                t0: 1.0,
                split,
                resume: split,
                step: 0.0,
                t1: 2.0,
            };
            let hit = first_root::<arith_revaa::RevAaArith, _>(
                &Neg,
                DVec3::ZERO,
                DVec3::X,
                start,
                &params,
                &mut stats,
            );
            assert_eq!(hit, None);
            assert!(stats.range_evals <= 25, "{stats:?}");
        }
    }

    /// Rays searched four at a time find what each finds alone, with the same counts:
    /// every paper model (the packed operations and the lane-by-lane ones) and every
    /// progressive-refinement model (noise: not packed), every arithmetic
    /// (the SIMD pack and the lane-by-lane one), rays that finish at once, early or late
    /// (lanes refilled mid-search), and a last ray searched alone.
    #[test]
    fn packed_search_is_the_scalar_search() {
        let mut seed = 0x2545_F491_4F6C_DD1Du64;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        // Virtual Shikki evaluates one form at a time anyway (its tape branches).
        let models = model_sources::PaperModel::ALL
            .into_iter()
            .filter(|&m| m != model_sources::PaperModel::Shikki)
            .map(|m| m.model())
            .chain(model_sources::gamito_maddock::all());
        for m in models {
            let cam = model_ir::camera::Camera::try_new(m.view, 64, 64).unwrap();
            let params = pruned_at(&m, 1e-4);
            let mut jobs = Vec::new();
            // Rays until 16 meet the domain (the draws are shared between models).
            for _ in 0..400 {
                if jobs.len() == 16 {
                    break;
                }
                let (o, d) = cam.ray_at(64.0 * rnd(), 64.0 * rnd());
                let Some((t0, t1)) = clip(o, d, &m.domain, 0.0) else {
                    continue;
                };
                // A first piece of any length, the shortest ones resolved at once.
                let split = t0 + (t1 - t0) * rnd().powi(6);
                let resume = split + (t1 - split) * 0.5 * rnd();
                let start = Start {
                    t0,
                    split,
                    resume,
                    step: 0.0,
                    t1,
                };
                jobs.push(RayJob {
                    o,
                    d,
                    start,
                    shape: 0,
                    depth: 1.0,
                });
            }
            assert!(jobs.len() >= 9, "{}: {} rays", m.name, jobs.len());
            for kind in model_ir::arith::ArithKind::ALL {
                model_ir::with_arith!(kind, A => {
                    let mut got = vec![None; jobs.len()];
                    first_roots::<A, _>(&m, &[], &params, &jobs, |k, hit, st| {
                        assert!(got[k].is_none(), "ray {k} reported twice");
                        got[k] = Some((hit, st));
                    });
                    for (k, j) in jobs.iter().enumerate() {
                        let mut st = RayStats::default();
                        let hit = first_root::<A, _>(&m, j.o, j.d, j.start, &params, &mut st);
                        assert_eq!(got[k], Some((hit, st)), "{} {kind} ray {k}", m.name);
                    }
                });
            }
        }
    }

    /// Pruning on, an absolute precision of `rel` times the model's domain diagonal.
    fn pruned_at(m: &model_sources::Model, rel: f64) -> RayParams {
        RayParams {
            precision: Precision {
                abs: rel * (m.domain.max - m.domain.min).length(),
                rel: 0.0,
            },
            pruning: true,
        }
    }

    /// A stop ends the search: the rays it reports are found as alone, the rest are not
    /// reported, and without a stop every ray is.
    #[test]
    fn a_stop_ends_the_search_and_keeps_what_finished() {
        let m = model_sources::PaperModel::Mitchell.model();
        let cam = model_ir::camera::Camera::try_new(m.view, 32, 32).unwrap();
        let params = pruned_at(&m, 1e-9);
        let jobs: Vec<RayJob> = (0..32 * 32)
            .filter_map(|k| {
                let (o, d) = cam.ray_at((k % 32) as f64 + 0.5, (k / 32) as f64 + 0.5);
                let (t0, t1) = clip(o, d, &m.domain, 0.0)?;
                Some(RayJob {
                    o,
                    d,
                    start: Start::whole(t0, t1),
                    shape: 0,
                    depth: 1.0,
                })
            })
            .collect();
        type A = arith_ia::IaArith;
        let run = |stop_at: u32| {
            let asked = std::cell::Cell::new(0u32);
            let mut got = Vec::new();
            let all = first_roots_until::<A, _>(
                &m,
                &[],
                &params,
                &jobs,
                || {
                    asked.set(asked.get() + 1);
                    asked.get() >= stop_at
                },
                |k, hit, st| got.push((k, hit, st)),
            );
            (all, got)
        };
        let (all, got) = run(u32::MAX);
        assert!(all);
        assert_eq!(got.len(), jobs.len());
        let (all, got) = run(2);
        assert!(!all);
        assert!(
            !got.is_empty() && got.len() < jobs.len(),
            "{} rays",
            got.len()
        );
        for (k, hit, st) in got {
            let mut alone = RayStats::default();
            let j = &jobs[k];
            assert_eq!(
                hit,
                first_root::<A, _>(&m, j.o, j.d, j.start, &params, &mut alone)
            );
            assert_eq!(st, alone);
        }
    }

    #[test]
    fn clip_to_box() {
        let b = Aabb::cube(1.0);
        let (t0, t1) = clip(
            DVec3::new(0.0, 0.0, 5.0),
            DVec3::new(0.0, 0.0, -1.0),
            &b,
            0.0,
        )
        .unwrap();
        assert!((4.0 - 1e-12..=4.0).contains(&t0) && (6.0..6.0 + 1e-12).contains(&t1));
        assert!(clip(
            DVec3::new(2.0, 0.0, 5.0),
            DVec3::new(0.0, 0.0, -1.0),
            &b,
            0.0
        )
        .is_none());
        // Inside: starts at tmin.
        let (t0, _) = clip(DVec3::ZERO, DVec3::X, &b, 0.0).unwrap();
        assert_eq!(t0, 0.0);
        // Box behind the eye.
        assert!(clip(DVec3::new(0.0, 0.0, 5.0), DVec3::Z, &b, 0.0).is_none());
    }
}
