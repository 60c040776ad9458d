//! HyperFun to formula: the program is run symbolically, once, with the coordinates
//! `x[1..3]` as the formula's `x, y, z`. Every assigned value becomes a binding of a
//! formula [`Program`] (so values read many times are computed once), library calls
//! and calls of other bodies are expanded in place, and the result is the body's value.
//!
//! Control flow:
//! - `if c then A else B endif`: where `c` folds to a constant only the branch taken
//!   runs (as in HyperFun); otherwise both run on copies of the variables and every
//!   variable they leave different becomes `if(c, a, b)` (an [`Op::Select`] of the
//!   tape: the hull of both over a range where `c` is undecided). A variable assigned
//!   in one branch only may be unassigned afterwards: reading it is an error.
//! - `while c loop A endloop`: unrolled. An iteration whose condition folds runs or
//!   ends the loop; one whose condition depends on the point runs `A` as the `then`
//!   branch of an `if`. A loop that has not ended after [`MAX_ITERATIONS`] iterations (or
//!   [`MAX_OPEN_ITERATIONS`] that depend on the point) is an error.
//!
//! [`Op::Select`]: crate::formula::Op::Select

use super::lib::{self, Arg, Ctx, Kind, LIBRARY};
use super::parse::{Body, HBin, HExpr, Pos, Stmt};
use super::HfError;
use crate::formula::{folded_const, BinOp, Binding, Expr, Func, Program, Var, EPS};
use std::collections::HashMap;

/// Most iterations of one `while` loop.
pub const MAX_ITERATIONS: usize = 100_000;
/// Most iterations of one `while` loop whose condition depends on the point.
pub const MAX_OPEN_ITERATIONS: usize = 64;
/// Most statements run in all (loops unrolled, bodies expanded).
pub const MAX_STATEMENTS: usize = 2_000_000;
/// Most values (bindings) a program may compile to.
pub const MAX_VALUES: usize = 1_000_000;
/// Largest integer exponent of `^`.
pub const MAX_EXPONENT: f64 = 1024.0;

#[derive(Clone, Debug, PartialEq)]
enum Slot {
    Val(Expr),
    /// Assigned on one branch of the `if` at this position only.
    Maybe(Pos),
}

#[derive(Clone, Debug, Default, PartialEq)]
struct Env {
    scalars: HashMap<String, Slot>,
    arrays: HashMap<String, Vec<Option<Expr>>>,
    /// Arrays that may not be assigned to (the coordinates and the parameters).
    fixed: Vec<String>,
}

pub(crate) struct Compiler<'a> {
    bodies: &'a [Body],
    bindings: Vec<Binding>,
    consts: Vec<Option<f64>>,
    statements: usize,
}

type Res<T> = Result<T, HfError>;

fn err<T>(p: Pos, msg: impl Into<String>) -> Res<T> {
    Err(HfError::new(p.line, p.col, msg))
}

/// The interpreter's rounding of an index or size: to the nearest, halves up.
fn hf_round(d: f64) -> f64 {
    let c = d.ceil();
    if c - d > 0.5 {
        c - 1.0
    } else {
        c
    }
}

/// HyperFun's built-in functions the subset has, and their arities.
const BUILTINS: [(&str, usize); 12] = [
    ("sqrt", 1),
    ("exp", 1),
    ("log", 1),
    ("logd", 1),
    ("sin", 1),
    ("cos", 1),
    ("tan", 1),
    ("abs", 1),
    ("max", 2),
    ("min", 2),
    ("sinh", 1),
    ("cosh", 1),
];
const MORE_BUILTINS: [(&str, usize); 2] = [("tanh", 1), ("sign", 1)];
/// Built-ins of HyperFun the subset does not have.
const UNSUPPORTED: [&str; 9] = [
    "asin", "acos", "atan", "atan2", "mod", "ceil", "floor", "int", "frac",
];

impl Ctx for Compiler<'_> {
    fn share(&mut self, e: Expr) -> Expr {
        if matches!(e, Expr::Num(_) | Expr::Var(_) | Expr::Ref(_)) {
            return e;
        }
        if let Some(c) = folded_const(&e, &self.consts) {
            return Expr::Num(c);
        }
        self.consts.push(None);
        self.bindings.push(Binding {
            name: format!("v{}", self.bindings.len()),
            expr: e,
        });
        Expr::Ref(self.bindings.len() - 1)
    }
    fn constant(&self, e: &Expr) -> Option<f64> {
        folded_const(e, &self.consts)
    }
}

