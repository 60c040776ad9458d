//! The gradient kernel: forward-mode dual numbers over eight-lane blocks of `f64`, a
//! value and its three partials per lane, each instruction's chain rule as plain lane
//! operations.
//!
//! Every formula is the one of [`arith_core::dual::Dual`] over `f64`, operation for
//! operation and in the same order (a product's partials are `da * b + db * a`, a
//! quotient's `(da - db * q) / b`, `min`/`max`/`abs` take the partials of the side the
//! values pick, a selection the branch its truth value picks, a step has zero
//! partials; the R-functions are their compositions), so each lane is, bit for bit,
//! what [`crate::Tape::eval`] gives over `Dual<f64>` (NaN payloads aside). No
//! rounding is directed: these are points, as the point kernel's. `exp`, `ln`, `sin`,
//! `cos` and `powi` take their value and derivative lane by lane from the scalar
//! functions, then the chain rule in lanes.

use super::parts::{PartOps, Step};
use super::points::{real_max, real_min, real_sqrt};
use crate::instr::{Instr, Op};
use arith_core::lanes::{F64x8, Isa, LANES};
use arith_core::Real;

/// The gradient kernel's values ([`super::parts`]): four blocks per register and block
/// index, the values, then the partials by `x`, `y`, `z`.
pub(crate) struct Duals;

/// Blocks per register and block index.
const PARTS: usize = 4;

/// Eight dual numbers in registers: values and partials.
#[derive(Clone, Copy)]
struct D<V> {
    v: V,
    g: [V; 3],
}

/// `Dual::constant(c)`: the value `c`, zero partials.
#[inline(always)]
fn constant<I: Isa>(s: I, c: f64) -> D<I::V> {
    let zero = s.splat(0.0);
    D {
        v: s.splat(c),
        g: [zero; 3],
    }
}

/// `[f(0), f(1), f(2)]`: the three partials, written out (`array::map` and `from_fn`
/// need not inline, and a lane operation outside the path's target-feature function
/// becomes a call).
#[inline(always)]
fn each<V>(f: impl Fn(usize) -> V) -> [V; 3] {
    [f(0), f(1), f(2)]
}

/// Value `v`, partials `a.g * dv` (the chain rule of a unary function).
#[inline(always)]
fn chain<I: Isa>(s: I, a: D<I::V>, v: I::V, dv: I::V) -> D<I::V> {
    D {
        v,
        g: each(|k| s.mul(a.g[k], dv)),
    }
}

/// Each part `f(a, b)`.
#[inline(always)]
fn zip<I: Isa>(a: D<I::V>, b: D<I::V>, f: impl Fn(I::V, I::V) -> I::V) -> D<I::V> {
    D {
        v: f(a.v, b.v),
        g: [f(a.g[0], b.g[0]), f(a.g[1], b.g[1]), f(a.g[2], b.g[2])],
    }
}

/// `a` where `m`, else `b`, every part.
#[inline(always)]
fn pick<I: Isa>(s: I, m: I::M, a: D<I::V>, b: D<I::V>) -> D<I::V> {
    zip::<I>(a, b, |x, y| s.select(m, x, y))
}

#[inline(always)]
fn neg<I: Isa>(s: I, a: D<I::V>) -> D<I::V> {
    D {
        v: s.neg(a.v),
        g: each(|k| s.neg(a.g[k])),
    }
}

#[inline(always)]
fn add<I: Isa>(s: I, a: D<I::V>, b: D<I::V>) -> D<I::V> {
    zip::<I>(a, b, |x, y| s.add(x, y))
}

#[inline(always)]
fn sub<I: Isa>(s: I, a: D<I::V>, b: D<I::V>) -> D<I::V> {
    zip::<I>(a, b, |x, y| s.sub(x, y))
}

/// `a + c` for a constant: the partials unchanged.
#[inline(always)]
fn add_c<I: Isa>(s: I, a: D<I::V>, c: I::V) -> D<I::V> {
    D {
        v: s.add(a.v, c),
        g: a.g,
    }
}

/// `a * c` for a constant, every part.
#[inline(always)]
fn mul_c<I: Isa>(s: I, a: D<I::V>, c: I::V) -> D<I::V> {
    D {
        v: s.mul(a.v, c),
        g: each(|k| s.mul(a.g[k], c)),
    }
}

/// The product rule, `(a b)' = a' b + b' a`.
#[inline(always)]
fn mul<I: Isa>(s: I, a: D<I::V>, b: D<I::V>) -> D<I::V> {
    D {
        v: s.mul(a.v, b.v),
        g: each(|k| s.add(s.mul(a.g[k], b.v), s.mul(b.g[k], a.v))),
    }
}

