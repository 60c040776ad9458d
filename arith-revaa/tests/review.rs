//! Adversarial soundness review of arith-revaa: hostile ranges, operands and exponents,
//! checked against the multi-precision reference of the test kit (the generic checks
//! live in `arith_core::testkit::review`, shared by every arithmetic crate).

use arith_core::testkit::review::*;
use arith_core::Range;

#[test]
fn hostile_trees_1() {
    hostile_trees::<arith_revaa::RevAa<1>>(1000);
}
#[test]
fn hostile_trees_3() {
    hostile_trees::<arith_revaa::RevAa<3>>(1000);
}
#[test]
fn hostile_joint_1() {
    hostile_joint::<arith_revaa::RevAa<1>>(1000);
}
#[test]
fn hostile_joint_3() {
    hostile_joint::<arith_revaa::RevAa<3>>(1000);
}

/// The [`Range`] contract: `sqrt` of a range wholly below 0 is exactly `[0, 0]`. An
/// approximation with `alpha = 0` is the constant `zeta ± delta` whatever the operand,
/// with nothing to round.
#[test]
fn sqrt_of_negative_range_is_exactly_zero() {
    use arith_core::Real;
    use arith_revaa::RevAa;
    let x = RevAa::<1>::input(0, -3.0, -1.0);
    assert_eq!(x.sqrt().bounds(), (0.0, 0.0));
    let y = RevAa::<3>::input(2, 1.0, 2.0) * 0.1 - 5.0;
    assert_eq!(y.sqrt().bounds(), (0.0, 0.0));
    // A wide operand: sin's fallback [-1, 1] stays exactly [-1, 1].
    let z = RevAa::<1>::input(0, 0.0, 100.0).sin();
    assert_eq!(z.bounds(), (-1.0, 1.0));
}

#[test]
fn square_identity_all_scales() {
    square_identity::<arith_revaa::RevAa<1>>(3000);
    square_identity::<arith_revaa::RevAa<3>>(1000);
}

#[test]
fn product_identity_all_scales() {
    product_identity::<arith_revaa::RevAa<1>>(1000);
    product_identity::<arith_revaa::RevAa<3>>(2000);
}
