//! Lexer and recursive-descent parser. Every malformed input is an [`ParseError`] with
//! the position of the offending token; nesting is bounded so that no input can
//! overflow the stack (here, in compilation, printing or dropping the tree).
//!
//! Long input stays shallow: an operand that would put its node at [`MAX_TREE_DEPTH`]
//! (a flat sum or product of thousands of terms nests to the left) becomes a hidden
//! binding, and the tree refers to it, so a file of 100 000 terms parses, compiles and drops without
//! deep recursion, into the same tape (a binding is computed where it is written, in
//! the same order). Hidden bindings are named with a prefix that no name in the text
//! starts with (`_h0`, `_h1`, ... or `__h0`, ...), so the printed program parses back.
//!
//! Grammar (whitespace and `#` comments to end of line are ignored):
//! ```text
//! program  := (NAME '=' or ';')* or ';'? END
//! or       := and ('or' and)*
//! and      := cmp ('and' cmp)*
//! cmp      := union (('<' | '<=' | '>' | '>=' | '==' | '!=') union)*
//! union    := inter ('|' inter)*
//! inter    := sum (('&' | '\') sum)*
//! sum      := product (('+' | '-') product)*
//! product  := unary (('*' | '/') unary)*
//! unary    := '-' unary | power
//! power    := primary ('^' exponent)?
//! exponent := '-'? INTEGER ('^' exponent)? | '-'? REAL | '(' exponent ')'
//! primary  := NUMBER | 'pi' | NAME | NAME '(' or (',' or)* ')' | '(' or ')'
//! ```
//!
//! A `REAL` exponent is a number literal with a fraction or an exponent mark; one whose
//! value is an integer (`2.0`) is that integer.

use super::ast::{BinOp, Binding, Expr, Func, Program, Var};
use super::compile::folded_const;
use std::collections::HashMap;
use std::fmt;

/// A malformed formula: where and what.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseError {
    /// 0-based offset in characters (not bytes) into the formula.
    pub pos: usize,
    /// What was expected or what is wrong, without the position.
    pub message: String,
    /// 1-based line of `pos`.
    pub line: usize,
    /// 1-based column of `pos` within its line.
    pub column: usize,
}

impl ParseError {
    fn new(chars: &[char], pos: usize, message: impl Into<String>) -> Self {
        let pos = pos.min(chars.len());
        let before = &chars[..pos];
        let line = 1 + before.iter().filter(|&&c| c == '\n').count();
        let line_start = before.iter().rposition(|&c| c == '\n').map_or(0, |i| i + 1);
        ParseError {
            pos,
            message: message.into(),
            line,
            column: pos - line_start + 1,
        }
    }

    /// The error, the offending line of `src` and a caret under the position, e.g.
    /// ```text
    /// error at column 7: expected ')' but found end of input
    ///   (x + 1
    ///         ^
    /// ```
    pub fn render(&self, src: &str) -> String {
        let line = src
            .split('\n')
            .nth(self.line.saturating_sub(1))
            .unwrap_or("");
        let line = line.strip_suffix('\r').unwrap_or(line);
        // Copy tabs so the caret lines up however the terminal expands them.
        let pad: String = line
            .chars()
            .take(self.column.saturating_sub(1))
            .map(|c| if c == '\t' { '\t' } else { ' ' })
            .collect();
        format!("{self}\n  {line}\n  {pad}^")
    }
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 1 {
            write!(f, "error at column {}: {}", self.column, self.message)
        } else {
            write!(
                f,
                "error at line {}, column {}: {}",
                self.line, self.column, self.message
            )
        }
    }
}

impl std::error::Error for ParseError {}

/// What a number followed by a name, a number or `(` is told: `17x`, `20(x)`.
const PRODUCT_HINT: &str = "a product needs '*', as in 2*x";

