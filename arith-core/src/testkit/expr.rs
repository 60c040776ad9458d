//! Random expression trees over three inputs and constants, using every [`Real`]
//! operation, evaluated generically and at points with the [`Mp`] reference.

use super::mp::Mp;
use super::strategies::small_const;
use crate::Real;
use core::fmt;
use proptest::prelude::*;
use proptest::strategy::BoxedStrategy;

/// A unary operation (including the `f64`-operand ones).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Un {
    /// `-x`
    Neg,
    /// `x.sqr()`
    Sqr,
    /// `x.powi(n)`
    Powi(i32),
    /// `x.sqrt()` (extended: `sqrt(max(x, 0))`)
    Sqrt,
    /// `x.recip()`
    Recip,
    /// `x.exp()`
    Exp,
    /// `x.ln()` (extended: `-inf` for `x <= 0`)
    Ln,
    /// `x.sin()`
    Sin,
    /// `x.cos()`
    Cos,
    /// `x.abs()`
    Abs,
    /// `x + c`
    AddF(f64),
    /// `x - c`
    SubF(f64),
    /// `x * c`
    MulF(f64),
    /// `x / c`
    DivF(f64),
    /// `x.rsub(c)` = `c - x`
    RSubF(f64),
    /// `x.rdiv(c)` = `c / x`
    RDivF(f64),
}

/// A binary operation on two ranges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bin {
    /// `x + y`
    Add,
    /// `x - y`
    Sub,
    /// `x * y`
    Mul,
    /// `x / y`
    Div,
    /// `x.min(&y)`
    Min,
    /// `x.max(&y)`
    Max,
    /// `x.hypot(&y)` = `sqrt(x^2 + y^2)`
    Hypot,
}

impl Un {
    /// Applies the operation to any [`Real`].
    pub fn apply<R: Real>(self, x: R) -> R {
        match self {
            Un::Neg => -x,
            Un::Sqr => x.sqr(),
            Un::Powi(n) => x.powi(n),
            Un::Sqrt => x.sqrt(),
            Un::Recip => x.recip(),
            Un::Exp => x.exp(),
            Un::Ln => x.ln(),
            Un::Sin => x.sin(),
            Un::Cos => x.cos(),
            Un::Abs => x.abs(),
            Un::AddF(c) => x + c,
            Un::SubF(c) => x - c,
            Un::MulF(c) => x * c,
            Un::DivF(c) => x / c,
            Un::RSubF(c) => x.rsub(c),
            Un::RDivF(c) => x.rdiv(c),
        }
    }

    /// The reference enclosure (`None`: undefined at this point).
    pub fn reference(self, x: &Mp) -> Option<Mp> {
        let c = |c: f64| Mp::point_p(c, x.prec());
        match self {
            Un::Neg => Some(x.neg()),
            Un::Sqr => x.sqr(),
            Un::Powi(n) => x.powi(n),
            Un::Sqrt => x.sqrt(),
            Un::Recip => x.recip(),
            Un::Exp => x.exp(),
            Un::Ln => x.ln(),
            Un::Sin => x.sin(),
            Un::Cos => x.cos(),
            Un::Abs => Some(x.abs()),
            Un::AddF(k) => x.add(&c(k)?),
            Un::SubF(k) => x.sub(&c(k)?),
            Un::MulF(k) => x.mul(&c(k)?),
            Un::DivF(k) => x.div(&c(k)?),
            Un::RSubF(k) => c(k)?.sub(x),
            Un::RDivF(k) => c(k)?.div(x),
        }
    }
}

impl Bin {
    /// Applies the operation to any [`Real`].
    pub fn apply<R: Real>(self, x: R, y: R) -> R {
        match self {
            Bin::Add => x + y,
            Bin::Sub => x - y,
            Bin::Mul => x * y,
            Bin::Div => x / y,
            Bin::Min => x.min(&y),
            Bin::Max => x.max(&y),
            Bin::Hypot => x.hypot(&y),
        }
    }

    /// The reference enclosure (`None`: undefined at this point).
    pub fn reference(self, x: &Mp, y: &Mp) -> Option<Mp> {
        match self {
            Bin::Add => x.add(y),
            Bin::Sub => x.sub(y),
            Bin::Mul => x.mul(y),
            Bin::Div => x.div(y),
            Bin::Min => Some(x.min(y)),
            Bin::Max => Some(x.max(y)),
            Bin::Hypot => x.sqr()?.add(&y.sqr()?)?.sqrt(),
        }
    }
}

/// An expression over inputs `x0, x1, x2` (the same index twice is the same variable)
/// and constants.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// Input `i` (`Range::input(i, ..)` in range evaluation).
    Input(usize),
    /// A constant (`Real::constant`).
    Const(f64),
    /// A unary operation.
    Unary(Un, Box<Expr>),
    /// A binary operation.
    Binary(Bin, Box<Expr>, Box<Expr>),
}

impl Expr {
    /// `op(a)`.
    pub fn un(op: Un, a: Expr) -> Expr {
        Expr::Unary(op, Box::new(a))
    }

