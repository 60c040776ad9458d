//! Tests of [`bench_suite::tightness`].

use arith_core::Real;
use bench_suite::tightness::*;
use model_ir::arith::ArithKind;
use model_ir::shape::{Aabb, Shape};
use model_sources::noise::SplitMix64 as Rng;

/// `f = x*y - z`, whose true range over a box is known exactly.
struct Saddle;
impl Shape for Saddle {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        x * y - z
    }
}

#[test]
fn sampled_range_of_a_saddle_hits_the_corners() {
    let mut rng = Rng(3);
    let cell = [(-1.0, 2.0), (0.5, 1.0), (0.0, 0.25)];
    let (lo, hi) = sampled_cell_range(&Saddle, &cell, 5, 0, &mut rng);
    // extrema at corners: min = -1*1 - 0.25, max = 2*1 - 0
    assert_eq!((lo, hi), (-1.25, 2.0));
}

#[test]
fn cells_and_segments_stay_in_the_domain() {
    let dom = Aabb::cube(2.0);
    let mut rng = Rng(5);
    for _ in 0..200 {
        let c = random_cell(&mut rng, &dom, 0.25);
        for (lo, hi) in c {
            assert!(-2.0 <= lo && lo < hi && hi <= 2.0);
            assert!((hi - lo - 1.0).abs() < 1e-12);
        }
        let (o, d, len) = random_segment(&mut rng, &dom, 0.25);
        for i in 0..3 {
            assert!((-2.0..=2.0).contains(&o[i]));
            assert!((-2.0..=2.0).contains(&(o[i] + d[i] * len)));
        }
    }
}

#[test]
fn every_arithmetic_encloses_the_samples_so_ratios_are_at_least_one() {
    let dom = Aabb::cube(1.0);
    let s = Settings {
        samples: 10,
        ..Settings::default()
    };
    for (kind, cells, segs) in measure_model(&Saddle, &dom, &ArithKind::ALL, &s) {
        for r in cells.iter().chain(segs.iter()) {
            assert!(r.finite > 0, "{kind}");
            assert!(r.mean >= 1.0 - 1e-9, "{kind}: {r:?}");
        }
    }
}
