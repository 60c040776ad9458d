//! Interpreter against JIT, ns per instruction per lane, on the bear over the ray
//! segments of `bench-suite/benches/tape.rs` (64 short segments through the bear's box):
//! - `jit/ia/interp_batch_x4`: [`Tape::eval_batch`] over `IntervalX4` packs (the
//!   workspace's fastest interval path, `tape/ia/batch` of the `tape` bench);
//! - `jit/ia/interp_batch`: [`Tape::eval_batch`] over scalar `Interval` lanes;
//! - `jit/ia/jit`: [`IntervalJit::eval`] over the same 64 lanes;
//! - `jit/point/*`: the same in `f64` at the segments' midpoints;
//! - `jit/compile/*`: compiling the bear (ms per tape), for intervals and points.
//!
//! Throughput is instructions times lanes: criterion's elements per second is the
//! inverse of the cost per instruction per lane.

use arith_core::pack::{Pack, LANES};
use arith_ia::{Interval, IntervalX4};
use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use model_ir::Tape;
use std::hint::black_box;
use std::time::Duration;
use tape_jit::{IntervalJit, Lanes, PointJit};
use tracer::search::ray::ray_inputs;

const SEGMENTS: usize = 64;

fn bear() -> Tape {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../peers/fidget/models/bear.vm"
    );
    let text = std::fs::read_to_string(path).expect("the bear model");
    tracer::models::vm::parse(&text).expect("the bear as a tape")
}

/// The `tape` bench's segments.
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

fn all(c: &mut Criterion) {
    let t = bear();
    let segs = segments();
    let inputs: Vec<[Interval; 3]> = segs
        .iter()
        .map(|&(o, d, a, b)| ray_inputs(o.into(), d.into(), a, b))
        .collect();
    let iv: [Vec<Interval>; 3] = core::array::from_fn(|i| inputs.iter().map(|v| v[i]).collect());
    let packs: [Vec<IntervalX4>; 3] = core::array::from_fn(|i| {
        inputs
            .chunks(LANES)
            .map(|ch| IntervalX4::pack(core::array::from_fn(|l| ch[l][i])))
            .collect()
    });
    let lanes = iv.each_ref().map(|v| Lanes::from_intervals(v));
    let pts: [Vec<f64>; 3] =
        core::array::from_fn(|i| iv[i].iter().map(|v| 0.5 * (v.lo + v.hi)).collect());
    let ij = IntervalJit::new(&t).expect("compiles");
    let pj = PointJit::new(&t).expect("compiles");

    // The paths agree (the bench measures the same work).
    let mut out = Lanes::default();
    ij.eval(&lanes[0], &lanes[1], &lanes[2], &mut out);
    let mut batch = Vec::new();
    t.eval_batch(&iv[0], &iv[1], &iv[2], &mut batch);
    for (k, b) in batch.iter().enumerate() {
        assert_eq!(
            (b.lo.to_bits(), b.hi.to_bits()),
            (out.lo[k].to_bits(), out.hi[k].to_bits())
        );
    }

    let mut g = c.benchmark_group("jit/ia");
    g.throughput(Throughput::Elements((t.len() * SEGMENTS) as u64));
    let mut bx4 = Vec::new();
    g.bench_function("interp_batch_x4", |b| {
        b.iter(|| {
            t.eval_batch(&packs[0], &packs[1], &packs[2], &mut bx4);
            black_box(&bx4);
        })
    });
    g.bench_function("interp_batch", |b| {
        b.iter(|| {
            t.eval_batch(&iv[0], &iv[1], &iv[2], &mut batch);
            black_box(&batch);
        })
    });
    g.bench_function("jit", |b| {
        b.iter(|| {
            ij.eval(&lanes[0], &lanes[1], &lanes[2], &mut out);
            black_box(&out);
        })
    });
    g.finish();

    let mut g = c.benchmark_group("jit/point");
    g.throughput(Throughput::Elements((t.len() * SEGMENTS) as u64));
    let mut pb = Vec::new();
    g.bench_function("interp_batch", |b| {
        b.iter(|| {
            t.eval_batch(&pts[0], &pts[1], &pts[2], &mut pb);
            black_box(&pb);
        })
    });
    let mut po = Vec::new();
    g.bench_function("jit", |b| {
        b.iter(|| {
            pj.eval(&pts[0], &pts[1], &pts[2], &mut po);
            black_box(&po);
        })
    });
    g.finish();

    let mut g = c.benchmark_group("jit/compile");
    g.bench_function("bear_ia", |b| {
        b.iter(|| black_box(IntervalJit::new(&t).unwrap()))
    });
    g.bench_function("bear_point", |b| {
        b.iter(|| black_box(PointJit::new(&t).unwrap()))
    });
    g.finish();
}

fn config() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
        .sample_size(10)
}

criterion_group! { name = benches; config = config(); targets = all }
criterion_main!(benches);
