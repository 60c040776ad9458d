//! The instruction set: what one step of a tape computes ([`Op`]) and how it names its
//! operands ([`Instr`]). Every evaluator of the workspace runs these instructions (the
//! interpreter over any [`arith_core::Real`], the GPU's generated WGSL), every reader
//! compiles into them and specialisation rewrites them; nothing else defines an
//! instruction.

use std::fmt;

/// What an instruction computes. `a`, `b` are operand registers, `c` an `f64` constant,
/// `n` an integer exponent.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Op {
    /// The input `x`.
    X,
    /// The input `y`.
    Y,
    /// The input `z`.
    Z,
    /// `c`
    Const,
    /// `-a`
    Neg,
    /// `a^2`
    Sqr,
    /// `a^n`
    Powi,
    /// `sqrt(a)`
    Sqrt,
    /// `exp(a)`
    Exp,
    /// `ln(a)`
    Ln,
    /// `sin(a)`
    Sin,
    /// `cos(a)`
    Cos,
    /// `|a|`
    Abs,
    /// `1 / a`
    Recip,
    /// `a + c`
    AddC,
    /// `a - c`
    SubC,
    /// `c - a`
    RSubC,
    /// `a * c`
    MulC,
    /// `a / c`
    DivC,
    /// `c / a`
    RDivC,
    /// `a + b`
    Add,
    /// `a - b`
    Sub,
    /// `a * b`
    Mul,
    /// `a / b`
    Div,
    /// `sqrt(a^2 + b^2)`, the root of the R-functions ([`arith_core::Real::hypot`])
    Hypot,
    /// `min(a, b)`
    Min,
    /// `max(a, b)`
    Max,
    /// R-function `a & b`
    Intersect,
    /// R-function `a | b`
    Union,
    /// R-function `a \ b`
    Subtract,
    /// The paper's blending union `blend_union(a, b)`
    BlendUnion,
    /// The paper's blending intersection `blend_intersect(a, b)`
    BlendIntersect,
    /// `a > 0`: 1 or 0 (the range `[0, 1]` where undecided)
    Gt0,
    /// `a >= 0`: 1 or 0 (the range `[0, 1]` where undecided)
    Ge0,
    /// `b` where the truth value `a` is 1, `e` where it is 0 (the hull where undecided)
    Select,
}

impl Op {
    /// Every instruction.
    pub const ALL: [Op; 35] = {
        use Op::*;
        [
            X,
            Y,
            Z,
            Const,
            Neg,
            Sqr,
            Powi,
            Sqrt,
            Recip,
            Exp,
            Ln,
            Sin,
            Cos,
            Abs,
            AddC,
            SubC,
            RSubC,
            MulC,
            DivC,
            RDivC,
            Add,
            Sub,
            Mul,
            Div,
            Hypot,
            Min,
            Max,
            Intersect,
            Union,
            Subtract,
            BlendUnion,
            BlendIntersect,
            Gt0,
            Ge0,
            Select,
        ]
    };

    /// Number of register operands.
    pub fn arity(self) -> usize {
        use Op::*;
        match self {
            X | Y | Z | Const => 0,
            Neg | Sqr | Powi | Sqrt | Recip | Exp | Ln | Sin | Cos | Abs | Gt0 | Ge0 => 1,
            AddC | SubC | RSubC | MulC | DivC | RDivC => 1,
            Add | Sub | Mul | Div | Hypot | Min | Max | Intersect | Union | Subtract => 2,
            BlendUnion | BlendIntersect => 2,
            Select => 3,
        }
    }

