//! What the kernel tests share: the lane paths to run, and random tapes of every
//! instruction.

#![allow(dead_code)] // each test binary uses part of it

use arith_core::lanes::{Path, TRIG_ABS};
use arith_core::testkit::expr::{Expr, Un};
use model_ir::{Builder, Instr, Op, Tape, Val};
use proptest::prelude::*;

/// Every available path; the others are named on standard error.
pub fn paths() -> Vec<Path> {
    Path::ALL
        .into_iter()
        .filter(|p| {
            let ok = p.available();
            if !ok {
                eprintln!("kernels: skipped the {p} path (this processor lacks it)");
            }
            ok
        })
        .collect()
}

/// Whether two numbers have the same bits, or are both NaN.
pub fn same_bits(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// Points: ordinary, and now and then a special number.
pub fn point() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => -3.0..3.0f64,
        1 => prop::sample::select(vec![
            0.0,
            -0.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            1e308,
            -1e300,
            5e-324,
            0.5,
            1.0,
        ]),
    ]
}

/// The point at fractions `f` of the box `b` (kept inside it).
pub fn point_in(b: &[(f64, f64); 3], f: &[f64; 3]) -> Vec<f64> {
    (0..3)
        .map(|i| {
            let (lo, hi) = b[i];
            (lo + f[i] * (hi - lo)).clamp(lo, hi)
        })
        .collect()
}

/// Constants an instruction may carry: ordinary, zeros, infinities, NaN.
pub fn constant() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -4.0..4.0f64,
        1 => prop::sample::select(vec![0.0, -0.0, 2.0, f64::INFINITY, f64::NEG_INFINITY, f64::NAN]),
    ]
}

/// One random instruction: an op (not an input), its operands among the registers so
/// far (as fractions of their count), its exponent and constant.
pub type Draw = (usize, [f64; 3], i32, f64);

/// Random instruction lists for [`random_tape`].
pub fn draws() -> impl Strategy<Value = Vec<Draw>> {
    let ops = Op::ALL.len() - 3;
    prop::collection::vec(
        (
            0..ops,
            [0.0..1.0f64, 0.0..1.0, 0.0..1.0],
            -3..5i32,
            constant(),
        ),
        1..24,
    )
}

/// A tape of the drawn instructions after the three inputs, adding the last one to one
/// in the middle, so that every instruction of the set can be exercised with any
/// operands.
pub fn random_tape(ds: &[Draw]) -> Tape {
    let mut b = Builder::new();
    let mut regs = vec![
        b.emit(Instr::new(Op::X, 0, 0, 0, 0.0)),
        b.emit(Instr::new(Op::Y, 0, 0, 0, 0.0)),
        b.emit(Instr::new(Op::Z, 0, 0, 0, 0.0)),
    ];
    for &(op, f, n, c) in ds {
        let op = Op::ALL[3 + op];
        let pick = |k: usize| regs[(f[k] * regs.len() as f64) as usize % regs.len()];
        let mut i = Instr::new(op, pick(0), pick(1), n, c);
        if op == Op::Select {
            i.e = pick(2);
        }
        let r = b.emit(i);
        regs.push(r);
    }
    let k = regs.len();
    let sum = b.emit(Instr::new(Op::Add, regs[k - 1], regs[k / 2], 0, 0.0));
    b.finish(Val::R(sum))
}

/// Whether `e` applies `exp`, `ln`, `sin` or `cos`, whose lanes' enclosures are not
/// the scalar bits.
pub fn has_elementary(e: &Expr) -> bool {
    match e {
        Expr::Input(_) | Expr::Const(_) => false,
        Expr::Unary(op, a) => {
            matches!(op, Un::Exp | Un::Ln | Un::Sin | Un::Cos) || has_elementary(a)
        }
        Expr::Binary(_, a, b) => has_elementary(a) || has_elementary(b),
    }
}

/// The batched bounds of an expression with `exp`, `ln`, `sin` or `cos` against the
/// scalar ones: both enclose the exact range, so they overlap, and as the lanes'
/// functions differ from libm's by a few ulp under the same margin (without the
/// scalar's extra ulp outward; `sin` and `cos` add `TRIG_ABS`), the batched range is at
/// most twice as wide as the scalar one, plus `2^-30` of the scalar bounds' magnitude
/// and a few `TRIG_ABS` (also for RevAA on the AVX2 path). How far apart the
/// bounds may lie after a cancellation depends on the expression; the functions
/// themselves are checked against the reference in `tests/elementary.rs`.
pub fn close(batched: (f64, f64), scalar: (f64, f64)) -> bool {
    let width = |(lo, hi): (f64, f64)| hi - lo;
    let size = scalar.0.abs().max(scalar.1.abs());
    let overlap = batched.0 <= scalar.1 && scalar.0 <= batched.1;
    let narrow = !width(scalar).is_finite()
        || width(batched) <= 2.0 * width(scalar) + 2f64.powi(-30) * size + 4.0 * TRIG_ABS;
    overlap && narrow
}