/// Deepest nesting of parentheses, calls and unary minus signs accepted.
pub const MAX_NESTING: usize = 200;
/// Depth at which a subtree is no longer kept inline: its deep operand (long chains like
/// `x + x + ... + x` nest to the left) becomes a hidden binding (see the module docs),
/// so no tree is this deep.
pub const MAX_TREE_DEPTH: usize = 2000;
/// Largest exponent magnitude accepted after `^`.
pub const MAX_EXPONENT: i64 = 1024;

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    /// Value and whether the literal is a plain digit string (usable as an exponent).
    Num(f64, bool),
    Name(String),
    Sym(char),
    /// A comparison operator (`<`, `<=`, `>`, `>=`, `==`, `!=`).
    Cmp(BinOp),
    End,
}

#[derive(Clone, Debug)]
struct Token {
    tok: Tok,
    pos: usize,
    text: String,
}

fn describe(t: &Token) -> String {
    match &t.tok {
        Tok::End => "end of input".into(),
        Tok::Num(..) => format!("number '{}'", t.text),
        Tok::Name(n) => format!("name '{n}'"),
        Tok::Sym(c) => format!("'{c}'"),
        Tok::Cmp(op) => format!("'{}'", op.symbol()),
    }
}

fn lex(chars: &[char]) -> Result<Vec<Token>, ParseError> {
    let mut out = Vec::new();
    let mut i = 0;
    let n = chars.len();
    let is_word = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '.';
    while i < n {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if c == '#' {
            while i < n && chars[i] != '\n' {
                i += 1;
            }
        } else if c.is_ascii_digit() || (c == '.' && i + 1 < n && chars[i + 1].is_ascii_digit()) {
            let start = i;
            let digits = |i: &mut usize| {
                let s = *i;
                while *i < n && chars[*i].is_ascii_digit() {
                    *i += 1;
                }
                *i > s
            };
            digits(&mut i);
            let mut integer = true;
            if i < n && chars[i] == '.' {
                integer = false;
                i += 1;
                digits(&mut i);
            }
            if i < n && (chars[i] == 'e' || chars[i] == 'E') {
                integer = false;
                let e = i;
                i += 1;
                if i < n && (chars[i] == '+' || chars[i] == '-') {
                    i += 1;
                }
                if !digits(&mut i) {
                    let text: String = chars[start..i].iter().collect();
                    return Err(ParseError::new(
                        chars,
                        e,
                        format!("invalid number '{text}': expected digits after the exponent mark"),
                    ));
                }
            }
            if i < n && is_word(chars[i]) {
                let mut j = i;
                while j < n && is_word(chars[j]) {
                    j += 1;
                }
                let text: String = chars[start..j].iter().collect();
                return Err(ParseError::new(
                    chars,
                    start,
                    format!("invalid number '{text}' ({PRODUCT_HINT})"),
                ));
            }
            let text: String = chars[start..i].iter().collect();
            let v: f64 = match text.parse() {
                Ok(v) => v,
                Err(_) => {
                    return Err(ParseError::new(
                        chars,
                        start,
                        format!("invalid number '{text}'"),
                    ))
                }
            };
            if !v.is_finite() {
                return Err(ParseError::new(
                    chars,
                    start,
                    format!("number '{text}' is too large"),
                ));
            }
            out.push(Token {
                tok: Tok::Num(v, integer),
                pos: start,
                text,
            });
        } else if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < n && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let text: String = chars[start..i].iter().collect();
            out.push(Token {
                tok: Tok::Name(text.clone()),
                pos: start,
                text,
            });
        } else if let Some((op, len)) = comparison(chars, i) {
            out.push(Token {
                tok: Tok::Cmp(op),
                pos: i,
                text: op.symbol().to_string(),
            });
            i += len;
        } else if "+-*/^&|\\(),;=".contains(c) {
            out.push(Token {
                tok: Tok::Sym(c),
                pos: i,
                text: c.to_string(),
            });
            i += 1;
        } else {
            return Err(ParseError::new(
                chars,
                i,
                format!("unexpected character '{}'", c.escape_debug()),
            ));
        }
    }
    out.push(Token {
        tok: Tok::End,
        pos: n,
        text: String::new(),
    });
    Ok(out)
}

