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
//! whole function are in `docs/specialisation.md`. A specialised tape is only valid in
//! the region it was derived for, and its values there are not those of the function
//! (only their signs are): it serves root finding and culling, never shading.
//!
//! Identical decisions give identical tapes, so each tape keeps the tapes it has built,
//! keyed by its decisions ([`CACHE_LIMIT`] of them), and neighbouring cells share one.

use super::tape::{finish, with_registers, Builder, Instr, Op, Tape, Val};
use crate::models::formula::branch::Step;
use arith_core::pack::{Pack, LANES};
use arith_core::{Known, Range, Real};
use arith_ia::{Interval, IntervalX4};
use rustc_hash::FxHashMap as HashMap;
use std::any::TypeId;
use std::sync::Mutex;

/// Tapes shorter than this are evaluated whole: building a tape costs more than a
/// short tape's evaluations save.
pub const MIN_SPECIALISE_LEN: usize = 24;

/// Specialised tapes a tape keeps for reuse.
pub const CACHE_LIMIT: usize = 512;

/// What a tape's specialisation needs, computed once per tape.
#[derive(Debug)]
pub(crate) struct Specialiser {
    /// Per register: only its sign matters.
    sign_only: Vec<bool>,
    /// Per register: it reaches the result only through `min`, `max` and negation
    /// (a subset of the sign-only ones), so it may be folded by level.
    level_only: Vec<bool>,
    /// Per register: its bounds can decide something.
    watch: Vec<bool>,
    /// The tape's chains of `min` (`max`) whose inner nodes have no other use: n-ary
    /// minima (maxima) of their leaves.
    chains: Vec<Chain>,
    /// Whether specialising can ever shorten the tape.
    worth: bool,
    /// Whether specialising by value can ever shorten it: long enough, with a `min` or
    /// `max` to decide or fold by level. Without one the value rules can only fold the
    /// result itself to an infinity, which no shading sample near a root reads (an
    /// R-function union of balls: every fold would run the whole tape for nothing).
    values_worth: bool,
    /// Whether some sign-only register is an R-function (`&`, `|`, `\`), which a
    /// sign-specialised tape turns into `min` or `max`: rebuilt even where nothing is
    /// decided.
    r_functions: bool,
    /// How many of them are `a \ b`, which becomes `min(a, -b)`: a tape may get that
    /// many instructions longer.
    subtracts: usize,
    /// Tapes built so far, by decisions (`None`: no shorter than this one).
    cache: Mutex<HashMap<Vec<u8>, Option<Tape>>>,
}

/// An n-ary `min` or `max` spread over a tree of binary ones (see [`Specialiser`]).
#[derive(Debug)]
struct Chain {
    max: bool,
    /// Its nodes, operands before their consumers (by register), the root last.
    nodes: Vec<ChainNode>,
}

#[derive(Debug)]
struct ChainNode {
    reg: u32,
    kids: [Kid; 2],
}

/// An operand of a chain's node.
#[derive(Clone, Copy, Debug)]
enum Kid {
    /// Another node of the chain (its index in [`Chain::nodes`]).
    Node(u32),
    /// A leaf (its register).
    Leaf(u32),
}

/// What the rewrite may fold besides the exact rule.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Fold {
    /// Nothing: the value is kept everywhere.
    Exact,
    /// Sign-only registers of one sign, to `1` or `-1`: the sign is kept.
    Sign,
    /// Level-only registers beyond `(-d, d)`, to `inf` or `-inf`: the value is kept
    /// wherever it lies in `(-d, d)` (see [`Tape::specialise_values`]).
    Level(f64),
}

/// A register kept as it is.
const KEEP: u8 = 0;
/// Strictly positive over the region (sign only): the constant 1.
const POS: u8 = 1;
/// Strictly negative over the region (sign only): the constant -1.
const NEG: u8 = 2;
/// A `min` or `max` that is its first operand over the region.
const TAKE_A: u8 = 3;
/// A `min` or `max` that is its second operand over the region.
const TAKE_B: u8 = 4;

