//! Building tapes: the [`Builder`] readers compile into, and [`finish`], which drops
//! dead code, renumbers and marks each operand's last read (so the interpreter moves
//! values out of registers instead of cloning them, which matters for heap-backed
//! affine forms).
//!
//! Comparisons compile to steps `d > 0` / `d >= 0` of a difference (exact in sign in
//! `f64`), conditions to truth values 0 or 1, and `if` to [`Op::Select`]; see
//! [`arith_core::branch`] for why they are sound over ranges. A condition that folds to
//! a constant picks its branch at build time, so only the branch taken is built.

use crate::fold::{exact_powi, fold_bin, fold_cmp, fold_unary, Bin, EPS};
use crate::instr::{Instr, Key, Op};
use arith_core::branch::Step;
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};

/// A value being built: a constant (folded where exact) or a register.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Val {
    /// A constant, not yet an instruction.
    C(f64),
    /// A register.
    R(u32),
}

/// Builds a tape instruction by instruction: identical instructions are shared
/// (hash-consing), constants folded where the result is exact ([`crate::fold`]), `a * a`
/// becomes `sqr(a)`, comparisons become steps of a difference and conditions truth
/// values 0 or 1. [`Builder::finish`] (in [`crate::tape`]) drops what the result does not read.
#[derive(Default)]
pub struct Builder {
    pub(crate) ins: Vec<Instr>,
    memo: HashMap<Key, u32>,
    /// Registers whose value is a truth value, exactly 0 or 1 at every point.
    bools: HashSet<u32>,
}

impl Builder {
    /// An empty builder.
    pub fn new() -> Self {
        Builder::with_capacity(0)
    }

    /// A builder with room for `n` instructions.
    pub fn with_capacity(n: usize) -> Self {
        Builder {
            ins: Vec::with_capacity(n),
            memo: HashMap::with_capacity_and_hasher(n, Default::default()),
            bools: HashSet::default(),
        }
    }

    /// Appends `i` (or finds the same instruction built before): its register.
    pub fn emit(&mut self, mut i: Instr) -> u32 {
        if i.op.commutative() && i.a > i.b {
            std::mem::swap(&mut i.a, &mut i.b);
        }
        if i.op == Op::Mul && i.a == i.b {
            // `a * a` as `sqr(a)`: the same `f64` value, never a wider range.
            i = Instr::new(Op::Sqr, i.a, 0, 0, 0.0);
        }
        let is_bool = |r: u32| self.bools.contains(&r);
        let boolean = match i.op {
            Op::Gt0 | Op::Ge0 => true,
            Op::Const => i.c == 0.0 || i.c == 1.0,
            Op::Min | Op::Max => is_bool(i.a) && is_bool(i.b),
            Op::RSubC => i.c == 1.0 && is_bool(i.a),
            Op::Select => is_bool(i.b) && is_bool(i.e),
            _ => false,
        };
        let r = *self.memo.entry(i.key()).or_insert_with(|| {
            self.ins.push(i);
            (self.ins.len() - 1) as u32
        });
        if boolean {
            self.bools.insert(r);
        }
        r
    }

    /// The truth value of `v`: `v` itself where it is one, else `|v| >= EPS`.
    pub fn truth(&mut self, v: Val) -> Val {
        match v {
            Val::C(c) => Val::C(if c.abs() >= EPS { 1.0 } else { 0.0 }),
            Val::R(r) if self.bools.contains(&r) => v,
            Val::R(_) => {
                let a = self.unary(Op::Abs, v);
                let d = self.binary(Bin::Sub, a, Val::C(EPS));
                self.step(Step::NonNeg, d)
            }
        }
    }

    /// The step `s` of `v` (1 or 0), folded where `v` is a constant.
    pub fn step(&mut self, s: Step, v: Val) -> Val {
        match v {
            Val::C(c) => Val::C(s.at(c)),
            Val::R(r) => {
                let op = if s == Step::Pos { Op::Gt0 } else { Op::Ge0 };
                Val::R(self.emit(Instr::new(op, r, 0, 0, 0.0)))
            }
        }
    }

