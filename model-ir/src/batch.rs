//! Batched evaluation: one tape over many inputs per call, instruction by instruction
//! over all of them (structure of arrays: each register holds one value per lane). The
//! dispatch on the instruction, the operand lookups and the register traffic are paid
//! once per instruction and batch, not once per evaluation, and each instruction's loop
//! over the lanes is a tight loop of one operation. Every lane's result is, bit for bit,
//! what [`Tape::eval`] gives on that lane's inputs: the same operations on the same
//! values, and no lane ever reads another's.
//!
//! Lanes may themselves be SIMD packs ([`arith_core::pack::Pack`]: four ray forms in
//! one value), so a batch of `n` packs evaluates `4 n` ray segments.

use crate::instr::{Instr, Op};
use crate::tape::Tape;
use arith_core::branch::Step;
use arith_core::{rfunc, Real};
use std::any::Any;
use std::cell::RefCell;

thread_local! {
    /// Spare register vectors per value type and thread, reused across batches.
    static SPARE: RefCell<Vec<Box<dyn Any>>> = const { RefCell::new(Vec::new()) };
}

/// The register file of one batch: one vector of lanes per register, taken at an
/// operand's last read (so its allocation becomes the result's) and otherwise copied.
struct Regs<R> {
    regs: Vec<Vec<R>>,
    spare: Vec<Vec<R>>,
}

impl<R: Clone> Regs<R> {
    /// Operand `k` of `i`, owned: moved out at its last read, else copied.
    fn owned(&mut self, i: &Instr, k: usize) -> Vec<R> {
        let r = i.reg(k) as usize;
        if i.last & (1 << k) != 0 {
            std::mem::take(&mut self.regs[r])
        } else {
            let mut v = self.spare.pop().unwrap_or_default();
            v.clone_from(&self.regs[r]);
            v
        }
    }

    /// Operand `k` of `i`, borrowed.
    fn get(&self, i: &Instr, k: usize) -> &[R] {
        &self.regs[i.reg(k) as usize]
    }

    /// Gives back the storage of operand `k` of `i` if this was its last read.
    fn release(&mut self, i: &Instr, k: usize) {
        if i.last & (1 << k) != 0 {
            let mut v = std::mem::take(&mut self.regs[i.reg(k) as usize]);
            v.clear();
            self.spare.push(v);
        }
    }

    fn fresh(&mut self) -> Vec<R> {
        self.spare.pop().unwrap_or_default()
    }
}

/// `f(a[l])` for every lane, into a fresh vector (`a`'s storage goes back to the
/// spares).
#[inline(always)]
fn map<R: Real>(regs: &mut Regs<R>, mut a: Vec<R>, f: impl Fn(R) -> R) -> Vec<R> {
    let mut o = regs.fresh();
    o.extend(a.drain(..).map(f));
    regs.spare.push(a);
    o
}

/// `f(a[l], b[l])` for every lane, into a fresh vector.
#[inline(always)]
fn zip<R: Real>(
    regs: &mut Regs<R>,
    mut a: Vec<R>,
    k: usize,
    i: &Instr,
    f: impl Fn(R, R) -> R,
) -> Vec<R> {
    let mut o = regs.fresh();
    o.extend(
        a.drain(..)
            .zip(regs.get(i, k))
            .map(|(x, y)| f(x, y.clone())),
    );
    regs.spare.push(a);
    o
}

impl Tape {
    /// Evaluates the tape on every lane `l` of the inputs, `(x[l], y[l], z[l])`, into
    /// `out` (cleared first): `out[l]` is bit for bit `self.eval(x[l], y[l], z[l])`.
    /// The three slices have the same length.
    ///
    /// ```
    /// use arith_core::{Range, Real};
    /// use arith_ia::Interval;
    /// use model_ir::Tape;
    /// let t = Tape::record(|x, y, z| (x.sqr() + y.sqr() + z.sqr()).rsub(1.0));
    /// let xs: Vec<Interval> = (0..8).map(|k| Interval::from_interval(k as f64 / 8.0, 1.0)).collect();
    /// let zero = vec![Interval::constant(0.0); 8];
    /// let mut out = Vec::new();
    /// t.eval_batch(&xs, &zero, &zero, &mut out);
    /// for (o, x) in out.iter().zip(&xs) {
    ///     assert_eq!(o.bounds(), t.eval(*x, zero[0], zero[0]).bounds());
    /// }
    /// ```
    pub fn eval_batch<R: Real>(&self, x: &[R], y: &[R], z: &[R], out: &mut Vec<R>) {
        let n = x.len();
        assert!(
            y.len() == n && z.len() == n,
            "eval_batch: inputs of unequal lengths"
        );
        out.clear();
        if n == 0 {
            return;
        }
        let ins = self.instructions();
        let spare = take_spare::<R>();
        let mut regs = Regs {
            regs: Vec::with_capacity(ins.len()),
            spare,
        };
        for i in ins {
            let v = step(&mut regs, i, [x, y, z]);
            regs.regs.push(v);
        }
        let last = regs.regs.pop().unwrap_or_default();
        out.extend(last);
        let Regs { regs, mut spare } = regs;
        for mut v in regs {
            if v.capacity() > 0 {
                v.clear();
                spare.push(v);
            }
        }
        give_spare(spare);
    }
}

