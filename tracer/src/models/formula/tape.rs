//! The tape: a formula compiled to a flat list of SSA instructions, interpreted over any
//! [`Real`].
//!
//! Compilation folds constant subexpressions **only when the `f64` result is exact**
//! (checked with error-free transformations): a folded constant then equals the real
//! value, so range evaluation stays sound; an inexact one such as `1/3` stays an
//! instruction and every [`arith_core::Range`] encloses it. Identical subexpressions
//! (and every let-bound value) are computed once (hash-consing); unused bindings are
//! dropped. Each operand carries a "last use" flag so the interpreter moves values out
//! of registers instead of cloning them (which matters for heap-backed affine forms).
//!
//! Comparisons compile to steps `d > 0` / `d >= 0` of a difference (exact in sign in
//! `f64`), conditions to truth values 0 or 1, and `if` to [`Op::Select`]; see
//! [`super::branch`] for why they are sound over ranges. A condition that folds to a
//! constant picks its branch at compile time, so only the branch taken is compiled.

use super::ast::{BinOp, Expr, Func, Program, Var};
use super::branch::{select, step, Step};
use arith_core::round::two_sum;
use arith_core::{rfunc, Real};
use rustc_hash::{FxHashMap as HashMap, FxHashSet as HashSet};
use std::any::Any;
use std::cell::RefCell;
use std::fmt;
use std::sync::{Arc, OnceLock};

/// What an instruction computes. `a`, `b` are operand registers, `c` an `f64` constant,
/// `n` an integer exponent.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Op {
    /// The input `x`.
    X,
    /// The input `y`.
    Y,
    /// The input `z`.
    Z,
    /// `c`
    Const,
    /// `-a`
    Neg,
    /// `a^2`
    Sqr,
    /// `a^n`
    Powi,
    /// `sqrt(a)`
    Sqrt,
    /// `exp(a)`
    Exp,
    /// `ln(a)`
    Ln,
    /// `sin(a)`
    Sin,
    /// `cos(a)`
    Cos,
    /// `|a|`
    Abs,
    /// `a + c`
    AddC,
    /// `a - c`
    SubC,
    /// `c - a`
    RSubC,
    /// `a * c`
    MulC,
    /// `a / c`
    DivC,
    /// `c / a`
    RDivC,
    /// `a + b`
    Add,
    /// `a - b`
    Sub,
    /// `a * b`
    Mul,
    /// `a / b`
    Div,
    /// `min(a, b)`
    Min,
    /// `max(a, b)`
    Max,
    /// R-function `a & b`
    Intersect,
    /// R-function `a | b`
    Union,
    /// R-function `a \ b`
    Subtract,
    /// The paper's blending union `blend_union(a, b)`
    BlendUnion,
    /// The paper's blending intersection `blend_intersect(a, b)`
    BlendIntersect,
    /// `a > 0`: 1 or 0 (the range `[0, 1]` where undecided)
    Gt0,
    /// `a >= 0`: 1 or 0 (the range `[0, 1]` where undecided)
    Ge0,
    /// `b` where the truth value `a` is 1, `e` where it is 0 (the hull where undecided)
    Select,
}

impl Op {
    /// Number of register operands.
    pub fn arity(self) -> usize {
        use Op::*;
        match self {
            X | Y | Z | Const => 0,
            Neg | Sqr | Powi | Sqrt | Exp | Ln | Sin | Cos | Abs | Gt0 | Ge0 => 1,
            AddC | SubC | RSubC | MulC | DivC | RDivC => 1,
            Add | Sub | Mul | Div | Min | Max | Intersect | Union | Subtract => 2,
            BlendUnion | BlendIntersect => 2,
            Select => 3,
        }
    }

    /// Lower-case mnemonic used in listings.
    pub fn name(self) -> &'static str {
        use Op::*;
        match self {
            X => "x",
            Y => "y",
            Z => "z",
            Const => "const",
            Neg => "neg",
            Sqr => "sqr",
            Powi => "powi",
            Sqrt => "sqrt",
            Exp => "exp",
            Ln => "ln",
            Sin => "sin",
            Cos => "cos",
            Abs => "abs",
            AddC => "addc",
            SubC => "subc",
            RSubC => "rsubc",
            MulC => "mulc",
            DivC => "divc",
            RDivC => "rdivc",
            Add => "add",
            Sub => "sub",
            Mul => "mul",
            Div => "div",
            Min => "min",
            Max => "max",
            Intersect => "intersect",
            Union => "union",
            Subtract => "subtract",
            BlendUnion => "blend_union",
            BlendIntersect => "blend_intersect",
            Gt0 => "gt0",
            Ge0 => "ge0",
            Select => "select",
        }
    }

    /// Whether swapping the operands never changes a bit of the result, so that the
    /// builder may order them to share `a op b` and `b op a`. Not `min`/`max`: for
    /// `-0` and `+0` the `f64` result is whichever operand comes second.
    fn commutative(self) -> bool {
        matches!(
            self,
            Op::Add | Op::Mul | Op::Intersect | Op::Union | Op::BlendUnion | Op::BlendIntersect
        )
    }
}

