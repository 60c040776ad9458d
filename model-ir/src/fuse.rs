//! R-function fusion: `sqrt(a^2 + b^2)` written out becomes one [`Op::Hypot`]
//! ([`Tape::fuse_hypot`]), and the R-functions written out as `a + b + h`, `a + b - h` and
//! `a - b - h` with `h = hypot(a, b)` (as [`arith_core::rfunc`] computes them, and so
//! as a recording of generic model code holds them) become single instructions
//! ([`Op::Union`], [`Op::Intersect`], [`Op::Subtract`]), and what only the written-out
//! form read is dropped.
//!
//! Over the real numbers the fused instruction is the same function, and the
//! interpreter evaluates it as [`arith_core::rfunc`] does, so every range still
//! encloses it. Evaluators in `f32` (the GPU) need the fused form: there the written-out
//! form loses the result to cancellation wherever one operand is far more negative than
//! the other is large (a union with a distant part of a scene: `-1e4 + 1e4 + 1e-3`
//! keeps none of the `1e-3`), while a fused union can be evaluated as
//! `o + o^2 / (h - m)` (`m` the negative operand, `o` the other), free of cancellation.

use crate::builder::finish;
use crate::instr::{Instr, Op};
use crate::tape::Tape;

impl Tape {
    /// This tape with its written-out R-functions fused (see the module doc).
    ///
    /// ```
    /// use arith_core::{rfunc, Real};
    /// use model_ir::{Op, Tape};
    /// let t = Tape::record(|x, y, z| rfunc::union(x, y) - z);
    /// let f = t.fuse_rfunctions();
    /// assert!(f.instructions().iter().any(|i| i.op == Op::Union));
    /// assert!(!f.instructions().iter().any(|i| i.op == Op::Hypot));
    /// assert_eq!(f.eval(0.3_f64, -0.2, 0.1), t.eval(0.3_f64, -0.2, 0.1));
    /// ```
    pub fn fuse_rfunctions(&self) -> Tape {
        let mut ins: Vec<Instr> = self.instructions().to_vec();
        for k in 0..ins.len() {
            if let Some(f) = fused(&ins, &ins[k]) {
                ins[k] = f;
            }
        }
        let out = (ins.len() - 1) as u32;
        Tape::from_instructions(finish(ins, out))
    }

    /// This tape with each `sqrt(a^2 + b^2)` written out (two squares, their sum, its
    /// root: as `.vm` tapes and formulas spell the R-functions) read as one
    /// [`Op::Hypot`], and what only the written-out form read dropped.
    ///
    /// The value at a point is the same bit for bit: [`arith_core::Real::hypot`] of a
    /// point is those very operations in that order. Ranges enclose the same real
    /// function, and the arithmetics' `hypot` is tighter where both operands reach 0
    /// (its floor is the operands' mignitudes; the dual numbers keep its gradient
    /// within `[-1, 1]` times the operands', where the chain rule through `sqrt` has no
    /// bound). Then [`Tape::fuse_rfunctions`] can see the R-functions.
    ///
    /// ```
    /// use model_ir::{Op, Tape};
    /// use arith_core::Real;
    /// let t = Tape::record(|x, y, z| (x.sqr() + y.sqr()).sqrt() - z);
    /// let f = t.fuse_hypot();
    /// assert!(f.instructions().iter().any(|i| i.op == Op::Hypot));
    /// assert_eq!(f.eval(0.3_f64, -0.2, 0.1).to_bits(), t.eval(0.3_f64, -0.2, 0.1).to_bits());
    /// ```
    pub fn fuse_hypot(&self) -> Tape {
        let mut ins: Vec<Instr> = self.instructions().to_vec();
        let mut any = false;
        for k in 0..ins.len() {
            if let Some(h) = written_hypot(&ins, &ins[k]) {
                ins[k] = h;
                any = true;
            }
        }
        if !any {
            return self.clone();
        }
        let out = (ins.len() - 1) as u32;
        Tape::from_instructions(finish(ins, out))
    }
}

