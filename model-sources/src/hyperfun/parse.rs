//! The HyperFun parser: a program (one or more bodies) to its syntax tree, with the
//! grammar and operator precedence of the reference interpreter (`int_parse_N.c`):
//!
//! ```text
//! program   := body+
//! body      := NAME '(' NAME '[' NUM ']' ',' NAME '[' NUM ']' (',' NAME '[' NUM ']')? ')'
//!              '{' ('array' NAME '[' NUM ']' (',' NAME '[' NUM ']')* ';')*
//!              statement* NAME '=' expr ';' '}'          -- the body's own name, last
//! statement := 'if' cond 'then' statement* ('else' statement*)? 'endif' ';'
//!            | 'while' cond 'loop' statement* 'endloop' ';'
//!            | NAME '[' expr ']' '=' expr ';'
//!            | NAME '=' '[' expr (',' expr)* ']' ';'
//!            | NAME '=' expr ';'
//! cond      := compare (('and' | 'or') compare)*          -- one level, left to right
//! compare   := boolatom (('<' | '>' | '<=' | '>=' | '=' | '/=') boolatom)*
//! boolatom  := 'not' boolatom | expr
//! expr      := term (('+' | '-' | '&' | '|' | '\' | '@') term)*   -- one level
//! term      := factor (('*' | '/') factor)*
//! factor    := unary ('^' unary)*                          -- left to right
//! unary     := ('-' | '+' | '~') unary | NUM | '(' cond ')' | NAME | NAME '[' expr ']'
//!            | NAME '(' (arg (',' arg)*)? ')'
//! ```
//!
//! So `-x^2 = (-x)^2`, `2^3^2 = (2^3)^2` and `a + b & c = (a + b) & c`, as in HyperFun.
//! Two extensions: a parenthesised condition is a value (0 or 1) anywhere, and the
//! entries of `name = [...]` may be expressions, not only numbers.

use super::lex::{describe, Tok, Token};
use super::HfError;

/// Deepest nesting of expressions and statements accepted.
pub const MAX_DEPTH: usize = 200;

/// Where a piece of syntax starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Pos {
    pub line: usize,
    pub col: usize,
}

/// A binary operator of HyperFun.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum HBin {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Inter,
    Union,
    Subtract,
    Lt,
    Gt,
    Le,
    Ge,
    Eq,
    Ne,
    And,
    Or,
}

/// An expression.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum HExpr {
    Num(f64),
    Str(String, Pos),
    Name(String, Pos),
    Index(String, Box<HExpr>, Pos),
    Call(String, Vec<HExpr>, Pos),
    Neg(Box<HExpr>),
    Not(Box<HExpr>),
    /// Operator, operands, position and the depth of the tree it roots.
    Bin(HBin, Box<HExpr>, Box<HExpr>, Pos, usize),
}

impl HExpr {
    /// Depth of the tree (cheap: chains of operators store theirs, and other nesting is
    /// bounded by [`MAX_DEPTH`]).
    pub(crate) fn depth(&self) -> usize {
        match self {
            HExpr::Num(_) | HExpr::Str(..) | HExpr::Name(..) => 1,
            HExpr::Index(_, i, _) => 1 + i.depth(),
            HExpr::Call(_, args, _) => 1 + args.iter().map(HExpr::depth).max().unwrap_or(0),
            HExpr::Neg(a) | HExpr::Not(a) => 1 + a.depth(),
            HExpr::Bin(.., d) => *d,
        }
    }
}

/// Deepest expression tree accepted (long chains like `a + a + ... + a` nest to the left).
pub const MAX_TREE_DEPTH: usize = 2000;

/// A statement.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Stmt {
    Assign(String, Pos, HExpr),
    AssignItem(String, Pos, HExpr, HExpr),
    AssignArray(String, Pos, Vec<HExpr>),
    If(HExpr, Vec<Stmt>, Vec<Stmt>, Pos),
    While(HExpr, Vec<Stmt>, Pos),
}

/// An array parameter or declaration: name, size, position.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ArrayDecl {
    pub name: String,
    pub size: usize,
    pub pos: Pos,
}

