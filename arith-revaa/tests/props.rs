//! Hand-checked forms and property tests of RevAA's own formulas (multiplication, square,
//! subtraction), and the comparison with AF1 (`arith-raa`) on the same operands.

#![allow(clippy::manual_range_contains)] // interval checks read better spelled out

use arith_core::round::{libm_enclose, two_prod, U};
use arith_core::{Range, Real};
use arith_raa::Raa;
use arith_revaa::RevAa;
use proptest::prelude::*;

fn rev<const N: usize>(x0: f64, xs: [f64; N], e: f64) -> RevAa<N> {
    RevAa::new(x0, xs, e).expect("e >= 0")
}

/// The exact product `x y` and whether it lies in `[lo, hi]`, using `x y = p + t`
/// exactly (`two_prod`), `|t| <= ulp(p)/2`. `lo < p` implies `lo <= pred(p) <= p + t`.
fn product_in(x: f64, y: f64, (lo, hi): (f64, f64)) -> bool {
    let (p, t) = two_prod(x, y);
    let lo_ok = lo < p || (lo == p && t >= 0.0);
    let hi_ok = hi > p || (hi == p && t <= 0.0);
    lo_ok && hi_ok
}

#[test]
fn product_n1_matches_hand_computed_form() {
    // x = 2 + ε + [-0.5, 0.5], y = 3 + 2ε + [-0.25, 0.25].
    // centre 2*3 + ½*1*2 = 7; coefficient 2*2 + 1*3 = 7;
    // e = 0.5*0.25 + 0.25*(2+1) + 0.5*(3+2) + 1*2 - ½*|1*2| = 4.375.
    let p = rev(2.0, [1.0], 0.5) * rev(3.0, [2.0], 0.25);
    assert_eq!(p.centre(), 7.0);
    assert_eq!(p.coeffs(), &[7.0]);
    assert!(p.err() >= 4.375, "e = {}", p.err());
    // Only rounding allowances on top (relative 1e-13 is thousands of ulps).
    assert!(p.err() <= 4.375 * (1.0 + 1e-13), "e = {}", p.err());
}

#[test]
fn product_n3_matches_hand_computed_form_and_beats_the_papers_radius() {
    // x = 1 + ε1 + 2ε2, y = 2 + ε1 - ε2 + 3ε3 (no error terms).
    // centre 2 + ½(1 - 2 + 0) = 1.5; coefficients (1+2, -1+4, 3+0) = (3, 3, 3);
    // diagonal radius ½(1 + 2 + 0) = 1.5; off-diagonal pairs
    // |x1y2 + x2y1| = |-1 + 2| = 1, |x1y3 + x3y1| = 3, |x2y3 + x3y2| = 6: e = 11.5.
    // The paper's uv - ½Σ|xi yi| = 3*5 - 1.5 = 13.5 is sound but looser.
    let x = rev(1.0, [1.0, 2.0, 0.0], 0.0);
    let y = rev(2.0, [1.0, -1.0, 3.0], 0.0);
    let p = x * y;
    assert_eq!(p.centre(), 1.5);
    assert_eq!(p.coeffs(), &[3.0, 3.0, 3.0]);
    assert!(
        p.err() >= 11.5 && p.err() <= 11.5 * (1.0 + 1e-13),
        "e = {}",
        p.err()
    );
    // Every corner of the input cube (εi = ±1) gives a product inside the form at
    // those inputs: the true product is bilinear per symbol, the corners are extreme.
    for mask in 0..8 {
        let eps: Vec<f64> = (0..3)
            .map(|i| if mask >> i & 1 == 1 { 1.0 } else { -1.0 })
            .collect();
        let xv = 1.0 + eps[0] + 2.0 * eps[1];
        let yv = 2.0 + eps[0] - eps[1] + 3.0 * eps[2];
        assert!(
            product_in(xv, yv, p.bounds_at_inputs(&eps)),
            "corner {eps:?}"
        );
    }
}

