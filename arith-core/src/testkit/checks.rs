//! Reusable generic property checks over any [`Range`], run by [`crate::range_test_suite!`].
//!
//! Each `check_*` function runs a proptest [`TestRunner`] for `cases` cases (overridden
//! by the `PROPTEST_CASES` environment variable when set) and panics with the shrunk
//! failing case. A failure means a computed range provably misses the exact value: the
//! multi-precision enclosure of the exact value ([`Mp`]) is disjoint from the bounds.
//! Points where the reference is undefined (division by exact zero, `inf - inf`) are
//! skipped; an undecidable overlap at 256 bits is retried at 1024 bits and then counted
//! as passed. To keep tests from passing vacuously, each run also asserts that a fair
//! share of its points were decided "inside" with finite bounds.

use super::expr::{expr_strategy, un_strategy, Bin, Expr, Un};
use super::mp::{Mp, Verdict, PREC};
use super::strategies::*;
use crate::{Known, Range};
use core::fmt::Debug;
use core::sync::atomic::{AtomicU64, Ordering::Relaxed};
use proptest::prelude::*;
use proptest::strategy::BoxedStrategy;
use proptest::test_runner::{Config, TestCaseResult, TestRunner};

/// Default case count of the per-operation tests.
pub const CASES_OP: u32 = 512;
/// Default case count of the random expression tree tests.
pub const CASES_TREE: u32 = 1024;

/// `PROPTEST_CASES` if set, else `default`.
pub fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// Runs `test` on `cases(default)` values of `strategy`; panics with the shrunk
/// counterexample on failure.
pub fn run<S>(
    name: &str,
    default_cases: u32,
    strategy: S,
    test: impl Fn(S::Value) -> TestCaseResult,
) where
    S: Strategy,
    S::Value: Debug,
{
    let mut config = Config::with_cases(cases(default_cases));
    config.failure_persistence = None;
    let mut runner = TestRunner::new(config);
    if let Err(e) = runner.run(&strategy, test) {
        panic!("{name}: {e}");
    }
}

/// Counters guarding against vacuous runs.
#[derive(Debug, Default)]
pub struct Stats {
    /// Points checked (reference defined).
    pub checked: AtomicU64,
    /// Points decided inside bounds that are both finite.
    pub inside_finite: AtomicU64,
}

impl Stats {
    /// Asserts that at least `min_fraction` of the checked points were decided inside
    /// finite bounds (so the run tested something).
    pub fn assert_informative(&self, name: &str, min_fraction: f64) {
        let (c, f) = (self.checked.load(Relaxed), self.inside_finite.load(Relaxed));
        // Shown with `--nocapture`: how much each run really tested.
        eprintln!("{name}: {c} points checked, {f} inside finite bounds");
        assert!(
            c > 0,
            "{name}: no point was checked (reference always undefined?)"
        );
        assert!(
            f as f64 >= min_fraction * c as f64,
            "{name}: only {f} of {c} checked points had finite bounds; the test is nearly vacuous"
        );
    }
}

/// One soundness case: an expression, one range per input, and point sets (one point
/// per input each) inside the ranges.
#[derive(Clone, Debug)]
pub struct Case {
    /// The expression.
    pub expr: Expr,
    /// Input `i` ranges over `ranges[i]`.
    pub ranges: Vec<(f64, f64)>,
    /// Points to check, each with one coordinate per input.
    pub points: Vec<Vec<f64>>,
}

/// Cases for `expr` with input ranges from `ranges` (one strategy per input) and
/// `npoints` point sets.
pub fn case_strategy(
    expr: BoxedStrategy<Expr>,
    ranges: Vec<BoxedStrategy<(f64, f64)>>,
    npoints: usize,
) -> BoxedStrategy<Case> {
    (expr, ranges)
        .prop_flat_map(move |(expr, ranges)| {
            let pts = vec![points_in(&ranges); npoints];
            (Just(expr), Just(ranges), pts)
        })
        .prop_map(|(expr, ranges, points)| Case {
            expr,
            ranges,
            points,
        })
        .boxed()
}

/// Checks that the reference value of `expr` at `point` lies in `[lo, hi]`; `Ok(None)`
/// when undefined there, `Ok(Some(decided_inside))` otherwise.
pub fn check_point(expr: &Expr, point: &[f64], lo: f64, hi: f64) -> Result<Option<bool>, String> {
    check_point_mp(
        expr,
        &|p| point.iter().map(|&x| Mp::point_p(x, p)).collect(),
        lo,
        hi,
    )
    .map_err(|m| format!("{m}\n  at point {point:?}"))
}

