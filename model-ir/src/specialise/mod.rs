//! Region specialisation: a tape rewritten for one region of space (a cell of
//! Algorithm 2 and the rays it hands out) that is shorter and has, at every point of the
//! region, the same sign as the whole tape, so the same zero set and the same first root
//! along every ray there.
//!
//! One range evaluation over the region ([`Tape::specialise`]) gives the bounds of the
//! registers that can decide something, and two rules rewrite the tape:
//!
//! - **exact**: `min(a, b)` where `a`'s range lies at or below `b`'s is `a` (and `max`
//!   likewise): the value itself is unchanged;
//! - **sign only**: a register whose value matters only through its sign (the result,
//!   and whatever reaches it only through `min`, `max`, the R-functions `&`, `|`, `\`,
//!   negation, products and quotients by finite nonzero constants, the branches of a
//!   selection, or is compared with 0) is replaced by the constant `1` (`-1`) where its
//!   range lies strictly above (below) 0; then `min(1, b)` and `1 & b` become `b`,
//!   `min(-1, b)` and `-1 & b` become `-1`, and so on. Over the reals
//!   `sign(a & b) = min(sign a, sign b)` and `sign(a | b) = max(sign a, sign b)`, like
//!   `min` and `max`, so each rewrite keeps the sign of every consumer up to the result.
//!   For the same reason a sign-only `a & b` becomes `min(a, b)`, `a | b` `max(a, b)`
//!   and `a \ b` `min(a, -b)` (everywhere, not only in the region): the same sign at
//!   every point, and a range as tight as the operands' where the R-function's, over
//!   operands that overlap, reaches far past both.
//!
//! The proofs, the region a cell's tape must cover and why normals still come from the
//! whole function are in [`proofs`]. A specialised tape is only valid in
//! the region it was derived for, and its values there are not those of the function
//! (only their signs are): it serves root finding and culling, never shading.
//!
//! Identical decisions give identical tapes, so each tape keeps the tapes it has built,
//! keyed by its decisions ([`CACHE_LIMIT`] of them), and neighbouring cells share one.

use crate::instr::Instr;
use crate::tape::Tape;
use arith_core::Range;
use arith_ia::Interval;
use one_pass::rebuild;
use rules::{Fold, Specialiser, KEEP};
use rustc_hash::FxHashMap as HashMap;
use std::any::TypeId;

mod one_pass;
pub(crate) mod rules;
mod trace;
pub use rules::MIN_SPECIALISE_LEN;
pub use trace::Trace;

/// Specialised tapes a tape keeps for reuse.
pub const CACHE_LIMIT: usize = 512;

#[doc = include_str!("../../docs/specialisation.md")]
pub mod proofs {}

impl Tape {
    fn specialiser(&self) -> &Specialiser {
        self.shared()
            .rules
            .get_or_init(|| Specialiser::new(self.instructions(), self.shared().affine_bounds))
    }

    /// Whether [`Tape::specialise`] can ever give a shorter tape (long enough, and with
    /// a `min`, `max` or a sign-only register to decide).
    pub fn specialises(&self) -> bool {
        self.specialiser().worth
    }

    /// Whether [`Tape::specialise_values`] can ever give a shorter tape (long enough,
    /// and with a `min` or `max`).
    pub fn specialises_values(&self) -> bool {
        self.specialiser().values_worth
    }

    /// The tape specialised to the union of the regions that the ranges `[x, y, z]` of
    /// `regions` enclose: shorter (or, with its sign-only R-functions turned into `min`
    /// and `max`, longer by at most one negation per `a \ b`), and at every point there
    /// of the same sign as this tape (see the module doc). Each register's bounds are
    /// the hull of its bounds over the regions, so slicing a long region gives tighter
    /// bounds (and a shorter tape) than one range over it. `None` when nothing shortens
    /// it and it has no such R-function.
    ///
    /// ```
    /// use arith_core::{Range, Real};
    /// use arith_ia::Interval;
    /// use model_ir::Tape;
    /// // Four balls in a row; only the one at the origin reaches the box around it.
    /// fn balls<R: Real>(x: R, y: R, z: R) -> R {
    ///     let ball = |cx: f64| ((x.clone() - cx).sqr() + y.sqr() + z.sqr()).rsub(0.25);
    ///     ball(0.0).max(&ball(2.0)).max(&ball(4.0).max(&ball(6.0)))
    /// }
    /// let t = Tape::record(balls);
    /// let i = |lo, hi| Interval::from_interval(lo, hi);
    /// let s = t.specialise(&[[i(-0.6, 0.6), i(-0.6, 0.6), i(-0.6, 0.6)]]).unwrap();
    /// // The first ball alone: its ten instructions.
    /// let ball = Tape::record(|x, y, z| ((x - 0.0).sqr() + y.sqr() + z.sqr()).rsub(0.25));
    /// assert_eq!(s.len(), ball.len());
    /// assert_eq!(s.eval(0.1_f64, 0.2, 0.3), ball.eval(0.1_f64, 0.2, 0.3));
    /// ```
    pub fn specialise<R: Range>(&self, regions: &[[R; 3]]) -> Option<Tape> {
        let (mut tapes, which) = self.specialise_groups(regions, &[(0, regions.len())]);
        which[0].map(|k| tapes.swap_remove(k))
    }

