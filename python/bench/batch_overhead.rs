//! The Rust side of the binding's overhead measurement (`bench/overhead.py` runs it in
//! turn with the Python side): the very batch code behind `Shape.eval` and
//! `Shape.eval_boxes` ([`batch`]), called on the same points and boxes, timed in
//! process, one line per call:
//!
//! ```text
//! points SECONDS
//! boxes ARITH SECONDS
//! ```
//!
//! `cargo bench -p tracer-python --bench batch_overhead -- MODEL POINTS BOXES REPS
//! ARITH[,ARITH...]`; MODEL is a built-in model's name or a formula.

#[allow(dead_code)]
#[path = "../src/batch.rs"]
mod batch;
#[allow(unused_imports, dead_code)]
#[path = "../src/toolkit.rs"]
mod toolkit;

use std::sync::atomic::AtomicBool;
use std::time::Instant;
use toolkit::models::{find, Model};
use toolkit::ArithKind;

/// The `k`-th point of the benchmark's sequence in `[lo, hi]^3`: each coordinate a
/// Weyl sequence, as `bench/overhead.py` computes it with numpy (the same IEEE
/// operations, so the same doubles).
fn point(k: usize, lo: f64, hi: f64) -> [f64; 3] {
    const G: [f64; 3] = [
        0.618_033_988_749_894_9,
        0.754_877_666_246_692_7,
        0.569_840_290_998_053_2,
    ];
    G.map(|g| lo + (hi - lo) * ((k as f64 * g) % 1.0))
}

/// Half the side of the benchmark's boxes.
const HALF_SIDE: f64 = 0.01;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let [model, points, boxes, reps, ariths] = &args[..] else {
        return Err("usage: batch_overhead MODEL POINTS BOXES REPS ARITH[,ARITH...]".into());
    };
    let parse = |s: &str| s.parse::<usize>().map_err(|e| format!("{s}: {e}"));
    let (points, boxes, reps) = (parse(points)?, parse(boxes)?, parse(reps)?);
    let kinds: Vec<ArithKind> = ariths
        .split(',')
        .map(str::parse)
        .collect::<Result<_, _>>()?;
    let model: Model = match find(model) {
        Ok(m) => m,
        Err(_) => Model::formula(model, None)?,
    };
    let (lo, hi) = (model.domain.min.x, model.domain.max.x);
    let xyz: Vec<f64> = (0..points).flat_map(|k| point(k, lo, hi)).collect();
    let centres: Vec<f64> = (0..boxes).flat_map(|k| point(k, lo, hi)).collect();
    let blo: Vec<f64> = centres.iter().map(|c| c - HALF_SIDE).collect();
    let bhi: Vec<f64> = centres.iter().map(|c| c + HALF_SIDE).collect();
    let never = AtomicBool::new(false);
    // In the order of the Python side: every call of one batch, then the next batch.
    for _ in 0..reps {
        let t = Instant::now();
        let mut out = vec![0.0; points];
        batch::eval_points(&model.shape, &xyz, &mut out, &never);
        println!("points {}", t.elapsed().as_secs_f64());
        std::hint::black_box(&out);
    }
    for &k in &kinds {
        for _ in 0..reps {
            let t = Instant::now();
            let mut out = vec![0.0; 2 * boxes];
            batch::eval_boxes_kind(k, &model.shape, &blo, &bhi, &mut out, &never);
            println!("boxes {k} {}", t.elapsed().as_secs_f64());
            std::hint::black_box(&out);
        }
    }
    Ok(())
}
