//! The default arithmetic: RevAA with its unconfirmed hits searched again in Hull.
//! It removes RevAA's wall on fidget's bear, misses no hit that RevAA or Hull finds,
//! and on a model without walls gives RevAA's image.

use glam::DVec3;
use model_ir::arith::ArithKind;
use model_ir::shape::{Aabb, View};
use model_sources::vm;
use tracer::render::auto_arith::render_auto;
use tracer::render::{render_kind, RenderOptions, RenderResult};

fn bear_options(w: u32, h: u32) -> (model_sources::formula::Tape, RenderOptions) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../bench-suite/peers/fidget/models/bear.vm"
    );
    let tape = vm::parse(&std::fs::read_to_string(path).unwrap()).unwrap();
    let view = View {
        eye: DVec3::new(0.0, 0.0, 2.0),
        look_at: DVec3::ZERO,
        up: DVec3::Y,
        fov_deg: 45.0,
        ortho: Some(2.0),
    };
    (tape, RenderOptions::for_view(view, Aabb::cube(1.0), w, h))
}

/// Pixels hit in `a` but not in `b`.
fn extra(a: &RenderResult, b: &RenderResult) -> usize {
    a.hit
        .iter()
        .zip(&b.hit)
        .filter(|(x, y)| **x && !**y)
        .count()
}

#[test]
fn the_bear_loses_its_wall() {
    let (bear, opts) = bear_options(64, 64);
    let revaa = render_kind(ArithKind::Revaa, &bear, &opts).unwrap();
    let hull = render_kind(ArithKind::Hull, &bear, &opts).unwrap();
    let auto = render_auto(&bear, &opts).unwrap();
    let (r, h, a) = (&revaa.stats, &hull.stats, &auto.stats);
    // RevAA draws a wall that Hull does not, and the default removes it.
    assert!(r.unconfirmed > 10 * (h.unconfirmed + 1), "{r:?} {h:?}");
    assert!(a.unconfirmed <= h.unconfirmed, "{a:?} {h:?}");
    assert_eq!(a.researched, r.unconfirmed, "{a:?} {r:?}");
    assert!(a.hits < r.hits, "{a:?} {r:?}");
    // No root is missed: every pixel Hull hits (Hull never misses one) the default
    // hits too; its only other hits are RevAA's confirmed ones.
    assert_eq!(extra(&hull, &auto), 0);
    assert!(extra(&auto, &hull) <= extra(&revaa, &hull));
    assert_eq!(a.hits, auto.hit.iter().filter(|&&x| x).count() as u64);
}

#[test]
fn tiles_after_a_sample_with_walls_go_to_hull() {
    let (bear, mut opts) = bear_options(96, 96);
    opts.tile = 16;
    // 36 tiles: every fourth one is the sample, the rest follow its choice.
    let hull = render_kind(ArithKind::Hull, &bear, &opts).unwrap();
    let auto = render_auto(&bear, &opts).unwrap();
    let a = &auto.stats;
    assert_eq!((a.tiles_total, a.tiles_hull), (36, 27), "{a:?}");
    assert!(a.unconfirmed <= hull.stats.unconfirmed, "{a:?}");
    assert_eq!(extra(&hull, &auto), 0);
    // The Hull tiles are Hull's image.
    let (w, t) = (96, 16);
    for k in (0..36).filter(|k| k % 4 != 2) {
        let (i0, j0) = ((k % 6) * t, (k / 6) * t);
        for j in j0..j0 + t {
            for i in i0..i0 + t {
                assert_eq!(
                    auto.depth[j * w + i].to_bits(),
                    hull.depth[j * w + i].to_bits()
                );
            }
        }
    }
}

#[test]
fn a_model_without_walls_keeps_revaa_image() {
    let m = model_sources::find("mitchell").unwrap();
    let opts = RenderOptions::new(&m, 80, 60);
    let revaa = render_kind(ArithKind::Revaa, &m.shape, &opts).unwrap();
    let auto = render_auto(&m.shape, &opts).unwrap();
    // Only the rays of unconfirmed hits are searched again, and they are few.
    assert_eq!(auto.stats.researched, revaa.stats.unconfirmed);
    assert!(auto.stats.researched * 100 <= revaa.stats.hits);
    let same = revaa
        .hit
        .iter()
        .zip(&auto.hit)
        .filter(|(a, b)| a == b)
        .count();
    assert!(same as u64 + auto.stats.researched >= revaa.hit.len() as u64);
    // A pixel RevAA hits and the default misses is one whose hit was searched again.
    assert!(extra(&revaa, &auto) as u64 <= auto.stats.researched);
}