    /// A tape with the same value as this one, for shading, at every point of the
    /// region that `region` encloses where its own value lies strictly inside
    /// `(-within, within)` (everywhere for `within = inf`): the exact rule applied
    /// (decided `min`/`max`, dominated operands of n-ary ones dropped), and registers
    /// that reach the result only through `min`, `max` and negation folded to `inf`
    /// (`-inf`) where they lie above `within` (below `-within`). `None` when nothing
    /// shortens it.
    ///
    /// Why the folding keeps those values: the clamp `k(t) = min(max(t, -d), d)`
    /// commutes with `min`, `max` and negation, and maps a folded register and its
    /// constant alike, so `k(g) = k(f)` at every point of the region; where
    /// `|g| < d`, `g = k(g) = k(f)`, which only `f = g` gives. `min` and `max` select one
    /// operand, so this holds for the rounded values too, the bounds enclosing the
    /// rounded values of the folded registers. Applied again to the tape it gives (same
    /// `within`, a region inside this one), it keeps the same property.
    ///
    /// ```
    /// use arith_core::{Range, Real};
    /// use arith_ia::Interval;
    /// use model_ir::Tape;
    /// // A ball at the origin and three a little way off.
    /// fn balls<R: Real>(x: R, y: R, z: R) -> R {
    ///     let ball = |c: [f64; 3]| {
    ///         ((x.clone() - c[0]).sqr() + (y.clone() - c[1]).sqr() + (z.clone() - c[2]).sqr())
    ///             .rsub(0.25)
    ///     };
    ///     let (b0, bx) = (ball([0.0; 3]), ball([2.0, 0.0, 0.0]));
    ///     b0.max(&bx).max(&ball([0.0, 2.0, 0.0]).max(&ball([0.0, 0.0, 2.0])))
    /// }
    /// let t = Tape::record(balls);
    /// let i = |lo, hi| Interval::from_interval(lo, hi);
    /// let around = [i(-1.0, 1.0), i(-1.0, 1.0), i(-1.0, 1.0)];
    /// // Over the box the balls' ranges overlap: the exact rules keep them all...
    /// assert!(t.specialise_values(&around, f64::INFINITY).is_none());
    /// // ... while the others lie below -0.75 there, so within 0.5 of 0 the value is
    /// // the first ball's.
    /// let s = t.specialise_values(&around, 0.5).unwrap();
    /// assert!(s.len() * 3 < t.len());
    /// assert_eq!(s.eval(0.3_f64, 0.2, -0.1), t.eval(0.3_f64, 0.2, -0.1));
    /// ```
    pub fn specialise_values<R: Range>(&self, region: &[R; 3], within: f64) -> Option<Tape> {
        let spec = self.specialiser();
        if !spec.values_worth {
            return None;
        }
        let ins = self.instructions();
        let fold = if within < f64::INFINITY {
            Fold::Level(within)
        } else {
            Fold::Exact
        };
        let mut decisions = Vec::new();
        if TypeId::of::<R>() == TypeId::of::<Interval>() {
            // A box: its bounds from the lane kernel, compact.
            let mut bounds = Vec::new();
            spec.regions_bounds(self, std::slice::from_ref(region), &mut bounds);
            let bound = |k: usize| match spec.place[k] {
                u32::MAX => (f64::NAN, f64::NAN),
                p => bounds[p as usize],
            };
            spec.decide(ins, bound, fold, &mut decisions);
        } else {
            let bounds = spec.watched_bounds(ins, region);
            spec.decide(ins, |k| bounds[k], fold, &mut decisions);
        }
        if decisions.iter().all(|&d| d == KEEP) {
            return None;
        }
        let folded = (fold != Fold::Exact).then_some(&spec.level_only[..]);
        let t = rebuild(ins, folded, fold, &decisions);
        (t.len() < ins.len()).then(|| Tape::specialised(t, spec.affine_bounds()))
    }

