//! What the hull adds to its two parts: half-lines survive, domain edges use the
//! tighter range, and a result is never wider than interval arithmetic's.

use arith_core::testkit::checks::run;
use arith_core::testkit::expr::expr_strategy;
use arith_core::testkit::proptest::prelude::*;
use arith_core::testkit::strategies::range_tree;
use arith_core::{Range, Real};
use arith_hull::Hull;
use arith_ia::Interval;
use arith_revaa::RevAa;

const INF: f64 = f64::INFINITY;

/// `[0.49, 0.51]` and a half-line `[1/0.51 - 0.5 ...]`: `max(1 - x, 1/(x - 0.5))` is
/// `[0.49, inf)` in intervals and the whole line in revised affine forms.
fn half_line() -> Hull<1> {
    let x = Hull::<1>::input(0, 0.49, 0.51);
    x.rsub(1.0).max(&(x - 0.5).recip())
}

#[test]
fn max_keeps_a_half_line() {
    let h = half_line();
    let (lo, hi) = h.bounds();
    assert!((0.48..=0.49).contains(&lo) && hi == INF, "[{lo}, {hi}]");
    let x = RevAa::<1>::input(0, 0.49, 0.51);
    let r = x.rsub(1.0).max(&(x - 0.5).recip());
    assert_eq!(r.bounds(), (-INF, INF), "the affine part alone loses it");
}

#[test]
fn min_keeps_a_half_line() {
    let (lo, hi) = (-half_line()).min(&Hull::constant(0.0)).bounds();
    assert!(lo == -INF && (-0.49..=-0.48).contains(&hi), "[{lo}, {hi}]");
}

#[test]
fn exp_of_a_half_line_is_bounded_and_the_affine_part_comes_back() {
    let e = (-(half_line() * 30.0)).exp();
    let (lo, hi) = e.bounds();
    assert!(lo >= 0.0 && hi < 1e-6, "[{lo}, {hi}]");
    let (alo, ahi) = e.affine.bounds();
    assert!(
        alo.is_finite() && ahi.is_finite(),
        "affine part rebuilt: {e:?}"
    );
    let f = e - 0.5;
    assert!(f.bounds().1 < 0.0 && !f.contains_zero(), "{:?}", f.bounds());
}

#[test]
fn recip_sqrt_ln_of_a_half_line_keep_it() {
    let h = half_line() + 0.01; // [0.5, inf)
    let (lo, hi) = h.recip().bounds();
    assert!(lo >= 0.0 && (2.0..2.1).contains(&hi), "recip [{lo}, {hi}]");
    let (lo, hi) = h.sqrt().bounds();
    assert!((0.7..=0.71).contains(&lo) && hi == INF, "sqrt [{lo}, {hi}]");
    let (lo, hi) = h.ln().bounds();
    assert!((-0.7..-0.69).contains(&lo) && hi == INF, "ln [{lo}, {hi}]");
}

/// `ln` of a range reaching 0 keeps its finite upper side in the interval part.
#[test]
fn ln_reaching_zero_keeps_its_upper_side() {
    let x = Hull::<1>::input(0, 0.0, 2.0);
    let (lo, hi) = x.ln().bounds();
    assert!(lo == -INF && (0.69..0.7).contains(&hi), "[{lo}, {hi}]");
}

/// The affine range of `(x - y)^2 + 0.5` over `[0, 2] x [0, 1]` dips below 0 (revised
/// affine `ln` is then the whole line); its interval is `[0.5, 4.5]`, where `ln` is
/// fitted instead.
#[test]
fn ln_is_fitted_on_the_interval_where_it_is_tighter() {
    fn f<R: Range>() -> (f64, f64) {
        let x = R::input(0, 0.0, 2.0);
        let y = R::input(1, 0.0, 1.0);
        ((x - y).sqr() + 0.5).ln().bounds()
    }
    assert_eq!(f::<RevAa<3>>(), (-INF, INF));
    let (lo, hi) = f::<Hull<3>>();
    assert!(
        lo >= 0.5f64.ln() - 1e-12 && hi <= 4.5f64.ln() + 1e-12,
        "[{lo}, {hi}]"
    );
}

