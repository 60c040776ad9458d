//! The slab search against the paper's: on every built-in model (default view, a small
//! image), each search hits every pixel whose first root the other confirms, at a depth
//! within the precision of the other's.
//!
//! Both report the midpoint of a segment at most the precision long, everything before
//! which is proved root-free; where `f` changes sign across the precision around a
//! search's depth there is a root within it, so the first root lies at most a
//! precision before it and the other search, sound too, reports a depth within a
//! precision of that root. Pixels without such a sign change (unconfirmed hits,
//! roots closer together than the precision) are not compared: there the segments
//! each search happens to test decide what it reports.

use model_ir::arith::ArithKind;
use model_ir::camera::Camera;
use model_ir::shape::Shape;
use model_sources::Model;
use tracer::render::{render_kind, RenderOptions, RenderResult, Search};

fn render(m: &Model, k: ArithKind, search: Search, (w, h): (u32, u32)) -> RenderResult {
    let mut o = RenderOptions::new(m, w, h);
    o.search = search;
    render_kind(k, &m.shape, &o).unwrap()
}

/// Whether `f` changes sign across `[t - e, t + e]` on the ray of pixel `(i, j)`.
fn confirmed(m: &Model, cam: &Camera, (i, j): (u32, u32), t: f64, e: f64) -> bool {
    let (o, d) = cam.ray(i, j);
    let f = |t: f64| {
        let p = o + d * t;
        m.shape.eval::<f64>(p.x, p.y, p.z)
    };
    let (a, b) = (f(t - e), f(t + e));
    a * b < 0.0
}

/// Each search's confirmed hits are the other's hits, depths within twice the
/// precision (plus the depth's f32 storage).
fn check(m: &Model, k: ArithKind, size: (u32, u32)) {
    let slabs = render(m, k, Search::Slabs, size);
    let paper = render(m, k, Search::Paper, size);
    let opts = RenderOptions::new(m, size.0, size.1);
    let cam = Camera::new(opts.view, size.0, size.1);
    let prec = opts.precision(&cam);
    let mut compared = 0;
    for (a, b, which) in [(&slabs, &paper, "slabs"), (&paper, &slabs, "paper")] {
        for idx in 0..a.hit.len() {
            if !a.hit[idx] {
                continue;
            }
            let px = (
                (idx % size.0 as usize) as u32,
                (idx / size.0 as usize) as u32,
            );
            let t = a.depth[idx] as f64;
            let e = prec.at(t);
            if !confirmed(m, &cam, px, t, e) {
                continue;
            }
            compared += 1;
            let tag = format!("{} {k}: pixel {px:?}, {which} confirms t={t}", m.name);
            assert!(b.hit[idx], "{tag}, the other search misses it");
            let u = b.depth[idx] as f64;
            let tol = 2.0 * e.max(prec.at(u)) + 1e-6 * t.abs();
            assert!(
                (t - u).abs() <= tol,
                "{tag}, the other gives t={u} (tol {tol})"
            );
        }
    }
    assert!(compared > 0, "{}: no confirmed hit to compare", m.name);
}

#[test]
fn slab_and_paper_searches_agree_on_every_builtin_model_in_revaa() {
    for m in model_sources::all() {
        check(&m, ArithKind::Revaa, (40, 30));
    }
}

#[test]
fn slab_and_paper_searches_agree_in_ia_and_hull() {
    for m in model_sources::all().iter().take(6) {
        check(m, ArithKind::Ia, (24, 18));
        check(m, ArithKind::Hull, (24, 18));
    }
}

/// The default search is the slab search for a tape that specialises and the paper's
/// for one that does not (or with specialisation off).
#[test]
fn auto_search_follows_specialisation() {
    use arith_core::Real;
    use model_ir::Tape;
    let balls = Tape::record(|x, y, z| {
        let ball = |c: f64| ((x - c).sqr() + y.sqr() + z.sqr()).rsub(0.25);
        ball(0.0).max(&ball(0.5)).max(&ball(1.0).max(&ball(-0.5)))
    });
    let one = Tape::record(|x, y, z| (x.sqr() + y.sqr() + z.sqr()).rsub(1.0));
    assert!(balls.specialises() && !one.specialises());
    assert_eq!(Search::Auto.resolve(&balls, true), Search::Slabs);
    assert_eq!(Search::Auto.resolve(&balls, false), Search::Paper);
    assert_eq!(Search::Auto.resolve(&one, true), Search::Paper);
    assert_eq!(Search::Paper.resolve(&balls, true), Search::Paper);
    assert_eq!(Search::Slabs.resolve(&one, true), Search::Slabs);
}
