//! HyperFun programs (`.hf`): a subset of the HyperFun language, compiled onto the
//! formula tape ([`crate::formula::Tape`]), so a HyperFun model renders in every
//! arithmetic like any other model.
//!
//! The language follows its reference implementation, the HyperFun interpreter and
//! library (`interpreter_lib`, `hflibrary_lib`): a program is one or more bodies
//! `name(x[3], a[1]) { ... name = expr; }`; local variables and `array` declarations;
//! `x[1]..x[3]` the coordinates, `a[..]` the parameters (0 unless given); arithmetic,
//! `^`, the set operators with HyperFun's R-functions (`|` union, `&` and `@`
//! intersection, `\` subtraction, `~` negation), `if`/`then`/`else`/`endif`,
//! `while`/`loop`/`endloop`, comparisons and `and`/`or`/`not`; the built-in functions
//! and the library primitives the models use ([`lib::LIBRARY`]). The object rendered is
//! the body named `my_model`, else the first one (as `hfp -o` defaults), or the one
//! [`HfOptions::object`] names. See [`parse`] for the grammar and [`compile`] for how
//! control flow becomes a tape that is sound over every range arithmetic.
//!
//! What HyperFun reports as run-time errors (a division by a value near 0, `sqrt` or
//! `log` of a negative value, a real power of a negative base) is not reproduced: the
//! tape uses the extended real functions of [`arith_core::Real`] instead.
//!
//! ```
//! let src = "my_model(x[3], a[1]) {
//!     array c[3];
//!     c = [0, 0, 0];
//!     my_model = hfSphere(x, c, 1) \\ hfBlock(x, c, 2, 2, 2);
//! }";
//! let t = model_sources::hyperfun::parse_hyperfun(src).unwrap();
//! assert!(t.eval(-0.5_f64, -0.5, -0.5) > 0.0 && t.eval(0.5_f64, 0.5, 0.5) < 0.0);
//! let e = model_sources::hyperfun::parse_hyperfun("m(x[3], a[1]) { m = hfFoo(x); }").unwrap_err();
//! assert_eq!((e.line, e.column), (1, 21));
//! ```

pub mod compile;
pub mod lex;
pub mod lib;
pub mod parse;

use crate::formula::Tape;
use std::fmt;

/// A HyperFun program that cannot be compiled: where (1-based line and column, in
/// characters) and what.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct HfError {
    /// 1-based line.
    pub line: usize,
    /// 1-based column within the line.
    pub column: usize,
    /// What is wrong, without the position.
    pub message: String,
}

impl HfError {
    pub(crate) fn new(line: usize, column: usize, message: impl Into<String>) -> Self {
        HfError {
            line,
            column,
            message: message.into(),
        }
    }
}

impl fmt::Display for HfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "error at line {}, column {}: {}",
            self.line, self.column, self.message
        )
    }
}

impl std::error::Error for HfError {}

/// Which object of a program to compile, and its parameters.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HfOptions {
    /// The body to compile; `None`: `my_model` if there is one, else the first body.
    pub object: Option<String>,
    /// The parameter array `a` (missing entries are 0, as `hfp -a` defaults).
    pub params: Vec<f64>,
}

/// Default domain half-side of a HyperFun model: `[-10, 10]^3`, the `hfp` polygonizer's
/// default box.
pub const DEFAULT_DOMAIN: f64 = 10.0;

/// Compiles the HyperFun program `text` (its `my_model`, else its first body) to a tape.
pub fn parse_hyperfun(text: &str) -> Result<Tape, HfError> {
    parse_hyperfun_with(text, &HfOptions::default())
}

/// [`parse_hyperfun`] with a choice of object and parameters.
pub fn parse_hyperfun_with(text: &str, opts: &HfOptions) -> Result<Tape, HfError> {
    let toks = lex::lex(text)?;
    let bodies = parse::parse(toks)?;
    let k = match &opts.object {
        Some(name) => {
            let lower = name.to_ascii_lowercase();
            match bodies.iter().position(|b| b.name == lower) {
                Some(k) => k,
                None => {
                    let names: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
                    return Err(HfError::new(
                        1,
                        1,
                        format!(
                            "no object named '{name}' (the program defines: {})",
                            names.join(", ")
                        ),
                    ));
                }
            }
        }
        None => bodies
            .iter()
            .position(|b| b.name == "my_model")
            .unwrap_or(0),
    };
    let program = compile::Compiler::new(&bodies).model(k, &opts.params)?;
    let p = bodies[k].pos;
    crate::formula::compile(&program)
        .map_err(|e| HfError::new(p.line, p.col, format!("internal error: {e}")))
}