/// One tape instruction; its result is the register with its own index.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instr {
    /// What it computes.
    pub op: Op,
    /// Exponent of [`Op::Powi`], 0 otherwise.
    pub n: i32,
    /// Operand registers (unused ones are 0).
    pub a: u32,
    /// Second operand register (unused ones are 0).
    pub b: u32,
    /// Third operand register: the else value of [`Op::Select`] (0 otherwise).
    pub e: u32,
    /// Constant of [`Op::Const`] and the `...C` ops, 0 otherwise.
    pub c: f64,
    /// Bit 0: this is the last read of `a`; bit 1: of `b`; bit 2: of `e` (the value is
    /// moved, not cloned).
    pub last: u8,
}

impl Instr {
    pub(super) fn new(op: Op, a: u32, b: u32, n: i32, c: f64) -> Self {
        Instr {
            op,
            n,
            a,
            b,
            e: 0,
            c,
            last: 0,
        }
    }

    /// Register operands, in reading order.
    pub fn operands(&self) -> &'static [usize] {
        match self.op.arity() {
            0 => &[],
            1 => &[0],
            2 => &[0, 1],
            _ => &[0, 1, 2],
        }
    }

    pub(super) fn reg(&self, k: usize) -> u32 {
        match k {
            0 => self.a,
            1 => self.b,
            _ => self.e,
        }
    }

    fn reg_mut(&mut self, k: usize) -> &mut u32 {
        match k {
            0 => &mut self.a,
            1 => &mut self.b,
            _ => &mut self.e,
        }
    }

    fn key(&self) -> Key {
        (self.op, self.n, [self.a, self.b, self.e], self.c.to_bits())
    }
}

impl fmt::Display for Instr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.op.name())?;
        for &k in self.operands() {
            let sep = if k == 0 { " " } else { ", " };
            let moved = if self.last & (1 << k) != 0 { "!" } else { "" };
            write!(f, "{sep}r{}{moved}", self.reg(k))?;
        }
        match self.op {
            Op::Const => write!(f, " {:?}", self.c),
            Op::Powi => write!(f, ", {}", self.n),
            Op::AddC | Op::SubC | Op::RSubC | Op::MulC | Op::DivC | Op::RDivC => {
                write!(f, ", {:?}", self.c)
            }
            _ => Ok(()),
        }
    }
}

/// A compiled formula: evaluate it with [`Tape::eval`] (or through [`crate::shape::Shape`]).
#[derive(Clone, Debug)]
pub struct Tape {
    ins: Arc<[Instr]>,
    /// What region specialisation needs of this tape, built on first use
    /// ([`super::specialise`]); shared by clones.
    pub(super) spec: Arc<OnceLock<super::specialise::Specialiser>>,
}

/// Why a hand-built [`Program`] cannot be compiled (the parser never produces one).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CompileError(pub String);

impl fmt::Display for CompileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for CompileError {}

#[derive(Clone, Copy, Debug)]
pub(super) enum Val {
    C(f64),
    R(u32),
}

/// What identifies an instruction for sharing: op, exponent, operands, constant bits.
type Key = (Op, i32, [u32; 3], u64);

/// HyperFun's tolerance for truth values and equality: `|v| >= EPS` holds.
pub const EPS: f64 = 1e-6;

pub(super) struct Builder {
    pub(super) ins: Vec<Instr>,
    memo: HashMap<Key, u32>,
    /// Registers whose value is a truth value, exactly 0 or 1 at every point.
    bools: HashSet<u32>,
}

impl Builder {
    pub(super) fn new() -> Self {
        Builder::with_capacity(0)
    }

    /// A builder with room for `n` instructions.
    pub(super) fn with_capacity(n: usize) -> Self {
        Builder {
            ins: Vec::with_capacity(n),
            memo: HashMap::with_capacity_and_hasher(n, Default::default()),
            bools: HashSet::default(),
        }
    }

