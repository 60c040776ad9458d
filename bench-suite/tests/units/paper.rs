//! Tests of [`bench_suite::paper`].

use bench_suite::paper::*;

#[test]
fn names_map_to_the_right_rows() {
    assert_eq!(find("mitchell").unwrap().label, "Mitchell");
    assert_eq!(find("csg").unwrap().label, "CSG");
    assert_eq!(find("csg-blend").unwrap().label, "CSG with blending");
    assert_eq!(find("csg_blending_x").unwrap().label, "CSG with blending");
    assert_eq!(find("Sphere-Noise").unwrap().label, "Sphere with noise");
    assert!(find("teapot").is_none());
}

#[test]
fn algebraic_rows_have_only_multiplications_as_non_affine() {
    for r in &TABLE1[..3] {
        assert_eq!(r.ops.non_affine, r.ops.mul, "{}", r.label);
    }
}
