//! The register walk every batch kernel shares, over values of one or more `f64` parts
//! (a point; an interval's bounds; a dual number's value and partials; a revised affine
//! form's centre, coefficients and error term). Each register holds [`PartOps::PARTS`] blocks per block index (slot `s`,
//! block `c` at `PARTS * (s * chunks + c)`), the inputs' registers are copied in, a
//! constant's register holds one block index ([`PartOps::constant`]: by default its
//! value, then zeros, as a constant's partials, coefficients and error term are), and
//! every other instruction is the value type's [`PartOps::instruction`].

use super::regfile::Slots;
use crate::instr::{Instr, Op};
use arith_core::lanes::{F64x8, Isa, Kernel};
use core::marker::PhantomData;

/// The most parts a value may have.
pub(crate) const MAX_PARTS: usize = 5;

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
    /// One instruction (not an input or a constant) over every block ([`Step`]). Each
    /// block's operands are read before its result is written (the result may take the
    /// slot of an operand read for the last time).
    fn instruction<I: Isa>(s: I, at: Step<'_>);
}

/// Where one instruction runs: the instruction `i`, its result's blocks from `o` on in
/// `file`, operand `k`'s block `j` at `ops[k].0 + ops[k].1 * j` (the step is 0 for a
/// constant's one block), over `ch` block indices.
pub(crate) struct Step<'a> {
    pub(crate) i: &'a Instr,
    pub(crate) file: &'a mut [F64x8],
    pub(crate) o: usize,
    pub(crate) ops: [(usize, usize); 3],
    pub(crate) ch: usize,
}

/// One tape over `chunks` blocks of values of type `P`: `file` holds `P::PARTS` blocks
/// per slot and block index, `inputs` the blocks of `x`, `y`, `z` likewise.
pub(crate) struct Parts<'a, P> {
    pub(crate) ins: &'a [Instr],
    pub(crate) slots: &'a Slots,
    pub(crate) file: &'a mut [F64x8],
    pub(crate) inputs: &'a [F64x8],
    pub(crate) chunks: usize,
    /// Where `watch[k]` is some `w` (not `u32::MAX`; `watch` empty: none), register
    /// `k`'s blocks are also copied to `seen`, laid out as a slot `w` of `file`, before
    /// a later register takes its slot.
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
            chunks: ch,
            watch,
            seen,
            ..
        } = self;
        let parts = P::PARTS;
        let slot = &slots.slot;
        for (k, i) in ins.iter().enumerate() {
            let at = |r: u32| parts * slot[r as usize] as usize * ch;
            let o = at(k as u32);
            // A constant's register holds its first block index only.
            let step = |r: u32| parts * usize::from(ins[r as usize].op != Op::Const);
            match i.op {
                Op::X | Op::Y | Op::Z => {
                    let q = match i.op {
                        Op::X => 0,
                        Op::Y => 1,
                        _ => 2,
                    };
                    let src = parts * q * ch;
                    file[o..o + parts * ch].copy_from_slice(&inputs[src..src + parts * ch]);
                }
                Op::Const => P::constant(i.c, &mut file[o..o + parts]),
                _ => {
                    let ops = [
                        (at(i.a), step(i.a)),
                        (at(i.b), step(i.b)),
                        (at(i.e), step(i.e)),
                    ];
                    let file = &mut *file;
                    P::instruction(
                        s,
                        Step {
                            i,
                            file,
                            o,
                            ops,
                            ch,
                        },
                    );
                }
            }
            if let Some(&w) = watch.get(k).filter(|&&w| w != u32::MAX) {
                let step = step(k as u32);
                for j in 0..ch {
                    let at = parts * (w as usize * ch + j);
                    let from = o + step * j;
                    seen[at..at + parts].copy_from_slice(&file[from..from + parts]);
                }
            }
        }
    }
}
