//! The RevAA kernel: a tape over eight-lane blocks of revised affine forms
//! `x0 + Σ xs[i] εi ± e` with `N` input symbols (`RevAa<N>`: a centre, `N`
//! coefficients and the error term per lane), each operation's rounding errors added
//! to `e` upward as the scalar form adds them.
//!
//! The affine operations (`+`, `-`, negation, the constant ones), the product (with its
//! `½ Σ xi yi` centre shift and cross terms) and the square (the Chebyshev square where
//! its gain survives, else the product) are the scalar form's `f64` operations in the
//! same order, with the same selects: round to nearest on every path, so each lane is
//! the scalar `RevAa<N>` bit for bit (NaN payloads aside) and inherits its soundness
//! proof. One part is directed: the square's radius bound `W` (`add_dir_up` in the
//! scalar form, the ceiling of each partial sum) is the lanes' `add_up`, the same number
//! on the AVX-512 and emulated paths and at most an ulp above it per addition on the
//! AVX2 path, where any `W >= Σ|xi| + e` is as sound. `|x|` and `sqrt x` are the
//! scalar form's approximations, ported step by step ([`super::revaa_approx`], which
//! says where its directed steps stand on each path); `min` and `max` take a whole
//! operand where the directed bounds decide the order (the scalar rule; the AVX2
//! path's wider bounds decide no more lanes), else `((x + y) ∓ |x - y|) * 0.5` from
//! the operations above. The lanes these leave to a branch not ported (unbounded or
//! degenerate ranges, `sqrt`'s general path), and every other instruction, run the
//! scalar operation lane by lane. [`crate::Tape::eval_batch`]
//! runs this kernel on the hardware paths; on the emulated path the directed sums cost
//! more than the generic loop over four-form packs, which gives the same bits.

use super::parts::{PartOps, Step, MAX_PARTS};
use super::revaa_approx;
use crate::eval::apply;
use crate::instr::{Instr, Op};
use arith_core::affine_round::{k_lin, k_mul, slack, sqr_margin, TINY};
use arith_core::lanes::{F64x8, Isa, LANES};
use arith_core::round::{ETA, U};
use arith_revaa::RevAa;

/// The RevAA kernel's values ([`super::parts`]): `N + 2` blocks per register and block
/// index, the centres, the coefficients, the error terms.
pub(crate) struct Forms<const N: usize>;

/// Eight forms in registers.
#[derive(Clone, Copy)]
pub(super) struct F<V, const N: usize> {
    pub(super) x0: V,
    pub(super) xs: [V; N],
    pub(super) e: V,
}

pub(super) type Form<I, const N: usize> = F<<I as Isa>::V, N>;

/// `affine_round::up_rel` per lane.
#[inline(always)]
fn up_rel<I: Isa>(s: I, v: I::V, k: usize) -> I::V {
    s.mul(v, s.splat(slack(k)))
}

/// `affine_round::up_abs` per lane.
#[inline(always)]
pub(super) fn up_abs<I: Isa>(s: I, v: I::V, k: usize) -> I::V {
    s.add(s.mul(v, s.splat(slack(k))), s.splat((k + 1) as f64 * ETA))
}

/// `U * |v|`.
#[inline(always)]
fn u_abs<I: Isa>(s: I, v: I::V) -> I::V {
    s.mul(s.splat(U), s.abs(v))
}

/// `a ± b` (the scalar `Add` and `Sub`: the radii add, each part's rounding in `e`).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // several arrays indexed together
pub(super) fn add<I: Isa, const N: usize>(
    s: I,
    a: Form<I, N>,
    b: Form<I, N>,
    minus: bool,
) -> Form<I, N> {
    let op = |x, y| if minus { s.sub(x, y) } else { s.add(x, y) };
    let x0 = op(a.x0, b.x0);
    let mut acc = s.add(s.add(a.e, b.e), u_abs(s, x0));
    let mut xs = a.xs;
    for k in 0..N {
        xs[k] = op(a.xs[k], b.xs[k]);
        acc = s.add(acc, u_abs(s, xs[k]));
    }
    F {
        x0,
        xs,
        e: up_rel(s, acc, N + 3),
    }
}

