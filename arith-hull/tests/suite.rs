//! The shared soundness suite of `arith_core::testkit` on the ray and the cell form.

use arith_hull::Hull;

arith_core::range_test_suite!(hull1, Hull<1>, affine = true);
arith_core::range_test_suite!(hull3, Hull<3>, affine = true);

/// The lane packs are the scalar ray and cell forms, lane for lane.
#[test]
fn pack_lanes_are_the_scalar_form() {
    use arith_core::testkit::checks::{check_pack, CASES_TREE};
    use arith_core::Arithmetic;
    check_pack::<<arith_hull::HullArith as Arithmetic>::RayPack>(CASES_TREE);
    check_pack::<<arith_hull::HullArith as Arithmetic>::CellPack>(CASES_TREE);
}
