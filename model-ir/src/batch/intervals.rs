//! The interval kernel: a tape over eight-lane blocks of intervals, each bound one
//! directed lane operation ([`arith_core::lanes`]).
//!
//! Every vector formula computes what the scalar [`Interval`] operation computes from
//! the same tight bounds: a product is the least of the four corners' floors and the
//! greatest of their ceilings (the floor is monotone, so that is the floor of the least
//! corner, the one the scalar picks by the signs), a square bounds `mig^2` and `mag^2`,
//! and so on. On the AVX-512 and emulated paths each lane therefore equals the scalar
//! result (bit for bit but for the sign of a zero bound); on the AVX2 path each bound
//! lies at most one ulp further out per rounding, so it still encloses the scalar
//! result. Where a formula and the scalar operation part ways (a corner product
//! `0 * inf`, a quotient `inf / inf`, a sum `inf - inf`: the lanes whose raw directed
//! results are NaN; square roots outside the range where the scalar one is tight;
//! constants that are not finite nonzero numbers), the block's NaN mask picks the
//! lanes, and they are redone through the scalar operation.
//!
//! `exp` and `ln` are monotone: their bounds are the lanes' functions at the ends
//! ([`arith_core::lanes::exp`], [`arith_core::lanes::ln`], proven within 9 ulp-units
//! of the exact value), widened by the margin the scalar arithmetic gives libm's values
//! (`round::LIBM_REL`, which libm is only assumed to meet). So they enclose the exact
//! range as the scalar ones do, but are not the scalar bits: the two differ by a few
//! units in the last place. `sin` and `cos` take the scalar's decisions (a width of
//! 6.2 or more gives `[-1, 1]`; a maximum or minimum the interval may hold by the
//! scalar's conservative test gives `1` or `-1`), in the same floating-point
//! operations, and the lanes' `sin` and `cos` at the ends (proven within `3.9` ulp-units
//! plus `1.5e-26`, widened by `LIBM_REL` and `2^-80`). Arguments outside the proven
//! domains (`|x| > 700` for `exp`, zero, subnormal, infinite or NaN for `ln`,
//! `|x| > 10^5` for `sin` and `cos`) are redone through the scalar operation. Negative
//! powers run lane by lane through the scalar operation.

use super::parts::{PartOps, Step};
use crate::eval::apply;
use crate::instr::{Instr, Op};
use arith_core::lanes::{
    exp_enclosure, ln_enclosure, trig_enclosure, F64x8, Isa, EXP_MAX_ARG, LANES, TRIG_MAX_ARG,
};
use arith_ia::Interval;

/// The interval kernel's values ([`super::parts`]): two blocks per register and block
/// index, the lower bounds, then the upper ones.
pub(crate) struct Intervals;

/// One block's three operands.
type Ops3<'a> = (&'a [F64x8; 2], &'a [F64x8; 2], &'a [F64x8; 2]);

/// Lower and upper bounds of eight intervals in registers.
type P<I> = (<I as Isa>::V, <I as Isa>::V);

/// The smallest and largest magnitude over each interval (the scalar `mig_mag`).
#[inline(always)]
fn mig_mag<I: Isa>(s: I, (lo, hi): P<I>) -> P<I> {
    let zero = s.splat(0.0);
    let pos = s.le(zero, lo);
    let neg = s.le(hi, zero);
    let mig = s.select(pos, lo, s.select(neg, s.neg(hi), zero));
    let straddle = s.max(s.neg(lo), hi);
    let mag = s.select(pos, hi, s.select(neg, s.neg(lo), straddle));
    (mig, mag)
}

/// `arith_core::round::pow_lo_nonneg` (`up == false`) or `pow_hi_nonneg` per lane:
/// the same binary powering of directed products.
#[inline(always)]
fn pow_nonneg<I: Isa>(s: I, x: I::V, mut n: u32, up: bool) -> I::V {
    let zero = s.splat(0.0);
    let mul = |a, b| {
        if up {
            s.mul_up_raw(a, b)
        } else {
            s.max(s.mul_down_raw(a, b), zero)
        }
    };
    let mut result: Option<I::V> = None;
    let mut base = x;
    loop {
        if n & 1 == 1 {
            result = Some(match result {
                None => base,
                Some(r) => mul(r, base),
            });
        }
        n >>= 1;
        if n == 0 {
            return result.unwrap_or(s.splat(1.0));
        }
        base = mul(base, base);
    }
}

