//! Formulas from text: `tracer render --expr "FORMULA"`.
//!
//! A formula over `x, y, z` is parsed ([`parse`]) into a [`Tape`] of the model IR
//! (`model-ir`), a flat list of instructions that evaluates at points (`f64`) and over every [`arith_core::Range`],
//! like the hand-written models (it implements [`Shape`]).
//!
//! The language is [`SYNTAX`] (also printed by `tracer render --help`).
//!
//! Decimal literals round to the nearest `f64`, exactly like the same literal in Rust
//! source, so a formula and a hand-written model denote the same function. Constant
//! subexpressions are folded only where the `f64` result is exact, so range evaluation
//! of the tape encloses the formula's real value (see [`Tape`]).
//!
//! API: [`parse`] (text to tape), or [`parse_program`] (text to [`Program`], which
//! prints back as text) then [`compile`]. Errors: [`ParseError`] with a 0-based
//! character `pos`, 1-based `line`/`column`, `Display` (`error at column 7: ...`) and
//! [`ParseError::render`] (the line with a caret under the position). A tape prints as
//! an instruction listing (`Display`) or back as a formula ([`ToFormula::to_formula`]).
//!
//! ```
//! use model_sources::formula::parse;
//! let t = parse("s = 1 - x^2 - y^2 - z^2; s & -z").unwrap();
//! assert!(t.eval(0.0_f64, 0.0, -0.5) > 0.0);
//! let e = parse("(x + 1").unwrap_err();
//! assert_eq!(e.to_string(), "error at column 7: expected ')' to close the '(' at column 1 but found end of input");
//! ```

mod ast;
mod compile;
mod parse;

pub use ast::{BinOp, Binding, Expr, Func, Program, Var};
pub(crate) use compile::folded_const;
pub use compile::{compile, CompileError, ToFormula};
/// The model IR this reader compiles into (`model-ir`), re-exported.
pub use model_ir::{Instr, Op, Tape, CACHE_LIMIT, EPS, MIN_SPECIALISE_LEN};
pub use parse::{parse_program, ParseError, MAX_EXPONENT, MAX_NESTING, MAX_TREE_DEPTH};

/// The text of [`SYNTAX`], also the item's rustdoc.
macro_rules! syntax_text {
    () => {
        r#"Formula language (f >= 0 inside, f < 0 outside):
  numbers      2  0.36  .5  1e-3  2.5E+2, and pi (the f64 nearest to pi)
  variables    x  y  z
  arithmetic   + - * / and unary -; a product needs '*': 2*x, 2*(x+1)
  powers       x^2, x^-2: integer exponents, right-associative (2^3^2 = 2^9) and
               tighter than unary minus (-x^2 = -(x^2)); x^2.5, x^-0.5: a real
               exponent c is exp(c*ln(x)), so 0 (c > 0) or +inf (c < 0) where x <= 0
  functions    sqrt sqr exp ln sin cos tan abs not (one argument), min max (two),
               if(c, a, b): a where c holds, else b
  R-functions  a & b (intersection), a \ b (subtraction), a | b (union): looser than
               arithmetic, & and \ tighter than |, all left-associative:
               a | b & c = a | (b & c), a \ b & c = (a \ b) & c
  blends       blend_union(a, b), blend_intersect(a, b): the revised-affine paper's
               a + b +- sqrt(a^2 + b^2 + 0.5/(1 + a^2 + b^2)); HyperFun's
               hf_blend_union(a, b, a0, a1, a2) = (a | b) + a0/(1 + (a/a1)^2 + (b/a2)^2)
               and hf_blend_intersect(a, b, a0, a1, a2), the same with a & b
  comparisons  a < b, <=, >, >=, == and != give 1 or 0 (== and != within 1e-6), looser
               than |; then a and b, then a or b. A value v holds where |v| >= 1e-6:
               if(x < 0 and y < 0, x + y, x*y)
  bindings     name = expr; before the final expression, each usable by later ones:
               b = 0.36 - x^2; s = 0.7 - x^2 - y^2; b | s
  comments     # to the end of the line; whitespace and newlines are ignored
  refused      a division by a constant 0 (1/0, x/(1-1)) and ln of a constant <= 0:
               such a formula is infinite or NaN everywhere
"#
    };
}

/// The formula language in brief: what `tracer render --help` (and `range`, `preview`)
/// print after the options, and the README's "Formula language".
#[doc = ""]
#[doc = concat!("```text\n", syntax_text!(), "```")]
pub const SYNTAX: &str = syntax_text!();

/// Parses and compiles a formula.
pub fn parse(src: &str) -> Result<Tape, ParseError> {
    let program = parse_program(src)?;
    // The parser only builds trees the compiler accepts; should that ever fail, report
    // it as an error at the start rather than panic.
    compile(&program).map_err(|e| ParseError {
        pos: 0,
        message: format!("internal error: {e}"),
        line: 1,
        column: 1,
    })
}
