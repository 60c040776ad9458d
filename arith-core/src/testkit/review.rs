//! Adversarial soundness review, generic over [`Range`]: hostile ranges, operands and
//! exponents, checked against the multi-precision reference of the kit. Each arithmetic
//! crate's `tests/review.rs` runs these for its forms (and adds its own cases).
//!
//! The standard suite draws random trees over small, well-scaled ranges. These checks
//! draw trees over adversarial ranges (huge, tiny, subnormal, touching 0, near overflow,
//! trig arguments near multiples of pi/2 up to and beyond 1e7), f64 operands of any
//! magnitude and `powi` exponents of any size, and check soundness against the
//! multi-precision reference; for the affine forms also `bounds_at_inputs` and
//! `linear_part` on such ranges (inexact midpoints and radii included); and two
//! cancellation identities at every scale ([`square_identity`], [`product_identity`]).

use super::checks::{self, check_bounds_shape, check_point, collapsed_ranges, inputs_of, Case};
use super::expr::{bin_strategy_of, un_strategy_with, BINS};
use super::mp::{Mp, Verdict};
use super::strategies::*;
use super::{Bin, Expr, Un};
use crate::Range;
use proptest::prelude::*;
use proptest::strategy::BoxedStrategy;
use proptest::test_runner::TestCaseError;

fn sorted2((a, b): (f64, f64)) -> (f64, f64) {
    if a <= b {
        (a, b)
    } else {
        (b, a)
    }
}

/// Ranges where bugs live.
fn hostile_range() -> BoxedStrategy<(f64, f64)> {
    let big_trig = (1i64..7_000_000, -1e-6..1e-6f64, 0.0..1e-3f64).prop_map(|(k, off, w)| {
        let c = k as f64 * core::f64::consts::FRAC_PI_2 + off;
        (c, c + w)
    });
    let at_limit = (9.99e6..1.001e7f64, 0.0..4.0f64).prop_map(|(c, w)| (c, c + w));
    let touching = prop_oneof![
        any_finite().prop_map(|x| sorted2((0.0, x))),
        any_finite().prop_map(|x| sorted2((-0.0, x))),
    ];
    let overflow = prop_oneof![
        float_exp(1000, 1023).prop_map(|x| sorted2((x, f64::MAX.copysign(x)))),
        float_exp(1000, 1023).prop_map(|x| (-x.abs(), x.abs())),
    ];
    prop_oneof![
        3 => range_any(),
        1 => range_tiny(),
        1 => range_near_zero(),
        1 => range_huge(),
        1 => big_trig,
        1 => at_limit,
        1 => touching,
        1 => overflow,
        2 => range_tree(),
    ]
    .boxed()
}

fn any_const() -> BoxedStrategy<f64> {
    prop_oneof![3 => small_const(), 2 => any_finite()].boxed()
}

/// Every unary operation, `powi` (twice as often as the others) with exponents from
/// `-12..=12` or the extremes, operands of any magnitude.
fn hostile_un() -> BoxedStrategy<Un> {
    let exponents = prop_oneof![
        -12i32..=12,
        prop_oneof![
            Just(i32::MIN),
            Just(i32::MAX),
            Just(-i32::MAX),
            Just(63),
            Just(64),
            Just(65),
            Just(-65),
            Just(1001)
        ]
    ];
    un_strategy_with(2, exponents.boxed(), any_const)
}

/// The binary operations of `Bin` before `Hypot` was added (the review's trees).
fn hostile_bin() -> BoxedStrategy<Bin> {
    bin_strategy_of(&BINS[..6])
}

fn hostile_expr(depth: u32) -> BoxedStrategy<Expr> {
    let leaf = prop_oneof![
        3 => (0usize..3).prop_map(Expr::Input),
        1 => any_const().prop_map(Expr::Const),
    ];
    leaf.prop_recursive(depth, 24, 2, |inner| {
        prop_oneof![
            3 => (hostile_un(), inner.clone()).prop_map(|(op, a)| Expr::un(op, a)),
            2 => (hostile_bin(), inner.clone(), inner).prop_map(|(op, a, b)| Expr::bin(op, a, b)),
        ]
    })
    .boxed()
}

fn hostile_cases() -> BoxedStrategy<Case> {
    checks::case_strategy(
        hostile_expr(4),
        vec![hostile_range(), hostile_range(), hostile_range()],
        3,
    )
}

