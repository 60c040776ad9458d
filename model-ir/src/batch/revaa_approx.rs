//! The RevAA kernel's non-affine unary operations, `|x|` and `sqrt x`, through the
//! shared affine approximations: per lane, the scalar form's `Reduced::unary` (the
//! range from `affine_round::bounds_fast`, the approximation `alpha*x + zeta ± delta`
//! of `approx::abs` or `approx::sqrt` on it, then `Reduced::apply`), operation for
//! operation.
//!
//! The steps in round to nearest are the scalar `f64` operations in the same order; the
//! directed ones (`abs`'s `g_enc` bounds: `mul_lo`, `sub_hi`) are the lanes' raw
//! directed operations, which on the AVX-512 and emulated paths are the same floor and
//! ceiling as `round::tight`'s (they differ only in the sign of an exact zero, which
//! the `max` that follows never picks: the other end is positive), and `f64::next_up`
//! and `next_down` of `sqrt`'s closed forms are the ceiling of `v + 2^-1074` and the
//! floor of `v - 2^-1074`, the same numbers for the finite values taken there (an
//! exact zero's sign aside, which the subtractions that follow ignore). So each lane
//! is the scalar `RevAa<N>` bit for bit on those paths and inherits its soundness
//! proof. On the AVX2 path each directed operation is at most an ulp further out:
//! every bound stays a bound (a wider `g` range, a larger `next_up`), so the lanes
//! still enclose, and `|x|`'s sign test may leave to the approximation a lane whose
//! tight bounds decide it.
//!
//! A lane whose approximation takes a branch not written here (an unbounded or
//! degenerate range, `sqrt`'s general path through tangent bounds, a slope that is not
//! a normal number, an overflow) is flagged for the scalar operation.

use super::revaa::{bounds, finite, neg, select, up_abs, Form, F};
use arith_core::affine_round::{k_lin, slack};
use arith_core::lanes::{
    exp as exp_lanes, ln as ln_lanes, ln_enclosure, widen, Isa, EXP_COEFFS, EXP_MAX_ARG,
};
use arith_core::round::{ETA, U};

/// An affine approximation `alpha*x + zeta ± delta` per lane.
#[derive(Clone, Copy)]
struct Approx<V> {
    alpha: V,
    zeta: V,
    delta: V,
}

/// Whether each lane of `v` is finite.
#[inline(always)]
fn finite1<I: Isa>(s: I, v: I::V) -> I::M {
    finite(s, (v, v))
}

/// `affine_round::bounds_fast`: `x0 ∓ rad` with `rad >= Σ|xs[i]| + e` rounded up
/// relatively, each bound moved out by `2U` of itself and `ETA`.
#[inline(always)]
fn bounds_fast<I: Isa, const N: usize>(s: I, x: Form<I, N>) -> (I::V, I::V) {
    let mut acc = x.e;
    for c in x.xs {
        acc = s.add(acc, s.abs(c));
    }
    let rad = s.mul(acc, s.splat(slack(N + 1)));
    let (lo, hi) = (s.sub(x.x0, rad), s.add(x.x0, rad));
    let (two_u, eta) = (s.splat(2.0 * U), s.splat(ETA));
    (
        s.sub(lo, s.add(s.mul(s.abs(lo), two_u), eta)),
        s.add(hi, s.add(s.mul(s.abs(hi), two_u), eta)),
    )
}

/// `approx::finish`: `zeta` near the midpoint of `g ∈ [lo, hi]`, `delta` the larger
/// half-width times `1 + 4U`; with the lanes where the scalar gives a bounded
/// approximation (else `Approx::ENTIRE`).
#[inline(always)]
fn finish<I: Isa>(s: I, alpha: I::V, lo: I::V, hi: I::V) -> (Approx<I::V>, I::M) {
    let half = s.splat(0.5);
    let zeta = s.add(s.mul(half, lo), s.mul(half, hi));
    let d = s.max(s.max(s.sub(hi, zeta), s.sub(zeta, lo)), s.splat(0.0));
    let delta = s.mul(d, s.splat(1.0 + 4.0 * U));
    let ok = s.and(
        s.and(finite1(s, alpha), s.and(finite(s, (lo, hi)), s.le(lo, hi))),
        s.and(finite1(s, zeta), finite1(s, delta)),
    );
    (Approx { alpha, zeta, delta }, ok)
}