    /// `op(a, b)`.
    pub fn bin(op: Bin, a: Expr, b: Expr) -> Expr {
        Expr::Binary(op, Box::new(a), Box::new(b))
    }

    /// Evaluates over any [`Real`]; `inputs[i]` is input `i` (cloned at each use, so
    /// affine forms keep their correlation). Panics if an input index is out of range
    /// (a test-writing error).
    pub fn eval<R: Real>(&self, inputs: &[R]) -> R {
        match self {
            Expr::Input(i) => inputs[*i].clone(),
            Expr::Const(c) => R::constant(*c),
            Expr::Unary(op, a) => op.apply(a.eval(inputs)),
            Expr::Binary(op, a, b) => op.apply(a.eval(inputs), b.eval(inputs)),
        }
    }

    /// A rigorous enclosure of the exact value at the point whose coordinates are
    /// enclosed by `inputs`; `None` where undefined (division by a value that may be
    /// exactly 0, `inf - inf`, `0 * inf`).
    pub fn reference(&self, inputs: &[Mp]) -> Option<Mp> {
        match self {
            Expr::Input(i) => Some(inputs[*i].clone()),
            Expr::Const(c) => Mp::point_p(*c, inputs.first().map_or(super::mp::PREC, Mp::prec)),
            Expr::Unary(op, a) => op.reference(&a.reference(inputs)?),
            Expr::Binary(op, a, b) => op.reference(&a.reference(inputs)?, &b.reference(inputs)?),
        }
    }

    /// [`Expr::reference`] at an `f64` point, with `prec` bits.
    pub fn reference_at(&self, point: &[f64], prec: usize) -> Option<Mp> {
        let inputs: Option<Vec<Mp>> = point.iter().map(|&x| Mp::point_p(x, prec)).collect();
        self.reference(&inputs?)
    }

    /// Depth of the tree (a leaf has depth 0).
    pub fn depth(&self) -> usize {
        match self {
            Expr::Input(_) | Expr::Const(_) => 0,
            Expr::Unary(_, a) => 1 + a.depth(),
            Expr::Binary(_, a, b) => 1 + a.depth().max(b.depth()),
        }
    }

    /// Number of nodes.
    pub fn size(&self) -> usize {
        match self {
            Expr::Input(_) | Expr::Const(_) => 1,
            Expr::Unary(_, a) => 1 + a.size(),
            Expr::Binary(_, a, b) => 1 + a.size() + b.size(),
        }
    }
}

impl fmt::Display for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Expr::Input(i) => write!(f, "x{i}"),
            Expr::Const(c) => write!(f, "{c:?}"),
            Expr::Unary(op, a) => match op {
                Un::Neg => write!(f, "-({a})"),
                Un::Powi(n) => write!(f, "powi({a}, {n})"),
                Un::AddF(c) => write!(f, "({a} + {c:?})"),
                Un::SubF(c) => write!(f, "({a} - {c:?})"),
                Un::MulF(c) => write!(f, "({a} * {c:?})"),
                Un::DivF(c) => write!(f, "({a} / {c:?})"),
                Un::RSubF(c) => write!(f, "({c:?} - {a})"),
                Un::RDivF(c) => write!(f, "({c:?} / {a})"),
                other => write!(f, "{}({a})", format!("{other:?}").to_lowercase()),
            },
            Expr::Binary(op, a, b) => match op {
                Bin::Add => write!(f, "({a} + {b})"),
                Bin::Sub => write!(f, "({a} - {b})"),
                Bin::Mul => write!(f, "({a} * {b})"),
                Bin::Div => write!(f, "({a} / {b})"),
                Bin::Min => write!(f, "min({a}, {b})"),
                Bin::Max => write!(f, "max({a}, {b})"),
                Bin::Hypot => write!(f, "hypot({a}, {b})"),
            },
        }
    }
}

/// Every unary operation, `powi` exponents in `-3..=5`, `f64` operands from
/// [`small_const`].
pub fn un_strategy() -> BoxedStrategy<Un> {
    un_strategy_with(1, (-3i32..=5).boxed(), small_const)
}

/// Every unary operation, `powi` (weight `powi_weight` against 1 for each other
/// operation) with exponents from `powi`, `f64` operands from `c`.
pub fn un_strategy_with(
    powi_weight: u32,
    powi: BoxedStrategy<i32>,
    c: fn() -> BoxedStrategy<f64>,
) -> BoxedStrategy<Un> {
    prop_oneof![
        1 => Just(Un::Neg),
        1 => Just(Un::Sqr),
        powi_weight => powi.prop_map(Un::Powi),
        1 => Just(Un::Sqrt),
        1 => Just(Un::Recip),
        1 => Just(Un::Exp),
        1 => Just(Un::Ln),
        1 => Just(Un::Sin),
        1 => Just(Un::Cos),
        1 => Just(Un::Abs),
        1 => c().prop_map(Un::AddF),
        1 => c().prop_map(Un::SubF),
        1 => c().prop_map(Un::MulF),
        1 => c().prop_map(Un::DivF),
        1 => c().prop_map(Un::RSubF),
        1 => c().prop_map(Un::RDivF),
    ]
    .boxed()
}

