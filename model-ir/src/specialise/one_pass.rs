//! The specialised tape written in one backward and one forward pass over the parent,
//! without a [`crate::Builder`]: no hashing, no maps, buffers kept per thread.
//!
//! The parent was built by the builder (its instructions shared and folded already), so
//! re-emitting a kept instruction needs neither hash-consing nor general constant
//! folding. The only constants the decisions bring in are those that stand for a sign
//! (`1`, `-1`, [`Fold::Sign`]) or for "beyond the level" (`inf`, `-inf`,
//! [`Fold::Level`]), and the parent's own constants that a decided `min` or `max` now
//! passes on. A folded register flows, by the definition of sign-only (level-only)
//! registers, only into instructions that read its sign (its clamped value): it folds
//! through the rules below where the instruction is itself folded, and is written as a
//! `Const` instruction where it is not (a comparison with 0, a selection's branch, an
//! operand a decided `min` handed on), which reads the same sign.
//!
//! The rules, for a folded instruction with a constant operand. By sign (`p > 0` stands
//! for "positive", `p < 0` for "negative"; a zero constant folds nothing):
//! `min(p, b) = b`, `min(-p, b) = -1`, `max(-p, b) = b`, `max(p, b) = 1` (the
//! R-functions `&` and `|` likewise, as they have the signs of `min` and `max`, and a
//! sign-only `&`, `|` between registers becomes `min`, `max`), `a \ b = a & -b`, and
//! `-c`, `c * k`, `c / k` of a constant folded. By level the same for `min`, `max` and
//! negation with `inf` and `-inf` alone (a model's constants keep their values). These
//! are the rules of [`super::proofs`].

use super::rules::{Fold, KEEP, NEG, POS, TAKE_A, TAKE_B};
use crate::builder::finish;
use crate::instr::{Instr, Op};
use std::cell::RefCell;

/// A value of the rebuilt tape: a register of it, or a constant not yet written.
#[derive(Clone, Copy, Debug, PartialEq)]
enum V {
    R(u32),
    C(f64),
}

/// Buffers kept per thread.
#[derive(Default)]
struct Scratch {
    live: Vec<bool>,
    map: Vec<V>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::default();
}

/// `ins` with `decisions` applied (see [`super::rules::Specialiser::decide`]), the
/// registers marked in `folded` (none where `None`) folded as `fold` says (by sign, the
/// sign-only R-functions turned into `min` and `max`), stripped of dead code and with
/// its last reads marked.
pub(crate) fn rebuild(
    ins: &[Instr],
    folded: Option<&[bool]>,
    fold: Fold,
    decisions: &[u8],
) -> Vec<Instr> {
    let level = matches!(fold, Fold::Level(_));
    let top = if level { f64::INFINITY } else { 1.0 };
    let run = |sc: &mut Scratch| {
        live_under(ins, decisions, &mut sc.live);
        let mut out = Writer {
            ins: Vec::with_capacity(sc.live.iter().filter(|&&l| l).count() + 2),
        };
        sc.map.clear();
        sc.map.resize(ins.len(), V::C(f64::NAN));
        for (k, i) in ins.iter().enumerate() {
            if !sc.live[k] {
                continue;
            }
            let how = match folded {
                Some(f) if f[k] && level => How::Level,
                Some(f) if f[k] => How::Sign,
                _ => How::Exact,
            };
            let map = &sc.map;
            sc.map[k] = match decisions[k] {
                POS => V::C(top),
                NEG => V::C(-top),
                TAKE_A => map[i.a as usize],
                TAKE_B => map[i.b as usize],
                _ => out.rewrite(i, map, how),
            };
        }
        let result = sc.map[ins.len() - 1];
        let r = out.reg(result);
        finish(out.ins, r)
    };
    SCRATCH.with(|c| match c.try_borrow_mut() {
        Ok(mut sc) => run(&mut sc),
        Err(_) => run(&mut Scratch::default()),
    })
}

/// How an instruction's constant operands may fold.
#[derive(Clone, Copy, PartialEq)]
enum How {
    /// Its value is kept: only a negated constant folds (exactly).
    Exact,
    /// Only its sign matters.
    Sign,
    /// It reaches the result only through `min`, `max` and negation.
    Level,
}

/// Which registers the result still reads once the decisions are made, into `live`.
fn live_under(ins: &[Instr], decisions: &[u8], live: &mut Vec<bool>) {
    let n = ins.len();
    live.clear();
    live.resize(n, false);
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
            d => {
                debug_assert_eq!(d, KEEP);
                for &p in i.operands() {
                    live[i.reg(p) as usize] = true;
                }
            }
        }
    }
}