/// One body (object) of a program.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Body {
    pub name: String,
    pub pos: Pos,
    /// The coordinate, parameter and (optional) attribute arrays.
    pub params: Vec<ArrayDecl>,
    pub arrays: Vec<ArrayDecl>,
    pub stmts: Vec<Stmt>,
    pub result: HExpr,
}

struct Parser {
    toks: Vec<Token>,
    i: usize,
    depth: usize,
}

type Res<T> = Result<T, HfError>;

impl Parser {
    fn peek(&self) -> &Token {
        &self.toks[self.i.min(self.toks.len() - 1)]
    }
    fn pos(&self) -> Pos {
        let t = self.peek();
        Pos {
            line: t.line,
            col: t.col,
        }
    }
    fn bump(&mut self) -> Token {
        let t = self.peek().clone();
        if self.i < self.toks.len() - 1 {
            self.i += 1;
        }
        t
    }
    fn is(&self, s: &str) -> bool {
        matches!(self.peek().tok, Tok::Sym(t) if t == s)
    }
    fn is_key(&self, k: &str) -> bool {
        matches!(self.peek().tok, Tok::Key(t) if t == k)
    }
    fn fail<T>(&self, what: &str) -> Res<T> {
        let t = self.peek();
        Err(HfError::new(
            t.line,
            t.col,
            format!("expected {what} but found {}", describe(&t.tok)),
        ))
    }
    fn expect(&mut self, s: &str) -> Res<()> {
        if self.is(s) {
            self.bump();
            Ok(())
        } else {
            self.fail(&format!("'{s}'"))
        }
    }
    fn expect_key(&mut self, k: &str) -> Res<()> {
        if self.is_key(k) {
            self.bump();
            Ok(())
        } else {
            self.fail(&format!("'{k}'"))
        }
    }
    fn name(&mut self, what: &str) -> Res<(String, Pos)> {
        let p = self.pos();
        match self.peek().tok.clone() {
            Tok::Name(n) => {
                self.bump();
                Ok((n, p))
            }
            _ => self.fail(what),
        }
    }
    fn enter(&mut self) -> Res<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            let p = self.pos();
            return Err(HfError::new(
                p.line,
                p.col,
                format!("program nested too deeply (more than {MAX_DEPTH} levels)"),
            ));
        }
        Ok(())
    }
    fn leave(&mut self) {
        self.depth -= 1;
    }
    fn bin(&self, op: HBin, l: HExpr, r: HExpr, p: Pos) -> Res<HExpr> {
        let d = 1 + l.depth().max(r.depth());
        if d > MAX_TREE_DEPTH {
            return Err(HfError::new(
                p.line,
                p.col,
                format!("expression too long or deep (syntax tree deeper than {MAX_TREE_DEPTH})"),
            ));
        }
        Ok(HExpr::Bin(op, Box::new(l), Box::new(r), p, d))
    }

    /// `NAME '[' NUM ']'`.
    fn array_decl(&mut self) -> Res<ArrayDecl> {
        let (name, pos) = self.name("an array name")?;
        self.expect("[")?;
        let p = self.pos();
        let size = match self.peek().tok {
            Tok::Num(v) => v,
            _ => return self.fail("the array size (a number)"),
        };
        self.bump();
        // The reference rounds the size to the nearest integer.
        let size = size.round();
        if !(1.0..=1e6).contains(&size) {
            return Err(HfError::new(
                p.line,
                p.col,
                "the array size must be between 1 and 1000000".to_string(),
            ));
        }
        self.expect("]")?;
        Ok(ArrayDecl {
            name,
            size: size as usize,
            pos,
        })
    }

    fn body(&mut self) -> Res<Body> {
        let (name, pos) = self.name("a body name, as in my_model(x[3], a[1]) { ... }")?;
        self.expect("(")?;
        let mut params = vec![self.array_decl()?];
        self.expect(",")?;
        params.push(self.array_decl()?);
        if self.is(",") {
            self.bump();
            params.push(self.array_decl()?);
        }
        self.expect(")")?;
        self.expect("{")?;
        let mut arrays = Vec::new();
        while self.is_key("array") {
            self.bump();
            arrays.push(self.array_decl()?);
            while self.is(",") {
                self.bump();
                arrays.push(self.array_decl()?);
            }
            self.expect(";")?;
        }
        let mut stmts = Vec::new();
        loop {
            if let Tok::Name(n) = &self.peek().tok {
                if *n == name
                    && matches!(self.toks.get(self.i + 1), Some(t) if t.tok == Tok::Sym("="))
                {
                    break;
                }
            }
            match self.statement()? {
                Some(s) => stmts.push(s),
                None => {
                    return self.fail(&format!(
                        "a statement or the result '{name} = ...;' of the body"
                    ))
                }
            }
        }
        self.bump();
        self.bump();
        let result = self.expr()?;
        self.expect(";")?;
        if !self.is("}") {
            return self.fail(&format!("'}}' after the result '{name} = ...;'"));
        }
        self.bump();
        Ok(Body {
            name,
            pos,
            params,
            arrays,
            stmts,
            result,
        })
    }

    /// Statements up to one of the `stop` keywords.
    fn block(&mut self, stop: &[&str]) -> Res<Vec<Stmt>> {
        let mut out = Vec::new();
        while !stop.iter().any(|k| self.is_key(k)) {
            match self.statement()? {
                Some(s) => out.push(s),
                None => {
                    let want: Vec<String> = stop.iter().map(|k| format!("'{k}'")).collect();
                    return self.fail(&format!("a statement or {}", want.join(" or ")));
                }
            }
        }
        Ok(out)
    }

    /// One statement, `None` where none starts here.
    fn statement(&mut self) -> Res<Option<Stmt>> {
        let p = self.pos();
        if self.is_key("if") {
            self.bump();
            self.enter()?;
            let c = self.cond()?;
            self.expect_key("then")?;
            let then = self.block(&["else", "endif"])?;
            let other = if self.is_key("else") {
                self.bump();
                self.block(&["endif"])?
            } else {
                Vec::new()
            };
            self.expect_key("endif")?;
            self.expect(";")?;
            self.leave();
            return Ok(Some(Stmt::If(c, then, other, p)));
        }
        if self.is_key("while") {
            self.bump();
            self.enter()?;
            let c = self.cond()?;
            self.expect_key("loop")?;
            let body = self.block(&["endloop"])?;
            self.expect_key("endloop")?;
            self.expect(";")?;
            self.leave();
            return Ok(Some(Stmt::While(c, body, p)));
        }
        let Tok::Name(name) = self.peek().tok.clone() else {
            return Ok(None);
        };
        self.bump();
        let s = if self.is("[") {
            self.bump();
            let idx = self.expr()?;
            self.expect("]")?;
            self.expect("=")?;
            let v = self.expr()?;
            Stmt::AssignItem(name, p, idx, v)
        } else {
            self.expect("=")?;
            if self.is("[") {
                self.bump();
                let mut items = vec![self.expr()?];
                while self.is(",") {
                    self.bump();
                    items.push(self.expr()?);
                }
                self.expect("]")?;
                Stmt::AssignArray(name, p, items)
            } else {
                Stmt::Assign(name, p, self.expr()?)
            }
        };
        self.expect(";")?;
        Ok(Some(s))
    }

    fn cond(&mut self) -> Res<HExpr> {
        self.enter()?;
        let mut e = self.compare()?;
        loop {
            let op = if self.is_key("and") {
                HBin::And
            } else if self.is_key("or") {
                HBin::Or
            } else {
                break;
            };
            let p = self.pos();
            self.bump();
            let r = self.compare()?;
            e = self.bin(op, e, r, p)?;
        }
        self.leave();
        Ok(e)
    }

    fn compare(&mut self) -> Res<HExpr> {
        let mut e = self.boolatom()?;
        loop {
            let op = match self.peek().tok {
                Tok::Sym("<") => HBin::Lt,
                Tok::Sym(">") => HBin::Gt,
                Tok::Sym("<=") => HBin::Le,
                Tok::Sym(">=") => HBin::Ge,
                Tok::Sym("=") => HBin::Eq,
                Tok::Sym("/=") => HBin::Ne,
                _ => return Ok(e),
            };
            let p = self.pos();
            self.bump();
            let r = self.boolatom()?;
            e = self.bin(op, e, r, p)?;
        }
    }

    fn boolatom(&mut self) -> Res<HExpr> {
        if self.is_key("not") {
            self.bump();
            self.enter()?;
            let e = self.boolatom()?;
            self.leave();
            return Ok(HExpr::Not(Box::new(e)));
        }
        self.expr()
    }

    fn expr(&mut self) -> Res<HExpr> {
        self.enter()?;
        let mut e = self.term()?;
        loop {
            let op = match self.peek().tok {
                Tok::Sym("+") => HBin::Add,
                Tok::Sym("-") => HBin::Sub,
                Tok::Sym("&") | Tok::Sym("@") => HBin::Inter,
                Tok::Sym("|") => HBin::Union,
                Tok::Sym("\\") => HBin::Subtract,
                _ => break,
            };
            let p = self.pos();
            self.bump();
            let r = self.term()?;
            e = self.bin(op, e, r, p)?;
        }
        self.leave();
        Ok(e)
    }

    fn term(&mut self) -> Res<HExpr> {
        let mut e = self.factor()?;
        loop {
            let op = match self.peek().tok {
                Tok::Sym("*") => HBin::Mul,
                Tok::Sym("/") => HBin::Div,
                _ => return Ok(e),
            };
            let p = self.pos();
            self.bump();
            let r = self.factor()?;
            e = self.bin(op, e, r, p)?;
        }
    }

    fn factor(&mut self) -> Res<HExpr> {
        let mut e = self.unary()?;
        while self.is("^") {
            let p = self.pos();
            self.bump();
            let r = self.unary()?;
            e = self.bin(HBin::Pow, e, r, p)?;
        }
        Ok(e)
    }

    fn unary(&mut self) -> Res<HExpr> {
        let p = self.pos();
        match self.peek().tok.clone() {
            Tok::Sym("-") | Tok::Sym("~") => {
                self.bump();
                self.enter()?;
                let e = self.unary()?;
                self.leave();
                Ok(HExpr::Neg(Box::new(e)))
            }
            Tok::Sym("+") => {
                self.bump();
                self.enter()?;
                let e = self.unary();
                self.leave();
                e
            }
            Tok::Num(v) => {
                self.bump();
                Ok(HExpr::Num(v))
            }
            Tok::Str(s) => {
                self.bump();
                Ok(HExpr::Str(s, p))
            }
            Tok::Sym("(") => {
                self.bump();
                let e = self.cond()?;
                self.expect(")")?;
                Ok(e)
            }
            Tok::Name(n) => {
                self.bump();
                if self.is("[") {
                    self.bump();
                    let idx = self.expr()?;
                    self.expect("]")?;
                    Ok(HExpr::Index(n, Box::new(idx), p))
                } else if self.is("(") {
                    self.bump();
                    let mut args = Vec::new();
                    if !self.is(")") {
                        args.push(self.cond()?);
                        while self.is(",") {
                            self.bump();
                            args.push(self.cond()?);
                        }
                    }
                    self.expect(")")?;
                    Ok(HExpr::Call(n, args, p))
                } else {
                    Ok(HExpr::Name(n, p))
                }
            }
            _ => self.fail("an expression"),
        }
    }
}

/// Parses a whole program into its bodies.
pub(crate) fn parse(toks: Vec<Token>) -> Res<Vec<Body>> {
    let mut p = Parser {
        toks,
        i: 0,
        depth: 0,
    };
    let mut bodies: Vec<Body> = Vec::new();
    if p.peek().tok == Tok::End {
        return p.fail("a body, as in my_model(x[3], a[1]) { ... }");
    }
    while p.peek().tok != Tok::End {
        let b = p.body()?;
        if bodies.iter().any(|o| o.name == b.name) {
            return Err(HfError::new(
                b.pos.line,
                b.pos.col,
                format!("a body named '{}' is already defined", b.name),
            ));
        }
        bodies.push(b);
    }
    Ok(bodies)
}