/// `Reduced::apply` of a bounded approximation: `alpha*x + zeta`, `e = delta +
/// |alpha| e_x` and the rounding errors; the constant `zeta ± delta` where `alpha` is 0.
#[inline(always)]
fn apply<I: Isa, const N: usize>(s: I, x: Form<I, N>, a: Approx<I::V>) -> Form<I, N> {
    let ax0 = s.mul(a.alpha, x.x0);
    let x0 = s.add(ax0, a.zeta);
    let mut r = s.add(s.abs(ax0), s.abs(x0));
    let mut xs = x.xs;
    for z in &mut xs {
        *z = s.mul(a.alpha, *z);
        r = s.add(r, s.abs(*z));
    }
    let sum = s.add(
        s.add(a.delta, s.mul(s.abs(a.alpha), x.e)),
        s.mul(s.splat(U), r),
    );
    let line = F {
        x0,
        xs,
        e: up_abs(s, sum, k_lin(N)),
    };
    let zero = s.splat(0.0);
    let flat = F {
        x0: a.zeta,
        xs: [zero; N],
        e: a.delta,
    };
    select(s, s.eq(a.alpha, zero), flat, line)
}

/// `approx::abs` on `[a, b]` with `a < 0 < b` (the lanes where that fails are in the
/// mask): the Chebyshev slope clamped to `[-1, 1]`, `g = |x| - alpha*x` in `[0, max of
/// its ends]` (convex).
#[inline(always)]
fn abs_across<I: Isa>(s: I, a: I::V, b: I::V) -> (Approx<I::V>, I::M) {
    let (zero, one) = (s.splat(0.0), s.splat(1.0));
    let q = s.div(s.add(a, b), s.sub(b, a));
    let q = s.max(s.min(q, one), s.neg(one));
    // `approx::flush`: a subnormal slope is 0.
    let alpha = s.select(s.lt(s.abs(q), s.splat(f64::MIN_POSITIVE)), zero, q);
    let ga = s.sub_up_raw(s.neg(a), s.mul_down_raw(alpha, a));
    let gb = s.sub_up_raw(b, s.mul_down_raw(alpha, b));
    let (ap, ok) = finish(s, alpha, zero, s.max(ga, gb));
    (ap, s.and(ok, s.and(s.lt(a, zero), s.lt(zero, b))))
}

/// RevAA's `|x|` (`Reduced::abs`): the operand or its negation where the directed
/// bounds hold no value of the other sign, else the approximation on the fast bounds.
/// Returns the forms and the lanes left to the scalar operation.
#[inline(always)]
pub(super) fn abs<I: Isa, const N: usize>(s: I, x: Form<I, N>) -> (Form<I, N>, I::M) {
    let zero = s.splat(0.0);
    let b = bounds(s, x);
    let ok = finite(s, b);
    let pos = s.and(ok, s.le(zero, b.0));
    let neg_ = s.and(ok, s.le(b.1, zero));
    let (lo, hi) = bounds_fast(s, x);
    let (ap, good) = abs_across(s, lo, hi);
    let good = s.and(good, finite(s, (lo, hi)));
    let r = select(s, pos, x, select(s, neg_, neg(s, x), apply(s, x, ap)));
    (r, s.not(s.or(s.or(pos, neg_), good)))
}