/// The rebuilt tape as it is written.
struct Writer {
    ins: Vec<Instr>,
}

impl Writer {
    fn push(&mut self, i: Instr) -> u32 {
        self.ins.push(i);
        (self.ins.len() - 1) as u32
    }

    /// `v` as a register (a constant written as a `Const` instruction).
    fn reg(&mut self, v: V) -> u32 {
        match v {
            V::R(r) => r,
            V::C(c) => self.push(Instr::new(Op::Const, 0, 0, 0, c)),
        }
    }

    /// `-v`.
    fn neg(&mut self, v: V) -> V {
        match v {
            V::C(c) => V::C(-c),
            V::R(r) => V::R(self.push(Instr::new(Op::Neg, r, 0, 0, 0.0))),
        }
    }

    /// `i` over its rewritten operands (`map`), folded as `how` allows.
    fn rewrite(&mut self, i: &Instr, map: &[V], how: How) -> V {
        let sign = how == How::Sign;
        let level = how == How::Level;
        let arity = i.op.arity();
        let arg = |k: usize| map[i.reg(k) as usize];
        let (a, b) = (
            if arity > 0 { arg(0) } else { V::C(0.0) },
            if arity > 1 { arg(1) } else { V::C(0.0) },
        );
        let folded = match i.op {
            Op::Const => return V::C(i.c),
            Op::Neg => match a {
                V::C(p) => Some(V::C(-p)),
                _ => None,
            },
            Op::MulC | Op::DivC if sign => match a {
                V::C(p) if i.op == Op::MulC => Some(V::C(p * i.c)),
                V::C(p) => Some(V::C(p / i.c)),
                _ => None,
            },
            Op::Min | Op::Intersect if sign => meet(a, b, 1.0),
            Op::Max | Op::Union if sign => join(a, b, 1.0),
            Op::Min if level => meet(a, b, f64::INFINITY),
            Op::Max if level => join(a, b, f64::INFINITY),
            // `a \ b` is `a & -b`.
            Op::Subtract if sign => match (a, b) {
                (_, V::C(q)) => meet(a, V::C(-q), 1.0),
                (V::C(p), V::R(_)) if p > 0.0 => Some(self.neg(b)),
                (V::C(p), V::R(_)) if p < 0.0 => Some(V::C(-1.0)),
                _ => None,
            },
            _ => None,
        };
        if let Some(v) = folded {
            return v;
        }
        let op = match i.op {
            Op::Intersect if sign => Op::Min,
            Op::Union if sign => Op::Max,
            Op::Subtract if sign => {
                let (ra, nb) = (self.reg(a), self.neg(b));
                let rb = self.reg(nb);
                return V::R(self.push(Instr::new(Op::Min, ra, rb, 0, 0.0)));
            }
            op => op,
        };
        let mut out = Instr { last: 0, op, ..*i };
        for k in 0..arity {
            let r = self.reg(arg(k));
            *out.reg_mut(k) = r;
        }
        V::R(self.push(out))
    }
}

/// `min(a, b)` where an operand is a folded constant: the other operand where one
/// stands for "above" (`p > 0` by sign, `top = 1`; `inf` by level, `top = inf`), `-top`
/// where one stands for "below"; `None` otherwise (two registers, or a constant that
/// stands for neither beside a register).
fn meet(a: V, b: V, top: f64) -> Option<V> {
    let (pos, neg) = stands(top);
    if neg(a) || neg(b) {
        Some(V::C(-top))
    } else if pos(a) {
        Some(b)
    } else if pos(b) {
        Some(a)
    } else {
        None
    }
}

/// `max(a, b)` as [`meet`]: the other operand where one stands for "below", `top` where
/// one stands for "above".
fn join(a: V, b: V, top: f64) -> Option<V> {
    let (pos, neg) = stands(top);
    if pos(a) || pos(b) {
        Some(V::C(top))
    } else if neg(a) {
        Some(b)
    } else if neg(b) {
        Some(a)
    } else {
        None
    }
}

/// Whether a value stands for "above" and for "below": by sign (`top = 1`) any positive
/// (negative) constant, by level only `inf` (`-inf`).
fn stands(top: f64) -> (impl Fn(V) -> bool, impl Fn(V) -> bool) {
    let level = top == f64::INFINITY;
    (
        move |v: V| matches!(v, V::C(p) if p > 0.0 && (!level || p == f64::INFINITY)),
        move |v: V| matches!(v, V::C(p) if p < 0.0 && (!level || p == f64::NEG_INFINITY)),
    )
}
