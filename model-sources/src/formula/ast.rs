//! The syntax tree of a formula, and its printing back to text.
//!
//! Printing puts parentheses only where the grammar needs them, so that
//! `parse_program(&p.to_string()) == Ok(p)` for every tree whose literals are finite and
//! non-negative (the parser never produces others) and whose binding names are valid.

use std::fmt;

/// One of the three coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Var {
    /// `x`.
    X,
    /// `y`.
    Y,
    /// `z`.
    Z,
}

impl Var {
    /// Its name in formulas.
    pub fn name(self) -> &'static str {
        match self {
            Var::X => "x",
            Var::Y => "y",
            Var::Z => "z",
        }
    }
}

/// A named function.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Func {
    /// `sqrt`.
    Sqrt,
    /// `sqr`: the square.
    Sqr,
    /// `exp`.
    Exp,
    /// `ln`: the natural logarithm.
    Ln,
    /// `sin`.
    Sin,
    /// `cos`.
    Cos,
    /// `tan`, computed as `sin(a) / cos(a)` (each bounded soundly, and the quotient's
    /// range is the whole line where `cos` can be 0: at a pole).
    Tan,
    /// `abs`.
    Abs,
    /// `min` of two arguments.
    Min,
    /// `max` of two arguments.
    Max,
    /// `if(c, a, b)`: `a` where the condition `c` holds (`|c| >= 1e-6`, HyperFun's
    /// truth test), else `b`.
    If,
    /// `not(c)`: 1 where `c` does not hold, else 0.
    Not,
    /// `blend_union(a, b)`: the revised-affine paper's blending union
    /// (`arith_core::rfunc::blend_union`).
    BlendUnion,
    /// `blend_intersect(a, b)`: the paper's blending intersection
    /// (`arith_core::rfunc::blend_intersect`).
    BlendIntersect,
    /// `hf_blend_union(a, b, a0, a1, a2)`: HyperFun's `hfBlendUni`,
    /// `a | b + a0 / (1 + (a/a1)^2 + (b/a2)^2)`.
    HfBlendUnion,
    /// `hf_blend_intersect(a, b, a0, a1, a2)`: HyperFun's `hfBlendInt`,
    /// `a & b + a0 / (1 + (a/a1)^2 + (b/a2)^2)`.
    HfBlendIntersect,
}

impl Func {
    /// Every function, for lookups and test generators.
    pub const ALL: [Func; 16] = [
        Func::Sqrt,
        Func::Sqr,
        Func::Exp,
        Func::Ln,
        Func::Sin,
        Func::Cos,
        Func::Tan,
        Func::Abs,
        Func::Min,
        Func::Max,
        Func::If,
        Func::Not,
        Func::BlendUnion,
        Func::BlendIntersect,
        Func::HfBlendUnion,
        Func::HfBlendIntersect,
    ];

    /// Its name in formulas.
    pub fn name(self) -> &'static str {
        match self {
            Func::Sqrt => "sqrt",
            Func::Sqr => "sqr",
            Func::Exp => "exp",
            Func::Ln => "ln",
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Abs => "abs",
            Func::Min => "min",
            Func::Max => "max",
            Func::If => "if",
            Func::Not => "not",
            Func::BlendUnion => "blend_union",
            Func::BlendIntersect => "blend_intersect",
            Func::HfBlendUnion => "hf_blend_union",
            Func::HfBlendIntersect => "hf_blend_intersect",
        }
    }

    /// Number of arguments.
    pub fn arity(self) -> usize {
        match self {
            Func::Min | Func::Max | Func::BlendUnion | Func::BlendIntersect => 2,
            Func::If => 3,
            Func::HfBlendUnion | Func::HfBlendIntersect => 5,
            _ => 1,
        }
    }

    /// The function named `s`, if any.
    pub fn from_name(s: &str) -> Option<Func> {
        Func::ALL.into_iter().find(|f| f.name() == s)
    }
}

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinOp {
    /// `+`.
    Add,
    /// `-`.
    Sub,
    /// `*`.
    Mul,
    /// `/`.
    Div,
    /// R-function intersection `&`.
    Intersect,
    /// R-function union `|`.
    Union,
    /// R-function subtraction `\`.
    Subtract,
    /// `a < b`: 1 or 0.
    Lt,
    /// `a <= b`: 1 or 0.
    Le,
    /// `a > b`: 1 or 0.
    Gt,
    /// `a >= b`: 1 or 0.
    Ge,
    /// `a == b` within HyperFun's tolerance: `|a - b| < 1e-6`, 1 or 0.
    Eq,
    /// `a != b`: `|a - b| >= 1e-6`, 1 or 0.
    Ne,
    /// `a and b`: 1 where both hold (`|v| >= 1e-6`), else 0.
    And,
    /// `a or b`: 1 where either holds, else 0.
    Or,
}