/// `x^n` for `n >= 1` (the scalar `powi_pos`).
#[inline(always)]
fn powi_pos<I: Isa>(s: I, a: P<I>, n: u32) -> P<I> {
    if n & 1 == 0 {
        let (mig, mag) = mig_mag(s, a);
        return (pow_nonneg(s, mig, n, false), pow_nonneg(s, mag, n, true));
    }
    let zero = s.splat(0.0);
    let (alo, ahi) = (s.abs(a.0), s.abs(a.1));
    let lo = s.select(
        s.le(zero, a.0),
        pow_nonneg(s, alo, n, false),
        s.neg(pow_nonneg(s, alo, n, true)),
    );
    let hi = s.select(
        s.le(zero, a.1),
        pow_nonneg(s, ahi, n, true),
        s.neg(pow_nonneg(s, ahi, n, false)),
    );
    (lo, hi)
}

#[inline(always)]
fn add<I: Isa>(s: I, a: P<I>, b: P<I>) -> (P<I>, I::M) {
    let (lo, hi) = (s.add_down_raw(a.0, b.0), s.add_up_raw(a.1, b.1));
    ((lo, hi), s.unord(lo, hi))
}

#[inline(always)]
fn sub<I: Isa>(s: I, a: P<I>, b: P<I>) -> (P<I>, I::M) {
    let (lo, hi) = (s.sub_down_raw(a.0, b.1), s.sub_up_raw(a.1, b.0));
    ((lo, hi), s.unord(lo, hi))
}

#[inline(always)]
fn mul<I: Isa>(s: I, a: P<I>, b: P<I>) -> (P<I>, I::M) {
    let (l1, l2) = (s.mul_down_raw(a.0, b.0), s.mul_down_raw(a.0, b.1));
    let (l3, l4) = (s.mul_down_raw(a.1, b.0), s.mul_down_raw(a.1, b.1));
    let (h1, h2) = (s.mul_up_raw(a.0, b.0), s.mul_up_raw(a.0, b.1));
    let (h3, h4) = (s.mul_up_raw(a.1, b.0), s.mul_up_raw(a.1, b.1));
    let lo = s.min(s.min(l1, l2), s.min(l3, l4));
    let hi = s.max(s.max(h1, h2), s.max(h3, h4));
    ((lo, hi), s.or(s.unord(l1, l2), s.unord(l3, l4)))
}

/// Whether each interval holds 0 (the scalar `contains_zero`).
#[inline(always)]
fn holds_zero<I: Isa>(s: I, (lo, hi): P<I>) -> I::M {
    let zero = s.splat(0.0);
    s.not(s.or(s.lt(zero, lo), s.lt(hi, zero)))
}

/// The whole line where `m` is set.
#[inline(always)]
fn entire_where<I: Isa>(s: I, m: I::M, (lo, hi): P<I>) -> P<I> {
    (
        s.select(m, s.splat(f64::NEG_INFINITY), lo),
        s.select(m, s.splat(f64::INFINITY), hi),
    )
}

#[inline(always)]
fn div<I: Isa>(s: I, a: P<I>, b: P<I>) -> (P<I>, I::M) {
    let z = holds_zero(s, b);
    let (l1, l2) = (s.div_down_raw(a.0, b.0), s.div_down_raw(a.0, b.1));
    let (l3, l4) = (s.div_down_raw(a.1, b.0), s.div_down_raw(a.1, b.1));
    let (h1, h2) = (s.div_up_raw(a.0, b.0), s.div_up_raw(a.0, b.1));
    let (h3, h4) = (s.div_up_raw(a.1, b.0), s.div_up_raw(a.1, b.1));
    let lo = s.min(s.min(l1, l2), s.min(l3, l4));
    let hi = s.max(s.max(h1, h2), s.max(h3, h4));
    let bad = s.and(s.not(z), s.or(s.unord(l1, l2), s.unord(l3, l4)));
    (entire_where(s, z, (lo, hi)), bad)
}

/// `c / b` for a finite `c` (the scalar `Interval::point(c) / b`).
#[inline(always)]
fn rdiv<I: Isa>(s: I, c: I::V, b: P<I>) -> P<I> {
    let z = holds_zero(s, b);
    let lo = s.min(s.div_down_raw(c, b.0), s.div_down_raw(c, b.1));
    let hi = s.max(s.div_up_raw(c, b.0), s.div_up_raw(c, b.1));
    entire_where(s, z, (lo, hi))
}

