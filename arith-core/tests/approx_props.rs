//! Property tests of `arith_core::approx`: every affine approximation and every range
//! enclosure must contain the real function value, computed at 256 bits with
//! `astro-float`, at random points of random intervals (zero width, straddling 0, tiny
//! and huge magnitudes, domain edges, wide and large trig arguments), and no function may
//! ever return NaN.

use arith_core::approx::{self, Approx};
use astro_float::{BigFloat, Consts, RoundingMode};
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

const P: usize = 256;
const RM: RoundingMode = RoundingMode::ToEven;
/// Precision of the affine evaluation `alpha*x + zeta ± delta`: any sum of products of
/// f64 values spans fewer than `2*1024 + 2*1074 + 106` bits, so these are exact.
const PA: usize = 4416;

#[derive(Clone, Copy, Debug, PartialEq)]
enum F {
    Sqr,
    Pow(i32),
    Sqrt,
    Recip,
    Exp,
    Ln,
    Sin,
    Cos,
    Abs,
}

/// The reference value at a finite `x`: `Some(v)` (256 bits), or `None` where the real
/// function has no finite value (`1/0`, `ln` of `x <= 0`, `e^x` beyond the reference's
/// reach). Huge exponentials are reported through [`Ref`].
enum Ref {
    Val(BigFloat),
    /// `ln x` for `x <= 0`: `-inf` by the extended definition.
    NegInf,
    /// `1/0`, `x^-n` at 0: no real value.
    Undefined,
    /// `e^x` with `x > 1e5`: above `f64::MAX`.
    Huge,
    /// `e^x` with `x < -1e5`: in `(0, 2^-1074)`.
    Tiny,
}

/// `x` exactly. astro-float's `from_f64` misreads subnormals, so those are scaled into
/// the normal range first and scaled back exactly.
fn big(x: f64) -> BigFloat {
    if x != 0.0 && x.abs() < f64::MIN_POSITIVE {
        let two64 = 18_446_744_073_709_551_616.0;
        BigFloat::from_f64(x * two64, P).div(&BigFloat::from_f64(two64, P), P, RM)
    } else {
        BigFloat::from_f64(x, P)
    }
}

#[test]
fn big_reads_subnormals_exactly() {
    let tiny = f64::from_bits(1);
    // 2^-1074 * 2^1074 = 1, and 3 * 2^-1074 is three times the smallest subnormal.
    let scaled = big(tiny).mul(&BigFloat::from_f64(2f64.powi(537), P), P, RM);
    let one = scaled.mul(&BigFloat::from_f64(2f64.powi(537), P), P, RM);
    assert!(matches!(one.cmp(&big(1.0)), Some(0)));
    let three = big(3.0 * tiny).div(&big(tiny), P, RM);
    assert!(matches!(three.cmp(&big(3.0)), Some(0)));
}

fn reference(f: F, x: f64, cc: &mut Consts) -> Ref {
    let bx = big(x);
    Ref::Val(match f {
        F::Sqr => bx.mul(&bx, P, RM),
        F::Pow(n) if n >= 0 => bx.powi(n as usize, P, RM),
        F::Pow(n) => {
            if x == 0.0 {
                return Ref::Undefined;
            }
            bx.powi(n.unsigned_abs() as usize, P, RM).reciprocal(P, RM)
        }
        F::Sqrt => {
            if x <= 0.0 {
                big(0.0)
            } else {
                bx.sqrt(P, RM)
            }
        }
        F::Recip => {
            if x == 0.0 {
                return Ref::Undefined;
            }
            bx.reciprocal(P, RM)
        }
        F::Exp => {
            if x > 1e5 {
                return Ref::Huge;
            }
            if x < -1e5 {
                return Ref::Tiny;
            }
            bx.exp(P, RM, cc)
        }
        F::Ln => {
            if x <= 0.0 {
                return Ref::NegInf;
            }
            bx.ln(P, RM, cc)
        }
        F::Sin => bx.sin(P, RM, cc),
        F::Cos => bx.cos(P, RM, cc),
        F::Abs => bx.abs(),
    })
}

