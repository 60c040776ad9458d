//! The register walk every batch kernel shares, over values of one or more `f64` parts
//! (a point; an interval's bounds; a dual number's value and partials; a revised affine
//! form's centre, coefficients and error term).
//!
//! The batch is walked in passes of at most [`pass_blocks`] blocks of eight lanes: each
//! pass runs the whole tape over its blocks, so the register file is bounded however
//! large the batch. Within a pass of `ch` blocks each register holds
//! [`PartOps::PARTS`] blocks per block index (slot `s`, block `c` at
//! `PARTS * (s * ch + c)`). The inputs' registers are copied in from the staged batch,
//! a constant's register holds one block index ([`PartOps::constant`]: by default its
//! value, then zeros, as a constant's partials, coefficients and error term are), which
//! is repeated over a scratch slot for an instruction that reads it, and every other
//! instruction is the value type's [`PartOps::instruction`] over operands and a result
//! in distinct slots, as plain slices: the kernels' loops carry no index arithmetic
//! or bounds checks, and the walk reads each instruction's slots from one precomputed
//! entry ([`Slots::places`]).

use super::regfile::Slots;
use crate::instr::{Instr, Op};
use arith_core::lanes::{F64x8, Isa, Kernel};
use core::marker::PhantomData;

/// The most parts a value may have.
pub(crate) const MAX_PARTS: usize = 5;

/// The most blocks of eight lanes per pass over the tape (512 lanes).
pub(crate) const PASS_BLOCKS: usize = 64;

/// Blocks per pass for values of `parts` parts. Each pass pays the walk's cost per
/// instruction again, which outweighs keeping the registers in the level-one cache for
/// points and intervals (on fidget's colonnade and bear, 512 lanes in passes of 64 ran
/// 1.1 to 1.5 times slower than in one pass), but not for values of more parts: dual
/// numbers over 512 lanes ran 1.2 to 1.6 times faster in passes of 128 lanes than in
/// one pass.
pub(crate) fn pass_blocks(parts: usize) -> usize {
    if parts <= 2 {
        PASS_BLOCKS
    } else {
        PASS_BLOCKS / 4
    }
}

/// Scratch slots after a tape's own, for constants repeated over a pass.
pub(crate) const SCRATCH: usize = 3;

/// A value type of several parts in lanes.
pub(crate) trait PartOps {
    /// Blocks per register and block index (at most [`MAX_PARTS`]).
    const PARTS: usize;
    /// The constant `c` in every lane, into the `PARTS` blocks of `block`: by default
    /// `c`, then zeros.
    #[inline(always)]
    fn constant(c: f64, block: &mut [F64x8]) {
        block[0] = F64x8::splat(c);
        block[1..].fill(F64x8::splat(0.0));
    }
    /// One instruction (not an input or a constant) over every block ([`Step`]).
    fn instruction<I: Isa>(s: I, at: Step<'_>);
}

/// Where one instruction runs: the instruction `i`, its result's `PARTS * ch` blocks
/// `out`, operand `k`'s blocks `ops[k]` laid out likewise (block `j`'s parts from
/// `PARTS * j` on; an operand the instruction does not read is some other operand's),
/// over `ch` block indices. The result never shares storage with an operand.
pub(crate) struct Step<'a> {
    pub(crate) i: &'a Instr,
    pub(crate) out: &'a mut [F64x8],
    pub(crate) ops: [&'a [F64x8]; 3],
    pub(crate) ch: usize,
}

impl Step<'_> {
    /// `f(result, [a, b, e])` over every block index, each a block index's `P` parts
    /// (`P` is the kernel's `PARTS`).
    #[inline(always)]
    pub(crate) fn each<const P: usize>(self, mut f: impl FnMut(&mut [F64x8; P], [&[F64x8; P]; 3])) {
        let n = P * self.ch;
        let out = self.out[..n].as_chunks_mut::<P>().0;
        // Written out: `array::map` need not inline into the path's function.
        let [a, b, e] = self.ops;
        let (a, b, e) = (
            a[..n].as_chunks::<P>().0,
            b[..n].as_chunks::<P>().0,
            e[..n].as_chunks::<P>().0,
        );
        for (o, ((x, y), z)) in out.iter_mut().zip(a.iter().zip(b).zip(e)) {
            f(o, [x, y, z]);
        }
    }
}