/// Whether `sign(i)` depends on operand `k` only through `sign(operand)`, monotonically or
/// antitonically, given that only `sign(i)` matters.
fn passes_sign(i: &Instr, k: usize) -> bool {
    match i.op {
        Op::Min | Op::Max | Op::Intersect | Op::Union | Op::Subtract | Op::Neg => true,
        Op::MulC | Op::DivC => i.c.is_finite() && i.c != 0.0,
        // The condition's value matters, the branches' only through their signs.
        Op::Select => k > 0,
        _ => false,
    }
}

impl Specialiser {
    fn new(ins: &[Instr]) -> Self {
        let n = ins.len();
        let mut sign_only = vec![false; n];
        let mut level_only = vec![false; n];
        let mut all_uses_pass = vec![true; n];
        let mut all_uses_level = vec![true; n];
        let mut used = vec![false; n];
        // Consumers come after their operands: walking backwards, a register's every
        // use has been seen when it is reached.
        for j in (0..n).rev() {
            sign_only[j] = j == n - 1 || (used[j] && all_uses_pass[j]);
            level_only[j] = j == n - 1 || (used[j] && all_uses_level[j]);
            let i = &ins[j];
            for &k in i.operands() {
                let r = i.reg(k) as usize;
                used[r] = true;
                // A comparison with 0 reads only the sign, whatever its own use.
                let passes =
                    matches!(i.op, Op::Gt0 | Op::Ge0) || (sign_only[j] && passes_sign(i, k));
                all_uses_pass[r] &= passes;
                all_uses_level[r] &= level_only[j] && matches!(i.op, Op::Min | Op::Max | Op::Neg);
            }
        }
        // Every operand of a `min` or `max` (constants too), and the sign-only registers.
        let mut watch = sign_only.clone();
        let mut choices = 0usize;
        for i in ins {
            if matches!(i.op, Op::Min | Op::Max) {
                watch[i.a as usize] = true;
                watch[i.b as usize] = true;
                choices += 1;
            }
        }
        let chains = chains(ins);
        let signs = sign_only[..n.saturating_sub(1)]
            .iter()
            .zip(ins)
            .filter(|(&s, i)| s && !matches!(i.op, Op::Const))
            .count();
        let (mut r_functions, mut subtracts) = (false, 0);
        for (i, _) in ins.iter().zip(&sign_only).filter(|(_, &s)| s) {
            r_functions |= matches!(i.op, Op::Intersect | Op::Union | Op::Subtract);
            subtracts += usize::from(i.op == Op::Subtract);
        }
        Specialiser {
            sign_only,
            level_only,
            watch,
            chains,
            worth: n >= MIN_SPECIALISE_LEN && choices + signs > 0,
            values_worth: n >= MIN_SPECIALISE_LEN && choices > 0,
            r_functions,
            subtracts,
            cache: Mutex::new(HashMap::default()),
        }
    }

    /// The decision for each register, from the bounds of the watched ones, with the
    /// exact rule and the folding `fold`.
    fn decide(&self, ins: &[Instr], bounds: &[(f64, f64)], fold: Fold) -> Vec<u8> {
        let mut decisions: Vec<u8> = ins
            .iter()
            .enumerate()
            .map(|(k, i)| {
                let (lo, hi) = bounds[k];
                // A constant keeps its own value (and the result deciding alone means
                // no root at all: nothing to shorten, but harmless).
                let folds = match fold {
                    Fold::Exact => None,
                    Fold::Sign => self.sign_only[k].then_some(0.0),
                    Fold::Level(d) => self.level_only[k].then_some(d),
                };
                if let Some(d) = folds.filter(|_| i.op != Op::Const) {
                    if lo > d {
                        return POS;
                    }
                    if hi < -d {
                        return NEG;
                    }
                }
                let (a, b) = (bounds[i.a as usize], bounds[i.b as usize]);
                match i.op {
                    Op::Min if a.1 <= b.0 => TAKE_A,
                    Op::Min if b.1 <= a.0 => TAKE_B,
                    Op::Max if a.0 >= b.1 => TAKE_A,
                    Op::Max if b.0 >= a.1 => TAKE_B,
                    _ => KEEP,
                }
            })
            .collect();
        let mut gone = Vec::new();
        for c in &self.chains {
            c.drop_dominated(bounds, &mut decisions, &mut gone);
        }
        decisions
    }
}

