//! The default arithmetic's probe: Hull where RevAA's ranges draw a wall of unconfirmed
//! hits (fidget's bear), RevAA elsewhere; and a render in the chosen arithmetic keeps
//! the wall away.

use glam::DVec3;
use model_ir::arith::ArithKind;
use model_ir::shape::{Aabb, View};
use model_sources::vm;
use tracer::render::auto_arith::choose;
use tracer::render::{render_kind, RenderOptions};

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

#[test]
fn the_bear_takes_hull_and_loses_its_wall() {
    let (bear, opts) = bear_options(64, 64);
    let c = choose(&bear, &opts).unwrap();
    assert_eq!(c.kind, ArithKind::Hull, "{c:?}");
    let hull = c
        .unconfirmed
        .1
        .expect("RevAA's wall makes the probe look at Hull");
    assert!(c.unconfirmed.0 > hull + c.hits / 100, "{c:?}");
    let revaa = render_kind(ArithKind::Revaa, &bear, &opts).unwrap().stats;
    let hull = render_kind(c.kind, &bear, &opts).unwrap().stats;
    // RevAA's wall adds hits where Hull finds none; every Hull hit is one of RevAA's
    // too (both never miss a root).
    assert!(hull.hits < revaa.hits, "{revaa:?} {hull:?}");
    assert!(
        hull.unconfirmed * 10 < revaa.unconfirmed,
        "{revaa:?} {hull:?}"
    );
}

#[test]
fn a_model_without_walls_keeps_revaa() {
    let m = model_sources::find("mitchell").unwrap();
    let opts = RenderOptions::new(&m, 80, 60);
    let c = choose(&m.shape, &opts).unwrap();
    assert_eq!(c.kind, ArithKind::Revaa, "{c:?}");
    assert_eq!(c.size, (48, 36));
    // Few unconfirmed hits in RevAA: no Hull count could change the choice.
    assert_eq!(c.unconfirmed.1, None, "{c:?}");
}