#[inline(always)]
pub(super) fn neg<I: Isa, const N: usize>(s: I, a: Form<I, N>) -> Form<I, N> {
    let mut xs = a.xs;
    for x in &mut xs {
        *x = s.neg(*x);
    }
    F {
        x0: s.neg(a.x0),
        xs,
        e: a.e,
    }
}

/// `a + c` (`a - c` with `minus`) for a constant.
#[inline(always)]
fn add_c<I: Isa, const N: usize>(s: I, a: Form<I, N>, c: I::V, minus: bool) -> Form<I, N> {
    let x0 = if minus {
        s.sub(a.x0, c)
    } else {
        s.add(a.x0, c)
    };
    F {
        x0,
        xs: a.xs,
        e: up_rel(s, s.add(a.e, u_abs(s, x0)), 2),
    }
}

/// `a * c` (`a / c` with `div`, for `c != 0`) for a constant.
#[inline(always)]
pub(super) fn mul_c<I: Isa, const N: usize>(s: I, a: Form<I, N>, c: I::V, div: bool) -> Form<I, N> {
    let op = |x| if div { s.div(x, c) } else { s.mul(x, c) };
    let x0 = op(a.x0);
    let mut r = s.abs(x0);
    let mut xs = a.xs;
    for x in &mut xs {
        *x = op(*x);
        r = s.add(r, s.abs(*x));
    }
    let spread = if div {
        s.div(a.e, s.abs(c))
    } else {
        s.mul(s.abs(c), a.e)
    };
    F {
        x0,
        xs,
        e: up_abs(s, s.add(spread, s.mul(s.splat(U), r)), k_lin(N)),
    }
}

/// RevAA's product (`arith_revaa`'s `mul_forms`) with its cross terms, the same sums in
/// the same order; where the scalar form skips the cross terms (each exactly 0),
/// adding them changes no bit.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // several arrays indexed together
fn mul<I: Isa, const N: usize>(s: I, x: Form<I, N>, y: Form<I, N>) -> Form<I, N> {
    let zero = s.splat(0.0);
    let p0 = s.mul(x.x0, y.x0);
    let (mut d, mut diag, mut u, mut v) = (zero, zero, zero, zero);
    let mut r = s.abs(p0);
    let mut xs = [zero; N];
    for i in 0..N {
        let q = s.mul(x.xs[i], y.xs[i]);
        d = s.add(d, q);
        diag = s.add(diag, s.abs(q));
        let a = s.mul(x.x0, y.xs[i]);
        let b = s.mul(x.xs[i], y.x0);
        xs[i] = s.add(a, b);
        // `r += |q| + |d| + |a| + |b| + |xs[i]|`, summed left to right.
        let t = s.add(s.add(s.abs(q), s.abs(d)), s.abs(a));
        let t = s.add(s.add(t, s.abs(b)), s.abs(xs[i]));
        r = s.add(r, t);
        u = s.add(u, s.abs(x.xs[i]));
        v = s.add(v, s.abs(y.xs[i]));
    }
    let mut off = zero;
    for i in 0..N {
        for j in i + 1..N {
            let a = s.mul(x.xs[i], y.xs[j]);
            let b = s.mul(x.xs[j], y.xs[i]);
            let sum = s.add(a, b);
            off = s.add(off, s.abs(sum));
            let t = s.add(s.add(s.abs(a), s.abs(b)), s.abs(sum));
            r = s.add(r, t);
        }
    }
    let hd = s.mul(s.splat(0.5), d);
    let x0 = s.add(p0, hd);
    let r = s.add(r, s.add(s.abs(hd), s.abs(x0)));
    let main = s.add(
        s.add(
            s.add(
                s.add(s.mul(x.e, y.e), s.mul(y.e, s.add(s.abs(x.x0), u))),
                s.mul(x.e, s.add(s.abs(y.x0), v)),
            ),
            s.mul(s.splat(0.5), diag),
        ),
        off,
    );
    F {
        x0,
        xs,
        e: up_abs(s, s.add(main, s.mul(s.splat(U), r)), k_mul(N)),
    }
}