#[test]
fn raa_product_hand_computed_and_wider() {
    // AF1 on the N = 1 operands above: centre 6, coefficient 7,
    // acc = 2*0.25 + 3*0.5 + (1 + 0.5)(2 + 0.25) = 5.375.
    let p = Raa::new(2.0, [1.0], 0.5).unwrap() * Raa::new(3.0, [2.0], 0.25).unwrap();
    assert_eq!(p.centre(), 6.0);
    assert_eq!(p.coeffs(), &[7.0]);
    assert!(p.acc() >= 5.375 && p.acc() <= 5.375 * (1.0 + 1e-13));
    let q = rev(2.0, [1.0], 0.5) * rev(3.0, [2.0], 0.25);
    let (ql, qh) = q.bounds();
    let (pl, ph) = p.bounds();
    // RevAA: 7 ± 11.375 = [-4.375, 18.375]; AF1: 6 ± 12.375 = [-6.375, 18.375].
    assert!(
        ql > pl && qh <= ph,
        "revaa {:?} raa {:?}",
        (ql, qh),
        (pl, ph)
    );
}

#[test]
fn self_subtraction_is_exactly_zero_and_independent_is_not() {
    let x = RevAa::<3>::input(0, -1.5, 2.25);
    let y = RevAa::<3>::input(1, -1.5, 2.25);
    assert_eq!((x - x).bounds(), (0.0, 0.0));
    // Exactly ±3.75 up to the cheap rounding allowance of the subtraction (U |z|).
    let (lo, hi) = (x - y).bounds();
    assert!(lo <= -3.75 && lo > -3.75 - 1e-14 && hi >= 3.75 && hi < 3.75 + 1e-14);
    let t = RevAa::<1>::input(0, 0.125, 0.625);
    assert_eq!((t - t).bounds(), (0.0, 0.0));
    // An input without a symbol of its own (i >= N) is not correlated with input 0.
    let z = RevAa::<1>::input(1, 0.125, 0.625);
    let (lo, hi) = (t - z).bounds();
    assert!(lo <= -0.5 && lo > -0.5 - 1e-15 && hi >= 0.5 && hi < 0.5 + 1e-15);
    // A midpoint that is not a float: its rounding goes into e (so that eps = ±1 map to
    // the real ends exactly), and x - x keeps that radius twice.
    let t = RevAa::<1>::input(0, 0.1, 0.7);
    let (lo, hi) = (t - t).bounds();
    assert!(t.err() > 0.0 && t.err() <= 1e-16);
    assert!(lo == -hi && hi >= 2.0 * t.err() && hi <= 2.0 * t.err() * (1.0 + 1e-13));
}

#[test]
fn square_of_input_is_the_chebyshev_parallelogram() {
    // x ∈ [1, 3]: x² = 4 + 4ε + [0, 1] -> centre 4.5, coefficient 4, e = 0.5.
    let s = RevAa::<1>::input(0, 1.0, 3.0).sqr();
    assert_eq!(s.centre(), 4.5);
    assert_eq!(s.coeffs(), &[4.0]);
    assert!(s.err() >= 0.5 && s.err() <= 0.5 * (1.0 + 1e-13));
    let (lo, hi) = s.bounds();
    assert!(lo <= 0.0 && (lo - 0.0).abs() < 1e-12 && hi >= 9.0 && hi < 9.0 + 1e-12);
}

/// Random forms: moderate exponents, some zero coefficients and error terms.
fn coef() -> impl Strategy<Value = f64> {
    prop_oneof![
        1 => Just(0.0),
        6 => (-1.0f64..1.0, -8i32..8).prop_map(|(m, k)| m * 2f64.powi(k)),
    ]
}
fn err_term() -> impl Strategy<Value = f64> {
    prop_oneof![
        1 => Just(0.0),
        3 => (0.0f64..1.0, -8i32..4).prop_map(|(m, k)| m * 2f64.powi(k)),
    ]
}
fn form<const N: usize>() -> impl Strategy<Value = (f64, [f64; N], f64)> {
    (coef(), proptest::array::uniform(coef()), err_term())
}

/// A point of the form's value set at given input symbols `eps`: the computed centre
/// `ĉ ≈ x0 + Σ xi eps_i` moved by `tau * e / 2`. `e` is raised above the rounding of
/// `ĉ` so the point provably lies in `x0 + Σ xi eps_i + [-e, e]`.
fn point<const N: usize>(x0: f64, xs: &[f64; N], e: &mut f64, eps: &[f64; N], tau: f64) -> f64 {
    let mag = x0.abs() + xs.iter().map(|c| c.abs()).sum::<f64>();
    *e = e.max(16.0 * (N as f64 + 2.0) * U * mag + 1e-300);
    let mut c = x0;
    for i in 0..N {
        c += xs[i] * eps[i];
    }
    c + tau * (*e * 0.5)
}