/// The closed forms of `approx::sqrt` for finite `a < b` (`sqrt_fast` where `a > 0`,
/// `sqrt_fast_across` where `a < 0 < b`), `sb = sqrt(b)`; the lanes where the scalar
/// takes one of them and gets a bounded approximation.
#[inline(always)]
fn sqrt_closed<I: Isa>(s: I, a: I::V, b: I::V, sb: I::V) -> (Approx<I::V>, I::M) {
    let (zero, one) = (s.splat(0.0), s.splat(1.0));
    let next_up = |v| s.add_up_raw(v, s.splat(ETA));
    let next_down = |v| s.add_down_raw(v, s.splat(-ETA));
    // `a > 0`: the secant slope; `g`'s ends with one allowance below, `1/(4 alpha)`
    // through `sum / 4` above.
    let sa = s.sqrt(a);
    let sum = s.add(sa, sb);
    let alpha_in = s.div(one, sum);
    let ga = s.sub(sa, s.mul(alpha_in, a));
    let gb = s.sub(sb, s.mul(alpha_in, b));
    let slack_in = s.add(
        s.mul(s.splat(4.0 * U), s.add(sb, s.mul(alpha_in, b))),
        s.splat(2.0 * ETA),
    );
    let lo_in = s.sub(s.min(ga, gb), slack_in);
    let hi_in = s.mul(s.mul(s.splat(0.25), sum), s.splat(1.0 + 8.0 * U));
    // `a < 0 < b`: the minimax slope of the clipped root.
    let l = s.neg(a);
    let alpha_across = s.select(
        s.le(l, s.mul(s.splat(0.25), b)),
        s.div(one, sb),
        s.select(
            s.le(l, b),
            s.div(s.splat(0.5), s.sqrt(l)),
            s.div(sb, s.sub(b, a)),
        ),
    );
    let ab = s.mul(alpha_across, b);
    let gb_across = next_down(s.sub(next_down(sb), next_up(ab)));
    let rising = s.le(
        s.mul(s.mul(s.splat(2.0), alpha_across), sb),
        s.splat(1.0 - 1e-9),
    );
    let top = s.select(
        rising,
        next_up(s.sub(next_up(sb), next_down(ab))),
        next_up(s.div(s.splat(0.25), alpha_across)),
    );
    let hi_across = s.max(top, next_up(s.neg(s.mul(alpha_across, a))));
    let lo_across = s.min(gb_across, zero);
    let inside = s.lt(zero, a);
    let alpha = s.select(inside, alpha_in, alpha_across);
    let (ap, ok) = finish(
        s,
        alpha,
        s.select(inside, lo_in, lo_across),
        s.select(inside, hi_in, hi_across),
    );
    // Both take a normal positive slope (the across one after `flush`, which makes a
    // subnormal one 0 and so fails the same test).
    let normal = s.and(
        s.le(s.splat(f64::MIN_POSITIVE), alpha),
        s.lt(alpha, s.splat(f64::INFINITY)),
    );
    let taken = s.and(s.lt(a, b), s.or(inside, s.lt(a, zero)));
    (ap, s.and(ok, s.and(normal, taken)))
}

/// RevAA's `sqrt x` (`Reduced::sqrt`): exactly 0 where the fast bounds lie at or below
/// 0, else the closed-form approximation on them. Returns the forms and the lanes left
/// to the scalar operation.
#[inline(always)]
pub(super) fn sqrt<I: Isa, const N: usize>(s: I, x: Form<I, N>) -> (Form<I, N>, I::M) {
    let zero = s.splat(0.0);
    let (a, b) = bounds_fast(s, x);
    let ok = finite(s, (a, b));
    let flat = s.le(b, zero);
    let (ap, good) = sqrt_closed(s, a, b, s.sqrt(b));
    let nought = F {
        x0: zero,
        xs: [zero; N],
        e: zero,
    };
    let r = select(s, flat, nought, apply(s, x, ap));
    (r, s.not(s.and(ok, s.or(flat, good))))
}

/// `1/(k + 1)!` for `k = 12` down to `0`: `(e^w - 1) / w = sum_k w^k / (k + 1)!`.
const EXPM1_COEFFS: &[f64] = EXP_COEFFS.split_at(13).0;