/// `affine_round::rad_dir`: `e + Σ |xs[i]|`, each partial sum rounded up (exact sums
/// stay exact on the tight paths).
#[inline(always)]
fn rad_dir<I: Isa, const N: usize>(s: I, x: Form<I, N>) -> I::V {
    let mut r = x.e;
    for c in x.xs {
        r = s.add_up_raw(r, s.abs(c));
    }
    r
}

/// `affine_round::cheb_sqr` for `w >= Σ|xs[i]| + e`.
#[inline(always)]
fn cheb_sqr<I: Isa, const N: usize>(s: I, x: Form<I, N>, w: I::V) -> Form<I, N> {
    let p0 = s.mul(x.x0, x.x0);
    let ww = s.mul(w, w);
    let h = s.mul(s.splat(0.5), ww);
    let c0 = s.add(p0, h);
    let tx0 = s.mul(s.splat(2.0), x.x0);
    let mut r = s.add(s.add(s.abs(p0), ww), s.abs(c0));
    let mut xs = x.xs;
    for z in &mut xs {
        *z = s.mul(tx0, *z);
        r = s.add(r, s.abs(*z));
    }
    let main = s.add(h, s.mul(s.abs(tx0), x.e));
    F {
        x0: c0,
        xs,
        e: up_abs(s, s.add(main, s.mul(s.splat(U), r)), k_mul(N)),
    }
}

/// `m ? a : b`, every part.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // several arrays indexed together
pub(super) fn select<I: Isa, const N: usize>(
    s: I,
    m: I::M,
    a: Form<I, N>,
    b: Form<I, N>,
) -> Form<I, N> {
    let mut xs = a.xs;
    for k in 0..N {
        xs[k] = s.select(m, a.xs[k], b.xs[k]);
    }
    F {
        x0: s.select(m, a.x0, b.x0),
        xs,
        e: s.select(m, a.e, b.e),
    }
}

/// RevAA's square: the Chebyshev square where its gain over `x * x` survives the
/// rounding allowances and its bound is finite, else `x * x`.
#[inline(always)]
fn sqr<I: Isa, const N: usize>(s: I, x: Form<I, N>) -> Form<I, N> {
    let w = rad_dir(s, x);
    let mut s2 = s.splat(0.0);
    for c in x.xs {
        s2 = s.add(s2, s.mul(c, c));
    }
    let m = s.add(s.abs(x.x0), w);
    let margin = s.add(s.mul(s.splat(sqr_margin(N)), s.mul(m, m)), s.splat(TINY));
    let gain = s.lt(margin, s.sub(s.mul(w, w), s2));
    let cheb = cheb_sqr(s, x, w);
    let finite = s.lt(cheb.e, s.splat(f64::INFINITY));
    select(s, s.and(gain, finite), cheb, mul(s, x, x))
}

/// The directed bounds `x0 ∓ rad` (the scalar `bounds`; where one is not finite the
/// scalar gives the whole line, which decides no order: such lanes compare false).
#[inline(always)]
pub(super) fn bounds<I: Isa, const N: usize>(s: I, x: Form<I, N>) -> (I::V, I::V) {
    let rad = rad_dir(s, x);
    (s.add_down_raw(x.x0, s.neg(rad)), s.add_up_raw(x.x0, rad))
}

/// Whether each lane's bounds are finite.
#[inline(always)]
pub(super) fn finite<I: Isa>(s: I, (lo, hi): (I::V, I::V)) -> I::M {
    let inf = s.splat(f64::INFINITY);
    s.and(s.lt(s.neg(inf), lo), s.lt(hi, inf))
}

