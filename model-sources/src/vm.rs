//! fidget's `.vm` tapes: the SSA text format of the fidget library (and of MPR before
//! it), read into our formula [`Program`] and compiled to a [`Tape`].
//!
//! ```text
//! # a comment (from '#' to the end of the line)
//! _0 var-x
//! _1 const 0.5
//! _2 square _0
//! _3 sub _2 _1
//! ```
//!
//! Each line defines one value: an identifier (any word), an opcode, and operands that
//! name earlier values (or, for `const`, a number). The last value defined is the
//! function. An identifier may be defined again; later lines then mean the new value,
//! as in fidget. Opcodes read: `var-x var-y var-z const add sub mul div min max neg
//! square sqrt abs exp ln sin cos tan recip` (`tan` as `sin / cos`). fidget also
//! defines `floor ceil round asin acos atan atan2 not rand compare mod and or mix`; they are refused with an error
//! naming the opcode and its line and column.
//!
//! **Sign convention.** fidget's functions are negative inside, ours are `>= 0` inside,
//! so the tape is the negation of the file's function (exact in every arithmetic). Our
//! `sqrt` and `ln` are the extended ones of [`arith_core::Real`] (`sqrt` is 0 below 0),
//! where fidget returns NaN.
//!
//! The SSA values become bindings (each a node over earlier ones), so the text's sharing
//! is kept and nothing recurses over the length of the tape: a tape of any length reads
//! in one pass. A header ([`super::header`], `#` comments) may state the domain and
//! view; the default domain is fidget's `[-1, 1]^3`.

use super::formula::{self, BinOp, Binding, Expr, Func, Program, Tape, Var};
use std::collections::HashMap;

/// fidget opcodes this reader refuses.
pub const UNSUPPORTED: [&str; 14] = [
    "floor", "ceil", "round", "asin", "acos", "atan", "atan2", "not", "rand", "compare", "mod",
    "and", "or", "mix",
];

/// What an opcode reads.
#[derive(Clone, Copy)]
enum Kind {
    Var(Var),
    Const,
    Unary(fn(Expr) -> Expr),
    Call(Func),
    Binary(fn(Expr, Expr) -> Expr),
}

fn opcode(op: &str) -> Option<Kind> {
    use Kind::*;
    Some(match op {
        "var-x" => Var(super::formula::Var::X),
        "var-y" => Var(super::formula::Var::Y),
        "var-z" => Var(super::formula::Var::Z),
        "const" => Const,
        "add" => Binary(|a, b| Expr::bin(BinOp::Add, a, b)),
        "sub" => Binary(|a, b| Expr::bin(BinOp::Sub, a, b)),
        "mul" => Binary(|a, b| Expr::bin(BinOp::Mul, a, b)),
        "div" => Binary(|a, b| Expr::bin(BinOp::Div, a, b)),
        "min" => Binary(|a, b| Expr::Call(Func::Min, vec![a, b])),
        "max" => Binary(|a, b| Expr::Call(Func::Max, vec![a, b])),
        "neg" => Unary(Expr::neg),
        "square" => Unary(|a| Expr::pow(a, 2)),
        "recip" => Unary(|a| Expr::bin(BinOp::Div, Expr::Num(1.0), a)),
        "sqrt" => Call(Func::Sqrt),
        "abs" => Call(Func::Abs),
        "exp" => Call(Func::Exp),
        "ln" => Call(Func::Ln),
        "sin" => Call(Func::Sin),
        "cos" => Call(Func::Cos),
        "tan" => Call(Func::Tan),
        _ => return None,
    })
}

/// Opcodes read, for messages.
const SUPPORTED: &str =
    "var-x var-y var-z const add sub mul div min max neg square recip sqrt abs exp ln sin cos tan";

/// A malformed tape: 1-based line and column (in characters) and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VmError {
    /// 1-based line.
    pub line: usize,
    /// 1-based column of the offending word.
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

impl std::fmt::Display for VmError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: {}", self.line, self.column, self.message)
    }
}

impl std::error::Error for VmError {}

/// The words of a line without its comment, each with its 1-based column.
fn words(line: &str) -> Vec<(usize, &str)> {
    let line = line.split('#').next().unwrap_or("");
    let mut out = Vec::new();
    let mut start = None;
    for (k, (b, c)) in line.char_indices().enumerate() {
        if c.is_whitespace() {
            if let Some((s, sc)) = start.take() {
                out.push((sc, &line[s..b]));
            }
        } else if start.is_none() {
            start = Some((b, k + 1));
        }
    }
    if let Some((s, sc)) = start {
        out.push((sc, &line[s..]));
    }
    out
}

