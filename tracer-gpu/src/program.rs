//! The GPU's tape: a model as a flat list of SSA operations (register `k` is the result
//! of operation `k`, the last one is the function's value), produced by the tracer from
//! a formula's tape or by recording a generic model, and compiled to WGSL by
//! [`crate::codegen`]. Constants are `f64`; the generated code encloses each in an `f32`
//! interval rounded outward.

/// One operation; operands are earlier registers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Op {
    /// The input `x`.
    X,
    /// The input `y`.
    Y,
    /// The input `z`.
    Z,
    /// An exact constant.
    Const(f64),
    /// `-a`
    Neg(u32),
    /// `a^2`
    Sqr(u32),
    /// `a^n`
    Powi(u32, i32),
    /// `sqrt(max(a, 0))`
    Sqrt(u32),
    /// `1 / a`
    Recip(u32),
    /// `e^a`
    Exp(u32),
    /// `ln a` (`-inf` at or below 0)
    Ln(u32),
    /// `sin a`
    Sin(u32),
    /// `cos a`
    Cos(u32),
    /// `|a|`
    Abs(u32),
    /// `a + c`
    AddC(u32, f64),
    /// `a * c`
    MulC(u32, f64),
    /// `a / c`
    DivC(u32, f64),
    /// `c - a`
    RSubC(u32, f64),
    /// `c / a`
    RDivC(u32, f64),
    /// `a + b`
    Add(u32, u32),
    /// `a - b`
    Sub(u32, u32),
    /// `a * b`
    Mul(u32, u32),
    /// `a / b`
    Div(u32, u32),
    /// `min(a, b)`
    Min(u32, u32),
    /// `max(a, b)`
    Max(u32, u32),
    /// `sqrt(a^2 + b^2)` (the R-functions' root; affine forms know its argument's floor)
    Hypot(u32, u32),
    /// `a > 0`: 1 or 0 (the range `[0, 1]` where undecided)
    Gt0(u32),
    /// `a >= 0`: 1 or 0 (the range `[0, 1]` where undecided)
    Ge0(u32),
    /// `t` where the truth value `c` is above 1/2, else `e` (the hull where undecided):
    /// `Select(c, t, e)`
    Select(u32, u32, u32),
}

impl Op {
    /// The registers this operation reads.
    pub fn operands(&self) -> Vec<u32> {
        use Op::*;
        match *self {
            X | Y | Z | Const(_) => vec![],
            Neg(a)
            | Sqr(a)
            | Powi(a, _)
            | Sqrt(a)
            | Recip(a)
            | Exp(a)
            | Ln(a)
            | Sin(a)
            | Cos(a)
            | Abs(a)
            | Gt0(a)
            | Ge0(a)
            | AddC(a, _)
            | MulC(a, _)
            | DivC(a, _)
            | RSubC(a, _)
            | RDivC(a, _) => vec![a],
            Add(a, b) | Sub(a, b) | Mul(a, b) | Div(a, b) | Min(a, b) | Max(a, b) | Hypot(a, b) => {
                vec![a, b]
            }
            Select(c, t, e) => vec![c, t, e],
        }
    }
}

/// A model for the GPU: operations in order, the last one's value is `f(x, y, z)`.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Program {
    /// The operations.
    pub ops: Vec<Op>,
}

impl Program {
    /// Appends `op`, returning its register.
    pub fn push(&mut self, op: Op) -> u32 {
        self.ops.push(op);
        (self.ops.len() - 1) as u32
    }

    /// `Ok` when the program is non-empty and every operand names an earlier register.
    pub fn check(&self) -> Result<(), String> {
        if self.ops.is_empty() {
            return Err("the GPU program is empty".into());
        }
        for (k, op) in self.ops.iter().enumerate() {
            if let Some(bad) = op.operands().into_iter().find(|&r| r as usize >= k) {
                return Err(format!(
                    "GPU program operation {k} ({op:?}) reads register {bad}, not defined before it"
                ));
            }
        }
        Ok(())
    }

    /// `f` at a point in plain `f64` (for tests and the tracer's checks of a recording).
    pub fn eval_f64(&self, x: f64, y: f64, z: f64) -> f64 {
        let mut r: Vec<f64> = Vec::with_capacity(self.ops.len());
        for op in &self.ops {
            let g = |k: u32| r[k as usize];
            let v = match *op {
                Op::X => x,
                Op::Y => y,
                Op::Z => z,
                Op::Const(c) => c,
                Op::Neg(a) => -g(a),
                Op::Sqr(a) => g(a) * g(a),
                Op::Powi(a, n) => g(a).powi(n),
                Op::Sqrt(a) => g(a).max(0.0).sqrt(),
                Op::Recip(a) => 1.0 / g(a),
                Op::Exp(a) => g(a).exp(),
                Op::Ln(a) => {
                    if g(a) <= 0.0 {
                        f64::NEG_INFINITY
                    } else {
                        g(a).ln()
                    }
                }
                Op::Sin(a) => g(a).sin(),
                Op::Cos(a) => g(a).cos(),
                Op::Abs(a) => g(a).abs(),
                Op::AddC(a, c) => g(a) + c,
                Op::MulC(a, c) => g(a) * c,
                Op::DivC(a, c) => g(a) / c,
                Op::RSubC(a, c) => c - g(a),
                Op::RDivC(a, c) => c / g(a),
                Op::Add(a, b) => g(a) + g(b),
                Op::Sub(a, b) => g(a) - g(b),
                Op::Mul(a, b) => g(a) * g(b),
                Op::Div(a, b) => g(a) / g(b),
                Op::Min(a, b) => g(a).min(g(b)),
                Op::Max(a, b) => g(a).max(g(b)),
                Op::Hypot(a, b) => (g(a) * g(a) + g(b) * g(b)).sqrt(),
                Op::Gt0(a) => f64::from(u8::from(g(a) > 0.0)),
                Op::Ge0(a) => f64::from(u8::from(g(a) >= 0.0)),
                Op::Select(c, t, e) => {
                    if g(c) > 0.5 {
                        g(t)
                    } else {
                        g(e)
                    }
                }
            };
            r.push(v);
        }
        r.last().copied().unwrap_or(f64::NAN)
    }
}