/// The comparison operator starting at `chars[i]`, and its length.
fn comparison(chars: &[char], i: usize) -> Option<(BinOp, usize)> {
    let next = chars.get(i + 1).copied();
    match (chars[i], next) {
        ('<', Some('=')) => Some((BinOp::Le, 2)),
        ('>', Some('=')) => Some((BinOp::Ge, 2)),
        ('=', Some('=')) => Some((BinOp::Eq, 2)),
        ('!', Some('=')) => Some((BinOp::Ne, 2)),
        ('<', _) => Some((BinOp::Lt, 1)),
        ('>', _) => Some((BinOp::Gt, 1)),
        _ => None,
    }
}

/// Words that are operators or constants, not names to bind.
const RESERVED: [&str; 3] = ["and", "or", "pi"];

/// An exponent after `^`: an integer (a power) or a real (`exp(c ln base)`).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Exponent {
    Int(i64),
    Real(f64),
}

struct Parser<'a> {
    chars: &'a [char],
    toks: Vec<Token>,
    i: usize,
    nesting: usize,
    names: Vec<String>,
    index: HashMap<String, usize>,
    /// The constant each binding folds to, if it does (see [`folded_const`]).
    consts: Vec<Option<f64>>,
    /// The bindings so far, the user's and the hidden ones, in order.
    bindings: Vec<Binding>,
    /// The prefix of hidden binding names, chosen at the first one.
    hidden_prefix: Option<String>,
}

/// A subtree and its depth.
type Node = (Expr, usize);

