//! Adversarial soundness review of arith-aa: hostile ranges, operands and exponents,
//! checked against the multi-precision reference of the test kit (the generic checks
//! live in `arith_core::testkit::review`, shared by every arithmetic crate).

use arith_core::testkit::review::*;
use arith_core::testkit::{Bin, Expr, Un};
use arith_core::Range;

#[test]
fn hostile_trees_1() {
    hostile_trees::<arith_aa::Aa>(1000);
}
#[test]
fn hostile_joint_1() {
    hostile_joint::<arith_aa::Aa>(1000);
}

/// `sqr`'s centre shift: `two_sum(p, h)` gives `c + t = p + h`, so the centre moves by
/// `h - t`, not `h + t`. With a subnormal `R²` (so `h = R²/2` is itself rounded) the
/// radius `max(h + t, r2 - h - t)` then misses the top of the quadratic part.
/// `(x - x0)²` written as `x² - 2·x0·x + x0²` over `x0 ± r`, `x0 = 2^-500`,
/// `r = (2^26 + 15)·2^-538`: every step but `sqr` is exact here, and the value at
/// `x0 + r` is `r²`, which is not a float (it lies between two subnormals).
#[test]
fn sqr_centre_shift_with_subnormal_radius_squared() {
    use arith_aa::Aa;
    use arith_core::Real;
    let x0 = 2f64.powi(-500);
    let r = (67_108_864.0 + 15.0) * 2f64.powi(-538);
    let (lo, hi) = (x0 - r, x0 + r);
    assert_eq!((lo + hi) * 0.5, x0);
    let e = Expr::bin(
        Bin::Add,
        Expr::bin(
            Bin::Sub,
            Expr::un(Un::Sqr, Expr::Input(0)),
            Expr::un(Un::MulF(2.0 * x0), Expr::Input(0)),
        ),
        Expr::Const(x0 * x0),
    );
    // The same value without the test kit: the upper bound must reach r² > fl(r²).
    let x = Aa::input(0, lo, hi);
    let y = (x.sqr() - x.clone() * (2.0 * x0)) + x0 * x0;
    assert!(y.bounds().1 > r * r, "{:?}", y.bounds());
    assert_sound::<Aa>(&e, &[(lo, hi)], &[hi]);
    assert_sound::<Aa>(&e, &[(lo, hi)], &[lo]);
}

#[test]
fn square_identity_all_scales() {
    square_identity::<arith_aa::Aa>(3000);
}

#[test]
fn product_identity_all_scales() {
    product_identity::<arith_aa::Aa>(2000);
}
