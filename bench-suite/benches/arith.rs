//! Each operation in each arithmetic, in the ray form (one input) and the cell form
//! (three inputs). Operands are typical mid-evaluation values: for rays
//! `a = t`, `b = t^2/2 + 0.7` over `t ∈ [0.5, 0.9]`; for cells `a = 0.3x + 0.2y + 0.1z + 1`,
//! `b = x*y + 2` over a small box. Both are positive, so `sqrt`, `ln`, `recip` and `/` take
//! their ordinary paths. Binary operations take their operands by value, so each
//! measurement includes the clones a model would also make.

use arith_core::{Arithmetic, Range, Real};
use criterion::{criterion_group, criterion_main, Criterion};
use model_ir::arith::ArithKind;
use std::hint::black_box;
use std::time::Duration;

type Op<R> = (&'static str, fn(&R, &R) -> R);

fn ops<R: Real>() -> Vec<Op<R>> {
    vec![
        ("add", |a, b| a.clone() + b.clone()),
        ("sub", |a, b| a.clone() - b.clone()),
        ("mul", |a, b| a.clone() * b.clone()),
        ("div", |a, b| a.clone() / b.clone()),
        ("sqr", |a, _| a.sqr()),
        ("sqrt", |a, _| a.sqrt()),
        ("recip", |a, _| a.recip()),
        ("exp", |a, _| a.exp()),
        ("ln", |a, _| a.ln()),
        ("sin", |a, _| a.sin()),
        ("cos", |a, _| a.cos()),
        ("abs", |a, _| a.abs()),
        ("min", |a, b| a.min(b)),
        ("max", |a, b| a.max(b)),
        ("powi3", |a, _| a.powi(3)),
    ]
}

fn ray_operands<R: Range>() -> (R, R) {
    let t = R::input(0, 0.5, 0.9);
    let b = t.sqr() * 0.5 + 0.7;
    (t, b)
}

fn cell_operands<R: Range>() -> (R, R) {
    let x = R::input(0, 0.1, 0.2);
    let y = R::input(1, -0.3, -0.2);
    let z = R::input(2, 0.4, 0.45);
    let a = x.clone() * 0.3 + y.clone() * 0.2 + z * 0.1 + 1.0;
    let b = x * y + 2.0;
    (a, b)
}

fn bench_form<R: Range>(c: &mut Criterion, form: &str, arith: &str, (a, b): (R, R)) {
    let mut g = c.benchmark_group(format!("op-{form}/{arith}"));
    for (name, f) in ops::<R>() {
        g.bench_function(name, |bench| bench.iter(|| f(black_box(&a), black_box(&b))));
    }
    g.finish();
}

fn bench_arith<A: Arithmetic>(c: &mut Criterion) {
    bench_form::<A::Ray>(c, "ray", A::NAME, ray_operands());
    bench_form::<A::Cell>(c, "cell", A::NAME, cell_operands());
}

fn all(c: &mut Criterion) {
    for kind in ArithKind::ALL {
        model_ir::with_arith!(kind, A => bench_arith::<A>(c));
    }
}

fn config() -> Criterion {
    // 120 benchmarks: short windows keep the whole file near a minute on 2 cores.
    Criterion::default()
        .warm_up_time(Duration::from_millis(150))
        .measurement_time(Duration::from_millis(300))
        .sample_size(10)
}

criterion_group! { name = benches; config = config(); targets = all }
criterion_main!(benches);
