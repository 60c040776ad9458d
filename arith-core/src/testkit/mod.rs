//! Shared property-test kit (feature `testkit`): proptest strategies for input ranges,
//! random expression trees over every [`Real`](crate::Real) operation, a rigorous
//! multi-precision reference evaluator (`astro-float`), and the standard soundness suite
//! every arithmetic crate runs against itself.
//!
//! # Using it from an arithmetic crate
//!
//! `Cargo.toml`:
//! ```toml
//! [dev-dependencies]
//! arith-core = { workspace = true, features = ["testkit"] }
//! ```
//! `tests/suite.rs`:
//! ```ignore
//! use arith_aa::Aa;
//! arith_core::range_test_suite!(aa_suite, Aa, affine = true);
//! // For a type with a const parameter, any type expression works:
//! arith_core::range_test_suite!(revaa3, arith_revaa::RevAa<3>, affine = true);
//! ```
//! This generates a module `aa_suite` of `#[test]`s (see [`range_test_suite!`](crate::range_test_suite!)).
//!
//! # What "sound" means in the checks
//!
//! Inputs are built with [`Range::input`](crate::Range::input)`(i, lo, hi)` for
//! `i = 0, 1, 2`; points are drawn inside the ranges (endpoints often). The exact value
//! of the expression at the point is enclosed by [`Mp`] (256-bit `astro-float`, directed
//! rounding, so the enclosure is rigorous and collapses to the exact value on exact
//! chains). A check fails only when that enclosure is *disjoint* from the computed
//! `bounds()`: no tolerance is involved. Extended definitions as in [`crate::Range`]:
//! `sqrt(x) = sqrt(max(x, 0))`, `ln(x <= 0) = -inf`, `x^0 = 1`; points where a divisor
//! is exactly 0 (or `inf - inf`, `0 * inf` arise) are skipped. `-inf`/`+inf` bounds are
//! compared as such (`ln(0) = -inf` lies in `[-inf, c]` but not in `[-1e308, c]`).
//!
//! # Input convention of the joint-inclusion test (affine arithmetics)
//!
//! [`Range::input`](crate::Range::input)`(i, lo, hi)` is `mid + rad * eps_i` with
//! `mid = (lo + hi)/2`, `rad = (hi - lo)/2` (exact reals): `eps_i = -1` is `lo`, `+1` is
//! `hi`. [`Range::bounds_at_inputs`](crate::Range::bounds_at_inputs)`(&eps)` must
//! enclose the exact value at `x_i = mid_i + rad_i * eps_i`; the kit computes that point
//! rigorously in multi-precision, and mostly uses ranges whose `mid`/`rad` are exact
//! `f64`s ([`strategies::range_exact_box`]). `eps` always has 3 entries; inputs with
//! `i >= R::INPUTS` are given zero-width ranges.
//!
//! # Modules
//! - [`strategies`]: floats and ranges (`range_any`, `range_point`,
//!   `range_straddling_zero`, `range_huge`, `range_tiny`, `range_near_zero`,
//!   `range_exact_box`, `range_domain_edge`, `range_exp_edges`, `range_trig`,
//!   `range_tree`), points (`point_in`, `points_in`), `eps_value`, `small_const`.
//! - [`expr`]: [`Expr`] (`Input`, `Const`, `Unary(Un, _)`, `Binary(Bin, _, _)`),
//!   `Expr::eval::<R: Real>(&self, &[R]) -> R`, `Expr::reference(&self, &[Mp])`,
//!   `Expr::reference_at(&self, &[f64], prec)`, `expr_strategy(depth, inputs)`.
//! - [`mp`]: [`Mp`], the reference enclosure, and its [`Verdict`] against bounds.
//! - [`checks`]: the generic checks behind the macro (`check_binary_op`,
//!   `check_unary_named`, `check_random_trees`, `check_constants_and_inputs`,
//!   `check_sqr_not_wider`, `check_joint_inclusion`, `check_correlation`,
//!   `check_linear_part`), and
//!   building blocks (`check_case`, `check_point`, `case_strategy`, `run`) for
//!   crate-specific property tests.
//!
//! Case counts: [`checks::CASES_OP`] per operation, [`checks::CASES_TREE`] for trees;
//! the `PROPTEST_CASES` environment variable overrides all of them.

pub mod checks;
pub mod expr;
pub mod mp;
pub mod review;
pub mod strategies;

pub use expr::{Bin, Expr, Un};
pub use mp::{Mp, Verdict};
/// Re-exported so the macro and users need no direct proptest dependency.
pub use proptest;

