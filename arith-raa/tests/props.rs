//! Hand-checked forms and property tests of AF1's own formulas (product, square,
//! subtraction) and of the non-affine operations through the shared approximations.

#![allow(clippy::manual_range_contains)] // interval checks read better spelled out

use arith_core::round::{libm_enclose, two_prod, U};
use arith_core::{Range, Real};
use arith_raa::Raa;
use proptest::prelude::*;

fn raa<const N: usize>(x0: f64, xs: [f64; N], acc: f64) -> Raa<N> {
    Raa::new(x0, xs, acc).expect("acc >= 0")
}

/// Whether the exact product `x y` lies in `[lo, hi]` (see arith-revaa's tests).
fn product_in(x: f64, y: f64, (lo, hi): (f64, f64)) -> bool {
    let (p, t) = two_prod(x, y);
    (lo < p || (lo == p && t >= 0.0)) && (hi > p || (hi == p && t <= 0.0))
}

#[test]
fn product_n3_matches_hand_computed_form() {
    // x = 1 + ε1 + 2ε2 + 0.5ε', y = 2 + ε1 - ε2 + 3ε3.
    // centre 2; coefficients (1*1 + 1*2, 1*(-1) + 2*2, 1*3) = (3, 3, 3);
    // acc = |1|*0 + |2|*0.5 + (3 + 0.5)(5 + 0) = 18.5.
    let p = raa(1.0, [1.0, 2.0, 0.0], 0.5) * raa(2.0, [1.0, -1.0, 3.0], 0.0);
    assert_eq!(p.centre(), 2.0);
    assert_eq!(p.coeffs(), &[3.0, 3.0, 3.0]);
    assert!(
        p.acc() >= 18.5 && p.acc() <= 18.5 * (1.0 + 1e-13),
        "acc = {}",
        p.acc()
    );
}

#[test]
fn accumulators_of_different_values_never_cancel() {
    // The paper's |δ + α x_{n+1} + β y_{n+1}| would give acc = 0 here (unsound: the two
    // accumulated errors are unrelated). Ours adds them.
    let x = raa(1.0, [0.5], 0.25);
    let y = raa(1.0, [0.5], 0.25);
    let d = x - y;
    assert_eq!((d.centre(), d.coeffs()[0]), (0.0, 0.0));
    let (lo, hi) = d.bounds();
    assert!(lo <= -0.5 && hi >= 0.5 && hi < 0.5 + 1e-15);
    // The same input minus itself is exactly zero.
    let t = Raa::<1>::input(0, 0.25, 0.75);
    assert_eq!((t - t).bounds(), (0.0, 0.0));
}

#[test]
fn square_of_input_is_the_chebyshev_parallelogram() {
    // x ∈ [1, 3]: x² = 4 + 4ε + [0, 1] -> centre 4.5, coefficient 4, acc = 0.5,
    // where AF1's self-product gives 4 + 4ε ± 1.
    let x = Raa::<1>::input(0, 1.0, 3.0);
    let s = x.sqr();
    assert_eq!((s.centre(), s.coeffs()[0]), (4.5, 4.0));
    assert!(s.acc() >= 0.5 && s.acc() <= 0.5 * (1.0 + 1e-13));
    let p = x * x;
    assert_eq!((p.centre(), p.coeffs()[0]), (4.0, 4.0));
    assert!(p.acc() >= 1.0 && p.acc() <= 1.0 + 1e-13);
}

fn coef() -> impl Strategy<Value = f64> {
    prop_oneof![
        1 => Just(0.0),
        6 => (-1.0f64..1.0, -8i32..8).prop_map(|(m, k)| m * 2f64.powi(k)),
    ]
}
fn acc_term() -> impl Strategy<Value = f64> {
    prop_oneof![
        1 => Just(0.0),
        3 => (0.0f64..1.0, -8i32..4).prop_map(|(m, k)| m * 2f64.powi(k)),
    ]
}
fn form<const N: usize>() -> impl Strategy<Value = (f64, [f64; N], f64)> {
    (coef(), proptest::array::uniform(coef()), acc_term())
}
fn eps_arr<const N: usize>() -> impl Strategy<Value = [f64; N]> {
    proptest::array::uniform(prop_oneof![Just(-1.0), Just(1.0), -1.0f64..1.0])
}