/// Soundness of random trees over hostile ranges and operands.
pub fn hostile_trees<R: Range>(cases: u32) {
    let stats = checks::Stats::default();
    checks::run(
        &format!("{}: hostile trees", R::NAME),
        cases,
        hostile_cases(),
        |case| checks::check_case::<R>(&case, &stats),
    );
    stats.assert_informative(&format!("{}: hostile trees", R::NAME), 0.05);
}

/// `x_i = mid_i + rad_i*eps_i` (exact reals) at precision `p`.
fn point_at(ranges: &[(f64, f64)], eps: &[f64], p: usize) -> Option<Vec<Mp>> {
    ranges
        .iter()
        .zip(eps)
        .map(|(&(a, b), &e)| {
            let (a, b, e) = (Mp::point_p(a, p)?, Mp::point_p(b, p)?, Mp::point_p(e, p)?);
            let half = Mp::point_p(0.5, p)?;
            let mid = a.add(&b)?.mul(&half)?;
            let rad = b.sub(&a)?.mul(&half)?;
            mid.add(&rad.mul(&e)?)
        })
        .collect()
}

fn verdict_at(
    expr: &Expr,
    ranges: &[(f64, f64)],
    eps: &[f64],
    lo: f64,
    hi: f64,
) -> Option<Verdict> {
    let r = point_at(ranges, eps, 256).and_then(|p| expr.reference(&p))?;
    match r.verdict(lo, hi) {
        Verdict::Unsure => {
            let r = point_at(ranges, eps, 1024).and_then(|p| expr.reference(&p))?;
            Some(r.verdict(lo, hi))
        }
        v => Some(v),
    }
}

/// Joint inclusion and the linear part on hostile ranges (inexact midpoints/radii).
pub fn hostile_joint<R: Range>(cases: u32) {
    let eps = prop_oneof![Just(-1.0), Just(0.0), Just(1.0), -1.0..=1.0f64];
    let s = (
        hostile_expr(4),
        vec![hostile_range(), hostile_range(), hostile_range()],
        vec![vec![eps; 3]; 3],
    );
    checks::run(
        &format!("{}: hostile joint inclusion", R::NAME),
        cases,
        s,
        |(expr, ranges, epss)| {
            let ranges = collapsed_ranges::<R>(&ranges);
            let inputs: Vec<R> = inputs_of(&ranges);
            let v = expr.eval(&inputs);
            check_bounds_shape(&v)?;
            for eps in &epss {
                let (lo, hi) = v.bounds_at_inputs(eps);
                prop_assert!(!lo.is_nan() && !hi.is_nan() && lo <= hi);
                if verdict_at(&expr, &ranges, eps, lo, hi) == Some(Verdict::Outside) {
                    return Err(TestCaseError::fail(format!(
                        "UNSOUND bounds_at_inputs [{lo:e}, {hi:e}] of {expr}\n eps {eps:?}\n ranges {ranges:?}"
                    )));
                }
                // Linear part: x0 fixed by eps[0], the others anywhere: check them at eps.
                if let Some(l) = v.linear_part() {
                    prop_assert!(!l.f0.is_nan() && !l.f1.is_nan() && l.e >= 0.0, "{l:?}");
                    let Some(r) = point_at(&ranges, eps, 256).and_then(|p| expr.reference(&p))
                    else {
                        continue;
                    };
                    let c = Mp::point(l.f0)
                        .and_then(|f0| f0.add(&Mp::point(l.f1)?.mul(&Mp::point(eps[0])?)?));
                    if let Some(d) = c.and_then(|c| r.sub(&c)) {
                        prop_assert!(
                            d.verdict(-l.e, l.e) != Verdict::Outside,
                            "UNSOUND linear part {l:?} of {expr} at eps {eps:?}, ranges {ranges:?}: value - centre in {}",
                            d.describe()
                        );
                    }
                }
            }
            Ok(())
        },
    );
}

/// A single expression at a single point must lie in the computed bounds.
pub fn assert_sound<R: Range>(expr: &Expr, ranges: &[(f64, f64)], point: &[f64]) {
    let inputs: Vec<R> = inputs_of(ranges);
    let v = expr.eval(&inputs);
    let (lo, hi) = v.bounds();
    assert!(
        !lo.is_nan() && !hi.is_nan() && lo <= hi,
        "{expr}: [{lo}, {hi}]"
    );
    if let Err(m) = check_point(expr, point, lo, hi) {
        panic!("{} {m}\n  ranges {ranges:?}", R::NAME);
    }
}