/// [`check_point`] where the point coordinates are themselves enclosures built at a
/// given precision by `point`.
fn check_point_mp(
    expr: &Expr,
    point: &dyn Fn(usize) -> Option<Vec<Mp>>,
    lo: f64,
    hi: f64,
) -> Result<Option<bool>, String> {
    let Some(r) = point(PREC).and_then(|p| expr.reference(&p)) else {
        return Ok(None);
    };
    match r.verdict(lo, hi) {
        Verdict::Inside => Ok(Some(true)),
        Verdict::Outside => Err(format!(
            "UNSOUND: {expr}\n  computed bounds [{lo:e}, {hi:e}]\n  exact value in {}",
            r.describe()
        )),
        Verdict::Unsure => {
            let fine = point(4 * PREC).and_then(|p| expr.reference(&p));
            match fine.map(|r| (r.verdict(lo, hi), r)) {
                Some((Verdict::Outside, r)) => Err(format!(
                    "UNSOUND: {expr}\n  computed bounds [{lo:e}, {hi:e}]\n  exact value in {}",
                    r.describe()
                )),
                Some((Verdict::Inside, _)) => Ok(Some(true)),
                _ => Ok(Some(false)),
            }
        }
    }
}

fn record(stats: &Stats, lo: f64, hi: f64, inside: bool) {
    stats.checked.fetch_add(1, Relaxed);
    if inside && lo.is_finite() && hi.is_finite() {
        stats.inside_finite.fetch_add(1, Relaxed);
    }
}

/// Basic contract of any computed range: bounds ordered and never NaN, and
/// `contains_zero()` answering "yes" whenever `0 ∈ bounds()`.
pub fn check_bounds_shape<R: Range>(v: &R) -> TestCaseResult {
    let (lo, hi) = v.bounds();
    prop_assert!(
        !lo.is_nan() && !hi.is_nan(),
        "NaN bound: [{lo}, {hi}] in {v:?}"
    );
    prop_assert!(lo <= hi, "inverted bounds: [{lo}, {hi}] in {v:?}");
    if lo <= 0.0 && 0.0 <= hi {
        prop_assert!(
            v.contains_zero(),
            "0 in [{lo}, {hi}] but contains_zero() is false"
        );
    }
    Ok(())
}

/// The point `x_i = mid_i + rad_i * eps_i` of the ranges (exact reals: where input `i`
/// is when its symbol is at `eps_i`), enclosed rigorously at precision `p`.
fn point_at(ranges: &[(f64, f64)], eps: &[f64], p: usize) -> Option<Vec<Mp>> {
    let half = Mp::point_p(0.5, p)?;
    ranges
        .iter()
        .zip(eps)
        .map(|(&(a, b), &e)| {
            let (a, b, e) = (Mp::point_p(a, p)?, Mp::point_p(b, p)?, Mp::point_p(e, p)?);
            let mid = a.add(&b)?.mul(&half)?;
            let rad = b.sub(&a)?.mul(&half)?;
            mid.add(&rad.mul(&e)?)
        })
        .collect()
}

/// The exact `value` minus `x0 + Σ xs[i] eps[i]` must lie in `[-e, e]`: a provable miss
/// fails with `what(residual)`; undecided points are counted, undefined ones skipped.
fn check_residual(
    value: &Mp,
    x0: f64,
    xs: &[f64],
    eps: &[f64],
    e: f64,
    stats: &Stats,
    what: impl FnOnce(String) -> String,
) -> TestCaseResult {
    let mut centre = Mp::point(x0);
    for (&c, &t) in xs.iter().zip(eps) {
        centre = centre.and_then(|m| m.add(&Mp::point(c)?.mul(&Mp::point(t)?)?));
    }
    let Some(d) = centre.and_then(|c| value.sub(&c)) else {
        return Ok(());
    };
    match d.verdict(-e, e) {
        Verdict::Outside => Err(TestCaseError::fail(what(d.describe()))),
        verdict => {
            record(stats, -e, e, verdict == Verdict::Inside);
            Ok(())
        }
    }
}

