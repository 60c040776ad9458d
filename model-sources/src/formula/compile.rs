//! Compiling formulas into the model IR: a syntax tree ([`Program`]) walked into a
//! [`Builder`] ([`compile`]), the constant a subexpression folds to ([`folded_const`],
//! which the parser uses to refuse `1/0`), and back from a tape to a formula
//! ([`ToFormula`]).
//!
//! Compilation folds constant subexpressions **only when the `f64` result is exact**
//! ([`model_ir::fold`]): a folded constant then equals the real value, so range
//! evaluation stays sound. Identical subexpressions (and every let-bound value) are
//! computed once (hash-consing); unused bindings are dropped.

use super::ast::{BinOp, Binding, Expr, Func, Program, Var};
use arith_core::Real;
use model_ir::fold::{exact_powi, fold_bin, fold_unary, Bin, EPS};
use model_ir::{Builder, Instr, Op, Tape, Val};
use std::fmt;

/// Why a hand-built [`Program`] cannot be compiled (the parser never produces one).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CompileError(pub String);

impl fmt::Display for CompileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for CompileError {}

/// Compiles a syntax tree.
pub fn compile(p: &Program) -> Result<Tape, CompileError> {
    let mut b = Builder::new();
    let mut binds = Vec::with_capacity(p.bindings.len());
    for bind in &p.bindings {
        let v = expr(&mut b, &bind.expr, &binds)?;
        binds.push(v);
    }
    let out = expr(&mut b, &p.body, &binds)?;
    Ok(b.finish(out))
}

/// `Ok` when `f` is called with as many arguments as it takes.
fn check_arity(f: Func, args: &[Expr]) -> Result<(), CompileError> {
    if args.len() == f.arity() {
        return Ok(());
    }
    Err(CompileError(format!(
        "{} takes {} argument(s), not {}",
        f.name(),
        f.arity(),
        args.len()
    )))
}

/// The builder's operator for a formula's.
fn bin(op: BinOp) -> Bin {
    match op {
        BinOp::Add => Bin::Add,
        BinOp::Sub => Bin::Sub,
        BinOp::Mul => Bin::Mul,
        BinOp::Div => Bin::Div,
        BinOp::Intersect => Bin::Intersect,
        BinOp::Union => Bin::Union,
        BinOp::Subtract => Bin::Subtract,
        BinOp::Lt => Bin::Lt,
        BinOp::Le => Bin::Le,
        BinOp::Gt => Bin::Gt,
        BinOp::Ge => Bin::Ge,
        BinOp::Eq => Bin::Eq,
        BinOp::Ne => Bin::Ne,
        BinOp::And => Bin::And,
        BinOp::Or => Bin::Or,
    }
}