/// The scalar `range_sqrt`, where it is tight: arguments `<= 0` or within
/// `[1e-250, 1e300]` (elsewhere the mask is set).
#[inline(always)]
fn sqrt<I: Isa>(s: I, (a, b): P<I>) -> (P<I>, I::M) {
    let zero = s.splat(0.0);
    let (small, large) = (s.splat(1.0e-250), s.splat(1.0e300));
    let tight = |x| s.or(s.le(x, zero), s.and(s.le(small, x), s.le(x, large)));
    let bad = s.not(s.and(tight(a), tight(b)));
    let lo = s.select(s.le(a, zero), zero, s.sqrt_down_raw(a));
    let hi = s.sqrt_up_raw(b);
    let none = s.le(b, zero);
    ((s.select(none, zero, lo), s.select(none, zero, hi)), bad)
}

/// The default `hypot`, `sqrt(a^2 + b^2)`.
#[inline(always)]
fn hypot<I: Isa>(s: I, a: P<I>, b: P<I>) -> (P<I>, I::M) {
    let (sum, bad) = add(s, powi_pos(s, a, 2), powi_pos(s, b, 2));
    let (r, bad2) = sqrt(s, sum);
    (r, s.or(bad, bad2))
}

/// The scalar `range_exp` where both bounds lie in `[-EXP_MAX_ARG, EXP_MAX_ARG]`
/// (elsewhere, and for NaN or reversed bounds, the mask is set): the bounds of the
/// lanes' `exp` at the ends, which, like the scalar libm values, are widened by
/// `LIBM_REL` (proven for the lanes' function), the lower one clipped at 0.
#[inline(always)]
fn exp<I: Isa>(s: I, (a, b): P<I>) -> (P<I>, I::M) {
    let lim = s.splat(EXP_MAX_ARG);
    let inside = |v| s.le(s.abs(v), lim);
    let good = s.and(s.and(inside(a), inside(b)), s.le(a, b));
    let lo = s.max(exp_enclosure(s, a).0, s.splat(0.0));
    ((lo, exp_enclosure(s, b).1), s.not(good))
}

/// The scalar `range_ln` where the upper bound is a positive normal number and the
/// lower one is too or is `<= 0` (elsewhere, and for NaN or reversed bounds, the mask is
/// set): the bounds of the lanes' `ln` at the ends, widened as the scalar libm values
/// are, `-inf` from a lower bound `<= 0`.
#[inline(always)]
fn ln<I: Isa>(s: I, (a, b): P<I>) -> (P<I>, I::M) {
    let (tiny, huge) = (s.splat(f64::MIN_POSITIVE), s.splat(f64::MAX));
    let normal = |v| s.and(s.le(tiny, v), s.le(v, huge));
    let nonpositive = s.le(a, s.splat(0.0));
    let good = s.and(normal(b), s.and(s.or(nonpositive, normal(a)), s.le(a, b)));
    let lo = s.select(
        nonpositive,
        s.splat(f64::NEG_INFINITY),
        ln_enclosure(s, a).0,
    );
    ((lo, ln_enclosure(s, b).1), s.not(good))
}

/// Whether `[a, b]` may hold `offset + 2 k pi` for an integer `k`: the scalar
/// `may_contain` (the quotients widened by `1e-6` periods, then `ceil(u) <= floor(v)`),
/// its roundings the same, the integer parts through the `1.5 * 2^52` shift (the
/// quotients are below `2^51`).
#[inline(always)]
fn may_contain<I: Isa>(s: I, a: I::V, b: I::V, offset: f64) -> I::M {
    use core::f64::consts::TAU;
    const PERIOD_EPS: f64 = 1.0e-6;
    let (off, period, eps) = (s.splat(offset), s.splat(TAU), s.splat(PERIOD_EPS));
    let u = s.sub(s.div(s.sub(a, off), period), eps);
    let v = s.add(s.div(s.sub(b, off), period), eps);
    let shift = s.splat(6_755_399_441_055_744.0);
    let near = |x| s.sub(s.add(x, shift), shift);
    let one = s.splat(1.0);
    let (nu, nv) = (near(u), near(v));
    let ceil_u = s.select(s.lt(nu, u), s.add(nu, one), nu);
    let floor_v = s.select(s.lt(v, nv), s.sub(nv, one), nv);
    s.le(ceil_u, floor_v)
}