/// `R::input(i, lo, hi)` for each range `i`.
pub fn inputs_of<R: Range>(ranges: &[(f64, f64)]) -> Vec<R> {
    ranges
        .iter()
        .enumerate()
        .map(|(i, &(lo, hi))| R::input(i, lo, hi))
        .collect()
}

/// The ranges with every input past `R::INPUTS` (one without its own symbol, so not
/// correlated across an evaluation) collapsed to its midpoint.
pub fn collapsed_ranges<R: Range>(ranges: &[(f64, f64)]) -> Vec<(f64, f64)> {
    ranges
        .iter()
        .enumerate()
        .map(|(i, &(lo, hi))| {
            if i < R::INPUTS {
                (lo, hi)
            } else {
                let m = (lo * 0.5 + hi * 0.5).clamp(lo, hi);
                (m, m)
            }
        })
        .collect()
}

/// Soundness of one case: evaluate over `R::input(i, ranges[i])`, then every defined
/// point's exact value must lie in `bounds()`.
pub fn check_case<R: Range>(case: &Case, stats: &Stats) -> TestCaseResult {
    let inputs: Vec<R> = inputs_of(&case.ranges);
    let v = case.expr.eval(&inputs);
    check_bounds_shape(&v)?;
    let (lo, hi) = v.bounds();
    for pt in &case.points {
        match check_point(&case.expr, pt, lo, hi) {
            Err(m) => {
                return Err(TestCaseError::fail(format!(
                    "{m}\n  ranges {:?}",
                    case.ranges
                )))
            }
            Ok(Some(inside)) => record(stats, lo, hi, inside),
            Ok(None) => {}
        }
    }
    Ok(())
}

/// Runs soundness cases from `strategy`; `min_informative` is the fraction of checked
/// points that must have had finite bounds.
pub fn check_cases<R: Range>(
    name: &str,
    default_cases: u32,
    strategy: BoxedStrategy<Case>,
    min_informative: f64,
) {
    let stats = Stats::default();
    run(name, default_cases, strategy, |case| {
        check_case::<R>(&case, &stats)
    });
    stats.assert_informative(name, min_informative);
}

/// Soundness of one binary operation `x0 op x1` on [`range_any`] inputs (divisors from
/// [`range_divisor`]).
pub fn check_binary_op<R: Range>(op: Bin, default_cases: u32) {
    let e = Expr::bin(op, Expr::Input(0), Expr::Input(1));
    let second = if op == Bin::Div {
        range_divisor()
    } else {
        range_any()
    };
    let s = case_strategy(Just(e).boxed(), vec![range_any(), second], 4);
    check_cases::<R>(&format!("{}: {op:?}", R::NAME), default_cases, s, 0.2);
}

/// Soundness of unary operations drawn from `ops`, on inputs from `ranges`.
pub fn check_unary_op<R: Range>(
    name: &str,
    ops: BoxedStrategy<Un>,
    ranges: BoxedStrategy<(f64, f64)>,
    default_cases: u32,
) {
    let e = ops.prop_map(|op| Expr::un(op, Expr::Input(0))).boxed();
    let s = case_strategy(e, vec![ranges], 4);
    check_cases::<R>(&format!("{}: {name}", R::NAME), default_cases, s, 0.2);
}

/// The unary-operation tests of the standard suite, by name: `neg`, `abs`, `sqr`,
/// `powi`, `sqrt`, `recip`, `exp`, `ln`, `sin`, `cos`, `f64_rhs` (`+ - * /` with an
/// `f64` on the right, `rsub`, `rdiv`), `any` (all of them on [`range_any`]).
pub fn check_unary_named<R: Range>(name: &str, default_cases: u32) {
    let f64_ops = || {
        let c = prop_oneof![small_const(), any_finite()];
        prop_oneof![
            c.clone().prop_map(Un::AddF),
            c.clone().prop_map(Un::SubF),
            c.clone().prop_map(Un::MulF),
            c.clone().prop_map(Un::DivF),
            c.clone().prop_map(Un::RSubF),
            c.prop_map(Un::RDivF),
        ]
        .boxed()
    };
    let (ops, ranges) = match name {
        "neg" => (Just(Un::Neg).boxed(), range_any()),
        "abs" => (Just(Un::Abs).boxed(), range_any()),
        "sqr" => (Just(Un::Sqr).boxed(), range_any()),
        "powi" => ((-6i32..=7).prop_map(Un::Powi).boxed(), range_divisor()),
        "sqrt" => (Just(Un::Sqrt).boxed(), range_positive_domain()),
        "recip" => (Just(Un::Recip).boxed(), range_divisor()),
        "exp" => (Just(Un::Exp).boxed(), range_exp_edges()),
        "ln" => (Just(Un::Ln).boxed(), range_positive_domain()),
        "sin" => (Just(Un::Sin).boxed(), range_trig()),
        "cos" => (Just(Un::Cos).boxed(), range_trig()),
        "f64_rhs" => (f64_ops(), range_any()),
        "any" => (un_strategy(), range_any()),
        other => panic!("unknown unary test {other}"),
    };
    check_unary_op::<R>(name, ops, ranges, default_cases);
}