fn eps_arr<const N: usize>() -> impl Strategy<Value = [f64; N]> {
    proptest::array::uniform(prop_oneof![Just(-1.0), Just(1.0), -1.0f64..1.0])
}

/// Bounds of `b` contain those of `a`, up to a rounding allowance of 16 ulps of the
/// larger end's magnitude: the two formulas are ordered in exact arithmetic and can
/// share an end exactly, where only their different rounding-error bookkeeping
/// decides (RevAA's product computes more terms, so it bounds more rounding errors).
fn within(a: (f64, f64), b: (f64, f64)) -> bool {
    let tol = 16.0 * f64::EPSILON * b.0.abs().max(b.1.abs());
    a.0 >= b.0 - tol && a.1 <= b.1 + tol
}

fn width(b: (f64, f64)) -> f64 {
    b.1 - b.0
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
    fn product_encloses_points_n1(
        (x0, xs, mut ex) in form::<1>(), (y0, ys, mut ey) in form::<1>(),
        eps in eps_arr::<1>(), tx in -1.0f64..1.0, ty in -1.0f64..1.0,
    ) {
        let px = point(x0, &xs, &mut ex, &eps, tx);
        let py = point(y0, &ys, &mut ey, &eps, ty);
        let p = rev(x0, xs, ex) * rev(y0, ys, ey);
        prop_assert!(product_in(px, py, p.bounds_at_inputs(&eps)));
        prop_assert!(product_in(px, py, p.bounds()));
    }

    #[test]
    fn product_encloses_points_n3(
        (x0, xs, mut ex) in form::<3>(), (y0, ys, mut ey) in form::<3>(),
        eps in eps_arr::<3>(), tx in -1.0f64..1.0, ty in -1.0f64..1.0,
    ) {
        let px = point(x0, &xs, &mut ex, &eps, tx);
        let py = point(y0, &ys, &mut ey, &eps, ty);
        let p = rev(x0, xs, ex) * rev(y0, ys, ey);
        prop_assert!(product_in(px, py, p.bounds_at_inputs(&eps)));
        prop_assert!(product_in(px, py, p.bounds()));
    }

    /// Points with dyadic coordinates make every value exact, so the extreme points
    /// (all `eps = ±1`, error parts at `±e`) are tested exactly, with no margin.
    #[test]
    fn product_encloses_exact_corners_n3(
        x0 in -64i32..64, xs in proptest::array::uniform3(-64i32..64), ex in 0i32..16,
        y0 in -64i32..64, ys in proptest::array::uniform3(-64i32..64), ey in 0i32..16,
        signs in proptest::array::uniform3(prop_oneof![Just(-1.0), Just(1.0), Just(0.5)]),
        tx in prop_oneof![Just(-1.0), Just(1.0), Just(0.0)],
        ty in prop_oneof![Just(-1.0), Just(1.0), Just(0.0)],
    ) {
        let s = 1.0 / 16.0;
        let f = |a: i32| a as f64 * s;
        let (x0, xs, ex) = (f(x0), xs.map(f), f(ex));
        let (y0, ys, ey) = (f(y0), ys.map(f), f(ey));
        let px = x0 + xs[0] * signs[0] + xs[1] * signs[1] + xs[2] * signs[2] + tx * ex;
        let py = y0 + ys[0] * signs[0] + ys[1] * signs[1] + ys[2] * signs[2] + ty * ey;
        let p = rev(x0, xs, ex) * rev(y0, ys, ey);
        let (lo, hi) = p.bounds_at_inputs(&signs);
        prop_assert!(lo <= px * py && px * py <= hi, "{} not in [{lo}, {hi}]", px * py);
    }

    #[test]
    fn square_encloses_points_and_is_not_wider_than_product_n3(
        (x0, xs, mut ex) in form::<3>(), eps in eps_arr::<3>(), tx in -1.0f64..1.0,
    ) {
        let px = point(x0, &xs, &mut ex, &eps, tx);
        let x = rev(x0, xs, ex);
        let s = x.sqr();
        prop_assert!(product_in(px, px, s.bounds_at_inputs(&eps)));
        prop_assert!(within(s.bounds(), (x * x).bounds()), "{:?} vs {:?}", s.bounds(), (x * x).bounds());
        // The width itself is never larger, exactly (sqr falls back to x * x where its
        // gain would be lost in rounding).
        prop_assert!(width(s.bounds()) <= width((x * x).bounds()));
    }

    #[test]
    fn square_encloses_points_and_is_not_wider_than_product_n1(
        (x0, xs, mut ex) in form::<1>(), eps in eps_arr::<1>(), tx in -1.0f64..1.0,
    ) {
        let px = point(x0, &xs, &mut ex, &eps, tx);
        let x = rev(x0, xs, ex);
        let s = x.sqr();
        prop_assert!(product_in(px, px, s.bounds_at_inputs(&eps)));
        prop_assert!(within(s.bounds(), (x * x).bounds()), "{:?} vs {:?}", s.bounds(), (x * x).bounds());
        prop_assert!(width(s.bounds()) <= width((x * x).bounds()));
    }

    /// For a form with no error term on a ray, the square and the self-product are the
    /// same form in exact arithmetic and are computed identically: never wider, exactly.
    #[test]
    fn square_of_ray_input_never_wider_exactly(lo in -100_000i32..100_000, w in 0i32..50_000) {
        let g = |k: i32| k as f64 / 1024.0;
        let x = RevAa::<1>::input(0, g(lo), g(lo + w));
        prop_assert_eq!(x.err(), 0.0);
        let (s, p) = (x.sqr().bounds(), (x * x).bounds());
        prop_assert!(s.0 >= p.0 && s.1 <= p.1, "{s:?} vs {p:?}");
    }

    #[test]
    fn revaa_product_never_wider_than_raa_n3(
        (x0, xs, ex) in form::<3>(), (y0, ys, ey) in form::<3>(),
    ) {
        let r = (rev(x0, xs, ex) * rev(y0, ys, ey)).bounds();
        let a = (Raa::new(x0, xs, ex).unwrap() * Raa::new(y0, ys, ey).unwrap()).bounds();
        prop_assert!(within(r, a), "revaa {r:?} raa {a:?}");
    }

    #[test]
    fn revaa_product_never_wider_than_raa_n1(
        (x0, xs, ex) in form::<1>(), (y0, ys, ey) in form::<1>(),
    ) {
        let r = (rev(x0, xs, ex) * rev(y0, ys, ey)).bounds();
        let a = (Raa::new(x0, xs, ex).unwrap() * Raa::new(y0, ys, ey).unwrap()).bounds();
        prop_assert!(within(r, a), "revaa {r:?} raa {a:?}");
    }

    /// `x - x` keeps only the input's own rounding radius, counted twice (the radius is
    /// an independent error interval); with an exactly representable midpoint and
    /// radius (a grid of dyadic bounds) that is exactly `[0, 0]`.
    #[test]
    fn self_difference_of_inputs(lo in -1e6f64..1e6, w in 0.0f64..1e6, i in 0usize..3,
                                 a in -1_000_000i64..1_000_000, b in 0i64..1_000_000) {
        let x = RevAa::<3>::input(i, lo, lo + w);
        let (dl, dh) = (x - x).bounds();
        prop_assert!(dl <= 0.0 && dh >= 0.0);
        prop_assert!(dh <= 2.0 * x.err() * (1.0 + 1e-13) && dl == -dh);
        prop_assert!(x.err() <= 2.0 * f64::EPSILON * (lo.abs() + w));
        let g = |k: i64| k as f64 / 1024.0;
        let x = RevAa::<3>::input(i, g(a), g(a + b));
        prop_assert_eq!((x - x).bounds(), (0.0, 0.0));
        prop_assert_eq!((-x + x).bounds(), (0.0, 0.0));
        let t = RevAa::<1>::input(0, g(a), g(a + b));
        prop_assert_eq!((t - t).bounds(), (0.0, 0.0));
    }

    #[test]
    fn unary_ops_enclose_points_n1(a in -4096i32..4096, w in 0i32..4096, s in 0i32..=16) {
        let g = |k: i32| k as f64 / 1024.0;
        check_unary::<RevAa<1>>(g(a), g(a + w), s as f64 / 16.0)?;
    }

    #[test]
    fn unary_ops_enclose_points_n3(a in -4096i32..4096, w in 0i32..4096, s in 0i32..=16) {
        let g = |k: i32| k as f64 / 1024.0;
        check_unary::<RevAa<3>>(g(a), g(a + w), s as f64 / 16.0)?;
    }

    #[test]
    fn min_max_enclose_points(a in -64i32..64, w in 0i32..64, b in -64i32..64, v in 0i32..64,
                              s in 0i32..=4, t in 0i32..=4) {
        let g = |k: i32| k as f64 / 16.0;
        let x = RevAa::<3>::input(0, g(a), g(a + w));
        let y = RevAa::<3>::input(1, g(b), g(b + v));
        let px = g(a) + g(w) * s as f64 / 4.0;
        let py = g(b) + g(v) * t as f64 / 4.0;
        let eps = [s as f64 / 2.0 - 1.0, t as f64 / 2.0 - 1.0, 0.0];
        for (r, val) in [(x.min(&y), px.min(py)), (x.max(&y), px.max(py))] {
            let (lo, hi) = r.bounds_at_inputs(&eps);
            prop_assert!(lo <= val && val <= hi, "{val} not in [{lo}, {hi}]");
        }
    }
}

