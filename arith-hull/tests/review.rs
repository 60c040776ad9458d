//! Adversarial soundness review of arith-hull: hostile ranges, operands and exponents,
//! checked against the multi-precision reference of the test kit.

use arith_core::testkit::review::*;

#[test]
fn hostile_trees_1() {
    hostile_trees::<arith_hull::Hull<1>>(1000);
}
#[test]
fn hostile_trees_3() {
    hostile_trees::<arith_hull::Hull<3>>(1000);
}
#[test]
fn hostile_joint_1() {
    hostile_joint::<arith_hull::Hull<1>>(1000);
}
#[test]
fn hostile_joint_3() {
    hostile_joint::<arith_hull::Hull<3>>(1000);
}

#[test]
fn square_identity_all_scales() {
    square_identity::<arith_hull::Hull<1>>(3000);
    square_identity::<arith_hull::Hull<3>>(1000);
}

#[test]
fn product_identity_all_scales() {
    product_identity::<arith_hull::Hull<1>>(1000);
    product_identity::<arith_hull::Hull<3>>(2000);
}
