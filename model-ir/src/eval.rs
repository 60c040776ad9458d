//! The interpreter: a tape's instructions run in order over any [`Real`], each result
//! in the register of its own index. Points (`f64`) take a lean path of plain
//! registers; every other type runs the generic loop, which moves a value out of its
//! register at its last read ([`Instr::last`]) instead of cloning it, and reuses one
//! register file per type and thread.

use crate::instr::{Instr, Op};
use arith_core::branch::Step;
use arith_core::{rfunc, Real};
use std::any::Any;
use std::cell::RefCell;

thread_local! {
    /// One register file per value type and thread, reused across evaluations.
    static REGISTERS: RefCell<Vec<Box<dyn Any>>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with an empty register file for `R`, reusing this thread's buffer when it
/// is free (a nested or late evaluation just allocates a fresh one).
pub(crate) fn with_registers<R: 'static, T>(f: impl FnOnce(&mut Vec<Option<R>>) -> T) -> T {
    let mut f = Some(f);
    let pooled = REGISTERS.try_with(|pool| {
        let Ok(mut pool) = pool.try_borrow_mut() else {
            return None;
        };
        let k = match pool.iter().position(|b| b.is::<Vec<Option<R>>>()) {
            Some(k) => k,
            None => {
                pool.push(Box::new(Vec::<Option<R>>::new()));
                pool.len() - 1
            }
        };
        let regs = pool[k].downcast_mut::<Vec<Option<R>>>()?;
        let out = (f.take()?)(regs);
        regs.clear();
        Some(out)
    });
    match (pooled, f) {
        (Ok(Some(out)), _) => out,
        (_, Some(f)) => f(&mut Vec::new()),
        // `f` ran but its result was lost: impossible, `out` is always `Some` then.
        (_, None) => unreachable!("register pool returned no result after running"),
    }
}

/// Reads operand `k` of `i`: moved out on its last read, cloned otherwise.
#[inline(always)]
fn read<R: Clone>(regs: &mut [Option<R>], i: &Instr, k: u8) -> R {
    let r = i.reg(k as usize) as usize;
    let slot = &mut regs[r];
    let v = if i.last & (1 << k) != 0 {
        slot.take()
    } else {
        slot.clone()
    };
    // The compiler only emits operands defined earlier and read before their last use.
    v.expect("tape invariant: operand register holds a value")
}

/// Evaluates `ins` at `(x, y, z)` in the arithmetic `R`.
pub(crate) fn eval<R: Real>(ins: &[Instr], x: R, y: R, z: R) -> R {
    // Points take a leaner path: plain `f64` registers on the stack. The type test
    // is resolved at compile time; `R::constant` is the identity on `f64`.
    let point = |v: &R| (v as &dyn Any).downcast_ref::<f64>().copied();
    if let (Some(px), Some(py), Some(pz)) = (point(&x), point(&y), point(&z)) {
        return R::constant(eval_f64(ins, px, py, pz));
    }
    with_registers(|regs: &mut Vec<Option<R>>| run(ins, regs, x, y, z, |_, _| {}))
}

/// Point evaluation with the same `Real` operations as the generic path.
fn eval_f64(ins: &[Instr], x: f64, y: f64, z: f64) -> f64 {
    const STACK: usize = 64;
    if ins.len() <= STACK {
        let mut regs = [0.0; STACK];
        run_f64(ins, &mut regs, x, y, z)
    } else {
        run_f64(ins, &mut vec![0.0; ins.len()], x, y, z)
    }
}