/// The Chebyshev branch of `approx::exp` on `[a, b]`: the secant slope `alpha`, `g =
/// e^x - alpha*x` (convex) at most its larger end and at least `alpha - alpha ln alpha`
/// (its minimum over the reals), with the lanes' proven `exp` and `ln` enclosures in
/// place of libm's, while the approximation's affine range stays above 0 at both ends;
/// else the min-range branch (the slope a lower bound of `e^a`, the same bounds). The
/// lanes where it applies: `-700 <= a < b <= 700` (the lanes' `exp` domain), a normal
/// positive slope and a bounded approximation.
///
/// The slope is `e^a (e^w - 1) / w` (`w = b - a`) with `(e^w - 1) / w` from its Taylor
/// polynomial where `w < 1/2` (to `w^12`, within `1.5e-15`), else `(e^b - e^a) / w` from
/// the lanes' values, not from libm's `exp` and `expm1`: any float slope gives sound
/// bounds (they are computed for the slope taken), but the lower bound holds only
/// near the slope's own minimum point `ln alpha`, which a slope from a cancelling
/// difference of a narrow range would move out of `[a, b]`. So these lanes are sound
/// but not the scalar form's bits (as the interval kernel's `exp` is not).
#[inline(always)]
fn exp_cheb<I: Isa>(s: I, a: I::V, b: I::V) -> (Approx<I::V>, I::M) {
    let zero = s.splat(0.0);
    let (ea, eb) = (exp_lanes(s, a), exp_lanes(s, b));
    let ((fa_lo, fa), fb) = (widen(s, ea), widen(s, eb).1);
    let w = s.sub(b, a);
    let mut q = s.splat(EXPM1_COEFFS[0]);
    for &c in &EXPM1_COEFFS[1..] {
        q = s.fma(w, q, s.splat(c));
    }
    let bound = |alpha| exp_bound(s, (a, b), (fa, fb), alpha);
    let (cheb, cheb_ok) =
        bound(s.select(s.lt(w, s.splat(0.5)), s.mul(ea, q), s.div(s.sub(eb, ea), w)));
    let low = s.sub(s.add(s.mul(cheb.alpha, a), cheb.zeta), cheb.delta);
    let keep = s.and(cheb_ok, s.lt(zero, low));
    // Min-range (the slope a lower bound of `e^a`), where some lane needs it.
    let (ap, ok) = if s.bits(keep) == u8::MAX {
        (cheb, keep)
    } else {
        let (range, range_ok) = bound(fa_lo);
        let ap = Approx {
            alpha: s.select(keep, cheb.alpha, range.alpha),
            zeta: s.select(keep, cheb.zeta, range.zeta),
            delta: s.select(keep, cheb.delta, range.delta),
        };
        (ap, s.or(keep, range_ok))
    };
    let max_arg = s.splat(EXP_MAX_ARG);
    let inside = s.and(s.and(s.le(s.neg(max_arg), a), s.le(b, max_arg)), s.lt(a, b));
    (ap, s.and(inside, ok))
}

/// `g = e^x - alpha*x` over `[a, b]` for a slope `alpha`, given upper bounds `fa`,
/// `fb` of `e^a`, `e^b`: at most its larger end, at least `alpha - alpha ln alpha`; the
/// approximation and whether it is bounded with a normal slope.
#[inline(always)]
fn exp_bound<I: Isa>(
    s: I,
    (a, b): (I::V, I::V),
    (fa, fb): (I::V, I::V),
    alpha: I::V,
) -> (Approx<I::V>, I::M) {
    let hi = s.max(
        s.sub_up_raw(fa, s.mul_down_raw(alpha, a)),
        s.sub_up_raw(fb, s.mul_down_raw(alpha, b)),
    );
    let normal = s.and(
        s.le(s.splat(f64::MIN_POSITIVE), alpha),
        s.lt(alpha, s.splat(f64::INFINITY)),
    );
    // `ln` of a slope outside its domain gives some value; those lanes are dropped.
    let ln_hi = ln_enclosure(s, s.select(normal, alpha, s.splat(1.0))).1;
    let lo = s.mul_down_raw(alpha, s.sub_down_raw(s.splat(1.0), ln_hi));
    let (ap, ok) = finish(s, alpha, lo, hi);
    (ap, s.and(ok, normal))
}

/// RevAA's `exp x` (`Reduced::exp`) where [`exp_cheb`] applies on the fast bounds.
/// Returns the forms and the lanes left to the scalar operation.
#[inline(always)]
pub(super) fn exp<I: Isa, const N: usize>(s: I, x: Form<I, N>) -> (Form<I, N>, I::M) {
    let (a, b) = bounds_fast(s, x);
    let (ap, good) = exp_cheb(s, a, b);
    (apply(s, x, ap), s.not(s.and(finite(s, (a, b)), good)))
}