/// The quotient rule, `(a / b)' = (a' - b' q) / b` with `q = a / b`.
#[inline(always)]
fn div<I: Isa>(s: I, a: D<I::V>, b: D<I::V>) -> D<I::V> {
    let q = s.div(a.v, b.v);
    D {
        v: q,
        g: each(|k| s.div(s.sub(a.g[k], s.mul(b.g[k], q)), b.v)),
    }
}

/// `a^2`, derivative `2 a`.
#[inline(always)]
fn sqr<I: Isa>(s: I, a: D<I::V>) -> D<I::V> {
    chain(s, a, s.mul(a.v, a.v), s.mul(a.v, s.splat(2.0)))
}

/// `1 / a`, derivative `-(1/a)^2`.
#[inline(always)]
fn recip<I: Isa>(s: I, a: D<I::V>) -> D<I::V> {
    let r = s.div(s.splat(1.0), a.v);
    chain(s, a, r, s.neg(s.mul(r, r)))
}

/// `Real::sqrt` for `f64` (the root of `max(a, +0)`), derivative `1 / (2 sqrt a)`.
#[inline(always)]
fn sqrt<I: Isa>(s: I, a: D<I::V>) -> D<I::V> {
    let r = real_sqrt(s, a.v);
    chain(s, a, r, s.div(s.splat(1.0), s.mul(r, s.splat(2.0))))
}

/// `sqrt(a^2 + b^2)` with the partials `(a/h) a' + (b/h) b'`, each ratio kept in
/// `[-1, 1]` and 0 where it is NaN (`Dual::hypot`'s `unit_ratio` for points).
#[inline(always)]
fn hypot<I: Isa>(s: I, a: D<I::V>, b: D<I::V>) -> D<I::V> {
    let h = real_sqrt(s, s.add(s.mul(a.v, a.v), s.mul(b.v, b.v)));
    let unit = |x: I::V| {
        let q = s.div(x, h);
        let clamped = s.max(s.min(q, s.splat(1.0)), s.splat(-1.0));
        s.select(s.unord(q, q), s.splat(0.0), clamped)
    };
    let (ra, rb) = (unit(a.v), unit(b.v));
    D {
        v: h,
        g: each(|k| s.add(s.mul(ra, a.g[k]), s.mul(rb, b.g[k]))),
    }
}

/// `min(a, b)`: the partials of `a` where `a <= b`, else of `b` (NaN included).
#[inline(always)]
fn min<I: Isa>(s: I, a: D<I::V>, b: D<I::V>) -> D<I::V> {
    let mut r = pick(s, s.le(a.v, b.v), a, b);
    r.v = real_min(s, a.v, b.v);
    r
}

/// `max(a, b)`: the partials of `b` where `a <= b`, else of `a` (NaN included).
#[inline(always)]
fn max<I: Isa>(s: I, a: D<I::V>, b: D<I::V>) -> D<I::V> {
    let mut r = pick(s, s.le(a.v, b.v), b, a);
    r.v = real_max(s, a.v, b.v);
    r
}

/// The step `d > 0` (`strict`) or `d >= 0`: 1 or 0, zero partials.
#[inline(always)]
fn step<I: Isa>(s: I, a: D<I::V>, strict: bool) -> D<I::V> {
    let zero = s.splat(0.0);
    let holds = if strict {
        s.lt(zero, a.v)
    } else {
        s.le(zero, a.v)
    };
    D {
        v: s.select(holds, s.splat(1.0), zero),
        g: [zero; 3],
    }
}

/// `sqrt(a^2 + b^2 + 0.5 / (1 + a^2 + b^2))`, the blends' root, as `rfunc` composes it.
#[inline(always)]
fn blend_root<I: Isa>(s: I, a: D<I::V>, b: D<I::V>) -> D<I::V> {
    let sum = add(s, sqr(s, a), sqr(s, b));
    let bump = mul_c(s, recip(s, add_c(s, sum, s.splat(1.0))), s.splat(0.5));
    sqrt(s, add(s, sum, bump))
}

/// `exp`, `ln`, `sin`, `cos` or `powi` (`n != 0`) of one `f64`, with its derivative,
/// as `Dual` computes them.
fn value_slope(i: &Instr, x: f64) -> (f64, f64) {
    match i.op {
        Op::Exp => {
            let e = Real::exp(&x);
            (e, e)
        }
        Op::Ln => (Real::ln(&x), Real::recip(&x)),
        Op::Sin => (Real::sin(&x), Real::cos(&x)),
        Op::Cos => (Real::cos(&x), -Real::sin(&x)),
        _ => (
            Real::powi(&x, i.n),
            Real::powi(&x, i.n - 1) * f64::from(i.n),
        ),
    }
}