fn le(x: &BigFloat, y: &BigFloat) -> bool {
    matches!(x.cmp(y), Some(c) if c <= 0)
}

fn approx_of(f: F, a: f64, b: f64) -> Approx {
    match f {
        F::Sqr => approx::sqr(a, b),
        F::Pow(n) => approx::powi(a, b, n),
        F::Sqrt => approx::sqrt(a, b),
        F::Recip => approx::recip(a, b),
        F::Exp => approx::exp(a, b),
        F::Ln => approx::ln(a, b),
        F::Sin => approx::sin(a, b),
        F::Cos => approx::cos(a, b),
        F::Abs => approx::abs(a, b),
    }
}

/// The rigorous range function for `f`, where there is one.
fn range_of(f: F, a: f64, b: f64) -> Option<(f64, f64)> {
    Some(match f {
        F::Sqr => approx::range_powi(a, b, 2),
        F::Pow(n) => approx::range_powi(a, b, n),
        F::Recip => approx::range_powi(a, b, -1),
        F::Sqrt => approx::range_sqrt(a, b),
        F::Exp => approx::range_exp(a, b),
        F::Ln => approx::range_ln(a, b),
        F::Sin => approx::range_sin(a, b),
        F::Cos => approx::range_cos(a, b),
        F::Abs => return None,
    })
}

/// Checks the approximation and the range of `f` on `[a, b]` at the real point `x`.
fn check_point(f: F, a: f64, b: f64, x: f64, cc: &mut Consts) -> Result<(), String> {
    assert!(x.is_finite() && a <= x && x <= b);
    let ap = approx_of(f, a, b);
    let rg = range_of(f, a, b);
    let ctx = || format!("{f:?} on [{a:e}, {b:e}] at x = {x:e}: {ap:?}, range {rg:?}");
    let r = reference(f, x, cc);
    if !ap.is_entire() {
        // (astro-float's *_full_prec mishandle zero operands; PA bits are exact here.)
        let ax = big(ap.alpha).mul(&big(x), PA, RM);
        let centre = ax.add(&big(ap.zeta), PA, RM);
        let lo = centre.sub(&big(ap.delta), PA, RM);
        let hi = centre.add(&big(ap.delta), PA, RM);
        match &r {
            Ref::Val(v) => {
                if !(le(&lo, v) && le(v, &hi)) {
                    return Err(format!("approx misses f(x): {}", ctx()));
                }
            }
            Ref::Tiny => {
                // 0 < e^x < 2^-1074: the upper line must be > 0, the lower <= any such value.
                if !le(&lo, &big(0.0)) || le(&hi, &big(0.0)) {
                    return Err(format!("approx misses tiny e^x: {}", ctx()));
                }
            }
            _ => return Err(format!("bounded approx where f is unbounded: {}", ctx())),
        }
    }
    if let Some((rlo, rhi)) = rg {
        if rlo.is_nan() || rhi.is_nan() {
            return Err(format!("NaN range: {}", ctx()));
        }
        let ok = match &r {
            Ref::Val(v) => {
                (rlo == f64::NEG_INFINITY || le(&big(rlo), v))
                    && (rhi == f64::INFINITY || le(v, &big(rhi)))
            }
            Ref::NegInf => rlo == f64::NEG_INFINITY,
            Ref::Undefined => rhi == f64::INFINITY,
            Ref::Huge => rhi == f64::INFINITY,
            Ref::Tiny => rlo <= 0.0 && rhi > 0.0,
        };
        if !ok {
            return Err(format!("range misses f(x): {}", ctx()));
        }
    }
    Ok(())
}

const ALL: [F; 13] = [
    F::Sqr,
    F::Pow(3),
    F::Pow(4),
    F::Pow(5),
    F::Pow(-1),
    F::Pow(-2),
    F::Sqrt,
    F::Recip,
    F::Exp,
    F::Ln,
    F::Sin,
    F::Cos,
    F::Abs,
];

