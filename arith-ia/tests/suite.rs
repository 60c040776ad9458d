//! The shared soundness suite (arith_core::testkit) applied to interval arithmetic.

use arith_ia::Interval;

arith_core::range_test_suite!(ia_suite, Interval, affine = false);

/// The SIMD pack is the scalar interval, lane for lane, bit for bit.
#[test]
fn pack_lanes_are_the_scalar_form() {
    use arith_core::testkit::checks::{check_pack, CASES_TREE};
    check_pack::<arith_ia::IntervalX4>(CASES_TREE);
}
