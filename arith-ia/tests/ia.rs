//! Interval-specific behaviour: outward rounding, the whole line for division by a
//! range holding 0, clipping of even powers, exact min/max, and no NaN with infinities.

use arith_core::testkit::proptest::prelude::*;
use arith_core::testkit::{strategies, Mp, Verdict};
use arith_core::{Arithmetic, Range, Real};
use arith_ia::{IaArith, Interval};

const INF: f64 = f64::INFINITY;

fn iv(lo: f64, hi: f64) -> Interval {
    Interval::new(lo, hi)
}

#[test]
fn names() {
    assert_eq!(<IaArith as Arithmetic>::NAME, "ia");
    assert_eq!(IaArith::LABEL, "IA");
    assert_eq!(<Interval as Range>::NAME, "ia");
}

#[test]
fn outward_rounding_is_visible() {
    let s = Interval::constant(0.1) + Interval::constant(0.2);
    assert!(s.lo < s.hi, "0.1 + 0.2 is inexact: the bounds must differ");
    // The real number 3/10, enclosed rigorously.
    let three_tenths = Mp::point(3.0)
        .unwrap()
        .div(&Mp::point(10.0).unwrap())
        .unwrap();
    assert_eq!(three_tenths.verdict(s.lo, s.hi), Verdict::Inside);
    // The exact sum of the two doubles lies strictly below the rounded sum, so the
    // lower bound had to move below fl(0.1 + 0.2).
    assert!(s.lo < 0.1 + 0.2);
    // 1/3 is bracketed by adjacent floats.
    let t = Interval::constant(1.0) / 3.0;
    assert_eq!(t.lo.next_up(), t.hi);
    let exact = Mp::point(1.0)
        .unwrap()
        .div(&Mp::point(3.0).unwrap())
        .unwrap();
    assert_eq!(exact.verdict(t.lo, t.hi), Verdict::Inside);
}

#[test]
fn exact_operations_stay_tight() {
    assert_eq!(iv(1.0, 2.0) + iv(3.0, 4.0), iv(4.0, 6.0));
    assert_eq!(iv(1.0, 2.0) - iv(3.0, 4.0), iv(-3.0, -1.0));
    assert_eq!(iv(1.0, 2.0) * iv(-3.0, 4.0), iv(-6.0, 8.0));
    assert_eq!(iv(1.0, 2.0) / iv(4.0, 8.0), iv(0.125, 0.5));
    assert_eq!(iv(-1.5, 2.0) * 2.0, iv(-3.0, 4.0));
    assert_eq!(2.0 * iv(-1.5, 2.0), iv(-3.0, 4.0));
    assert_eq!(1.0 - iv(-1.5, 2.0), iv(-1.0, 2.5));
    assert_eq!(3.0 + iv(-1.5, 2.0), iv(1.5, 5.0));
    assert_eq!(1.0 / iv(2.0, 4.0), iv(0.25, 0.5));
    assert_eq!(iv(2.0, 4.0).recip(), iv(0.25, 0.5));
}

#[test]
fn division_by_a_range_holding_zero_is_the_whole_line() {
    let whole = (-INF, INF);
    for d in [
        iv(-1.0, 1.0),
        iv(0.0, 1.0),
        iv(-1.0, 0.0),
        iv(0.0, 0.0),
        iv(-0.0, 0.0),
    ] {
        assert_eq!((iv(1.0, 2.0) / d).bounds(), whole, "{d:?}");
        assert_eq!(d.recip().bounds(), whole, "{d:?}");
        assert_eq!(d.rdiv(1.0).bounds(), whole);
    }
    assert_eq!((iv(1.0, 2.0) / 0.0).bounds(), whole);
    assert_eq!(iv(1.0, 2.0).rdiv(0.0), iv(0.0, 0.0));
    assert_eq!((iv(1.0, 2.0) / -0.0).bounds(), whole);
}

