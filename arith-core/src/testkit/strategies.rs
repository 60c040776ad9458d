//! proptest strategies for floats, input ranges and points inside ranges.
//!
//! Every range strategy yields `(lo, hi)` with `lo <= hi`, both finite (the
//! [`crate::Range::input`] precondition). Points are drawn inside `[lo, hi]` with the
//! endpoints (where bugs live) picked often.

use proptest::prelude::*;
use proptest::strategy::BoxedStrategy;

/// `2^e` for `-1022 <= e <= 1023`, exactly.
pub fn pow2(e: i32) -> f64 {
    assert!(
        (-1022..=1023).contains(&e),
        "pow2 exponent out of range: {e}"
    );
    f64::from_bits(((e + 1023) as u64) << 52)
}

/// A float with random sign, random 52-bit mantissa and binary exponent in
/// `emin..=emax` (`-1022 <= emin <= emax <= 1023`): log-uniform magnitudes.
pub fn float_exp(emin: i32, emax: i32) -> BoxedStrategy<f64> {
    (any::<bool>(), 0u64..(1u64 << 52), emin..=emax)
        .prop_map(|(neg, m, e)| {
            let x = f64::from_bits((((e + 1023) as u64) << 52) | m);
            if neg {
                -x
            } else {
                x
            }
        })
        .boxed()
}

/// Subnormal floats of either sign.
pub fn subnormal() -> BoxedStrategy<f64> {
    (any::<bool>(), 1u64..(1u64 << 52))
        .prop_map(|(neg, m)| {
            let x = f64::from_bits(m);
            if neg {
                -x
            } else {
                x
            }
        })
        .boxed()
}

/// "Nice" values that hit exact cases: small integers, halves, quarters, 0 and -0.
pub fn nice() -> BoxedStrategy<f64> {
    prop_oneof![
        (-8i32..=8).prop_map(|k| k as f64),
        (-32i32..=32).prop_map(|k| k as f64 * 0.25),
        Just(0.0),
        Just(-0.0),
    ]
    .boxed()
}

/// Floats of moderate magnitude (`|x|` in about `[2^-20, 2^20]`, plus nice values).
pub fn moderate() -> BoxedStrategy<f64> {
    prop_oneof![3 => float_exp(-20, 20), 1 => nice(), 1 => -8.0..8.0f64].boxed()
}

/// Any finite float: moderate, huge, tiny or subnormal.
pub fn any_finite() -> BoxedStrategy<f64> {
    prop_oneof![
        4 => moderate(),
        1 => float_exp(-1022, 1023),
        1 => float_exp(500, 1023),
        1 => float_exp(-1022, -500),
        1 => subnormal(),
        1 => prop_oneof![Just(f64::MAX), Just(-f64::MAX), Just(f64::MIN_POSITIVE), Just(-f64::MIN_POSITIVE)],
    ]
    .boxed()
}

fn sorted((a, b): (f64, f64)) -> (f64, f64) {
    if a <= b {
        (a, b)
    } else {
        (b, a)
    }
}

/// Zero-width ranges `[x, x]`.
pub fn range_point() -> BoxedStrategy<(f64, f64)> {
    any_finite().prop_map(|x| (x, x)).boxed()
}

/// Ranges `[-a, b]` with `a, b >= 0`: straddling (or touching) 0.
pub fn range_straddling_zero() -> BoxedStrategy<(f64, f64)> {
    let mag = prop_oneof![3 => moderate().prop_map(f64::abs), 1 => Just(0.0), 1 => any_finite().prop_map(f64::abs)];
    (mag.clone(), mag).prop_map(|(a, b)| (-a, b)).boxed()
}

/// Ranges between two moderate floats.
pub fn range_moderate() -> BoxedStrategy<(f64, f64)> {
    (moderate(), moderate()).prop_map(sorted).boxed()
}

/// Ranges with huge magnitudes (`2^500 ..= f64::MAX`), of either sign or straddling 0.
pub fn range_huge() -> BoxedStrategy<(f64, f64)> {
    (float_exp(500, 1023), float_exp(500, 1023))
        .prop_map(sorted)
        .boxed()
}

/// Ranges with tiny magnitudes (subnormal up to `2^-500`), of either sign.
pub fn range_tiny() -> BoxedStrategy<(f64, f64)> {
    let t = prop_oneof![float_exp(-1022, -500), subnormal(), Just(0.0)];
    (t.clone(), t).prop_map(sorted).boxed()
}

