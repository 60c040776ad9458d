//! The batch kernels (points and intervals over eight-lane blocks) on every lane path
//! this processor has, against the scalar evaluation and the 256-bit reference:
//! points give the scalar bits; interval bounds are the scalar numbers on the AVX-512
//! and emulated paths and enclose them on the AVX2 path (with `exp` or `ln`, whose
//! lanes' enclosures are not libm's, they overlap them and are at most about twice as
//! wide); on every path each range holds
//! the exact value of the function at random points of its box, also over boxes with
//! infinite, zero and huge bounds (the lanes redone on the scalar path).

mod common;

use arith_core::lanes::Path;
use arith_core::pack::Pack;
use arith_core::testkit::checks::{cases, check_point, run};
use arith_core::testkit::expr::{expr_strategy, Expr};
use arith_core::{Range, Real};
use arith_ia::{Interval, IntervalX4};
use common::{close, has_elementary, paths, point, point_in, same_bits};
use model_ir::Tape;
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;

fn recorded(e: &Expr) -> Tape {
    Tape::record(|x, y, z| e.eval(&[x, y, z]))
}

type Side = (f64, f64);

/// Ordinary sides, and now and then one with an infinite, zero, tiny or huge bound.
fn side() -> impl Strategy<Value = Side> {
    let inf = f64::INFINITY;
    prop_oneof![
        8 => (-3.0..3.0f64, 0.0..1.5f64).prop_map(|(lo, w)| (lo, lo + w)),
        1 => prop::sample::select(vec![
            (-inf, 1.0),
            (-1.0, inf),
            (-inf, inf),
            (0.0, 0.0),
            (-0.0, 0.0),
            (0.0, 2.0),
            (-2.0, -0.0),
            (1e300, 1e308),
            (-1e308, 1e300),
            (5e-324, 1e-300),
            (-1e-310, 1e-310),
            (inf, inf),
        ]),
    ]
}

fn boxes(n: std::ops::Range<usize>) -> impl Strategy<Value = Vec<[Side; 3]>> {
    prop::collection::vec([side(), side(), side()], n)
}

fn columns(bs: &[[Side; 3]]) -> [Vec<Interval>; 3] {
    core::array::from_fn(|k| bs.iter().map(|b| Interval::new(b[k].0, b[k].1)).collect())
}

/// The batched bounds against the scalar ones on `path`. On the AVX2 path an exact
/// infinite result is stepped like every other (`inf + 0` has the lower bound
/// `f64::MAX`), which changes what the scalar operations make of sets that hold no real
/// number (`[inf, inf]`, the value of `-ln(0)`): where the scalar result is unbounded,
/// only the containment of the exact values is checked there
/// (`batched_ranges_hold_the_exact_values`).
fn agrees(path: Path, batched: (f64, f64), scalar: (f64, f64)) -> bool {
    match path {
        Path::Avx2 => {
            (batched.0 <= scalar.0 && scalar.1 <= batched.1)
                || scalar.0.is_infinite()
                || scalar.1.is_infinite()
        }
        _ => batched == scalar,
    }
}

fn check_intervals(e: &Expr, bs: &[[Side; 3]]) -> Result<(), TestCaseError> {
    let t = recorded(e);
    let [x, y, z] = columns(bs);
    for path in paths() {
        let mut out = Vec::new();
        t.eval_batch_on(path, &x, &y, &z, &mut out);
        prop_assert_eq!(out.len(), bs.len());
        for (l, o) in out.iter().enumerate() {
            let scalar = t.eval(x[l], y[l], z[l]).bounds();
            let ok = agrees(path, o.bounds(), scalar)
                || (has_elementary(e) && close(o.bounds(), scalar));
            prop_assert!(
                ok,
                "{path}, lane {l} of {}: {:?} batched, {scalar:?} scalar\n{e}",
                bs.len(),
                o.bounds()
            );
            prop_assert!(o.lo <= o.hi, "{path}: {o:?}");
        }
    }
    Ok(())
}

#[test]
fn interval_batches_match_the_scalar_arithmetic() {
    run(
        "kernel intervals",
        cases(256),
        (expr_strategy(6, 3), boxes(1..40)),
        |(e, bs)| check_intervals(&e, &bs),
    );
}

