//! The JIT and the interpreter agree bit for bit: on fidget's bear (the tape of the
//! `tape` bench), on specialisations of it, and on a tape with every instruction, over
//! many random boxes and points (small, large, degenerate, with zero and infinite bounds,
//! near overflow and underflow).

#![allow(clippy::needless_range_loop)] // lanes of three parallel arrays

use arith_core::Real;
use arith_ia::Interval;
use model_ir::{Builder, Instr, Op, Tape, Val};
use tape_jit::{IntervalJit, Lanes, PointJit};

fn bear() -> Tape {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../peers/fidget/models/bear.vm"
    );
    let text = std::fs::read_to_string(path).expect("the bear model");
    tracer::models::vm::parse(&text).expect("the bear as a tape")
}

/// xorshift64.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// A coordinate: mostly in the model's box, sometimes special.
    fn coord(&mut self) -> f64 {
        match self.next() % 40 {
            0 => 0.0,
            1 => -0.0,
            2 => 1e-310,
            3 => -1e-200,
            4 => 1e200,
            5 => -1e300,
            6 => f64::MAX,
            7 => 0.5,
            _ => self.unit() * 2.4 - 1.2,
        }
    }
    /// An interval: widths from 0 (a point) to the whole box; a few unbounded.
    fn interval(&mut self) -> Interval {
        match self.next() % 60 {
            0 => Interval::ENTIRE,
            1 => Interval::new(0.0, f64::INFINITY),
            2 => Interval::new(-0.0, 0.0),
            3 => Interval::new(0.0, 0.0),
            4 => Interval::new(-0.0, 0.25),
            5 => Interval::new(-0.5, 0.0),
            _ => {
                let a = self.coord();
                let w = match self.next() % 5 {
                    0 => 0.0,
                    1 => self.unit() * 1e-9,
                    2 => self.unit() * 1e-3,
                    3 => self.unit() * 0.1,
                    _ => self.unit() * 2.0,
                };
                let b = a + w;
                if b.is_finite() {
                    Interval::new(a, b)
                } else {
                    Interval::point(a)
                }
            }
        }
    }
}