    pub(super) fn emit(&mut self, mut i: Instr) -> u32 {
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
    fn truth(&mut self, v: Val) -> Val {
        match v {
            Val::C(c) => Val::C(if c.abs() >= EPS { 1.0 } else { 0.0 }),
            Val::R(r) if self.bools.contains(&r) => v,
            Val::R(_) => {
                let a = self.unary(Op::Abs, v);
                let d = self.binary(BinOp::Sub, a, Val::C(EPS));
                self.step(Step::NonNeg, d)
            }
        }
    }

    pub(super) fn step(&mut self, s: Step, v: Val) -> Val {
        match v {
            Val::C(c) => Val::C(s.at(c)),
            Val::R(r) => {
                let op = if s == Step::Pos { Op::Gt0 } else { Op::Ge0 };
                Val::R(self.emit(Instr::new(op, r, 0, 0, 0.0)))
            }
        }
    }

    /// A comparison as the step of a difference (exact in sign in `f64`).
    fn compare(&mut self, op: BinOp, l: Val, r: Val) -> Val {
        if let (Val::C(a), Val::C(b)) = (l, r) {
            return Val::C(fold_cmp(op, a, b));
        }
        let zero = matches!(r, Val::C(c) if c == 0.0);
        // `<` and `>` are strict steps, `<=` and `>=` not.
        let s = if matches!(op, BinOp::Lt | BinOp::Gt) {
            Step::Pos
        } else {
            Step::NonNeg
        };
        match op {
            BinOp::Gt | BinOp::Ge if zero => self.step(s, l),
            BinOp::Lt | BinOp::Le => {
                let d = self.binary(BinOp::Sub, r, l);
                self.step(s, d)
            }
            BinOp::Gt | BinOp::Ge => {
                let d = self.binary(BinOp::Sub, l, r);
                self.step(s, d)
            }
            _ => {
                let d = self.binary(BinOp::Sub, l, r);
                let t = self.unary(Op::Abs, d);
                if op == BinOp::Eq {
                    let d = self.binary(BinOp::Sub, Val::C(EPS), t);
                    self.step(Step::Pos, d)
                } else {
                    let d = self.binary(BinOp::Sub, t, Val::C(EPS));
                    self.step(Step::NonNeg, d)
                }
            }
        }
    }

    /// `and` as the minimum, `or` as the maximum of two truth values.
    fn logic(&mut self, op: BinOp, l: Val, r: Val) -> Val {
        let (a, b) = (self.truth(l), self.truth(r));
        let and = op == BinOp::And;
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
    pub(super) fn select(&mut self, c: Val, t: Val, e: Val) -> Val {
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
    fn hf_blend(&mut self, union: bool, v: &[Val]) -> Val {
        let (f1, f2, a0, a1, a2) = (v[0], v[1], v[2], v[3], v[4]);
        let op = if union {
            BinOp::Union
        } else {
            BinOp::Intersect
        };
        let set = self.binary(op, f1, f2);
        let q1 = self.binary(BinOp::Div, f1, a1);
        let q1 = self.powi(q1, 2);
        let q2 = self.binary(BinOp::Div, f2, a2);
        let q2 = self.powi(q2, 2);
        let s = self.binary(BinOp::Add, Val::C(1.0), q1);
        let s = self.binary(BinOp::Add, s, q2);
        let d = self.binary(BinOp::Div, a0, s);
        self.binary(BinOp::Add, set, d)
    }

    pub(super) fn reg(&mut self, v: Val) -> u32 {
        match v {
            Val::R(r) => r,
            Val::C(c) => self.emit(Instr::new(Op::Const, 0, 0, 0, c)),
        }
    }

    pub(super) fn unary(&mut self, op: Op, v: Val) -> Val {
        let a = self.reg(v);
        Val::R(self.emit(Instr::new(op, a, 0, 0, 0.0)))
    }

    /// `op(v)`, folded where `v` is a constant and the result is exact.
    pub(super) fn unary_folded(&mut self, op: Op, v: Val) -> Val {
        if let Val::C(c) = v {
            if let Some(r) = fold_unary(op, c) {
                return Val::C(r);
            }
        }
        self.unary(op, v)
    }

    pub(super) fn powi(&mut self, v: Val, n: i32) -> Val {
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

    pub(super) fn binary(&mut self, op: BinOp, l: Val, r: Val) -> Val {
        match op {
            BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge | BinOp::Eq | BinOp::Ne => {
                return self.compare(op, l, r)
            }
            BinOp::And | BinOp::Or => return self.logic(op, l, r),
            _ => {}
        }
        if let (Val::C(a), Val::C(b)) = (l, r) {
            if let Some(v) = fold_bin(op, a, b) {
                return Val::C(v);
            }
        }
        let with_c = |op: Op, a: u32, c: f64| Instr::new(op, a, 0, 0, c);
        let i = match (op, l, r) {
            (BinOp::Add, Val::R(a), Val::C(c)) | (BinOp::Add, Val::C(c), Val::R(a)) => {
                with_c(Op::AddC, a, c)
            }
            (BinOp::Sub, Val::R(a), Val::C(c)) => with_c(Op::SubC, a, c),
            (BinOp::Sub, Val::C(c), Val::R(a)) => with_c(Op::RSubC, a, c),
            (BinOp::Mul, Val::R(a), Val::C(c)) | (BinOp::Mul, Val::C(c), Val::R(a)) => {
                with_c(Op::MulC, a, c)
            }
            (BinOp::Div, Val::R(a), Val::C(c)) => with_c(Op::DivC, a, c),
            (BinOp::Div, Val::C(c), Val::R(a)) => with_c(Op::RDivC, a, c),
            (BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div, Val::C(a), Val::C(c)) => {
                // Both constant but not exactly foldable: evaluate in the arithmetic.
                let a = self.reg(Val::C(a));
                let op = match op {
                    BinOp::Add => Op::AddC,
                    BinOp::Sub => Op::SubC,
                    BinOp::Mul => Op::MulC,
                    _ => Op::DivC,
                };
                with_c(op, a, c)
            }
            _ => {
                let a = self.reg(l);
                let b = self.reg(r);
                let op = match op {
                    BinOp::Add => Op::Add,
                    BinOp::Sub => Op::Sub,
                    BinOp::Mul => Op::Mul,
                    BinOp::Div => Op::Div,
                    BinOp::Intersect => Op::Intersect,
                    BinOp::Union => Op::Union,
                    // Comparisons and logic returned above.
                    _ => Op::Subtract,
                };
                Instr::new(op, a, b, 0, 0.0)
            }
        };
        Val::R(self.emit(i))
    }

    fn expr(&mut self, e: &Expr, binds: &[Val]) -> Result<Val, CompileError> {
        Ok(match e {
            Expr::Num(c) => Val::C(*c),
            Expr::Var(v) => {
                let op = match v {
                    Var::X => Op::X,
                    Var::Y => Op::Y,
                    Var::Z => Op::Z,
                };
                Val::R(self.emit(Instr::new(op, 0, 0, 0, 0.0)))
            }
            Expr::Ref(i) => *binds
                .get(*i)
                .ok_or_else(|| CompileError(format!("binding #{i} used before it is defined")))?,
            Expr::Neg(a) => match self.expr(a, binds)? {
                Val::C(c) => Val::C(-c),
                v => self.unary(Op::Neg, v),
            },
            Expr::Pow(a, n) => {
                let v = self.expr(a, binds)?;
                self.powi(v, *n)
            }
            Expr::PowF(a, c) => {
                let v = self.expr(a, binds)?;
                let l = self.unary_folded(Op::Ln, v);
                let m = self.binary(BinOp::Mul, l, Val::C(*c));
                self.unary_folded(Op::Exp, m)
            }
            Expr::Call(f, args)
                if f.arity() > 2
                    || matches!(f, Func::Not | Func::BlendUnion | Func::BlendIntersect) =>
            {
                if args.len() != f.arity() {
                    return Err(CompileError(format!(
                        "{} takes {} argument(s), not {}",
                        f.name(),
                        f.arity(),
                        args.len()
                    )));
                }
                let mut v = Vec::with_capacity(args.len());
                for a in args {
                    v.push(self.expr(a, binds)?);
                }
                match f {
                    Func::If => self.select(v[0], v[1], v[2]),
                    Func::Not => {
                        let t = self.truth(v[0]);
                        self.binary(BinOp::Sub, Val::C(1.0), t)
                    }
                    Func::BlendUnion | Func::BlendIntersect => {
                        let (a, b) = (self.reg(v[0]), self.reg(v[1]));
                        let op = if *f == Func::BlendUnion {
                            Op::BlendUnion
                        } else {
                            Op::BlendIntersect
                        };
                        Val::R(self.emit(Instr::new(op, a, b, 0, 0.0)))
                    }
                    _ => self.hf_blend(*f == Func::HfBlendUnion, &v),
                }
            }
            Expr::Call(f, args) => {
                if args.len() != f.arity() {
                    return Err(CompileError(format!(
                        "{} takes {} argument(s), not {}",
                        f.name(),
                        f.arity(),
                        args.len()
                    )));
                }
                let v = self.expr(&args[0], binds)?;
                match f {
                    Func::Min | Func::Max => {
                        let w = self.expr(&args[1], binds)?;
                        if let (Val::C(a), Val::C(b)) = (v, w) {
                            // min and max of finite values are exact.
                            return Ok(Val::C(if *f == Func::Min {
                                Real::min(&a, &b)
                            } else {
                                Real::max(&a, &b)
                            }));
                        }
                        let (a, b) = (self.reg(v), self.reg(w));
                        let op = if *f == Func::Min { Op::Min } else { Op::Max };
                        Val::R(self.emit(Instr::new(op, a, b, 0, 0.0)))
                    }
                    Func::Sqr => self.powi(v, 2),
                    Func::Tan => {
                        let s = self.unary_folded(Op::Sin, v);
                        let c = self.unary_folded(Op::Cos, v);
                        self.binary(BinOp::Div, s, c)
                    }
                    _ => {
                        let op = match f {
                            Func::Sqrt => Op::Sqrt,
                            Func::Exp => Op::Exp,
                            Func::Ln => Op::Ln,
                            Func::Sin => Op::Sin,
                            Func::Cos => Op::Cos,
                            _ => Op::Abs,
                        };
                        if let Val::C(c) = v {
                            if let Some(r) = fold_unary(op, c) {
                                return Ok(Val::C(r));
                            }
                        }
                        self.unary(op, v)
                    }
                }
            }
            Expr::Bin(op, a, b) => {
                let l = self.expr(a, binds)?;
                let r = self.expr(b, binds)?;
                self.binary(*op, l, r)
            }
        })
    }
}

/// The value of `e` if compilation folds it to a constant (the same rules as
/// [`Tape::compile`]), `binds` holding the constant value, if any, of each binding.
pub(crate) fn folded_const(e: &Expr, binds: &[Option<f64>]) -> Option<f64> {
    match e {
        Expr::Num(c) => Some(*c),
        Expr::Var(_) => None,
        Expr::Ref(i) => binds.get(*i).copied().flatten(),
        Expr::Neg(a) => folded_const(a, binds).map(|c| -c),
        Expr::Pow(a, n) => exact_powi(folded_const(a, binds)?, *n),
        Expr::PowF(..) => None,
        Expr::Call(Func::If, args) => {
            let c = folded_const(args.first()?, binds)?;
            let k = if c.abs() >= EPS { 1 } else { 2 };
            folded_const(args.get(k)?, binds)
        }
        Expr::Call(Func::Not, args) => {
            let c = folded_const(args.first()?, binds)?;
            Some(if c.abs() >= EPS { 0.0 } else { 1.0 })
        }
        Expr::Call(..) if matches!(e, Expr::Call(f, _) if f.arity() > 2 || matches!(f, Func::BlendUnion | Func::BlendIntersect)) => {
            None
        }
        Expr::Call(f, args) => {
            let v = folded_const(args.first()?, binds)?;
            match f {
                Func::Min => Some(Real::min(&v, &folded_const(args.get(1)?, binds)?)),
                Func::Max => Some(Real::max(&v, &folded_const(args.get(1)?, binds)?)),
                Func::Sqr => exact_powi(v, 2),
                Func::Sqrt => fold_unary(Op::Sqrt, v),
                Func::Exp => fold_unary(Op::Exp, v),
                Func::Ln => fold_unary(Op::Ln, v),
                Func::Sin => fold_unary(Op::Sin, v),
                Func::Cos => fold_unary(Op::Cos, v),
                Func::Tan => fold_bin(BinOp::Div, fold_unary(Op::Sin, v)?, fold_unary(Op::Cos, v)?),
                Func::Abs => fold_unary(Op::Abs, v),
                // Handled above.
                _ => None,
            }
        }
        Expr::Bin(op @ (BinOp::And | BinOp::Or), a, b) => {
            // One operand that decides is enough, as in the compiler.
            let (fa, fb) = (folded_const(a, binds), folded_const(b, binds));
            let holds = |v: Option<f64>| v.map(|c| c.abs() >= EPS);
            let decide = *op == BinOp::Or;
            if holds(fa) == Some(decide) || holds(fb) == Some(decide) {
                return Some(if decide { 1.0 } else { 0.0 });
            }
            fold_bin(*op, fa?, fb?)
        }
        Expr::Bin(op, a, b) => fold_bin(*op, folded_const(a, binds)?, folded_const(b, binds)?),
    }
}

/// `a + b` if the `f64` sum is exact and finite.
fn exact_add(a: f64, b: f64) -> Option<f64> {
    let (s, e) = two_sum(a, b);
    (s.is_finite() && e == 0.0).then_some(s)
}

/// `a * b` if the `f64` product is exact and finite. Products in the subnormal range are
/// refused: there the fused error term may itself underflow to 0.
fn exact_mul(a: f64, b: f64) -> Option<f64> {
    let p = a * b;
    if !p.is_finite() {
        return None;
    }
    if p == 0.0 {
        return (a == 0.0 || b == 0.0).then_some(p);
    }
    if p.abs() < f64::MIN_POSITIVE * 2f64.powi(53) {
        return None;
    }
    (a.mul_add(b, -p) == 0.0).then_some(p)
}

fn exact_div(a: f64, b: f64) -> Option<f64> {
    let q = a / b;
    if b == 0.0 || !q.is_finite() {
        return None;
    }
    if q == 0.0 {
        return (a == 0.0).then_some(q);
    }
    (exact_mul(q, b) == Some(a)).then_some(q)
}

fn exact_sqrt(a: f64) -> Option<f64> {
    if a <= 0.0 {
        // The extended square root is exactly 0 there, in every arithmetic.
        return Some(Real::sqrt(&a));
    }
    let r = a.sqrt();
    (exact_mul(r, r) == Some(a)).then_some(r)
}

fn exact_powi(c: f64, n: i32) -> Option<f64> {
    if n == 0 {
        return Some(1.0);
    }
    if n.unsigned_abs() > 4096 {
        // Only hand-built trees get here (the parser caps exponents); not worth folding.
        return None;
    }
    let mut p = c;
    for _ in 1..n.unsigned_abs() {
        p = exact_mul(p, c)?;
    }
    if n < 0 {
        exact_div(1.0, p)
    } else {
        Some(p)
    }
}

fn fold_unary(op: Op, c: f64) -> Option<f64> {
    match op {
        Op::Sqrt => exact_sqrt(c),
        Op::Abs => Some(c.abs()),
        Op::Exp if c == 0.0 => Some(1.0),
        Op::Ln if c == 1.0 => Some(0.0),
        Op::Sin if c == 0.0 => Some(c),
        Op::Cos if c == 0.0 => Some(1.0),
        _ => None,
    }
}

fn fold_bin(op: BinOp, a: f64, b: f64) -> Option<f64> {
    let norm = || exact_sqrt(exact_add(exact_mul(a, a)?, exact_mul(b, b)?)?);
    match op {
        BinOp::Add => exact_add(a, b),
        BinOp::Sub => exact_add(a, -b),
        BinOp::Mul => exact_mul(a, b),
        BinOp::Div => exact_div(a, b),
        BinOp::Intersect => exact_add(exact_add(a, b)?, -norm()?),
        BinOp::Union => exact_add(exact_add(a, b)?, norm()?),
        BinOp::Subtract => exact_add(exact_add(a, -b)?, -norm()?),
        BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge | BinOp::Eq | BinOp::Ne => {
            Some(fold_cmp(op, a, b))
        }
        BinOp::And | BinOp::Or => {
            let (p, q) = (a.abs() >= EPS, b.abs() >= EPS);
            let v = if op == BinOp::And { p && q } else { p || q };
            Some(if v { 1.0 } else { 0.0 })
        }
    }
}

/// A comparison of two constants, computed as the tape computes it at points.
fn fold_cmp(op: BinOp, a: f64, b: f64) -> f64 {
    match op {
        BinOp::Lt => Step::Pos.at(b - a),
        BinOp::Le => Step::NonNeg.at(b - a),
        BinOp::Gt => Step::Pos.at(a - b),
        BinOp::Ge => Step::NonNeg.at(a - b),
        BinOp::Eq => Step::Pos.at(EPS - (a - b).abs()),
        _ => Step::NonNeg.at((a - b).abs() - EPS),
    }
}

thread_local! {
    /// One register file per value type and thread, reused across evaluations.
    static REGISTERS: RefCell<Vec<Box<dyn Any>>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with an empty register file for `R`, reusing this thread's buffer when it
/// is free (a nested or late evaluation just allocates a fresh one).
pub(super) fn with_registers<R: 'static, T>(f: impl FnOnce(&mut Vec<Option<R>>) -> T) -> T {
    let mut f = Some(f);
    let pooled = REGISTERS.try_with(|pool| {
        let Ok(mut pool) = pool.try_borrow_mut() else {
            return None;
        };
        let k = match pool.iter().position(|b| b.is::<Vec<Option<R>>>()) {
            Some(k) => k,
            None => {
                pool.push(Box::new(Vec::<Option<R>>::new()));
                pool.len() - 1
            }
        };
        let regs = pool[k].downcast_mut::<Vec<Option<R>>>()?;
        let out = (f.take()?)(regs);
        regs.clear();
        Some(out)
    });
    match (pooled, f) {
        (Ok(Some(out)), _) => out,
        (_, Some(f)) => f(&mut Vec::new()),
        // `f` ran but its result was lost: impossible, `out` is always `Some` then.
        (_, None) => unreachable!("register pool returned no result after running"),
    }
}

/// Reads operand `k` of `i`: moved out on its last read, cloned otherwise.
#[inline(always)]
fn read<R: Clone>(regs: &mut [Option<R>], i: &Instr, k: u8) -> R {
    let r = i.reg(k as usize) as usize;
    let slot = &mut regs[r];
    let v = if i.last & (1 << k) != 0 {
        slot.take()
    } else {
        slot.clone()
    };
    // The compiler only emits operands defined earlier and read before their last use.
    v.expect("tape invariant: operand register holds a value")
}

impl Tape {
    /// Compiles a syntax tree.
    pub fn compile(p: &Program) -> Result<Tape, CompileError> {
        let mut b = Builder::new();
        let mut binds = Vec::with_capacity(p.bindings.len());
        for bind in &p.bindings {
            let v = b.expr(&bind.expr, &binds)?;
            binds.push(v);
        }
        let out = b.expr(&p.body, &binds)?;
        let out = b.reg(out);
        Ok(Tape::from_instructions(finish(b.ins, out)))
    }

    /// A tape of instructions [`finish`] produced.
    pub(super) fn from_instructions(ins: Vec<Instr>) -> Tape {
        Tape {
            ins: ins.into(),
            spec: Arc::new(OnceLock::new()),
        }
    }

    /// Whether the tape compares or selects ([`Op::Gt0`], [`Op::Ge0`], [`Op::Select`]).
    pub fn has_branches(&self) -> bool {
        self.ins
            .iter()
            .any(|i| matches!(i.op, Op::Gt0 | Op::Ge0 | Op::Select))
    }

    /// Number of instructions.
    pub fn len(&self) -> usize {
        self.ins.len()
    }

    /// Always false: a tape computes at least one value.
    pub fn is_empty(&self) -> bool {
        self.ins.is_empty()
    }

    /// The instructions; the last one's register is the result.
    pub fn instructions(&self) -> &[Instr] {
        &self.ins
    }

    /// Evaluates the formula at `(x, y, z)` in the arithmetic `R`.
    pub fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        // Points take a leaner path: plain `f64` registers on the stack. The type test
        // is resolved at compile time; `R::constant` is the identity on `f64`.
        let point = |v: &R| (v as &dyn Any).downcast_ref::<f64>().copied();
        if let (Some(px), Some(py), Some(pz)) = (point(&x), point(&y), point(&z)) {
            return R::constant(self.eval_f64(px, py, pz));
        }
        with_registers(|regs: &mut Vec<Option<R>>| self.run(regs, x, y, z, |_, _| {}))
    }

    /// Point evaluation with the same `Real` operations as the generic path.
    fn eval_f64(&self, x: f64, y: f64, z: f64) -> f64 {
        const STACK: usize = 64;
        if self.ins.len() <= STACK {
            let mut regs = [0.0; STACK];
            self.run_f64(&mut regs, x, y, z)
        } else {
            self.run_f64(&mut vec![0.0; self.ins.len()], x, y, z)
        }
    }

    fn run_f64(&self, regs: &mut [f64], x: f64, y: f64, z: f64) -> f64 {
        for (k, i) in self.ins.iter().enumerate() {
            // Unused operand fields are 0: reading register 0 then is harmless.
            let a = regs[i.a as usize];
            let b = regs[i.b as usize];
            let e = regs[i.e as usize];
            regs[k] = match i.op {
                Op::X => x,
                Op::Y => y,
                Op::Z => z,
                Op::Const => i.c,
                Op::Neg => -a,
                Op::Sqr => Real::sqr(&a),
                Op::Powi => Real::powi(&a, i.n),
                Op::Sqrt => Real::sqrt(&a),
                Op::Exp => Real::exp(&a),
                Op::Ln => Real::ln(&a),
                Op::Sin => Real::sin(&a),
                Op::Cos => Real::cos(&a),
                Op::Abs => Real::abs(&a),
                Op::AddC => a + i.c,
                Op::SubC => a - i.c,
                Op::RSubC => Real::rsub(a, i.c),
                Op::MulC => a * i.c,
                Op::DivC => a / i.c,
                Op::RDivC => Real::rdiv(a, i.c),
                Op::Add => a + b,
                Op::Sub => a - b,
                Op::Mul => a * b,
                Op::Div => a / b,
                Op::Min => Real::min(&a, &b),
                Op::Max => Real::max(&a, &b),
                Op::Intersect => rfunc::intersect(a, b),
                Op::Union => rfunc::union(a, b),
                Op::Subtract => rfunc::subtract(a, b),
                Op::BlendUnion => rfunc::blend_union(a, b),
                Op::BlendIntersect => rfunc::blend_intersect(a, b),
                Op::Gt0 => Step::Pos.at(a),
                Op::Ge0 => Step::NonNeg.at(a),
                Op::Select => select(&a, b, e),
            };
        }
        regs[self.ins.len() - 1]
    }

    /// The generic interpreter; `seen(k, v)` is told each register's value as it is
    /// computed (a no-op for plain evaluation, compiled away).
    pub(super) fn run<R: Real>(
        &self,
        regs: &mut Vec<Option<R>>,
        x: R,
        y: R,
        z: R,
        mut seen: impl FnMut(usize, &R),
    ) -> R {
        regs.clear();
        regs.reserve(self.ins.len());
        for (k, i) in self.ins.iter().enumerate() {
            let v = match i.op {
                Op::X => x.clone(),
                Op::Y => y.clone(),
                Op::Z => z.clone(),
                Op::Const => R::constant(i.c),
                Op::Neg => -read(regs, i, 0),
                Op::Sqr => read(regs, i, 0).sqr(),
                Op::Powi => read(regs, i, 0).powi(i.n),
                Op::Sqrt => read(regs, i, 0).sqrt(),
                Op::Exp => read(regs, i, 0).exp(),
                Op::Ln => read(regs, i, 0).ln(),
                Op::Sin => read(regs, i, 0).sin(),
                Op::Cos => read(regs, i, 0).cos(),
                Op::Abs => read(regs, i, 0).abs(),
                Op::AddC => read(regs, i, 0) + i.c,
                Op::SubC => read(regs, i, 0) - i.c,
                Op::RSubC => read(regs, i, 0).rsub(i.c),
                Op::MulC => read(regs, i, 0) * i.c,
                Op::DivC => read(regs, i, 0) / i.c,
                Op::RDivC => read(regs, i, 0).rdiv(i.c),
                Op::Add => read(regs, i, 0) + read(regs, i, 1),
                Op::Sub => read(regs, i, 0) - read(regs, i, 1),
                Op::Mul => read(regs, i, 0) * read(regs, i, 1),
                Op::Div => read(regs, i, 0) / read(regs, i, 1),
                Op::Min => read(regs, i, 0).min(&read(regs, i, 1)),
                Op::Max => read(regs, i, 0).max(&read(regs, i, 1)),
                Op::Intersect => rfunc::intersect(read(regs, i, 0), read(regs, i, 1)),
                Op::Union => rfunc::union(read(regs, i, 0), read(regs, i, 1)),
                Op::Subtract => rfunc::subtract(read(regs, i, 0), read(regs, i, 1)),
                Op::BlendUnion => rfunc::blend_union(read(regs, i, 0), read(regs, i, 1)),
                Op::BlendIntersect => rfunc::blend_intersect(read(regs, i, 0), read(regs, i, 1)),
                Op::Gt0 => step(Step::Pos, &read(regs, i, 0)),
                Op::Ge0 => step(Step::NonNeg, &read(regs, i, 0)),
                Op::Select => {
                    let c = read(regs, i, 0);
                    select(&c, read(regs, i, 1), read(regs, i, 2))
                }
            };
            seen(k, &v);
            regs.push(Some(v));
        }
        let out = regs.pop().flatten();
        out.expect("tape invariant: a tape has at least one instruction")
    }

    /// The tape as a formula: registers read more than once become bindings `tN = ...;`.
    /// Parsing it gives a tape with the same values (bit for bit at points).
    pub fn to_program(&self) -> Program {
        let mut uses = vec![0usize; self.ins.len()];
        for i in self.ins.iter() {
            for &k in i.operands() {
                uses[i.reg(k) as usize] += 1;
            }
        }
        let mut bindings = Vec::new();
        let mut exprs: Vec<Option<Expr>> = vec![None; self.ins.len()];
        let get = |exprs: &mut Vec<Option<Expr>>, r: u32| -> Expr {
            let r = r as usize;
            if uses[r] > 1 || matches!(self.ins[r].op, Op::X | Op::Y | Op::Z | Op::Const) {
                exprs[r].clone().unwrap_or(Expr::Num(f64::NAN))
            } else {
                exprs[r].take().unwrap_or(Expr::Num(f64::NAN))
            }
        };
        let last = self.ins.len().saturating_sub(1);
        // Depth of each inlined expression: deep ones become bindings too, so that the
        // text stays within the parser's nesting limits.
        let mut depth = vec![1usize; self.ins.len()];
        for (r, i) in self.ins.iter().enumerate() {
            let d = 1 + i
                .operands()
                .iter()
                .map(|&k| depth[i.reg(k) as usize])
                .max()
                .unwrap_or(0);
            let a = if i.op.arity() >= 1 {
                get(&mut exprs, i.a)
            } else {
                Expr::Num(0.0)
            };
            let b = if i.op.arity() >= 2 {
                get(&mut exprs, i.b)
            } else {
                Expr::Num(0.0)
            };
            let e3 = if i.op.arity() == 3 {
                get(&mut exprs, i.e)
            } else {
                Expr::Num(0.0)
            };
            let call = |f: Func, args: Vec<Expr>| Expr::Call(f, args);
            let e = match i.op {
                Op::X => Expr::Var(Var::X),
                Op::Y => Expr::Var(Var::Y),
                Op::Z => Expr::Var(Var::Z),
                Op::Const => Expr::Num(i.c),
                Op::Neg => Expr::neg(a),
                Op::Sqr => Expr::pow(a, 2),
                Op::Powi => Expr::pow(a, i.n),
                Op::Sqrt => call(Func::Sqrt, vec![a]),
                Op::Exp => call(Func::Exp, vec![a]),
                Op::Ln => call(Func::Ln, vec![a]),
                Op::Sin => call(Func::Sin, vec![a]),
                Op::Cos => call(Func::Cos, vec![a]),
                Op::Abs => call(Func::Abs, vec![a]),
                Op::AddC => Expr::bin(BinOp::Add, a, Expr::Num(i.c)),
                Op::SubC => Expr::bin(BinOp::Sub, a, Expr::Num(i.c)),
                Op::RSubC => Expr::bin(BinOp::Sub, Expr::Num(i.c), a),
                Op::MulC => Expr::bin(BinOp::Mul, a, Expr::Num(i.c)),
                Op::DivC => Expr::bin(BinOp::Div, a, Expr::Num(i.c)),
                Op::RDivC => Expr::bin(BinOp::Div, Expr::Num(i.c), a),
                Op::Add => Expr::bin(BinOp::Add, a, b),
                Op::Sub => Expr::bin(BinOp::Sub, a, b),
                Op::Mul => Expr::bin(BinOp::Mul, a, b),
                Op::Div => Expr::bin(BinOp::Div, a, b),
                Op::Min => call(Func::Min, vec![a, b]),
                Op::Max => call(Func::Max, vec![a, b]),
                Op::Intersect => Expr::bin(BinOp::Intersect, a, b),
                Op::Union => Expr::bin(BinOp::Union, a, b),
                Op::Subtract => Expr::bin(BinOp::Subtract, a, b),
                Op::BlendUnion => call(Func::BlendUnion, vec![a, b]),
                Op::BlendIntersect => call(Func::BlendIntersect, vec![a, b]),
                Op::Gt0 => Expr::bin(BinOp::Gt, a, Expr::Num(0.0)),
                Op::Ge0 => Expr::bin(BinOp::Ge, a, Expr::Num(0.0)),
                Op::Select => call(Func::If, vec![a, b, e3]),
            };
            let shared = uses[r] > 1 || d > INLINE_DEPTH;
            let e = if shared && r != last && !matches!(e, Expr::Var(_) | Expr::Num(_)) {
                bindings.push(super::ast::Binding {
                    name: format!("t{r}"),
                    expr: e,
                });
                Expr::Ref(bindings.len() - 1)
            } else {
                depth[r] = d;
                e
            };
            exprs[r] = Some(e);
        }
        let body = exprs
            .get_mut(last)
            .and_then(Option::take)
            .unwrap_or(Expr::Num(f64::NAN));
        Program { bindings, body }
    }

    /// The formula text of [`Tape::to_program`].
    pub fn to_formula(&self) -> String {
        self.to_program().to_string()
    }
}

/// Deepest expression [`Tape::to_program`] writes inline (far below the parser's limit).
const INLINE_DEPTH: usize = 64;

/// Drops instructions the result does not depend on, renumbers, and marks last reads.
pub(super) fn finish(ins: Vec<Instr>, out: u32) -> Vec<Instr> {
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

impl fmt::Display for Tape {
    /// One instruction per line, `rN = op operands`; `!` marks a moved (last) read.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (r, i) in self.ins.iter().enumerate() {
            writeln!(f, "r{r} = {i}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `f64` fast path and the generic interpreter agree bit for bit on every op.
    #[test]
    fn point_path_matches_generic_path() {
        let src = "a = x^2 - y; b = sqrt(abs(a)) + exp(-y) / 3 - ln(z) * sin(x) + cos(y);
                   c = min(a, b) * max(x, z) - 1 / x + 2 / (y - 5) - (z - 0.1) + x^-3 * y^5 + x / y + (3 - z) * (z + 2) * sin(1) + 4 * z;
                   d = blend_union(a, y) - blend_intersect(b, z) + if(x < y, c, z) + (y >= 0);
                   (a & b) | (c \\ x) & -z + d";
        let t = crate::models::formula::parse(src).unwrap();
        let ops: std::collections::HashSet<Op> = t.instructions().iter().map(|i| i.op).collect();
        assert_eq!(ops.len(), 33, "every op is exercised:\n{t}");
        for &(x, y, z) in &[
            (0.3, -0.7, 1.1),
            (-1.9, 0.25, 0.4),
            (2.0, 2.0, -1.0),
            (0.0, 0.0, 0.0),
        ] {
            let fast = t.eval(x, y, z);
            let generic =
                with_registers(|regs: &mut Vec<Option<f64>>| t.run(regs, x, y, z, |_, _| {}));
            assert!(
                fast.to_bits() == generic.to_bits() || (fast.is_nan() && generic.is_nan()),
                "{fast} vs {generic} at ({x}, {y}, {z})"
            );
        }
    }
}