/// `approx::ln` on `[a, b]` (`ln` is concave): the secant slope `alpha`, `g = ln x -
/// alpha*x` at least its smaller end and at most the tangent at `p = 1/alpha` (its
/// maximum point, clamped into `[a, b]`) over `[a, b]`, `bounds::bound_piece`'s steps
/// with the lanes' proven `ln` enclosures in place of libm's. The lanes where it
/// applies: `0 < a < b`, `a` normal, `b` finite, a normal slope and a bounded result.
///
/// The slope is `(ln b - ln a) / (b - a)` from the lanes' values where `(b - a) / a >=
/// 1/16`, else `2 / (a + b)` (the slope at the midpoint, within `r^2 / 12` relative of
/// the secant's for `r = (b - a) / a`), not libm's `ln_1p`: any slope gives sound
/// bounds, and this one keeps the tangent point inside `[a, b]` where the difference
/// would cancel. Sound, not the scalar form's bits.
#[inline(always)]
fn ln_cheb<I: Isa>(s: I, a: I::V, b: I::V) -> (Approx<I::V>, I::M) {
    let one = s.splat(1.0);
    let (la, lb) = (ln_lanes(s, a), ln_lanes(s, b));
    let (fa, fb) = (widen(s, la).0, widen(s, lb).0);
    let w = s.sub(b, a);
    let alpha = s.select(
        s.lt(w, s.mul(a, s.splat(0.0625))),
        s.div(s.splat(2.0), s.add(a, b)),
        s.div(s.sub(lb, la), w),
    );
    let lo = s.min(
        s.sub_down_raw(fa, s.mul_up_raw(alpha, a)),
        s.sub_down_raw(fb, s.mul_up_raw(alpha, b)),
    );
    // The tangent at `p`: `g(x) <= g(p) + g'(p)(x - p)`, `g'(p) = 1/p - alpha`.
    let p = s.max(s.min(s.div(one, alpha), b), a);
    let fp = ln_enclosure(s, p).1;
    let gp = s.sub_up_raw(fp, s.mul_down_raw(alpha, p));
    let dg = (
        s.sub_down_raw(s.div_down_raw(one, p), alpha),
        s.sub_up_raw(s.div_up_raw(one, p), alpha),
    );
    let (ta, tb) = (s.sub_down_raw(a, p), s.sub_up_raw(b, p));
    let thi = s.max(s.mul_up_raw(dg.0, ta), s.mul_up_raw(dg.1, tb));
    let hi = s.add_up_raw(gp, thi);
    let (ap, ok) = finish(s, alpha, lo, hi);
    let normal = s.and(
        s.le(s.splat(f64::MIN_POSITIVE), alpha),
        s.lt(alpha, s.splat(f64::INFINITY)),
    );
    let inside = s.and(
        s.and(s.le(s.splat(f64::MIN_POSITIVE), a), s.lt(a, b)),
        s.lt(b, s.splat(f64::INFINITY)),
    );
    (ap, s.and(ok, s.and(normal, inside)))
}

/// RevAA's `ln x` (`Reduced::ln`) where [`ln_cheb`] applies on the fast bounds.
/// Returns the forms and the lanes left to the scalar operation.
#[inline(always)]
pub(super) fn ln<I: Isa, const N: usize>(s: I, x: Form<I, N>) -> (Form<I, N>, I::M) {
    let (a, b) = bounds_fast(s, x);
    let (ap, good) = ln_cheb(s, a, b);
    (apply(s, x, ap), s.not(s.and(finite(s, (a, b)), good)))
}