impl BinOp {
    /// Every operator.
    pub const ALL: [BinOp; 15] = [
        BinOp::Add,
        BinOp::Sub,
        BinOp::Mul,
        BinOp::Div,
        BinOp::Intersect,
        BinOp::Union,
        BinOp::Subtract,
        BinOp::Lt,
        BinOp::Le,
        BinOp::Gt,
        BinOp::Ge,
        BinOp::Eq,
        BinOp::Ne,
        BinOp::And,
        BinOp::Or,
    ];

    /// Its symbol in formulas.
    pub fn symbol(self) -> &'static str {
        match self {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Intersect => "&",
            BinOp::Union => "|",
            BinOp::Subtract => "\\",
            BinOp::Lt => "<",
            BinOp::Le => "<=",
            BinOp::Gt => ">",
            BinOp::Ge => ">=",
            BinOp::Eq => "==",
            BinOp::Ne => "!=",
            BinOp::And => "and",
            BinOp::Or => "or",
        }
    }

    /// Binding strength; all binary operators are left-associative.
    pub(crate) fn prec(self) -> u8 {
        match self {
            BinOp::Or => PREC_OR,
            BinOp::And => PREC_AND,
            BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge | BinOp::Eq | BinOp::Ne => PREC_CMP,
            BinOp::Union => PREC_UNION,
            BinOp::Intersect | BinOp::Subtract => PREC_INTERSECT,
            BinOp::Add | BinOp::Sub => PREC_SUM,
            BinOp::Mul | BinOp::Div => PREC_PRODUCT,
        }
    }
}

pub(crate) const PREC_OR: u8 = 1;
pub(crate) const PREC_AND: u8 = 2;
pub(crate) const PREC_CMP: u8 = 3;
pub(crate) const PREC_UNION: u8 = 4;
pub(crate) const PREC_INTERSECT: u8 = 5;
pub(crate) const PREC_SUM: u8 = 6;
pub(crate) const PREC_PRODUCT: u8 = 7;
pub(crate) const PREC_UNARY: u8 = 8;
pub(crate) const PREC_POWER: u8 = 9;
pub(crate) const PREC_PRIMARY: u8 = 10;

/// An expression.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A literal (the parser only makes finite, non-negative ones).
    Num(f64),
    /// A coordinate.
    Var(Var),
    /// The value of binding number `i` of the enclosing [`Program`] (only earlier
    /// bindings may be referred to).
    Ref(usize),
    /// `-a`.
    Neg(Box<Expr>),
    /// `base ^ n`.
    Pow(Box<Expr>, i32),
    /// `base ^ c` for a finite, non-integer `c`: `exp(c ln(base))`, so 0 (for `c > 0`)
    /// or `+inf` (for `c < 0`) where `base <= 0`.
    PowF(Box<Expr>, f64),
    /// A function applied to its arguments.
    Call(Func, Vec<Expr>),
    /// A binary operator applied to two operands.
    Bin(BinOp, Box<Expr>, Box<Expr>),
}

