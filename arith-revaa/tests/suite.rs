//! The shared soundness suite of `arith_core::testkit` on the ray and the cell form.

use arith_revaa::RevAa;

arith_core::range_test_suite!(revaa1, RevAa<1>, affine = true);
arith_core::range_test_suite!(revaa3, RevAa<3>, affine = true);
