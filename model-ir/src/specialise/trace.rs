//! Specialisation read from a range evaluation's own trace: one interval evaluation
//! of a batch of boxes keeps the bounds of the registers that can decide something
//! (a [`Trace`]), and each box's tape is then written from them in one backward and one
//! forward pass ([`super::one_pass`]), without evaluating the box again, without
//! hashing, locks or shared caches. Boxes of one batch whose decisions agree share one
//! tape.

use super::rules::{Fold, KEEP};
use crate::tape::Tape;
use arith_core::lanes::{F64x8, LANES};
use arith_ia::Interval;

/// What [`Tape::eval_boxes_traced`] records of an evaluation for
/// [`Tape::specialise_traced`]: per box, the interval bounds of the tape's watched
/// registers (the operands of its `min` and `max` and its sign-only registers), and the
/// tapes built from them so far. Keep one per batch being worked on and reuse it: its
/// buffers grow to the largest batch and stay.
#[derive(Debug, Default)]
pub struct Trace {
    /// The tape that filled it (a trace read with another tape gives nothing).
    tape: Option<Tape>,
    /// Boxes evaluated.
    lanes: usize,
    /// Blocks of [`LANES`] boxes.
    chunks: usize,
    /// The watched bounds, laid out as [`Tape::watched_intervals`] does.
    seen: Vec<F64x8>,
    /// Tapes built from this trace: the range of their key in `keys`, and the tape
    /// (`None`: no shorter than the parent).
    built: Vec<(usize, usize, Option<Tape>)>,
    keys: Vec<u8>,
    decisions: Vec<u8>,
    key: Vec<u8>,
}

impl Trace {
    /// An empty trace.
    pub fn new() -> Self {
        Trace::default()
    }

    /// Forgets the last evaluation (its tapes too).
    pub fn clear(&mut self) {
        self.tape = None;
        self.lanes = 0;
        self.built.clear();
        self.keys.clear();
    }

    /// Boxes of the last evaluation.
    pub fn len(&self) -> usize {
        self.lanes
    }

    /// Whether it records no evaluation.
    pub fn is_empty(&self) -> bool {
        self.lanes == 0
    }
}

impl Tape {
    /// [`Tape::eval_batch`] over the boxes `(x[l], y[l], z[l])` (the same ranges, bit
    /// for bit), recording into `trace` what [`Tape::specialise_traced`] needs to
    /// specialise the tape to any of them without evaluating it again.
    pub fn eval_boxes_traced(
        &self,
        x: &[Interval],
        y: &[Interval],
        z: &[Interval],
        out: &mut Vec<Interval>,
        trace: &mut Trace,
    ) {
        let n = x.len();
        assert!(
            y.len() == n && z.len() == n,
            "eval_boxes_traced: inputs of unequal lengths"
        );
        trace.clear();
        let spec = self.specialiser();
        if !spec.worth {
            self.eval_batch(x, y, z, out);
            return;
        }
        trace.tape = Some(self.clone());
        trace.lanes = n;
        trace.chunks = n.div_ceil(LANES);
        trace.seen.clear();
        trace
            .seen
            .resize(2 * spec.watched * trace.chunks, F64x8::splat(f64::NAN));
        self.eval_boxes_watched([x, y, z], out, (&spec.place, &mut trace.seen));
    }

    /// The tape specialised to box `lane` of the evaluation `trace` recorded (by
    /// [`Tape::eval_boxes_traced`] on this tape), as [`Tape::specialise`] gives it over
    /// that box alone: the same decisions, from the same bounds. `None` where nothing
    /// shortens it, or `trace` was recorded with another tape. Boxes of the trace
    /// with the same decisions get one tape (a clone of it).
    pub fn specialise_traced(&self, trace: &mut Trace, lane: usize) -> Option<Tape> {
        let ins = self.instructions();
        let same = |t: &Tape| std::ptr::eq(t.instructions().as_ptr(), ins.as_ptr());
        if !trace.tape.as_ref().is_some_and(same) || lane >= trace.lanes {
            return None;
        }
        let spec = self.specialiser();
        let (chunks, seen) = (trace.chunks, &trace.seen);
        let (block, at) = (lane / LANES, lane % LANES);
        let bound = |k: usize| match spec.place[k] {
            u32::MAX => (f64::NAN, f64::NAN),
            p => {
                let i = 2 * (p as usize * chunks + block);
                (seen[i].0[at], seen[i + 1].0[at])
            }
        };
        spec.decide(ins, bound, Fold::Sign, &mut trace.decisions);
        if !spec.r_functions && trace.decisions.iter().all(|&d| d == KEEP) {
            return None;
        }
        spec.key(&trace.decisions, &mut trace.key);
        let keys = &trace.keys;
        let key = &trace.key;
        if let Some((_, _, t)) = trace.built.iter().find(|(i, j, _)| &keys[*i..*j] == key) {
            return t.clone();
        }
        let t = spec.sign_tape(ins, &trace.decisions);
        let i = trace.keys.len();
        trace.keys.extend_from_slice(&trace.key);
        trace.built.push((i, trace.keys.len(), t.clone()));
        t
    }
}