/// The chains of `ins` (see [`Specialiser::chains`]): a `min` or `max` node is inner
/// when its one use is an operand of the same operation.
fn chains(ins: &[Instr]) -> Vec<Chain> {
    let n = ins.len();
    let mut uses = vec![0u32; n];
    let mut user = vec![u32::MAX; n];
    for (j, i) in ins.iter().enumerate() {
        for &k in i.operands() {
            let r = i.reg(k) as usize;
            uses[r] += 1;
            user[r] = j as u32;
        }
    }
    let inner = |r: usize| {
        matches!(ins[r].op, Op::Min | Op::Max)
            && r != n - 1
            && uses[r] == 1
            && ins[user[r] as usize].op == ins[r].op
    };
    let mut out = Vec::new();
    for (root, i) in ins.iter().enumerate() {
        if !matches!(i.op, Op::Min | Op::Max) || inner(root) {
            continue;
        }
        // The nodes below the root, found from it, then put in register order.
        let mut regs = vec![root];
        let mut k = 0;
        while k < regs.len() {
            let j = &ins[regs[k]];
            for r in [j.a as usize, j.b as usize] {
                if inner(r) {
                    regs.push(r);
                }
            }
            k += 1;
        }
        if regs.len() < 2 {
            continue;
        }
        regs.sort_unstable();
        let nodes = regs
            .iter()
            .map(|&r| ChainNode {
                reg: r as u32,
                kids: [ins[r].a, ins[r].b].map(|o| match regs.binary_search(&(o as usize)) {
                    Ok(p) if inner(o as usize) => Kid::Node(p as u32),
                    _ => Kid::Leaf(o),
                }),
            })
            .collect();
        out.push(Chain {
            max: i.op == Op::Max,
            nodes,
        });
    }
    out
}

impl Chain {
    /// Drops the leaves that another leaf dominates over the region (for a `max`, a
    /// leaf whose upper bound is at most the greatest lower bound of a leaf: it is
    /// never above that leaf, so never the maximum alone), by turning the nodes above
    /// them into decided ones. Exact, like the binary rule it extends: the chain's value
    /// is unchanged at every point of the region. `gone` is scratch space.
    fn drop_dominated(&self, bounds: &[(f64, f64)], decisions: &mut [u8], gone: &mut Vec<bool>) {
        // A leaf's key: how far up (for a max) it is sure to reach, and where it may end.
        let key = |r: u32| {
            let (lo, hi) = bounds[r as usize];
            if self.max {
                (lo, hi)
            } else {
                (-hi, -lo)
            }
        };
        let mut best: Option<(usize, usize, f64)> = None;
        for (p, node) in self.nodes.iter().enumerate() {
            for (s, kid) in node.kids.iter().enumerate() {
                if let Kid::Leaf(r) = *kid {
                    let sure = key(r).0;
                    if best.is_none_or(|b| sure > b.2) {
                        best = Some((p, s, sure));
                    }
                }
            }
        }
        let Some((bp, bs, floor)) = best else {
            return;
        };
        gone.clear();
        gone.resize(self.nodes.len(), false);
        for (p, node) in self.nodes.iter().enumerate() {
            let d: [bool; 2] = core::array::from_fn(|s| match node.kids[s] {
                Kid::Node(c) => gone[c as usize],
                // NaN bounds compare false: an unknown leaf stays.
                Kid::Leaf(r) => (p, s) != (bp, bs) && key(r).1 <= floor,
            });
            gone[p] = d[0] && d[1];
            let k = node.reg as usize;
            if matches!(decisions[k], POS | NEG) {
                continue;
            }
            if d[0] && !d[1] {
                decisions[k] = TAKE_B;
            } else if d[1] && !d[0] {
                decisions[k] = TAKE_A;
            }
        }
    }
}

