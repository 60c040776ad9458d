//! Tests of [`bench_suite::formulas`].

use bench_suite::formulas::*;
use model_ir::arith::ArithKind;
use model_sources::formula;
use model_sources::noise::SplitMix64 as Rng;

#[test]
fn formulas_parse_and_the_study_counts_every_one() {
    let mut rng = Rng(3);
    let parsed = (0..200)
        .filter(|_| formula::parse(&random_formula(&mut rng, 5)).is_ok())
        .count();
    assert!(parsed > 150, "only {parsed} of 200 formulas parse");
    let s = Settings {
        formulas: 30,
        ..Settings::default()
    };
    let (rows, _) = study(&ArithKind::ALL, &s);
    for (k, sh) in &rows {
        assert_eq!(sh.formulas, 30, "{k:?}");
        // A reference is never wider than itself.
        if k.name() == "ia" {
            assert_eq!(sh.wider_than_ia, 0);
        }
        if k.name() == "revaa" {
            assert_eq!(sh.wider_than_revaa, 0);
        }
    }
}

#[test]
fn wider_allows_rounding_only() {
    assert!(!wider((0.0, 1.0), (0.0, 1.0)));
    assert!(!wider((-1e-16, 1.0), (0.0, 1.0)));
    assert!(wider((-1e-9, 1.0), (0.0, 1.0)));
    assert!(wider((0.0, f64::INFINITY), (0.0, 1.0)));
    assert!(!wider((0.0, 5.0), (0.0, f64::INFINITY)));
}