    /// A comparison as the step of a difference (exact in sign in `f64`).
    pub fn compare(&mut self, op: Bin, l: Val, r: Val) -> Val {
        if let (Val::C(a), Val::C(b)) = (l, r) {
            return Val::C(fold_cmp(op, a, b));
        }
        let zero = matches!(r, Val::C(c) if c == 0.0);
        // `<` and `>` are strict steps, `<=` and `>=` not.
        let s = if matches!(op, Bin::Lt | Bin::Gt) {
            Step::Pos
        } else {
            Step::NonNeg
        };
        match op {
            Bin::Gt | Bin::Ge if zero => self.step(s, l),
            Bin::Lt | Bin::Le => {
                let d = self.binary(Bin::Sub, r, l);
                self.step(s, d)
            }
            Bin::Gt | Bin::Ge => {
                let d = self.binary(Bin::Sub, l, r);
                self.step(s, d)
            }
            _ => {
                let d = self.binary(Bin::Sub, l, r);
                let t = self.unary(Op::Abs, d);
                if op == Bin::Eq {
                    let d = self.binary(Bin::Sub, Val::C(EPS), t);
                    self.step(Step::Pos, d)
                } else {
                    let d = self.binary(Bin::Sub, t, Val::C(EPS));
                    self.step(Step::NonNeg, d)
                }
            }
        }
    }

    /// `and` as the minimum, `or` as the maximum of two truth values.
    pub fn logic(&mut self, op: Bin, l: Val, r: Val) -> Val {
        let (a, b) = (self.truth(l), self.truth(r));
        let and = op == Bin::And;
        match (a, b) {
            (Val::C(p), Val::C(q)) => Val::C(if and { p.min(q) } else { p.max(q) }),
            (Val::C(p), v) | (v, Val::C(p)) => match (and, p == 1.0) {
                (true, true) | (false, false) => v,
                (true, false) => Val::C(0.0),
                (false, true) => Val::C(1.0),
            },
            (Val::R(a), Val::R(b)) => {
                let op = if and { Op::Min } else { Op::Max };
                Val::R(self.emit(Instr::new(op, a, b, 0, 0.0)))
            }
        }
    }

    /// `if(c, t, e)`: the branch itself where `c` folds, else a selection.
    pub fn select(&mut self, c: Val, t: Val, e: Val) -> Val {
        match self.truth(c) {
            Val::C(p) => {
                if p == 1.0 {
                    t
                } else {
                    e
                }
            }
            Val::R(c) => {
                if let (Val::C(a), Val::C(b)) = (t, e) {
                    if a.to_bits() == b.to_bits() {
                        return t;
                    }
                }
                let (t, e) = (self.reg(t), self.reg(e));
                if t == e {
                    return Val::R(t);
                }
                let mut i = Instr::new(Op::Select, c, t, 0, 0.0);
                i.e = e;
                Val::R(self.emit(i))
            }
        }
    }

    /// HyperFun's `hfBlendUni` / `hfBlendInt`: `f1 | f2` (or `&`) plus
    /// `a0 / (1 + (f1/a1)^2 + (f2/a2)^2)`, in the library's order of operations.
    pub fn hf_blend(&mut self, union: bool, v: [Val; 5]) -> Val {
        let [f1, f2, a0, a1, a2] = v;
        let op = if union { Bin::Union } else { Bin::Intersect };
        let set = self.binary(op, f1, f2);
        let q1 = self.binary(Bin::Div, f1, a1);
        let q1 = self.powi(q1, 2);
        let q2 = self.binary(Bin::Div, f2, a2);
        let q2 = self.powi(q2, 2);
        let s = self.binary(Bin::Add, Val::C(1.0), q1);
        let s = self.binary(Bin::Add, s, q2);
        let d = self.binary(Bin::Div, a0, s);
        self.binary(Bin::Add, set, d)
    }

    /// The register of `v`, a constant instruction where it is a constant.
    pub fn reg(&mut self, v: Val) -> u32 {
        match v {
            Val::R(r) => r,
            Val::C(c) => self.emit(Instr::new(Op::Const, 0, 0, 0, c)),
        }
    }

    /// `op(v)` as an instruction (never folded).
    pub fn unary(&mut self, op: Op, v: Val) -> Val {
        let a = self.reg(v);
        Val::R(self.emit(Instr::new(op, a, 0, 0, 0.0)))
    }

    /// `op(v)`, folded where `v` is a constant and the result is exact.
    pub fn unary_folded(&mut self, op: Op, v: Val) -> Val {
        if let Val::C(c) = v {
            if let Some(r) = fold_unary(op, c) {
                return Val::C(r);
            }
        }
        self.unary(op, v)
    }

    /// `v^n`: folded where exact, `v` itself for `n = 1`, `sqr` for `n = 2`.
    pub fn powi(&mut self, v: Val, n: i32) -> Val {
        if let Val::C(c) = v {
            if let Some(p) = exact_powi(c, n) {
                return Val::C(p);
            }
        }
        let a = self.reg(v);
        Val::R(match n {
            1 => a,
            2 => self.emit(Instr::new(Op::Sqr, a, 0, 0, 0.0)),
            _ => self.emit(Instr::new(Op::Powi, a, 0, n, 0.0)),
        })
    }