/// Bounds of a value as [`Real::known`] tells them (NaN where unknown: decides nothing).
fn bounds_of<R: Real>(v: &R) -> (f64, f64) {
    match v.known() {
        Known::Range(lo, hi) => (lo, hi),
        Known::Point(p) => (p, p),
        Known::Unknown => (f64::NAN, f64::NAN),
    }
}

impl Tape {
    fn specialiser(&self) -> &Specialiser {
        self.spec
            .get_or_init(|| Specialiser::new(self.instructions()))
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
    /// use arith_core::Range;
    /// use arith_ia::Interval;
    /// use tracer::models::formula::parse;
    /// // Four balls in a row; only the one at the origin reaches the box around it.
    /// let t = parse("ball = 0.25 - x^2 - y^2 - z^2;
    ///                max(max(ball, 0.25 - (x-2)^2 - y^2 - z^2),
    ///                    max(0.25 - (x-4)^2 - y^2 - z^2, 0.25 - (x-6)^2 - y^2 - z^2))").unwrap();
    /// let i = |lo, hi| Interval::from_interval(lo, hi);
    /// let s = t.specialise(&[[i(-0.6, 0.6), i(-0.6, 0.6), i(-0.6, 0.6)]]).unwrap();
    /// assert_eq!(s.to_formula(), "0.25 - x^2 - y^2 - z^2");
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
    /// use arith_core::Range;
    /// use arith_ia::Interval;
    /// use tracer::models::formula::parse;
    /// // A ball at the origin and three a little way off.
    /// let t = parse("ball = 0.25 - x^2 - y^2 - z^2;
    ///                max(max(ball, 0.25 - (x-2)^2 - y^2 - z^2),
    ///                    max(0.25 - x^2 - (y-2)^2 - z^2, 0.25 - x^2 - y^2 - (z-2)^2))").unwrap();
    /// let i = |lo, hi| Interval::from_interval(lo, hi);
    /// let around = [i(-1.0, 1.0), i(-1.0, 1.0), i(-1.0, 1.0)];
    /// // Over the box the balls' ranges overlap: the exact rules keep them all...
    /// assert!(t.specialise_values(&around, f64::INFINITY).is_none());
    /// // ... while the others lie below -0.75 there, so within 0.5 of 0 the value is
    /// // the first ball's.
    /// let s = t.specialise_values(&around, 0.5).unwrap();
    /// assert_eq!(s.to_formula(), "0.25 - x^2 - y^2 - z^2");
    /// ```
    pub fn specialise_values<R: Range>(&self, region: &[R; 3], within: f64) -> Option<Tape> {
        let spec = self.specialiser();
        if !spec.values_worth {
            return None;
        }
        let ins = self.instructions();
        let bounds = self.watched_bounds(spec, region);
        let fold = if within < f64::INFINITY {
            Fold::Level(within)
        } else {
            Fold::Exact
        };
        let decisions = spec.decide(ins, &bounds, fold);
        if decisions.iter().all(|&d| d == KEEP) {
            return None;
        }
        let folded = (fold != Fold::Exact).then_some(&spec.level_only[..]);
        let t = rebuild(ins, folded, fold, &decisions);
        (t.len() < ins.len()).then_some(t)
    }

    /// Each watched register's bounds over each of `regions`, in `R` and, for an
    /// arithmetic with symbols, also in intervals over the box of the region's inputs:
    /// both enclose the register's values there, so their intersection does. Over a
    /// long oblique region (a culling cell's depth slice) intervals over its box keep
    /// the far parts of a scene apart that an affine form loses to its quadratic error
    /// terms, while over the thin regions of the rays' segments the affine forms are
    /// the tighter; measured on scenes of balls and the Shikki scene, the two together
    /// shorten the tapes more than either. The boxes go four at a time through
    /// [`IntervalX4`], each lane bit for bit the scalar interval.
    fn regions_bounds<R: Range>(
        &self,
        spec: &Specialiser,
        regions: &[[R; 3]],
    ) -> Vec<Vec<(f64, f64)>> {
        // Intervals are their own boxes: the packs alone give their bounds.
        let boxes_only = TypeId::of::<R>() == TypeId::of::<Interval>();
        let mut out: Vec<Vec<(f64, f64)>> = if boxes_only {
            vec![vec![(f64::NAN, f64::NAN); self.len()]; regions.len()]
        } else {
            regions
                .iter()
                .map(|r| self.watched_bounds(spec, r))
                .collect()
        };
        if R::INPUTS == usize::MAX && !boxes_only {
            return out;
        }
        for (c, chunk) in regions.chunks(LANES).enumerate() {
            let lane = |l: usize, k: usize| {
                let (lo, hi) = chunk[l.min(chunk.len() - 1)][k].bounds();
                Interval::from_interval(lo, hi)
            };
            let input = |k: usize| IntervalX4::pack(core::array::from_fn(|l| lane(l, k)));
            let mut seen = |k: usize, v: &IntervalX4| {
                for (l, i) in v.unpack().iter().enumerate().take(chunk.len()) {
                    let a = &mut out[c * LANES + l][k];
                    let b = bounds_of(i);
                    *a = if a.0.is_nan() {
                        b
                    } else if b.0.is_nan() {
                        *a
                    } else {
                        let (lo, hi) = (a.0.max(b.0), a.1.min(b.1));
                        // Empty only through a NaN among the values: decide nothing.
                        if lo <= hi {
                            (lo, hi)
                        } else {
                            (f64::NAN, f64::NAN)
                        }
                    };
                }
            };
            with_registers(|regs: &mut Vec<Option<IntervalX4>>| {
                self.run(regs, input(0), input(1), input(2), |k, v| {
                    if spec.watch[k] {
                        seen(k, v);
                    }
                })
            });
        }
        out
    }

    /// Each watched register's bounds over `region`; NaN (decides nothing) for the
    /// others.
    fn watched_bounds<R: Range>(&self, spec: &Specialiser, [x, y, z]: &[R; 3]) -> Vec<(f64, f64)> {
        let mut bounds = vec![(f64::NAN, f64::NAN); self.len()];
        with_registers(|regs: &mut Vec<Option<R>>| {
            self.run(regs, x.clone(), y.clone(), z.clone(), |k, v| {
                if spec.watch[k] {
                    bounds[k] = bounds_of(v);
                }
            })
        });
        bounds
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
        let per_region = self.regions_bounds(spec, regions);
        let mut tapes: Vec<Tape> = Vec::new();
        let mut built: HashMap<Vec<u8>, Option<usize>> = HashMap::default();
        let which = groups
            .iter()
            .map(|&(i, j)| {
                let rs = per_region.get(i..j).filter(|r| !r.is_empty())?;
                // The hull over the group's regions; NaN stays (it decides nothing).
                let bounds: Vec<(f64, f64)> = (0..ins.len())
                    .map(|k| {
                        rs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |b, r| {
                            let (lo, hi) = r[k];
                            (
                                if lo.is_nan() || b.0.is_nan() {
                                    f64::NAN
                                } else {
                                    b.0.min(lo)
                                },
                                if hi.is_nan() || b.1.is_nan() {
                                    f64::NAN
                                } else {
                                    b.1.max(hi)
                                },
                            )
                        })
                    })
                    .collect();
                let decisions = spec.decide(ins, &bounds, Fold::Sign);
                if !spec.r_functions && decisions.iter().all(|&d| d == KEEP) {
                    return None;
                }
                if let Some(&k) = built.get(&decisions) {
                    return k;
                }
                let k = self.rebuilt(spec, ins, &decisions).map(|t| {
                    tapes.push(t);
                    tapes.len() - 1
                });
                built.insert(decisions, k);
                k
            })
            .collect();
        (tapes, which)
    }