/// The point interpreter: plain `f64` registers, no moves.
fn run_f64(ins: &[Instr], regs: &mut [f64], x: f64, y: f64, z: f64) -> f64 {
    for (k, i) in ins.iter().enumerate() {
        // Unused operand fields are 0: reading register 0 then is harmless.
        let a = regs[i.a as usize];
        let b = regs[i.b as usize];
        let e = regs[i.e as usize];
        regs[k] = match i.op {
            Op::X => x,
            Op::Y => y,
            Op::Z => z,
            Op::Const => i.c,
            Op::Neg => -a,
            Op::Sqr => Real::sqr(&a),
            Op::Powi => Real::powi(&a, i.n),
            Op::Sqrt => Real::sqrt(&a),
            Op::Exp => Real::exp(&a),
            Op::Ln => Real::ln(&a),
            Op::Sin => Real::sin(&a),
            Op::Cos => Real::cos(&a),
            Op::Abs => Real::abs(&a),
            Op::Recip => Real::recip(&a),
            Op::AddC => a + i.c,
            Op::SubC => a - i.c,
            Op::RSubC => Real::rsub(a, i.c),
            Op::MulC => a * i.c,
            Op::DivC => a / i.c,
            Op::RDivC => Real::rdiv(a, i.c),
            Op::Add => a + b,
            Op::Sub => a - b,
            Op::Mul => a * b,
            Op::Div => a / b,
            Op::Hypot => Real::hypot(&a, &b),
            Op::Min => Real::min(&a, &b),
            Op::Max => Real::max(&a, &b),
            Op::Intersect => rfunc::intersect(a, b),
            Op::Union => rfunc::union(a, b),
            Op::Subtract => rfunc::subtract(a, b),
            Op::BlendUnion => rfunc::blend_union(a, b),
            Op::BlendIntersect => rfunc::blend_intersect(a, b),
            Op::Gt0 => Real::step(&a, Step::Pos),
            Op::Ge0 => Real::step(&a, Step::NonNeg),
            Op::Select => Real::select(&a, b, e),
        };
    }
    regs[ins.len() - 1]
}

/// One instruction on operand values `a`, `b`, `e` (those it does not read are ignored),
/// with the operations of [`run`]: the batch kernels' lane-by-lane path.
#[inline]
pub(crate) fn apply<R: Real>(i: &Instr, a: R, b: R, e: R) -> R {
    match i.op {
        Op::X | Op::Y | Op::Z => unreachable!("inputs are not operations"),
        Op::Const => R::constant(i.c),
        Op::Neg => -a,
        Op::Sqr => a.sqr(),
        Op::Powi => a.powi(i.n),
        Op::Sqrt => a.sqrt(),
        Op::Exp => a.exp(),
        Op::Ln => a.ln(),
        Op::Sin => a.sin(),
        Op::Cos => a.cos(),
        Op::Abs => a.abs(),
        Op::Recip => a.recip(),
        Op::AddC => a + i.c,
        Op::SubC => a - i.c,
        Op::RSubC => a.rsub(i.c),
        Op::MulC => a * i.c,
        Op::DivC => a / i.c,
        Op::RDivC => a.rdiv(i.c),
        Op::Add => a + b,
        Op::Sub => a - b,
        Op::Mul => a * b,
        Op::Div => a / b,
        Op::Hypot => a.hypot(&b),
        Op::Min => a.min(&b),
        Op::Max => a.max(&b),
        Op::Intersect => rfunc::intersect(a, b),
        Op::Union => rfunc::union(a, b),
        Op::Subtract => rfunc::subtract(a, b),
        Op::BlendUnion => rfunc::blend_union(a, b),
        Op::BlendIntersect => rfunc::blend_intersect(a, b),
        Op::Gt0 => a.step(Step::Pos),
        Op::Ge0 => a.step(Step::NonNeg),
        Op::Select => a.select(b, e),
    }
}

