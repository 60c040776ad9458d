//! The formula language of `tracer --expr`: precedence, bindings, values against
//! hand-written Rust, every error path with its position, round trips through text,
//! range evaluation, and no panics on arbitrary input.

use arith_core::rfunc::{intersect, subtract, union};
use arith_core::{Range, Real};
use model_sources::formula::{
    compile, parse, parse_program, BinOp, Binding, Expr, Func, Op, ParseError, Program, Tape,
    ToFormula, Var, MAX_TREE_DEPTH, SYNTAX,
};
use proptest::prelude::*;
use proptest::sample::select;

/// Bitwise equality that treats every NaN as equal.
fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn tape(src: &str) -> Tape {
    match parse(src) {
        Ok(t) => t,
        Err(e) => panic!("{src:?} should parse:\n{}", e.render(src)),
    }
}

fn at(src: &str, x: f64, y: f64, z: f64) -> f64 {
    tape(src).eval(x, y, z)
}

fn err(src: &str) -> ParseError {
    match parse(src) {
        Ok(t) => panic!("{src:?} should fail, parsed to\n{t}"),
        Err(e) => e,
    }
}

fn count(t: &Tape, op: Op) -> usize {
    t.instructions().iter().filter(|i| i.op == op).count()
}

fn x() -> Expr {
    Expr::Var(Var::X)
}
fn y() -> Expr {
    Expr::Var(Var::Y)
}
fn z() -> Expr {
    Expr::Var(Var::Z)
}
fn num(c: f64) -> Expr {
    Expr::Num(c)
}

// ---------------------------------------------------------------- precedence

#[test]
fn arithmetic_precedence_and_associativity() {
    assert_eq!(at("1 + 2 * 3", 0.0, 0.0, 0.0), 7.0);
    assert_eq!(at("(1 + 2) * 3", 0.0, 0.0, 0.0), 9.0);
    assert_eq!(at("-2^2", 0.0, 0.0, 0.0), -4.0);
    assert_eq!(at("(-2)^2", 0.0, 0.0, 0.0), 4.0);
    assert_eq!(at("2^3^2", 0.0, 0.0, 0.0), 512.0);
    assert_eq!(at("(2^3)^2", 0.0, 0.0, 0.0), 64.0);
    assert_eq!(at("2^-1", 0.0, 0.0, 0.0), 0.5);
    assert_eq!(at("2^(-2)", 0.0, 0.0, 0.0), 0.25);
    assert_eq!(at("-x^2", 3.0, 0.0, 0.0), -9.0);
    assert_eq!(at("x^-2", 2.0, 0.0, 0.0), 0.25);
    assert_eq!(at("2 * -x", 3.0, 0.0, 0.0), -6.0);
    assert_eq!(at("x - -y", 3.0, 2.0, 0.0), 5.0);
    // Left associativity of `-` and `/`.
    assert_eq!(at("2 - 3 - 4", 0.0, 0.0, 0.0), -5.0);
    assert_eq!(at("64 / 4 / 2", 0.0, 0.0, 0.0), 8.0);
    assert_eq!(at("x - y - z", 10.0, 3.0, 4.0), 3.0);
    assert_eq!(at("x / y / z", 64.0, 4.0, 2.0), 8.0);
    assert_eq!(at("x - y + z", 10.0, 3.0, 4.0), 11.0);
    assert_eq!(at("x / y * z", 8.0, 4.0, 2.0), 4.0);
}

#[test]
fn precedence_trees() {
    let p = |s: &str| parse_program(s).unwrap().body;
    let b = Expr::bin;
    // `-x^2 = -(x^2)`, `2^3^2 = 2^9`.
    assert_eq!(p("-x^2"), Expr::neg(Expr::pow(x(), 2)));
    assert_eq!(p("2^3^2"), Expr::pow(num(2.0), 9));
    // `a | b & c = a | (b & c)`; `a \ b & c = (a \ b) & c`; `a & b | c = (a & b) | c`.
    assert_eq!(
        p("x | y & z"),
        b(BinOp::Union, x(), b(BinOp::Intersect, y(), z()))
    );
    assert_eq!(
        p("x \\ y & z"),
        b(BinOp::Intersect, b(BinOp::Subtract, x(), y()), z())
    );
    assert_eq!(
        p("x & y \\ z"),
        b(BinOp::Subtract, b(BinOp::Intersect, x(), y()), z())
    );
    assert_eq!(
        p("x & y | z"),
        b(BinOp::Union, b(BinOp::Intersect, x(), y()), z())
    );
    assert_eq!(
        p("x | y | z"),
        b(BinOp::Union, b(BinOp::Union, x(), y()), z())
    );
    // R-functions bind looser than arithmetic.
    assert_eq!(
        p("x + 1 & y * 2"),
        b(
            BinOp::Intersect,
            b(BinOp::Add, x(), num(1.0)),
            b(BinOp::Mul, y(), num(2.0))
        )
    );
    assert_eq!(p("x - y - z"), b(BinOp::Sub, b(BinOp::Sub, x(), y()), z()));
    assert_eq!(p("x / y / z"), b(BinOp::Div, b(BinOp::Div, x(), y()), z()));
}