    /// The tape rebuilt with `decisions` (from the cache where it was built before),
    /// `None` when it is no shorter (or, with R-functions turned into `min` and `max`,
    /// longer than by the negations `a \ b` needs as `min(a, -b)`).
    fn rebuilt(&self, spec: &Specialiser, ins: &[Instr], decisions: &[u8]) -> Option<Tape> {
        if let Ok(cache) = spec.cache.lock() {
            if let Some(t) = cache.get(decisions) {
                return t.clone();
            }
        }
        let t = rebuild(ins, Some(&spec.sign_only), Fold::Sign, decisions);
        // (`a \ b` as `min(a, -b)` can take one more instruction.)
        let kept = t.len() < ins.len() || spec.r_functions && t.len() <= ins.len() + spec.subtracts;
        let t = kept.then_some(t);
        if let Ok(mut cache) = spec.cache.lock() {
            if cache.len() < CACHE_LIMIT {
                cache.insert(decisions.to_vec(), t.clone());
            }
        }
        t
    }
}

/// The tape `ins` with `decisions` applied, simplified and stripped of dead code;
/// registers marked in `folded` (none where `None`) are folded as `fold` says.
fn rebuild(ins: &[Instr], folded: Option<&[bool]>, fold: Fold, decisions: &[u8]) -> Tape {
    let level = matches!(fold, Fold::Level(_));
    let (plus, minus) = if level {
        (f64::INFINITY, f64::NEG_INFINITY)
    } else {
        (1.0, -1.0)
    };
    let n = ins.len();
    // What the result still reads once the decisions are made (emitting the rest would
    // only be undone by `finish`).
    let mut live = vec![false; n];
    live[n - 1] = true;
    for k in (0..n).rev() {
        if !live[k] {
            continue;
        }
        let i = &ins[k];
        match decisions[k] {
            POS | NEG => {}
            TAKE_A => live[i.a as usize] = true,
            TAKE_B => live[i.b as usize] = true,
            _ => {
                for &p in i.operands() {
                    live[i.reg(p) as usize] = true;
                }
            }
        }
    }
    let mut b = Builder::with_capacity(live.iter().filter(|&&l| l).count());
    let mut map: Vec<Val> = vec![Val::C(f64::NAN); n];
    for (k, i) in ins.iter().enumerate() {
        if !live[k] {
            continue;
        }
        let arg = |p: usize| map[i.reg(p) as usize];
        map[k] = match decisions[k] {
            POS => Val::C(plus),
            NEG => Val::C(minus),
            TAKE_A => arg(0),
            TAKE_B => arg(1),
            _ => reemit(
                &mut b,
                i,
                [arg(0), arg(1), arg(2)],
                folded.is_some_and(|s| s[k]).then_some(level),
            ),
        };
    }
    let out = b.reg(map[n - 1]);
    Tape::from_instructions(finish(b.ins, out))
}