impl Parser<'_> {
    fn peek(&self) -> &Token {
        &self.toks[self.i.min(self.toks.len() - 1)]
    }
    fn peek_at(&self, k: usize) -> &Token {
        &self.toks[(self.i + k).min(self.toks.len() - 1)]
    }
    fn bump(&mut self) -> Token {
        let t = self.peek().clone();
        if self.i < self.toks.len() - 1 {
            self.i += 1;
        }
        t
    }
    fn is_sym(&self, c: char) -> bool {
        self.peek().tok == Tok::Sym(c)
    }
    fn err_at<T>(&self, pos: usize, msg: impl Into<String>) -> Result<T, ParseError> {
        Err(ParseError::new(self.chars, pos, msg))
    }
    fn expected<T>(&self, what: &str) -> Result<T, ParseError> {
        let t = self.peek();
        self.err_at(t.pos, format!("expected {what} but found {}", describe(t)))
    }
    /// [`Parser::expected`] where an operator could come next: an operand right after
    /// a complete one (`20(x)`, `x y`) is told that a product needs '*'.
    fn expected_operator<T>(&self, what: &str) -> Result<T, ParseError> {
        let t = self.peek();
        let hint = match t.tok {
            Tok::Sym('(') | Tok::Name(_) | Tok::Num(..) => format!(" ({PRODUCT_HINT})"),
            _ => String::new(),
        };
        self.err_at(
            t.pos,
            format!("expected {what} but found {}{hint}", describe(t)),
        )
    }
    fn enter(&mut self) -> Result<(), ParseError> {
        self.nesting += 1;
        if self.nesting > MAX_NESTING {
            let pos = self.peek().pos;
            return self.err_at(
                pos,
                format!("formula nested too deeply (more than {MAX_NESTING} levels)"),
            );
        }
        Ok(())
    }
    fn node(&self, e: Expr, depth: usize, pos: usize) -> Result<Node, ParseError> {
        if depth > MAX_TREE_DEPTH {
            // Operands are made shallow first (see `shallow`): not reached by the grammar.
            return self.err_at(
                pos,
                format!("formula too deep (syntax tree deeper than {MAX_TREE_DEPTH})"),
            );
        }
        Ok((e, depth))
    }

    /// `n`, or, when a node over it would reach [`MAX_TREE_DEPTH`], a reference to a new
    /// hidden binding of it (so a hidden binding's tree is shallower than the limit, and
    /// its printed text parses back without new ones).
    fn shallow(&mut self, n: Node) -> Node {
        let (e, d) = n;
        if d + 1 < MAX_TREE_DEPTH {
            return (e, d);
        }
        let prefix = self.hidden_prefix.get_or_insert_with(|| {
            let mut prefix = String::from("_h");
            while self
                .toks
                .iter()
                .any(|t| matches!(&t.tok, Tok::Name(n) if n.starts_with(prefix.as_str())))
            {
                prefix.insert(0, '_');
            }
            prefix
        });
        let name = format!("{prefix}{}", self.names.len());
        (Expr::Ref(self.bind(name, e)), 1)
    }

    /// The node `l op r`, its operands made shallow.
    fn join(&mut self, op: BinOp, l: Node, r: Node, pos: usize) -> Result<Node, ParseError> {
        let (l, ld) = self.shallow(l);
        let (r, rd) = self.shallow(r);
        self.node(Expr::bin(op, l, r), 1 + ld.max(rd), pos)
    }

    /// Appends the binding `name = expr` and returns its index.
    fn bind(&mut self, name: String, expr: Expr) -> usize {
        let i = self.names.len();
        self.index.insert(name.clone(), i);
        self.names.push(name.clone());
        self.consts.push(folded_const(&expr, &self.consts));
        self.bindings.push(Binding { name, expr });
        i
    }

    fn program(&mut self) -> Result<Program, ParseError> {
        if self.peek().tok == Tok::End {
            return self.err_at(0, "empty formula");
        }
        while let (Tok::Name(name), Tok::Sym('=')) = (&self.peek().tok, &self.peek_at(1).tok) {
            let name = name.clone();
            let pos = self.peek().pos;
            if ["x", "y", "z"].contains(&name.as_str()) {
                return self.err_at(pos, format!("cannot bind '{name}': it is a coordinate"));
            }
            if Func::from_name(&name).is_some() {
                return self.err_at(pos, format!("cannot bind '{name}': it is a function name"));
            }
            if RESERVED.contains(&name.as_str()) {
                return self.err_at(pos, format!("cannot bind '{name}': it is a reserved word"));
            }
            if self.index.contains_key(&name) {
                return self.err_at(pos, format!("'{name}' is already bound"));
            }
            self.bump();
            self.bump();
            let (expr, _) = self.or()?;
            if !self.is_sym(';') {
                return self.expected(&format!("';' after the binding of '{name}'"));
            }
            self.bump();
            self.bind(name, expr);
            if self.peek().tok == Tok::End {
                return self.expected("the final expression after the bindings");
            }
        }
        let (body, _) = self.or()?;
        if self.is_sym(';') {
            self.bump();
            if self.peek().tok != Tok::End {
                let pos = self.peek().pos;
                return self.err_at(
                    pos,
                    "only bindings 'name = expression;' may come before the final expression",
                );
            }
        }
        if self.peek().tok != Tok::End {
            return self.expected_operator("an operator or end of input");
        }
        Ok(Program {
            bindings: std::mem::take(&mut self.bindings),
            body,
        })
    }

    fn is_word(&self, w: &str) -> bool {
        matches!(&self.peek().tok, Tok::Name(n) if n == w)
    }

    fn or(&mut self) -> Result<Node, ParseError> {
        self.enter()?;
        let (mut e, mut d) = self.and()?;
        while self.is_word("or") {
            let pos = self.bump().pos;
            let (r, rd) = self.and()?;
            (e, d) = self.node(Expr::bin(BinOp::Or, e, r), 1 + d.max(rd), pos)?;
        }
        self.nesting -= 1;
        Ok((e, d))
    }

    fn and(&mut self) -> Result<Node, ParseError> {
        let (mut e, mut d) = self.cmp()?;
        while self.is_word("and") {
            let pos = self.bump().pos;
            let (r, rd) = self.cmp()?;
            (e, d) = self.node(Expr::bin(BinOp::And, e, r), 1 + d.max(rd), pos)?;
        }
        Ok((e, d))
    }

    fn cmp(&mut self) -> Result<Node, ParseError> {
        let (mut e, mut d) = self.union()?;
        while let Tok::Cmp(op) = self.peek().tok {
            let pos = self.bump().pos;
            let (r, rd) = self.union()?;
            (e, d) = self.node(Expr::bin(op, e, r), 1 + d.max(rd), pos)?;
        }
        Ok((e, d))
    }

    fn union(&mut self) -> Result<Node, ParseError> {
        let (mut e, mut d) = self.inter()?;
        while self.is_sym('|') {
            let pos = self.bump().pos;
            let r = self.inter()?;
            (e, d) = self.join(BinOp::Union, (e, d), r, pos)?;
        }
        Ok((e, d))
    }

    fn inter(&mut self) -> Result<Node, ParseError> {
        let (mut e, mut d) = self.sum()?;
        loop {
            let op = match self.peek().tok {
                Tok::Sym('&') => BinOp::Intersect,
                Tok::Sym('\\') => BinOp::Subtract,
                _ => return Ok((e, d)),
            };
            let pos = self.bump().pos;
            let r = self.sum()?;
            (e, d) = self.join(op, (e, d), r, pos)?;
        }
    }

    fn sum(&mut self) -> Result<Node, ParseError> {
        let (mut e, mut d) = self.product()?;
        loop {
            let op = match self.peek().tok {
                Tok::Sym('+') => BinOp::Add,
                Tok::Sym('-') => BinOp::Sub,
                _ => return Ok((e, d)),
            };
            let pos = self.bump().pos;
            let r = self.product()?;
            (e, d) = self.join(op, (e, d), r, pos)?;
        }
    }

    fn product(&mut self) -> Result<Node, ParseError> {
        let (mut e, mut d) = self.unary()?;
        loop {
            let op = match self.peek().tok {
                Tok::Sym('*') => BinOp::Mul,
                Tok::Sym('/') => BinOp::Div,
                _ => return Ok((e, d)),
            };
            let pos = self.bump().pos;
            let (r, rd) = self.unary()?;
            // A constant divisor 0 makes the formula infinite or NaN everywhere: its
            // ranges are the whole line and every ray would report a root.
            if op == BinOp::Div && folded_const(&r, &self.consts) == Some(0.0) {
                return self.err_at(
                    pos,
                    "division by zero: the divisor is the constant 0 (after folding)",
                );
            }
            (e, d) = self.join(op, (e, d), (r, rd), pos)?;
        }
    }

    fn unary(&mut self) -> Result<Node, ParseError> {
        if self.is_sym('-') {
            let pos = self.bump().pos;
            self.enter()?;
            let a = self.unary()?;
            self.nesting -= 1;
            let (e, d) = self.shallow(a);
            return self.node(Expr::neg(e), d + 1, pos);
        }
        self.power()
    }

    fn power(&mut self) -> Result<Node, ParseError> {
        let (e, d) = self.primary()?;
        if self.is_sym('^') {
            let (e, d) = self.shallow((e, d));
            let pos = self.bump().pos;
            let n = self.exponent(0)?;
            let e = match n {
                Exponent::Int(n) => Expr::pow(e, n as i32),
                Exponent::Real(c) => Expr::PowF(Box::new(e), c),
            };
            return self.node(e, d + 1, pos);
        }
        Ok((e, d))
    }

    /// An exponent, evaluated now; `2^3^2 = 2^9`.
    fn exponent(&mut self, depth: usize) -> Result<Exponent, ParseError> {
        if depth > MAX_NESTING {
            let pos = self.peek().pos;
            return self.err_at(pos, "exponent nested too deeply");
        }
        if self.is_sym('(') {
            let open = self.bump().pos;
            let n = self.exponent(depth + 1)?;
            if !self.is_sym(')') {
                let t = self.peek();
                return self.err_at(
                    t.pos,
                    format!(
                        "expected ')' to close the '(' at column {} but found {}",
                        ParseError::new(self.chars, open, "").column,
                        describe(t)
                    ),
                );
            }
            self.bump();
            return match n {
                Exponent::Int(n) => self.check_exponent(n, open),
                real => Ok(real),
            };
        }
        let start = self.peek().pos;
        let negative = self.is_sym('-');
        if negative {
            self.bump();
        }
        let t = self.peek().clone();
        let base = match t.tok {
            Tok::Num(_, true) => match t.text.parse::<i64>() {
                Ok(v) if v <= MAX_EXPONENT => v,
                _ => {
                    return self.err_at(
                        t.pos,
                        format!("exponent {} is too large (at most {MAX_EXPONENT})", t.text),
                    )
                }
            },
            Tok::Num(v, false) => {
                self.bump();
                if self.is_sym('^') {
                    let pos = self.peek().pos;
                    return self.err_at(
                        pos,
                        "a real exponent cannot be raised to a power (use parentheses around the base)",
                    );
                }
                let v = if negative { -v } else { v };
                if v.fract() == 0.0 && v.abs() <= MAX_EXPONENT as f64 {
                    return Ok(Exponent::Int(v as i64));
                }
                if v.fract() == 0.0 {
                    return self.err_at(
                        t.pos,
                        format!("exponent {} is too large (at most {MAX_EXPONENT})", t.text),
                    );
                }
                return Ok(Exponent::Real(v));
            }
            _ => return self.expected("an exponent after '^'"),
        };
        self.bump();
        let mut n = base;
        if self.is_sym('^') {
            let pos = self.bump().pos;
            let e = match self.exponent(depth + 1)? {
                Exponent::Int(e) => e,
                Exponent::Real(_) => {
                    return self.err_at(
                        pos,
                        "an integer cannot be raised to a real exponent inside an exponent",
                    )
                }
            };
            n = int_pow(base, e).ok_or_else(|| {
                ParseError::new(
                    self.chars,
                    pos,
                    format!(
                        "exponent {base}^{e} is not an integer of magnitude at most {MAX_EXPONENT}"
                    ),
                )
            })?;
        }
        self.check_exponent(if negative { -n } else { n }, start)
    }

    fn check_exponent(&self, n: i64, pos: usize) -> Result<Exponent, ParseError> {
        if n.abs() > MAX_EXPONENT {
            return self.err_at(
                pos,
                format!("exponent {n} is too large (at most {MAX_EXPONENT})"),
            );
        }
        Ok(Exponent::Int(n))
    }

    fn primary(&mut self) -> Result<Node, ParseError> {
        let t = self.peek().clone();
        match t.tok {
            Tok::Num(v, _) => {
                self.bump();
                Ok((Expr::Num(v), 1))
            }
            Tok::Sym('(') => {
                self.bump();
                let (e, d) = self.or()?;
                if !self.is_sym(')') {
                    let col = ParseError::new(self.chars, t.pos, "").column;
                    return self
                        .expected_operator(&format!("')' to close the '(' at column {col}"));
                }
                self.bump();
                Ok((e, d))
            }
            Tok::Name(name) => {
                self.bump();
                let call = self.is_sym('(');
                if let Some(f) = Func::from_name(&name) {
                    if !call {
                        return self.expected(&format!("'(' after the function name '{name}'"));
                    }
                    return self.call(f, t.pos);
                }
                if call {
                    let what = if ["x", "y", "z"].contains(&name.as_str())
                        || self.index.contains_key(&name)
                    {
                        format!("'{name}' is not a function")
                    } else {
                        let known: Vec<&str> = Func::ALL.iter().map(|f| f.name()).collect();
                        format!("unknown function '{name}' (known: {})", known.join(" "))
                    };
                    return self.err_at(t.pos, what);
                }
                let e = match name.as_str() {
                    "pi" => Expr::Num(std::f64::consts::PI),
                    "and" | "or" => {
                        return self.err_at(
                            t.pos,
                            format!("expected an operand before '{name}'"),
                        )
                    }
                    "x" => Expr::Var(Var::X),
                    "y" => Expr::Var(Var::Y),
                    "z" => Expr::Var(Var::Z),
                    _ => match self.index.get(&name) {
                        Some(&i) => Expr::Ref(i),
                        None => {
                            return self.err_at(
                                t.pos,
                                format!(
                                    "unknown variable '{name}' (use x, y, z or a name bound earlier with '{name} = ...;')"
                                ),
                            )
                        }
                    },
                };
                Ok((e, 1))
            }
            _ => self.expected("a number, a variable, a function or '('"),
        }
    }

    fn call(&mut self, f: Func, pos: usize) -> Result<Node, ParseError> {
        let open = self.bump().pos;
        let mut args = Vec::new();
        let mut depth = 0;
        if !self.is_sym(')') {
            loop {
                let a = self.or()?;
                let (a, d) = self.shallow(a);
                args.push(a);
                depth = depth.max(d);
                if self.is_sym(',') {
                    self.bump();
                } else {
                    break;
                }
            }
        }
        if !self.is_sym(')') {
            let col = ParseError::new(self.chars, open, "").column;
            return self.expected_operator(&format!("',' or ')' to close the '(' at column {col}"));
        }
        self.bump();
        if args.len() != f.arity() {
            let plural = if f.arity() == 1 { "" } else { "s" };
            return self.err_at(
                pos,
                format!(
                    "{} takes {} argument{plural} but was given {}",
                    f.name(),
                    f.arity(),
                    args.len()
                ),
            );
        }
        // ln of a constant <= 0 is -inf or NaN everywhere (see the division above).
        if f == Func::Ln {
            if let Some(c) = args.first().and_then(|a| folded_const(a, &self.consts)) {
                if c <= 0.0 {
                    return self.err_at(
                        pos,
                        format!("ln of the constant {c:?}: ln needs a positive argument"),
                    );
                }
            }
        }
        self.node(Expr::Call(f, args), depth + 1, pos)
    }
}