/// Soundness on random expression trees (depth up to 6, three inputs, every
/// operation) over [`range_tree`] inputs.
pub fn check_random_trees<R: Range>(default_cases: u32) {
    let s = case_strategy(
        expr_strategy(6, 3),
        vec![range_tree(), range_tree(), range_tree()],
        3,
    );
    check_cases::<R>(&format!("{}: random trees", R::NAME), default_cases, s, 0.1);
}

/// `R::constant(c)`, `R::from_interval` and `R::input` enclose what they were given.
pub fn check_constants_and_inputs<R: Range>(default_cases: u32) {
    let s = (any_finite(), range_any(), 0usize..4);
    run(
        &format!("{}: constants and inputs", R::NAME),
        default_cases,
        s,
        |(c, (lo, hi), i)| {
            let k = R::constant(c);
            check_bounds_shape(&k)?;
            let (a, b) = k.bounds();
            prop_assert!(a <= c && c <= b, "constant {c} not in [{a}, {b}]");
            // Generic code (dual numbers, noise) learns a range's bounds through `known`
            // and builds ranges through `from_bounds`.
            prop_assert_eq!(k.known(), Known::Range(a, b));
            let made = R::from_bounds(lo, hi);
            prop_assert!(made.is_some(), "from_bounds gives no range");
            for v in [R::from_interval(lo, hi), R::input(i, lo, hi)]
                .into_iter()
                .chain(made)
            {
                check_bounds_shape(&v)?;
                let (a, b) = v.bounds();
                prop_assert!(a <= lo && hi <= b, "[{lo}, {hi}] not in [{a}, {b}]");
                prop_assert_eq!(v.known(), Known::Range(a, b));
            }
            Ok(())
        },
    );
}

/// `x.sqr()` is never wider than `x * x` (same operand `x = R::input(0, lo, hi)`).
pub fn check_sqr_not_wider<R: Range>(default_cases: u32) {
    fn width((lo, hi): (f64, f64)) -> f64 {
        if lo == hi {
            0.0
        } else {
            hi - lo
        }
    }
    run(
        &format!("{}: sqr vs x*x", R::NAME),
        default_cases,
        range_any(),
        |(lo, hi)| {
            let x = R::input(0, lo, hi);
            let s = x.sqr();
            let m = x.clone() * x;
            check_bounds_shape(&s)?;
            let (ws, wm) = (width(s.bounds()), width(m.bounds()));
            prop_assert!(
                ws <= wm,
                "sqr {:?} wider than x*x {:?} for [{lo}, {hi}]",
                s.bounds(),
                m.bounds()
            );
            Ok(())
        },
    );
}

/// One joint-inclusion case.
#[derive(Clone, Debug)]
pub struct JointCase {
    /// The expression over inputs 0, 1, 2.
    pub expr: Expr,
    /// Input ranges (inputs `i >= R::INPUTS` are collapsed to their midpoint).
    pub ranges: Vec<(f64, f64)>,
    /// Noise symbol values to fix, one per input, each in `[-1, 1]`.
    pub eps: Vec<Vec<f64>>,
}