fn same_point(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn same_interval(a: Interval, b: Interval) -> bool {
    a.lo.to_bits() == b.lo.to_bits() && a.hi.to_bits() == b.hi.to_bits()
}

/// Boxes and points over `lanes` lanes each, compared lane by lane with `Tape::eval` and
/// `Tape::eval_batch`; returns how many interval lanes the interpreter redid (left the
/// common path).
fn check(t: &Tape, seed: u64, lanes: usize, rounds: usize) -> u64 {
    let before = tape_jit::lanes_redone();
    let ij = IntervalJit::new(t).expect("compiles for intervals");
    let pj = PointJit::new(t).expect("compiles for points");
    let mut rng = Rng(seed);
    let mut out = Lanes::default();
    let mut pout = Vec::new();
    let mut batch = Vec::new();
    let mut pbatch = Vec::new();
    for _ in 0..rounds {
        let v: [Vec<Interval>; 3] =
            core::array::from_fn(|_| (0..lanes).map(|_| rng.interval()).collect());
        let l = v.each_ref().map(|v| Lanes::from_intervals(v));
        ij.eval(&l[0], &l[1], &l[2], &mut out);
        t.eval_batch(&v[0], &v[1], &v[2], &mut batch);
        for k in 0..lanes {
            let one = t.eval(v[0][k], v[1][k], v[2][k]);
            let jit = out.get(k);
            assert!(
                same_interval(jit, one) && same_interval(batch[k], one),
                "interval lane {k}: jit {jit:?}, eval {one:?}, batch {:?} at {:?}",
                batch[k],
                [v[0][k], v[1][k], v[2][k]]
            );
        }
        let p: [Vec<f64>; 3] = core::array::from_fn(|_| (0..lanes).map(|_| rng.coord()).collect());
        pj.eval(&p[0], &p[1], &p[2], &mut pout);
        t.eval_batch(&p[0], &p[1], &p[2], &mut pbatch);
        for k in 0..lanes {
            let one = t.eval(p[0][k], p[1][k], p[2][k]);
            assert!(
                same_point(pout[k], one) && same_point(pbatch[k], one),
                "point lane {k}: jit {:e}, eval {one:e}, batch {:e} at {:?}",
                pout[k],
                pbatch[k],
                [p[0][k], p[1][k], p[2][k]]
            );
        }
    }
    tape_jit::lanes_redone() - before
}

#[test]
fn bear_agrees_bit_for_bit() {
    let t = bear();
    let (lanes, rounds) = (64, 300);
    let redone = check(&t, 0x9E37_79B9_7F4A_7C15, lanes, rounds);
    // Random boxes leave the common path often (points, infinite and tiny bounds), but
    // not always: both paths are compared.
    let n = (lanes * rounds) as u64;
    eprintln!("random boxes: {redone} of {n} lanes redone by the interpreter");
    assert!(redone > 0 && redone < n / 2, "{redone} of {n}");
}

/// Ray segments as the renderer and the `tape` bench evaluate them: `x = o + d t`.
#[test]
fn bear_agrees_on_ray_segments() {
    let t = bear();
    let ij = IntervalJit::new(&t).unwrap();
    let mut rng = Rng(77);
    let n = 2000;
    let mut v: [Vec<Interval>; 3] = Default::default();
    for _ in 0..n {
        let a = rng.unit() * std::f64::consts::TAU;
        let o = [2.0 * a.cos(), 0.3 * a.sin(), 2.0 * a.sin()];
        let len = (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt();
        let t0 = rng.unit() * 3.0;
        let t1 = t0 + rng.unit() * 0.05;
        let ti = Interval::new(t0, t1);
        for k in 0..3 {
            v[k].push(ti * (-o[k] / len) + o[k]);
        }
    }
    let l = v.each_ref().map(|v| Lanes::from_intervals(v));
    let mut out = Lanes::default();
    let before = tape_jit::lanes_redone();
    ij.eval(&l[0], &l[1], &l[2], &mut out);
    let redone = tape_jit::lanes_redone() - before;
    for k in 0..n {
        let one = t.eval(v[0][k], v[1][k], v[2][k]);
        assert!(same_interval(out.get(k), one), "lane {k}");
    }
    // The common path is the one mostly taken: the comparison above is of compiled code.
    // (About 3% of these segments leave it: there the bear's `c / a` of a range holding
    // 0 is the whole line, and unbounded ranges leave it (`report paths`). The `tape`
    // bench's 64 segments all stay on it.)
    eprintln!("ray segments: {redone} of {n} lanes redone by the interpreter");
    assert!(
        redone * 10 <= n as u64,
        "{redone} of {n} lanes left the common path"
    );
}

/// Specialised bears (what a renderer would compile per region).
#[test]
fn specialised_bears_agree() {
    let t = bear();
    let mut rng = Rng(5);
    let mut done = 0;
    for _ in 0..40 {
        let c = [0, 1, 2].map(|_| rng.unit() * 2.0 - 1.0);
        let w = 0.05 + rng.unit() * 0.3;
        let region = c.map(|c| Interval::new(c - w, c + w));
        if let Some(s) = t.specialise(&[region]) {
            let _ = check(&s, rng.next(), 16, 10);
            done += 1;
        }
    }
    assert!(done > 10, "only {done} regions specialised");
}

/// A tape with every instruction (helpers included), each reading earlier values.
fn every_op() -> Tape {
    let mut b = Builder::new();
    let r = |b: &mut Builder, op: Op, a: u32, c: u32, k: f64| b.emit(Instr::new(op, a, c, 3, k));
    let (x, y, z) = (
        r(&mut b, Op::X, 0, 0, 0.0),
        r(&mut b, Op::Y, 0, 0, 0.0),
        r(&mut b, Op::Z, 0, 0, 0.0),
    );
    let mut acc = Vec::new();
    for op in Op::ALL {
        for k in [0.7, -1.3] {
            let v = match op.arity() {
                0 => continue,
                1 => r(&mut b, op, x, 0, k),
                2 => r(&mut b, op, y, z, k),
                _ => {
                    let c = r(&mut b, Op::Gt0, x, 0, 0.0);
                    let mut i = Instr::new(Op::Select, c, y, 0, 0.0);
                    i.e = z;
                    b.emit(i)
                }
            };
            acc.push(v);
        }
    }
    // Products and squares of mixed operands, powers 2.
    let p = r(&mut b, Op::Mul, x, y, 0.0);
    let q = r(&mut b, Op::Mul, p, z, 0.0);
    let s = r(&mut b, Op::Sqr, q, 0, 0.0);
    let mut i = Instr::new(Op::Powi, p, 0, 2, 0.0);
    i.n = 2;
    let pw = b.emit(i);
    acc.extend([p, q, s, pw]);
    let c = b.emit(Instr::new(Op::Const, 0, 0, 0, 0.25));
    let sum = acc
        .into_iter()
        .fold(c, |s, v| b.emit(Instr::new(Op::Add, s, v, 0, 0.0)));
    b.finish(Val::R(sum))
}

#[test]
fn every_op_agrees() {
    let t = every_op();
    let _ = check(&t, 42, 32, 200);
    let ij = IntervalJit::new(&t).unwrap();
    assert!(ij.coverage.helper > 0 && ij.coverage.inline > 0);
}

/// Every unary and binary instruction alone (so one lane's path does not hide another's).
#[test]
fn each_op_alone_agrees() {
    for op in Op::ALL {
        for k in [0.7, -1.3, 0.0, 1e-300, f64::INFINITY] {
            let mut b = Builder::new();
            let x = b.emit(Instr::new(Op::X, 0, 0, 0, 0.0));
            let y = b.emit(Instr::new(Op::Y, 0, 0, 0, 0.0));
            let z = b.emit(Instr::new(Op::Z, 0, 0, 0, 0.0));
            let n = if k < 0.0 {
                3
            } else if k == 0.0 {
                -2
            } else {
                2
            };
            let mut i = match op.arity() {
                0 => Instr::new(op, 0, 0, n, k),
                1 => Instr::new(op, x, 0, n, k),
                _ => Instr::new(op, x, y, n, k),
            };
            if op == Op::Select {
                i.e = z;
            }
            let v = b.emit(i);
            let t = b.finish(Val::R(v));
            let _ = check(&t, 1 + op as u64, 64, 30);
        }
    }
}

/// `sqrt` of signed zeros and NaN in points, and `min`/`max` of signed zeros.
#[test]
fn points_signed_zeros() {
    let t = Tape::record(|x: model_ir::Recorder, y, z| {
        x.sqrt() + y.min(&z) * 3.0 + y.max(&z) + (x - y).sqrt()
    });
    let pj = PointJit::new(&t).unwrap();
    let zs = [
        0.0,
        -0.0,
        f64::NAN,
        -1.0,
        1.0,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    let mut out = Vec::new();
    for &a in &zs {
        for &b in &zs {
            for &c in &zs {
                pj.eval(&[a], &[b], &[c], &mut out);
                let one = t.eval(a, b, c);
                assert!(same_point(out[0], one), "{a} {b} {c}: {} vs {one}", out[0]);
            }
        }
    }
    let _ = Real::sqrt(&0.0_f64);
}