impl Expr {
    /// `a op b`.
    pub fn bin(op: BinOp, a: Expr, b: Expr) -> Expr {
        Expr::Bin(op, Box::new(a), Box::new(b))
    }
    #[allow(clippy::should_implement_trait)]
    /// `-a`.
    pub fn neg(a: Expr) -> Expr {
        Expr::Neg(Box::new(a))
    }
    /// `a ^ n`.
    pub fn pow(a: Expr, n: i32) -> Expr {
        Expr::Pow(Box::new(a), n)
    }

    fn prec(&self) -> u8 {
        match self {
            Expr::Num(c) if c.is_sign_negative() || !c.is_finite() => PREC_PRIMARY,
            Expr::Num(_) | Expr::Var(_) | Expr::Ref(_) | Expr::Call(..) => PREC_PRIMARY,
            Expr::Neg(_) => PREC_UNARY,
            Expr::Pow(..) | Expr::PowF(..) => PREC_POWER,
            Expr::Bin(op, ..) => op.prec(),
        }
    }
}

/// `name = expr;` before the final expression.
#[derive(Clone, Debug, PartialEq)]
pub struct Binding {
    /// The bound name.
    pub name: String,
    /// Its value.
    pub expr: Expr,
}

/// A whole formula: bindings, then the expression whose value is the function.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    /// The bindings, in order.
    pub bindings: Vec<Binding>,
    /// The final expression.
    pub body: Expr,
}

impl Program {
    fn write_expr(&self, f: &mut fmt::Formatter<'_>, e: &Expr) -> fmt::Result {
        match e {
            Expr::Num(c) => write_num(f, *c),
            Expr::Var(v) => f.write_str(v.name()),
            Expr::Ref(i) => match self.bindings.get(*i) {
                Some(b) => f.write_str(&b.name),
                // Not produced by the parser; printed so that re-parsing fails loudly.
                None => write!(f, "?{i}"),
            },
            Expr::Neg(a) => {
                f.write_str("-")?;
                self.write_operand(f, a, a.prec() < PREC_UNARY)
            }
            Expr::Pow(a, n) => {
                self.write_operand(f, a, a.prec() < PREC_PRIMARY)?;
                write!(f, "^{n}")
            }
            Expr::PowF(a, c) => {
                self.write_operand(f, a, a.prec() < PREC_PRIMARY)?;
                write!(f, "^{c:?}")
            }
            Expr::Call(func, args) => {
                write!(f, "{}(", func.name())?;
                for (k, a) in args.iter().enumerate() {
                    if k > 0 {
                        f.write_str(", ")?;
                    }
                    self.write_expr(f, a)?;
                }
                f.write_str(")")
            }
            Expr::Bin(op, a, b) => {
                let p = op.prec();
                self.write_operand(f, a, a.prec() < p)?;
                write!(f, " {} ", op.symbol())?;
                self.write_operand(f, b, b.prec() <= p)
            }
        }
    }

    fn write_operand(&self, f: &mut fmt::Formatter<'_>, e: &Expr, paren: bool) -> fmt::Result {
        if paren {
            f.write_str("(")?;
            self.write_expr(f, e)?;
            f.write_str(")")
        } else {
            self.write_expr(f, e)
        }
    }
}

/// Literals print in Rust's shortest round-trip form; negative and non-finite values
/// (only from folded or hand-built trees) print as parenthesised expressions.
fn write_num(f: &mut fmt::Formatter<'_>, c: f64) -> fmt::Result {
    if c.is_nan() {
        f.write_str("(0/0)")
    } else if c == f64::INFINITY {
        f.write_str("(1/0)")
    } else if c == f64::NEG_INFINITY {
        f.write_str("(-1/0)")
    } else if c.is_sign_negative() {
        write!(f, "(-{:?})", -c)
    } else {
        write!(f, "{c:?}")
    }
}

impl fmt::Display for Program {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for b in &self.bindings {
            write!(f, "{} = ", b.name)?;
            self.write_expr(f, &b.expr)?;
            f.write_str("; ")?;
        }
        self.write_expr(f, &self.body)
    }
}
