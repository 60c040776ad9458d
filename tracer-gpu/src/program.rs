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
    /// The R-union `a + b + sqrt(a^2 + b^2)`, evaluated without its cancellation.
    RUnion(u32, u32),
    /// The R-intersection `a + b - sqrt(a^2 + b^2)`, evaluated without its cancellation.
    RIntersect(u32, u32),
    /// The R-subtraction `a - b - sqrt(a^2 + b^2)` (`a & -b`).
    RSubtract(u32, u32),
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
            Add(a, b)
            | Sub(a, b)
            | Mul(a, b)
            | Div(a, b)
            | Min(a, b)
            | Max(a, b)
            | Hypot(a, b)
            | RUnion(a, b)
            | RIntersect(a, b)
            | RSubtract(a, b) => vec![a, b],
            Select(c, t, e) => vec![c, t, e],
        }
    }

    /// This operation reading `f(r)` for each register `r` it reads.
    pub fn map_operands(&self, f: impl Fn(u32) -> u32) -> Op {
        use Op::*;
        match *self {
            X | Y | Z | Const(_) => *self,
            Neg(a) => Neg(f(a)),
            Sqr(a) => Sqr(f(a)),
            Powi(a, n) => Powi(f(a), n),
            Sqrt(a) => Sqrt(f(a)),
            Recip(a) => Recip(f(a)),
            Exp(a) => Exp(f(a)),
            Ln(a) => Ln(f(a)),
            Sin(a) => Sin(f(a)),
            Cos(a) => Cos(f(a)),
            Abs(a) => Abs(f(a)),
            Gt0(a) => Gt0(f(a)),
            Ge0(a) => Ge0(f(a)),
            AddC(a, c) => AddC(f(a), c),
            MulC(a, c) => MulC(f(a), c),
            DivC(a, c) => DivC(f(a), c),
            RSubC(a, c) => RSubC(f(a), c),
            RDivC(a, c) => RDivC(f(a), c),
            Add(a, b) => Add(f(a), f(b)),
            Sub(a, b) => Sub(f(a), f(b)),
            Mul(a, b) => Mul(f(a), f(b)),
            Div(a, b) => Div(f(a), f(b)),
            Min(a, b) => Min(f(a), f(b)),
            Max(a, b) => Max(f(a), f(b)),
            Hypot(a, b) => Hypot(f(a), f(b)),
            RUnion(a, b) => RUnion(f(a), f(b)),
            RIntersect(a, b) => RIntersect(f(a), f(b)),
            RSubtract(a, b) => RSubtract(f(a), f(b)),
            Select(c, t, e) => Select(f(c), f(t), f(e)),
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

    /// The R-functions written out as `a + b + h`, `a + b - h` and `a - b - h` with
    /// `h = hypot(a, b)` (as generic model code records them) become [`Op::RUnion`],
    /// [`Op::RIntersect`] and [`Op::RSubtract`], and what only they read is dropped.
    ///
    /// In `f32` the written-out form loses the result to cancellation wherever one
    /// operand is far more negative than the other is large (a union with a distant
    /// part of a scene: `-1e4 + 1e4 + 1e-3` keeps none of the `1e-3`); the fused
    /// operations evaluate it as `o + o^2 / (h - m)` there (`m` the negative operand,
    /// `o` the other), which has no cancellation.
    pub fn fuse_rfunctions(&mut self) {
        let n = self.ops.len();
        for k in 0..n {
            let (s, h, minus) = match self.ops[k] {
                Op::Add(s, h) => (s, h, false),
                Op::Sub(s, h) => (s, h, true),
                _ => continue,
            };
            let Op::Hypot(ha, hb) = self.ops[h as usize] else {
                continue;
            };
            let same = |a: u32, b: u32| (a, b) == (ha, hb) || (b, a) == (ha, hb);
            let fused = match (self.ops[s as usize], minus) {
                (Op::Add(a, b), false) if same(a, b) => Op::RUnion(a, b),
                (Op::Add(a, b), true) if same(a, b) => Op::RIntersect(a, b),
                (Op::Sub(a, b), true) if same(a, b) => Op::RSubtract(a, b),
                _ => continue,
            };
            self.ops[k] = fused;
        }
        self.eliminate_dead_code();
    }

    /// Drops the operations the result does not depend on (the inputs stay), keeping
    /// the order of the rest.
    pub fn eliminate_dead_code(&mut self) {
        let n = self.ops.len();
        if n == 0 {
            return;
        }
        let mut live = vec![false; n];
        live[n - 1] = true;
        for k in (0..n).rev() {
            if live[k] || matches!(self.ops[k], Op::X | Op::Y | Op::Z) {
                live[k] = true;
                for r in self.ops[k].operands() {
                    live[r as usize] = true;
                }
            }
        }
        let mut new_reg = vec![0u32; n];
        let mut ops = Vec::with_capacity(n);
        for k in 0..n {
            if live[k] {
                new_reg[k] = ops.len() as u32;
                ops.push(self.ops[k].map_operands(|r| new_reg[r as usize]));
            }
        }
        self.ops = ops;
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
                Op::RUnion(a, b) => g(a) + g(b) + (g(a) * g(a) + g(b) * g(b)).sqrt(),
                Op::RIntersect(a, b) => g(a) + g(b) - (g(a) * g(a) + g(b) * g(b)).sqrt(),
                Op::RSubtract(a, b) => g(a) - g(b) - (g(a) * g(a) + g(b) * g(b)).sqrt(),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `(x | y) & z` written out as generic model code records it, plus an unused
    /// operation, and `x \ y` on top.
    fn written_out() -> Program {
        let mut p = Program::default();
        let (x, y, z) = (p.push(Op::X), p.push(Op::Y), p.push(Op::Z));
        let _dead = p.push(Op::Sin(x));
        let s = p.push(Op::Add(x, y));
        let h = p.push(Op::Hypot(y, x));
        let u = p.push(Op::Add(s, h));
        let s2 = p.push(Op::Add(u, z));
        let h2 = p.push(Op::Hypot(u, z));
        let i = p.push(Op::Sub(s2, h2));
        let d = p.push(Op::Sub(x, y));
        let h3 = p.push(Op::Hypot(x, y));
        let sub = p.push(Op::Sub(d, h3));
        p.push(Op::Max(i, sub));
        p
    }

    #[test]
    fn fusing_keeps_the_values_and_drops_what_only_the_written_out_form_read() {
        let unfused = written_out();
        let mut fused = unfused.clone();
        fused.fuse_rfunctions();
        fused.check().expect("valid after fusing");
        let ops = &fused.ops;
        assert_eq!(&ops[..3], &[Op::X, Op::Y, Op::Z]);
        assert_eq!(
            ops.iter().filter(|o| matches!(o, Op::RUnion(..))).count(),
            1
        );
        assert_eq!(
            ops.iter()
                .filter(|o| matches!(o, Op::RIntersect(..)))
                .count(),
            1
        );
        assert_eq!(
            ops.iter()
                .filter(|o| matches!(o, Op::RSubtract(..)))
                .count(),
            1
        );
        assert!(!ops.iter().any(|o| matches!(o, Op::Hypot(..) | Op::Sin(_))));
        assert_eq!(ops.len(), 3 + 3 + 1);
        for (x, y, z) in [(0.3, -0.7, 2.0), (-40.0, 1e-3, 0.5), (1.0, 1.0, -1.0)] {
            let (a, b) = (unfused.eval_f64(x, y, z), fused.eval_f64(x, y, z));
            assert!((a - b).abs() <= 1e-12 * a.abs().max(1.0), "{a} vs {b}");
        }
    }

    #[test]
    fn a_sum_that_is_not_an_r_function_stays() {
        let mut p = Program::default();
        let (x, y, z) = (p.push(Op::X), p.push(Op::Y), p.push(Op::Z));
        let s = p.push(Op::Add(x, z));
        let h = p.push(Op::Hypot(x, y));
        p.push(Op::Add(s, h));
        let before = p.clone();
        p.fuse_rfunctions();
        assert_eq!(p, before);
    }
}
