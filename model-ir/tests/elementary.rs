//! The lanes' `exp`, `ln`, `sin` and `cos` (`arith_core::lanes`), which the interval
//! and point kernels run: on every path, and for one `f64` alone (`f64`'s `Real`
//! functions), the same bits as on the emulated one; within their
//! proven error (`ELEMENTARY_REL`, and `TRIG_ABS` for `sin` and `cos`) of the 256-bit
//! reference over their domains; their enclosures hold the reference; and the interval
//! kernel's ranges hold the reference at both ends of random intervals (special ones
//! included, redone on the scalar path) and lie within a few ulp of the scalar
//! enclosures, which widen libm's values by the same margin.

mod common;

use arith_core::lanes::{
    cos, cos_f64, dispatch, exp, exp_enclosure, exp_f64, ln, ln_enclosure, ln_f64, sin, sin_f64,
    trig_enclosure, F64x8, Isa, Kernel, Path, ELEMENTARY_REL, EXP_MAX_ARG, TRIG_ABS, TRIG_MAX_ARG,
};
use arith_core::testkit::checks::{cases, run};
use arith_core::testkit::mp::{Mp, Verdict};
use arith_core::Real;
use arith_ia::Interval;
use common::paths;
use model_ir::Tape;
use proptest::prelude::*;

/// The lanes' functions.
#[derive(Clone, Copy, Debug, PartialEq)]
enum F {
    Exp,
    Ln,
    Sin,
    Cos,
}

/// One of the lanes' functions over eight lanes: the value and its enclosure.
struct Lanes {
    f: F,
    x: F64x8,
}

impl Kernel for Lanes {
    type Output = (F64x8, F64x8, F64x8);
    #[inline(always)]
    fn run<I: Isa>(self, s: I) -> Self::Output {
        let x = s.load(&self.x);
        let (v, (lo, hi)) = match self.f {
            F::Exp => (exp(s, x), exp_enclosure(s, x)),
            F::Ln => (ln(s, x), ln_enclosure(s, x)),
            F::Sin => (sin(s, x), trig_enclosure(s, x, false)),
            F::Cos => (cos(s, x), trig_enclosure(s, x, true)),
        };
        (s.store(v), s.store(lo), s.store(hi))
    }
}

/// The value and enclosure of `x` on `path`.
fn lanes(path: Path, f: F, x: f64) -> (f64, f64, f64) {
    let (v, lo, hi) = dispatch(
        path,
        Lanes {
            f,
            x: F64x8([x; 8]),
        },
    );
    (v.0[3], lo.0[3], hi.0[3])
}

/// The reference of the function at `x`.
fn reference(f: F, x: f64) -> Mp {
    let p = Mp::point(x).unwrap();
    match f {
        F::Exp => p.exp(),
        F::Ln => p.ln(),
        F::Sin => p.sin(),
        F::Cos => p.cos(),
    }
    .unwrap()
}

/// Checks one argument in the function's domain on every path: the same bits, within
/// the proven error of the reference (`sin`, `cos`: plus their absolute term), and
/// enclosed.
fn check(f: F, x: f64) -> Result<(), TestCaseError> {
    let (v, lo, hi) = lanes(Path::Emulated, f, x);
    for path in paths() {
        let other = lanes(path, f, x);
        prop_assert!(
            other.0.to_bits() == v.to_bits(),
            "{path} {f:?}({x:e}) = {:e}, emulated {v:e}",
            other.0
        );
    }
    let alone = match f {
        F::Exp => (exp_f64(x), Real::exp(&x)),
        F::Ln => (ln_f64(x), Real::ln(&x)),
        F::Sin => (sin_f64(x), Real::sin(&x)),
        F::Cos => (cos_f64(x), Real::cos(&x)),
    };
    prop_assert!(
        alone.0.to_bits() == v.to_bits() && alone.1.to_bits() == v.to_bits(),
        "{f:?}({x:e}) = {v:e} in lanes, {:e} alone, {:e} as f64's Real",
        alone.0,
        alone.1
    );
    let r = reference(f, x);
    let abs = if matches!(f, F::Sin | F::Cos) {
        TRIG_ABS
    } else {
        0.0
    };
    let e = ELEMENTARY_REL * v.abs() + abs;
    prop_assert!(
        r.verdict(v - e, v + e) != Verdict::Outside,
        "{f:?}({x:e}) = {v:e}, beyond {e:e} of {}",
        r.describe()
    );
    prop_assert!(
        lo <= hi && r.verdict(lo, hi) == Verdict::Inside,
        "{f:?}({x:e}) enclosed by [{lo:e}, {hi:e}], not {}",
        r.describe()
    );
    Ok(())
}

/// Arguments of `exp`: the whole domain, small ones, and the ends.
fn exp_arg() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -EXP_MAX_ARG..=EXP_MAX_ARG,
        2 => -2.0..2.0f64,
        1 => -1e-6..1e-6f64,
        1 => (-40i32..40, -1.0..1.0f64).prop_map(|(k, d)| (f64::from(k) + 0.5) * core::f64::consts::LN_2 + d * 1e-12),
        1 => prop::sample::select(vec![
            0.0, -0.0, 5e-324, -5e-324, 1e-300, EXP_MAX_ARG, -EXP_MAX_ARG, 0.34657359027997264,
            -0.34657359027997264, 1.0, -1.0,
        ]),
    ]
}

