//! Model files through the one registry (`model_sources::load`, `from_text`): a formula
//! file and a fidget `.vm` tape describing the same solid as hand-written Rust give the
//! same values at random points and the same hit masks and depths (also against the
//! analytic answer); headers set the domain and view; errors name file, line and
//! column; no parser panics on any input.

use arith_core::{Range, Real};
use glam::DVec3;
use model_ir::arith::ArithKind;
use model_ir::camera::Camera;
use model_ir::shape::{Aabb, Shape, View};
use model_sources::{format, from_text, Model};
use proptest::prelude::*;
use tracer::render::{render_kind, RenderOptions};

/// The unit ball minus the box `[-0.5, 0.5]^2 x [0, 2]` (a square notch from the top),
/// with `min` as intersection: `min(1 - r^2, -min(0.25 - x^2, 0.25 - y^2, 1 - (z-1)^2))`.
struct Notched;
impl Shape for Notched {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        let ball = (x.sqr() + y.sqr() + z.sqr()).rsub(1.0);
        let slab = x.sqr().rsub(0.25).min(&y.sqr().rsub(0.25));
        let cut = slab.min(&(z - 1.0).sqr().rsub(1.0));
        ball.min(&-cut)
    }
}

const FORMULA: &str = "\
# The unit ball with a square notch, f >= 0 inside.
# domain: -1.2,-1.2,-1.2,1.2,1.2,1.2
# view: eye=0.9,1.1,3.2 look-at=0,0,0.1 fov=40
ball = 1 - (x^2 + y^2 + z^2);
cut = min(min(0.25 - x^2, 0.25 - y^2), 1 - (z - 1)^2);
min(ball, -cut)
";

/// The same solid in fidget's convention (< 0 inside): `max(r^2 - 1, -box)` with the
/// box `max(x^2 - 0.25, y^2 - 0.25, (z-1)^2 - 1)`.
const VM: &str = "\
# The unit ball with a square notch, fidget convention (f < 0 inside).
# domain: -1.2,-1.2,-1.2,1.2,1.2,1.2
# view: eye=0.9,1.1,3.2 look-at=0,0,0.1 fov=40
x var-x
y var-y
z var-z
x2 square x
y2 square y
z2 square z
xy add x2 y2
r2 add xy z2
one const 1
ball sub r2 one
q const 0.25
bx sub x2 q
by sub y2 q
zc sub z one
zc2 square zc
bz sub zc2 one
bxy max bx by
box max bxy bz
nbox neg box
out max ball nbox
";

fn load_text(text: &str, fmt: &str) -> Model {
    from_text(text, "test", format(fmt).unwrap(), None).unwrap()
}

fn view() -> View {
    View {
        eye: DVec3::new(0.9, 1.1, 3.2),
        look_at: DVec3::new(0.0, 0.0, 0.1),
        up: DVec3::Y,
        fov_deg: 40.0,
        ortho: None,
    }
}

/// The analytic first hit of the notched ball along `o + t d` (unit `d`): `(margin, t)`,
/// a hit iff `margin > 0`, where `margin` is how far the answer is from flipping.
fn analytic(o: DVec3, d: DVec3) -> (f64, f64) {
    let b = o.dot(d);
    let disc = b * b - (o.length_squared() - 1.0);
    if disc <= 0.0 {
        return (disc, f64::INFINITY);
    }
    let (s0, s1) = (-b - disc.sqrt(), -b + disc.sqrt());
    // The open box (slabs), entry and exit.
    let (lo, hi) = (DVec3::new(-0.5, -0.5, 0.0), DVec3::new(0.5, 0.5, 2.0));
    let (mut b0, mut b1) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..3 {
        let (a, c) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
        b0 = b0.max(a.min(c));
        b1 = b1.min(a.max(c));
    }
    let in_box = |t: f64| b0 < t && t < b1;
    if !in_box(s0) {
        // Near an edge of the notch the answer is fragile.
        let m = disc.min((s0 - b0).abs()).min((s0 - b1).abs());
        (m, s0)
    } else if b1 < s1 {
        (disc.min(s1 - b1).min(b1 - s0).min(s0 - b0), b1)
    } else {
        // Through the notch and out: a miss by how far the box outlasts the ball.
        (-(b1 - s1).min(s0 - b0), f64::INFINITY)
    }
}

#[test]
fn the_three_writings_have_the_same_values() {
    let f = load_text(FORMULA, "expr");
    let v = load_text(VM, "vm");
    let mut rng = model_sources::noise::SplitMix64(7);
    for _ in 0..20_000 {
        let p = [(); 3].map(|_| rng.range(-1.3, 1.3));
        let want = Notched.eval(p[0], p[1], p[2]);
        assert_eq!(f.eval(p[0], p[1], p[2]), want, "formula at {p:?}");
        assert_eq!(v.eval(p[0], p[1], p[2]), want, "vm at {p:?}");
    }
    // Over ranges each encloses the point values.
    for _ in 0..200 {
        let c = [(); 3].map(|_| rng.range(-1.2, 1.2));
        let r = 0.05;
        let iv = |k: usize| arith_ia::Interval::input(k, c[k] - r, c[k] + r);
        for m in [&f, &v] {
            let (lo, hi) = m.eval(iv(0), iv(1), iv(2)).bounds();
            for _ in 0..20 {
                let q = [0, 1, 2].map(|k| c[k] + rng.range(-r, r));
                let w = Notched.eval(q[0], q[1], q[2]);
                assert!(lo <= w && w <= hi, "{w} not in [{lo}, {hi}]");
            }
        }
    }
}

