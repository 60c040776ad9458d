//! A sphere seen head-on: hits inside the disc, at the right distance.
mod common;

use model_ir::arith_core::Real;
use tracer_gpu::{Bundle, Frame, GpuArith, Status, Tape, Tracer};

fn sphere() -> Tape {
    Tape::record(|x, y, z| (x.sqr() + y.sqr() + z.sqr()).rsub(1.0))
}

#[test]
fn sphere_head_on() {
    let Some(gpu) = common::gpu() else { return };
    let n = 32u32;
    let mut rays = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let u = (i as f64 + 0.5) / n as f64 * 2.0 - 1.0;
            let v = 1.0 - (j as f64 + 0.5) / n as f64 * 2.0;
            let d = [u * 0.5, v * 0.5, -1.0];
            let l = (d[0] * d[0] + d[1] * d[1] + 1.0f64).sqrt();
            rays.push(Bundle {
                origin: [0.0, 0.0, 3.0],
                origin_rad: [0.0; 3],
                dir: [d[0] / l, d[1] / l, d[2] / l],
                dir_rad: [0.0; 3],
                s0: 0.5,
                s1: 6.0,
            });
        }
    }
    let frame = Frame {
        width: n,
        height: n,
        rays: rays.clone(),
        eps_abs: 1e-4,
        eps_rel: 0.0,
        normal_h: 1e-4,
        pruning: true,
        cells: None,
    };
    for arith in GpuArith::ALL {
        let t = Tracer::new(gpu, &sphere(), arith).unwrap();
        let out = t.render(&frame).unwrap();
        for (k, r) in rays.iter().enumerate() {
            // Distance from the centre to the ray's line.
            let d = r.dir;
            let o = [0.0, 0.0, 3.0];
            let tc = -(o[2] * d[2]);
            let p = [o[0] + tc * d[0], o[1] + tc * d[1], o[2] + tc * d[2]];
            let dist = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            let st = out.status[k];
            if dist < 0.99 {
                assert_eq!(st, Status::Hit, "{arith:?} pixel {k} dist {dist}");
                let t_true = tc - (1.0 - dist * dist).sqrt();
                assert!(
                    (out.depth[k] as f64 - t_true).abs() < 2e-4,
                    "{arith:?} {k}: {} vs {t_true}",
                    out.depth[k]
                );
            } else if dist > 1.01 {
                assert_eq!(st, Status::Miss, "{arith:?} pixel {k} dist {dist}");
            }
        }
        eprintln!(
            "{arith:?}: {} evals",
            out.evals.iter().map(|&e| e as u64).sum::<u64>()
        );
    }
}