#[test]
fn even_powers_of_ranges_across_zero_start_at_zero() {
    assert_eq!(iv(-2.0, 3.0).sqr(), iv(0.0, 9.0));
    assert_eq!(iv(-3.0, 2.0).sqr(), iv(0.0, 9.0));
    assert_eq!(iv(-2.0, 3.0).powi(4), iv(0.0, 81.0));
    assert_eq!(iv(-2.0, 3.0).powi(3), iv(-8.0, 27.0));
    assert_eq!(iv(-3.0, -2.0).powi(3), iv(-27.0, -8.0));
    assert_eq!(iv(-3.0, -2.0).sqr(), iv(4.0, 9.0));
    assert_eq!(iv(-2.0, 3.0).powi(0), iv(1.0, 1.0));
    assert_eq!(iv(-2.0, 3.0).powi(1), iv(-2.0, 3.0));
    // Negative even power: positive wherever defined, unbounded above.
    assert_eq!(iv(-2.0, 4.0).powi(-2), iv(1.0 / 16.0, INF));
    assert_eq!(iv(2.0, 4.0).powi(-2), iv(1.0 / 16.0, 0.25));
    // Negative odd power across 0: the whole line.
    assert_eq!(iv(-2.0, 4.0).powi(-3).bounds(), (-INF, INF));
    // Negative even power of exactly 0: within every `[1/h^2, inf)` of a range `[0, h]`.
    assert_eq!(iv(0.0, 0.0).powi(-2), iv(f64::MAX, INF));
    assert_eq!(iv(-0.0, 0.0).powi(-4), iv(f64::MAX, INF));
    assert_eq!(iv(0.0, 0.0).powi(-3).bounds(), (-INF, INF));
    // abs
    assert_eq!(iv(-2.0, 3.0).abs(), iv(0.0, 3.0));
    assert_eq!(iv(-5.0, -3.0).abs(), iv(3.0, 5.0));
}

#[test]
fn min_max_are_exact() {
    assert_eq!(iv(1.0, 4.0).min(&iv(2.0, 3.0)), iv(1.0, 3.0));
    assert_eq!(iv(1.0, 4.0).max(&iv(2.0, 3.0)), iv(2.0, 4.0));
    assert_eq!(iv(0.1, 0.7).min(&iv(0.3, 0.5)), iv(0.1, 0.5));
}

#[test]
fn dependency_problem_is_visible() {
    // Intervals do not know that both operands are the same x.
    let x = Interval::input(0, 0.0, 1.0);
    assert_eq!(x - x, iv(-1.0, 1.0));
    assert_eq!(x * x, iv(0.0, 1.0));
    let y = Interval::input(0, -1.0, 1.0);
    assert_eq!(y * y, iv(-1.0, 1.0));
    assert_eq!(y.sqr(), iv(0.0, 1.0));
    assert_eq!(x.linear_part(), None);
    assert_eq!(x.bounds_at_inputs(&[0.5]), x.bounds());
}

#[test]
fn bad_constructor_input_is_made_safe() {
    assert_eq!(Interval::new(2.0, 1.0), iv(1.0, 2.0));
    assert_eq!(Interval::new(f64::NAN, 1.0), Interval::ENTIRE);
    assert_eq!(Interval::constant(f64::NAN), Interval::ENTIRE);
    assert!(Interval::ENTIRE.is_entire());
    assert!(iv(1.0, 2.0).contains(1.5) && !iv(1.0, 2.0).contains(2.5));
    assert_eq!(iv(1.0, 3.0).width(), 2.0);
    assert_eq!(Interval::ENTIRE.width(), INF);
}

#[test]
fn overflow_gives_infinite_bounds() {
    // e^710 > f64::MAX: the largest float is the tightest sound lower bound.
    assert_eq!(iv(710.0, 720.0).exp(), iv(f64::MAX, INF));
    let p = iv(1e200, 1e201) * iv(1e200, 1e201);
    assert_eq!(p, iv(f64::MAX, INF));
    let s = iv(f64::MAX, f64::MAX) + iv(f64::MAX, f64::MAX);
    assert_eq!(s, iv(f64::MAX, INF));
    assert_eq!(iv(-1.0, 1e300).powi(3).hi, INF);
}