/// Reads a `.vm` tape into a program whose value is the negated tape (see the module
/// docs for the sign convention).
pub fn parse_program(text: &str) -> Result<Program, VmError> {
    let mut values: HashMap<&str, Expr> = HashMap::new();
    let mut bindings: Vec<Binding> = Vec::new();
    let mut last: Option<Expr> = None;
    for (k, line) in text.lines().enumerate() {
        let err = |column: usize, message: String| VmError {
            line: k + 1,
            column,
            message,
        };
        let w = words(line);
        let Some(&(_, id)) = w.first() else {
            continue;
        };
        let Some(&(op_col, op)) = w.get(1) else {
            return Err(err(
                w[0].0 + id.chars().count(),
                format!("expected an opcode after '{id}'"),
            ));
        };
        let Some(kind) = opcode(op) else {
            let why = if UNSUPPORTED.contains(&op) {
                format!("fidget opcode '{op}' is not supported (supported: {SUPPORTED})")
            } else {
                format!("unknown opcode '{op}' (supported: {SUPPORTED})")
            };
            return Err(err(op_col, why));
        };
        let args = &w[2..];
        let want = match kind {
            Kind::Var(_) => 0,
            Kind::Const | Kind::Unary(_) | Kind::Call(_) => 1,
            Kind::Binary(_) => 2,
        };
        if args.len() != want {
            let col = args.get(want).map_or(op_col, |a| a.0);
            let plural = if want == 1 { "" } else { "s" };
            return Err(err(
                col,
                format!("'{op}' takes {want} operand{plural}, found {}", args.len()),
            ));
        }
        let operand = |i: usize| -> Result<Expr, VmError> {
            let (col, name) = args[i];
            values
                .get(name)
                .cloned()
                .ok_or_else(|| err(col, format!("'{name}' is not defined on an earlier line")))
        };
        let e = match kind {
            Kind::Var(v) => Expr::Var(v),
            Kind::Const => {
                let (col, t) = args[0];
                match t.parse::<f64>() {
                    Ok(c) if c.is_finite() => Expr::Num(c),
                    _ => return Err(err(col, format!("'{t}' is not a finite number"))),
                }
            }
            Kind::Unary(f) => {
                let a = operand(0)?;
                bind(&mut bindings, f(a))
            }
            Kind::Call(f) => {
                let a = operand(0)?;
                bind(&mut bindings, Expr::Call(f, vec![a]))
            }
            Kind::Binary(f) => {
                let (a, b) = (operand(0)?, operand(1)?);
                bind(&mut bindings, f(a, b))
            }
        };
        values.insert(id, e.clone());
        last = Some(e);
    }
    let Some(out) = last else {
        return Err(VmError {
            line: 1,
            column: 1,
            message: "no instructions (each line is 'ID OPCODE OPERANDS...')".into(),
        });
    };
    Ok(Program {
        bindings,
        body: Expr::neg(out),
    })
}

/// Appends `e` as a binding and returns a reference to it.
fn bind(bindings: &mut Vec<Binding>, e: Expr) -> Expr {
    let i = bindings.len();
    bindings.push(Binding {
        name: format!("v{i}"),
        expr: e,
    });
    Expr::Ref(i)
}

/// Reads and compiles a `.vm` tape (negated, see the module docs).
pub fn parse(text: &str) -> Result<Tape, VmError> {
    let p = parse_program(text)?;
    formula::compile(&p).map_err(|e| VmError {
        line: 1,
        column: 1,
        message: format!("internal error: {e}"),
    })
}

/// The domain of a `.vm` model without a `domain:` header line: fidget's `[-1, 1]^3`.
pub const DEFAULT_DOMAIN: f64 = 1.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_shares_and_negates() {
        let t = parse(
            "# quarter circle\n y var-y\nx var-x # x\n\nx2 square x\ny2 square y\nr2 add x2 y2\nh const 0.5\nout sub r2 h\n",
        )
        .unwrap();
        // Ours: 0.5 - x^2 - y^2 (negated), >= 0 inside.
        assert_eq!(t.eval(0.0_f64, 0.0, 0.0), 0.5);
        assert_eq!(t.eval(1.0_f64, 0.0, 0.0), -0.5);
        // x, y, two squares, add, subc, neg.
        assert_eq!(t.len(), 7, "{t}");
    }

    #[test]
    fn errors_name_line_and_column() {
        let e = |s: &str| parse(s).unwrap_err().to_string();
        assert_eq!(
            e("_0 var-x\n_1 atan _0"),
            format!("2:4: fidget opcode 'atan' is not supported (supported: {SUPPORTED})")
        );
        assert!(e("_0 var-x\n_1 frob _0").starts_with("2:4: unknown opcode 'frob'"));
        assert_eq!(
            e("a var-x\nb add a c"),
            "2:9: 'c' is not defined on an earlier line"
        );
        assert_eq!(
            e("a var-x\nb add a"),
            "2:3: 'add' takes 2 operands, found 1"
        );
        assert_eq!(e("a var-x x"), "1:9: 'var-x' takes 0 operands, found 1");
        assert_eq!(e("a const 1e999"), "1:9: '1e999' is not a finite number");
        assert_eq!(e("  abc"), "1:6: expected an opcode after 'abc'");
        assert!(e("# nothing\n\n").starts_with("1:1: no instructions"));
        // A redefined identifier means its new value from then on.
        let t = parse("a var-x\na var-y\nb neg a").unwrap();
        assert_eq!(t.eval(1.0_f64, 2.0, 0.0), 2.0);
    }
}
