//! The shared soundness suite of `arith_core::testkit` on the ray and the cell form.

use arith_raa::Raa;

arith_core::range_test_suite!(raa1, Raa<1>, affine = true);
arith_core::range_test_suite!(raa3, Raa<3>, affine = true);

/// The SIMD packs are the scalar ray and cell forms, lane for lane and bit for bit.
#[test]
fn pack_lanes_are_the_scalar_form() {
    use arith_core::testkit::checks::{check_pack, CASES_TREE};
    check_pack::<arith_raa::Raa1x4>(CASES_TREE);
    check_pack::<arith_raa::Raa3x4>(CASES_TREE);
}