/// Generates the standard property-test suite for a [`Range`](crate::Range) type.
///
/// ```ignore
/// arith_core::range_test_suite!(suite_name, RangeType, affine = true);  // or false
/// ```
/// A compiled example (any type expression works, `RevAa<3>` included):
/// ```
/// arith_core::range_test_suite!(ia_suite, arith_ia::Interval, affine = false);
/// ```
///
/// Expands to `mod suite_name { ... }` (with `use super::*;`, so a type imported at the
/// call site resolves) holding these `#[test]`s:
/// - per operation, soundness at random points of random ranges: `op_add`, `op_sub`,
///   `op_mul`, `op_div`, `op_min`, `op_max`, `op_hypot`, `op_neg`, `op_abs`, `op_sqr`, `op_powi`,
///   `op_sqrt`, `op_recip`, `op_exp`, `op_ln`, `op_sin`, `op_cos`, `op_f64_rhs`;
/// - `constants_and_inputs`: `constant`, `from_interval`, `input` enclose their values;
/// - `random_trees`: soundness of random expression trees (depth <= 6, 3 inputs);
/// - `sqr_not_wider_than_mul`: `x.sqr()` never wider than `x * x`;
/// - with `affine = true` also `joint_inclusion`, `correlation` and `linear_part` (see
///   [`checks::check_joint_inclusion`], [`checks::check_correlation`],
///   [`checks::check_linear_part`]).
#[macro_export]
macro_rules! range_test_suite {
    ($suite:ident, $t:ty, affine = $affine:tt) => {
        #[allow(unused_imports)]
        mod $suite {
            use super::*;
            use $crate::testkit::checks as __c;
            use $crate::testkit::Bin as __Bin;

            #[test]
            fn op_add() {
                __c::check_binary_op::<$t>(__Bin::Add, __c::CASES_OP)
            }
            #[test]
            fn op_sub() {
                __c::check_binary_op::<$t>(__Bin::Sub, __c::CASES_OP)
            }
            #[test]
            fn op_mul() {
                __c::check_binary_op::<$t>(__Bin::Mul, __c::CASES_OP)
            }
            #[test]
            fn op_div() {
                __c::check_binary_op::<$t>(__Bin::Div, __c::CASES_OP)
            }
            #[test]
            fn op_min() {
                __c::check_binary_op::<$t>(__Bin::Min, __c::CASES_OP)
            }
            #[test]
            fn op_max() {
                __c::check_binary_op::<$t>(__Bin::Max, __c::CASES_OP)
            }
            #[test]
            fn op_hypot() {
                __c::check_binary_op::<$t>(__Bin::Hypot, __c::CASES_OP)
            }
            #[test]
            fn op_neg() {
                __c::check_unary_named::<$t>("neg", __c::CASES_OP)
            }
            #[test]
            fn op_abs() {
                __c::check_unary_named::<$t>("abs", __c::CASES_OP)
            }
            #[test]
            fn op_sqr() {
                __c::check_unary_named::<$t>("sqr", __c::CASES_OP)
            }
            #[test]
            fn op_powi() {
                __c::check_unary_named::<$t>("powi", __c::CASES_OP)
            }
            #[test]
            fn op_sqrt() {
                __c::check_unary_named::<$t>("sqrt", __c::CASES_OP)
            }
            #[test]
            fn op_recip() {
                __c::check_unary_named::<$t>("recip", __c::CASES_OP)
            }
            #[test]
            fn op_exp() {
                __c::check_unary_named::<$t>("exp", __c::CASES_OP)
            }
            #[test]
            fn op_ln() {
                __c::check_unary_named::<$t>("ln", __c::CASES_OP)
            }
            #[test]
            fn op_sin() {
                __c::check_unary_named::<$t>("sin", __c::CASES_OP)
            }
            #[test]
            fn op_cos() {
                __c::check_unary_named::<$t>("cos", __c::CASES_OP)
            }
            #[test]
            fn op_f64_rhs() {
                __c::check_unary_named::<$t>("f64_rhs", __c::CASES_OP)
            }
            #[test]
            fn constants_and_inputs() {
                __c::check_constants_and_inputs::<$t>(__c::CASES_OP)
            }
            #[test]
            fn random_trees() {
                __c::check_random_trees::<$t>(__c::CASES_TREE)
            }
            #[test]
            fn sqr_not_wider_than_mul() {
                __c::check_sqr_not_wider::<$t>(__c::CASES_OP)
            }
            #[test]
            fn affine_inputs() {
                __c::check_from_affine::<$t>(__c::CASES_TREE)
            }

            $crate::__range_test_suite_affine!($t, $affine);
        }
    };
}

/// Implementation detail of [`range_test_suite!`]: the affine-only tests.
#[doc(hidden)]
#[macro_export]
macro_rules! __range_test_suite_affine {
    ($t:ty, true) => {
        #[test]
        fn joint_inclusion() {
            __c::check_joint_inclusion::<$t>(__c::CASES_TREE)
        }
        #[test]
        fn correlation() {
            __c::check_correlation::<$t>(__c::CASES_OP)
        }
        #[test]
        fn linear_part() {
            __c::check_linear_part::<$t>(__c::CASES_TREE)
        }
        #[test]
        fn affine_part() {
            __c::check_affine_part::<$t>(__c::CASES_TREE)
        }
    };
    ($t:ty, false) => {};
}