/// Any `f64` an affine form can hold: ordinary, tiny, huge (near overflow), zero.
fn any_part() -> impl Strategy<Value = f64> {
    prop_oneof![
        -4.0..4.0f64,
        (-1.0..1.0f64, -1075i32..1024).prop_map(|(m, e)| m * 2f64.powi(e)),
        Just(0.0),
        Just(f64::MAX),
        Just(-f64::MAX),
    ]
}

proptest! {
    /// `contains_zero` (computed without the bounds) says exactly whether
    /// `0 ∈ bounds()`, for RevAA and RAA* alike, overflow and subnormals included.
    #[test]
    fn contains_zero_is_zero_in_bounds(
        x0 in any_part(),
        xs in proptest::array::uniform3(any_part()),
        e in any_part(),
    ) {
        let e = e.abs();
        let zero_in = |(lo, hi): (f64, f64)| lo <= 0.0 && 0.0 <= hi;
        let r = rev(x0, xs, e);
        prop_assert_eq!(r.contains_zero(), zero_in(r.bounds()), "{:?} {:?}", r, r.bounds());
        let r1 = rev(x0, [xs[0]], e);
        prop_assert_eq!(r1.contains_zero(), zero_in(r1.bounds()), "{:?}", r1);
        let a = Raa::new(x0, xs, e).unwrap();
        prop_assert_eq!(a.contains_zero(), zero_in(a.bounds()), "{:?} {:?}", a, a.bounds());
    }
}