/// `(x - x0)²` written as `x² - 2·x0·x + x0²` (and with `x * x`) over `x0 ± r` for
/// short-significand `x0`, `r` at every scale, subnormal `r²` included: the affine
/// parts cancel exactly, so what is left is the quadratic part's own bookkeeping.
pub fn square_identity<R: Range>(cases: u32) {
    let stats = checks::Stats::default();
    let s = (
        1i64..64,
        prop_oneof![-1060i32..60, -520i32..-490],
        1i64..(1i64 << 27),
        prop_oneof![0i32..70, 0i32..4],
        any::<bool>(),
    );
    checks::run(
        &format!("{}: square identity", R::NAME),
        cases,
        s,
        |(a, e0, m, dk, mul)| {
            let x0 = a as f64 * 2f64.powi(e0);
            let r = m as f64 * 2f64.powi(e0 - 27 - dk);
            let (lo, hi) = (x0 - r, x0 + r);
            if !(x0.is_finite() && r > 0.0 && lo < hi && (lo + hi) * 0.5 == x0 && hi - x0 == r) {
                return Ok(());
            }
            let sq = if mul {
                Expr::bin(Bin::Mul, Expr::Input(0), Expr::Input(0))
            } else {
                Expr::un(Un::Sqr, Expr::Input(0))
            };
            let e = Expr::bin(
                Bin::Add,
                Expr::bin(Bin::Sub, sq, Expr::un(Un::MulF(2.0 * x0), Expr::Input(0))),
                Expr::Const(x0 * x0),
            );
            let case = Case {
                expr: e,
                ranges: vec![(lo, hi)],
                points: vec![vec![lo], vec![hi], vec![x0]],
            };
            checks::check_case::<R>(&case, &stats)
        },
    );
    stats.assert_informative(&format!("{}: square identity", R::NAME), 0.5);
}

/// `(x - x0)(y - y0)` written as `x·y - y0·x - x0·y + x0·y0` over `x0 ± r`, `y0 ± s`
/// (two inputs) at every scale, subnormal `r·s` included: the affine parts cancel
/// exactly, what is left is the product's own bookkeeping of its quadratic part.
pub fn product_identity<R: Range>(cases: u32) {
    let stats = checks::Stats::default();
    let scale = || prop_oneof![-1060i32..60, -520i32..-490];
    let s = (
        (
            1i64..64,
            scale(),
            1i64..(1i64 << 27),
            prop_oneof![0i32..70, 0i32..4],
        ),
        (
            -64i64..64,
            scale(),
            1i64..(1i64 << 27),
            prop_oneof![0i32..70, 0i32..4],
        ),
    );
    checks::run(
        &format!("{}: product identity", R::NAME),
        cases,
        s,
        |((a, ea, m, da), (b, eb, n, db))| {
            let x0 = a as f64 * 2f64.powi(ea);
            let r = m as f64 * 2f64.powi(ea - 27 - da);
            let y0 = b as f64 * 2f64.powi(eb);
            let s = n as f64 * 2f64.powi(eb - 27 - db);
            let exact = |c: f64, w: f64| {
                let (lo, hi) = (c - w, c + w);
                c.is_finite() && w > 0.0 && lo < hi && (lo + hi) * 0.5 == c && hi - c == w
            };
            if !(exact(x0, r) && exact(y0, s)) {
                return Ok(());
            }
            let (x, y) = (Expr::Input(0), Expr::Input(1));
            let e = Expr::bin(
                Bin::Add,
                Expr::bin(
                    Bin::Sub,
                    Expr::bin(
                        Bin::Sub,
                        Expr::bin(Bin::Mul, x.clone(), y.clone()),
                        Expr::un(Un::MulF(y0), x),
                    ),
                    Expr::un(Un::MulF(x0), y),
                ),
                Expr::Const(x0 * y0),
            );
            let (xl, xh, yl, yh) = (x0 - r, x0 + r, y0 - s, y0 + s);
            let case = Case {
                expr: e,
                ranges: vec![(xl, xh), (yl, yh)],
                points: vec![vec![xl, yl], vec![xl, yh], vec![xh, yl], vec![xh, yh]],
            };
            checks::check_case::<R>(&case, &stats)
        },
    );
    stats.assert_informative(&format!("{}: product identity", R::NAME), 0.5);
}