/// Every binary operation.
pub const BINS: [Bin; 7] = [
    Bin::Add,
    Bin::Sub,
    Bin::Mul,
    Bin::Div,
    Bin::Min,
    Bin::Max,
    Bin::Hypot,
];

/// Every binary operation ([`BINS`]), uniformly.
pub fn bin_strategy() -> BoxedStrategy<Bin> {
    bin_strategy_of(&BINS)
}

/// The binary operations `ops`, uniformly.
pub fn bin_strategy_of(ops: &'static [Bin]) -> BoxedStrategy<Bin> {
    proptest::sample::select(ops).boxed()
}

/// Random trees of depth up to `depth` over inputs `0..inputs` and constants in
/// `[-4, 4]`, using every operation. An `exp` argument is, two times in three, damped
/// (`exp(0.25 * a)` or `exp(sin(a))`) so that deep trees are not mostly overflow; the
/// undamped third still exercises overflow.
pub fn expr_strategy(depth: u32, inputs: usize) -> BoxedStrategy<Expr> {
    assert!(inputs >= 1);
    let leaf = prop_oneof![
        3 => (0..inputs).prop_map(Expr::Input),
        1 => small_const().prop_map(Expr::Const),
    ];
    leaf.prop_recursive(depth, 48, 2, |inner| {
        prop_oneof![
            3 => (un_strategy(), 0u8..3, inner.clone()).prop_map(|(op, damp, a)| {
                if op == Un::Exp {
                    let a = match damp {
                        0 => a,
                        1 => Expr::un(Un::MulF(0.25), a),
                        _ => Expr::un(Un::Sin, a),
                    };
                    Expr::un(Un::Exp, a)
                } else {
                    Expr::un(op, a)
                }
            }),
            2 => (bin_strategy(), inner.clone(), inner).prop_map(|(op, a, b)| Expr::bin(op, a, b)),
        ]
    })
    .boxed()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testkit::mp::Verdict;
    use proptest::test_runner::TestRunner;

    #[test]
    fn f64_eval_agrees_with_reference_on_exact_trees() {
        // (x0 + 1.5) * x1 - min(x0, 2) is exact in f64 for these small dyadic values.
        let e = Expr::bin(
            Bin::Sub,
            Expr::bin(
                Bin::Mul,
                Expr::un(Un::AddF(1.5), Expr::Input(0)),
                Expr::Input(1),
            ),
            Expr::bin(Bin::Min, Expr::Input(0), Expr::Const(2.0)),
        );
        let v = e.eval(&[0.25f64, -3.0]);
        assert_eq!(v, (0.25 + 1.5) * -3.0 - 0.25);
        let r = e.reference_at(&[0.25, -3.0], 256).unwrap();
        assert_eq!(r.verdict(v, v), Verdict::Inside);
        assert_eq!(r.verdict(v.next_up(), 10.0), Verdict::Outside);
        assert_eq!(format!("{e}"), "(((x0 + 1.5) * x1) - min(x0, 2.0))");
    }

    #[test]
    fn division_by_exact_zero_is_undefined() {
        let e = Expr::bin(
            Bin::Div,
            Expr::Const(1.0),
            Expr::bin(Bin::Sub, Expr::Input(0), Expr::Input(0)),
        );
        assert!(e.reference_at(&[0.3], 256).is_none());
        assert!(Expr::un(Un::DivF(0.0), Expr::Input(0))
            .reference_at(&[1.0], 256)
            .is_none());
    }

    #[test]
    fn trees_respect_depth_and_use_all_inputs_somewhere() {
        let mut runner = TestRunner::deterministic();
        let mut seen = [false; 3];
        for _ in 0..200 {
            let t = expr_strategy(6, 3).new_tree(&mut runner).unwrap().current();
            // Damped exp adds at most one level per exp node on the path.
            assert!(t.depth() <= 12, "{t}");
            fn mark(e: &Expr, seen: &mut [bool; 3]) {
                match e {
                    Expr::Input(i) => seen[*i] = true,
                    Expr::Const(_) => {}
                    Expr::Unary(_, a) => mark(a, seen),
                    Expr::Binary(_, a, b) => {
                        mark(a, seen);
                        mark(b, seen)
                    }
                }
            }
            mark(&t, &mut seen);
        }
        assert_eq!(seen, [true; 3]);
    }

    #[test]
    fn f64_point_eval_lies_near_reference() {
        // Sanity check of the reference against plain f64 on a smooth tree.
        let e = Expr::bin(
            Bin::Add,
            Expr::un(Un::Sin, Expr::Input(0)),
            Expr::un(Un::Exp, Expr::Input(1)),
        );
        let v = e.eval(&[0.7f64, -0.3]);
        let r = e.reference_at(&[0.7, -0.3], 256).unwrap();
        assert_eq!(r.verdict(v - 1e-15, v + 1e-15), Verdict::Inside);
    }
}
