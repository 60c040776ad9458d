//! Constant folding, exact only: an operation on constants is replaced by its `f64`
//! value only where that value is the real one (checked with error-free
//! transformations), so range evaluation of a tape stays sound; an inexact one such as
//! `1/3` stays an instruction and every [`arith_core::Range`] encloses it. Also the
//! binary operators of the builder ([`Bin`]) and HyperFun's tolerance for truth values
//! ([`EPS`]).

use crate::instr::Op;
use arith_core::branch::Step;
use arith_core::round::two_sum;
use arith_core::Real;

/// HyperFun's tolerance for truth values and equality: `|v| >= EPS` holds.
pub const EPS: f64 = 1e-6;

/// A binary operator as a reader hands it to the [`crate::Builder`]: arithmetic,
/// R-functions, comparisons (1 or 0) and logic on truth values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Bin {
    /// `a + b`.
    Add,
    /// `a - b`.
    Sub,
    /// `a * b`.
    Mul,
    /// `a / b`.
    Div,
    /// R-function intersection `a & b`.
    Intersect,
    /// R-function union `a | b`.
    Union,
    /// R-function subtraction `a \ b`.
    Subtract,
    /// `a < b`: 1 or 0.
    Lt,
    /// `a <= b`: 1 or 0.
    Le,
    /// `a > b`: 1 or 0.
    Gt,
    /// `a >= b`: 1 or 0.
    Ge,
    /// `a == b` within [`EPS`]: `|a - b| < EPS`, 1 or 0.
    Eq,
    /// `a != b`: `|a - b| >= EPS`, 1 or 0.
    Ne,
    /// `a and b`: 1 where both hold (`|v| >= EPS`), else 0.
    And,
    /// `a or b`: 1 where either holds, else 0.
    Or,
}

/// `a + b` if the `f64` sum is exact and finite.
pub fn exact_add(a: f64, b: f64) -> Option<f64> {
    let (s, e) = two_sum(a, b);
    (s.is_finite() && e == 0.0).then_some(s)
}

/// `a * b` if the `f64` product is exact and finite. Products in the subnormal range are
/// refused: there the fused error term may itself underflow to 0.
pub fn exact_mul(a: f64, b: f64) -> Option<f64> {
    let p = a * b;
    if !p.is_finite() {
        return None;
    }
    if p == 0.0 {
        return (a == 0.0 || b == 0.0).then_some(p);
    }
    if p.abs() < f64::MIN_POSITIVE * 2f64.powi(53) {
        return None;
    }
    (a.mul_add(b, -p) == 0.0).then_some(p)
}

/// `a / b` if the `f64` quotient is exact and finite.
pub fn exact_div(a: f64, b: f64) -> Option<f64> {
    let q = a / b;
    if b == 0.0 || !q.is_finite() {
        return None;
    }
    if q == 0.0 {
        return (a == 0.0).then_some(q);
    }
    (exact_mul(q, b) == Some(a)).then_some(q)
}

/// `sqrt(a)` if exact (and `0` for `a <= 0`, the extended root).
pub fn exact_sqrt(a: f64) -> Option<f64> {
    if a <= 0.0 {
        // The extended square root is exactly 0 there, in every arithmetic.
        return Some(Real::sqrt(&a));
    }
    let r = a.sqrt();
    (exact_mul(r, r) == Some(a)).then_some(r)
}

/// `c^n` if every product (and the final reciprocal) is exact.
pub fn exact_powi(c: f64, n: i32) -> Option<f64> {
    if n == 0 {
        return Some(1.0);
    }
    if n.unsigned_abs() > 4096 {
        // Only hand-built trees get here (the parser caps exponents); not worth folding.
        return None;
    }
    let mut p = c;
    for _ in 1..n.unsigned_abs() {
        p = exact_mul(p, c)?;
    }
    if n < 0 {
        exact_div(1.0, p)
    } else {
        Some(p)
    }
}

/// A unary instruction on a constant, where its value is exact.
pub fn fold_unary(op: Op, c: f64) -> Option<f64> {
    match op {
        Op::Sqrt => exact_sqrt(c),
        Op::Abs => Some(c.abs()),
        Op::Recip => exact_div(1.0, c),
        Op::Exp if c == 0.0 => Some(1.0),
        Op::Ln if c == 1.0 => Some(0.0),
        Op::Sin if c == 0.0 => Some(c),
        Op::Cos if c == 0.0 => Some(1.0),
        _ => None,
    }
}

/// A binary operator on constants, where its value is exact (comparisons and logic
/// always are).
pub fn fold_bin(op: Bin, a: f64, b: f64) -> Option<f64> {
    let norm = || exact_sqrt(exact_add(exact_mul(a, a)?, exact_mul(b, b)?)?);
    match op {
        Bin::Add => exact_add(a, b),
        Bin::Sub => exact_add(a, -b),
        Bin::Mul => exact_mul(a, b),
        Bin::Div => exact_div(a, b),
        Bin::Intersect => exact_add(exact_add(a, b)?, -norm()?),
        Bin::Union => exact_add(exact_add(a, b)?, norm()?),
        Bin::Subtract => exact_add(exact_add(a, -b)?, -norm()?),
        Bin::Lt | Bin::Le | Bin::Gt | Bin::Ge | Bin::Eq | Bin::Ne => Some(fold_cmp(op, a, b)),
        Bin::And | Bin::Or => {
            let (p, q) = (a.abs() >= EPS, b.abs() >= EPS);
            let v = if op == Bin::And { p && q } else { p || q };
            Some(if v { 1.0 } else { 0.0 })
        }
    }
}

/// A comparison of two constants, computed as the tape computes it at points.
pub fn fold_cmp(op: Bin, a: f64, b: f64) -> f64 {
    match op {
        Bin::Lt => Step::Pos.at(b - a),
        Bin::Le => Step::NonNeg.at(b - a),
        Bin::Gt => Step::Pos.at(a - b),
        Bin::Ge => Step::NonNeg.at(a - b),
        Bin::Eq => Step::Pos.at(EPS - (a - b).abs()),
        _ => Step::NonNeg.at((a - b).abs() - EPS),
    }
}
