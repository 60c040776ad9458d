//! The shared soundness suite (arith_core::testkit) applied to interval arithmetic.

use arith_ia::Interval;

arith_core::range_test_suite!(ia_suite, Interval, affine = false);