    /// Lower-case mnemonic used in listings.
    pub fn name(self) -> &'static str {
        use Op::*;
        match self {
            X => "x",
            Y => "y",
            Z => "z",
            Const => "const",
            Neg => "neg",
            Sqr => "sqr",
            Powi => "powi",
            Sqrt => "sqrt",
            Exp => "exp",
            Ln => "ln",
            Sin => "sin",
            Cos => "cos",
            Abs => "abs",
            Recip => "recip",
            AddC => "addc",
            SubC => "subc",
            RSubC => "rsubc",
            MulC => "mulc",
            DivC => "divc",
            RDivC => "rdivc",
            Add => "add",
            Sub => "sub",
            Mul => "mul",
            Div => "div",
            Hypot => "hypot",
            Min => "min",
            Max => "max",
            Intersect => "intersect",
            Union => "union",
            Subtract => "subtract",
            BlendUnion => "blend_union",
            BlendIntersect => "blend_intersect",
            Gt0 => "gt0",
            Ge0 => "ge0",
            Select => "select",
        }
    }

    /// Whether swapping the operands never changes a bit of the result, so that the
    /// builder may order them to share `a op b` and `b op a`. Not `min`/`max`: for
    /// `-0` and `+0` the `f64` result is whichever operand comes second.
    pub(crate) fn commutative(self) -> bool {
        matches!(
            self,
            Op::Add | Op::Mul | Op::Intersect | Op::Union | Op::BlendUnion | Op::BlendIntersect
        )
    }
}

/// One tape instruction; its result is the register with its own index.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instr {
    /// What it computes.
    pub op: Op,
    /// Exponent of [`Op::Powi`], 0 otherwise.
    pub n: i32,
    /// Operand registers (unused ones are 0).
    pub a: u32,
    /// Second operand register (unused ones are 0).
    pub b: u32,
    /// Third operand register: the else value of [`Op::Select`] (0 otherwise).
    pub e: u32,
    /// Constant of [`Op::Const`] and the `...C` ops, 0 otherwise.
    pub c: f64,
    /// Bit 0: this is the last read of `a`; bit 1: of `b`; bit 2: of `e` (the value is
    /// moved, not cloned).
    pub last: u8,
}

impl Instr {
    /// An instruction reading `a` and `b` (0 where unused), with exponent `n` and
    /// constant `c`; no third operand, no last reads marked.
    pub fn new(op: Op, a: u32, b: u32, n: i32, c: f64) -> Self {
        Instr {
            op,
            n,
            a,
            b,
            e: 0,
            c,
            last: 0,
        }
    }

    /// Register operands, in reading order.
    pub fn operands(&self) -> &'static [usize] {
        match self.op.arity() {
            0 => &[],
            1 => &[0],
            2 => &[0, 1],
            _ => &[0, 1, 2],
        }
    }

    /// The register of operand `k` (0: `a`, 1: `b`, 2: `e`).
    pub fn reg(&self, k: usize) -> u32 {
        match k {
            0 => self.a,
            1 => self.b,
            _ => self.e,
        }
    }

    pub(crate) fn reg_mut(&mut self, k: usize) -> &mut u32 {
        match k {
            0 => &mut self.a,
            1 => &mut self.b,
            _ => &mut self.e,
        }
    }

    pub(crate) fn key(&self) -> Key {
        (self.op, self.n, [self.a, self.b, self.e], self.c.to_bits())
    }
}

impl fmt::Display for Instr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.op.name())?;
        for &k in self.operands() {
            let sep = if k == 0 { " " } else { ", " };
            let moved = if self.last & (1 << k) != 0 { "!" } else { "" };
            write!(f, "{sep}r{}{moved}", self.reg(k))?;
        }
        match self.op {
            Op::Const => write!(f, " {:?}", self.c),
            Op::Powi => write!(f, ", {}", self.n),
            Op::AddC | Op::SubC | Op::RSubC | Op::MulC | Op::DivC | Op::RDivC => {
                write!(f, ", {:?}", self.c)
            }
            _ => Ok(()),
        }
    }
}

/// What identifies an instruction for sharing: op, exponent, operands, constant bits.
pub(crate) type Key = (Op, i32, [u32; 3], u64);