/// `e^x` against `f64::MAX = 2^1024 (1 - 2^-53)`, decided exactly: `e^x = 2^1024 e^t` with
/// `t = x - 1024 ln 2`, and `d = x - 1024 LN_2` is exact (Sterbenz) and within `2^-44` of
/// `t` (`|LN_2 - ln 2| <= 2^-54`). `Some(true)`: `e^x > 2^1024 > MAX` (`t > 0`);
/// `Some(false)`: `e^x < MAX` (`t < -2^-52 < ln(1 - 2^-53)`); `None`: too close to tell.
fn exp_exceeds_max(x: f64) -> Option<bool> {
    let d = x - 1024.0 * core::f64::consts::LN_2;
    let slack = 2f64.powi(-44);
    if d - slack > 0.0 {
        Some(true)
    } else if d + slack < -(2f64.powi(-52)) {
        Some(false)
    } else {
        None
    }
}

/// `exp` of ranges at and past the overflow threshold `ln(MAX) = 709.7827..`: the lower
/// bound is `f64::MAX` once `e^lo > MAX` (the largest float not above it), and below the
/// threshold a finite enclosure of `e^lo` (checked in multi-precision); never 0.
#[test]
fn exp_lower_bound_is_tight_near_overflow() {
    assert_eq!(exp_exceeds_max(709.78), Some(false));
    assert_eq!(exp_exceeds_max(709.79), Some(true));
    // The first float past ln(MAX): its `e^x` already exceeds MAX.
    let first_over = (1024.0 * core::f64::consts::LN_2).next_up();
    assert_eq!(exp_exceeds_max(first_over), Some(true));
    // The float before it, `1024 LN_2` itself, is too close for that argument; the
    // multi-precision reference decides: `e^x < MAX` (by about 2^-45 of it).
    assert_eq!(exp_exceeds_max(first_over.next_down()), None);
    let below = Mp::point(first_over.next_down()).unwrap().exp().unwrap();
    assert_eq!(below.verdict(0.0, f64::MAX), Verdict::Inside);
    // And the reference agrees with the decided facts.
    for (x, over) in [(709.78, false), (709.79, true), (first_over, true)] {
        let v = if over {
            Verdict::Outside
        } else {
            Verdict::Inside
        };
        assert_eq!(
            Mp::point(x).unwrap().exp().unwrap().verdict(0.0, f64::MAX),
            v,
            "{x}"
        );
    }
    for (lo, hi) in [
        (709.7, 709.78),
        (709.78, 710.0),
        (first_over.next_down(), 709.79),
        (first_over, first_over),
        (709.79, 709.8),
        (710.0, 800.0),
        (1e300, f64::MAX),
        (709.0, INF),
        (INF, INF),
    ] {
        let e = iv(lo, hi).exp();
        assert_no_nan(e, &format!("exp [{lo}, {hi}]"));
        match exp_exceeds_max(lo) {
            Some(true) => assert_eq!(e.lo, f64::MAX, "exp [{lo}, {hi}] = {e:?}"),
            _ => {
                // Sound, and within the libm margin (a few ulps) of e^lo.
                let exact = Mp::point(lo).unwrap().exp().unwrap();
                assert_ne!(
                    exact.verdict(e.lo, INF),
                    Verdict::Outside,
                    "exp [{lo}, {hi}] = {e:?}"
                );
                assert_eq!(
                    exact.verdict(-INF, e.lo * (1.0 + 1e-14)),
                    Verdict::Inside,
                    "{e:?}"
                );
            }
        }
        match exp_exceeds_max(hi) {
            Some(true) => assert_eq!(e.hi, INF),
            _ => assert!(e.hi.is_finite(), "exp [{lo}, {hi}] = {e:?}"),
        }
    }
}

/// Intervals with infinite and zero bounds, as operations on overflowed or degenerate
/// results produce them.
fn specials() -> Vec<Interval> {
    vec![
        Interval::ENTIRE,
        iv(-INF, -INF),
        iv(INF, INF),
        iv(-INF, 0.0),
        iv(0.0, INF),
        iv(f64::MAX, INF),
        iv(-INF, -1.0),
        iv(0.0, 0.0),
        iv(-0.0, -0.0),
        iv(-1.0, 1.0),
        iv(2.0, 3.0),
        iv(-f64::MAX, f64::MAX),
        iv(5e-324, 5e-324),
    ]
}

