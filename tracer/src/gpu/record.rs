//! Models as GPU programs: a formula's tape converts operation by operation; a model
//! written in generic Rust over [`Real`] is recorded by evaluating it once over
//! [`Recorder`], a `Real` whose operations append to a [`Program`] instead of computing.
//! The recording is the model's own code, so the GPU evaluates the operations the CPU
//! arithmetics do, except that the R-functions become single operations, which `f32`
//! evaluates without the cancellation of their written-out sum.

use crate::models::formula::{Op as TOp, Tape};
use crate::models::{AnyShape, Model};
use crate::shape::Shape;
use arith_core::{rfunc, Real};
use core::ops::{Add, Div, Mul, Neg, Sub};
use std::cell::RefCell;
use tracer_gpu::{Op, Program};

thread_local! {
    static PROGRAM: RefCell<Program> = RefCell::new(Program::default());
}

fn push(op: Op) -> Recorder {
    Recorder(PROGRAM.with(|p| p.borrow_mut().push(op)))
}

/// A value being recorded: the register of the operation that computes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Recorder(pub u32);

/// Records `f` over the inputs `x`, `y`, `z` into a program (on this thread), with the
/// R-functions it writes out fused ([`Program::fuse_rfunctions`]).
pub fn record(f: impl FnOnce(Recorder, Recorder, Recorder) -> Recorder) -> Program {
    PROGRAM.with(|p| *p.borrow_mut() = Program::default());
    let (x, y, z) = (push(Op::X), push(Op::Y), push(Op::Z));
    let out = f(x, y, z);
    let mut p = PROGRAM.with(|p| std::mem::take(&mut *p.borrow_mut()));
    if out.0 as usize + 1 != p.ops.len() {
        // The result is an earlier value (an input, say): copy it to the end.
        p.push(Op::AddC(out.0, 0.0));
    }
    p.fuse_rfunctions();
    p
}

/// The program of `model`: its tape converted, or its generic code recorded. Errors for
/// models whose code looks at the type of its values (procedural noise), which no
/// program can express.
pub fn program_of(model: &Model) -> Result<Program, String> {
    match &model.shape {
        AnyShape::Expr(t) => Ok(from_tape(t)),
        s if !s.packs() => Err(format!(
            "model '{}' uses procedural noise, which the GPU renderer does not support",
            model.name
        )),
        s => Ok(record(|x, y, z| s.eval(x, y, z))),
    }
}

/// A formula's tape as a program, recorded operation by operation (the blends through
/// [`arith_core::rfunc`], as the CPU evaluates them).
pub fn from_tape(t: &Tape) -> Program {
    record(|x, y, z| {
        // Tape register k -> its recorded value.
        let mut reg: Vec<Recorder> = Vec::with_capacity(t.len());
        for i in t.instructions() {
            let at = |k: u32| reg.get(k as usize).copied().unwrap_or(x);
            let (ra, rb, re) = (at(i.a), at(i.b), at(i.e));
            let (a, b) = (ra.0, rb.0);
            let r = match i.op {
                TOp::X => x,
                TOp::Y => y,
                TOp::Z => z,
                TOp::Const => push(Op::Const(i.c)),
                TOp::Neg => push(Op::Neg(a)),
                TOp::Sqr => push(Op::Sqr(a)),
                TOp::Powi => push(Op::Powi(a, i.n)),
                TOp::Sqrt => push(Op::Sqrt(a)),
                TOp::Exp => push(Op::Exp(a)),
                TOp::Ln => push(Op::Ln(a)),
                TOp::Sin => push(Op::Sin(a)),
                TOp::Cos => push(Op::Cos(a)),
                TOp::Abs => push(Op::Abs(a)),
                TOp::AddC => push(Op::AddC(a, i.c)),
                TOp::SubC => push(Op::AddC(a, -i.c)),
                TOp::RSubC => push(Op::RSubC(a, i.c)),
                TOp::MulC => push(Op::MulC(a, i.c)),
                TOp::DivC => push(Op::DivC(a, i.c)),
                TOp::RDivC => push(Op::RDivC(a, i.c)),
                TOp::Add => push(Op::Add(a, b)),
                TOp::Sub => push(Op::Sub(a, b)),
                TOp::Mul => push(Op::Mul(a, b)),
                TOp::Div => push(Op::Div(a, b)),
                TOp::Min => push(Op::Min(a, b)),
                TOp::Max => push(Op::Max(a, b)),
                TOp::Union => push(Op::RUnion(a, b)),
                TOp::Intersect => push(Op::RIntersect(a, b)),
                TOp::Subtract => push(Op::RSubtract(a, b)),
                TOp::BlendUnion => rfunc::blend_union(ra, rb),
                TOp::BlendIntersect => rfunc::blend_intersect(ra, rb),
                TOp::Gt0 => push(Op::Gt0(a)),
                TOp::Ge0 => push(Op::Ge0(a)),
                TOp::Select => push(Op::Select(a, b, re.0)),
            };
            reg.push(r);
        }
        reg.last().copied().unwrap_or(x)
    })
}