/// Every operation the recorder emits, on one tape, at blocks that hit the scalar
/// redo of every kind (`0 * inf`, `inf - inf`, `inf / inf`, roots outside the tight
/// range).
#[test]
fn special_bounds_are_redone_exactly() {
    let inf = f64::INFINITY;
    let e = expr_strategy(7, 3);
    let specials = [
        (-inf, 1.0),
        (0.0, 0.0),
        (-1.0, inf),
        (inf, inf),
        (-inf, -inf),
        (1e-300, 1e-290),
        (-inf, inf),
        (2.0, 2.0),
        (1e300, inf),
    ];
    let bs: Vec<[Side; 3]> = (0..specials.len() * specials.len())
        .map(|k| {
            let (a, b) = (specials[k % specials.len()], specials[k / specials.len()]);
            [a, b, (0.5, 0.75)]
        })
        .collect();
    run("kernel special bounds", cases(64), e, |e| {
        check_intervals(&e, &bs)
    });
}

/// The exact value at random points of each box lies in the batched range, on every
/// path.
#[test]
fn batched_ranges_hold_the_exact_values() {
    let fractions = prop::collection::vec([0.0..=1.0f64, 0.0..=1.0f64, 0.0..=1.0f64], 1..24);
    run(
        "kernel containment",
        cases(128),
        (expr_strategy(6, 3), fractions),
        |(e, fr)| {
            let t = recorded(&e);
            let bs: Vec<[Side; 3]> = fr
                .iter()
                .enumerate()
                .map(|(k, f)| {
                    core::array::from_fn(|i| {
                        let lo = -2.0 + 0.37 * ((k + i) % 9) as f64;
                        (lo, lo + 0.25 + f[i])
                    })
                })
                .collect();
            let [x, y, z] = columns(&bs);
            for path in paths() {
                let mut out = Vec::new();
                t.eval_batch_on(path, &x, &y, &z, &mut out);
                for (l, (o, f)) in out.iter().zip(&fr).enumerate() {
                    let p = point_in(&bs[l], f);
                    if let Err(m) = check_point(&e, &p, o.lo, o.hi) {
                        return Err(TestCaseError::fail(format!("{path}: {m}")));
                    }
                }
            }
            Ok(())
        },
    );
}

/// Points give the scalar evaluation's bits on every path.
#[test]
fn point_batches_give_the_scalar_bits() {
    let pts = prop::collection::vec([point(), point(), point()], 1..40);
    run(
        "kernel points",
        cases(256),
        (expr_strategy(6, 3), pts),
        |(e, pts)| {
            let t = recorded(&e);
            let col = |k: usize| pts.iter().map(|p| p[k]).collect::<Vec<f64>>();
            let (x, y, z) = (col(0), col(1), col(2));
            for path in paths() {
                let mut out = Vec::new();
                t.eval_batch_on(path, &x, &y, &z, &mut out);
                prop_assert_eq!(out.len(), pts.len());
                for (l, o) in out.iter().enumerate() {
                    let s = t.eval(x[l], y[l], z[l]);
                    prop_assert!(
                        same_bits(*o, s),
                        "{path}, lane {l}: {o:e} batched, {s:e} scalar\n{e}"
                    );
                }
            }
            Ok(())
        },
    );
}

/// Four-interval packs run the interval kernel, lane for lane as the packs' own
/// evaluation.
#[test]
fn pack_batches_match_pack_evaluation() {
    run(
        "kernel packs",
        cases(128),
        (expr_strategy(6, 3), boxes(4..36)),
        |(e, bs)| {
            let t = recorded(&e);
            let [x, y, z] = columns(&bs);
            let pack = |v: &[Interval]| -> Vec<IntervalX4> {
                v.chunks_exact(4)
                    .map(|c| IntervalX4::pack([c[0], c[1], c[2], c[3]]))
                    .collect()
            };
            let (px, py, pz) = (pack(&x), pack(&y), pack(&z));
            for path in paths() {
                let mut out = Vec::new();
                t.eval_batch_on(path, &px, &py, &pz, &mut out);
                prop_assert_eq!(out.len(), px.len());
                for (k, o) in out.iter().enumerate() {
                    let one = t.eval(px[k], py[k], pz[k]).unpack();
                    for (a, b) in o.unpack().iter().zip(&one) {
                        let ok = agrees(path, a.bounds(), b.bounds())
                            || (has_elementary(&e) && close(a.bounds(), b.bounds()));
                        prop_assert!(ok, "{path}: {a:?} vs {b:?}");
                    }
                }
            }
            Ok(())
        },
    );
}