/// Whether `[bl, bh]` lies in `[cl, ch]` up to a few ulps of the ranges' magnitude: the
/// rounding that one more or less exact operation can move (the interval part works on
/// intersections, whose bounds need not be the ones plain intervals round to, and an
/// affine form bounds its rounding errors relative to its centre, not to each bound).
fn inside((bl, bh): (f64, f64), (cl, ch): (f64, f64)) -> bool {
    let scale = [bl, bh, cl, ch]
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let slack = 8.0 * f64::EPSILON * scale + 1e-300;
    (cl == -INF || bl >= cl - slack) && (ch == INF || bh <= ch + slack)
}

/// `((z - z)^2 * x)^-2`: the affine part knows the base is exactly 0 where intervals
/// have `[0, h]`; the narrower operand must not give the wider result.
#[test]
fn negative_even_power_of_an_affine_zero_stays_within_intervals() {
    let (x, z) = (
        Hull::<3>::input(0, 0.0, 1.0),
        Hull::<3>::input(2, 0.0, 0.65),
    );
    let h = ((z - z).sqr() * x).powi(-2).bounds();
    let (xi, zi) = (Interval::input(0, 0.0, 1.0), Interval::input(2, 0.0, 0.65));
    let i = ((zi - zi).sqr() * xi).powi(-2).bounds();
    assert!(i.0 > 1.0 && i.1 == INF, "{i:?}");
    assert!(inside(h, i), "hull {h:?} wider than ia {i:?}");
}

/// `x^3 + max(-0.25, x - x)`: the hull decides the `max` (its `x - x` is exactly 0)
/// where intervals take `[-0.25, h]`; what the decided operand passes on must not be its
/// wider interval `[-h, h]`.
#[test]
fn a_decided_max_passes_on_the_range_both_parts_agree_on() {
    let (lo, hi) = (5.878796858173593, 6.215486183170195);
    let x = Hull::<1>::input(0, lo, hi);
    let h = (x.sqr() * x + Hull::constant(-0.25).max(&(x - x))).bounds();
    let xi = Interval::input(0, lo, hi);
    let i = (xi.sqr() * xi + Interval::constant(-0.25).max(&(xi - xi))).bounds();
    assert!(inside(h, i), "hull {h:?} wider than ia {i:?}");
    let m = (-x.sqr() * x + Hull::constant(0.25).min(&(x - x))).bounds();
    let mi = (-xi.sqr() * xi + Interval::constant(0.25).min(&(xi - xi))).bounds();
    assert!(inside(m, mi), "hull {m:?} wider than ia {mi:?}");
}

/// `min(x / -x, x) * min(z - z, 0)`: the hull's right factor is exactly 0 where
/// intervals have `[-h, 0]`, and `(-inf, 0] * 0` must be `0`, within intervals'
/// `(-inf, 0] * [-h, 0] = [0, inf)`.
#[test]
fn a_half_line_times_an_exact_zero_is_zero() {
    let (x, z) = (
        Hull::<3>::input(0, -7.0, 0.0),
        Hull::<3>::input(2, 0.0, 0.6),
    );
    let h = ((x / -x).min(&x) * (z - z).min(&Hull::constant(0.0))).bounds();
    let (xi, zi) = (Interval::input(0, -7.0, 0.0), Interval::input(2, 0.0, 0.6));
    let i = ((xi / -xi).min(&xi) * (zi - zi).min(&Interval::constant(0.0))).bounds();
    assert_eq!(i, (0.0, INF));
    assert!(inside(h, i), "hull {h:?} wider than ia {i:?}");
}

/// Never wider than intervals: every random tree's hull bounds lie in plain interval
/// arithmetic's, up to [`inside`], also where the tree has no real value (`ln` or a
/// negative power of an exact 0, which the hull's affine part can know where intervals
/// see `[-h, h]`).
#[test]
fn never_wider_than_intervals() {
    let s = (
        expr_strategy(6, 3),
        proptest::collection::vec(range_tree(), 3),
    );
    run("hull within ia", 2000, s, |(e, ranges)| {
        let hull: Vec<Hull<3>> = (0..3)
            .map(|i| Hull::input(i, ranges[i].0, ranges[i].1))
            .collect();
        let ia: Vec<Interval> = (0..3)
            .map(|i| Interval::input(i, ranges[i].0, ranges[i].1))
            .collect();
        let h = e.eval(&hull).bounds();
        let i = e.eval(&ia).bounds();
        prop_assert!(
            inside(h, i),
            "hull {h:?} wider than ia {i:?} for {e:?} over {ranges:?}"
        );
        Ok(())
    });
}