/// Ranges at the domain edge 0 of `sqrt`, `ln`, `recip`: the lower end is 0, -0, a tiny or
/// subnormal number of either sign, or slightly negative; the upper end is 0 or a small
/// or moderate positive number.
pub fn range_near_zero() -> BoxedStrategy<(f64, f64)> {
    let lo = prop_oneof![
        Just(0.0),
        Just(-0.0),
        subnormal(),
        float_exp(-1022, -30),
        float_exp(-30, -1).prop_map(|x| -x.abs()),
    ];
    let hi = prop_oneof![
        Just(0.0),
        subnormal().prop_map(f64::abs),
        float_exp(-1022, -30).prop_map(f64::abs),
        float_exp(-30, 4).prop_map(f64::abs),
    ];
    (lo, hi).prop_map(sorted).boxed()
}

/// A range with exactly representable midpoint and radius: `mid = m*2^e`,
/// `rad = r*2^e` for integers `|m| < 2^30`, `0 <= r < 2^20`, so `lo = mid - rad` and
/// `hi = mid + rad` are exact and `(lo + hi)/2`, `(hi - lo)/2` computed in `f64` are exact
/// too. Use it where a test needs the type's own `mid`/`rad` without rounding (joint
/// inclusion, `x - x == 0`).
pub fn range_exact_box() -> BoxedStrategy<(f64, f64)> {
    let e = prop_oneof![4 => -40i32..=20, 1 => -900i32..=900];
    (-(1i64 << 30)..(1i64 << 30), 0i64..(1i64 << 20), e)
        .prop_map(|(m, r, e)| {
            let s = pow2(e);
            ((m - r) as f64 * s, (m + r) as f64 * s)
        })
        .boxed()
}

/// Half-lines and the whole line, as `(lo, hi)`: one bound or both infinite.
pub fn range_unbounded() -> BoxedStrategy<(f64, f64)> {
    prop_oneof![
        any_finite().prop_map(|lo| (lo, f64::INFINITY)),
        any_finite().prop_map(|hi| (f64::NEG_INFINITY, hi)),
        Just((f64::NEG_INFINITY, f64::INFINITY)),
    ]
    .boxed()
}

/// Every kind of input range, weighted towards ordinary ones.
pub fn range_any() -> BoxedStrategy<(f64, f64)> {
    prop_oneof![
        4 => range_moderate(),
        2 => range_straddling_zero(),
        2 => range_point(),
        1 => range_huge(),
        1 => range_tiny(),
        1 => range_near_zero(),
        2 => range_exact_box(),
        1 => (any_finite(), any_finite()).prop_map(sorted),
    ]
    .boxed()
}

/// Ranges for the domain edge at 0 (`sqrt`, `ln`, `recip`, divisors): half near zero.
pub fn range_domain_edge() -> BoxedStrategy<(f64, f64)> {
    prop_oneof![range_any(), range_near_zero()].boxed()
}

/// Ranges for divisors, `recip` and negative powers: mostly ranges not holding 0 (whose
/// results are finite, so the checks say something), including tiny ones next to 0,
/// plus ranges at or across 0 (the whole-line case).
pub fn range_divisor() -> BoxedStrategy<(f64, f64)> {
    let nonzero = range_any().prop_filter("divisor range without 0", |&(a, b)| a > 0.0 || b < 0.0);
    let tiny = (range_tiny(), any::<bool>())
        .prop_filter("tiny range without 0", |&((a, b), _)| a > 0.0 || b < 0.0)
        .prop_map(|((a, b), neg)| if neg { (-b, -a) } else { (a, b) });
    prop_oneof![4 => nonzero, 1 => tiny, 1 => range_near_zero(), 1 => range_straddling_zero()]
        .boxed()
}

/// Ranges for `sqrt` and `ln`: the domain edge at 0, negative ranges, and (for half of
/// the cases) ranges inside the positive domain, where the results are finite.
pub fn range_positive_domain() -> BoxedStrategy<(f64, f64)> {
    let positive = range_any().prop_map(|(a, b)| sorted((a.abs(), b.abs())));
    prop_oneof![2 => positive, 1 => range_near_zero(), 1 => range_any()].boxed()
}

/// Ranges for `exp`: besides [`range_any`], ranges around the overflow (`~709.78`) and
/// underflow (`~-745.13`) edges.
pub fn range_exp_edges() -> BoxedStrategy<(f64, f64)> {
    let edge = prop_oneof![700.0..720.0f64, -760.0..-700.0f64, -40.0..40.0f64];
    prop_oneof![
        range_any(),
        (edge.clone(), edge.clone()).prop_map(sorted),
        edge.prop_map(|x| (x, x)),
    ]
    .boxed()
}

/// Ranges for `sin`/`cos`: besides [`range_any`], short ranges around multiples of
/// `pi/2` (where the extrema are) and large arguments.
pub fn range_trig() -> BoxedStrategy<(f64, f64)> {
    let near_crit = (-20i32..=20, -1e-3..1e-3f64, 0.0..1e-2f64).prop_map(|(k, off, w)| {
        let c = k as f64 * core::f64::consts::FRAC_PI_2 + off;
        (c, c + w)
    });
    prop_oneof![
        2 => range_any(),
        2 => near_crit,
        1 => (float_exp(20, 1023), 0.0..1e3f64).prop_map(|(x, w)| (x, x + w)),
    ]
    .boxed()
}