/// JOINT INCLUSION (affine forms): for inputs `x_i = R::input(i, lo_i, hi_i)` and a
/// random tree `F`, fixing the input symbols at `eps` (with `eps_i ∈ {-1, 0, 1}` or
/// uniform), the exact value `F(mid_i + rad_i * eps_i)` — `mid = (lo+hi)/2`,
/// `rad = (hi-lo)/2` as exact reals, computed rigorously in multi-precision — lies in
/// `bounds_at_inputs(&eps)` (and in `bounds()`). `eps.len()` is always 3. Inputs with
/// `i >= R::INPUTS` get a zero-width range, as they have no symbol to fix.
pub fn check_joint_inclusion<R: Range>(default_cases: u32) {
    let ranges = prop_oneof![3 => range_tree_exact(), 1 => range_tree()];
    let s = (
        expr_strategy(6, 3),
        vec![ranges.clone(), ranges.clone(), ranges],
        vec![vec![eps_value(); 3]; 4],
    )
        .prop_map(|(expr, ranges, eps)| JointCase { expr, ranges, eps });
    let name = format!("{}: joint inclusion", R::NAME);
    let stats = Stats::default();
    run(&name, default_cases, s, |case| {
        let ranges = collapsed_ranges::<R>(&case.ranges);
        let inputs: Vec<R> = inputs_of(&ranges);
        let v = case.expr.eval(&inputs);
        check_bounds_shape(&v)?;
        let (glo, ghi) = v.bounds();
        for eps in &case.eps {
            let (lo, hi) = v.bounds_at_inputs(eps);
            prop_assert!(
                !lo.is_nan() && !hi.is_nan() && lo <= hi,
                "bounds_at_inputs({eps:?}) = [{lo}, {hi}]"
            );
            let point = |p: usize| point_at(&ranges, eps, p);
            for (what, l, h) in [("bounds_at_inputs", lo, hi), ("bounds", glo, ghi)] {
                match check_point_mp(&case.expr, &point, l, h) {
                    Err(m) => {
                        return Err(TestCaseError::fail(format!(
                            "{what}: {m}\n  eps {eps:?}\n  ranges {ranges:?}"
                        )))
                    }
                    Ok(Some(inside)) if what == "bounds_at_inputs" => record(&stats, l, h, inside),
                    _ => {}
                }
            }
        }
        Ok(())
    });
    stats.assert_informative(&name, 0.1);
}

/// CORRELATION (affine forms): `x - x` is exactly `[0, 0]` for `x = R::input(0, ..)` on
/// an exact box, while `x - y` for independent inputs 0 and 1 of positive width is not
/// a single point.
pub fn check_correlation<R: Range>(default_cases: u32) {
    let s = (range_exact_box(), range_exact_box());
    run(
        &format!("{}: correlation", R::NAME),
        default_cases,
        s,
        |((lo0, hi0), (lo1, hi1))| {
            let x = R::input(0, lo0, hi0);
            let y = R::input(1, lo1, hi1);
            let d = x.clone() - x.clone();
            let (a, b) = d.bounds();
            prop_assert!(
                a == 0.0 && b == 0.0,
                "x - x = [{a}, {b}] for x in [{lo0}, {hi0}]"
            );
            let (a, b) = (x - y).bounds();
            if lo0 < hi0 || lo1 < hi1 {
                prop_assert!(
                    a < b,
                    "x - y = [{a}, {b}] for independent x in [{lo0}, {hi0}], y in [{lo1}, {hi1}]"
                );
            }
            Ok(())
        },
    );
}

/// LINEAR PART (affine forms, used by argument pruning): when
/// [`Range::linear_part`] gives `f0 + f1*eps1 ± e`, then fixing input 0 at
/// `x0 = mid0 + rad0*eps1` and the other inputs anywhere in their ranges, the exact
/// value lies in `[f0 + f1*eps1 - e, f0 + f1*eps1 + e]` (checked in multi-precision).
/// Forms returning `None` are skipped (counted, not failed).
pub fn check_linear_part<R: Range>(default_cases: u32) {
    let ranges = prop_oneof![3 => range_tree_exact(), 1 => range_tree()];
    let s = (
        expr_strategy(6, 3),
        vec![ranges.clone(), ranges.clone(), ranges],
        eps_value(),
    )
        .prop_flat_map(|(expr, ranges, eps1)| {
            let pts = vec![points_in(&ranges); 3];
            (Just(expr), Just(ranges), Just(eps1), pts)
        });
    let name = format!("{}: linear part", R::NAME);
    let stats = Stats::default();
    run(&name, default_cases, s, |(expr, ranges, eps1, pts)| {
        let inputs: Vec<R> = inputs_of(&ranges);
        let v = expr.eval(&inputs);
        let Some(lin) = v.linear_part() else {
            return Ok(());
        };
        prop_assert!(
            !lin.f0.is_nan() && !lin.f1.is_nan() && lin.e >= 0.0,
            "linear part {lin:?} has NaN or negative e"
        );
        let (a0, b0) = ranges[0];
        for pt in &pts {
            // x0 = mid0 + rad0*eps1 (exact reals), the others at the drawn points.
            let point = |p: usize| -> Option<Vec<Mp>> {
                let mut xs = point_at(&[(a0, b0)], &[eps1], p)?;
                for &x in &pt[1..] {
                    xs.push(Mp::point_p(x, p)?);
                }
                Some(xs)
            };
            let Some(r) = point(PREC).and_then(|xs| expr.reference(&xs)) else {
                continue;
            };
            check_residual(&r, lin.f0, &[lin.f1], &[eps1], lin.e, &stats, |d| {
                format!(
                    "UNSOUND linear part: {expr}\n  {lin:?} at eps1 = {eps1}\n  value - (f0 + f1*eps1) in {d}\n  point {pt:?} (x0 from eps1)\n  ranges {ranges:?}"
                )
            })?;
        }
        Ok(())
    });
    let checked = stats.checked.load(Relaxed);
    eprintln!("{name}: {checked} points checked against a linear part");
}