/// The lanes of instruction `i`.
fn step<R: Real>(regs: &mut Regs<R>, i: &Instr, [x, y, z]: [&[R]; 3]) -> Vec<R> {
    let input = |regs: &mut Regs<R>, v: &[R]| {
        let mut o = regs.fresh();
        o.extend_from_slice(v);
        o
    };
    let c = i.c;
    macro_rules! un {
        ($f:expr) => {{
            let a = regs.owned(i, 0);
            map(regs, a, $f)
        }};
    }
    macro_rules! bin {
        ($f:expr) => {{
            let a = regs.owned(i, 0);
            let out = zip(regs, a, 1, i, $f);
            regs.release(i, 1);
            out
        }};
    }
    match i.op {
        Op::X => input(regs, x),
        Op::Y => input(regs, y),
        Op::Z => input(regs, z),
        Op::Const => {
            let mut o = regs.fresh();
            o.resize(x.len(), R::constant(c));
            o
        }
        Op::Neg => un!(|a: R| -a),
        Op::Sqr => un!(|a: R| a.sqr()),
        Op::Powi => un!(|a: R| a.powi(i.n)),
        Op::Sqrt => un!(|a: R| a.sqrt()),
        Op::Recip => un!(|a: R| a.recip()),
        Op::Exp => un!(|a: R| a.exp()),
        Op::Ln => un!(|a: R| a.ln()),
        Op::Sin => un!(|a: R| a.sin()),
        Op::Cos => un!(|a: R| a.cos()),
        Op::Abs => un!(|a: R| a.abs()),
        Op::AddC => un!(|a: R| a + c),
        Op::SubC => un!(|a: R| a - c),
        Op::RSubC => un!(|a: R| a.rsub(c)),
        Op::MulC => un!(|a: R| a * c),
        Op::DivC => un!(|a: R| a / c),
        Op::RDivC => un!(|a: R| a.rdiv(c)),
        Op::Gt0 => un!(|a: R| a.step(Step::Pos)),
        Op::Ge0 => un!(|a: R| a.step(Step::NonNeg)),
        Op::Add => bin!(|a: R, b: R| a + b),
        Op::Sub => bin!(|a: R, b: R| a - b),
        Op::Mul => bin!(|a: R, b: R| a * b),
        Op::Div => bin!(|a: R, b: R| a / b),
        Op::Hypot => bin!(|a: R, b: R| a.hypot(&b)),
        Op::Min => bin!(|a: R, b: R| a.min(&b)),
        Op::Max => bin!(|a: R, b: R| a.max(&b)),
        Op::Intersect => bin!(rfunc::intersect),
        Op::Union => bin!(rfunc::union),
        Op::Subtract => bin!(rfunc::subtract),
        Op::BlendUnion => bin!(rfunc::blend_union),
        Op::BlendIntersect => bin!(rfunc::blend_intersect),
        Op::Select => {
            let cnd = regs.owned(i, 0);
            let (t, e) = (regs.get(i, 1), regs.get(i, 2));
            let mut o = cnd;
            for ((c, t), e) in o.iter_mut().zip(t).zip(e) {
                *c = c.select(t.clone(), e.clone());
            }
            regs.release(i, 1);
            regs.release(i, 2);
            o
        }
    }
}

fn take_spare<R: 'static>() -> Vec<Vec<R>> {
    SPARE
        .try_with(|pool| {
            let mut pool = pool.try_borrow_mut().ok()?;
            let k = pool.iter().position(|b| b.is::<Vec<Vec<R>>>())?;
            let b = pool.swap_remove(k);
            b.downcast::<Vec<Vec<R>>>().ok().map(|b| *b)
        })
        .ok()
        .flatten()
        .unwrap_or_default()
}

fn give_spare<R: 'static>(spare: Vec<Vec<R>>) {
    let _ = SPARE.try_with(|pool| {
        if let Ok(mut pool) = pool.try_borrow_mut() {
            pool.push(Box::new(spare));
        }
    });
}