/// The scalar `range_sin` (`cos`: `range_cos`) where both bounds lie in
/// `[-TRIG_MAX_ARG, TRIG_MAX_ARG]` (elsewhere, and for NaN or reversed bounds, the mask
/// is set): `[-1, 1]` from a width of 6.2 on, else the lanes' enclosures at the ends,
/// and `1` (`-1`) where the scalar test says the interval may hold a maximum (minimum).
#[inline(always)]
fn trig<I: Isa>(s: I, (a, b): P<I>, cos: bool) -> (P<I>, I::M) {
    use core::f64::consts::{FRAC_PI_2, PI};
    let lim = s.splat(TRIG_MAX_ARG);
    let inside = |v| s.le(s.abs(v), lim);
    let good = s.and(s.and(inside(a), inside(b)), s.le(a, b));
    let (fa, fb) = (trig_enclosure(s, a, cos), trig_enclosure(s, b, cos));
    let (max_at, min_at) = if cos {
        (0.0, PI)
    } else {
        (FRAC_PI_2, -FRAC_PI_2)
    };
    let (one, minus_one) = (s.splat(1.0), s.splat(-1.0));
    let wide = s.le(s.splat(6.2), s.sub(b, a));
    let hi = s.select(
        s.or(wide, may_contain(s, a, b, max_at)),
        one,
        s.max(fa.1, fb.1),
    );
    let lo = s.select(
        s.or(wide, may_contain(s, a, b, min_at)),
        minus_one,
        s.min(fa.0, fb.0),
    );
    ((s.max(lo, minus_one), s.min(hi, one)), s.not(good))
}

/// `t` where the truth values `c` are 1, `e` where they are 0, the hull where undecided.
#[inline(always)]
fn select<I: Isa>(s: I, c: P<I>, t: P<I>, e: P<I>) -> P<I> {
    let half = s.splat(0.5);
    let (yes, no) = (s.lt(half, c.0), s.lt(c.1, half));
    let lo = s.select(yes, t.0, s.select(no, e.0, s.min(t.0, e.0)));
    let hi = s.select(yes, t.1, s.select(no, e.1, s.max(t.1, e.1)));
    (lo, hi)
}

impl PartOps for Intervals {
    const PARTS: usize = 2;

    /// The bounds of `Interval::point(c)`.
    fn constant(c: f64, block: &mut [F64x8]) {
        let p = Interval::point(c);
        block[0] = F64x8::splat(p.lo);
        block[1] = F64x8::splat(p.hi);
    }

