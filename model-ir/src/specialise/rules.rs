//! The rewrite rules of region specialisation (see [`crate::specialise`]): which
//! registers matter only by sign or by level, and the decisions the bounds of a region
//! allow (the tape is rewritten with them by [`super::one_pass`]). Works on instruction
//! slices; the cache and the public API are in [`crate::specialise`].

use crate::eval::{run, with_registers};
use crate::instr::{Instr, Op};
use crate::tape::Tape;
use arith_core::{Known, Range, Real};
use arith_ia::Interval;
use std::any::TypeId;

/// Tapes shorter than this are evaluated whole: building a tape costs more than a
/// short tape's evaluations save.
pub const MIN_SPECIALISE_LEN: usize = 24;

/// What a tape's specialisation needs, computed once per tape.
#[derive(Debug)]
pub(crate) struct Specialiser {
    /// Per register: only its sign matters.
    pub(crate) sign_only: Vec<bool>,
    /// Per register: it reaches the result only through `min`, `max` and negation
    /// (a subset of the sign-only ones), so it may be folded by level.
    pub(crate) level_only: Vec<bool>,
    /// Per register: its bounds can decide something.
    pub(crate) watch: Vec<bool>,
    /// Per register: its place among the watched ones (`u32::MAX`: not watched), where
    /// compact bounds ([`Specialiser::regions_bounds`]) keep it.
    pub(crate) place: Vec<u32>,
    /// How many registers are watched.
    pub(crate) watched: usize,
    /// The registers a decision can change (sign-only ones that are not constants,
    /// `min` and `max`), in order.
    decidable: Vec<u32>,
    /// The tape's chains of `min` (`max`) whose inner nodes have no other use: n-ary
    /// minima (maxima) of their leaves.
    chains: Vec<Chain>,
    /// Whether specialising can ever shorten the tape.
    pub(crate) worth: bool,
    /// Whether specialising by value can ever shorten it: long enough, with a `min` or
    /// `max` to decide or fold by level. Without one the value rules can only fold the
    /// result itself to an infinity, which no shading sample near a root reads (an
    /// R-function union of balls: every fold would run the whole tape for nothing).
    pub(crate) values_worth: bool,
    /// Whether some sign-only register is an R-function (`&`, `|`, `\`), which a
    /// sign-specialised tape turns into `min` or `max`: rebuilt even where nothing is
    /// decided.
    pub(crate) r_functions: bool,
    /// How many of them are `a \ b`, which becomes `min(a, -b)`: a tape may get that
    /// many instructions longer.
    pub(crate) subtracts: usize,
    /// Whether a region's bounds are also taken in the region's own arithmetic, not
    /// only in intervals over its box (see [`Specialiser::regions_bounds`]).
    affine_bounds: bool,
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
pub(crate) enum Fold {
    /// Nothing: the value is kept everywhere.
    Exact,
    /// Sign-only registers of one sign, to `1` or `-1`: the sign is kept.
    Sign,
    /// Level-only registers beyond `(-d, d)`, to `inf` or `-inf`: the value is kept
    /// wherever it lies in `(-d, d)` (see [`crate::Tape::specialise_values`]).
    Level(f64),
}

/// A register kept as it is.
pub(crate) const KEEP: u8 = 0;
/// Strictly positive over the region (sign only): the constant 1.
pub(crate) const POS: u8 = 1;
/// Strictly negative over the region (sign only): the constant -1.
pub(crate) const NEG: u8 = 2;
/// A `min` or `max` that is its first operand over the region.
pub(crate) const TAKE_A: u8 = 3;
/// A `min` or `max` that is its second operand over the region.
pub(crate) const TAKE_B: u8 = 4;

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
    /// The analysis of `ins`; `affine` says the bounds are taken in the region's own
    /// arithmetic too, whatever the instructions (a tape specialised from one whose
    /// were).
    pub(crate) fn new(ins: &[Instr], affine: bool) -> Self {
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
        let mut watched = 0u32;
        let place = watch
            .iter()
            .map(|&w| {
                watched += u32::from(w);
                if w {
                    watched - 1
                } else {
                    u32::MAX
                }
            })
            .collect();
        let decidable = (0..n as u32)
            .filter(|&k| {
                let op = ins[k as usize].op;
                (sign_only[k as usize] && op != Op::Const) || matches!(op, Op::Min | Op::Max)
            })
            .collect();
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
            place,
            watched: watched as usize,
            decidable,
            chains,
            worth: n >= MIN_SPECIALISE_LEN && choices + signs > 0,
            values_worth: n >= MIN_SPECIALISE_LEN && choices > 0,
            r_functions,
            subtracts,
            affine_bounds: affine
                || ins.iter().any(|i| {
                    matches!(
                        i.op,
                        Op::Intersect
                            | Op::Union
                            | Op::Subtract
                            | Op::BlendUnion
                            | Op::BlendIntersect
                            | Op::Hypot
                    )
                }),
        }
    }

    /// The decision for each register into `decisions` (resized to the tape), from the
    /// bounds of the watched ones (`bound(k)` for register `k`; NaN decides nothing),
    /// with the exact rule and the folding `fold`.
    pub(crate) fn decide(
        &self,
        ins: &[Instr],
        bound: impl Fn(usize) -> (f64, f64),
        fold: Fold,
        decisions: &mut Vec<u8>,
    ) {
        decisions.clear();
        decisions.resize(ins.len(), KEEP);
        for &k in &self.decidable {
            let k = k as usize;
            let i = &ins[k];
            // A constant keeps its own value (and the result deciding alone means no
            // root at all: nothing to shorten, but harmless).
            let folds = match fold {
                Fold::Exact => None,
                Fold::Sign => self.sign_only[k].then_some(0.0),
                Fold::Level(d) => self.level_only[k].then_some(d),
            };
            if let Some(d) = folds.filter(|_| i.op != Op::Const) {
                let (lo, hi) = bound(k);
                if lo > d {
                    decisions[k] = POS;
                    continue;
                }
                if hi < -d {
                    decisions[k] = NEG;
                    continue;
                }
            }
            if matches!(i.op, Op::Min | Op::Max) {
                let (a, b) = (bound(i.a as usize), bound(i.b as usize));
                decisions[k] = match i.op {
                    Op::Min if a.1 <= b.0 => TAKE_A,
                    Op::Min if b.1 <= a.0 => TAKE_B,
                    Op::Max if a.0 >= b.1 => TAKE_A,
                    Op::Max if b.0 >= a.1 => TAKE_B,
                    _ => KEEP,
                };
            }
        }
        if self.chains.is_empty() {
            return;
        }
        // The chains' scratch space, kept per thread (a decision is made per region).
        thread_local! {
            static GONE: std::cell::RefCell<Vec<bool>> = const { std::cell::RefCell::new(Vec::new()) };
        }
        GONE.with(|g| {
            let mut gone = g.borrow_mut();
            for c in &self.chains {
                c.drop_dominated(&bound, decisions, &mut gone);
            }
        });
    }

    /// The key of `decisions` for sharing tapes: the decisions of the registers a
    /// decision can change, in order.
    pub(crate) fn key(&self, decisions: &[u8], key: &mut Vec<u8>) {
        key.clear();
        key.extend(self.decidable.iter().map(|&k| decisions[k as usize]));
    }

    /// Each watched register's bounds over each of `regions`, in intervals over the
    /// box of the region's inputs and, for an arithmetic with symbols over a tape with
    /// R-functions, blends or `hypot`, also in `R`: both enclose the register's values
    /// there, so their intersection does. Over a long oblique region (a culling cell's
    /// depth slice) intervals over its box keep the far parts of a scene apart that an
    /// affine form loses to its quadratic error terms, while the square roots of the
    /// R-functions are where intervals lose the correlations an affine form keeps. On
    /// the Shikki scene (R-functions) the two together give 20% fewer instructions
    /// per range than intervals alone; on `min`/`max` scenes of primitives (a union
    /// of 2000 balls, fidget's colonnade, a CSG tree of 300 balls and boxes) intervals
    /// alone give the same tapes within 0.2%, and the affine evaluation over each
    /// region took up to a fifth of the render's time. A tape specialised from one with
    /// such instructions keeps its parent's choice (its R-functions became `min` and
    /// `max`). The boxes go four at a time through
    /// [`IntervalX4`], each lane bit for bit the scalar interval.
    /// Whether bounds are taken in the region's own arithmetic too.
    pub(crate) fn affine_bounds(&self) -> bool {
        self.affine_bounds
    }

    ///
    /// The bounds are compact: register `k`'s over region `r` at
    /// `out[r * self.watched + self.place[k]]`, written into `out` (resized).
    pub(crate) fn regions_bounds<R: Range>(
        &self,
        tape: &Tape,
        regions: &[[R; 3]],
        out: &mut Vec<(f64, f64)>,
    ) {
        let (ins, w) = (tape.instructions(), self.watched);
        // Intervals are their own boxes: the lanes alone give their bounds.
        let boxes_only = TypeId::of::<R>() == TypeId::of::<Interval>()
            || (!self.affine_bounds && R::INPUTS != usize::MAX);
        out.clear();
        out.resize(regions.len() * w, (f64::NAN, f64::NAN));
        if !boxes_only {
            for (r, [x, y, z]) in regions.iter().enumerate() {
                let own = &mut out[r * w..(r + 1) * w];
                with_registers(|regs: &mut Vec<Option<R>>| {
                    run(ins, regs, x.clone(), y.clone(), z.clone(), |k, v| {
                        if let Some(&p) = self.place.get(k).filter(|&&p| p != u32::MAX) {
                            own[p as usize] = bounds_of(v);
                        }
                    })
                });
            }
            if R::INPUTS == usize::MAX {
                return;
            }
        }
        let lane = |q: usize, l: usize| regions[l][q].bounds();
        tape.watched_intervals(&self.place, w, regions.len(), lane, |r, p, b| {
            let a = &mut out[r * w + p];
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
        });
    }

    /// Each watched register's bounds over `region`; NaN (decides nothing) for the
    /// others.
    pub(crate) fn watched_bounds<R: Range>(
        &self,
        ins: &[Instr],
        [x, y, z]: &[R; 3],
    ) -> Vec<(f64, f64)> {
        let spec = self;
        let mut bounds = vec![(f64::NAN, f64::NAN); ins.len()];
        with_registers(|regs: &mut Vec<Option<R>>| {
            run(ins, regs, x.clone(), y.clone(), z.clone(), |k, v| {
                if spec.watch[k] {
                    bounds[k] = bounds_of(v);
                }
            })
        });
        bounds
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
    fn drop_dominated(
        &self,
        bound: &impl Fn(usize) -> (f64, f64),
        decisions: &mut [u8],
        gone: &mut Vec<bool>,
    ) {
        // A leaf's key: how far up (for a max) it is sure to reach, and where it may end.
        let key = |r: u32| {
            let (lo, hi) = bound(r as usize);
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
pub(crate) fn bounds_of<R: Real>(v: &R) -> (f64, f64) {
    match v.known() {
        Known::Range(lo, hi) => (lo, hi),
        Known::Point(p) => (p, p),
        Known::Unknown => (f64::NAN, f64::NAN),
    }
}