/// Positive normal arguments of `ln`: every exponent, near 1, near the splits of the
/// significand (0.75, 1.5) and the ends.
fn ln_arg() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => (1u64..0x7ff, 0u64..(1 << 52)).prop_map(|(e, m)| f64::from_bits((e << 52) | m)),
        2 => 0.5..2.0f64,
        1 => (-1e-9..1e-9f64).prop_map(|d| 1.0 + d),
        1 => (-1021i32..1022, -4i64..4).prop_map(|(k, d)| {
            let b = (0.75 * 2f64.powi(k)).to_bits() as i64 + d;
            f64::from_bits(b as u64) * if d % 2 == 0 { 1.0 } else { 2.0 }
        }),
        1 => prop::sample::select(vec![
            f64::MIN_POSITIVE, f64::MAX, 1.0, 2.0, 0.5, 0.75, 1.5, 3.0, 1.0 - f64::EPSILON / 2.0,
            1.0 + f64::EPSILON,
        ]),
    ]
}

#[test]
fn lanes_exp_is_within_its_bound() {
    run("lanes exp", cases(2000), exp_arg(), |x| check(F::Exp, x));
}

#[test]
fn lanes_ln_is_within_its_bound() {
    run("lanes ln", cases(2000), ln_arg(), |x| {
        prop_assume!(x.is_normal() && x > 0.0);
        check(F::Ln, x)
    });
}

/// Arguments of `sin` and `cos`: the whole domain, small ones, the floats nearest to
/// multiples of `pi/2` (the hardest reductions) and the ends.
fn trig_arg() -> impl Strategy<Value = f64> {
    prop_oneof![
        3 => -TRIG_MAX_ARG..=TRIG_MAX_ARG,
        2 => -10.0..10.0f64,
        1 => -1e-6..1e-6f64,
        2 => (-63000i32..63000, -3i64..4).prop_map(|(k, d)| {
            let x = f64::from(k) * core::f64::consts::FRAC_PI_2;
            f64::from_bits((x.to_bits() as i64 + d) as u64)
        }),
        1 => prop::sample::select(vec![
            0.0, -0.0, 5e-324, 1e-300, -1e-300, TRIG_MAX_ARG, -TRIG_MAX_ARG,
            core::f64::consts::FRAC_PI_4, 0.7853981633974484, 355.0, 103993.0 / 33102.0 * 4.0,
        ]),
    ]
}

#[test]
fn lanes_sin_and_cos_are_within_their_bound() {
    run("lanes sin cos", cases(1000), trig_arg(), |x| {
        check(F::Sin, x)?;
        check(F::Cos, x)
    });
}

/// Interval sides of every kind: ordinary, wide, around the domains' ends, infinite,
/// zero, subnormal, NaN-free.
fn side() -> impl Strategy<Value = (f64, f64)> {
    let inf = f64::INFINITY;
    prop_oneof![
        6 => (-30.0..30.0f64, 0.0..5.0f64).prop_map(|(lo, w)| (lo, lo + w)),
        2 => (1e-300..1e300f64, 1.0..1e10f64).prop_map(|(lo, f)| (lo, lo * f)),
        1 => (690.0..710.0f64, 0.0..5.0f64).prop_map(|(lo, w)| (lo, lo + w)),
        1 => (-710.0..-690.0f64, 0.0..5.0f64).prop_map(|(lo, w)| (lo, lo + w)),
        1 => (0.99e5..1.01e5f64, 0.0..8.0f64, any::<bool>())
            .prop_map(|(lo, w, neg)| if neg { (-lo - w, -lo) } else { (lo, lo + w) }),
        1 => prop::sample::select(vec![
            (-inf, 1.0),
            (-1.0, inf),
            (-inf, inf),
            (0.0, 0.0),
            (-0.0, 0.0),
            (0.0, 2.0),
            (-2.0, -0.5),
            (5e-324, 1e-310),
            (1e-310, 1.0),
            (f64::MAX, inf),
            (inf, inf),
            (-inf, -inf),
        ]),
    ]
}

/// The interval kernel's `exp`, `ln`, `sin` and `cos` on random intervals: each range
/// holds the reference values at both ends, and lies within a few ulp of the scalar
/// enclosure's (both widen a value within `ELEMENTARY_REL` or libm's error by
/// `LIBM_REL`; the scalar steps one ulp further out; `sin` and `cos` make the same
/// decisions for the extrema and add `2^-80`).
#[test]
fn interval_elementary_functions_hold_the_reference() {
    let tapes = [
        (F::Exp, Tape::record(|x, _y, _z| x.exp())),
        (F::Ln, Tape::record(|x, _y, _z| x.ln())),
        (F::Sin, Tape::record(|x, _y, _z| x.sin())),
        (F::Cos, Tape::record(|x, _y, _z| x.cos())),
    ];
    run(
        "kernel elementary",
        cases(256),
        prop::collection::vec(side(), 1..40),
        |sides| {
            let x: Vec<Interval> = sides.iter().map(|&(a, b)| Interval::new(a, b)).collect();
            for (f, t) in &tapes {
                for path in paths() {
                    let mut out = Vec::new();
                    t.eval_batch_on(path, &x, &x, &x, &mut out);
                    for (o, i) in out.iter().zip(&x) {
                        let s = t.eval(*i, *i, *i);
                        for end in [i.lo, i.hi] {
                            if end.is_finite() && (*f != F::Ln || end > 0.0) {
                                let r = reference(*f, end);
                                prop_assert!(
                                    r.verdict(o.lo, o.hi) != Verdict::Outside,
                                    "{path}: {i:?} gives {o:?}, beyond {}",
                                    r.describe()
                                );
                            }
                        }
                        let near = |a: f64, b: f64| {
                            a == b
                                || (a - b).abs()
                                    <= 40.0 * f64::EPSILON * a.abs().max(b.abs()) + 2.0 * TRIG_ABS
                        };
                        prop_assert!(
                            near(o.lo, s.lo) && near(o.hi, s.hi),
                            "{path}: {i:?} gives {o:?}, scalar {s:?}"
                        );
                    }
                }
            }
            Ok(())
        },
    );
}