/// A real point of `[a, b]` chosen by `t ∈ [0, 1]`; `None` when there is none.
fn point_in(a: f64, b: f64, t: f64) -> Option<f64> {
    let x = match (a.is_finite(), b.is_finite()) {
        (true, true) => {
            let w = b - a;
            if w.is_finite() {
                a + t * w
            } else {
                a * (1.0 - t) + b * t
            }
        }
        (true, false) => a + 10f64.powf(300.0 * t) - 1.0,
        (false, true) => b - 10f64.powf(300.0 * t) + 1.0,
        (false, false) => (t - 0.5) * 1e300,
    };
    let x = x.clamp(a, b);
    x.is_finite().then_some(x)
}

fn check_interval(fs: &[F], a: f64, b: f64, ts: &[f64]) -> Result<(), String> {
    let mut cc = Consts::new().expect("astro-float constants");
    for &f in fs {
        for &t in ts {
            if let Some(x) = point_in(a, b, t) {
                check_point(f, a, b, x, &mut cc)?;
            }
        }
    }
    Ok(())
}

/// `m * 10^e` with a random sign: magnitudes from subnormal to near `f64::MAX`.
fn sci(emin: i32, emax: i32) -> impl Strategy<Value = f64> {
    (any::<bool>(), 1.0..10.0f64, emin..=emax).prop_map(|(neg, m, e)| {
        let v = m * 10f64.powi(e);
        let v = if v.is_finite() { v } else { f64::MAX };
        if neg {
            -v
        } else {
            v
        }
    })
}

fn special() -> impl Strategy<Value = f64> {
    prop::sample::select(vec![
        0.0,
        -0.0,
        1.0,
        -1.0,
        2.0,
        f64::from_bits(1),
        -f64::from_bits(1),
        f64::MIN_POSITIVE,
        1e-300,
        -1e-300,
        1e-8,
        -1e-8,
        PI,
        -PI,
        FRAC_PI_2,
        -FRAC_PI_2,
        3.0 * FRAC_PI_2,
        2.0 * PI,
        700.0,
        709.0,
        710.0,
        -745.0,
        1e7,
        -1e7,
        1e300,
        -1e300,
        f64::MAX,
        -f64::MAX,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ])
}

fn sorted((x, y): (f64, f64)) -> (f64, f64) {
    if x <= y {
        (x, y)
    } else {
        (y, x)
    }
}

/// Intervals of every kind; each mixes in its special cases.
fn interval() -> impl Strategy<Value = (f64, f64)> {
    prop_oneof![
        3 => (-10.0..10.0f64, 0.0..10.0f64).prop_map(|(a, w)| (a, a + w)),
        1 => (-10.0..10.0f64).prop_map(|a| (a, a)),
        2 => (sci(-320, 308), sci(-320, 308)).prop_map(sorted),
        2 => (sci(-320, -1), sci(-320, -1)).prop_map(sorted),
        2 => (sci(-30, 30), -16i32..0).prop_map(|(a, e)| (a, a + a.abs() * 10f64.powi(e))),
        1 => (special(), special()).prop_map(sorted),
        1 => (special(), sci(-320, 308)).prop_map(sorted),
    ]
}