impl<'a> Compiler<'a> {
    pub(crate) fn new(bodies: &'a [Body]) -> Self {
        Compiler {
            bodies,
            bindings: Vec::new(),
            consts: Vec::new(),
            statements: 0,
        }
    }

    /// The formula of body `k` with coordinates `x, y, z` and parameters `params`.
    pub(crate) fn model(mut self, k: usize, params: &[f64]) -> Res<Program> {
        let b = &self.bodies[k];
        let xs = &b.params[0];
        if xs.size != 3 {
            return err(
                xs.pos,
                format!(
                    "the model's coordinate array must be {}[3] (x, y, z), not {}[{}]",
                    xs.name, xs.name, xs.size
                ),
            );
        }
        let mut arrays = vec![vec![
            Expr::Var(Var::X),
            Expr::Var(Var::Y),
            Expr::Var(Var::Z),
        ]];
        let a = &b.params[1];
        arrays.push(
            (0..a.size)
                .map(|i| Expr::Num(params.get(i).copied().unwrap_or(0.0)))
                .collect(),
        );
        if let Some(s) = b.params.get(2) {
            arrays.push(vec![Expr::Num(0.0); s.size]);
        }
        let body = self.run_body(k, arrays)?;
        let body = self.share(body);
        if self.bindings.len() > MAX_VALUES {
            return err(
                b.pos,
                format!("the program compiles to more than {MAX_VALUES} values"),
            );
        }
        Ok(Program {
            bindings: self.bindings,
            body,
        })
    }

    /// Runs body `k` on the given parameter arrays and returns its value.
    fn run_body(&mut self, k: usize, params: Vec<Vec<Expr>>) -> Res<Expr> {
        let b = &self.bodies[k];
        let mut env = Env::default();
        for (decl, vals) in b.params.iter().zip(params) {
            env.arrays
                .insert(decl.name.clone(), vals.into_iter().map(Some).collect());
        }
        env.fixed = b.params.iter().take(2).map(|d| d.name.clone()).collect();
        // A body without an attribute array has `s[1]` (HyperFun acts as if it had one).
        if b.params.len() < 3 && !env.arrays.contains_key("s") {
            env.arrays.insert("s".into(), vec![Some(Expr::Num(0.0))]);
        }
        for d in &b.arrays {
            if env.arrays.contains_key(&d.name) {
                return err(d.pos, format!("array '{}' is already declared", d.name));
            }
            env.arrays.insert(d.name.clone(), vec![None; d.size]);
        }
        self.block(k, &b.stmts, &mut env)?;
        let r = self.eval(k, &b.result, &mut env)?;
        Ok(r)
    }

    fn count(&mut self, p: Pos) -> Res<()> {
        self.statements += 1;
        if self.statements > MAX_STATEMENTS || self.bindings.len() > MAX_VALUES {
            return err(
                p,
                format!(
                    "the program is too large once its loops are unrolled and its calls expanded \
                     (more than {MAX_STATEMENTS} statements or {MAX_VALUES} values)"
                ),
            );
        }
        Ok(())
    }

    fn block(&mut self, k: usize, stmts: &[Stmt], env: &mut Env) -> Res<()> {
        for s in stmts {
            self.stmt(k, s, env)?;
        }
        Ok(())
    }

    fn index(&self, p: Pos, name: &str, len: usize, idx: &Expr) -> Res<usize> {
        let Some(i) = folded_const(idx, &self.consts) else {
            return err(
                p,
                format!("the index of '{name}' must be known without the coordinates (a constant or a loop counter)"),
            );
        };
        let i = hf_round(i);
        if !(i >= 1.0 && i <= len as f64) {
            return err(
                p,
                format!(
                    "index {i} is out of range for '{name}' of size {len} (indices start at 1)"
                ),
            );
        }
        Ok(i as usize - 1)
    }

    fn assignable(&self, p: Pos, name: &str, env: &Env) -> Res<()> {
        if env.fixed.iter().any(|f| f == name) {
            return err(
                p,
                format!("'{name}' is a parameter of the body and cannot be assigned"),
            );
        }
        if self.is_function(name) {
            return err(p, format!("'{name}' is a function and cannot be assigned"));
        }
        Ok(())
    }

    fn is_function(&self, name: &str) -> bool {
        BUILTINS
            .iter()
            .chain(MORE_BUILTINS.iter())
            .any(|(n, _)| *n == name)
            || UNSUPPORTED.contains(&name)
            || LIBRARY.iter().any(|(n, _, _)| *n == name)
    }