fn expr(bd: &mut Builder, e: &Expr, binds: &[Val]) -> Result<Val, CompileError> {
    Ok(match e {
        Expr::Num(c) => Val::C(*c),
        Expr::Var(v) => {
            let op = match v {
                Var::X => Op::X,
                Var::Y => Op::Y,
                Var::Z => Op::Z,
            };
            Val::R(bd.emit(Instr::new(op, 0, 0, 0, 0.0)))
        }
        Expr::Ref(i) => *binds
            .get(*i)
            .ok_or_else(|| CompileError(format!("binding #{i} used before it is defined")))?,
        Expr::Neg(a) => match expr(bd, a, binds)? {
            Val::C(c) => Val::C(-c),
            v => bd.unary(Op::Neg, v),
        },
        Expr::Pow(a, n) => {
            let v = expr(bd, a, binds)?;
            bd.powi(v, *n)
        }
        Expr::PowF(a, c) => {
            let v = expr(bd, a, binds)?;
            let l = bd.unary_folded(Op::Ln, v);
            let m = bd.binary(Bin::Mul, l, Val::C(*c));
            bd.unary_folded(Op::Exp, m)
        }
        Expr::Call(f, args)
            if f.arity() > 2
                || matches!(f, Func::Not | Func::BlendUnion | Func::BlendIntersect) =>
        {
            check_arity(*f, args)?;
            let mut v = Vec::with_capacity(args.len());
            for a in args {
                v.push(expr(bd, a, binds)?);
            }
            match f {
                Func::If => bd.select(v[0], v[1], v[2]),
                Func::Not => {
                    let t = bd.truth(v[0]);
                    bd.binary(Bin::Sub, Val::C(1.0), t)
                }
                Func::BlendUnion | Func::BlendIntersect => {
                    let (a, b) = (bd.reg(v[0]), bd.reg(v[1]));
                    let op = if *f == Func::BlendUnion {
                        Op::BlendUnion
                    } else {
                        Op::BlendIntersect
                    };
                    Val::R(bd.emit(Instr::new(op, a, b, 0, 0.0)))
                }
                _ => bd.hf_blend(*f == Func::HfBlendUnion, [v[0], v[1], v[2], v[3], v[4]]),
            }
        }
        Expr::Call(f, args) => {
            check_arity(*f, args)?;
            let v = expr(bd, &args[0], binds)?;
            match f {
                Func::Min | Func::Max => {
                    let w = expr(bd, &args[1], binds)?;
                    if let (Val::C(a), Val::C(b)) = (v, w) {
                        // min and max of finite values are exact.
                        return Ok(Val::C(if *f == Func::Min {
                            Real::min(&a, &b)
                        } else {
                            Real::max(&a, &b)
                        }));
                    }
                    let (a, b) = (bd.reg(v), bd.reg(w));
                    let op = if *f == Func::Min { Op::Min } else { Op::Max };
                    Val::R(bd.emit(Instr::new(op, a, b, 0, 0.0)))
                }
                Func::Sqr => bd.powi(v, 2),
                Func::Tan => {
                    let s = bd.unary_folded(Op::Sin, v);
                    let c = bd.unary_folded(Op::Cos, v);
                    bd.binary(Bin::Div, s, c)
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
                    bd.unary(op, v)
                }
            }
        }
        Expr::Bin(op, a, b) => {
            let l = expr(bd, a, binds)?;
            let r = expr(bd, b, binds)?;
            bd.binary(bin(*op), l, r)
        }
    })
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
                Func::Tan => fold_bin(Bin::Div, fold_unary(Op::Sin, v)?, fold_unary(Op::Cos, v)?),
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
            fold_bin(bin(*op), fa?, fb?)
        }
        Expr::Bin(op, a, b) => fold_bin(bin(*op), folded_const(a, binds)?, folded_const(b, binds)?),
    }
}

/// A tape back as a formula.
pub trait ToFormula {
    /// The tape as a formula: registers read more than once become bindings `tN = ...;`.
    /// Parsing it gives a tape with the same values (bit for bit at points).
    fn to_program(&self) -> Program;
    /// The formula text of [`ToFormula::to_program`].
    fn to_formula(&self) -> String;
}

impl ToFormula for Tape {
    /// The tape as a formula: registers read more than once become bindings `tN = ...;`.
    /// Parsing it gives a tape with the same values (bit for bit at points).
    fn to_program(&self) -> Program {
        let mut uses = vec![0usize; self.instructions().len()];
        for i in self.instructions().iter() {
            for &k in i.operands() {
                uses[i.reg(k) as usize] += 1;
            }
        }
        let mut bindings = Vec::new();
        let mut exprs: Vec<Option<Expr>> = vec![None; self.instructions().len()];
        let get = |exprs: &mut Vec<Option<Expr>>, r: u32| -> Expr {
            let r = r as usize;
            if uses[r] > 1 || matches!(self.instructions()[r].op, Op::X | Op::Y | Op::Z | Op::Const)
            {
                exprs[r].clone().unwrap_or(Expr::Num(f64::NAN))
            } else {
                exprs[r].take().unwrap_or(Expr::Num(f64::NAN))
            }
        };
        let last = self.instructions().len().saturating_sub(1);
        // Depth of each inlined expression: deep ones become bindings too, so that the
        // text stays within the parser's nesting limits.
        let mut depth = vec![1usize; self.instructions().len()];
        for (r, i) in self.instructions().iter().enumerate() {
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
                Op::Recip => Expr::bin(BinOp::Div, Expr::Num(1.0), a),
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
                Op::Hypot => call(
                    Func::Sqrt,
                    vec![Expr::bin(BinOp::Add, Expr::pow(a, 2), Expr::pow(b, 2))],
                ),
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
                bindings.push(Binding {
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
    fn to_formula(&self) -> String {
        self.to_program().to_string()
    }
}

/// Deepest expression [`ToFormula::to_program`] writes inline (far below the parser's limit).
const INLINE_DEPTH: usize = 64;