/// Points: the ends often, the interior otherwise.
fn ts() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(
        prop_oneof![1 => Just(0.0), 1 => Just(1.0), 1 => Just(0.5), 3 => 0.0..=1.0f64],
        3..6,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 600, ..ProptestConfig::default() })]

    #[test]
    fn every_function_encloses_on_random_intervals((a, b) in interval(), ts in ts()) {
        check_interval(&ALL, a, b, &ts).map_err(TestCaseError::fail)?;
    }

    #[test]
    fn powers_of_any_order_enclose((a, b) in interval(), n in -9i32..=9, ts in ts()) {
        check_interval(&[F::Pow(n)], a, b, &ts).map_err(TestCaseError::fail)?;
    }

    /// sqrt, ln and recip near 0: tiny intervals touching, straddling or just above 0.
    #[test]
    fn domain_edges_near_zero(
        a in prop_oneof![sci(-323, 0), Just(0.0), Just(f64::from_bits(1))],
        w in prop_oneof![sci(-323, 2).prop_map(f64::abs), Just(0.0)],
        ts in ts(),
    ) {
        let b = a + w;
        check_interval(&[F::Sqrt, F::Ln, F::Recip, F::Pow(-2), F::Pow(3)], a, b, &ts)
            .map_err(TestCaseError::fail)?;
    }

    /// sin and cos: narrow to wide intervals at small to large arguments.
    #[test]
    fn trig_narrow_wide_and_large(
        c in prop_oneof![-10.0..10.0f64, -1e4..1e4f64, -2e7..2e7f64, sci(-300, 12)],
        w in prop_oneof![0.0..8.0f64, sci(-16, 1).prop_map(f64::abs), Just(0.0)],
        ts in ts(),
    ) {
        check_interval(&[F::Sin, F::Cos], c, c + w, &ts).map_err(TestCaseError::fail)?;
    }

    /// Intervals ending close to multiples of pi/2, where the trig case analysis switches.
    #[test]
    fn trig_near_critical_points(
        k in -2000i32..2000,
        da in -1e-5..1e-5f64,
        w in prop_oneof![sci(-12, 0).prop_map(f64::abs), 0.0..4.0f64],
        ts in ts(),
    ) {
        let a = k as f64 * FRAC_PI_2 + da;
        check_interval(&[F::Sin, F::Cos], a, a + w, &ts).map_err(TestCaseError::fail)?;
        check_interval(&[F::Sin, F::Cos], a - w, a, &ts).map_err(TestCaseError::fail)?;
    }

    /// The closed-form `sqrt` fast path (`0 < a < b`): every magnitude, relative widths
    /// from one ulp to huge, and never looser than the float Chebyshev estimate
    /// `(1/(4 alpha) - min g(ends))/2` by more than a few ulps of `sqrt(b)`.
    #[test]
    fn sqrt_fast_path_positive_intervals(
        a in sci(-323, 307).prop_map(f64::abs),
        rel in prop_oneof![sci(-17, 3).prop_map(f64::abs), Just(f64::EPSILON)],
        ts in ts(),
    ) {
        let b = (a + a * rel).min(f64::MAX);
        prop_assume!(a > 0.0 && b > a);
        check_interval(&[F::Sqrt], a, b, &ts).map_err(TestCaseError::fail)?;
        let ap = approx::sqrt(a, b);
        prop_assert!(!ap.is_entire());
        let (sa, sb, al) = (a.sqrt(), b.sqrt(), ap.alpha);
        let est = 0.5 * (0.25 / al - (sa - al * a).min(sb - al * b));
        prop_assert!(
            ap.delta <= est + 16.0 * f64::EPSILON * sb + 1e-300,
            "[{a:e}, {b:e}]: {ap:?} vs {est:e}"
        );
    }

    /// The closed-form `recip` fast path (`0 < a < b`, and mirrored), both slopes.
    #[test]
    fn recip_fast_path_nonzero_intervals(
        a in sci(-307, 307).prop_map(f64::abs),
        rel in prop_oneof![sci(-17, 3).prop_map(f64::abs), Just(f64::EPSILON), 0.0..10.0f64],
        neg in any::<bool>(),
        ts in ts(),
    ) {
        let b = (a + a * rel).min(f64::MAX);
        prop_assume!(a > 0.0 && b > a);
        let (a, b) = if neg { (-b, -a) } else { (a, b) };
        check_interval(&[F::Recip, F::Pow(-1)], a, b, &ts).map_err(TestCaseError::fail)?;
    }

    /// exp's closed-form lower bound `alpha (1 - ln alpha)`: narrow to wide intervals,
    /// both slopes (Chebyshev, min-range), near under- and overflow.
    #[test]
    fn exp_closed_form_bounds(
        a in prop_oneof![-20.0..20.0f64, -750.0..710.0f64],
        w in prop_oneof![sci(-16, 1).prop_map(f64::abs), 0.0..30.0f64],
        ts in ts(),
    ) {
        check_interval(&[F::Exp], a, a + w, &ts).map_err(TestCaseError::fail)?;
    }

    /// The narrow-interval Taylor path of sin and cos (half-width <= 1/4): around
    /// extrema, inflections and elsewhere, at small to large arguments.
    #[test]
    fn trig_taylor_path_narrow(
        c in prop_oneof![
            -10.0..10.0f64,
            -1e7..1e7f64,
            (-6000i32..6000, -1e-3..1e-3f64).prop_map(|(k, d)| k as f64 * FRAC_PI_2 + d),
        ],
        w in prop_oneof![0.0..0.5f64, sci(-16, -1).prop_map(f64::abs), Just(0.5)],
        ts in ts(),
    ) {
        check_interval(&[F::Sin, F::Cos], c, c + w, &ts).map_err(TestCaseError::fail)?;
        check_interval(&[F::Sin, F::Cos], c - w, c, &ts).map_err(TestCaseError::fail)?;
    }

    /// exp around under- and overflow.
    #[test]
    fn exp_over_and_underflow(a in -800.0..800.0f64, w in 0.0..100.0f64, ts in ts()) {
        check_interval(&[F::Exp], a, a + w, &ts).map_err(TestCaseError::fail)?;
    }

    /// Never needlessly loose: the Chebyshev / min-range / minimax slopes all beat the
    /// constant approximation, so `delta` is at most half the width of the rigorous range,
    /// up to the rounding of `g = f - alpha*x` (a few ulps of `|f| + |alpha*x|`).
    /// A bounded range also means a bounded approximation.
    #[test]
    fn delta_at_most_half_the_range((a, b) in interval()) {
        for f in ALL {
            let Some((lo, hi)) = range_of(f, a, b) else { continue };
            if !(lo.is_finite() && hi.is_finite()) {
                continue;
            }
            let ap = approx_of(f, a, b);
            prop_assert!(!ap.is_entire(), "{f:?} on [{a:e}, {b:e}]: entire, range ({lo}, {hi})");
            let ax = if ap.alpha == 0.0 { 0.0 } else { ap.alpha.abs() * a.abs().max(b.abs()) };
            let scale = lo.abs() + hi.abs() + ax;
            let tol = 1e-14 * scale + 1e-300;
            prop_assert!(
                ap.delta <= 0.5 * (hi - lo) + tol,
                "{f:?} on [{a:e}, {b:e}]: {ap:?} vs range ({lo}, {hi})"
            );
        }
    }

    /// No field is ever NaN, for any bit pattern (NaN, infinities, reversed ends included).
    #[test]
    fn never_nan_on_arbitrary_bits(a in any::<f64>(), b in any::<f64>(), n in any::<i32>()) {
        assert_no_nan(a, b, n);
    }
}