    fn stmt(&mut self, k: usize, s: &Stmt, env: &mut Env) -> Res<()> {
        match s {
            Stmt::Assign(name, p, e) => {
                self.count(*p)?;
                self.assignable(*p, name, env)?;
                if env.arrays.contains_key(name) {
                    return err(
                        *p,
                        format!(
                            "'{name}' is an array: assign '{name}[i] = ...' or '{name} = [...]'"
                        ),
                    );
                }
                let v = self.eval(k, e, env)?;
                let v = self.share(v);
                env.scalars.insert(name.clone(), Slot::Val(v));
            }
            Stmt::AssignItem(name, p, idx, e) => {
                self.count(*p)?;
                self.assignable(*p, name, env)?;
                let Some(len) = env.arrays.get(name).map(Vec::len) else {
                    return err(
                        *p,
                        format!("'{name}' is not an array (declare it with 'array {name}[n];')"),
                    );
                };
                let i = self.eval(k, idx, env)?;
                let i = self.index(*p, name, len, &i)?;
                let v = self.eval(k, e, env)?;
                let v = self.share(v);
                if let Some(a) = env.arrays.get_mut(name) {
                    a[i] = Some(v);
                }
            }
            Stmt::AssignArray(name, p, items) => {
                self.count(*p)?;
                self.assignable(*p, name, env)?;
                let Some(len) = env.arrays.get(name).map(Vec::len) else {
                    return err(
                        *p,
                        format!("'{name}' is not an array (declare it with 'array {name}[n];')"),
                    );
                };
                if items.len() != len {
                    return err(
                        *p,
                        format!(
                            "'{name}' has {len} elements but {} values are given",
                            items.len()
                        ),
                    );
                }
                let mut vals = Vec::with_capacity(len);
                for it in items {
                    let v = self.eval(k, it, env)?;
                    vals.push(Some(self.share(v)));
                }
                env.arrays.insert(name.clone(), vals);
            }
            Stmt::If(c, then, other, p) => {
                self.count(*p)?;
                let c = self.eval(k, c, env)?;
                let c = self.truth(c);
                match self.constant(&c) {
                    Some(v) if v != 0.0 => self.block(k, then, env)?,
                    Some(_) => self.block(k, other, env)?,
                    None => {
                        let mut te = env.clone();
                        self.block(k, then, &mut te)?;
                        let mut ee = env.clone();
                        self.block(k, other, &mut ee)?;
                        *env = self.merge(&c, te, ee, *p);
                    }
                }
            }
            Stmt::While(c, body, p) => {
                let mut n = 0;
                self.run_while(k, c, body, *p, env, &mut n, 0)?;
            }
        }
        Ok(())
    }

    /// Unrolls `while c loop body endloop` from `env`: iterations whose condition folds
    /// run (or end the loop) in place; at one that depends on the point, the rest of the
    /// loop runs on a copy that takes the body, and the copy is merged with the exit.
    /// `n` counts iterations, `open` the point-dependent ones on this path.
    #[allow(clippy::too_many_arguments)]
    fn run_while(
        &mut self,
        k: usize,
        c: &HExpr,
        body: &[Stmt],
        p: Pos,
        env: &mut Env,
        n: &mut usize,
        open: usize,
    ) -> Res<()> {
        loop {
            self.count(p)?;
            *n += 1;
            if *n > MAX_ITERATIONS {
                return err(p, format!("this while loop runs more than {MAX_ITERATIONS} iterations (loops are unrolled)"));
            }
            let cv = self.eval(k, c, env)?;
            let cv = self.truth(cv);
            match self.constant(&cv) {
                Some(0.0) => return Ok(()),
                Some(_) => self.block(k, body, env)?,
                None => {
                    if open >= MAX_OPEN_ITERATIONS {
                        return err(p, format!(
                            "the condition of this while loop depends on the point and does not become false \
                             for every point within {MAX_OPEN_ITERATIONS} such iterations (loops are unrolled)"
                        ));
                    }
                    let mut te = env.clone();
                    self.block(k, body, &mut te)?;
                    self.run_while(k, c, body, p, &mut te, n, open + 1)?;
                    let exit = env.clone();
                    *env = self.merge(&cv, te, exit, p);
                    return Ok(());
                }
            }
        }
    }