/// A point of the form's value set at input symbols `eps` (accumulator raised above the
/// rounding of the computed centre, so the point provably belongs to the set).
fn point<const N: usize>(x0: f64, xs: &[f64; N], a: &mut f64, eps: &[f64; N], tau: f64) -> f64 {
    let mag = x0.abs() + xs.iter().map(|c| c.abs()).sum::<f64>();
    *a = a.max(16.0 * (N as f64 + 2.0) * U * mag + 1e-300);
    let mut c = x0;
    for i in 0..N {
        c += xs[i] * eps[i];
    }
    c + tau * (*a * 0.5)
}

/// `a ⊆ b` up to 16 ulps of the larger end of `b` (ends that coincide in exact
/// arithmetic are decided by the different rounding bookkeeping only).
fn within(a: (f64, f64), b: (f64, f64)) -> bool {
    let tol = 16.0 * f64::EPSILON * b.0.abs().max(b.1.abs());
    a.0 >= b.0 - tol && a.1 <= b.1 + tol
}

/// The operations with a libm-style reference, each with a domain for its argument.
type UnaryRef = (&'static str, fn(f64) -> f64);

const UNARY: [UnaryRef; 8] = [
    ("sqrt", |v| v.max(0.0).sqrt()),
    ("recip", |v| 1.0 / v),
    ("exp", f64::exp),
    ("ln", |v| if v <= 0.0 { f64::NEG_INFINITY } else { v.ln() }),
    ("sin", f64::sin),
    ("cos", f64::cos),
    ("abs", f64::abs),
    ("cube", |v| v * v * v),
];

fn apply<R: Range>(name: &str, x: &R) -> R {
    match name {
        "sqrt" => x.sqrt(),
        "recip" => x.recip(),
        "exp" => x.exp(),
        "ln" => x.ln(),
        "sin" => x.sin(),
        "cos" => x.cos(),
        "abs" => x.abs(),
        "cube" => x.powi(3),
        _ => unreachable!(),
    }
}

/// `f(x)` for a point `x` of an input range lies in the form's bounds and in its bounds
/// at the point's own symbol value (the libm value is widened to a rigorous
/// enclosure; the cube is exact for the dyadic points used).
fn check_unary<R: Range>(lo: f64, hi: f64, s: f64) -> Result<(), TestCaseError> {
    let x = R::input(0, lo, hi);
    let eps = 2.0 * s - 1.0; // s ∈ [0, 1] dyadic below, so eps and v are exact
    let v = lo + (hi - lo) * s;
    for (name, f) in UNARY {
        let y = apply(name, &x);
        let (flo, fhi) = if name == "cube" || name == "abs" {
            (f(v), f(v))
        } else {
            libm_enclose(f(v))
        };
        for (blo, bhi) in [y.bounds(), y.bounds_at_inputs(&[eps])] {
            prop_assert!(!blo.is_nan() && !bhi.is_nan());
            prop_assert!(
                blo <= fhi && flo <= bhi,
                "{name}({v}) ∈ [{flo}, {fhi}] outside [{blo}, {bhi}]"
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn product_encloses_points_n3(
        (x0, xs, mut ax) in form::<3>(), (y0, ys, mut ay) in form::<3>(),
        eps in eps_arr::<3>(), tx in -1.0f64..1.0, ty in -1.0f64..1.0,
    ) {
        let px = point(x0, &xs, &mut ax, &eps, tx);
        let py = point(y0, &ys, &mut ay, &eps, ty);
        let p = raa(x0, xs, ax) * raa(y0, ys, ay);
        prop_assert!(product_in(px, py, p.bounds_at_inputs(&eps)));
        prop_assert!(product_in(px, py, p.bounds()));
    }

    #[test]
    fn product_encloses_points_n1(
        (x0, xs, mut ax) in form::<1>(), (y0, ys, mut ay) in form::<1>(),
        eps in eps_arr::<1>(), tx in -1.0f64..1.0, ty in -1.0f64..1.0,
    ) {
        let px = point(x0, &xs, &mut ax, &eps, tx);
        let py = point(y0, &ys, &mut ay, &eps, ty);
        let p = raa(x0, xs, ax) * raa(y0, ys, ay);
        prop_assert!(product_in(px, py, p.bounds_at_inputs(&eps)));
    }

    #[test]
    fn square_encloses_points_and_is_not_wider_than_product(
        (x0, xs, mut ax) in form::<3>(), eps in eps_arr::<3>(), tx in -1.0f64..1.0,
    ) {
        let px = point(x0, &xs, &mut ax, &eps, tx);
        let x = raa(x0, xs, ax);
        let s = x.sqr();
        prop_assert!(product_in(px, px, s.bounds_at_inputs(&eps)));
        prop_assert!(within(s.bounds(), (x * x).bounds()), "{:?} vs {:?}", s.bounds(), (x * x).bounds());
        // The width itself is never larger, exactly (sqr falls back to x * x where its
        // gain would be lost in rounding).
        let w = |b: (f64, f64)| b.1 - b.0;
        prop_assert!(w(s.bounds()) <= w((x * x).bounds()));
    }

    #[test]
    fn unary_ops_enclose_points_n1(a in -4096i32..4096, w in 0i32..4096, s in 0i32..=16) {
        let g = |k: i32| k as f64 / 1024.0;
        check_unary::<Raa<1>>(g(a), g(a + w), s as f64 / 16.0)?;
    }

    #[test]
    fn unary_ops_enclose_points_n3(a in -4096i32..4096, w in 0i32..4096, s in 0i32..=16) {
        let g = |k: i32| k as f64 / 1024.0;
        check_unary::<Raa<3>>(g(a), g(a + w), s as f64 / 16.0)?;
    }

    #[test]
    fn min_max_enclose_points(a in -64i32..64, w in 0i32..64, b in -64i32..64, v in 0i32..64,
                              s in 0i32..=4, t in 0i32..=4) {
        let g = |k: i32| k as f64 / 16.0;
        let x = Raa::<3>::input(0, g(a), g(a + w));
        let y = Raa::<3>::input(1, g(b), g(b + v));
        let px = g(a) + g(w) * s as f64 / 4.0;
        let py = g(b) + g(v) * t as f64 / 4.0;
        let eps = [s as f64 / 2.0 - 1.0, t as f64 / 2.0 - 1.0, 0.0];
        for (r, val) in [(x.min(&y), px.min(py)), (x.max(&y), px.max(py))] {
            let (lo, hi) = r.bounds_at_inputs(&eps);
            prop_assert!(lo <= val && val <= hi, "{val} not in [{lo}, {hi}]");
        }
    }
}

/// `from_interval(lo, hi)` and `input(i, lo, hi)`: no NaN part (centre, coefficients,
/// accumulator; Debug shows them all), `acc >= 0`, and bounds holding `[lo, hi]`.
fn check_unbounded_input<const N: usize>(lo: f64, hi: f64, i: usize) -> Result<(), TestCaseError> {
    for x in [Raa::<N>::from_interval(lo, hi), Raa::<N>::input(i, lo, hi)] {
        let nan = x.centre().is_nan() || x.coeffs().iter().any(|c| c.is_nan()) || x.acc().is_nan();
        prop_assert!(
            !nan && !format!("{x:?}").contains("NaN"),
            "[{lo}, {hi}] gave {x:?}"
        );
        prop_assert!(x.acc() >= 0.0, "[{lo}, {hi}] gave {x:?}");
        let (a, b) = x.bounds();
        prop_assert!(a <= lo && hi <= b, "[{lo}, {hi}] not in [{a}, {b}] ({x:?})");
    }
    Ok(())
}

#[test]
fn unbounded_inputs_are_the_unbounded_form() {
    const INF: f64 = f64::INFINITY;
    for (lo, hi) in [
        (1.0, INF),
        (-INF, 1.0),
        (-INF, INF),
        (INF, INF),
        (-INF, -INF),
    ] {
        for i in 0..4 {
            check_unbounded_input::<1>(lo, hi, i).unwrap();
            check_unbounded_input::<3>(lo, hi, i).unwrap();
        }
        assert_eq!(Raa::<3>::from_interval(lo, hi), Raa::<3>::UNBOUNDED);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Any half-line or the whole line gives a sound form without NaN.
    #[test]
    fn unbounded_inputs_never_give_nan((lo, hi) in arith_core::testkit::strategies::range_unbounded(), i in 0usize..4) {
        check_unbounded_input::<1>(lo, hi, i)?;
        check_unbounded_input::<3>(lo, hi, i)?;
    }
}
