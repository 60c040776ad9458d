//! The cost of one tape instruction per lane in each arithmetic, by evaluation path:
//! `scalar` (one [`Tape::eval`] per ray segment), `pack` (one per four segments, the
//! arithmetic's SIMD pack) and `batch` (one [`Tape::eval_batch`] over
//! [`SEGMENTS`] segments as packs). Throughput is instructions times segments, so
//! criterion's elements per second is the inverse of the cost per instruction per lane;
//! the `arith` bench gives the cost of each operation alone (its rounding and
//! approximation), which no path can go below.
//!
//! The tape is fidget's bear (`bench-suite/peers/fidget/models/bear.vm`), the segments
//! short pieces of rays through its box, as the ray search evaluates them.

use arith_core::pack::{Pack, LANES};
use arith_core::{Arithmetic, Range};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use model_ir::arith::ArithKind;
use model_sources::formula::Tape;
use std::hint::black_box;
use std::time::Duration;
use tracer::search::ray::ray_inputs;

/// Ray segments per batch.
const SEGMENTS: usize = 64;

fn bear() -> Tape {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/peers/fidget/models/bear.vm");
    let text = std::fs::read_to_string(path).expect("the bear model");
    model_sources::vm::parse(&text).expect("the bear as a tape")
}

/// Short segments of rays from a ring of eyes through the middle of the bear's box.
fn segments() -> Vec<([f64; 3], [f64; 3], f64, f64)> {
    (0..SEGMENTS)
        .map(|k| {
            let a = k as f64 * 0.37;
            let o = [2.0 * a.cos(), 0.3 * a.sin(), 2.0 * a.sin()];
            let n = (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt();
            let d = [-o[0] / n, -o[1] / n, -o[2] / n];
            let t0 = 1.4 + 0.01 * (k % 7) as f64;
            (o, d, t0, t0 + 0.02)
        })
        .collect()
}

fn bench_arith<A: Arithmetic>(c: &mut Criterion, t: &Tape) {
    let segs = segments();
    let inputs: Vec<[A::Ray; 3]> = segs
        .iter()
        .map(|&(o, d, a, b)| ray_inputs(o.into(), d.into(), a, b))
        .collect();
    let packs: [Vec<A::RayPack>; 3] = core::array::from_fn(|i| {
        inputs
            .chunks(LANES)
            .map(|ch| A::RayPack::pack(core::array::from_fn(|l| ch[l][i].clone())))
            .collect()
    });
    let mut g = c.benchmark_group(format!("tape/{}", A::NAME));
    g.throughput(Throughput::Elements((t.len() * SEGMENTS) as u64));
    g.bench_function("scalar", |bench| {
        bench.iter(|| {
            for [x, y, z] in &inputs {
                black_box(t.eval(x.clone(), y.clone(), z.clone()));
            }
        })
    });
    g.bench_function("pack", |bench| {
        bench.iter(|| {
            for ((x, y), z) in packs[0].iter().zip(&packs[1]).zip(&packs[2]) {
                black_box(t.eval(x.clone(), y.clone(), z.clone()));
            }
        })
    });
    let mut out = Vec::new();
    g.bench_function("batch", |bench| {
        bench.iter(|| {
            t.eval_batch(&packs[0], &packs[1], &packs[2], &mut out);
            black_box(&out);
        })
    });
    g.finish();
    // The paths agree lane by lane (the bench measures the same work).
    t.eval_batch(&packs[0], &packs[1], &packs[2], &mut out);
    for (k, p) in out.iter().enumerate() {
        let [x, y, z] = [0, 1, 2].map(|i| packs[i][k].clone());
        let one = t.eval(x, y, z);
        for (a, b) in p.clone().unpack().iter().zip(one.unpack().iter()) {
            assert_eq!(a.bounds(), b.bounds());
        }
    }
}

fn all(c: &mut Criterion) {
    let t = bear();
    for kind in ArithKind::ALL {
        if kind.name() == "aa" {
            // Full affine arithmetic has no fixed-size form to batch.
            continue;
        }
        model_ir::with_arith!(kind, A => bench_arith::<A>(c, &t));
    }
}

fn config() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
        .sample_size(10)
}

criterion_group! { name = benches; config = config(); targets = all }
criterion_main!(benches);