proptest! {
    /// R-function precedence checked by value against `arith_core::rfunc`.
    #[test]
    fn rfunction_precedence_by_value(x in -2.0..2.0f64, y in -2.0..2.0f64, z in -2.0..2.0f64) {
        let (a, b, c) = (1.0 - x * x, y - 0.5, z * 3.0);
        let f = "1 - x^2 | y - 0.5 & z * 3";
        prop_assert!(same(at(f, x, y, z), union(a, intersect(b, c))));
        let f = "1 - x^2 \\ y - 0.5 & z * 3";
        prop_assert!(same(at(f, x, y, z), intersect(subtract(a, b), c)));
        let f = "1 - x^2 & y - 0.5 \\ z * 3 | x";
        prop_assert!(same(at(f, x, y, z), union(subtract(intersect(a, b), c), x)));
    }
}

// ---------------------------------------------------------------- values

/// Formula and the same function written in Rust.
type Case = (&'static str, fn(f64, f64, f64) -> f64);

fn cases() -> Vec<Case> {
    vec![
        ("x", |x, _, _| x),
        ("x + y * z", |x, y, z| x + y * z),
        ("x^2 + y^2 + z^2 - 1", |x, y, z| x * x + y * y + z * z - 1.0),
        ("x^3 - 2*y^4 + z^-1", |x, y, z| {
            x.powi(3) - 2.0 * y.powi(4) + z.powi(-1)
        }),
        ("sqrt(x^2 + y^2) - 0.5", |x, y, _| (x * x + y * y).sqrt() - 0.5),
        ("sqrt(x)", |x, _, _| x.max(0.0).sqrt()),
        ("exp(x) * ln(y)", |x, y, _| Real::exp(&x) * Real::ln(&y)),
        ("sin(3*x) + cos(y / 2)", |x, y, _| {
            Real::sin(&(3.0 * x)) + Real::cos(&(y / 2.0))
        }),
        ("abs(x) - min(y, z) + max(x, -z)", |x, y, z| {
            x.abs() - y.min(z) + x.max(-z)
        }),
        ("sqr(x - y)", |x, y, _| (x - y) * (x - y)),
        ("1 / x - 2 / (y + 3)", |x, y, _| 1.0 / x - 2.0 / (y + 3.0)),
        ("x / 3 - z * 0.1", |x, _, z| x / 3.0 - z * 0.1),
        ("0.5 - x", |x, _, _| 0.5 - x),
        ("1e-3 * x + 2.5E+2 * y + .5 * z", |x, y, z| {
            1e-3 * x + 2.5e2 * y + 0.5 * z
        }),
        // Mitchell's surface (Appendix A).
        (
            "20 * (x^2 + y^2 + z^2) - 4 * (x^4 + (y^2 + z^2)^2) - 17*x^2 * (y^2 + z^2) - 17",
            |x, y, z| {
                20.0 * (x * x + y * y + z * z)
                    - 4.0 * (x.powi(4) + (y * y + z * z).powi(2))
                    - 17.0 * (x * x) * (y * y + z * z)
                    - 17.0
            },
        ),
        // Decocube (Appendix A).
        (
            "0.02 - ((x^2 + y^2 - 0.82)^2 + (z^2 - 1)^2) * ((y^2 + z^2 - 0.82)^2 + (x^2 - 1)^2) * ((x^2 + z^2 - 0.82)^2 + (y^2 - 1)^2)",
            |x, y, z| {
                let (x2, y2, z2) = (x * x, y * y, z * z);
                let sq = |v: f64| v * v;
                0.02 - (sq(x2 + y2 - 0.82) + sq(z2 - 1.0))
                    * (sq(y2 + z2 - 0.82) + sq(x2 - 1.0))
                    * (sq(x2 + z2 - 0.82) + sq(y2 - 1.0))
            },
        ),
    ]
}

proptest! {
    /// Tape values equal the Rust closures bit for bit: both perform the same IEEE
    /// operations in the same order.
    #[test]
    fn values_match_rust(x in -3.0..3.0f64, y in -3.0..3.0f64, z in -3.0..3.0f64) {
        for (src, f) in cases() {
            let got = at(src, x, y, z);
            let want = f(x, y, z);
            prop_assert!(same(got, want), "{}: tape {} vs rust {} at ({}, {}, {})", src, got, want, x, y, z);
        }
    }
}

#[test]
fn numbers_and_comments() {
    assert_eq!(at("1e-3", 0.0, 0.0, 0.0), 1e-3);
    assert_eq!(at("2.5E+2", 0.0, 0.0, 0.0), 250.0);
    assert_eq!(at(".5", 0.0, 0.0, 0.0), 0.5);
    assert_eq!(at("5.", 0.0, 0.0, 0.0), 5.0);
    assert_eq!(at("12e2", 0.0, 0.0, 0.0), 1200.0);
    assert_eq!(
        at(
            "# a sphere\n  1 - x^2 # minus x squared\n\t- y^2 - z^2\n",
            0.5,
            0.5,
            0.5
        ),
        0.25
    );
}

// ---------------------------------------------------------------- bindings, tape

#[test]
fn bindings() {
    let f = "b = 0.36 - x^2; s = 0.7 - x^2 - y^2; b | s";
    for &(x, y) in &[(0.1, 0.2), (-0.7, 0.3), (1.5, -1.0)] {
        let want = union(0.36 - x * x, 0.7 - x * x - y * y);
        assert!(same(at(f, x, y, 0.0), want));
    }
    // Later bindings use earlier ones; names may hold digits and underscores.
    let f = "r_2 = x^2 + y^2; d1 = r_2 + z^2; 1 - d1 + r_2";
    assert_eq!(at(f, 1.0, 2.0, 3.0), 1.0 - 14.0 + 5.0);
    // A trailing ';' after the final expression is accepted.
    assert_eq!(at("a = x; a;", 4.0, 0.0, 0.0), 4.0);
}

#[test]
fn shared_values_are_computed_once() {
    // A let-bound value used three times: one `sin`.
    let t = tape("s = sin(x); s * s + s");
    assert_eq!(count(&t, Op::Sin), 1);
    assert_eq!(count(&t, Op::Sqr), 1, "s * s becomes sqr(s):\n{t}");
    // Repeated subexpressions written out: one `x^2`, one `sqrt`.
    let t = tape("sqrt(x^2 + y^2) + sqrt(y^2 + x^2) + x^2");
    assert_eq!(count(&t, Op::Sqr), 2, "{t}");
    assert_eq!(count(&t, Op::Sqrt), 1, "{t}");
    // Unused bindings cost nothing.
    let t = tape("u = sin(x) + cos(y); v = u * 2; z");
    assert_eq!(t.len(), 1, "{t}");
    assert_eq!(t.eval(1.0, 2.0, 3.0), 3.0);
}

/// `min(-0, +0)` is `-0` and `max(-0, +0)` is `+0` in either order, and a tape keeps
/// `min`'s and `max`'s operand order (other `Real` types need not be symmetric in
/// them), so a tape printed and parsed again gives the same bits. Found by
/// `tape_print_parse_round_trip`: `min(-0.0, x * 0.0) * 0.0` came back as `+0`.
#[test]
fn min_and_max_of_signed_zeros() {
    for (src, want) in [
        ("min(-0.0, x)", -0.0),
        ("min(x, -0.0)", -0.0),
        ("max(-0.0, x)", 0.0),
        ("max(x, -0.0)", 0.0),
        ("min(-0.0, x * 0.0) * 0.0", -0.0),
        ("min(x * 0.0, -0.0) * 0.0", -0.0),
    ] {
        let t = tape(src);
        let v = t.eval(0.0, 0.0, 0.0);
        assert!(same(v, want), "{src}: {v}\n{t}");
        let back = tape(&t.to_formula());
        assert!(
            same(back.eval(0.0, 0.0, 0.0), want),
            "{src} printed: {}",
            t.to_formula()
        );
    }
    // Written both ways they are two values, not one.
    assert_eq!(count(&tape("min(x, y) + min(y, x)"), Op::Min), 2);
}

#[test]
fn constants_fold_only_when_exact() {
    // Exact: one constant instruction.
    for (src, v) in [
        ("1 + 2 * 3", 7.0),
        ("-2^2", -4.0),
        ("2^-1 + sqrt(16)", 4.5),
        ("max(1, 2) - abs(-3) + min(4, 5)", 3.0),
        ("exp(0) + cos(0) + sin(0) + ln(1)", 2.0),
        ("sqrt(-4)", 0.0),
        ("3 & 4", 2.0), // 3 + 4 - sqrt(9 + 16)
    ] {
        let t = tape(src);
        assert_eq!(t.len(), 1, "{src}:\n{t}");
        assert_eq!(t.instructions()[0].op, Op::Const);
        assert_eq!(t.eval(0.0, 0.0, 0.0), v, "{src}");
    }
    // Inexact in f64: left to the arithmetic, which encloses the real value.
    for src in ["1 / 3", "0.1 + 0.2", "sqrt(2)", "exp(1)", "1 & 1"] {
        let t = tape(src);
        assert!(t.len() > 1, "{src} must not be folded:\n{t}");
        let r = t.eval(
            arith_ia::Interval::constant(0.0),
            arith_ia::Interval::constant(0.0),
            arith_ia::Interval::constant(0.0),
        );
        let (lo, hi) = r.bounds();
        assert!(
            lo < hi,
            "{src}: an inexact constant must give a proper interval"
        );
    }
    let third = tape("1/3").eval(
        arith_ia::Interval::constant(0.0),
        arith_ia::Interval::constant(0.0),
        arith_ia::Interval::constant(0.0),
    );
    // The real 1/3 is enclosed.
    assert!(third.lo * 3.0 <= 1.0 && third.hi * 3.0 >= 1.0);
}

#[test]
fn listing_and_len() {
    let t = tape("x^2 + y^3 - 1");
    // x, sqr, y, powi, add, subc
    assert_eq!(t.len(), 6, "{t}");
    assert!(!t.is_empty());
    let listing = t.to_string();
    assert_eq!(listing.lines().count(), 6);
    assert!(listing.contains("sqr r0"), "{listing}");
    assert!(listing.contains("powi r2!, 3"), "{listing}");
    assert!(listing.contains("subc"), "{listing}");
}

// ---------------------------------------------------------------- errors

#[test]
fn every_error_path_has_its_position() {
    // (formula, 0-based position, part of the message)
    let table: &[(&str, usize, &str)] = &[
        ("", 0, "empty formula"),
        ("  # nothing but a comment\n", 0, "empty formula"),
        ("x + $", 4, "unexpected character '$'"),
        ("x + é", 4, "unexpected character 'é'"),
        (
            "(x + 1",
            6,
            "expected ')' to close the '(' at column 1 but found end of input",
        ),
        ("((x + 1)", 8, "expected ')' to close the '(' at column 1"),
        (
            "x +",
            3,
            "expected a number, a variable, a function or '(' but found end of input",
        ),
        ("x * * y", 4, "but found '*'"),
        ("x & ", 4, "but found end of input"),
        ("|x", 0, "but found '|'"),
        ("()", 1, "but found ')'"),
        (
            "x y",
            2,
            "expected an operator or end of input but found name 'y'",
        ),
        (
            "x)",
            1,
            "expected an operator or end of input but found ')'",
        ),
        ("x, y", 1, "but found ','"),
        ("1 2", 2, "but found number '2'"),
        ("1.2.3", 0, "invalid number '1.2.3'"),
        ("2x", 0, "invalid number '2x'"),
        // An operand right after a number: both spellings say why.
        ("17x", 0, "invalid number '17x' (a product needs '*'"),
        ("20(x)", 2, "but found '(' (a product needs '*'"),
        ("1 - 3 (x + 1)", 6, "a product needs '*'"),
        ("(2 x)", 3, "a product needs '*'"),
        ("sin(2(x))", 5, "a product needs '*'"),
        ("1e", 1, "expected digits after the exponent mark"),
        ("1e+ 2", 1, "expected digits after the exponent mark"),
        ("1e999", 0, "too large"),
        (
            "x^",
            2,
            "expected an exponent after '^' but found end of input",
        ),
        ("x^-", 3, "expected an exponent after '^'"),
        ("x^y", 2, "but found name 'y'"),
        ("x^2.5^2", 5, "a real exponent cannot be raised"),
        ("x^1e5", 2, "too large"),
        ("x^2^0.5", 3, "real exponent inside an exponent"),
        ("x^(2", 4, "expected ')'"),
        ("x^99999", 2, "too large"),
        ("x^2^-1", 3, "not an integer"),
        ("x^10^10", 4, "not an integer of magnitude"),
        ("foo(x)", 0, "unknown function 'foo'"),
        ("w + 1", 0, "unknown variable 'w'"),
        ("X", 0, "unknown variable 'X'"),
        ("x(1)", 0, "'x' is not a function"),
        (
            "sin x",
            4,
            "expected '(' after the function name 'sin' but found name 'x'",
        ),
        ("1 + cos", 7, "expected '(' after the function name 'cos'"),
        ("sin(x, y)", 0, "sin takes 1 argument but was given 2"),
        ("min(x)", 0, "min takes 2 arguments but was given 1"),
        ("max()", 0, "max takes 2 arguments but was given 0"),
        (
            "sin(x",
            5,
            "expected ',' or ')' to close the '(' at column 4",
        ),
        (
            "b = 1 - x^2 b",
            12,
            "expected ';' after the binding of 'b' but found name 'b'",
        ),
        (
            "b = 1 - x^2",
            11,
            "expected ';' after the binding of 'b' but found end of input",
        ),
        (
            "b = 1 - x^2;",
            12,
            "expected the final expression after the bindings",
        ),
        ("b = 1; # no body", 16, "expected the final expression"),
        ("b = ; b", 4, "but found ';'"),
        ("x = 1; x", 0, "cannot bind 'x': it is a coordinate"),
        (
            "sin = 1; sin(0)",
            0,
            "cannot bind 'sin': it is a function name",
        ),
        ("b = 1; b = 2; b", 7, "'b' is already bound"),
        ("b = b + 1; b", 4, "unknown variable 'b'"),
        ("b = 1; c(x)", 7, "unknown function 'c'"),
        ("b = 1; b(x)", 7, "'b' is not a function"),
        ("x; y", 3, "only bindings"),
        ("x = = 1", 0, "cannot bind 'x'"),
        // Constants that make the formula infinite or NaN everywhere, after folding.
        ("1/0 - x^2", 1, "division by zero"),
        ("x/0", 1, "division by zero"),
        ("0/0 + x", 1, "division by zero"),
        ("x/(1-1)", 1, "division by zero"),
        ("x / -0", 2, "division by zero"),
        ("x / sqrt(-4)", 2, "division by zero"),
        ("b = 1 - 1; x / b", 13, "division by zero"),
        ("b = 2 - 2; c = b * 3; y + x / c", 28, "division by zero"),
        ("ln(0) + x", 0, "ln of the constant 0.0"),
        ("x + ln(-1)", 4, "ln of the constant -1.0"),
        ("ln(1 - 3) * x", 0, "ln of the constant -2.0"),
        ("b = 0; ln(b) + x", 7, "ln of the constant 0.0"),
    ];
    for &(src, pos, msg) in table {
        let e = err(src);
        assert_eq!(e.pos, pos, "{src:?}: {e}");
        assert!(
            e.message.contains(msg),
            "{src:?}: got {:?}, want {msg:?}",
            e.message
        );
        assert_eq!(
            e.to_string(),
            format!("error at column {}: {}", pos + 1, e.message),
            "{src:?}"
        );
    }
}

#[test]
fn constant_zero_divisors_and_ln_domain() {
    // Multi-line: the line and column of the operator or function.
    let e = err("b = x^2;\n1 - b / (2 - 2)");
    assert_eq!((e.line, e.column), (2, 7), "{e}");
    assert_eq!(
        e.to_string(),
        "error at line 2, column 7: division by zero: the divisor is the constant 0 (after folding)"
    );
    let e = err("# comment\n  ln(0)");
    assert_eq!((e.line, e.column), (2, 3), "{e}");
    // Divisors and ln arguments that are not folded constants stay allowed.
    for src in [
        "1/x",
        "x/(0*y)",
        "x/(0.1 + 0.2 - 0.3)",
        "ln(1) + x",
        "ln(x^2 + 1)",
        "b = 1; x / b",
        "x / 1e-300",
    ] {
        tape(src);
    }
    // A hand-built tree with a zero divisor still compiles (the parser refuses it).
    let p = Program {
        bindings: vec![],
        body: Expr::bin(BinOp::Div, Expr::Var(Var::X), Expr::Num(0.0)),
    };
    assert!(compile(&p).is_ok());
}

/// The one text of the language names every function and operator, and is the one its
/// documentation page shows.
#[test]
fn syntax_text_is_complete_and_in_its_page() {
    for f in Func::ALL {
        assert!(SYNTAX.contains(f.name()), "{}", f.name());
    }
    for op in BinOp::ALL {
        assert!(SYNTAX.contains(op.symbol()), "{}", op.symbol());
    }
    for w in ["^", "#", "name = expr;", "x  y  z"] {
        assert!(SYNTAX.contains(w), "{w}");
    }
    let page = include_str!("../../docs/formula-language.md");
    assert!(
        page.contains(SYNTAX),
        "docs/formula-language.md lacks the formula language text"
    );
    // Its example binding parses.
    tape("b = 0.36 - x^2; s = 0.7 - x^2 - y^2; b | s");
}

#[test]
fn render_survives_hand_made_errors() {
    let e = ParseError {
        pos: 99,
        message: "m".into(),
        line: 0,
        column: 0,
    };
    assert!(e.render("x").contains('^'));
}

#[test]
fn error_display_and_caret() {
    let src = "(x + 1";
    let e = err(src);
    assert_eq!(
        e.to_string(),
        "error at column 7: expected ')' to close the '(' at column 1 but found end of input"
    );
    assert_eq!(
        e.render(src),
        "error at column 7: expected ')' to close the '(' at column 1 but found end of input\n  (x + 1\n        ^"
    );
    // Multi-line formulas name the line; the caret sits under the offending token.
    let src = "b = 1 - x^2;\nb & (y ~ 2)";
    let e = err(src);
    assert_eq!(e.pos, 20);
    assert_eq!((e.line, e.column), (2, 8));
    assert_eq!(
        e.render(src),
        "error at line 2, column 8: unexpected character '~'\n  b & (y ~ 2)\n         ^"
    );
    // Positions count characters, not bytes.
    let e = err("éé + $");
    assert_eq!(e.pos, 0);
    let e = err("1 + 2 # é\n + $");
    assert_eq!((e.pos, e.line, e.column), (13, 2, 4));
}

#[test]
fn deep_or_long_input_is_an_error_not_a_crash() {
    let deep = format!("{}x{}", "(".repeat(100_000), ")".repeat(100_000));
    assert!(err(&deep).message.contains("nested too deeply"));
    let minus = format!("{}x", "-".repeat(100_000));
    assert!(err(&minus).message.contains("nested too deeply"));
    let calls = format!("{}x{}", "sin(".repeat(10_000), ")".repeat(10_000));
    assert!(err(&calls).message.contains("nested too deeply"));
    // A long flat chain is not deep: it parses (see `long_flat_chains_parse`).
    let long = vec!["x"; 100_000].join(" + ");
    assert_eq!(at(&long, 1.0, 0.0, 0.0), 100_000.0);
    let exps = format!("x{}", "^(1".repeat(10_000));
    assert!(err(&exps).message.contains("nested too deeply"));
    // Moderate sizes work.
    let ok = format!("{}x{}", "(".repeat(150), ")".repeat(150));
    assert_eq!(at(&ok, 2.0, 0.0, 0.0), 2.0);
    let sum = vec!["x"; 1000].join(" + ");
    assert_eq!(at(&sum, 1.0, 0.0, 0.0), 1000.0);
    // Many chained bindings compile without deep recursion.
    let mut chain = String::from("b0 = x;");
    for i in 1..5000 {
        chain.push_str(&format!(" b{i} = b{} + 1;", i - 1));
    }
    chain.push_str(" b4999");
    assert_eq!(at(&chain, 0.5, 0.0, 0.0), 4999.5);
    // Printing such tapes keeps the text within the nesting limits.
    for src in [
        chain,
        sum,
        format!("{}x{}", "sin(".repeat(150), ")".repeat(150)),
    ] {
        let t = tape(&src);
        let back = tape(&t.to_formula());
        assert!(same(t.eval(0.5, 0.0, 0.0), back.eval(0.5, 0.0, 0.0)));
    }
    // A near-limit tree parses, compiles, prints and drops on a test thread's stack.
    let near = vec!["x"; MAX_TREE_DEPTH - 1].join(" + ");
    let p = parse_program(&near).unwrap();
    assert_eq!(parse_program(&p.to_string()).unwrap(), p);
    assert_eq!(
        compile(&p).unwrap().eval(1.0, 0.0, 0.0),
        (MAX_TREE_DEPTH - 1) as f64
    );
}

/// Flat sums and products of 100 000 terms parse, compile, evaluate, print and drop
/// without deep recursion, into the tape of the same chain written with bindings; their
/// printed text parses back to the same program.
#[test]
fn long_flat_chains_parse() {
    let n = 100_000;
    let terms: Vec<String> = (0..n).map(|k| format!("{}*x^2", k % 7 + 1)).collect();
    let sum = terms.join(" + ");
    let t = tape(&sum);
    // The same chain, cut into bindings by hand every 1000 terms.
    let mut chained = String::new();
    for (c, chunk) in terms.chunks(1000).enumerate() {
        let head = if c == 0 {
            String::new()
        } else {
            format!("c{} + ", c - 1)
        };
        chained.push_str(&format!("c{c} = {head}{};\n", chunk.join(" + ")));
    }
    chained.push_str(&format!("c{}", n / 1000 - 1));
    let by_hand = tape(&chained);
    for &(x, y, z) in &[(0.5, 0.0, 0.0), (-1.25, 3.0, 1.0), (1e-3, 0.0, 0.0)] {
        let (a, b) = (t.eval(x, y, z), by_hand.eval(x, y, z));
        assert!(same(a, b), "{a} vs {b}");
    }
    // The sum of k % 7 + 1 over k < n, times x^2: exact at x = 1.
    let total: u64 = (0..n as u64).map(|k| k % 7 + 1).sum();
    assert_eq!(t.eval(1.0, 0.0, 0.0), total as f64);
    let r = t.eval(
        arith_ia::Interval::input(0, 0.5, 1.0),
        arith_ia::Interval::input(1, 0.0, 0.0),
        arith_ia::Interval::input(2, 0.0, 0.0),
    );
    let (lo, hi) = r.bounds();
    assert!(
        lo <= total as f64 * 0.25 && hi >= total as f64,
        "[{lo}, {hi}]"
    );
    // Products too, and bindings over long chains.
    let prod = vec!["x"; n].join(" * ");
    assert_eq!(at(&prod, 1.0, 0.0, 0.0), 1.0);
    assert_eq!(at(&prod, -1.0, 0.0, 0.0), 1.0);
    let bound = format!(
        "a = {}; a - {}",
        vec!["y"; n].join(" + "),
        vec!["x"; n].join(" - ")
    );
    assert_eq!(at(&bound, 0.5, 1.0, 0.0), (n / 2) as f64);
    // The hidden bindings print as ordinary ones, and the text parses back the same.
    let p = parse_program(&prod).unwrap();
    assert!(p.bindings.len() >= n / MAX_TREE_DEPTH);
    let text = p.to_string();
    assert_eq!(parse_program(&text).unwrap(), p);
    // Hidden names avoid every name of the text: here `_h0` is the user's.
    let clash = format!("_h0 = 2; {} + _h0", vec!["x"; 5000].join(" + "));
    assert_eq!(at(&clash, 1.0, 0.0, 0.0), 5002.0);
    let p = parse_program(&clash).unwrap();
    assert_eq!(p.bindings[0].name, "_h0");
    assert!(p.bindings[1..].iter().all(|b| b.name.starts_with("__h")));
    // Genuinely nested input still has its limit.
    let deep = format!("{}x{}", "(".repeat(n), ")".repeat(n));
    assert!(err(&deep).message.contains("nested too deeply"));
}

// ---------------------------------------------------------------- the paper's CSG model

/// Appendix A "CSG" of the revised-affine paper, as text.
const CSG: &str = "
    # f = b | (s & ((c1 \\ c2) | (c3 \\ c4)) \\ c5), Appendix A
    b = (0.36 - x^2) & (0.36 - y^2) & (0.36 - z^2);
    s = 0.7056 - x^2 - y^2 - z^2;
    c1 = 0.09 - y^2 - z^2;
    c2 = 0.04 - y^2 - z^2;
    c3 = 0.09 - x^2 - z^2;
    c4 = 0.04 - x^2 - z^2;
    c5 = 0.25 - x^2 - y^2;
    b | (s & ((c1 \\ c2) | (c3 \\ c4)) \\ c5)
";

/// The same model written in Rust, generic over `Real`.
fn csg_rust<R: Real>(x: R, y: R, z: R) -> R {
    let (x2, y2, z2) = (x.sqr(), y.sqr(), z.sqr());
    let b = intersect(
        intersect(x2.clone().rsub(0.36), y2.clone().rsub(0.36)),
        z2.clone().rsub(0.36),
    );
    let s = x2.clone().rsub(0.7056) - y2.clone() - z2.clone();
    let c1 = y2.clone().rsub(0.09) - z2.clone();
    let c2 = y2.clone().rsub(0.04) - z2.clone();
    let c3 = x2.clone().rsub(0.09) - z2.clone();
    let c4 = x2.clone().rsub(0.04) - z2;
    let c5 = x2.rsub(0.25) - y2;
    union(
        b,
        subtract(intersect(s, union(subtract(c1, c2), subtract(c3, c4))), c5),
    )
}

proptest! {
    #[test]
    fn csg_text_matches_rust(x in -1.0..1.0f64, y in -1.0..1.0f64, z in -1.0..1.0f64) {
        let t = tape(CSG);
        prop_assert!(same(t.eval(x, y, z), csg_rust(x, y, z)));
    }
}

#[test]
fn csg_has_both_signs() {
    // Guards the comparison above against a constant function.
    let t = tape(CSG);
    assert!(t.eval(0.0, 0.0, 0.0) > 0.0);
    assert!(t.eval(0.9, 0.9, 0.9) < 0.0);
}

// ---------------------------------------------------------------- ranges

/// Every point value lies in the range computed over the box holding it.
fn check_ranges<R: Range>(src: &str, boxes: &[[(f64, f64); 3]], steps: usize) {
    let t = tape(src);
    for b in boxes {
        let r = t.eval(
            R::input(0, b[0].0, b[0].1),
            R::input(1, b[1].0, b[1].1),
            R::input(2, b[2].0, b[2].1),
        );
        let (lo, hi) = r.bounds();
        assert!(!lo.is_nan() && !hi.is_nan());
        for i in 0..=steps {
            for j in 0..=steps {
                for k in 0..=steps {
                    let p =
                        |d: usize, s: usize| b[d].0 + (b[d].1 - b[d].0) * s as f64 / steps as f64;
                    let v = t.eval(p(0, i), p(1, j), p(2, k));
                    assert!(
                        v.is_nan() || (lo <= v && v <= hi),
                        "{} over {b:?}: f = {v} outside [{lo}, {hi}]",
                        R::NAME
                    );
                }
            }
        }
    }
}

fn range_suite<R: Range>() {
    let boxes = [
        [(-1.0, 1.0), (-1.0, 1.0), (-1.0, 1.0)],
        [(0.1, 0.3), (-0.2, 0.05), (0.5, 0.7)],
        [(-0.6, -0.55), (0.2, 0.25), (-0.01, 0.01)],
        [(0.35, 0.45), (0.0, 0.1), (0.0, 0.0)],
    ];
    check_ranges::<R>(CSG, &boxes, 6);
    check_ranges::<R>(
        "20 * (x^2 + y^2 + z^2) - 4 * (x^4 + (y^2 + z^2)^2) - 17*x^2 * (y^2 + z^2) - 17",
        &boxes,
        6,
    );
    check_ranges::<R>(
        "s = sin(3*x) * cos(2*y); sqrt(abs(s)) + exp(z) / 3 - ln(x^2 + 1) + min(x, y) * max(y, z) + x^-2 & 0.1 - z",
        &boxes,
        6,
    );
    // `tan` = `sin / cos`: bounded off its poles (x = +-pi/2 in [-2, 2]), the whole line
    // over one.
    check_ranges::<R>("tan(2*x) * y + tan(z)", &boxes, 6);
    let t = tape("tan(x)");
    let over = |a: f64, b: f64| {
        let i = R::input(0, a, b);
        t.eval(i.clone(), i.clone(), i).bounds()
    };
    let (lo, hi) = over(1.5, 1.6);
    assert!(
        lo == f64::NEG_INFINITY && hi == f64::INFINITY,
        "[{lo}, {hi}]"
    );
    let (lo, hi) = over(0.0, 1.0);
    assert!(lo <= 0.0 && hi >= 1.0f64.tan() && hi < 2.0, "[{lo}, {hi}]");
}

/// One `ranges_enclose_points` test per arithmetic of the one list (module named after
/// its `ArithKind` variant), over its cell form.
macro_rules! per_arithmetic {
    ([ $($variant:ident => $family:path),* $(,)? ]) => {
        $(
            #[allow(non_snake_case)]
            mod $variant {
                #[test]
                fn ranges_enclose_points() {
                    super::range_suite::<<$family as arith_core::Arithmetic>::Cell>();
                }
            }
        )*
    };
}
model_ir::arith_list!([per_arithmetic] {});

#[test]
fn tape_is_a_shape() {
    fn via_shape<S: model_ir::shape::Shape>(s: &S) -> f64 {
        s.eval(0.5, 0.25, 0.0)
    }
    assert_eq!(via_shape(&tape("x + y")), 0.75);
}

// ---------------------------------------------------------------- round trips

fn leaf() -> impl Strategy<Value = Expr> {
    prop_oneof![
        (0.0..100.0f64).prop_map(Expr::Num),
        select(vec![0.0, 0.5, 1.0, 2.0, 3.0, 0.1, 1e-7, 2.5e21, 1e300]).prop_map(Expr::Num),
        select(vec![Var::X, Var::Y, Var::Z]).prop_map(Expr::Var),
        (0usize..6).prop_map(Expr::Ref),
    ]
}

fn expr() -> impl Strategy<Value = Expr> {
    leaf().prop_recursive(6, 64, 2, |inner| {
        prop_oneof![
            inner.clone().prop_map(Expr::neg),
            (inner.clone(), -3i32..=5).prop_map(|(a, n)| Expr::pow(a, n)),
            (inner.clone(), select(vec![0.5, 2.5, -1.5, 1e-3]))
                .prop_map(|(a, c)| Expr::PowF(Box::new(a), c)),
            (
                select(Func::ALL.to_vec()),
                prop::collection::vec(inner.clone(), 5)
            )
                .prop_map(|(f, mut args)| {
                    args.truncate(f.arity());
                    Expr::Call(f, args)
                }),
            (select(BinOp::ALL.to_vec()), inner.clone(), inner.clone())
                .prop_map(|(op, a, b)| Expr::bin(op, a, b)),
            (select(BinOp::ALL.to_vec()), inner.clone(), inner)
                .prop_map(|(op, a, b)| Expr::bin(op, a, b)),
        ]
    })
}

/// Makes references point at earlier bindings only (`x` where there are none).
fn fix_refs(e: &mut Expr, bound: usize) {
    match e {
        Expr::Ref(i) => {
            if bound == 0 {
                *e = Expr::Var(Var::X);
            } else {
                *i %= bound;
            }
        }
        Expr::Num(_) | Expr::Var(_) => {}
        Expr::Neg(a) | Expr::Pow(a, _) | Expr::PowF(a, _) => fix_refs(a, bound),
        Expr::Call(_, args) => args.iter_mut().for_each(|a| fix_refs(a, bound)),
        Expr::Bin(_, a, b) => {
            fix_refs(a, bound);
            fix_refs(b, bound);
        }
    }
}

fn program() -> impl Strategy<Value = Program> {
    (prop::collection::vec(expr(), 0..4), expr()).prop_map(|(binds, mut body)| {
        let n = binds.len();
        let bindings = binds
            .into_iter()
            .enumerate()
            .map(|(i, mut e)| {
                fix_refs(&mut e, i);
                Binding {
                    name: format!("b{i}"),
                    expr: e,
                }
            })
            .collect();
        fix_refs(&mut body, n);
        Program { bindings, body }
    })
}

/// The parser's refusal of a constant zero divisor or `ln` of a constant `<= 0`, which
/// generated trees may hold (the compiler takes them).
fn degenerate(e: &ParseError) -> bool {
    e.message.starts_with("division by zero") || e.message.starts_with("ln of the constant")
}

const POINTS: [(f64, f64, f64); 5] = [
    (0.3, -0.7, 1.1),
    (-1.9, 0.25, -0.4),
    (2.0, 2.0, 0.0),
    (0.0, 1e-3, -3.5),
    (1.0, -1.0, 0.5),
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// AST -> text -> AST is the identity, so the tapes agree too.
    #[test]
    fn ast_print_parse_round_trip(p in program()) {
        let text = p.to_string();
        let back = match parse_program(&text) {
            Ok(b) => b,
            Err(e) if degenerate(&e) => return Ok(()),
            Err(e) => return Err(TestCaseError::fail(format!("{}\n{:?}", e.render(&text), p))),
        };
        prop_assert_eq!(&back, &p, "{}", text);
        let (t1, t2) = (compile(&p).unwrap(), parse(&text).unwrap());
        for &(x, y, z) in &POINTS {
            prop_assert!(same(t1.eval(x, y, z), t2.eval(x, y, z)), "{}", text);
        }
    }

    /// Tape -> text -> tape gives the same values bit for bit.
    #[test]
    fn tape_print_parse_round_trip(p in program()) {
        let t1 = compile(&p).unwrap();
        let text = t1.to_formula();
        let t2 = match parse(&text) {
            Ok(t) => t,
            Err(e) if degenerate(&e) => return Ok(()),
            Err(e) => return Err(TestCaseError::fail(format!("{}\n{}", e.render(&text), t1))),
        };
        prop_assert!(t2.len() <= t1.len(), "{}\n{}\n{}", text, t1, t2);
        for &(x, y, z) in &POINTS {
            let (a, b) = (t1.eval(x, y, z), t2.eval(x, y, z));
            prop_assert!(same(a, b), "{} vs {} for {}\n{}", a, b, text, t1);
        }
        // And over a range type.
        let r = |t: &Tape| {
            t.eval(
                arith_ia::Interval::input(0, 0.1, 0.4),
                arith_ia::Interval::input(1, -0.8, -0.6),
                arith_ia::Interval::input(2, 1.0, 1.2),
            )
        };
        let (a, b) = (r(&t1).bounds(), r(&t2).bounds());
        prop_assert!(same(a.0, b.0) && same(a.1, b.1), "{:?} vs {:?} for {}", a, b, text);
    }

    /// Arbitrary text never panics: it parses (and then evaluates and prints) or gives
    /// an error whose position lies within the text.
    #[test]
    fn random_text_never_panics(
        src in prop_oneof![
            ".{0,40}",
            "[xyzabsinqrtcoelmp0-9.eE+*/^()&|\\\\,;=# _\n-]{0,40}",
            "[xyz0-9.()^+*-]{0,24}",
        ]
    ) {
        match parse(&src) {
            Ok(t) => {
                let _ = t.eval(0.3, -0.7, 1.1);
                let _ = t.eval(
                    arith_ia::Interval::input(0, -1.0, 1.0),
                    arith_ia::Interval::input(1, -1.0, 1.0),
                    arith_ia::Interval::input(2, -1.0, 1.0),
                );
                let text = t.to_formula();
                prop_assert!(parse(&text).is_ok(), "{} printed as {}", src, text);
            }
            Err(e) => {
                prop_assert!(e.pos <= src.chars().count());
                prop_assert!(e.line >= 1 && e.column >= 1);
                let _ = e.render(&src);
            }
        }
    }
}
