//! The RevAA kernel (revised affine forms over eight-lane blocks: a centre, the input
//! symbols' coefficients and the error term per lane) on every lane path this
//! processor has (the emulated one runs the generic loop): on the AVX-512 and emulated
//! paths every part of every lane is the
//! scalar `RevAa<N>` evaluation's, bit for bit, for one and three symbols and for
//! four-form packs, on recorded expressions and on random tapes of every instruction
//! over random forms (zeros of both signs, huge, tiny, infinite and NaN parts), but
//! where a tape takes `exp` or `ln` (their lanes' Chebyshev approximations use the
//! lanes' proven `exp` and `ln` instead of libm's: the ranges are then close to the
//! scalar ones); on
//! every path, the AVX2 one included (whose square, `abs`, `sqrt`, `min` and `max` may
//! take directed bounds an ulp further out), each batched range holds the exact value
//! of the function at random points of the inputs' boxes.

mod common;

use arith_core::lanes::Path;
use arith_core::pack::Pack;
use arith_core::testkit::checks::{cases, check_point, run};
use arith_core::testkit::expr::expr_strategy;
use arith_core::{Range, Real};
use arith_revaa::{RevAa, RevAa1x4};
use common::{close, draws, paths, point_in, random_tape, same_bits};
use model_ir::{Op, Tape};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;

fn same_form<const N: usize>(a: &RevAa<N>, b: &RevAa<N>) -> bool {
    same_bits(a.x0, b.x0) && same_bits(a.e, b.e) && (0..N).all(|k| same_bits(a.xs[k], b.xs[k]))
}

/// Whether the path computes the scalar bits (the AVX2 path's directed sums are wider).
fn tight(p: Path) -> bool {
    p != Path::Avx2
}

fn part() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => -3.0..3.0f64,
        1 => prop::sample::select(vec![
            0.0,
            -0.0,
            1e300,
            -1e-300,
            5e-324,
            f64::INFINITY,
            f64::NAN,
            0.5,
        ]),
    ]
}

/// A raw form: any centre and coefficients, an error term `>= 0` (or NaN, infinite).
fn form<const N: usize>() -> impl Strategy<Value = RevAa<N>> {
    let xs = prop::collection::vec(part(), N);
    let e = prop_oneof![4 => 0.0..1.0f64, 1 => part()];
    (part(), xs, e).prop_map(|(x0, xs, e)| {
        let e = if e < 0.0 { -e } else { e };
        RevAa::<N>::from_parts(x0, core::array::from_fn(|k| xs[k]), e)
    })
}

/// Whether a tape takes `exp` or `ln`, whose lanes are close to the scalar forms, not
/// the same.
fn takes_exp(t: &Tape) -> bool {
    t.instructions()
        .iter()
        .any(|i| matches!(i.op, Op::Exp | Op::Ln))
}

/// The batched forms against the scalar ones on the paths that give the same bits
/// (close ranges where the tape takes `exp` or `ln`).
fn check_forms<const N: usize>(
    t: &Tape,
    ins: &[[RevAa<N>; 3]],
    what: &dyn std::fmt::Display,
) -> Result<(), TestCaseError> {
    let exp = takes_exp(t);
    let col = |k: usize| ins.iter().map(|p| p[k]).collect::<Vec<_>>();
    let (x, y, z) = (col(0), col(1), col(2));
    for path in paths().into_iter().filter(|p| tight(*p)) {
        let mut out = Vec::new();
        t.eval_batch_on(path, &x, &y, &z, &mut out);
        prop_assert_eq!(out.len(), ins.len());
        for (l, o) in out.iter().enumerate() {
            let s = t.eval(x[l], y[l], z[l]);
            prop_assert!(
                same_form(o, &s) || (exp && close(o.bounds(), s.bounds())),
                "{path}, lane {l} of {}: {o:?} batched, {s:?} scalar\n{what}",
                ins.len()
            );
        }
    }
    Ok(())
}

#[test]
fn expressions_give_the_scalar_bits() {
    run(
        "revaa kernel, expressions",
        cases(256),
        (
            expr_strategy(6, 3),
            prop::collection::vec([form::<1>(), form(), form()], 1..30),
        ),
        |(e, ins)| {
            let t = Tape::record(|x, y, z| e.eval(&[x, y, z]));
            check_forms(&t, &ins, &e)
        },
    );
}

#[test]
fn three_symbols_give_the_scalar_bits() {
    run(
        "revaa kernel, three symbols",
        cases(128),
        (
            expr_strategy(6, 3),
            prop::collection::vec([form::<3>(), form(), form()], 1..30),
        ),
        |(e, ins)| {
            let t = Tape::record(|x, y, z| e.eval(&[x, y, z]));
            check_forms(&t, &ins, &e)
        },
    );
}