macro_rules! binop {
    ($tr:ident, $m:ident, $op:ident, $opc:ident) => {
        impl $tr for Recorder {
            type Output = Recorder;
            fn $m(self, rhs: Recorder) -> Recorder {
                push(Op::$op(self.0, rhs.0))
            }
        }
        impl $tr<f64> for Recorder {
            type Output = Recorder;
            fn $m(self, rhs: f64) -> Recorder {
                push($opc(self.0, rhs))
            }
        }
    };
}

#[allow(non_snake_case)]
fn AddF(a: u32, c: f64) -> Op {
    Op::AddC(a, c)
}
#[allow(non_snake_case)]
fn SubF(a: u32, c: f64) -> Op {
    Op::AddC(a, -c)
}
#[allow(non_snake_case)]
fn MulF(a: u32, c: f64) -> Op {
    Op::MulC(a, c)
}
#[allow(non_snake_case)]
fn DivF(a: u32, c: f64) -> Op {
    Op::DivC(a, c)
}

binop!(Add, add, Add, AddF);
binop!(Sub, sub, Sub, SubF);
binop!(Mul, mul, Mul, MulF);
binop!(Div, div, Div, DivF);

impl Neg for Recorder {
    type Output = Recorder;
    fn neg(self) -> Recorder {
        push(Op::Neg(self.0))
    }
}

arith_core::impl_f64_lhs_ops!(Recorder);

impl Real for Recorder {
    fn constant(c: f64) -> Self {
        push(Op::Const(c))
    }
    fn sqr(&self) -> Self {
        push(Op::Sqr(self.0))
    }
    fn powi(&self, n: i32) -> Self {
        push(Op::Powi(self.0, n))
    }
    fn sqrt(&self) -> Self {
        push(Op::Sqrt(self.0))
    }
    fn hypot(&self, other: &Self) -> Self {
        push(Op::Hypot(self.0, other.0))
    }
    fn recip(&self) -> Self {
        push(Op::Recip(self.0))
    }
    fn exp(&self) -> Self {
        push(Op::Exp(self.0))
    }
    fn ln(&self) -> Self {
        push(Op::Ln(self.0))
    }
    fn sin(&self) -> Self {
        push(Op::Sin(self.0))
    }
    fn cos(&self) -> Self {
        push(Op::Cos(self.0))
    }
    fn abs(&self) -> Self {
        push(Op::Abs(self.0))
    }
    fn min(&self, other: &Self) -> Self {
        push(Op::Min(self.0, other.0))
    }
    fn max(&self, other: &Self) -> Self {
        push(Op::Max(self.0, other.0))
    }
    fn rsub(self, c: f64) -> Self {
        push(Op::RSubC(self.0, c))
    }
    fn rdiv(self, c: f64) -> Self {
        push(Op::RDivC(self.0, c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A recording computes what the model computes, at points.
    #[test]
    fn recordings_match_the_models_at_points() {
        for m in crate::models::all() {
            let Ok(p) = program_of(&m) else {
                assert!(!m.shape.packs(), "{} failed to record", m.name);
                continue;
            };
            p.check().unwrap();
            for &(x, y, z) in &[(0.3, -0.2, 0.1), (1.1, 0.7, -0.4), (-0.9, 0.05, 0.6)] {
                let a = p.eval_f64(x, y, z);
                let b = m.shape.eval(x, y, z);
                assert!(
                    (a - b).abs() <= 1e-9 * (1.0 + b.abs()) || (a.is_nan() && b.is_nan()),
                    "{}: {a} vs {b}",
                    m.name
                );
            }
        }
        for src in [
            "(x^2 + y^2 - 1) & (z - x / 3) | 2 - y",
            "blend_union(1 - x^2 - y^2, z - 0.5) - blend_intersect(x - y, 0.3 - z) \\ x",
        ] {
            let t = crate::models::formula::parse(src).unwrap();
            let p = from_tape(&t);
            p.check().unwrap();
            for &(x, y, z) in &[(0.2, 0.4, -0.3), (-1.5, 0.1, 2.0), (0.0, 0.0, 0.0)] {
                let (a, b) = (p.eval_f64(x, y, z), t.eval(x, y, z));
                assert!((a - b).abs() < 1e-12 * (1.0 + b.abs()), "{src}: {a} vs {b}");
            }
        }
    }
}