/// One tape over `chunks` blocks of values of type `P`, in passes ([`pass_blocks`]):
/// `file` holds `P::PARTS` blocks per slot and block index of a pass (the tape's slots,
/// then [`SCRATCH`] more), `inputs` the blocks of `x`, `y`, `z` over the whole batch
/// (input `q`'s block `c` at `PARTS * (q * chunks + c)`), `output` receives the last
/// register's blocks likewise.
pub(crate) struct Parts<'a, P> {
    pub(crate) ins: &'a [Instr],
    pub(crate) slots: &'a Slots,
    pub(crate) file: &'a mut [F64x8],
    pub(crate) inputs: &'a [F64x8],
    pub(crate) output: &'a mut [F64x8],
    pub(crate) chunks: usize,
    /// Where `watch[k]` is some `w` (not `u32::MAX`; `watch` empty: none), register
    /// `k`'s blocks are also copied to `seen`, laid out as an input `w` of `inputs`.
    pub(crate) watch: &'a [u32],
    pub(crate) seen: &'a mut [F64x8],
    pub(crate) kind: PhantomData<P>,
}

impl<P: PartOps> Kernel for Parts<'_, P> {
    type Output = ();

    #[inline(always)]
    fn run<I: Isa>(self, s: I) {
        let Parts {
            ins,
            slots,
            file,
            inputs,
            output,
            chunks,
            watch,
            seen,
            ..
        } = self;
        let parts = P::PARTS;
        let mut start = 0;
        while start < chunks {
            let ch = pass_blocks(parts).min(chunks - start);
            let n = parts * ch;
            pass::<P, I>(
                s,
                ins,
                slots,
                file,
                inputs,
                (start, ch, chunks),
                (watch, seen),
            );
            let r = read(ins, slots, file, parts, ch, ins.len() - 1);
            output[parts * start..parts * start + n].copy_from_slice(&file[r..r + n]);
            start += ch;
        }
    }
}

/// Where register `r`'s blocks of the current pass of `ch` blocks are in `file`: its
/// slot's, or a constant's one block index repeated over the first scratch slot.
fn read(
    ins: &[Instr],
    slots: &Slots,
    file: &mut [F64x8],
    parts: usize,
    ch: usize,
    r: usize,
) -> usize {
    let n = parts * ch;
    let at = n * slots.slot[r] as usize;
    if ins[r].op != Op::Const {
        return at;
    }
    let w = n * slots.count;
    repeat(file, at, parts, w, ch);
    w
}

/// The `parts` blocks at `file[from..]` repeated `ch` times from `file[to..]`.
fn repeat(file: &mut [F64x8], from: usize, parts: usize, to: usize, ch: usize) {
    for j in 0..ch {
        file.copy_within(from..from + parts, to + parts * j);
    }
}

/// One pass of the tape over the `ch` blocks from block `start` of `chunks`.
#[inline(always)]
fn pass<P: PartOps, I: Isa>(
    s: I,
    ins: &[Instr],
    slots: &Slots,
    file: &mut [F64x8],
    inputs: &[F64x8],
    (start, ch, chunks): (usize, usize, usize),
    (watch, seen): (&[u32], &mut [F64x8]),
) {
    let parts = P::PARTS;
    let n = parts * ch;
    for (k, (i, p)) in ins.iter().zip(&slots.places).enumerate() {
        let o = n * p.out as usize;
        match i.op {
            Op::X | Op::Y | Op::Z => {
                let q = match i.op {
                    Op::X => 0,
                    Op::Y => 1,
                    _ => 2,
                };
                let from = parts * (q * chunks + start);
                file[o..o + n].copy_from_slice(&inputs[from..from + n]);
            }
            Op::Const => P::constant(i.c, &mut file[o..o + parts]),
            _ => {
                let [a, b, e] = p.ops;
                let mut ops = [n * a as usize, n * b as usize, n * e as usize];
                if p.consts != 0 {
                    for (q, a) in ops.iter_mut().enumerate() {
                        if p.consts & (1 << q) != 0 {
                            let w = n * (slots.count + q);
                            repeat(file, *a, parts, w, ch);
                            *a = w;
                        }
                    }
                }
                let (left, rest) = file.split_at_mut(o);
                let (out, right) = rest.split_at_mut(n);
                let (left, right) = (&*left, &*right);
                let view = |a: usize| {
                    if a < o {
                        &left[a..a + n]
                    } else {
                        &right[a - o - n..a - o]
                    }
                };
                let ops = [view(ops[0]), view(ops[1]), view(ops[2])];
                P::instruction(s, Step { i, out, ops, ch });
            }
        }
        if let Some(&w) = watch.get(k).filter(|&&w| w != u32::MAX) {
            let from = read(ins, slots, file, parts, ch, k);
            let to = parts * (w as usize * chunks + start);
            seen[to..to + n].copy_from_slice(&file[from..from + n]);
        }
    }
}
