//! Recording: a model written in generic Rust over [`Real`] becomes a tape by being
//! evaluated once over [`Recorder`], a `Real` whose operations append instructions
//! instead of computing. The recording is the model's own code, operation by operation
//! (nothing is shared or folded), so evaluating the tape over any arithmetic performs
//! the operations the model performs.
//!
//! Code that looks at the values it computes ([`Real::known`], procedural noise that
//! picks a lattice cell from a point) cannot be recorded: a [`Recorder`] says nothing
//! about itself, so such code sees an unknown value. [`Real::step`] and
//! [`Real::select`] record as [`Op::Gt0`], [`Op::Ge0`] and [`Op::Select`].

use crate::builder::Builder;
use crate::instr::{Instr, Op};
use crate::tape::Tape;
use crate::Val;
use arith_core::branch::Step;
use arith_core::Real;
use core::ops::{Add, Div, Mul, Neg, Sub};
use std::cell::RefCell;

thread_local! {
    /// The recording under way on this thread.
    static RECORDING: RefCell<Builder> = RefCell::new(Builder::new());
}

/// A value being recorded: the register of the instruction that computes it. Only
/// meaningful inside the [`Tape::record`] call that made it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Recorder(pub u32);

fn push(op: Op, a: u32, b: u32, n: i32, c: f64) -> Recorder {
    Recorder(RECORDING.with(|r| r.borrow_mut().push(Instr::new(op, a, b, n, c))))
}

impl Tape {
    /// Records `f` over the inputs `x`, `y`, `z` (see the module doc). Recordings may
    /// nest: an inner one runs on a builder of its own.
    ///
    /// ```
    /// use arith_core::Real;
    /// use model_ir::{Op, Tape};
    /// fn torus<R: Real>(x: R, y: R, z: R) -> R {
    ///     let ring = (x.sqr() + z.sqr()).sqrt().rsub(1.0);
    ///     (ring.sqr() + y.sqr()).rsub(0.09)
    /// }
    /// let t = Tape::record(torus);
    /// assert_eq!(t.eval(1.0_f64, 0.0, 0.0), torus(1.0_f64, 0.0, 0.0));
    /// assert!(t.instructions().iter().any(|i| i.op == Op::Sqrt));
    /// ```
    pub fn record(f: impl FnOnce(Recorder, Recorder, Recorder) -> Recorder) -> Tape {
        let outer = RECORDING.with(|r| std::mem::take(&mut *r.borrow_mut()));
        let (x, y, z) = (
            push(Op::X, 0, 0, 0, 0.0),
            push(Op::Y, 0, 0, 0, 0.0),
            push(Op::Z, 0, 0, 0, 0.0),
        );
        let out = f(x, y, z);
        let b = RECORDING.with(|r| std::mem::replace(&mut *r.borrow_mut(), outer));
        b.finish(Val::R(out.0))
    }
}

macro_rules! binop {
    ($tr:ident, $m:ident, $op:ident, $opc:ident) => {
        impl $tr for Recorder {
            type Output = Recorder;
            fn $m(self, rhs: Recorder) -> Recorder {
                push(Op::$op, self.0, rhs.0, 0, 0.0)
            }
        }
        impl $tr<f64> for Recorder {
            type Output = Recorder;
            fn $m(self, rhs: f64) -> Recorder {
                push(Op::$opc, self.0, 0, 0, rhs)
            }
        }
    };
}

binop!(Add, add, Add, AddC);
binop!(Sub, sub, Sub, SubC);
binop!(Mul, mul, Mul, MulC);
binop!(Div, div, Div, DivC);

impl Neg for Recorder {
    type Output = Recorder;
    fn neg(self) -> Recorder {
        push(Op::Neg, self.0, 0, 0, 0.0)
    }
}

arith_core::impl_f64_lhs_ops!(Recorder);

impl Recorder {
    fn unary(&self, op: Op) -> Recorder {
        push(op, self.0, 0, 0, 0.0)
    }
    fn binary(&self, op: Op, o: &Recorder) -> Recorder {
        push(op, self.0, o.0, 0, 0.0)
    }
}

impl Real for Recorder {
    fn constant(c: f64) -> Self {
        push(Op::Const, 0, 0, 0, c)
    }
    fn sqr(&self) -> Self {
        self.unary(Op::Sqr)
    }
    fn powi(&self, n: i32) -> Self {
        push(Op::Powi, self.0, 0, n, 0.0)
    }
    fn sqrt(&self) -> Self {
        self.unary(Op::Sqrt)
    }
    fn hypot(&self, other: &Self) -> Self {
        self.binary(Op::Hypot, other)
    }
    fn recip(&self) -> Self {
        self.unary(Op::Recip)
    }
    fn exp(&self) -> Self {
        self.unary(Op::Exp)
    }
    fn ln(&self) -> Self {
        self.unary(Op::Ln)
    }
    fn sin(&self) -> Self {
        self.unary(Op::Sin)
    }
    fn cos(&self) -> Self {
        self.unary(Op::Cos)
    }
    fn abs(&self) -> Self {
        self.unary(Op::Abs)
    }
    fn min(&self, other: &Self) -> Self {
        self.binary(Op::Min, other)
    }
    fn max(&self, other: &Self) -> Self {
        self.binary(Op::Max, other)
    }
    fn rsub(self, c: f64) -> Self {
        push(Op::RSubC, self.0, 0, 0, c)
    }
    fn rdiv(self, c: f64) -> Self {
        push(Op::RDivC, self.0, 0, 0, c)
    }
    fn step(&self, s: Step) -> Self {
        self.unary(match s {
            Step::Pos => Op::Gt0,
            Step::NonNeg => Op::Ge0,
        })
    }
    fn select(&self, t: Self, e: Self) -> Self {
        let mut i = Instr::new(Op::Select, self.0, t.0, 0, 0.0);
        i.e = e.0;
        Recorder(RECORDING.with(|r| r.borrow_mut().push(i)))
    }
}