    /// `l op r`: folded where exact, with a constant operand as one instruction
    /// (`AddC`, `RSubC`, ...), comparisons and logic as steps and `min`/`max` of truth
    /// values.
    pub fn binary(&mut self, op: Bin, l: Val, r: Val) -> Val {
        match op {
            Bin::Lt | Bin::Le | Bin::Gt | Bin::Ge | Bin::Eq | Bin::Ne => {
                return self.compare(op, l, r)
            }
            Bin::And | Bin::Or => return self.logic(op, l, r),
            _ => {}
        }
        if let (Val::C(a), Val::C(b)) = (l, r) {
            if let Some(v) = fold_bin(op, a, b) {
                return Val::C(v);
            }
        }
        let with_c = |op: Op, a: u32, c: f64| Instr::new(op, a, 0, 0, c);
        let i = match (op, l, r) {
            (Bin::Add, Val::R(a), Val::C(c)) | (Bin::Add, Val::C(c), Val::R(a)) => {
                with_c(Op::AddC, a, c)
            }
            (Bin::Sub, Val::R(a), Val::C(c)) => with_c(Op::SubC, a, c),
            (Bin::Sub, Val::C(c), Val::R(a)) => with_c(Op::RSubC, a, c),
            (Bin::Mul, Val::R(a), Val::C(c)) | (Bin::Mul, Val::C(c), Val::R(a)) => {
                with_c(Op::MulC, a, c)
            }
            (Bin::Div, Val::R(a), Val::C(c)) => with_c(Op::DivC, a, c),
            (Bin::Div, Val::C(c), Val::R(a)) => with_c(Op::RDivC, a, c),
            (Bin::Add | Bin::Sub | Bin::Mul | Bin::Div, Val::C(a), Val::C(c)) => {
                // Both constant but not exactly foldable: evaluate in the arithmetic.
                let a = self.reg(Val::C(a));
                let op = match op {
                    Bin::Add => Op::AddC,
                    Bin::Sub => Op::SubC,
                    Bin::Mul => Op::MulC,
                    _ => Op::DivC,
                };
                with_c(op, a, c)
            }
            _ => {
                let a = self.reg(l);
                let b = self.reg(r);
                let op = match op {
                    Bin::Add => Op::Add,
                    Bin::Sub => Op::Sub,
                    Bin::Mul => Op::Mul,
                    Bin::Div => Op::Div,
                    Bin::Intersect => Op::Intersect,
                    Bin::Union => Op::Union,
                    // Comparisons and logic returned above.
                    _ => Op::Subtract,
                };
                Instr::new(op, a, b, 0, 0.0)
            }
        };
        Val::R(self.emit(i))
    }

    /// Appends `i` as it is: no sharing, no rewriting (a recording keeps every operation
    /// the recorded code performs).
    pub fn push(&mut self, i: Instr) -> u32 {
        self.ins.push(i);
        (self.ins.len() - 1) as u32
    }
}

/// Drops instructions the result does not depend on, renumbers, and marks last reads.
pub(crate) fn finish(ins: Vec<Instr>, out: u32) -> Vec<Instr> {
    let out = out as usize;
    let mut live = vec![false; ins.len()];
    live[out] = true;
    for r in (0..=out).rev() {
        if live[r] {
            let i = ins[r];
            for &k in i.operands() {
                live[i.reg(k) as usize] = true;
            }
        }
    }
    let mut new_index = vec![0u32; ins.len()];
    let mut kept = Vec::new();
    for (r, mut i) in ins.into_iter().enumerate().take(out + 1) {
        if !live[r] {
            continue;
        }
        // Last reads are marked afresh below (the input may be a finished tape).
        i.last = 0;
        let arity = i.op.arity();
        for k in 0..3 {
            let r = i.reg_mut(k);
            *r = if k < arity { new_index[*r as usize] } else { 0 };
        }
        new_index[r] = kept.len() as u32;
        kept.push(i);
    }
    // The result must be the last instruction.
    debug_assert_eq!(new_index[out] as usize, kept.len() - 1);
    // Last reads: walk backwards; the first read seen of a register (in reverse reading
    // order) is its last. The result register is read after the tape.
    let mut seen = vec![false; kept.len()];
    if let Some(s) = seen.last_mut() {
        *s = true;
    }
    for i in kept.iter_mut().rev() {
        for &k in i.operands().iter().rev() {
            let r = i.reg(k) as usize;
            if !seen[r] {
                seen[r] = true;
                i.last |= 1 << k;
            }
        }
    }
    kept
}
