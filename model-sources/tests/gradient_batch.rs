//! The batched gradients of real models (every built-in model a tape expresses, and
//! fidget's `.vm` models) on every lane path this processor has, against the scalar
//! evaluation over `Dual<f64>`: value and partials bit for bit, at a grid of points
//! through each model's domain.

use arith_core::dual::Dual;
use arith_core::lanes::Path;
use model_ir::shape::Aabb;
use model_ir::Tape;

/// `n^3` points of a grid inside `d`, off its planes of symmetry.
fn grid(d: &Aabb, n: usize) -> [Vec<f64>; 3] {
    let mut out: [Vec<f64>; 3] = Default::default();
    let at = |lo: f64, hi: f64, k: usize| lo + (hi - lo) * (k as f64 + 0.37) / n as f64;
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                out[0].push(at(d.min.x, d.max.x, i));
                out[1].push(at(d.min.y, d.max.y, j));
                out[2].push(at(d.min.z, d.max.z, k));
            }
        }
    }
    out
}

fn check(name: &str, t: &Tape, d: &Aabb) {
    let [x, y, z] = grid(d, 9);
    for path in Path::available_paths() {
        let mut out = Vec::new();
        t.eval_gradient_batch_on(path, &x, &y, &z, &mut out);
        assert_eq!(out.len(), x.len());
        for (l, o) in out.iter().enumerate() {
            let s = t.eval(Dual::var(x[l], 0), Dual::var(y[l], 1), Dual::var(z[l], 2));
            let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
            assert!(
                same(o.v, s.v) && (0..3).all(|k| same(o.g[k], s.g[k])),
                "{name}, {path}, at ({}, {}, {}): {o:?} batched, {s:?} scalar",
                x[l],
                y[l],
                z[l]
            );
        }
    }
    for p in Path::ALL.into_iter().filter(|p| !p.available()) {
        eprintln!("gradient_batch: skipped the {p} path (this processor lacks it)");
    }
}

#[test]
fn builtin_models_give_the_dual_bits() {
    let mut checked = 0;
    for m in model_sources::all() {
        if let Ok(t) = m.tape() {
            check(&m.name, &t, &m.domain);
            checked += 1;
        }
    }
    assert!(checked >= 10, "only {checked} built-in models have tapes");
}

#[test]
fn fidget_models_give_the_dual_bits() {
    let dir = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../bench-suite/peers/fidget/models"
    );
    for name in ["bear", "colonnade", "gyroid-sphere", "tanglecube"] {
        let text = std::fs::read_to_string(format!("{dir}/{name}.vm")).expect("model file");
        let t = model_sources::vm::parse(&text).expect("a .vm model");
        check(name, &t, &Aabb::cube(1.0));
    }
}