fn assert_no_nan(r: Interval, what: &str) {
    assert!(
        !r.lo.is_nan() && !r.hi.is_nan() && r.lo <= r.hi,
        "{what} = {r:?}"
    );
}

#[test]
fn no_nan_with_infinities() {
    let cs = [0.0, -0.0, 1.0, -2.5, INF, -INF, f64::MAX];
    for a in specials() {
        for f in [
            Real::sqr,
            Real::sqrt,
            Real::recip,
            Real::exp,
            Real::ln,
            Real::sin,
            Real::cos,
            Real::abs,
        ] {
            assert_no_nan(f(&a), &format!("unary on {a:?}"));
        }
        for n in -4..=5 {
            assert_no_nan(a.powi(n), &format!("{a:?}.powi({n})"));
        }
        assert_no_nan(-a, &format!("-{a:?}"));
        for c in cs {
            assert_no_nan(a + c, &format!("{a:?} + {c}"));
            assert_no_nan(a - c, &format!("{a:?} - {c}"));
            assert_no_nan(a * c, &format!("{a:?} * {c}"));
            assert_no_nan(a / c, &format!("{a:?} / {c}"));
            assert_no_nan(c - a, &format!("{c} - {a:?}"));
            assert_no_nan(c / a, &format!("{c} / {a:?}"));
        }
        for b in specials() {
            assert_no_nan(a + b, &format!("{a:?} + {b:?}"));
            assert_no_nan(a - b, &format!("{a:?} - {b:?}"));
            assert_no_nan(a * b, &format!("{a:?} * {b:?}"));
            assert_no_nan(a / b, &format!("{a:?} / {b:?}"));
            assert_no_nan(a.min(&b), &format!("min {a:?} {b:?}"));
            assert_no_nan(a.max(&b), &format!("max {a:?} {b:?}"));
        }
    }
    // `inf - inf` gives the whole line, not a NaN or a guess; an exact 0 times any set
    // of reals is exactly 0 (no member of an interval is infinite).
    assert_eq!(iv(-INF, -INF) + iv(INF, INF), Interval::ENTIRE);
    assert_eq!(iv(0.0, 0.0) * Interval::ENTIRE, iv(0.0, 0.0));
    assert_eq!(iv(INF, INF) * 0.0, iv(0.0, 0.0));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, failure_persistence: None, ..ProptestConfig::default() })]

    /// Sums, products and quotients of two points: the bounds are adjacent floats or
    /// equal, and hold the exact result (checked rigorously).
    #[test]
    fn point_ops_are_tight_and_sound(a in strategies::any_finite(), b in strategies::any_finite()) {
        let (x, y) = (Interval::constant(a), Interval::constant(b));
        let cases = [
            (x + y, Mp::point(a).unwrap().add(&Mp::point(b).unwrap())),
            (x * y, Mp::point(a).unwrap().mul(&Mp::point(b).unwrap())),
            (x / y, Mp::point(a).unwrap().div(&Mp::point(b).unwrap())),
        ];
        for (r, exact) in cases {
            let Some(exact) = exact else { continue };
            prop_assert_ne!(exact.verdict(r.lo, r.hi), Verdict::Outside, "{:?} vs {}", r, exact.describe());
            if r.lo.is_finite() && r.hi.is_finite() {
                // At most one ulp apart: rounding moved only one bound, by one step.
                prop_assert!(r.lo == r.hi || r.lo.next_up() == r.hi, "{:?}", r);
            }
        }
    }

    /// Results only ever get wider when an operand gets wider (inclusion isotonicity).
    #[test]
    fn inclusion_isotone(
        (a, b) in strategies::range_any(),
        (c, d) in strategies::range_any(),
        t in 0.0..=1.0f64,
    ) {
        let x = iv(a, b);
        let y = iv(c, d);
        let m = (a * (1.0 - t) + b * t).clamp(a, b);
        let sub = iv(m, m);
        for (wide, narrow) in [
            (x + y, sub + y), (x - y, sub - y), (x * y, sub * y), (x / y, sub / y),
            (x.sqr(), sub.sqr()), (x.abs(), sub.abs()), (x.recip(), sub.recip()),
            (x.powi(3), sub.powi(3)), (x.powi(-2), sub.powi(-2)),
        ] {
            prop_assert!(wide.lo <= narrow.lo && narrow.hi <= wide.hi, "{:?} not within {:?}", narrow, wide);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, failure_persistence: None, ..ProptestConfig::default() })]

    /// `from_interval(lo, hi)` and `input(i, lo, hi)` of a half-line or the whole line:
    /// exactly `[lo, hi]`, no NaN bound.
    #[test]
    fn unbounded_inputs_never_give_nan((lo, hi) in arith_core::testkit::strategies::range_unbounded(), i in 0usize..4) {
        for x in [Interval::from_interval(lo, hi), Interval::input(i, lo, hi)] {
            prop_assert!(!format!("{x:?}").contains("NaN"), "{:?}", x);
            prop_assert_eq!(x.bounds(), (lo, hi));
        }
    }
}