    #[inline(always)]
    fn instruction<I: Isa>(s: I, at: Step<'_>) {
        let i = at.i;
        let c = i.c;
        let cv = s.splat(c);
        let finite_nonzero = c.is_finite() && c != 0.0;
        let zero = s.splat(0.0);
        // Each block of the result from `f` of the operands' blocks, with the lanes of
        // its mask redone through the scalar operation.
        macro_rules! op {
            (|$x:ident, $y:ident, $z:ident| $body:expr) => {
                at.each::<2>(|out, ops| {
                    let ld = |k: usize| (s.load(&ops[k][0]), s.load(&ops[k][1]));
                    #[allow(unused_variables)]
                    let ($x, $y, $z): (P<I>, P<I>, P<I>) = (ld(0), ld(1), ld(2));
                    let ((lo, hi), bad): (P<I>, I::M) = $body;
                    *out = [s.store(lo), s.store(hi)];
                    let bad = s.bits(bad);
                    if bad != 0 {
                        let [a, b, e] = ops;
                        redo(i, (a, b, e), out, bad);
                    }
                })
            };
        }
        let ok = s.eq(zero, s.splat(1.0));
        match i.op {
            Op::X | Op::Y | Op::Z | Op::Const => {
                unreachable!("not an operation on registers")
            }
            Op::Neg => op!(|x, y, z| ((s.neg(x.1), s.neg(x.0)), ok)),
            Op::Sqr => op!(|x, y, z| (powi_pos(s, x, 2), ok)),
            Op::Powi if i.n == 1 => op!(|x, y, z| (x, ok)),
            Op::Powi if i.n >= 2 => op!(|x, y, z| (powi_pos(s, x, i.n as u32), ok)),
            Op::Sqrt => op!(|x, y, z| sqrt(s, x)),
            Op::Exp => op!(|x, y, z| exp(s, x)),
            Op::Ln => op!(|x, y, z| ln(s, x)),
            Op::Sin => op!(|x, y, z| trig(s, x, false)),
            Op::Cos => op!(|x, y, z| trig(s, x, true)),
            Op::Abs => op!(|x, y, z| (mig_mag(s, x), ok)),
            Op::Recip => op!(|x, y, z| (rdiv(s, s.splat(1.0), x), ok)),
            Op::AddC if !c.is_nan() => op!(|x, y, z| add(s, x, (cv, cv))),
            Op::SubC if !c.is_nan() => {
                let m = s.splat(-c);
                op!(|x, y, z| add(s, x, (m, m)))
            }
            Op::RSubC if !c.is_nan() => op!(|x, y, z| sub(s, (cv, cv), x)),
            Op::MulC if finite_nonzero && c > 0.0 => {
                op!(|x, y, z| ((s.mul_down_raw(x.0, cv), s.mul_up_raw(x.1, cv)), ok))
            }
            Op::MulC if finite_nonzero => {
                op!(|x, y, z| ((s.mul_down_raw(x.1, cv), s.mul_up_raw(x.0, cv)), ok))
            }
            Op::DivC if finite_nonzero && c > 0.0 => {
                op!(|x, y, z| ((s.div_down_raw(x.0, cv), s.div_up_raw(x.1, cv)), ok))
            }
            Op::DivC if finite_nonzero => {
                op!(|x, y, z| ((s.div_down_raw(x.1, cv), s.div_up_raw(x.0, cv)), ok))
            }
            Op::RDivC if c.is_finite() => op!(|x, y, z| (rdiv(s, cv, x), ok)),
            Op::Add => op!(|x, y, z| add(s, x, y)),
            Op::Sub => op!(|x, y, z| sub(s, x, y)),
            Op::Mul => op!(|x, y, z| mul(s, x, y)),
            Op::Div => op!(|x, y, z| div(s, x, y)),
            Op::Hypot => op!(|x, y, z| hypot(s, x, y)),
            Op::Min => op!(|x, y, z| ((s.min(x.0, y.0), s.min(x.1, y.1)), ok)),
            Op::Max => op!(|x, y, z| ((s.max(x.0, y.0), s.max(x.1, y.1)), ok)),
            Op::Intersect | Op::Union | Op::Subtract => op!(|x, y, z| {
                let (h, bad) = hypot(s, x, y);
                let (f, bad2) = match i.op {
                    Op::Subtract => sub(s, x, y),
                    _ => add(s, x, y),
                };
                let (r, bad3) = match i.op {
                    Op::Union => add(s, f, h),
                    _ => sub(s, f, h),
                };
                (r, s.or(bad, s.or(bad2, bad3)))
            }),
            Op::Gt0 => op!(|x, y, z| {
                let one = s.splat(1.0);
                let lo = s.select(s.lt(zero, x.0), one, zero);
                let hi = s.select(s.le(x.1, zero), zero, one);
                ((lo, hi), ok)
            }),
            Op::Ge0 => op!(|x, y, z| {
                let one = s.splat(1.0);
                let lo = s.select(s.le(zero, x.0), one, zero);
                let hi = s.select(s.lt(x.1, zero), zero, one);
                ((lo, hi), ok)
            }),
            Op::Select => op!(|x, y, z| (select(s, x, y, z), ok)),
            // Lane by lane through the scalar operation.
            _ => op!(|x, y, z| ((x.0, x.1), s.eq(zero, zero))),
        }
    }
}

/// Redoes the lanes of `bad` of one block through the scalar operation, from the
/// operands' blocks `ops`. (The operands come as a tuple of three references, which
/// the calling convention passes in registers: an array would be built on the stack
/// in every block of the hot loop.)
#[cold]
#[inline(never)]
fn redo(i: &Instr, ops: Ops3<'_>, out: &mut [F64x8; 2], bad: u8) {
    let ops = [ops.0, ops.1, ops.2];
    for l in 0..LANES {
        if bad & (1 << l) != 0 {
            let v = |k: usize| Interval {
                lo: ops[k][0].0[l],
                hi: ops[k][1].0[l],
            };
            let r = apply(i, v(0), v(1), v(2));
            out[0].0[l] = r.lo;
            out[1].0[l] = r.hi;
        }
    }
}
