//! One range evaluation of each Appendix A model over a 3-D cell, and one reliable ray
//! (Algorithm 1 through the centre pixel) of each model, in each arithmetic.
//!
//! The cell is a box of 1/16 of the domain side, placed near the domain's centre (the
//! cost of one evaluation hardly depends on where the cell is; AA's cost grows with the
//! number of symbols, which the position does not change).

use arith_core::{Arithmetic, Range};
use criterion::{criterion_group, criterion_main, Criterion};
use model_ir::arith::ArithKind;
use model_ir::camera::Camera;
use model_ir::shape::Shape;
use model_sources::Model;
use model_sources::PaperModel;
use std::hint::black_box;
use std::time::Duration;
use tracer::render::RenderOptions;
use tracer::search::ray::{clip, first_root, RayParams, RayStats, Start};

fn cell_of(m: &Model) -> [(f64, f64); 3] {
    let (lo, hi) = (m.domain.min.to_array(), m.domain.max.to_array());
    core::array::from_fn(|i| {
        let side = (hi[i] - lo[i]) / 16.0;
        let a = lo[i] + (hi[i] - lo[i]) * 0.45;
        (a, a + side)
    })
}

fn eval_cell<A: Arithmetic>(m: &PaperModel, c: &[(f64, f64); 3]) -> (f64, f64) {
    let x = A::Cell::input(0, c[0].0, c[0].1);
    let y = A::Cell::input(1, c[1].0, c[1].1);
    let z = A::Cell::input(2, c[2].0, c[2].1);
    m.eval(x, y, z).bounds()
}

fn range_eval(c: &mut Criterion) {
    for pm in PaperModel::ALL {
        let m = pm.model();
        let cell = cell_of(&m);
        let mut g = c.benchmark_group(format!("cell-eval/{}", m.name));
        for kind in ArithKind::ALL {
            g.bench_function(kind.name(), |b| {
                b.iter(|| model_ir::with_arith!(kind, A => eval_cell::<A>(black_box(&pm), black_box(&cell))))
            });
        }
        g.finish();
    }
}

fn one_ray(c: &mut Criterion) {
    // The paper's resolution, centre pixel: the precision is the renderer's own.
    for pm in PaperModel::ALL {
        let m = pm.model();
        let (w, h) = pm.table1_size();
        let opts = RenderOptions::new(&m, w, h);
        let cam = Camera::new(m.view, w, h);
        let params = RayParams {
            precision: opts.precision(&cam),
            pruning: true,
        };
        let (o, d) = cam.ray(w / 2, h / 2);
        let Some((t0, t1)) = clip(o, d, &m.domain, 0.0) else {
            continue;
        };
        let mut g = c.benchmark_group(format!("ray/{}", m.name));
        for kind in ArithKind::ALL {
            g.bench_function(kind.name(), |b| {
                b.iter(|| {
                    let mut st = RayStats::default();
                    model_ir::with_arith!(kind, A => first_root::<A, PaperModel>(
                        black_box(&pm), o, d, Start::whole(t0, t1), &params, &mut st
                    ))
                })
            });
        }
        g.finish();
    }
}

fn config() -> Criterion {
    // 72 benchmarks; some rays (AA on the hair model) take milliseconds each, so a
    // small sample keeps the file to a couple of minutes on 2 cores.
    Criterion::default()
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_millis(500))
        .sample_size(10)
}

criterion_group! { name = benches; config = config(); targets = range_eval, one_ray }
criterion_main!(benches);