/// `min` (or `max`): the whole lower (higher) operand where the bounds decide the
/// order, else `((x + y) ∓ |x - y|) * 0.5` (the scalar rule, the same operations); the
/// mask of the lanes whose `|x - y|` is left to the scalar operation.
#[inline(always)]
fn min_max<I: Isa, const N: usize>(
    s: I,
    x: Form<I, N>,
    y: Form<I, N>,
    max: bool,
) -> (Form<I, N>, I::M) {
    let (bx, by) = (bounds(s, x), bounds(s, y));
    let ok = s.and(finite(s, bx), finite(s, by));
    let x_low = s.and(ok, s.le(bx.1, by.0));
    let y_low = s.and(ok, s.and(s.not(x_low), s.le(by.1, bx.0)));
    let (lo, hi) = if max { (y, x) } else { (x, y) };
    // `x_low`: `min` is `x`, `max` is `y`; else `y_low`: the other way round.
    let r = select(s, x_low, lo, hi);
    let open = s.not(s.or(x_low, y_low));
    if s.bits(open) == 0 {
        return (r, open);
    }
    let (d, redo) = revaa_approx::abs(s, add(s, x, y, true));
    let f = mul_c(s, add(s, add(s, x, y, false), d, !max), s.splat(0.5), false);
    (select(s, open, f, r), s.and(open, redo))
}

/// Eight forms from the `N + 2` blocks at `file[k..]`.
#[inline(always)]
fn load<I: Isa, const N: usize>(s: I, file: &[F64x8], k: usize) -> Form<I, N> {
    let p = &file[k..k + N + 2];
    let mut xs = [s.splat(0.0); N];
    for (j, x) in xs.iter_mut().enumerate() {
        *x = s.load(&p[1 + j]);
    }
    F {
        x0: s.load(&p[0]),
        xs,
        e: s.load(&p[N + 1]),
    }
}

impl<const N: usize> PartOps for Forms<N> {
    const PARTS: usize = N + 2;

    /// [`PartOps::instruction`] for forms: the lanes an operation leaves to the scalar form
    /// are redone from the operands' blocks before the result is written.
    #[inline(always)]
    fn instruction<I: Isa>(s: I, at: Step<'_>) {
        let (i, ops, ch, res) = (at.i, at.ops, at.ch, at.out);
        let c = s.splat(i.c);
        let none = s.lt(c, c);
        let all = s.not(none);
        macro_rules! op {
            (|$x:ident, $y:ident| $body:expr) => {
                for j in 0..ch {
                    let at = (N + 2) * j;
                    #[allow(unused_variables)]
                    let ($x, $y) = (load::<I, N>(s, ops[0], at), load::<I, N>(s, ops[1], at));
                    let (r, redo): (Form<I, N>, I::M) = $body;
                    let mut out = [F64x8::default(); MAX_PARTS];
                    out[0] = s.store(r.x0);
                    for k in 0..N {
                        out[1 + k] = s.store(r.xs[k]);
                    }
                    out[N + 1] = s.store(r.e);
                    let redo = s.bits(redo);
                    if redo != 0 {
                        scalar::<N>(i, ops, at, &mut out, redo);
                    }
                    res[at..at + N + 2].copy_from_slice(&out[..N + 2]);
                }
            };
        }
        match i.op {
            Op::X | Op::Y | Op::Z | Op::Const => unreachable!("not an operation on registers"),
            Op::Neg => op!(|x, y| (neg(s, x), none)),
            Op::Sqr => op!(|x, y| (sqr(s, x), none)),
            Op::AddC => op!(|x, y| (add_c(s, x, c, false), none)),
            Op::SubC => op!(|x, y| (add_c(s, x, c, true), none)),
            // `Real::rsub`: `-x + c`.
            Op::RSubC => op!(|x, y| (add_c(s, neg(s, x), c, false), none)),
            Op::MulC => op!(|x, y| (mul_c(s, x, c, false), none)),
            Op::DivC if i.c != 0.0 => op!(|x, y| (mul_c(s, x, c, true), none)),
            Op::Add => op!(|x, y| (add(s, x, y, false), none)),
            Op::Sub => op!(|x, y| (add(s, x, y, true), none)),
            Op::Mul => op!(|x, y| (mul(s, x, y), none)),
            Op::Min => op!(|x, y| min_max(s, x, y, false)),
            Op::Max => op!(|x, y| min_max(s, x, y, true)),
            Op::Abs => op!(|x, y| revaa_approx::abs(s, x)),
            Op::Sqrt => op!(|x, y| revaa_approx::sqrt(s, x)),
            Op::Exp => op!(|x, y| revaa_approx::exp(s, x)),
            Op::Ln => op!(|x, y| revaa_approx::ln(s, x)),
            Op::Recip => op!(|x, y| revaa_approx::recip(s, x)),
            Op::RDivC => op!(|x, y| {
                let (r, redo) = revaa_approx::recip(s, x);
                (mul_c(s, r, c, false), redo)
            }),
            Op::Div => op!(|x, y| {
                let (r, redo) = revaa_approx::recip(s, y);
                (mul(s, x, r), redo)
            }),
            // Lane by lane through the scalar operation.
            _ => op!(|x, y| (x, all)),
        }
    }
}

