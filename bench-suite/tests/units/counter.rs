//! Tests of [`bench_suite::counter`].

use arith_core::Real;
use bench_suite::counter::*;

/// Mitchell's quartic as in the `arith-core` docs (the tracer's model may group the
/// sums differently, which changes All but not Non-affine or Multiplications).
fn mitchell<R: Real>(x: R, y: R, z: R) -> R {
    let (x2, y2, z2) = (x.sqr(), y.sqr(), z.sqr());
    let yz = y2.clone() + z2.clone();
    (x2.clone() + yz.clone()) * 20.0 - (x2.sqr() + yz.sqr()) * 4.0 - x2 * yz * 17.0 - 17.0
}

#[test]
fn counts_follow_the_rules() {
    let ((), c) = count_ops(|| {
        let x = Counter(2.0);
        let y = Counter(3.0);
        let _ = x + y; // affine
        let _ = x * 2.0; // affine
        let _ = 2.0 * x; // affine
        let _ = x * y; // mul
        let _ = x / y; // non-affine
        let _ = 1.0 - x; // affine (rsub)
        let _ = 1.0 / x; // non-affine (rdiv)
        let _ = x.sqrt(); // non-affine
        let _ = x.powi(3); // mul
        let _ = -x; // affine
    });
    assert_eq!(
        c,
        OpCounts {
            all: 10,
            non_affine: 5,
            mul: 2
        }
    );
}

#[test]
fn counter_computes_the_same_value_as_f64() {
    let (v, _) = count_ops(|| mitchell(Counter(0.3), Counter(-0.7), Counter(0.2)));
    assert_eq!(v.0, mitchell(0.3_f64, -0.7, 0.2));
}

#[test]
fn mitchell_non_affine_and_multiplications_match_the_paper() {
    let (_, c) = count_ops(|| mitchell(Counter(0.3), Counter(-0.7), Counter(0.2)));
    // Paper: 19 / 6 / 6. Our grouping has fewer additions, the same products.
    assert_eq!((c.non_affine, c.mul), (6, 6));
    assert!(c.all < 19, "{c}");
}

#[test]
fn r_function_intersection_has_one_square_root() {
    let (_, c) = count_ops(|| arith_core::rfunc::intersect(Counter(0.5), Counter(-0.25)));
    // two squares, one sqrt; f1 + f2 - r plus the inner sum: 3 affine
    assert_eq!(
        c,
        OpCounts {
            all: 6,
            non_affine: 3,
            mul: 2
        }
    );
}

#[test]
fn counts_are_reset_between_calls() {
    let _ = count_ops(|| Counter(1.0) * Counter(2.0));
    let (_, c) = count_ops(|| Counter(1.0) + 1.0);
    assert_eq!(
        c,
        OpCounts {
            all: 1,
            non_affine: 0,
            mul: 0
        }
    );
}