fn assert_no_nan(a: f64, b: f64, n: i32) {
    let aps = [
        approx::sqr(a, b),
        approx::powi(a, b, n),
        approx::powi(a, b, 3),
        approx::powi(a, b, 4),
        approx::sqrt(a, b),
        approx::recip(a, b),
        approx::exp(a, b),
        approx::ln(a, b),
        approx::sin(a, b),
        approx::cos(a, b),
        approx::abs(a, b),
        Approx::from_range(a, b),
    ];
    for ap in aps {
        assert!(
            !ap.alpha.is_nan() && !ap.zeta.is_nan() && !ap.delta.is_nan(),
            "NaN in {ap:?} on [{a:e}, {b:e}], n = {n}"
        );
        assert!(ap.delta >= 0.0, "negative delta {ap:?} on [{a:e}, {b:e}]");
    }
    let rgs = [
        approx::range_powi(a, b, n),
        approx::range_powi(a, b, -1),
        approx::range_powi(a, b, 2),
        approx::range_sqrt(a, b),
        approx::range_exp(a, b),
        approx::range_ln(a, b),
        approx::range_sin(a, b),
        approx::range_cos(a, b),
    ];
    for (lo, hi) in rgs {
        assert!(
            !lo.is_nan() && !hi.is_nan(),
            "NaN range ({lo}, {hi}) on [{a:e}, {b:e}], n = {n}"
        );
    }
}