/// Input ranges for random expression trees: mostly moderate (`|x| <= 8`-ish) so that
/// deep trees stay mostly finite, with points, straddling ranges and exact boxes.
pub fn range_tree() -> BoxedStrategy<(f64, f64)> {
    let small = prop_oneof![3 => -8.0..8.0f64, 1 => nice(), 1 => float_exp(-30, 2)];
    prop_oneof![
        3 => (small.clone(), small.clone()).prop_map(sorted),
        1 => small.clone().prop_map(|x| (x, x)),
        1 => (small.clone(), 0.0..1.0f64).prop_map(|(x, w)| (x, x + w)),
        1 => (small.clone().prop_map(f64::abs), small.prop_map(f64::abs)).prop_map(|(a, b)| (-a, b)),
        1 => range_tree_exact(),
    ]
    .boxed()
}

/// Exact-box ranges with moderate magnitudes for expression trees over affine forms.
pub fn range_tree_exact() -> BoxedStrategy<(f64, f64)> {
    let e = -30i32..=-20;
    (-(1i64 << 24)..(1i64 << 24), 0i64..(1i64 << 22), e)
        .prop_map(|(m, r, e)| {
            let s = pow2(e);
            ((m - r) as f64 * s, (m + r) as f64 * s)
        })
        .boxed()
}

/// A point inside `[lo, hi]` (both finite): either endpoint (often), the midpoint, or a
/// uniformly placed point. Always within `[lo, hi]` (clamped after rounding).
pub fn point_in(lo: f64, hi: f64) -> BoxedStrategy<f64> {
    let inner = (0.0..=1.0f64).prop_map(move |t| {
        // lo*(1-t) + hi*t never overflows for finite lo, hi.
        let x = lo * (1.0 - t) + hi * t;
        if x.is_nan() {
            lo
        } else {
            x.clamp(lo, hi)
        }
    });
    let mid = {
        let m = lo * 0.5 + hi * 0.5;
        if m.is_nan() {
            lo
        } else {
            m.clamp(lo, hi)
        }
    };
    prop_oneof![2 => Just(lo), 2 => Just(hi), 1 => Just(mid), 3 => inner].boxed()
}

/// One point inside each range.
pub fn points_in(ranges: &[(f64, f64)]) -> BoxedStrategy<Vec<f64>> {
    ranges
        .iter()
        .map(|&(lo, hi)| point_in(lo, hi))
        .collect::<Vec<_>>()
        .boxed()
}

/// A value for a noise symbol: `-1`, `0`, `+1` or uniform in `[-1, 1]`.
pub fn eps_value() -> BoxedStrategy<f64> {
    prop_oneof![Just(-1.0), Just(0.0), Just(1.0), -1.0..=1.0f64].boxed()
}

/// Constants for expression trees and `f64` operands: `[-4, 4]`, often exact.
pub fn small_const() -> BoxedStrategy<f64> {
    prop_oneof![
        (-4i32..=4).prop_map(|k| k as f64),
        (-16i32..=16).prop_map(|k| k as f64 * 0.25),
        -4.0..=4.0f64
    ]
    .boxed()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::test_runner::TestRunner;

    #[test]
    fn ranges_are_ordered_and_finite() {
        let mut runner = TestRunner::deterministic();
        for s in [
            range_any(),
            range_domain_edge(),
            range_positive_domain(),
            range_exp_edges(),
            range_trig(),
            range_tree(),
        ] {
            runner
                .run(&s, |(lo, hi)| {
                    prop_assert!(lo <= hi && lo.is_finite() && hi.is_finite(), "{lo} {hi}");
                    Ok(())
                })
                .unwrap();
        }
    }

    #[test]
    fn exact_boxes_have_exact_mid_and_rad() {
        let mut runner = TestRunner::deterministic();
        runner
            .run(&range_exact_box(), |(lo, hi)| {
                let (mid, rad) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
                prop_assert_eq!(mid - rad, lo);
                prop_assert_eq!(mid + rad, hi);
                Ok(())
            })
            .unwrap();
    }

    #[test]
    fn points_lie_inside() {
        let mut runner = TestRunner::deterministic();
        let s = range_any().prop_flat_map(|(lo, hi)| (Just((lo, hi)), point_in(lo, hi)));
        runner
            .run(&s, |((lo, hi), x)| {
                prop_assert!(lo <= x && x <= hi);
                Ok(())
            })
            .unwrap();
    }
}