/// A batch allocates its register file once per thread: a second batch of the same
/// tape and size runs in the buffers of the first (the kernels take no other memory),
/// and gives the same results.
#[test]
fn repeated_batches_agree() {
    let t = Tape::record(|x, y, z| (x.sqr() + y * z).sqrt() - 1.0);
    let x: Vec<Interval> = (0..100)
        .map(|k| Interval::new(k as f64, k as f64 + 1.0))
        .collect();
    let (mut a, mut b) = (Vec::new(), Vec::new());
    t.eval_batch(&x, &x, &x, &mut a);
    t.eval_batch(&x, &x, &x, &mut b);
    assert_eq!(a, b);
}

/// A constant read for the last time by an instruction over several blocks: its one
/// block must survive until every block of the result is written.
#[test]
fn constants_last_read_across_blocks() {
    let t = Tape::record(|x, y, _z| x.max(&Real::constant(0.5)) * y.min(&Real::constant(-0.25)));
    let x: Vec<Interval> = (0..40)
        .map(|k| Interval::new(k as f64 / 40.0, 1.0))
        .collect();
    let p: Vec<f64> = (0..40).map(|k| k as f64 / 40.0 - 0.5).collect();
    for path in paths() {
        let mut out = Vec::new();
        t.eval_batch_on(path, &x, &x, &x, &mut out);
        for (l, o) in out.iter().enumerate() {
            assert!(
                agrees(path, o.bounds(), t.eval(x[l], x[l], x[l]).bounds()),
                "{path} {l}"
            );
        }
        let mut out = Vec::new();
        t.eval_batch_on(path, &p, &p, &p, &mut out);
        for (l, o) in out.iter().enumerate() {
            assert_eq!(
                o.to_bits(),
                t.eval(p[l], p[l], p[l]).to_bits(),
                "{path} {l}"
            );
        }
    }
}

/// A batch longer than one pass of the kernels (512 lanes) runs in several passes:
/// every lane still gives what the scalar evaluation gives, also where the tape's
/// result is an input or a constant, and where constants are read in every pass.
#[test]
fn batches_of_several_passes() {
    let tapes = [
        Tape::record(|x, y, z| {
            let a = x.max(&Real::constant(0.5)) * y.min(&Real::constant(-0.25));
            (a + z.sqr()).sqrt() - x * y
        }),
        Tape::record(|_x, y, _z| y),
        Tape::record(|_x, _y, _z| Real::constant(1.5)),
    ];
    let n = 1100;
    let x: Vec<Interval> = (0..n)
        .map(|k| Interval::new(k as f64 / 400.0 - 1.0, k as f64 / 300.0))
        .collect();
    let p: Vec<f64> = (0..n).map(|k| (k as f64 * 0.37).sin()).collect();
    for t in &tapes {
        for path in paths() {
            let mut out = Vec::new();
            t.eval_batch_on(
                path,
                &x,
                &p.iter().map(|&v| Interval::point(v)).collect::<Vec<_>>(),
                &x,
                &mut out,
            );
            assert_eq!(out.len(), n);
            for (l, o) in out.iter().enumerate() {
                let s = t.eval(x[l], Interval::point(p[l]), x[l]).bounds();
                assert!(agrees(path, o.bounds(), s), "{path} {l}: {o:?} vs {s:?}");
            }
            let mut out = Vec::new();
            t.eval_batch_on(path, &p, &p, &p, &mut out);
            assert_eq!(out.len(), n);
            for (l, o) in out.iter().enumerate() {
                assert_eq!(
                    o.to_bits(),
                    t.eval(p[l], p[l], p[l]).to_bits(),
                    "{path} {l}"
                );
            }
        }
    }
}