/// AFFINE PART (a bundle's form restricted to one ray or one child cell): when
/// [`Range::affine_part`] gives `x0 + Σ xs[i] eps_i ± e` on the three inputs, the exact
/// value at the point `x_i = mid_i + rad_i*eps_i` lies in
/// `[x0 + Σ xs[i] eps_i - e, x0 + Σ xs[i] eps_i + e]` (multi-precision). Forms returning
/// `None` are skipped.
pub fn check_affine_part<R: Range>(default_cases: u32) {
    let ranges = prop_oneof![3 => range_tree_exact(), 1 => range_tree()];
    let s = (
        expr_strategy(6, 3),
        vec![ranges.clone(), ranges.clone(), ranges],
        vec![vec![eps_value(); 3]; 3],
    );
    let name = format!("{}: affine part", R::NAME);
    let stats = Stats::default();
    run(&name, default_cases, s, |(expr, ranges, draws)| {
        let inputs: Vec<R> = inputs_of(&ranges);
        let v = expr.eval(&inputs);
        let Some(a) = v.affine_part::<3>() else {
            return Ok(());
        };
        prop_assert!(
            !a.x0.is_nan() && a.xs.iter().all(|c| !c.is_nan()) && a.e >= 0.0,
            "affine part {a:?} has NaN or negative e"
        );
        for eps in &draws {
            let Some(r) = point_at(&ranges, eps, PREC).and_then(|xs| expr.reference(&xs)) else {
                continue;
            };
            check_residual(&r, a.x0, &a.xs, eps, a.e, &stats, |d| {
                format!(
                    "UNSOUND affine part: {expr}\n  {a:?} at eps {eps:?}\n  value - (x0 + Σ xs eps) in {d}\n  ranges {ranges:?}"
                )
            })?;
        }
        Ok(())
    });
    let checked = stats.checked.load(Relaxed);
    eprintln!("{name}: {checked} points checked against an affine part");
}

