//! The shared soundness suite of `arith_core::testkit` on the ray and the cell form.

use arith_raa::Raa;

arith_core::range_test_suite!(raa1, Raa<1>, affine = true);
arith_core::range_test_suite!(raa3, Raa<3>, affine = true);
