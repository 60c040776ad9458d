//! The tape: a model as a flat list of SSA instructions ([`crate::Instr`]), the last
//! one's register the function's value, shared cheaply between threads and clones, with
//! what region specialisation learns about it built once on first use.

use crate::builder::{finish, Builder, Val};
use crate::eval;
use crate::instr::{Instr, Op};
use crate::specialise::rules::Specialiser;
use arith_core::Real;
use rustc_hash::FxHashMap as HashMap;
use std::fmt;
use std::sync::{Arc, Mutex, OnceLock};

/// A compiled model: evaluate it with [`Tape::eval`] over any [`Real`] (points, every
/// range arithmetic, dual numbers), specialise it to a region
/// ([`Tape::specialise`]), or hand its [`Tape::instructions`] to another evaluator.
///
/// ```
/// use arith_core::{Range, Real};
/// use arith_ia::Interval;
/// use model_ir::Tape;
/// // A unit ball, recorded from generic code.
/// let t = Tape::record(|x, y, z| (x.sqr() + y.sqr() + z.sqr()).rsub(1.0));
/// assert_eq!(t.eval(0.5_f64, 0.0, 0.0), 0.75);
/// let r = t.eval(
///     Interval::from_interval(0.0, 0.5),
///     Interval::from_interval(0.0, 0.5),
///     Interval::from_interval(0.0, 0.5),
/// );
/// assert!(r.bounds().0 <= 0.25 && r.bounds().1 >= 1.0);
/// ```
#[derive(Clone, Debug)]
pub struct Tape {
    ins: Arc<[Instr]>,
    /// What region specialisation needs of this tape; shared by clones.
    shared: Arc<Shared>,
}

/// What specialisation builds once per tape: its rules and the tapes built so far.
#[derive(Debug, Default)]
pub(crate) struct Shared {
    /// The analysis of the tape ([`crate::specialise`]), built on first use.
    pub(crate) rules: OnceLock<Specialiser>,
    /// Specialised tapes by decisions (`None`: no shorter than this one).
    pub(crate) cache: Mutex<HashMap<Vec<u8>, Option<Tape>>>,
    /// The batch kernels' register slots ([`crate::batch`]), built on first use.
    pub(crate) slots: OnceLock<crate::batch::Slots>,
    /// Specialisation takes bounds in the region's own arithmetic whatever the
    /// instructions (this tape was specialised from one that did).
    pub(crate) affine_bounds: bool,
}

impl Builder {
    /// The tape computing `out`, without the instructions it does not read.
    pub fn finish(mut self, out: Val) -> Tape {
        let out = self.reg(out);
        Tape::from_instructions(finish(std::mem::take(&mut self.ins), out))
    }
}

impl Tape {
    /// A tape of instructions [`finish`] produced.
    pub(crate) fn from_instructions(ins: Vec<Instr>) -> Tape {
        Tape {
            ins: ins.into(),
            shared: Arc::default(),
        }
    }

    /// A tape specialised from one whose specialisation takes bounds in the region's
    /// own arithmetic (`affine`), which it then does too.
    pub(crate) fn specialised(ins: Vec<Instr>, affine: bool) -> Tape {
        Tape {
            ins: ins.into(),
            shared: Arc::new(Shared {
                affine_bounds: affine,
                ..Default::default()
            }),
        }
    }

    pub(crate) fn shared(&self) -> &Shared {
        &self.shared
    }

    /// Whether the tape compares or selects ([`Op::Gt0`], [`Op::Ge0`], [`Op::Select`]).
    pub fn has_branches(&self) -> bool {
        self.ins
            .iter()
            .any(|i| matches!(i.op, Op::Gt0 | Op::Ge0 | Op::Select))
    }

    /// Number of instructions.
    pub fn len(&self) -> usize {
        self.ins.len()
    }

    /// Always false: a tape computes at least one value.
    pub fn is_empty(&self) -> bool {
        self.ins.is_empty()
    }

    /// The instructions; the last one's register is the result.
    pub fn instructions(&self) -> &[Instr] {
        &self.ins
    }

    /// Evaluates the tape at `(x, y, z)` in the arithmetic `R`.
    pub fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        eval::eval(&self.ins, x, y, z)
    }
}

impl fmt::Display for Tape {
    /// One instruction per line, `rN = op operands`; `!` marks a moved (last) read.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (r, i) in self.ins.iter().enumerate() {
            writeln!(f, "r{r} = {i}")?;
        }
        Ok(())
    }
}