/// Redoes the lanes of `redo` of one block through the scalar operation on `RevAa<N>`,
/// from the operands' blocks at `at` (not yet overwritten: the result is written after
/// this).
#[cold]
#[inline(never)]
fn scalar<const N: usize>(
    i: &Instr,
    ops: [&[F64x8]; 3],
    at: usize,
    out: &mut [F64x8; MAX_PARTS],
    redo: u8,
) {
    for l in 0..LANES {
        if redo & (1 << l) != 0 {
            let v = |k: usize| {
                let p = &ops[k][at..at + N + 2];
                RevAa::<N>::from_parts(
                    p[0].0[l],
                    core::array::from_fn(|j| p[1 + j].0[l]),
                    p[N + 1].0[l],
                )
            };
            let r = apply(i, v(0), v(1), v(2));
            out[0].0[l] = r.x0;
            for k in 0..N {
                out[1 + k].0[l] = r.xs[k];
            }
            out[N + 1].0[l] = r.e;
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::Tape;
    use arith_core::lanes::Path;
    use arith_core::{Range, Real};
    use arith_revaa::RevAa;

    /// The kernel on the emulated path (which `eval_batch` leaves to the generic loop,
    /// and which runs where a thread flushes subnormals) gives the scalar bits too.
    #[test]
    fn emulated_kernel_gives_the_scalar_bits() {
        let t = Tape::record(|x, y, z| {
            let a = (x.sqr() + y * z - 0.5).max(&(x - y.sqr()));
            let b = (a.min(&(z * 3.0)) * (x + 1.0)).sqr().rsub(2.0) / 1.5 - y.sqrt();
            b + (x - z).abs().min(&y.abs()).sqrt()
        });
        let forms: Vec<RevAa<1>> = (0..37)
            .map(|k| {
                let lo = -1.5 + 0.08 * k as f64;
                RevAa::<1>::input(k % 2, lo, lo + 0.05 * (1 + k % 5) as f64)
            })
            .collect();
        let mut out = Vec::new();
        t.revaa_kernel::<1>(
            Path::Emulated,
            forms.len(),
            |_, l| forms[l],
            |_, f| out.push(f),
        );
        assert_eq!(out.len(), forms.len());
        for (o, f) in out.iter().zip(&forms) {
            let s = t.eval(*f, *f, *f);
            let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
            assert!(
                same(o.x0, s.x0) && same(o.xs[0], s.xs[0]) && same(o.e, s.e),
                "{o:?} vs {s:?}"
            );
        }
        // `max` decided (a whole operand) in some lanes, by the formula in others.
        let m = Tape::record(|x, y, _z| x.max(&y));
        let y = vec![RevAa::<1>::from_interval(0.0, 0.1); forms.len()];
        let mut out = Vec::new();
        m.revaa_kernel::<1>(
            Path::Emulated,
            forms.len(),
            |q, l| [forms[l], y[l], y[l]][q],
            |_, f| out.push(f),
        );
        let (mut whole, mut formula) = (0, 0);
        for ((o, x), y) in out.iter().zip(&forms).zip(&y) {
            let s = m.eval(*x, *y, *y);
            assert!(o.x0.to_bits() == s.x0.to_bits() && o.e.to_bits() == s.e.to_bits());
            assert!(o.xs[0].to_bits() == s.xs[0].to_bits(), "{o:?} vs {s:?}");
            if o == x || o == y {
                whole += 1;
            } else {
                formula += 1;
            }
        }
        assert!(whole > 0 && formula > 0, "{whole} decided, {formula} not");
    }
}