/// One dual number per lane of one block, the instruction's value and slope computed
/// lane by lane from the scalar functions ([`value_slope`]).
#[inline(always)]
fn scalar_chain<I: Isa>(s: I, i: &Instr, a: D<I::V>) -> D<I::V> {
    let x = s.store(a.v);
    let (mut v, mut dv) = (F64x8::default(), F64x8::default());
    for l in 0..LANES {
        (v.0[l], dv.0[l]) = value_slope(i, x.0[l]);
    }
    let (v, dv) = (s.load(&v), s.load(&dv));
    chain(s, a, v, dv)
}

/// Eight dual numbers from their [`PARTS`] blocks.
#[inline(always)]
fn load<I: Isa>(s: I, p: &[F64x8; PARTS]) -> D<I::V> {
    D {
        v: s.load(&p[0]),
        g: [s.load(&p[1]), s.load(&p[2]), s.load(&p[3])],
    }
}

impl PartOps for Duals {
    const PARTS: usize = PARTS;

    /// [`PartOps::instruction`] for dual numbers.
    #[inline(always)]
    fn instruction<I: Isa>(s: I, at: Step<'_>) {
        let i = at.i;
        let c = s.splat(i.c);
        macro_rules! op {
            (|$ops:ident| $body:expr) => {
                at.each::<PARTS>(|w, $ops| {
                    let r: D<I::V> = $body;
                    *w = [
                        s.store(r.v),
                        s.store(r.g[0]),
                        s.store(r.g[1]),
                        s.store(r.g[2]),
                    ];
                })
            };
        }
        macro_rules! un {
            (|$x:ident| $body:expr) => {
                op!(|ops| {
                    let $x = load(s, ops[0]);
                    $body
                })
            };
        }
        macro_rules! bin {
            (|$x:ident, $y:ident| $body:expr) => {
                op!(|ops| {
                    let ($x, $y) = (load(s, ops[0]), load(s, ops[1]));
                    $body
                })
            };
        }
        match i.op {
            Op::X | Op::Y | Op::Z | Op::Const => unreachable!("not an operation on registers"),
            Op::Neg => un!(|x| neg(s, x)),
            Op::Sqr => un!(|x| sqr(s, x)),
            Op::Powi if i.n == 0 => op!(|_ops| constant(s, 1.0)),
            Op::Exp | Op::Ln | Op::Sin | Op::Cos | Op::Powi => un!(|x| scalar_chain(s, i, x)),
            Op::Sqrt => un!(|x| sqrt(s, x)),
            Op::Recip => un!(|x| recip(s, x)),
            // `Dual::abs` is `max(x, -x)`.
            Op::Abs => un!(|x| max(s, x, neg(s, x))),
            Op::AddC => un!(|x| add_c(s, x, c)),
            Op::SubC => un!(|x| D {
                v: s.sub(x.v, c),
                g: x.g,
            }),
            // `Real::rsub` for duals: `-x + c`.
            Op::RSubC => un!(|x| add_c(s, neg(s, x), c)),
            Op::MulC => un!(|x| mul_c(s, x, c)),
            Op::DivC => un!(|x| D {
                v: s.div(x.v, c),
                g: each(|k| s.div(x.g[k], c)),
            }),
            // `Real::rdiv` for duals: `recip(x) * c`.
            Op::RDivC => un!(|x| mul_c(s, recip(s, x), c)),
            Op::Add => bin!(|x, y| add(s, x, y)),
            Op::Sub => bin!(|x, y| sub(s, x, y)),
            Op::Mul => bin!(|x, y| mul(s, x, y)),
            Op::Div => bin!(|x, y| div(s, x, y)),
            Op::Hypot => bin!(|x, y| hypot(s, x, y)),
            Op::Min => bin!(|x, y| min(s, x, y)),
            Op::Max => bin!(|x, y| max(s, x, y)),
            Op::Intersect => bin!(|x, y| sub(s, add(s, x, y), hypot(s, x, y))),
            Op::Union => bin!(|x, y| add(s, add(s, x, y), hypot(s, x, y))),
            Op::Subtract => bin!(|x, y| sub(s, sub(s, x, y), hypot(s, x, y))),
            Op::BlendIntersect => bin!(|x, y| sub(s, add(s, x, y), blend_root(s, x, y))),
            Op::BlendUnion => bin!(|x, y| add(s, add(s, x, y), blend_root(s, x, y))),
            Op::Gt0 => un!(|x| step(s, x, true)),
            Op::Ge0 => un!(|x| step(s, x, false)),
            // The branch the truth value picks, value and partials.
            Op::Select => op!(|ops| {
                let m = s.lt(s.splat(0.5), s.load(&ops[0][0]));
                pick(s, m, load(s, ops[1]), load(s, ops[2]))
            }),
        }
    }
}