#[test]
fn headers_set_domain_and_view() {
    for (text, fmt) in [(FORMULA, "expr"), (VM, "vm")] {
        let m = load_text(text, fmt);
        assert_eq!(m.domain, Aabb::cube(1.2));
        assert_eq!(m.view, view());
        // A domain flag replaces the header's; the header's view fields still apply.
        let d = Aabb::cube(1.5);
        let m = from_text(text, "t", format(fmt).unwrap(), Some(d)).unwrap();
        assert_eq!(m.domain, d);
        assert_eq!(m.view, view());
    }
    // Without a header: the format's domain, framed.
    let m = load_text("1 - x^2 - y^2 - z^2", "expr");
    assert_eq!(m.domain, Aabb::cube(2.0));
    assert_eq!(
        m.view,
        model_ir::camera::frame_box(&Aabb::cube(2.0)).unwrap()
    );
    let m = load_text("# domain: 0,0,0,1,2,3\n# view: ortho=2.5\nx", "expr");
    let framed = model_ir::camera::frame_box(&m.domain).unwrap();
    assert_eq!(
        m.view,
        View {
            ortho: Some(2.5),
            ..framed
        }
    );
    let m = load_text("a var-x", "vm");
    assert_eq!(m.domain, Aabb::cube(1.0));
}

#[test]
fn renders_agree_with_each_other_and_the_analytic_solid() {
    let f = load_text(FORMULA, "expr");
    let v = load_text(VM, "vm");
    let dom = Aabb::cube(1.2);
    let (w, h) = (48, 40);
    for ortho in [None, Some(2.6)] {
        let view = View { ortho, ..view() };
        let cam = Camera::new(view, w, h);
        for k in ArithKind::ALL {
            let mut o = RenderOptions::for_view(view, dom, w, h);
            o.eps = Some(1e-4);
            let rust = render_kind(k, &Notched, &o).unwrap();
            let rf = render_kind(k, &f, &o).unwrap();
            let rv = render_kind(k, &v, &o).unwrap();
            let mut hits = 0;
            for j in 0..h {
                for i in 0..w {
                    let idx = (j * w + i) as usize;
                    let tag = format!("{k} ortho={ortho:?} pixel ({i},{j})");
                    let (ro, rd) = cam.ray(i, j);
                    let (margin, t) = analytic(ro, rd);
                    // Every analytic hit is found; clear misses are misses (a ray that
                    // grazes an edge of the notch within the precision may report a
                    // root there, soundly).
                    if !(-1e-3..=1e-9).contains(&margin) {
                        let want = margin > 0.0;
                        assert_eq!(rust.hit[idx], want, "rust {tag}");
                        assert_eq!(rf.hit[idx], want, "formula {tag}");
                        assert_eq!(rv.hit[idx], want, "vm {tag}");
                    }
                    if margin > 1e-2 && k != ArithKind::Ia {
                        hits += 1;
                        for (name, r) in [("rust", &rust), ("formula", &rf), ("vm", &rv)] {
                            let d = r.depth[idx] as f64;
                            assert!((d - t).abs() < 1e-3, "{name} {tag}: depth {d} vs {t}");
                        }
                    }
                }
            }
            assert!(k == ArithKind::Ia || hits > 400, "{hits} clean hits");
        }
    }
}