/// The generic interpreter; `seen(k, v)` is told each register's value as it is
/// computed (a no-op for plain evaluation, compiled away).
pub(crate) fn run<R: Real>(
    ins: &[Instr],
    regs: &mut Vec<Option<R>>,
    x: R,
    y: R,
    z: R,
    mut seen: impl FnMut(usize, &R),
) -> R {
    regs.clear();
    regs.reserve(ins.len());
    for (k, i) in ins.iter().enumerate() {
        let v = match i.op {
            Op::X => x.clone(),
            Op::Y => y.clone(),
            Op::Z => z.clone(),
            Op::Const => R::constant(i.c),
            Op::Neg => -read(regs, i, 0),
            Op::Sqr => read(regs, i, 0).sqr(),
            Op::Powi => read(regs, i, 0).powi(i.n),
            Op::Sqrt => read(regs, i, 0).sqrt(),
            Op::Exp => read(regs, i, 0).exp(),
            Op::Ln => read(regs, i, 0).ln(),
            Op::Sin => read(regs, i, 0).sin(),
            Op::Cos => read(regs, i, 0).cos(),
            Op::Abs => read(regs, i, 0).abs(),
            Op::Recip => read(regs, i, 0).recip(),
            Op::AddC => read(regs, i, 0) + i.c,
            Op::SubC => read(regs, i, 0) - i.c,
            Op::RSubC => read(regs, i, 0).rsub(i.c),
            Op::MulC => read(regs, i, 0) * i.c,
            Op::DivC => read(regs, i, 0) / i.c,
            Op::RDivC => read(regs, i, 0).rdiv(i.c),
            Op::Add => read(regs, i, 0) + read(regs, i, 1),
            Op::Sub => read(regs, i, 0) - read(regs, i, 1),
            Op::Mul => read(regs, i, 0) * read(regs, i, 1),
            Op::Div => read(regs, i, 0) / read(regs, i, 1),
            Op::Hypot => read(regs, i, 0).hypot(&read(regs, i, 1)),
            Op::Min => read(regs, i, 0).min(&read(regs, i, 1)),
            Op::Max => read(regs, i, 0).max(&read(regs, i, 1)),
            Op::Intersect => rfunc::intersect(read(regs, i, 0), read(regs, i, 1)),
            Op::Union => rfunc::union(read(regs, i, 0), read(regs, i, 1)),
            Op::Subtract => rfunc::subtract(read(regs, i, 0), read(regs, i, 1)),
            Op::BlendUnion => rfunc::blend_union(read(regs, i, 0), read(regs, i, 1)),
            Op::BlendIntersect => rfunc::blend_intersect(read(regs, i, 0), read(regs, i, 1)),
            Op::Gt0 => read(regs, i, 0).step(Step::Pos),
            Op::Ge0 => read(regs, i, 0).step(Step::NonNeg),
            Op::Select => {
                let c = read(regs, i, 0);
                c.select(read(regs, i, 1), read(regs, i, 2))
            }
        };
        seen(k, &v);
        regs.push(Some(v));
    }
    let out = regs.pop().flatten();
    out.expect("tape invariant: a tape has at least one instruction")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Builder, Tape, Val};

    /// A tape with every instruction, each reading earlier values.
    fn every_op() -> Tape {
        let mut b = Builder::new();
        let r = |b: &mut Builder, op: Op, a: u32, c: u32| b.emit(Instr::new(op, a, c, 3, 0.7));
        let (x, y, z) = (
            r(&mut b, Op::X, 0, 0),
            r(&mut b, Op::Y, 0, 0),
            r(&mut b, Op::Z, 0, 0),
        );
        let mut acc = Vec::new();
        for op in Op::ALL {
            let v = match op.arity() {
                0 => continue,
                1 => r(&mut b, op, x, 0),
                2 => r(&mut b, op, y, z),
                _ => {
                    let c = r(&mut b, Op::Gt0, x, 0);
                    let mut i = Instr::new(Op::Select, c, y, 0, 0.0);
                    i.e = z;
                    b.emit(i)
                }
            };
            acc.push(v);
        }
        let c = b.emit(Instr::new(Op::Const, 0, 0, 0, 0.25));
        let sum = acc
            .into_iter()
            .fold(c, |s, v| b.emit(Instr::new(Op::Add, s, v, 0, 0.0)));
        b.finish(Val::R(sum))
    }

    /// The `f64` fast path and the generic interpreter agree bit for bit on every op.
    #[test]
    fn point_path_matches_generic_path() {
        let t = every_op();
        let ops: std::collections::HashSet<Op> = t.instructions().iter().map(|i| i.op).collect();
        assert_eq!(ops.len(), Op::ALL.len(), "every op is exercised:\n{t}");
        for &(x, y, z) in &[
            (0.3, -0.7, 1.1),
            (-1.9, 0.25, 0.4),
            (2.0, 2.0, -1.0),
            (0.0, 0.0, 0.0),
        ] {
            let fast = t.eval(x, y, z);
            let generic = with_registers(|regs: &mut Vec<Option<f64>>| {
                run(t.instructions(), regs, x, y, z, |_, _| {})
            });
            assert!(
                fast.to_bits() == generic.to_bits() || (fast.is_nan() && generic.is_nan()),
                "{fast} vs {generic} at ({x}, {y}, {z})"
            );
        }
    }
}
