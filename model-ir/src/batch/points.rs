//! The point kernel: a tape over eight-lane blocks of `f64` points. Each instruction
//! runs as lane instructions over every block of the batch (plain IEEE operations,
//! bit for bit the scalar `f64` evaluation's, whose operations `arith_core::Real`
//! for `f64` fixes). `exp`, `ln`, `sin` and `cos` are the lanes' functions
//! ([`arith_core::lanes::exp`] and the others), which `f64`'s `Real` computes alike
//! within their domains; lanes outside a domain (rare: `|x| > 700` for `exp`, zero,
//! subnormal, infinite or NaN for `ln`, `|x| > 10^5` for `sin` and `cos`), `powi` and
//! the R-functions go lane by lane through the scalar operation.

use super::parts::{PartOps, Step};
use crate::eval::apply;
use crate::instr::{Instr, Op};
use arith_core::lanes::{cos, exp, ln, sin, F64x8, Isa, EXP_MAX_ARG, LANES, TRIG_MAX_ARG};

/// The point kernel's values ([`super::parts`]): one block per register and block
/// index.
pub(crate) struct Points;

/// `f64`'s [`Real::min`] per lane: equal values give the or of their bits (a set sign
/// wins), otherwise `f64::min` (a NaN operand gives the other one).
#[inline(always)]
pub(super) fn real_min<I: Isa>(s: I, a: I::V, b: I::V) -> I::V {
    let m = s.select(s.unord(b, b), a, s.min(a, b));
    s.select(s.eq(a, b), s.or_bits(a, b), m)
}

/// `f64`'s [`Real::max`] per lane (equal values: the and of their bits).
#[inline(always)]
pub(super) fn real_max<I: Isa>(s: I, a: I::V, b: I::V) -> I::V {
    let m = s.select(s.unord(b, b), a, s.max(a, b));
    s.select(s.eq(a, b), s.and_bits(a, b), m)
}

/// `f64`'s [`Real::sqrt`] per lane: the root of `x` where `x > 0`, else of `+0`.
#[inline(always)]
pub(super) fn real_sqrt<I: Isa>(s: I, a: I::V) -> I::V {
    let zero = s.splat(0.0);
    s.sqrt(s.select(s.lt(zero, a), a, zero))
}

/// The lanes of `out` not in `inside` recomputed through the scalar operation of `i`
/// on `x` (the kernels' rare lanes outside a function's domain).
#[cold]
#[inline(never)]
fn redo(i: &Instr, inside: u8, x: &F64x8, out: &mut F64x8) {
    for l in 0..LANES {
        if inside & (1 << l) == 0 {
            out.0[l] = apply(i, x.0[l], x.0[l], x.0[l]);
        }
    }
}

/// Which lanes of `x` lie in the proven domain of `op`'s lane function.
#[inline(always)]
fn domain<I: Isa>(s: I, op: Op, x: I::V) -> I::M {
    match op {
        Op::Exp => s.le(s.abs(x), s.splat(EXP_MAX_ARG)),
        Op::Ln => s.and(
            s.le(s.splat(f64::MIN_POSITIVE), x),
            s.lt(x, s.splat(f64::INFINITY)),
        ),
        _ => s.le(s.abs(x), s.splat(TRIG_MAX_ARG)),
    }
}

/// Stores a block of lane function results `r` of `x` into `o`, the lanes outside the
/// function's proven domain redone through the scalar operation of `i`.
#[inline(always)]
fn put<I: Isa>(s: I, i: &Instr, o: &mut F64x8, x: &F64x8, r: I::V) {
    *o = s.store(r);
    let inside = s.bits(domain(s, i.op, s.load(x)));
    if inside != u8::MAX {
        redo(i, inside, x, o);
    }
}

/// The lane function `$f` of the instruction at `$at` over every block (a macro, so
/// that the function inlines into the path's code).
macro_rules! elementary {
    ($s:ident, $at:ident, $f:path) => {{
        let i = $at.i;
        $at.each::<1>(|[o], [[x], _, _]| put($s, i, o, x, $f($s, $s.load(x))))
    }};
}

impl PartOps for Points {
    const PARTS: usize = 1;

    #[inline(always)]
    fn instruction<I: Isa>(s: I, at: Step<'_>) {
        let i = at.i;
        let c = s.splat(i.c);
        macro_rules! un {
            (|$x:ident| $body:expr) => {
                at.each::<1>(|[o], [[x], _, _]| {
                    let $x = s.load(x);
                    *o = s.store($body);
                })
            };
        }
        macro_rules! bin {
            (|$x:ident, $y:ident| $body:expr) => {
                at.each::<1>(|[o], [[x], [y], _]| {
                    let ($x, $y) = (s.load(x), s.load(y));
                    *o = s.store($body);
                })
            };
        }
        match i.op {
            Op::X | Op::Y | Op::Z | Op::Const => {
                unreachable!("not an operation on registers")
            }
            Op::Neg => un!(|x| s.neg(x)),
            Op::Sqr => un!(|x| s.mul(x, x)),
            Op::Sqrt => un!(|x| real_sqrt(s, x)),
            Op::Abs => un!(|x| s.abs(x)),
            Op::Recip => un!(|x| s.div(s.splat(1.0), x)),
            Op::AddC => un!(|x| s.add(x, c)),
            Op::SubC => un!(|x| s.sub(x, c)),
            Op::RSubC => un!(|x| s.sub(c, x)),
            Op::MulC => un!(|x| s.mul(x, c)),
            Op::DivC => un!(|x| s.div(x, c)),
            Op::RDivC => un!(|x| s.div(c, x)),
            Op::Add => bin!(|x, y| s.add(x, y)),
            Op::Sub => bin!(|x, y| s.sub(x, y)),
            Op::Mul => bin!(|x, y| s.mul(x, y)),
            Op::Div => bin!(|x, y| s.div(x, y)),
            Op::Hypot => bin!(|x, y| real_sqrt(s, s.add(s.mul(x, x), s.mul(y, y)))),
            Op::Min => bin!(|x, y| real_min(s, x, y)),
            Op::Max => bin!(|x, y| real_max(s, x, y)),
            Op::Gt0 => {
                let (one, zero) = (s.splat(1.0), s.splat(0.0));
                un!(|x| s.select(s.lt(zero, x), one, zero))
            }
            Op::Ge0 => {
                let (one, zero) = (s.splat(1.0), s.splat(0.0));
                un!(|x| s.select(s.le(zero, x), one, zero))
            }
            Op::Select => {
                let half = s.splat(0.5);
                at.each::<1>(|[o], [[m], [t], [f]]| {
                    let m = s.lt(half, s.load(m));
                    *o = s.store(s.select(m, s.load(t), s.load(f)));
                })
            }
            Op::Exp => elementary!(s, at, exp),
            Op::Ln => elementary!(s, at, ln),
            Op::Sin => elementary!(s, at, sin),
            Op::Cos => elementary!(s, at, cos),
            // Lane by lane through the scalar operation.
            _ => at.each::<1>(|[o], [[x], [y], [z]]| {
                *o = F64x8(core::array::from_fn(|l| apply(i, x.0[l], y.0[l], z.0[l])));
            }),
        }
    }
}