#[test]
fn errors_name_the_file_line_and_column() {
    let e = |text: &str, fmt: &str| from_text(text, "m.x", format(fmt).unwrap(), None).unwrap_err();
    assert_eq!(
        e("# comment\nx +\n  (y", "expr"),
        "m.x:3:5: expected ')' to close the '(' at column 3 but found end of input"
    );
    assert_eq!(
        e("x\n# domain: 1,2", "expr"),
        "m.x:2:11: domain: expected 6 comma-separated numbers, got 2 in '1,2'"
    );
    assert!(e("a var-x\nb atan2 a a", "vm")
        .starts_with("m.x:2:3: fidget opcode 'atan2' is not supported"));
    assert_eq!(
        e("a var-x\n\nb neg c", "vm"),
        "m.x:3:7: 'c' is not defined on an earlier line"
    );
    assert!(e("x", "hf").starts_with("m.x:1:2: expected '('"));
    // Paths are checked before anything is read, naming the argument.
    let dir = std::env::temp_dir();
    let missing = dir.join("no-such-model-file.expr");
    let missing = missing.to_str().unwrap();
    let e = model_sources::load("MODEL", missing, None, None).unwrap_err();
    assert!(
        e.starts_with(&format!("MODEL '{missing}': cannot read the file")),
        "{e}"
    );
    let e = model_sources::load("--models", "foo.txt", None, None).unwrap_err();
    assert!(e.contains("--format expr|vm|hf"), "{e}");
    let e = model_sources::load("MODEL", "nonesuch", None, None).unwrap_err();
    assert!(
        e.contains("unknown model 'nonesuch'") && e.contains(".vm"),
        "{e}"
    );
    let d = dir.to_str().unwrap();
    let e = model_sources::load("MODEL", d, Some(format("expr").unwrap()), None).unwrap_err();
    assert!(e.contains("is a folder"), "{e}");
    // A built-in name wins, and a file loads by its extension.
    assert_eq!(
        model_sources::load("MODEL", "csg", None, None)
            .unwrap()
            .name,
        "csg"
    );
    let p = dir.join(format!("tracer-model-files-{}.vm", std::process::id()));
    std::fs::write(&p, VM).unwrap();
    let m = model_sources::load("MODEL", p.to_str().unwrap(), None, None).unwrap();
    assert_eq!(m.eval(0.0, 0.0, -0.5), Notched.eval(0.0, 0.0, -0.5));
    assert!(m.name.starts_with("tracer-model-files-"));
    let _ = std::fs::remove_file(&p);
}

/// Every built-in model's formula (what `tracer list` prints) parses and gives the same
/// values as the built-in at random points in its domain: bit for bit, except blobby,
/// whose point evaluation is its own code path (`u * u * u` for the generic `powi(3)`,
/// support clipping), within a few ulps.
#[test]
fn builtin_formulas_give_the_builtins_values() {
    let mut rng = model_sources::noise::SplitMix64(11);
    let mut n = 0;
    for m in model_sources::all() {
        let Some(text) = m.shape.formula() else {
            // Noise has no formula text.
            assert!(
                m.name.starts_with("hypertexture") || m.name == "landscape",
                "{}",
                m.name
            );
            continue;
        };
        n += 1;
        let t = model_sources::formula::parse(&text)
            .unwrap_or_else(|e| panic!("{}: {}", m.name, e.render(&text)));
        let d = m.domain;
        for _ in 0..2000 {
            let p = [0, 1, 2].map(|k| rng.range(d.min[k], d.max[k]));
            let (a, b) = (t.eval(p[0], p[1], p[2]), m.eval(p[0], p[1], p[2]));
            if m.name == "blobby" {
                assert!(
                    (a - b).abs() <= 1e-13 * (1.0 + b.abs()),
                    "{}: {a} vs {b} at {p:?}",
                    m.name
                );
            } else {
                assert!(
                    a.to_bits() == b.to_bits(),
                    "{}: {a} vs {b} at {p:?}",
                    m.name
                );
            }
        }
    }
    assert_eq!(n, 14);
}

/// Valid tapes with one line changed: dropped, duplicated, a word replaced.
fn mutated_vm() -> impl Strategy<Value = String> {
    let lines: Vec<String> = VM.lines().map(String::from).collect();
    let n = lines.len();
    (0..n, 0..4u8, "[a-z_0-9.+-]{0,8}").prop_map(move |(k, how, word)| {
        let mut l = lines.clone();
        match how {
            0 => {
                l.remove(k);
            }
            1 => {
                let dup = l[k].clone();
                l.insert(k, dup);
            }
            2 => {
                let mut w: Vec<String> = l[k].split(' ').map(String::from).collect();
                let i = w.len() / 2;
                w[i] = word;
                l[k] = w.join(" ");
            }
            _ => l[k].push_str(&format!(" {word}")),
        }
        l.join("\n")
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// No input makes the `.vm` reader, the header reader or the formula-file reader
    /// panic: each gives a model (that evaluates) or an error naming a position.
    #[test]
    fn model_file_readers_never_panic(
        text in prop_oneof![
            ".{0,60}",
            "([a-z_0-9]{1,3} (var-x|var-y|const|add|sub|neg|square|max|tan|sqrt) ?[a-z_0-9.e-]{0,4} ?[a-z_0-9]{0,3}\n){0,6}",
            "(# (domain|view|note): ?[-0-9.,= a-z]{0,30}\n){0,3}[xyz0-9+*() -]{0,10}",
            mutated_vm(),
        ]
    ) {
        for fmt in ["vm", "expr"] {
            match from_text(&text, "p", format(fmt).unwrap(), None) {
                Ok(m) => {
                    let _ = m.eval(0.3, -0.2, 0.1);
                    let _ = m.eval(
                        arith_ia::Interval::input(0, -1.0, 1.0),
                        arith_ia::Interval::input(1, -1.0, 1.0),
                        arith_ia::Interval::input(2, -1.0, 1.0),
                    );
                }
                Err(e) => {
                    prop_assert!(e.starts_with("p:"), "{}", e);
                    prop_assert!(!e.contains('\n'), "{}", e);
                }
            }
        }
    }
}