/// `base^e` as an integer of magnitude at most [`MAX_EXPONENT`], if it is one.
fn int_pow(base: i64, e: i64) -> Option<i64> {
    if e < 0 {
        // Only 1 and -1 have integer reciprocal powers.
        return match base {
            1 => Some(1),
            -1 => Some(if e % 2 == 0 { 1 } else { -1 }),
            _ => None,
        };
    }
    let mut acc: i64 = 1;
    for _ in 0..e {
        acc = acc.checked_mul(base)?;
        if acc.abs() > MAX_EXPONENT {
            return None;
        }
        if acc == 0 || acc == 1 {
            // 0 and 1 are fixed points: stop early on huge exponents.
            break;
        }
    }
    if base == -1 {
        acc = if e % 2 == 0 { 1 } else { -1 };
    }
    Some(acc)
}

/// Parses a formula into its syntax tree.
pub fn parse_program(src: &str) -> Result<Program, ParseError> {
    let chars: Vec<char> = src.chars().collect();
    let toks = lex(&chars)?;
    let mut p = Parser {
        chars: &chars,
        toks,
        i: 0,
        nesting: 0,
        names: Vec::new(),
        index: HashMap::new(),
        consts: Vec::new(),
        bindings: Vec::new(),
        hidden_prefix: None,
    };
    p.program()
}
