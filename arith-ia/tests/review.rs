//! Adversarial soundness review of arith-ia: hostile ranges, operands and exponents,
//! checked against the multi-precision reference of the test kit (the generic checks
//! live in `arith_core::testkit::review`, shared by every arithmetic crate).

use arith_core::testkit::checks::{self, Case};
use arith_core::testkit::review::*;
use arith_core::testkit::strategies::*;
use arith_core::testkit::{Bin, Expr, Un};
use proptest::prelude::*;
use proptest::strategy::BoxedStrategy;

#[test]
fn hostile_trees_1() {
    hostile_trees::<arith_ia::Interval>(1000);
}

/// Any finite `f64` bit pattern (subnormals, huge, every exponent).
fn any_bits() -> BoxedStrategy<f64> {
    prop_oneof![
        any::<f64>().prop_filter("finite", |x| x.is_finite()),
        any_finite(),
        (1u64..64, -1080i32..-1000).prop_map(|(m, e)| m as f64 * 2f64.powi(e)),
    ]
    .boxed()
}

/// The directed `+ - * /` of point intervals bracket the exact result for every pair
/// of floats, near underflow and overflow included (the error-free sign tests of `dir`).
#[test]
fn point_operations_bracket_exact_results() {
    use arith_ia::Interval;
    let ops = [Bin::Add, Bin::Sub, Bin::Mul, Bin::Div, Bin::Min, Bin::Max];
    let stats = checks::Stats::default();
    checks::run(
        "ia: point operations",
        4000,
        (any_bits(), any_bits(), 0usize..6, 1i32..=9),
        |(a, b, k, n)| {
            let e = Expr::bin(ops[k], Expr::Input(0), Expr::Input(1));
            let case = Case {
                expr: e,
                ranges: vec![(a, a), (b, b)],
                points: vec![vec![a, b]],
            };
            checks::check_case::<Interval>(&case, &stats)?;
            for op in [
                Un::Powi(n),
                Un::Powi(-n),
                Un::Sqrt,
                Un::Recip,
                Un::DivF(b),
                Un::MulF(b),
            ] {
                let case = Case {
                    expr: Expr::un(op, Expr::Input(0)),
                    ranges: vec![(a, a)],
                    points: vec![vec![a]],
                };
                checks::check_case::<Interval>(&case, &stats)?;
            }
            Ok(())
        },
    );
}

#[test]
fn square_identity_all_scales() {
    square_identity::<arith_ia::Interval>(1000);
}
