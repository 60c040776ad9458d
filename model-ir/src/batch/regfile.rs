//! The flat register file of the batch kernels: every register of a tape mapped to a
//! slot, a slot reused once its register is read for the last time ([`Instr::last`]),
//! and one buffer of eight-lane blocks per thread holding every slot's lanes of a pass
//! over the batch (structure of arrays), grown to the largest tape and batch seen and reused, so that a batch
//! allocates nothing once the thread has warmed up.
//!
//! An instruction's result never takes the slot of one of its operands, even one read
//! for the last time: the kernels read operands and write results as distinct slices.
//! A constant's register holds one block (the same value in every lane), repeated over
//! a scratch slot for each reader.

use crate::instr::{Instr, Op};
use arith_core::lanes::F64x8;
use std::cell::RefCell;

/// Each register's slot and the number of slots.
#[derive(Debug, Default)]
pub struct Slots {
    /// The slot of each instruction's register.
    pub(crate) slot: Vec<u32>,
    /// How many slots the tape needs at once.
    pub(crate) count: usize,
    /// Each instruction's slots, read by the kernels' walk.
    pub(crate) places: Vec<Places>,
}

/// The slots one instruction writes and reads.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Places {
    /// The result's slot.
    pub(crate) out: u32,
    /// The operands' slots (an operand the instruction does not read: the first
    /// operand's, or the result's where it reads none).
    pub(crate) ops: [u32; 3],
    /// Bit `k`: operand `k` (as `ops` names it) is a constant.
    pub(crate) consts: u8,
}

impl Slots {
    /// Linear scan over the tape: a register's slot is free again after its last read.
    pub(crate) fn allocate(ins: &[Instr]) -> Slots {
        let mut slot: Vec<u32> = Vec::with_capacity(ins.len());
        let mut free: Vec<u32> = Vec::new();
        let mut count = 0u32;
        for i in ins {
            // The operands' slots are freed after the result's is taken: a result
            // never shares storage with its operands (the kernels write it while they
            // read them), and a constant's one block is read for every block of it.
            let mut late = [None; 3];
            for &k in i.operands() {
                if i.last & (1 << k) != 0 {
                    late[k] = Some(slot[i.reg(k) as usize]);
                }
            }
            let s = free.pop().unwrap_or_else(|| {
                count += 1;
                count - 1
            });
            slot.push(s);
            for s in late.into_iter().flatten() {
                if !free.contains(&s) {
                    free.push(s);
                }
            }
        }
        let places = ins
            .iter()
            .zip(&slot)
            .map(|(i, &out)| {
                let arity = i.operands().len();
                let mut p = Places {
                    out,
                    ops: [out; 3],
                    consts: 0,
                };
                if arity > 0 {
                    for q in 0..3 {
                        let r = i.reg(q.min(arity - 1)) as usize;
                        p.ops[q] = slot[r];
                        if ins[r].op == Op::Const {
                            p.consts |= 1 << q;
                        }
                    }
                }
                p
            })
            .collect();
        Slots {
            slot,
            count: count as usize,
            places,
        }
    }
}

thread_local! {
    /// This thread's register file (eight-lane blocks), reused by every batch.
    static FILE: RefCell<Vec<F64x8>> = const { RefCell::new(Vec::new()) };
    /// This thread's staged inputs, reused likewise.
    static INPUTS: RefCell<Vec<F64x8>> = const { RefCell::new(Vec::new()) };
    /// This thread's copies of watched registers ([`with_seen`]), reused likewise.
    static SEEN: RefCell<Vec<F64x8>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with this thread's buffer for watched registers, `len` blocks long
/// (contents unspecified), or with a fresh one inside a nested call.
pub(crate) fn with_seen<T>(len: usize, f: impl FnOnce(&mut [F64x8]) -> T) -> T {
    let mut v = SEEN
        .try_with(|c| c.try_borrow_mut().map(|mut v| std::mem::take(&mut *v)).ok())
        .ok()
        .flatten()
        .unwrap_or_default();
    if v.len() < len {
        v.resize(len, F64x8::default());
    }
    let out = f(&mut v[..len]);
    let _ = SEEN.try_with(|c| {
        if let Ok(mut c) = c.try_borrow_mut() {
            if c.len() < v.len() {
                *c = v;
            }
        }
    });
    out
}

/// Runs `f` with this thread's register file and input buffer, `file` and `inputs`
/// blocks long (contents unspecified), or with fresh ones inside a nested batch.
pub(crate) fn with_file<T>(
    file: usize,
    inputs: usize,
    f: impl FnOnce(&mut [F64x8], &mut [F64x8]) -> T,
) -> T {
    let take = |cell: &'static std::thread::LocalKey<RefCell<Vec<F64x8>>>| {
        cell.try_with(|c| c.try_borrow_mut().map(|mut v| std::mem::take(&mut *v)).ok())
            .ok()
            .flatten()
            .unwrap_or_default()
    };
    let (mut fv, mut iv) = (take(&FILE), take(&INPUTS));
    if fv.len() < file {
        fv.resize(file, F64x8::default());
    }
    if iv.len() < inputs {
        iv.resize(inputs, F64x8::default());
    }
    let out = f(&mut fv[..file], &mut iv[..inputs]);
    let give = |cell: &'static std::thread::LocalKey<RefCell<Vec<F64x8>>>, v: Vec<F64x8>| {
        let _ = cell.try_with(|c| {
            if let Ok(mut c) = c.try_borrow_mut() {
                if c.len() < v.len() {
                    *c = v;
                }
            }
        });
    };
    give(&FILE, fv);
    give(&INPUTS, iv);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Tape;
    use arith_core::Real;

    /// A slot is never taken while its register may still be read.
    #[test]
    fn slots_never_overlap_live_registers() {
        let t = Tape::record(|x, y, z| {
            let a = x.sqr() + y.sqr();
            let b = (a + z.sqr()).sqrt();
            (a * b - x * 3.0).max(&(b - y * z)).rsub(1.0)
        });
        let ins = t.instructions();
        let s = Slots::allocate(ins);
        assert!(s.count < ins.len(), "slots are reused");
        // The last read of each register.
        let mut last = vec![0; ins.len()];
        for (k, i) in ins.iter().enumerate() {
            for &o in i.operands() {
                last[i.reg(o) as usize] = k;
            }
        }
        // A register read at or after instruction k keeps its slot to itself at k.
        for k in 0..ins.len() {
            for (r, &l) in last.iter().enumerate().take(k) {
                assert!(
                    l < k || s.slot[r] != s.slot[k],
                    "r{k} takes the slot of r{r}, still read at r{l}"
                );
            }
        }
    }
}