    /// The truth value of a condition: 1 where `|c| >= EPS`, else 0 (the interpreter's
    /// test), shared.
    fn truth(&mut self, c: Expr) -> Expr {
        let t = Expr::Call(Func::If, vec![c, Expr::Num(1.0), Expr::Num(0.0)]);
        self.share(t)
    }

    /// The variables after an `if` on the truth value `c` whose branches left `t` and `e`.
    fn merge(&mut self, c: &Expr, t: Env, e: Env, p: Pos) -> Env {
        let mut out = Env {
            fixed: t.fixed.clone(),
            ..Env::default()
        };
        let mut names: Vec<&String> = t.scalars.keys().chain(e.scalars.keys()).collect();
        names.sort();
        names.dedup();
        for name in names {
            let slot = match (t.scalars.get(name), e.scalars.get(name)) {
                (Some(Slot::Val(a)), Some(Slot::Val(b))) => Slot::Val(self.pick(c, a, b)),
                (Some(Slot::Maybe(q)), _) | (_, Some(Slot::Maybe(q))) => Slot::Maybe(*q),
                _ => Slot::Maybe(p),
            };
            out.scalars.insert(name.clone(), slot);
        }
        for (name, ta) in &t.arrays {
            let ea = e.arrays.get(name).cloned().unwrap_or_default();
            let merged = ta
                .iter()
                .zip(ea.iter())
                .map(|(a, b)| match (a, b) {
                    (Some(a), Some(b)) => Some(self.pick(c, a, b)),
                    _ => None,
                })
                .collect();
            out.arrays.insert(name.clone(), merged);
        }
        out
    }

    fn pick(&mut self, c: &Expr, a: &Expr, b: &Expr) -> Expr {
        if a == b {
            return a.clone();
        }
        let e = Expr::Call(Func::If, vec![c.clone(), a.clone(), b.clone()]);
        self.share(e)
    }

    fn lookup(&self, p: Pos, name: &str, env: &Env) -> Res<Expr> {
        match env.scalars.get(name) {
            Some(Slot::Val(v)) => return Ok(v.clone()),
            Some(Slot::Maybe(q)) => {
                return err(
                    p,
                    format!(
                        "'{name}' may be unassigned here: it is assigned on only one side of the \
                         'if' at line {}, column {}",
                        q.line, q.col
                    ),
                )
            }
            None => {}
        }
        if env.arrays.contains_key(name) {
            return err(p, format!("'{name}' is an array: use '{name}[i]'"));
        }
        if self.is_function(name) {
            return err(
                p,
                format!("'{name}' is a function: call it with '{name}(...)'"),
            );
        }
        err(
            p,
            format!("unknown variable '{name}' (assign it before use)"),
        )
    }

    fn eval(&mut self, k: usize, e: &HExpr, env: &mut Env) -> Res<Expr> {
        let v = match e {
            HExpr::Num(v) => Expr::Num(*v),
            HExpr::Str(_, p) => {
                return err(
                    *p,
                    "strings are only arguments of library functions the subset does not have",
                )
            }
            HExpr::Name(n, p) => self.lookup(*p, n, env)?,
            HExpr::Index(n, idx, p) => {
                let Some(len) = env.arrays.get(n).map(Vec::len) else {
                    return match env.scalars.get(n) {
                        Some(_) => err(*p, format!("'{n}' is not an array")),
                        None => err(*p, format!("unknown array '{n}'")),
                    };
                };
                let i = self.eval(k, idx, env)?;
                let i = self.index(*p, n, len, &i)?;
                match &env.arrays[n][i] {
                    Some(v) => v.clone(),
                    None => {
                        return err(
                            *p,
                            format!("'{n}[{}]' is used before it is assigned", i + 1),
                        )
                    }
                }
            }
            HExpr::Call(name, args, p) => self.call(k, name, args, *p, env)?,
            HExpr::Neg(a) => Expr::neg(self.eval(k, a, env)?),
            HExpr::Not(a) => Expr::Call(Func::Not, vec![self.eval(k, a, env)?]),
            HExpr::Bin(op, a, b, p, depth) => {
                let l = self.eval(k, a, env)?;
                let r = self.eval(k, b, env)?;
                let out = match op {
                    HBin::Pow => self.power(l, &r, *p)?,
                    _ => {
                        let op = match op {
                            HBin::Add => BinOp::Add,
                            HBin::Sub => BinOp::Sub,
                            HBin::Mul => BinOp::Mul,
                            HBin::Div => BinOp::Div,
                            HBin::Inter => BinOp::Intersect,
                            HBin::Union => BinOp::Union,
                            HBin::Subtract => BinOp::Subtract,
                            HBin::Lt => BinOp::Lt,
                            HBin::Gt => BinOp::Gt,
                            HBin::Le => BinOp::Le,
                            HBin::Ge => BinOp::Ge,
                            HBin::Eq => BinOp::Eq,
                            HBin::Ne => BinOp::Ne,
                            HBin::And => BinOp::And,
                            _ => BinOp::Or,
                        };
                        Expr::bin(op, l, r)
                    }
                };
                // Long chains are cut into bindings so that formula trees stay shallow.
                if depth % 128 == 0 {
                    self.share(out)
                } else {
                    out
                }
            }
        };
        Ok(v)
    }

