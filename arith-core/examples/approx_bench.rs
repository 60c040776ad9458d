//! Timing harness for the approximation hot paths (not a test: no assertions on time).
//!
//! `cargo run --release -p arith-core --example approx_bench [iters]` prints ns per call
//! (best of 5 runs) for the shared approximations, `RevAa<1>` operations, and one
//! evaluation of the CSG and Mitchell models over a ray-like segment (written here with
//! `arith_core::rfunc`, as in the tracer). Under `valgrind --tool=callgrind` pass a
//! small iteration count and a name filter for repeatable instruction counts.

use arith_core::approx;
use arith_core::rfunc::{intersect, subtract, union};
use arith_core::{Range, Real};
use arith_revaa::RevAa;
use std::hint::black_box;
use std::time::Instant;

/// Pseudo-random narrow intervals like those of ray segments: `(centre, width)` pairs.
fn intervals(n: usize, lo: f64, hi: f64, wmax: f64) -> Vec<(f64, f64)> {
    let mut s = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let c = lo + (hi - lo) * next();
            let w = wmax * next() * next();
            (c, c + w)
        })
        .collect()
}

fn time<F: FnMut(usize)>(name: &str, iters: usize, mut f: F) {
    // Optional second argument: run only the benchmark of that name (for
    // per-benchmark instruction counts under `perf stat` or callgrind).
    if let Some(filter) = std::env::args().nth(2) {
        if name != filter {
            return;
        }
    }
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let t = Instant::now();
        for i in 0..iters {
            f(i);
        }
        best = best.min(t.elapsed().as_secs_f64() * 1e9 / iters as f64);
    }
    println!("{name:<24} {best:9.1} ns");
}

fn mitchell<R: Real>(x: R, y: R, z: R) -> R {
    let x2 = x.sqr();
    let yz = y.sqr() + z.sqr();
    (x2.clone() + yz.clone()) * 20.0 - (x2.sqr() + yz.sqr()) * 4.0 - x2 * yz * 17.0 - 17.0
}

fn csg<R: Real>(x: R, y: R, z: R) -> R {
    let (x2, y2, z2) = (x.sqr(), y.sqr(), z.sqr());
    let b = intersect(
        intersect(x2.clone().rsub(0.36), y2.clone().rsub(0.36)),
        z2.clone().rsub(0.36),
    );
    let s = (x2.clone() + y2.clone() + z2.clone()).rsub(0.7056);
    let yz = y2.clone() + z2.clone();
    let xz = x2.clone() + z2;
    let c1 = yz.clone().rsub(0.09);
    let c2 = yz.rsub(0.04);
    let c3 = xz.clone().rsub(0.09);
    let c4 = xz.rsub(0.04);
    let c5 = (x2 + y2).rsub(0.25);
    let tubes = union(subtract(c1, c2), subtract(c3, c4));
    union(b, subtract(intersect(s, tubes), c5))
}

/// A ray segment `t ∈ [t0, t1]` through the model's box, as the tracer builds it.
fn ray_eval<R: Range>(model: fn(R, R, R) -> R, seg: (f64, f64), dir: [f64; 3]) -> (f64, f64) {
    let t = R::input(0, seg.0, seg.1);
    let o = [-0.9, -0.7, -0.8];
    let x = t.clone() * dir[0] + o[0];
    let y = t.clone() * dir[1] + o[1];
    let z = t * dir[2] + o[2];
    model(x, y, z).bounds()
}

fn main() {
    let iters: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(200_000);
    let n = 4096;
    let pos = intervals(n, 0.01, 2.0, 0.05);
    let any = intervals(n, -3.0, 3.0, 0.05);
    let sq = intervals(n, -1.0, 1.0, 0.1);
    let g = |v: &Vec<(f64, f64)>, i: usize| black_box(v[i % n]);
    time("approx::sqrt", iters, |i| {
        let (a, b) = g(&pos, i);
        black_box(approx::sqrt(a, b));
    });
    time("approx::sin", iters, |i| {
        let (a, b) = g(&any, i);
        black_box(approx::sin(a, b));
    });
    time("approx::cos", iters, |i| {
        let (a, b) = g(&any, i);
        black_box(approx::cos(a, b));
    });
    time("approx::exp", iters, |i| {
        let (a, b) = g(&any, i);
        black_box(approx::exp(a, b));
    });
    time("approx::recip", iters, |i| {
        let (a, b) = g(&pos, i);
        black_box(approx::recip(a, b));
    });
    time("approx::sqr", iters, |i| {
        let (a, b) = g(&sq, i);
        black_box(approx::sqr(a, b));
    });
    let rv = |v: &Vec<(f64, f64)>, i: usize| {
        let (a, b) = v[i % n];
        black_box(RevAa::<1>::input(0, a, b))
    };
    time("RevAa<1> mul", iters, |i| {
        black_box(rv(&sq, i) * rv(&any, i + 1));
    });
    time("RevAa<1> sqr", iters, |i| {
        black_box(rv(&sq, i).sqr());
    });
    time("RevAa<1> sqrt", iters, |i| {
        black_box(rv(&pos, i).sqrt());
    });
    time("RevAa<1> sin", iters, |i| {
        black_box(rv(&any, i).sin());
    });
    let segs = intervals(n, 0.0, 2.5, 0.02);
    let dirs = intervals(n, 0.2, 0.9, 0.0);
    let d = |i: usize| {
        let (a, _) = dirs[i % n];
        let (b, _) = dirs[(i + 7) % n];
        let (c, _) = dirs[(i + 13) % n];
        [a, b, c]
    };
    let it = iters / 10;
    time("csg RevAa<1>", it, |i| {
        black_box(ray_eval::<RevAa<1>>(csg, g(&segs, i), d(i)));
    });
    time("mitchell RevAa<1>", it, |i| {
        black_box(ray_eval::<RevAa<1>>(mitchell, g(&segs, i), d(i)));
    });
    time("csg Interval", it, |i| {
        black_box(ray_eval::<arith_ia::Interval>(csg, g(&segs, i), d(i)));
    });
    time("mitchell Interval", it, |i| {
        black_box(ray_eval::<arith_ia::Interval>(mitchell, g(&segs, i), d(i)));
    });
}