proptest! {
    /// The square of a cell's input (one coefficient, no error term) gains nothing over
    /// `x * x` and is `x * x` bit for bit, computed without the (zero) cross terms.
    #[test]
    fn square_of_an_input_is_the_product_bit_for_bit(
        i in 0usize..3,
        a in any_part(),
        b in any_part(),
    ) {
        let x = RevAa::<3>::input(i, a.min(b), a.max(b));
        let (s, p) = (x.sqr(), x * x);
        prop_assert_eq!(s, p, "{:?}", x);
    }
}

/// `from_interval(lo, hi)` and `input(i, lo, hi)`: no NaN part (centre, coefficients,
/// error term; Debug shows them all), `e >= 0`, and bounds holding `[lo, hi]`.
fn check_unbounded_input<const N: usize>(lo: f64, hi: f64, i: usize) -> Result<(), TestCaseError> {
    for x in [
        RevAa::<N>::from_interval(lo, hi),
        RevAa::<N>::input(i, lo, hi),
    ] {
        let nan = x.centre().is_nan() || x.coeffs().iter().any(|c| c.is_nan()) || x.err().is_nan();
        prop_assert!(
            !nan && !format!("{x:?}").contains("NaN"),
            "[{lo}, {hi}] gave {x:?}"
        );
        prop_assert!(x.err() >= 0.0, "[{lo}, {hi}] gave {x:?}");
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
        assert_eq!(RevAa::<3>::from_interval(lo, hi), RevAa::<3>::UNBOUNDED);
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