/// The `hypot` that `i` writes out (`sqrt(a^2 + b^2)`), if it does.
fn written_hypot(ins: &[Instr], i: &Instr) -> Option<Instr> {
    if i.op != Op::Sqrt {
        return None;
    }
    let sum = ins[i.a as usize];
    if sum.op != Op::Add {
        return None;
    }
    let (p, q) = (ins[sum.a as usize], ins[sum.b as usize]);
    (p.op == Op::Sqr && q.op == Op::Sqr).then(|| Instr::new(Op::Hypot, p.a, q.a, 0, 0.0))
}

/// The R-function `i` writes out, if it is one.
fn fused(ins: &[Instr], i: &Instr) -> Option<Instr> {
    let (s, h, minus) = match i.op {
        Op::Add => (i.a, i.b, false),
        Op::Sub => (i.a, i.b, true),
        _ => return None,
    };
    let hy = ins[h as usize];
    if hy.op != Op::Hypot {
        return None;
    }
    let sum = ins[s as usize];
    let same = (sum.a, sum.b) == (hy.a, hy.b) || (sum.b, sum.a) == (hy.a, hy.b);
    let op = match (sum.op, minus) {
        (Op::Add, false) if same => Op::Union,
        (Op::Add, true) if same => Op::Intersect,
        (Op::Sub, true) if same => Op::Subtract,
        _ => return None,
    };
    Some(Instr::new(op, sum.a, sum.b, 0, 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::{rfunc, Real};

    /// `(x | y) & z` and `x \ y`, written out, with an unused operation.
    fn written_out() -> Tape {
        Tape::record(|x, y, z| {
            let _dead = x.sin();
            let u = rfunc::union(x, y);
            let i = rfunc::intersect(u, z);
            i.max(&rfunc::subtract(x, y))
        })
    }

    #[test]
    fn fusing_keeps_the_values_and_drops_what_only_the_written_out_form_read() {
        let unfused = written_out();
        let fused = unfused.fuse_rfunctions();
        let count = |op: Op| fused.instructions().iter().filter(|i| i.op == op).count();
        assert_eq!(count(Op::Union), 1);
        assert_eq!(count(Op::Intersect), 1);
        assert_eq!(count(Op::Subtract), 1);
        assert_eq!(count(Op::Hypot) + count(Op::Sin), 0);
        assert_eq!(fused.len(), 3 + 3 + 1);
        for (x, y, z) in [(0.3, -0.7, 2.0), (-40.0, 1e-3, 0.5), (1.0, 1.0, -1.0)] {
            let (a, b) = (unfused.eval(x, y, z), fused.eval(x, y, z));
            assert_eq!(a.to_bits(), b.to_bits(), "{a} vs {b}");
        }
    }

    #[test]
    fn a_written_out_hypot_is_one_instruction_with_the_same_values() {
        // The three R-functions as `.vm` tapes write them: squares, sum, root.
        let t = Tape::record(|x, y, z| {
            let h = |a: &R64, b: &R64| (a.sqr() + b.sqr()).sqrt();
            let u = x + y + h(&x, &y);
            let i = u + z - h(&u, &z);
            i - x - h(&i, &x) + (x.sqr() + y).sqrt()
        });
        let f = t.fuse_hypot();
        let count = |t: &Tape, op: Op| t.instructions().iter().filter(|i| i.op == op).count();
        assert_eq!(count(&f, Op::Hypot), 3);
        // `sqrt(x^2 + y)` is not one.
        assert_eq!(count(&f, Op::Sqrt), 1);
        assert!(f.len() < t.len());
        let fused = f.fuse_rfunctions();
        assert_eq!(count(&fused, Op::Union), 1);
        assert_eq!(count(&fused, Op::Intersect), 1);
        assert_eq!(count(&fused, Op::Subtract), 1);
        for (x, y, z) in [
            (0.3, -0.7, 2.0),
            (-40.0, 1e-3, 0.5),
            (1.0, 1.0, -1.0),
            (0.0, 0.0, 0.0),
        ] {
            let a = t.eval(x, y, z);
            for g in [&f, &fused] {
                assert_eq!(a.to_bits(), g.eval(x, y, z).to_bits(), "at {x} {y} {z}");
            }
        }
    }

    /// The recorder's value type.
    type R64 = crate::record::Recorder;

    #[test]
    fn a_sum_that_is_not_an_r_function_stays() {
        let t = Tape::record(|x, y, z| x + z + x.hypot(&y));
        let f = t.fuse_rfunctions();
        assert_eq!(f.to_string(), t.to_string());
    }
}
