//! The shared standard soundness suite of `arith_core::testkit`, run against [`Aa`]:
//! every operation at random points, random expression trees, `sqr` versus `x * x`,
//! joint inclusion at fixed input symbols and correlation.

use arith_aa::Aa;

arith_core::range_test_suite!(aa_suite, Aa, affine = true);