/// `i` over the new operands `v`, folded where they are constants: exactly where the
/// value matters, by sign where only the sign does (`sign`).
fn reemit(b: &mut Builder, i: &Instr, v: [Val; 3], fold: Option<bool>) -> Val {
    use super::ast::BinOp;
    let [a, c2, e] = v;
    let c = Val::C(i.c);
    let regs = |b: &mut Builder, op: Op, x: Val, y: Val| {
        let (x, y) = (b.reg(x), b.reg(y));
        Val::R(b.emit(Instr::new(op, x, y, 0, 0.0)))
    };
    // By sign (`Some(false)`) every positive constant stands for "positive"; by level
    // (`Some(true)`) only the folded `inf` stands for "above the level" (a constant of
    // the model keeps its value), and only `min`, `max` and negation are folded.
    let sign = fold.is_some();
    let level = fold == Some(true);
    let (top, bottom) = if level {
        (f64::INFINITY, f64::NEG_INFINITY)
    } else {
        (1.0, -1.0)
    };
    let pos = |v: Val| matches!(v, Val::C(p) if p > 0.0 && (!level || p == f64::INFINITY));
    let neg = |v: Val| matches!(v, Val::C(p) if p < 0.0 && (!level || p == f64::NEG_INFINITY));
    let meet = matches!(i.op, Op::Min) || (!level && i.op == Op::Intersect);
    let join = matches!(i.op, Op::Max) || (!level && i.op == Op::Union);
    let subtract = !level && i.op == Op::Subtract;
    match i.op {
        Op::X | Op::Y | Op::Z => Val::R(b.emit(Instr::new(i.op, 0, 0, 0, 0.0))),
        Op::Const => c,
        Op::Neg => match a {
            Val::C(p) => Val::C(-p),
            _ => b.unary(Op::Neg, a),
        },
        Op::Sqr => b.powi(a, 2),
        Op::Powi => b.powi(a, i.n),
        Op::Sqrt | Op::Exp | Op::Ln | Op::Sin | Op::Cos | Op::Abs => b.unary_folded(i.op, a),
        Op::AddC => b.binary(BinOp::Add, a, c),
        Op::SubC => b.binary(BinOp::Sub, a, c),
        Op::RSubC => b.binary(BinOp::Sub, c, a),
        Op::MulC => b.binary(BinOp::Mul, a, c),
        Op::DivC => b.binary(BinOp::Div, a, c),
        Op::RDivC => b.binary(BinOp::Div, c, a),
        Op::Add => b.binary(BinOp::Add, a, c2),
        Op::Sub => b.binary(BinOp::Sub, a, c2),
        Op::Mul => b.binary(BinOp::Mul, a, c2),
        Op::Div => b.binary(BinOp::Div, a, c2),
        // By sign: a meet is its other operand where one is positive, negative where
        // one is negative; a join the other way round.
        _ if meet && sign && (pos(a) || pos(c2)) => {
            if pos(a) {
                c2
            } else {
                a
            }
        }
        _ if meet && sign && (neg(a) || neg(c2)) => Val::C(bottom),
        _ if join && sign && (neg(a) || neg(c2)) => {
            if neg(a) {
                c2
            } else {
                a
            }
        }
        _ if join && sign && (pos(a) || pos(c2)) => Val::C(top),
        // `a \ b` is `a & -b`.
        _ if subtract && sign && neg(c2) => a,
        _ if subtract && sign && pos(a) => match c2 {
            Val::C(q) => Val::C(-q),
            _ => b.unary(Op::Neg, c2),
        },
        _ if subtract && sign && (neg(a) || pos(c2)) => Val::C(-1.0),
        Op::Min | Op::Max => min_max(b, i.op, a, c2),
        // By sign, an R-function has the sign of `min` or `max` of its operands (see
        // `docs/specialisation.md`), whose ranges are far tighter.
        Op::Intersect | Op::Union | Op::Subtract if sign && !level => match i.op {
            Op::Intersect => min_max(b, Op::Min, a, c2),
            Op::Union => min_max(b, Op::Max, a, c2),
            _ => {
                let nb = match c2 {
                    Val::C(q) => Val::C(-q),
                    _ => b.unary(Op::Neg, c2),
                };
                min_max(b, Op::Min, a, nb)
            }
        },
        Op::Intersect => b.binary(BinOp::Intersect, a, c2),
        Op::Union => b.binary(BinOp::Union, a, c2),
        Op::Subtract => b.binary(BinOp::Subtract, a, c2),
        Op::BlendUnion | Op::BlendIntersect => regs(b, i.op, a, c2),
        Op::Gt0 => b.step(Step::Pos, a),
        Op::Ge0 => b.step(Step::NonNeg, a),
        Op::Select => b.select(a, c2, e),
    }
}

/// `min(x, y)` or `max(x, y)` (`op`), folded where both are constants.
fn min_max(b: &mut Builder, op: Op, x: Val, y: Val) -> Val {
    match (x, y) {
        (Val::C(p), Val::C(q)) => Val::C(if op == Op::Min {
            Real::min(&p, &q)
        } else {
            Real::max(&p, &q)
        }),
        _ => {
            let (x, y) = (b.reg(x), b.reg(y));
            Val::R(b.emit(Instr::new(op, x, y, 0, 0.0)))
        }
    }
}
