//! Tests of [`bench_suite::scaling`].

use bench_suite::scaling::*;
use model_sources::PaperModel;

#[test]
fn pixels_grow_fourfold_and_work_grows_with_them() {
    let o = Options {
        models: vec![PaperModel::Mitchell],
        base_scale: 0.01,
        steps: 2,
        ..Options::default()
    };
    let pts = measure(&o).unwrap();
    assert_eq!(pts.len(), 4);
    let (a, b) = (&pts[0], &pts[2]);
    assert!(!a.culling && !b.culling);
    assert!(b.width >= 2 * a.width - 1 && b.height >= 2 * a.height - 1);
    // More pixels, more rays: the ray work cannot shrink.
    assert!(b.ray_evals > a.ray_evals);
    // Culling on never adds ray evaluations (it only removes rays).
    assert!(pts[1].ray_evals <= pts[0].ray_evals);
    let md = markdown(&o, &pts);
    assert!(md.contains("mitchell") && md.contains("| on |"));
}

#[test]
fn bad_steps_are_errors() {
    let o = Options {
        steps: 0,
        ..Options::default()
    };
    assert!(measure(&o).is_err());
}