/// The product picks two of the four endpoint products by the factors' signs; it is
/// never wider than the hull of all four, rounded the same way, infinite bounds and
/// zeros included.
#[test]
fn product_by_signs_is_never_wider_than_the_four_products() {
    use arith_core::round::{mul_hi, mul_lo};
    let bound = prop_oneof![
        4 => -8.0..8.0f64,
        1 => Just(0.0),
        1 => Just(-0.0),
        1 => Just(INF),
        1 => Just(-INF),
    ];
    let s = (bound.clone(), bound.clone(), bound.clone(), bound);
    arith_core::testkit::checks::run("ia mul by signs", 4000, s, |(a, b, c, d)| {
        let (x, y) = (iv(a, b), iv(c, d));
        let p = x * y;
        let ends = [(x.lo, y.lo), (x.lo, y.hi), (x.hi, y.lo), (x.hi, y.hi)];
        let lo = ends
            .map(|(u, v)| mul_lo(u, v))
            .into_iter()
            .filter(|v| !v.is_nan())
            .fold(INF, f64::min);
        let hi = ends
            .map(|(u, v)| mul_hi(u, v))
            .into_iter()
            .filter(|v| !v.is_nan())
            .fold(-INF, f64::max);
        prop_assert!(!p.lo.is_nan() && !p.hi.is_nan(), "{x:?} * {y:?} = {p:?}");
        prop_assert!(
            lo <= p.lo && p.hi <= hi,
            "{x:?} * {y:?} = {p:?}, four give [{lo}, {hi}]"
        );
        Ok(())
    });
}

/// `[inf, inf]` holds no real number; its products and quotients lie within those of
/// every half-line that holds it, so a narrower operand never gives a wider result.
#[test]
fn infinite_points_stay_within_half_lines() {
    let ln0 = iv(0.0, 0.0).ln();
    assert_eq!(ln0, iv(-INF, -INF));
    for (narrow, wide) in [
        (ln0 * iv(-1.6, 0.0), iv(-INF, 0.5) * iv(-1.6, 0.0)),
        (ln0 * iv(0.0, 0.6), iv(-INF, -0.2) * iv(0.0, 0.6)),
        (ln0 * iv(-0.0, -0.0), iv(-INF, -0.2) * iv(-0.0, -0.0)),
        (iv(-0.0, -0.0) * ln0, iv(-0.0, -0.0) * iv(-INF, -0.2)),
        (ln0 / -ln0, iv(-INF, -13.8) / -ln0),
        (iv(-2.0, 3.0) / -ln0, iv(-2.0, 3.0) / iv(1.0, INF)),
    ] {
        assert!(
            wide.lo <= narrow.lo && narrow.hi <= wide.hi,
            "{narrow:?} not within {wide:?}"
        );
    }
    assert_eq!(ln0 * iv(-1.6, 0.0), iv(0.0, INF));
    // An exact 0 times a half-line: 0, within any range around 0 times it.
    for zero in [iv(0.0, 0.0), iv(-0.0, -0.0)] {
        assert_eq!(iv(-INF, 0.0) * zero, iv(0.0, 0.0));
        assert_eq!(zero * Interval::ENTIRE, iv(0.0, 0.0));
        assert_eq!(iv(-INF, 0.0) * 0.0, iv(0.0, 0.0));
    }
    assert_eq!(iv(-2.0, 3.0) / -ln0, iv(0.0, 0.0));
}