/// `approx::recip`'s closed form (`recip_fast`) on `[a, b]` with `0 < a < b`, or on
/// `[-b, -a]` mirrored where `a < b < 0`: with `c = -alpha > 0`, `g = 1/x + c x` at most
/// its larger end, each term's `next_up`, and at least `2 next_down(sqrt c)`; the
/// Chebyshev slope `c = 1/(ab)` while the approximation stays above 0 at both ends,
/// else `1/b^2`. Returns the lanes where the scalar takes this branch and gets a
/// bounded approximation (the same bits there on the tight paths, as for `sqrt`).
#[inline(always)]
fn recip_closed<I: Isa>(s: I, a: I::V, b: I::V) -> (Approx<I::V>, I::M) {
    let (zero, one, two) = (s.splat(0.0), s.splat(1.0), s.splat(2.0));
    let next_up = |v| s.add_up_raw(v, s.splat(ETA));
    let next_down = |v| s.add_down_raw(v, s.splat(-ETA));
    let mirrored = s.lt(b, zero);
    let (a, b) = (
        s.select(mirrored, s.neg(b), a),
        s.select(mirrored, s.neg(a), b),
    );
    let (ra, rb) = (s.div(one, a), s.div(one, b));
    let bound = |c: I::V| {
        let ga = next_up(s.add(next_up(ra), next_up(s.mul(c, a))));
        let gb = next_up(s.add(next_up(rb), next_up(s.mul(c, b))));
        let lo = s.mul(two, next_down(s.sqrt(c)));
        let (ap, ok) = finish(s, s.neg(c), lo, s.max(ga, gb));
        let normal = s.and(
            s.le(s.splat(f64::MIN_POSITIVE), c),
            s.lt(c, s.splat(f64::INFINITY)),
        );
        (ap, s.and(ok, normal))
    };
    let (cheb, cheb_ok) = bound(s.div(ra, b));
    let low = s.sub(
        s.add(s.min(s.mul(cheb.alpha, a), s.mul(cheb.alpha, b)), cheb.zeta),
        cheb.delta,
    );
    let keep = s.lt(zero, low);
    let (range, range_ok) = bound(s.div(rb, b));
    let ap = Approx {
        alpha: s.select(keep, cheb.alpha, range.alpha),
        zeta: s.select(keep, cheb.zeta, range.zeta),
        delta: s.select(keep, cheb.delta, range.delta),
    };
    let ap = Approx {
        zeta: s.select(mirrored, s.neg(ap.zeta), ap.zeta),
        ..ap
    };
    let ok = s.and(cheb_ok, s.or(keep, range_ok));
    let taken = s.and(
        s.lt(zero, a),
        s.and(s.lt(a, b), s.lt(b, s.splat(f64::INFINITY))),
    );
    (ap, s.and(ok, taken))
}

