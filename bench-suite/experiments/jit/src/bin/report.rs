//! Facts about the JIT on fidget's bear: the instructions of the tape and how many the
//! JIT compiles inline, compile times (the bear and specialisations of it, by length),
//! and, for the first ray segments that leave the common path, the first register with
//! an infinite or nonzero sub-`2^-960` bound (`report paths` skips the compile times).
//!
//! `cargo run --release --bin report`

use arith_ia::Interval;
use model_ir::{Builder, Op, Tape, Val};
use std::collections::BTreeMap;
use tape_jit::{IntervalJit, Lanes, PointJit};

fn bear() -> Tape {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../peers/fidget/models/bear.vm"
    );
    tracer::models::vm::parse(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The tape computing register `k` of `t`.
fn prefix(t: &Tape, k: usize) -> Tape {
    let mut b = Builder::new();
    let mut map = Vec::new();
    for i in &t.instructions()[..=k] {
        let mut j = *i;
        for op in 0..i.operands().len() {
            let r = i.reg(op) as usize;
            match op {
                0 => j.a = map[r],
                1 => j.b = map[r],
                _ => j.e = map[r],
            }
        }
        j.last = 0;
        map.push(b.emit(j));
    }
    b.finish(Val::R(map[k]))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

#[allow(clippy::needless_range_loop)]
fn main() {
    let t = bear();
    let mut hist: BTreeMap<&str, usize> = BTreeMap::new();
    for i in t.instructions() {
        *hist.entry(i.op.name()).or_default() += 1;
    }
    println!("bear: {} instructions: {hist:?}", t.len());
    let ij = IntervalJit::new(&t).unwrap();
    let pj = PointJit::new(&t).unwrap();
    println!(
        "coverage: intervals {:?}, points {:?}",
        ij.coverage, pj.coverage
    );

    // The `tape` bench's segments: how many leave the common path.
    let segs: Vec<[Interval; 3]> = (0..64)
        .map(|k| {
            let a = k as f64 * 0.37;
            let o = [2.0 * a.cos(), 0.3 * a.sin(), 2.0 * a.sin()];
            let n = (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt();
            let d = [-o[0] / n, -o[1] / n, -o[2] / n];
            let t0 = 1.4 + 0.01 * (k % 7) as f64;
            tracer::search::ray::ray_inputs::<Interval>(o.into(), d.into(), t0, t0 + 0.02)
        })
        .collect();
    let l: [Lanes; 3] = core::array::from_fn(|i| {
        Lanes::from_intervals(&segs.iter().map(|s| s[i]).collect::<Vec<_>>())
    });
    let before = tape_jit::lanes_redone();
    let mut o = Lanes::default();
    ij.eval(&l[0], &l[1], &l[2], &mut o);
    println!(
        "bench segments: {} of 64 lanes redone by the interpreter",
        tape_jit::lanes_redone() - before
    );
    let skip_compile = std::env::args().nth(1).as_deref() == Some("paths");
    // Compile times: the bear and specialisations to boxes of several sizes.
    let times = |t: &Tape| {
        let ia: Vec<f64> = (0..5)
            .map(|_| IntervalJit::new(t).unwrap().compile_time.as_secs_f64() * 1e3)
            .collect();
        let pt: Vec<f64> = (0..5)
            .map(|_| PointJit::new(t).unwrap().compile_time.as_secs_f64() * 1e3)
            .collect();
        (median(ia), median(pt))
    };
    let (ia, pt) = if skip_compile { (0.0, 0.0) } else { times(&t) };
    println!(
        "compile (median of 5): bear {} instr: intervals {ia:.2} ms, points {pt:.2} ms",
        t.len()
    );
    let mut seed = 0x2545_F491_4F6C_DD1Du64;
    let mut unit = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut by_len: BTreeMap<usize, (f64, f64)> = BTreeMap::new();
    for w in [0.4, 0.2, 0.1, 0.05, 0.02] {
        if skip_compile {
            break;
        }
        for _ in 0..6 {
            let c = [unit(), unit(), unit()].map(|u| u * 1.6 - 0.8);
            let region = c.map(|c| Interval::new(c - w, c + w));
            if let Some(s) = t.specialise(&[region]) {
                by_len.entry(s.len()).or_insert_with(|| times(&s));
            }
        }
    }
    for (len, (ia, pt)) in &by_len {
        println!("compile: specialised {len} instr: intervals {ia:.3} ms, points {pt:.3} ms");
    }

    // Which instructions leave the common path on ray segments through the box.
    let n = 2000;
    let mut v: [Vec<Interval>; 3] = Default::default();
    for _ in 0..n {
        let a = unit() * std::f64::consts::TAU;
        let o = [2.0 * a.cos(), 0.3 * a.sin(), 2.0 * a.sin()];
        let len = (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt();
        let t0 = unit() * 3.0;
        let t1 = t0 + unit() * 0.05;
        let ti = Interval::new(t0, t1);
        for k in 0..3 {
            v[k].push(ti * (-o[k] / len) + o[k]);
        }
    }
    let mut culprits: BTreeMap<String, usize> = BTreeMap::new();
    let mut out = Lanes::default();
    let redone_with = |j: &IntervalJit, k: usize, out: &mut Lanes| {
        let one = |v: &Vec<Interval>| Lanes::from_intervals(&v[k..=k]);
        let before = tape_jit::lanes_redone();
        j.eval(&one(&v[0]), &one(&v[1]), &one(&v[2]), out);
        tape_jit::lanes_redone() > before
    };
    let mut lanes_off = 0;
    for k in 0..n {
        if !redone_with(&ij, k, &mut out) {
            continue;
        }
        lanes_off += 1;
        if lanes_off > 6 {
            continue;
        }
        // The first register (in tape order) with a bound off the common path of the
        // arithmetic: infinite, or nonzero and below 2^-960 in magnitude.
        let vals: Vec<Interval> = (0..t.len())
            .map(|r| prefix(&t, r).eval(v[0][k], v[1][k], v[2][k]))
            .collect();
        let off = |b: f64| !b.is_finite() || (b != 0.0 && b.abs() < 1e-289);
        let Some(r) = vals.iter().position(|x| off(x.lo) || off(x.hi)) else {
            *culprits.entry("no extreme register".into()).or_default() += 1;
            continue;
        };
        let i = t.instructions()[r];
        let args: Vec<String> = i
            .operands()
            .iter()
            .map(|&o| format!("{:?}", vals[i.reg(o) as usize]))
            .collect();
        let key = format!(
            "r{r} = {} ({}) = {:?}",
            i.op.name(),
            args.join(", "),
            vals[r]
        );
        *culprits.entry(key).or_default() += 1;
        if i.op == Op::X {
            break;
        }
    }
    println!("ray segments: {lanes_off} of {n} lanes off the common path; first culprits:");
    for (k, c) in culprits {
        println!("  {c} x {k}");
    }
}
