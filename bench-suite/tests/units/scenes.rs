//! Tests of [`bench_suite::scenes`].

use bench_suite::scenes::*;

#[test]
fn scenes_parse_and_grow_with_n() {
    let a = model_sources::formula::parse(&scene(10, Join::Max, 1)).unwrap();
    let b = model_sources::formula::parse(&scene(100, Join::RUnion, 1)).unwrap();
    assert!(b.len() > 5 * a.len(), "{} vs {}", a.len(), b.len());
    assert_eq!(scene(7, Join::Max, 3), scene(7, Join::Max, 3));
}

/// A tiny run: every row measured, no pixel differs between on and off.
#[test]
fn a_small_run_agrees_on_and_off() {
    let o = Options {
        sizes: vec![10, 40],
        pixels: 24,
        paper_pixels: 16,
        rounds: 1,
        ..Options::default()
    };
    let pts = run(&o, |_| {}).unwrap();
    assert_eq!(pts.len(), 2 * 2 + 5);
    assert!(pts.iter().all(|p| p.differ == 0), "{pts:?}");
    assert!(pts.iter().all(|p| p.evals[0] > 0 && p.evals[1] > 0));
    let md = markdown(&o, &pts);
    // The header, its rule and one line per point.
    assert_eq!(md.matches("\n|").count(), pts.len() + 2);
}