/// RevAA's `1/x` (`Reduced::recip`) where [`recip_closed`] applies on the fast bounds.
/// Returns the forms and the lanes left to the scalar operation.
#[inline(always)]
pub(super) fn recip<I: Isa, const N: usize>(s: I, x: Form<I, N>) -> (Form<I, N>, I::M) {
    let (a, b) = bounds_fast(s, x);
    let (ap, good) = recip_closed(s, a, b);
    (apply(s, x, ap), s.not(s.and(finite(s, (a, b)), good)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::lanes::{dispatch, F64x8, Kernel, Path, LANES};
    use arith_core::{Range, Real};
    use arith_revaa::RevAa;

    /// Which function [`Unary`] takes.
    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Fun {
        Abs,
        Sqrt,
        Exp,
        Ln,
        Recip,
    }

    impl Fun {
        fn form(self, f: &RevAa<1>) -> RevAa<1> {
            match self {
                Fun::Abs => f.abs(),
                Fun::Sqrt => f.sqrt(),
                Fun::Exp => f.exp(),
                Fun::Ln => f.ln(),
                Fun::Recip => f.recip(),
            }
        }
        fn point(self, v: f64) -> f64 {
            match self {
                Fun::Abs => v.abs(),
                Fun::Sqrt => v.max(0.0).sqrt(),
                Fun::Exp => v.exp(),
                Fun::Ln => v.ln(),
                Fun::Recip => 1.0 / v,
            }
        }
    }

    /// `|x|`, `sqrt x` or `exp x` of eight forms on one path: the forms and the lanes
    /// left to the scalar operation.
    struct Unary<'a> {
        x: &'a [RevAa<1>],
        f: Fun,
    }

    impl Kernel for Unary<'_> {
        type Output = (Vec<RevAa<1>>, u8);
        #[inline(always)]
        fn run<I: Isa>(self, s: I) -> Self::Output {
            let part = |f: &dyn Fn(&RevAa<1>) -> f64| {
                s.load(&F64x8(core::array::from_fn(|l| f(&self.x[l]))))
            };
            let x = F {
                x0: part(&|f| f.x0),
                xs: [part(&|f| f.xs[0])],
                e: part(&|f| f.e),
            };
            let (r, redo) = match self.f {
                Fun::Abs => abs(s, x),
                Fun::Sqrt => sqrt(s, x),
                Fun::Exp => exp(s, x),
                Fun::Ln => ln(s, x),
                Fun::Recip => recip(s, x),
            };
            let (x0, c, e) = (s.store(r.x0), s.store(r.xs[0]), s.store(r.e));
            let forms = (0..LANES)
                .map(|l| RevAa::<1>::from_parts(x0.0[l], [c.0[l]], e.0[l]))
                .collect();
            (forms, s.bits(redo))
        }
    }

    /// Forms with dyadic parts (exact values at dyadic points): wholly negative, across
    /// 0 and wholly positive, with and without an error term.
    fn forms() -> Vec<RevAa<1>> {
        let mut v = Vec::new();
        for k in 0..49 {
            for c in [0.0, -0.125, 1.0, 2.5] {
                for e in [0.0, 1.0 / 64.0, 0.5] {
                    v.push(RevAa::<1>::from_parts(k as f64 / 8.0 - 3.0, [c], e));
                }
            }
        }
        v
    }

    /// On the tight paths each lane is the scalar form bit for bit and none is left to
    /// it; on every path each lane holds the function's values at points of the form.
    #[test]
    fn lanes_are_the_scalar_approximations() {
        let same = |a: &RevAa<1>, b: &RevAa<1>| {
            a.x0.to_bits() == b.x0.to_bits()
                && a.xs[0].to_bits() == b.xs[0].to_bits()
                && a.e.to_bits() == b.e.to_bits()
        };
        let xs = forms();
        for path in Path::available_paths() {
            for fun in [Fun::Abs, Fun::Sqrt] {
                let (mut across, mut redone) = (0, 0);
                for x in xs.chunks_exact(LANES) {
                    let (out, redo) = dispatch(path, Unary { x, f: fun });
                    redone += redo.count_ones();
                    for (l, (o, f)) in out.iter().zip(x).enumerate() {
                        if redo & (1 << l) != 0 {
                            continue;
                        }
                        let want = fun.form(f);
                        let (lo, hi) = f.bounds();
                        across += usize::from(lo < 0.0 && hi > 0.0);
                        if path != Path::Avx2 {
                            assert!(same(o, &want), "{path}: {o:?} vs {want:?} of {f:?}");
                        }
                        let (rl, rh) = o.bounds();
                        for eps in [-1.0, -0.5, 0.0, 0.25, 1.0] {
                            for d in [-f.e, 0.0, f.e] {
                                let v = f.x0 + f.xs[0] * eps + d;
                                let y = fun.point(v);
                                assert!(rl <= y && y <= rh, "{path}: {y} not in [{rl}, {rh}]");
                            }
                        }
                    }
                }
                if path != Path::Avx2 {
                    assert_eq!(redone, 0, "{path}: lanes left to the scalar operation");
                }
                assert!(across > 100, "{path}: {across} ranges across 0");
            }
        }
    }

    /// Two enclosures of one range overlap, and the batched one is at most twice as wide
    /// as the scalar one, plus `2^-30` of its magnitude.
    fn close(batched: (f64, f64), scalar: (f64, f64)) -> bool {
        let width = |(lo, hi): (f64, f64)| hi - lo;
        let size = scalar.0.abs().max(scalar.1.abs());
        batched.0 <= scalar.1
            && scalar.0 <= batched.1
            && width(batched) <= 2.0 * width(scalar) + 2f64.powi(-30) * size
    }

    /// The lanes of `fun` hold its values at points of the forms `xs` (libm's value
    /// within its ulp), are close to the scalar form's range (`exact`: the same bits on
    /// the tight paths), and take most forms (the rest are left to the scalar
    /// operation).
    fn lanes_enclose_and_stay_close(fun: Fun, xs: &[RevAa<1>], exact: bool) {
        for path in Path::available_paths() {
            let (mut taken, mut all) = (0, 0);
            for x in xs.chunks_exact(LANES) {
                let (out, redo) = dispatch(path, Unary { x, f: fun });
                for (l, (o, f)) in out.iter().zip(x).enumerate() {
                    all += 1;
                    if redo & (1 << l) != 0 {
                        continue;
                    }
                    taken += 1;
                    let (rl, rh) = o.bounds();
                    let want = fun.form(f).bounds();
                    assert!(
                        close((rl, rh), want),
                        "{path}, {fun:?}: [{rl}, {rh}] vs {want:?} of {f:?}"
                    );
                    if exact && path != Path::Avx2 {
                        let s = fun.form(f);
                        assert!(
                            o.x0.to_bits() == s.x0.to_bits()
                                && o.xs[0].to_bits() == s.xs[0].to_bits()
                                && o.e.to_bits() == s.e.to_bits(),
                            "{path}, {fun:?}: {o:?} vs {s:?} of {f:?}"
                        );
                    }
                    for eps in [-1.0, -0.5, 0.0, 0.25, 1.0] {
                        for d in [-f.e, 0.0, f.e] {
                            let y = fun.point(f.x0 + f.xs[0] * eps + d);
                            let m = y.abs() * 2f64.powi(-50);
                            assert!(
                                rl <= y + m && y - m <= rh,
                                "{path}, {fun:?}: {y} not in [{rl}, {rh}] of {f:?}"
                            );
                        }
                    }
                }
            }
            assert!(
                2 * taken > all,
                "{path}, {fun:?}: {taken} of {all} lanes taken"
            );
        }
    }

    /// Forms of [`forms`] moved by `shift`, and narrow ones (where a slope from a
    /// difference of the ends would cancel) with centres from `lowest` on.
    fn shifted_and_narrow(shift: f64, lowest: f64) -> Vec<RevAa<1>> {
        let mut xs: Vec<RevAa<1>> = forms()
            .iter()
            .map(|f| RevAa::<1>::from_parts(f.x0 + shift, f.xs, f.e))
            .collect();
        for k in 0..64 {
            let c = [1e-12, 1e-6, 0.01, 0.3][k % 4];
            xs.push(RevAa::<1>::from_parts(lowest + k as f64 / 4.0, [c], 0.0));
        }
        xs
    }

    #[test]
    fn exp_lanes_enclose_and_stay_close() {
        lanes_enclose_and_stay_close(Fun::Exp, &shifted_and_narrow(0.0, -8.0), false);
    }

    #[test]
    fn ln_lanes_enclose_and_stay_close() {
        lanes_enclose_and_stay_close(Fun::Ln, &shifted_and_narrow(6.0, 0.5), false);
    }

    /// `1/x` of positive and (mirrored) negative forms: the scalar bits.
    #[test]
    fn recip_lanes_are_the_scalar_closed_form() {
        let mut xs = shifted_and_narrow(6.0, 0.5);
        xs.extend(
            shifted_and_narrow(6.0, 0.5)
                .iter()
                .map(|f| RevAa::<1>::from_parts(-f.x0, f.xs, f.e)),
        );
        lanes_enclose_and_stay_close(Fun::Recip, &xs, true);
    }

    /// Unbounded, NaN and degenerate ranges are left to the scalar operation.
    #[test]
    fn unusual_lanes_go_to_the_scalar_operation() {
        let x = [
            RevAa::<1>::from_parts(f64::NAN, [1.0], 0.0),
            RevAa::<1>::from_parts(0.0, [f64::INFINITY], 0.0),
            RevAa::<1>::from_parts(1e308, [1e308], 1e308),
            RevAa::<1>::from_parts(0.0, [1.0], f64::NAN),
            RevAa::<1>::from_parts(-1.0, [f64::INFINITY], 0.0),
            RevAa::<1>::from_parts(f64::INFINITY, [0.0], 0.0),
            RevAa::<1>::from_parts(-f64::INFINITY, [0.0], 0.0),
            RevAa::<1>::from_parts(0.0, [1.0], f64::INFINITY),
        ];
        for path in Path::available_paths() {
            for f in [Fun::Abs, Fun::Sqrt, Fun::Exp, Fun::Ln, Fun::Recip] {
                let (_, redo) = dispatch(path, Unary { x: &x, f });
                assert_eq!(redo, 0xff, "{path}, {f:?}");
            }
        }
    }
}