#[test]
fn never_nan_on_special_pairs() {
    let sp = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::MAX,
        -f64::MAX,
        0.0,
        -0.0,
        f64::from_bits(1),
        -f64::from_bits(1),
        f64::MIN_POSITIVE,
        1.0,
        -1.0,
        709.8,
        -745.2,
        1e7,
        PI,
    ];
    for &a in &sp {
        for &b in &sp {
            for n in [i32::MIN, -3, -2, -1, 0, 1, 2, 3, 8, 1025, i32::MAX] {
                assert_no_nan(a, b, n);
            }
        }
    }
}

/// Soundness on every pair of special values that forms an interval, at its real points.
#[test]
fn special_pairs_enclose() {
    let sp = [
        f64::NEG_INFINITY,
        -f64::MAX,
        -1e300,
        -710.0,
        -PI,
        -1.0,
        -f64::from_bits(1),
        -0.0,
        0.0,
        f64::from_bits(1),
        f64::MIN_POSITIVE,
        1e-300,
        1.0,
        FRAC_PI_2,
        709.0,
        710.0,
        1e7,
        1e300,
        f64::MAX,
        f64::INFINITY,
    ];
    for &a in &sp {
        for &b in &sp {
            if a <= b {
                check_interval(&ALL, a, b, &[0.0, 0.25, 0.5, 1.0]).unwrap();
            }
        }
    }
}

/// The huge-argument trig cases are `[-1, 1]`; they must still contain the exact values.
#[test]
fn trig_huge_arguments() {
    for &x in &[1e8, -3e9, 1e15, 1e22, 1e300, f64::MAX] {
        for (a, b) in [(x, x), (x, x + x.abs() * 1e-15)] {
            for f in [approx::range_sin, approx::range_cos] {
                assert_eq!(f(a, b), (-1.0, 1.0));
            }
            for f in [approx::sin, approx::cos] {
                let ap = f(a, b);
                assert!(
                    ap.alpha == 0.0 && ap.zeta == 0.0 && ap.delta >= 1.0,
                    "{ap:?}"
                );
            }
        }
    }
}

/// Past the overflow threshold the range of `e^x` starts at `f64::MAX`, the largest float
/// not above `e^a`, not at 0; the threshold is the first float above `ln(f64::MAX)`.
/// Below it the lower bound stays libm's enclosure (finite, within a few ulps).
#[test]
fn exp_range_past_overflow_starts_at_max() {
    let mut cc = Consts::new().expect("astro-float constants");
    let first_over = (1024.0 * std::f64::consts::LN_2).next_up();
    let exp_of = |x: f64, cc: &mut Consts| match reference(F::Exp, x, cc) {
        Ref::Val(v) => v,
        _ => unreachable!("finite reference for {x}"),
    };
    let max = big(f64::MAX);
    // exp(709.78) < MAX < exp(709.79); the threshold is exactly where e^x passes MAX.
    assert!(le(&exp_of(709.78, &mut cc), &max));
    assert!(!le(&exp_of(709.79, &mut cc), &max));
    assert!(!le(&exp_of(first_over, &mut cc), &max));
    assert!(le(&exp_of(first_over.next_down(), &mut cc), &max));
    for a in [
        first_over,
        709.79,
        710.0,
        800.0,
        1e300,
        f64::MAX,
        f64::INFINITY,
    ] {
        for b in [a, a.next_up(), f64::INFINITY] {
            if a <= b {
                assert_eq!(
                    approx::range_exp(a, b),
                    (f64::MAX, f64::INFINITY),
                    "[{a}, {b}]"
                );
            }
        }
    }
    for a in [first_over.next_down(), 709.78, 709.7] {
        let (lo, hi) = approx::range_exp(a, 710.0);
        assert!(
            lo.is_finite() && lo < f64::MAX && hi == f64::INFINITY,
            "{lo} {hi}"
        );
        let v = exp_of(a, &mut cc);
        assert!(
            le(&big(lo), &v) && le(&v, &big(lo * (1.0 + 1e-14))),
            "{a}: {lo}"
        );
    }
}
