//! The gradient kernel (a value and three partials per lane over eight-lane blocks) on
//! every lane path this processor has, against the scalar evaluation over
//! `Dual<f64>`: every part of every lane bit for bit (NaN for NaN), on recorded
//! expressions, on random tapes of every instruction with random operands and
//! constants, at ordinary and special points (zeros of both signs, infinities, NaN,
//! huge and subnormal numbers), and with the inputs' partials seeded at will.

mod common;

use arith_core::dual::Dual;
use arith_core::testkit::checks::{cases, run};
use arith_core::testkit::expr::{expr_strategy, Expr};
use common::{draws, paths, point, random_tape, same_bits};
use model_ir::{Builder, Instr, Op, Tape, Val};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;

fn same_dual(a: &Dual<f64>, b: &Dual<f64>) -> bool {
    same_bits(a.v, b.v) && (0..3).all(|k| same_bits(a.g[k], b.g[k]))
}

/// `eval_gradient_batch_on` against the scalar dual evaluation at each point.
fn check_points(
    t: &Tape,
    pts: &[[f64; 3]],
    what: &dyn std::fmt::Display,
) -> Result<(), TestCaseError> {
    let col = |k: usize| pts.iter().map(|p| p[k]).collect::<Vec<f64>>();
    let (x, y, z) = (col(0), col(1), col(2));
    for path in paths() {
        let mut out = Vec::new();
        t.eval_gradient_batch_on(path, &x, &y, &z, &mut out);
        prop_assert_eq!(out.len(), pts.len());
        for (l, o) in out.iter().enumerate() {
            let s = t.eval(Dual::var(x[l], 0), Dual::var(y[l], 1), Dual::var(z[l], 2));
            prop_assert!(
                same_dual(o, &s),
                "{path}, lane {l} at {:?}: {o:?} batched, {s:?} scalar\n{what}",
                pts[l]
            );
        }
    }
    Ok(())
}

#[test]
fn gradient_batches_give_the_dual_bits() {
    let pts = prop::collection::vec([point(), point(), point()], 1..40);
    run(
        "kernel gradients",
        cases(256),
        (expr_strategy(6, 3), pts),
        |(e, pts): (Expr, Vec<[f64; 3]>)| {
            let t = Tape::record(|x, y, z| e.eval(&[x, y, z]));
            check_points(&t, &pts, &e)
        },
    );
}

#[test]
fn every_instruction_gives_the_dual_bits() {
    let pts = prop::collection::vec([point(), point(), point()], 1..30);
    run(
        "kernel gradients, every instruction",
        cases(512),
        (draws(), pts),
        |(ds, pts)| {
            let t = random_tape(&ds);
            check_points(&t, &pts, &t)
        },
    );
}

/// Each instruction alone, on both operands' ordinary and special values.
#[test]
fn each_instruction_alone() {
    let vals = [
        -2.5,
        -1.0,
        -0.0,
        0.0,
        0.25,
        0.5,
        1.0,
        3.0,
        1e308,
        5e-324,
        f64::INFINITY,
        f64::NAN,
    ];
    let pts: Vec<[f64; 3]> = vals
        .iter()
        .flat_map(|&a| vals.iter().map(move |&b| [a, b, 0.75]))
        .collect();
    for op in &Op::ALL[3..] {
        for (n, c) in [
            (0, 0.0),
            (1, -0.0),
            (2, 1.5),
            (-3, -2.0),
            (3, f64::INFINITY),
        ] {
            let mut b = Builder::new();
            let x = b.emit(Instr::new(Op::X, 0, 0, 0, 0.0));
            let y = b.emit(Instr::new(Op::Y, 0, 0, 0, 0.0));
            let z = b.emit(Instr::new(Op::Z, 0, 0, 0, 0.0));
            let mut i = Instr::new(*op, x, y, n, c);
            i.e = z;
            let r = b.emit(i);
            let t = b.finish(Val::R(r));
            if let Err(e) = check_points(&t, &pts, &t) {
                panic!("{}: {e}", op.name());
            }
        }
    }
}

/// Inputs with any partials (not only the unit seeds): `eval_batch` over `Dual<f64>`
/// runs the kernel and gives the scalar bits.
#[test]
fn seeded_dual_batches_give_the_dual_bits() {
    let dual = || (point(), [point(), point(), point()]).prop_map(|(v, g)| Dual { v, g });
    let inputs = prop::collection::vec([dual(), dual(), dual()], 1..30);
    run(
        "kernel gradients, seeded",
        cases(256),
        (expr_strategy(5, 3), inputs),
        |(e, ins)| {
            let t = Tape::record(|x, y, z| e.eval(&[x, y, z]));
            let col = |k: usize| ins.iter().map(|p| p[k].clone()).collect::<Vec<_>>();
            let (x, y, z) = (col(0), col(1), col(2));
            for path in paths() {
                let mut out = Vec::new();
                t.eval_batch_on(path, &x, &y, &z, &mut out);
                for (l, o) in out.iter().enumerate() {
                    let s = t.eval(x[l].clone(), y[l].clone(), z[l].clone());
                    prop_assert!(same_dual(o, &s), "{path}, lane {l}: {o:?} vs {s:?}\n{e}");
                }
            }
            Ok(())
        },
    );
}

/// A constant result, a constant read across blocks, and batches of one lane.
#[test]
fn constants_and_short_batches() {
    let t = Tape::record(|x, y, _z| {
        use arith_core::Real;
        x.max(&Real::constant(0.5)) * y.min(&Real::constant(-0.25))
    });
    let p: Vec<f64> = (0..41).map(|k| k as f64 / 20.0 - 1.0).collect();
    let pts: Vec<[f64; 3]> = p.iter().map(|&v| [v, -v, v]).collect();
    check_points(&t, &pts, &t).unwrap();
    check_points(&t, &pts[..1], &t).unwrap();
    let mut b = Builder::new();
    let c = b.emit(Instr::new(Op::Const, 0, 0, 0, 2.5));
    let t = b.finish(Val::R(c));
    check_points(&t, &pts, &t).unwrap();
    // More lanes than one pass of the kernel (512).
    let long: Vec<[f64; 3]> = (0..1100)
        .map(|k| {
            let v = (k as f64 * 0.37).sin();
            [v, -v, 0.5 * v]
        })
        .collect();
    let t = Tape::record(|x, y, z| {
        use arith_core::Real;
        (x.max(&Real::constant(0.5)) * y + z.sqr()).sqrt()
    });
    check_points(&t, &long, &t).unwrap();
}