#[test]
fn every_instruction_gives_the_scalar_bits() {
    run(
        "revaa kernel, every instruction",
        cases(512),
        (
            draws(),
            prop::collection::vec([form::<1>(), form(), form()], 1..30),
        ),
        |(ds, ins)| {
            let t = random_tape(&ds);
            check_forms(&t, &ins, &t)?;
            let ins3: Vec<[RevAa<3>; 3]> = ins
                .iter()
                .map(|p| {
                    p.map(|f| RevAa::<3>::from_parts(f.x0, [f.xs[0], -0.5 * f.xs[0], 0.25], f.e))
                })
                .collect();
            check_forms(&t, &ins3, &t)
        },
    );
}

/// Four-form packs run the kernel, lane for lane as the packs' own evaluation.
#[test]
fn packs_give_the_scalar_bits() {
    run(
        "revaa kernel, packs",
        cases(128),
        (
            expr_strategy(6, 3),
            prop::collection::vec([form::<1>(), form(), form()], 4..36),
        ),
        |(e, ins)| {
            let t = Tape::record(|x, y, z| e.eval(&[x, y, z]));
            let pack = |k: usize| -> Vec<RevAa1x4> {
                ins.chunks_exact(4)
                    .map(|c| RevAa1x4::pack([c[0][k], c[1][k], c[2][k], c[3][k]]))
                    .collect()
            };
            let (px, py, pz) = (pack(0), pack(1), pack(2));
            for path in paths().into_iter().filter(|p| tight(*p)) {
                let mut out = Vec::new();
                t.eval_batch_on(path, &px, &py, &pz, &mut out);
                prop_assert_eq!(out.len(), px.len());
                let exp = takes_exp(&t);
                for (k, o) in out.iter().enumerate() {
                    let one = t.eval(px[k], py[k], pz[k]).unpack();
                    for (a, b) in o.unpack().iter().zip(&one) {
                        prop_assert!(
                            same_form(a, b) || (exp && close(a.bounds(), b.bounds())),
                            "{path}: {a:?} vs {b:?}\n{e}"
                        );
                    }
                }
            }
            Ok(())
        },
    );
}

/// The exact value at random points of each box lies in the batched range, on every
/// path (the ray's parameter as the input symbol, the others as error terms).
#[test]
fn batched_forms_hold_the_exact_values() {
    let fractions = prop::collection::vec([0.0..=1.0f64, 0.0..=1.0f64, 0.0..=1.0f64], 1..24);
    run(
        "revaa kernel, containment",
        cases(128),
        (expr_strategy(6, 3), fractions),
        |(e, fr)| {
            let t = Tape::record(|x, y, z| e.eval(&[x, y, z]));
            let boxes: Vec<[(f64, f64); 3]> = fr
                .iter()
                .enumerate()
                .map(|(k, f)| {
                    core::array::from_fn(|i| {
                        let lo = -2.0 + 0.37 * ((k + i) % 9) as f64;
                        (lo, lo + 0.25 + f[(i + 1) % 3])
                    })
                })
                .collect();
            let col = |i: usize| -> Vec<RevAa<1>> {
                boxes
                    .iter()
                    .map(|b| RevAa::<1>::input(i, b[i].0, b[i].1))
                    .collect()
            };
            let (x, y, z) = (col(0), col(1), col(2));
            for path in paths() {
                let mut out = Vec::new();
                t.eval_batch_on(path, &x, &y, &z, &mut out);
                for (l, (o, f)) in out.iter().zip(&fr).enumerate() {
                    let p = point_in(&boxes[l], f);
                    let (lo, hi) = o.bounds();
                    if let Err(m) = check_point(&e, &p, lo, hi) {
                        return Err(TestCaseError::fail(format!("{path}: {m}")));
                    }
                }
            }
            Ok(())
        },
    );
}

/// Squares of forms where the Chebyshev square gains and where it does not, on every
/// path: the AVX2 result encloses the exact squares too (dyadic parts, so that the
/// points and their squares below are exact).
#[test]
fn squares_on_every_path() {
    let t = Tape::record(|x, _y, _z| x.sqr());
    let x: Vec<RevAa<1>> = (0..40)
        .map(|k| RevAa::<1>::from_parts(k as f64 / 8.0 - 2.0, [0.375], (k % 3) as f64 / 64.0))
        .collect();
    for path in paths() {
        let mut out = Vec::new();
        t.eval_batch_on(path, &x, &x, &x, &mut out);
        for (o, f) in out.iter().zip(&x) {
            let s = t.eval(*f, *f, *f);
            if tight(path) {
                assert!(same_form(o, &s), "{path}: {o:?} vs {s:?}");
            }
            let (lo, hi) = o.bounds();
            for eps in [-1.0, -0.5, 0.0, 0.5, 1.0] {
                for d in [-f.e, 0.0, f.e] {
                    let v = f.x0 + f.xs[0] * eps + d;
                    assert!(
                        lo <= v * v && v * v <= hi,
                        "{path}: {v}^2 not in [{lo}, {hi}]"
                    );
                }
            }
        }
    }
}