    /// `base ^ e` as the interpreter computes it, for a constant `e`: an integer power
    /// where `e` is an integer within `EPS`, else `exp(e ln base)`.
    fn power(&mut self, base: Expr, e: &Expr, p: Pos) -> Res<Expr> {
        let Some(c) = self.constant(e) else {
            return err(
                p,
                "the exponent of '^' must be known without the coordinates (a constant)",
            );
        };
        if c - c.floor() < EPS {
            let n = hf_round(c.abs());
            if n > MAX_EXPONENT {
                return err(
                    p,
                    format!("exponent {c} is too large (at most {MAX_EXPONENT})"),
                );
            }
            let n = if c < 0.0 { -(n as i32) } else { n as i32 };
            return Ok(Expr::pow(base, n));
        }
        if !c.is_finite() {
            return err(p, format!("exponent {c} is not finite"));
        }
        Ok(Expr::PowF(Box::new(base), c))
    }

    fn call(&mut self, k: usize, name: &str, args: &[HExpr], p: Pos, env: &mut Env) -> Res<Expr> {
        let arity_err = |want: usize| {
            err::<Expr>(
                p,
                format!(
                    "{name} takes {want} argument{} but was given {}",
                    if want == 1 { "" } else { "s" },
                    args.len()
                ),
            )
        };
        if let Some(&(_, n)) = BUILTINS
            .iter()
            .chain(MORE_BUILTINS.iter())
            .find(|(f, _)| *f == name)
        {
            if args.len() != n {
                return arity_err(n);
            }
            let mut v = Vec::new();
            for a in args {
                v.push(self.eval(k, a, env)?);
            }
            let f = |f: Func, v: Vec<Expr>| Expr::Call(f, v);
            let one = |v: &mut Vec<Expr>| v.remove(0);
            return Ok(match name {
                "sqrt" => f(Func::Sqrt, v),
                "exp" => f(Func::Exp, v),
                "log" => f(Func::Ln, v),
                "logd" => Expr::bin(
                    BinOp::Div,
                    f(Func::Ln, v),
                    Expr::Num(std::f64::consts::LN_10),
                ),
                "sin" => f(Func::Sin, v),
                "cos" => f(Func::Cos, v),
                "tan" => f(Func::Tan, v),
                "abs" => f(Func::Abs, v),
                "max" => f(Func::Max, v),
                "min" => f(Func::Min, v),
                "sinh" | "cosh" => {
                    let a = self.share(one(&mut v));
                    let (ep, en) = (
                        f(Func::Exp, vec![a.clone()]),
                        f(Func::Exp, vec![Expr::neg(a)]),
                    );
                    let op = if name == "sinh" {
                        BinOp::Sub
                    } else {
                        BinOp::Add
                    };
                    Expr::bin(BinOp::Mul, Expr::bin(op, ep, en), Expr::Num(0.5))
                }
                // 1 - 2 / (exp(2a) + 1): bounded where exp overflows.
                "tanh" => {
                    let a = one(&mut v);
                    let e2 = f(Func::Exp, vec![Expr::bin(BinOp::Mul, Expr::Num(2.0), a)]);
                    let q = Expr::bin(
                        BinOp::Div,
                        Expr::Num(2.0),
                        Expr::bin(BinOp::Add, e2, Expr::Num(1.0)),
                    );
                    Expr::bin(BinOp::Sub, Expr::Num(1.0), q)
                }
                // sign: -1 below 0, else 1.
                _ => {
                    let a = one(&mut v);
                    f(
                        Func::If,
                        vec![
                            Expr::bin(BinOp::Lt, a, Expr::Num(0.0)),
                            Expr::Num(-1.0),
                            Expr::Num(1.0),
                        ],
                    )
                }
            });
        }
        if UNSUPPORTED.contains(&name) {
            return err(
                p,
                format!("'{name}' is not in the HyperFun subset (no sound enclosure of it in every arithmetic here)"),
            );
        }
        if let Some(&(lname, doc, kinds)) = LIBRARY.iter().find(|(n, _, _)| *n == name) {
            if args.len() != kinds.len() {
                return err(
                    p,
                    format!(
                        "{doc} takes {} arguments but was given {}",
                        kinds.len(),
                        args.len()
                    ),
                );
            }
            // Real arguments first (they may call mappings), then the arrays.
            let mut reals = Vec::new();
            for (a, kind) in args.iter().zip(kinds.iter()) {
                reals.push(match kind {
                    Kind::Real => Some(self.eval(k, a, env)?),
                    Kind::Array => None,
                });
            }
            let mut vals = Vec::with_capacity(args.len());
            let mut array_names = Vec::new();
            for (j, (a, kind)) in args.iter().zip(kinds.iter()).enumerate() {
                match kind {
                    Kind::Array => {
                        let (an, ap) = match a {
                            HExpr::Name(n, q) => (n, *q),
                            _ => {
                                return err(
                                    p,
                                    format!(
                                        "argument {} of {doc} must be the name of an array",
                                        j + 1
                                    ),
                                )
                            }
                        };
                        let Some(arr) = env.arrays.get(an) else {
                            return err(
                                ap,
                                format!(
                                    "argument {} of {doc} must be an array; '{an}' is not one",
                                    j + 1
                                ),
                            );
                        };
                        if arr.len() < 3 {
                            return err(
                                ap,
                                format!(
                                    "{doc} needs an array of 3 elements; '{an}' has {}",
                                    arr.len()
                                ),
                            );
                        }
                        let mut v = Vec::with_capacity(arr.len());
                        for (i, x) in arr.iter().enumerate() {
                            match x {
                                Some(x) => v.push(x.clone()),
                                None => {
                                    return err(
                                        ap,
                                        format!("'{an}[{}]' is used before it is assigned", i + 1),
                                    )
                                }
                            }
                        }
                        array_names.push(Some(an.clone()));
                        vals.push(Arg::Array(v));
                    }
                    Kind::Real => {
                        let v = reals[j].take().unwrap_or(Expr::Num(0.0));
                        array_names.push(None);
                        vals.push(Arg::Real(v));
                    }
                }
            }
            let out = lib::apply(self, lname, &vals, p.line, p.col)?;
            if let Some((j, vals)) = out.update {
                let Some(Some(an)) = array_names.get(j) else {
                    return err(p, "internal: a mapping without its array");
                };
                if env.fixed.iter().any(|f| f == an) {
                    return err(p, format!("{doc} changes its array argument; '{an}' is a parameter of the body: copy it into a local array first"));
                }
                env.arrays
                    .insert(an.clone(), vals.into_iter().map(Some).collect());
            }
            return Ok(out.value);
        }
        // Another body, defined before this one.
        if let Some(j) = self.bodies.iter().position(|b| b.name == name) {
            if j >= k {
                return err(p, format!("'{name}' is defined after this body (or is this body): a body can only call bodies defined before it"));
            }
            let callee = &self.bodies[j];
            if args.len() != callee.params.len() && !(args.len() == 2 && callee.params.len() == 2) {
                return arity_err(callee.params.len());
            }
            let mut arrays = Vec::new();
            for (a, decl) in args.iter().zip(callee.params.iter()) {
                let (an, ap) = match a {
                    HExpr::Name(n, q) => (n, *q),
                    _ => {
                        return err(
                            p,
                            format!("the arguments of the body '{name}' must be array names"),
                        )
                    }
                };
                let Some(arr) = env.arrays.get(an) else {
                    return err(ap, format!("'{an}' is not an array"));
                };
                if arr.len() != decl.size {
                    return err(
                        ap,
                        format!(
                            "'{name}' takes {}[{}] here but '{an}' has {} elements",
                            decl.name,
                            decl.size,
                            arr.len()
                        ),
                    );
                }
                let mut v = Vec::new();
                for (i, x) in arr.iter().enumerate() {
                    match x {
                        Some(x) => v.push(x.clone()),
                        None => {
                            return err(
                                ap,
                                format!("'{an}[{}]' is used before it is assigned", i + 1),
                            )
                        }
                    }
                }
                arrays.push(v);
            }
            return self.run_body(j, arrays);
        }
        err(p, format!("unknown function '{name}'"))
    }
}