    /// [`Tape::specialise`] for several unions of regions at once: `groups[g] = (i, j)`
    /// is the union of `regions[i..j]`. Each region is evaluated once, whatever the
    /// number of groups it is in. Gives the distinct tapes built and, per group, the
    /// index of its tape (`None`: nothing shortens it); groups with the same decisions
    /// share one tape.
    pub fn specialise_groups<R: Range>(
        &self,
        regions: &[[R; 3]],
        groups: &[(usize, usize)],
    ) -> (Vec<Tape>, Vec<Option<usize>>) {
        let spec = self.specialiser();
        if !spec.worth || regions.is_empty() {
            return (Vec::new(), vec![None; groups.len()]);
        }
        let ins = self.instructions();
        with_scratch(|sc| {
            spec.regions_bounds(self, regions, &mut sc.bounds);
            let w = spec.watched;
            let mut tapes: Vec<Tape> = Vec::new();
            let mut built: HashMap<Vec<u8>, Option<usize>> = HashMap::default();
            let which = groups
                .iter()
                .map(|&(i, j)| {
                    let rs = sc.bounds.get(i * w..j * w).filter(|_| i < j)?;
                    hull(rs, w, &mut sc.hull);
                    let place = &spec.place;
                    let hull = &sc.hull;
                    let bound = |k: usize| match place[k] {
                        u32::MAX => (f64::NAN, f64::NAN),
                        p => hull[p as usize],
                    };
                    spec.decide(ins, bound, Fold::Sign, &mut sc.decisions);
                    if !spec.r_functions && sc.decisions.iter().all(|&d| d == KEEP) {
                        return None;
                    }
                    spec.key(&sc.decisions, &mut sc.key);
                    if let Some(&k) = built.get(&sc.key) {
                        return k;
                    }
                    let k = self.rebuilt(spec, ins, &sc.decisions, &sc.key).map(|t| {
                        tapes.push(t);
                        tapes.len() - 1
                    });
                    built.insert(sc.key.clone(), k);
                    k
                })
                .collect();
            (tapes, which)
        })
    }

    /// The tape rebuilt with `decisions` (from the cache where it was built before),
    /// `None` when it is no shorter (or, with R-functions turned into `min` and `max`,
    /// longer than by the negations `a \ b` needs as `min(a, -b)`).
    fn rebuilt(
        &self,
        spec: &Specialiser,
        ins: &[Instr],
        decisions: &[u8],
        key: &[u8],
    ) -> Option<Tape> {
        let shared = self.shared();
        if let Ok(cache) = shared.cache.lock() {
            if let Some(t) = cache.get(key) {
                return t.clone();
            }
        }
        let t = spec.sign_tape(ins, decisions);
        if let Ok(mut cache) = shared.cache.lock() {
            if cache.len() < CACHE_LIMIT {
                cache.insert(key.to_vec(), t.clone());
            }
        }
        t
    }
}

impl Specialiser {
    /// The sign-specialised tape of `ins` with `decisions`, `None` when it is no
    /// shorter (or, with R-functions turned into `min` and `max`, longer than by the
    /// negations `a \ b` needs as `min(a, -b)`).
    fn sign_tape(&self, ins: &[Instr], decisions: &[u8]) -> Option<Tape> {
        let t = rebuild(ins, Some(&self.sign_only), Fold::Sign, decisions);
        let kept = t.len() < ins.len() || self.r_functions && t.len() <= ins.len() + self.subtracts;
        kept.then(|| Tape::specialised(t, self.affine_bounds()))
    }
}

/// Buffers of [`Tape::specialise_groups`], kept per thread.
#[derive(Default)]
struct Scratch {
    /// Compact bounds per region ([`Specialiser::regions_bounds`]).
    bounds: Vec<(f64, f64)>,
    /// Their hull over a group.
    hull: Vec<(f64, f64)>,
    decisions: Vec<u8>,
    key: Vec<u8>,
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::default();
}

/// Runs `f` with this thread's [`Scratch`] (a fresh one inside a nested call).
fn with_scratch<T>(f: impl FnOnce(&mut Scratch) -> T) -> T {
    let mut f = Some(f);
    let pooled = SCRATCH.try_with(|c| {
        let mut sc = c.try_borrow_mut().ok()?;
        Some((f.take()?)(&mut sc))
    });
    match (pooled, f) {
        (Ok(Some(out)), _) => out,
        (_, Some(f)) => f(&mut Scratch::default()),
        (_, None) => unreachable!("the scratch buffers ran `f` but lost its result"),
    }
}

/// The hull over the regions of `rs` (`w` compact bounds each) into `out`; NaN stays
/// (it decides nothing).
fn hull(rs: &[(f64, f64)], w: usize, out: &mut Vec<(f64, f64)>) {
    out.clear();
    out.extend_from_slice(&rs[..w]);
    for r in rs.chunks_exact(w).skip(1) {
        for (b, &(lo, hi)) in out.iter_mut().zip(r) {
            b.0 = if lo.is_nan() || b.0.is_nan() {
                f64::NAN
            } else {
                b.0.min(lo)
            };
            b.1 = if hi.is_nan() || b.1.is_nan() {
                f64::NAN
            } else {
                b.1.max(hi)
            };
        }
    }
}