/// AFFINE INPUTS: three inputs built by [`Range::from_affine`] on shared symbols (so
/// correlated), an expression over them, and points given by symbol values `eps` and
/// error fractions `d`: `x_k = c0_k + Σ_i c_ki eps_i + err_k d_k`. The exact value must
/// lie in [`Range::bounds_at_inputs`]`(eps)` and in [`Range::bounds`] (multi-precision).
pub fn check_from_affine<R: Range>(default_cases: u32) {
    let coef = prop_oneof![3 => moderate(), 1 => Just(0.0)];
    let err = prop_oneof![Just(0.0), moderate().prop_map(f64::abs)];
    let form = (moderate(), vec![coef; 3], err);
    let draw = (vec![eps_value(); 3], vec![eps_value(); 3]);
    let s = (expr_strategy(6, 3), vec![form; 3], vec![draw; 3]);
    let name = format!("{}: affine inputs", R::NAME);
    let stats = Stats::default();
    run(&name, default_cases, s, |(expr, forms, draws)| {
        let inputs: Vec<R> = forms
            .iter()
            .map(|(c0, cs, err)| R::from_affine(*c0, cs, *err))
            .collect();
        for (x, (c0, cs, err)) in inputs.iter().zip(&forms) {
            let (lo, hi) = x.bounds();
            let r = cs.iter().map(|c| c.abs()).sum::<f64>() + err;
            prop_assert!(
                lo <= c0 - r * (1.0 - 1e-12) && c0 + r * (1.0 - 1e-12) <= hi,
                "from_affine({c0}, {cs:?}, {err}) has bounds [{lo}, {hi}]"
            );
        }
        let v = expr.eval(&inputs);
        check_bounds_shape(&v)?;
        let (glo, ghi) = v.bounds();
        for (eps, ds) in &draws {
            let (lo, hi) = v.bounds_at_inputs(eps);
            prop_assert!(
                !lo.is_nan() && !hi.is_nan() && lo <= hi,
                "bounds_at_inputs({eps:?}) = [{lo}, {hi}]"
            );
            let point = |p: usize| -> Option<Vec<Mp>> {
                forms
                    .iter()
                    .zip(ds)
                    .map(|((c0, cs, err), &d)| {
                        let mut x = Mp::point_p(*c0, p)?;
                        for (c, &t) in cs.iter().zip(eps) {
                            x = x.add(&Mp::point_p(*c, p)?.mul(&Mp::point_p(t, p)?)?)?;
                        }
                        x.add(&Mp::point_p(*err, p)?.mul(&Mp::point_p(d, p)?)?)
                    })
                    .collect()
            };
            for (what, l, h) in [("bounds_at_inputs", lo, hi), ("bounds", glo, ghi)] {
                match check_point_mp(&expr, &point, l, h) {
                    Err(m) => {
                        return Err(TestCaseError::fail(format!(
                            "{what}: {m}\n  eps {eps:?}, error fractions {ds:?}\n  forms {forms:?}"
                        )))
                    }
                    Ok(Some(inside)) if what == "bounds_at_inputs" => record(&stats, l, h, inside),
                    _ => {}
                }
            }
        }
        Ok(())
    });
    stats.assert_informative(&name, 0.1);
}

/// A [`crate::pack::Pack`] computes, lane for lane, bit for bit what its scalar form
/// computes: random expression trees (every operation, constants on either side) over
/// four lanes of three inputs each, every input a range on one of the form's symbols or
/// in the error term, then moved by [`crate::pack::Pack::mul_add_lanes`] (`x m + c`, as a
/// ray's coordinates are built), compared by their exact `Debug` text (shortest
/// round-trip digits, so two forms print alike only when every field has the same bits,
/// signed zeros included; every NaN prints alike: a NaN's sign and payload, which no
/// decision of a form reads, may differ between vector and scalar instructions).
pub fn check_pack<P: crate::pack::Pack>(default_cases: u32) {
    use crate::pack::LANES;
    let input = (range_tree(), 0usize..4, small_const(), any_finite());
    let lanes = proptest::collection::vec(proptest::collection::vec(input, 3), LANES);
    run(
        &format!("{}: packed lanes", <P::Lane as Range>::NAME),
        default_cases,
        (expr_strategy(6, 3), lanes),
        |(e, lanes)| {
            let form = |&((lo, hi), i, _, _): &((f64, f64), usize, f64, f64)| {
                P::Lane::input(if i < 3 { i } else { usize::MAX }, lo, hi)
            };
            let forms: Vec<Vec<P::Lane>> =
                lanes.iter().map(|l| l.iter().map(form).collect()).collect();
            let scalar: Vec<Vec<P::Lane>> = (0..LANES)
                .map(|k| {
                    (0..3)
                        .map(|i| forms[k][i].clone() * lanes[k][i].2 + lanes[k][i].3)
                        .collect()
                })
                .collect();
            let packed: Vec<P> = (0..3)
                .map(|i| {
                    P::pack(core::array::from_fn(|k| forms[k][i].clone())).mul_add_lanes(
                        core::array::from_fn(|k| lanes[k][i].2),
                        core::array::from_fn(|k| lanes[k][i].3),
                    )
                })
                .collect();
            let got = e.eval(&packed).unpack();
            for (k, lane) in got.iter().enumerate() {
                let want = e.eval(&scalar[k]);
                prop_assert_eq!(
                    format!("{lane:?}"),
                    format!("{want:?}"),
                    "lane {} of {:?}",
                    k,
                    e
                );
            }
            Ok(())
        },
    );
}
