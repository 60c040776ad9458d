// Reduced affine forms on the ray's one input symbol, c + t eps + [-e, e], in f32 (RAA*
// and RevAA; only the product differs, in affine_mul_*.wgsl). Every operation adds
// bounds of its own rounding errors to `e` (`rerr` of each rounded centre or
// coefficient) and rounds `e` itself upward. A form with a part at or beyond LIM is the
// whole line.

struct AF {
    c: f32,
    t: f32,
    e: f32,
}

const AF_ENTIRE = AF(0.0, 0.0, BIG);

fn af_ent(a: AF) -> bool {
    return !(abs(a.c) < LIM && abs(a.t) < LIM && a.e < LIM);
}

// An upper bound of |t| + e.
fn af_rad(a: AF) -> f32 {
    return acc(abs(a.t), a.e);
}

fn af_bounds(a: AF) -> IA {
    if (af_ent(a)) {
        return IA_ENTIRE;
    }
    let r = af_rad(a);
    return IA(dn(a.c - r), up(a.c + r));
}

// The segment [lo, hi] as the input symbol: t = m + r eps with [m - r, m + r] covering it.
fn af_input(lo: f32, hi: f32) -> AF {
    let m = opq(0.5 * lo + 0.5 * hi);
    let r = up(max(hi - m, m - lo));
    return AF(m, r, 0.0);
}

// A value only known to lie in [lo, hi].
fn af_from_ia(v: IA) -> AF {
    if (ia_ent(v)) {
        return AF_ENTIRE;
    }
    let z = opq(0.5 * v.lo + 0.5 * v.hi);
    return AF(z, 0.0, up(max(v.hi - z, z - v.lo)));
}

fn af_iv(lo: f32, hi: f32) -> AF {
    return af_from_ia(IA(lo, hi));
}

fn af_neg(a: AF) -> AF {
    return AF(-a.c, -a.t, a.e);
}

fn af_add(a: AF, b: AF) -> AF {
    if (af_ent(a) || af_ent(b)) {
        return AF_ENTIRE;
    }
    let c = opq(a.c + b.c);
    let t = opq(a.t + b.t);
    return AF(c, t, acc(acc(a.e, b.e), acc(rerr(c), rerr(t))));
}

fn af_sub(a: AF, b: AF) -> AF {
    return af_add(a, af_neg(b));
}

// a + k for a constant k in [lo, hi].
fn af_addc(a: AF, lo: f32, hi: f32) -> AF {
    if (af_ent(a)) {
        return AF_ENTIRE;
    }
    let c = opq(a.c + lo);
    var e = acc(a.e, rerr(c));
    if (hi != lo) {
        e = acc(e, up(hi - lo));
    }
    return AF(c, a.t, e);
}

// a * k for a constant k in [lo, hi].
fn af_mulc(a: AF, lo: f32, hi: f32) -> AF {
    if (af_ent(a)) {
        return AF_ENTIRE;
    }
    let c = opq(a.c * lo);
    let t = opq(a.t * lo);
    var e = acc(mulup(a.e, abs(lo)), acc(rerr(c), rerr(t)));
    if (hi != lo) {
        e = acc(e, mulup(acc(abs(a.c), af_rad(a)), up(hi - lo)));
    }
    return AF(c, t, e);
}

// alpha a + zeta +- delta with [zeta - delta, zeta + delta] covering [glo, ghi]: the
// affine approximation of a unary function f where g = f - alpha x ranges over
// [glo, ghi] on the operand's range.
fn af_apply(a: AF, alpha: f32, glo: f32, ghi: f32) -> AF {
    if (is_big(glo) || is_big(ghi) || is_big(alpha)) {
        return AF_ENTIRE;
    }
    let zeta = opq(0.5 * glo + 0.5 * ghi);
    let delta = up(max(ghi - zeta, zeta - glo));
    if (alpha == 0.0) {
        return AF(zeta, 0.0, delta);
    }
    let p = opq(alpha * a.c);
    let c = opq(p + zeta);
    let t = opq(alpha * a.t);
    let e = acc(acc(mulup(abs(alpha), a.e), delta), acc(acc(rerr(p), rerr(c)), rerr(t)));
    return AF(c, t, e);
}

// The Chebyshev square: with w = t eps + e u, |w| <= W, x^2 = c^2 + 2 c t eps + 2 c e u
// + w^2 and w^2 in [0, W^2] = W^2/2 +- W^2/2.
fn af_sqr(a: AF) -> AF {
    if (af_ent(a)) {
        return AF_ENTIRE;
    }
    let w = af_rad(a);
    let s = opq(a.c * a.c);
    let hw = up(0.5 * mulup(w, w));
    let c = opq(s + hw);
    let t = opq((2.0 * a.c) * a.t);
    let e = acc(acc(mulup(2.0 * abs(a.c), a.e), hw), acc(acc(rerr(s), rerr(c)), rerr(t)));
    return AF(c, t, e);
}

fn af_recip(a: AF) -> AF {
    let b = af_bounds(a);
    if (ia_ent(b) || !(b.lo >= 1.0 / LIM || b.hi <= -1.0 / LIM)) {
        return AF_ENTIRE;
    }
    // Min-range: with |alpha| <= 1 / max|x|^2, g = 1/x - alpha x decreases on the range.
    let q = recip_dn(max(-b.lo, b.hi));
    let alpha = -max(dn(q * q), 0.0);
    let ghi = up(recip_up(b.lo) - dn(alpha * b.lo));
    let glo = dn(recip_dn(b.hi) - up(alpha * b.hi));
    return af_apply(a, alpha, glo, ghi);
}

fn af_div(a: AF, b: AF) -> AF {
    return af_mul(a, af_recip(b));
}

fn af_powi(a: AF, n: i32) -> AF {
    if (n == 0) {
        return AF(1.0, 0.0, 0.0);
    }
    var m = u32(abs(n));
    var base = a;
    var r = a;
    var started = false;
    loop {
        if ((m & 1u) == 1u) {
            if (started) {
                r = af_mul(r, base);
            } else {
                r = base;
                started = true;
            }
        }
        m = m >> 1u;
        if (m == 0u) {
            break;
        }
        base = af_sqr(base);
    }
    if (n < 0) {
        return af_recip(r);
    }
    return r;
}

// sqrt(max(x, 0)) knowing x >= fl (a true bound of the value, not a clip at 0). Min-range with alpha <= 1 / (2 sqrt(hi)): g = sqrt - alpha x
// increases on [0, hi]; below 0 g = -alpha x, at most -alpha lo.
fn af_sqrt_floor(a: AF, fl: f32) -> AF {
    let b = af_bounds(a);
    if (ia_ent(b)) {
        return AF_ENTIRE;
    }
    if (b.hi <= 0.0) {
        return AF(0.0, 0.0, 0.0);
    }
    if (b.hi < 0x1p-100f) {
        return af_from_ia(IA(0.0, 0x1p-50f));
    }
    let lo = max(b.lo, fl);
    let alpha = max(step_dn(0.5 / sqrt_up(b.hi), 6u), 0.0);
    var glo = 0.0;
    if (lo > 0.0) {
        glo = dn(sqrt_dn(lo) - up(alpha * lo));
    }
    var ghi = up(sqrt_up(b.hi) - dn(alpha * b.hi));
    if (lo < 0.0) {
        ghi = max(ghi, up(-alpha * lo));
    }
    return af_apply(a, alpha, glo, ghi);
}

// No floor known: the part of the range below 0 counts (where g = -alpha x).
fn af_sqrt(a: AF) -> AF {
    return af_sqrt_floor(a, -BIG);
}

// sqrt(a^2 + b^2), whose argument is at least mig(a)^2 + mig(b)^2.
fn af_hypot(a: AF, b: AF) -> AF {
    let ma = ia_mig(af_bounds(a));
    let mb = ia_mig(af_bounds(b));
    let fl = max(dn(max(dn(ma * ma), 0.0) + max(dn(mb * mb), 0.0)), 0.0);
    return af_sqrt_floor(af_add(af_sqr(a), af_sqr(b)), fl);
}

// The R-union a + b + sqrt(a^2 + b^2). Written out, its sum cancels where one operand
// m is negative and at least as large in magnitude as the other, o, is anywhere: the
// rounding of the three terms (of m's size) then swamps the result (of o's size at
// most). There it is o + o^2 / (h - m), whose terms are of o's size or smaller and
// whose h - m >= -m > 0; o keeps its symbol, so pruning still sees the slope.
fn af_runion(a: AF, b: AF) -> AF {
    let ba = af_bounds(a);
    let bb = af_bounds(b);
    var m = b;
    var o = a;
    var bm = bb;
    var bo = ba;
    if (ba.hi < bb.hi) {
        m = a;
        o = b;
        bm = ba;
        bo = bb;
    }
    if (bm.hi < 0.0 && ia_mag(bo) <= -bm.hi) {
        return af_add(o, af_div(af_sqr(o), af_sub(af_hypot(o, m), m)));
    }
    return af_add(af_add(a, b), af_hypot(a, b));
}

// The R-intersection: -g(-a, -b).
fn af_rinter(a: AF, b: AF) -> AF {
    return af_neg(af_runion(af_neg(a), af_neg(b)));
}

// Min-range with alpha = a lower bound of e^lo: g = e^x - alpha x increases.
fn af_exp(a: AF) -> AF {
    let b = af_bounds(a);
    if (ia_ent(b) || b.hi > 41.0) {
        return AF_ENTIRE;
    }
    let alpha = exp_dn(b.lo);
    let glo = dn(exp_dn(b.lo) - up(alpha * b.lo));
    let ghi = up(exp_up(b.hi) - dn(alpha * b.hi));
    return af_apply(a, alpha, glo, ghi);
}

// Min-range with alpha = a lower bound of 1/hi: g = ln x - alpha x increases.
fn af_ln(a: AF) -> AF {
    let b = af_bounds(a);
    if (ia_ent(b) || b.lo < 1.0 / LIM) {
        return AF_ENTIRE;
    }
    let alpha = max(recip_dn(b.hi), 0.0);
    let glo = dn(ln_dn(b.lo) - up(alpha * b.lo));
    let ghi = up(ln_up(b.hi) - dn(alpha * b.hi));
    return af_apply(a, alpha, glo, ghi);
}

fn af_sin(a: AF) -> AF {
    return af_from_ia(ia_sin(af_bounds(a)));
}

fn af_cos(a: AF) -> AF {
    return af_from_ia(ia_cos(af_bounds(a)));
}

fn af_abs(a: AF) -> AF {
    let b = af_bounds(a);
    if (b.lo >= 0.0) {
        return a;
    }
    if (b.hi <= 0.0) {
        return af_neg(a);
    }
    return af_from_ia(ia_abs(b));
}

fn af_min(a: AF, b: AF) -> AF {
    let x = af_bounds(a);
    let y = af_bounds(b);
    if (x.hi <= y.lo) {
        return a;
    }
    if (y.hi <= x.lo) {
        return b;
    }
    return af_from_ia(ia_min(x, y));
}

fn af_max(a: AF, b: AF) -> AF {
    let x = af_bounds(a);
    let y = af_bounds(b);
    if (x.lo >= y.hi) {
        return a;
    }
    if (y.lo >= x.hi) {
        return b;
    }
    return af_from_ia(ia_max(x, y));
}

// Truth values and branches as in IA, on the forms' bounds; an undecided branch is the
// hull of both as an interval (no symbol is shared with either branch).
fn af_gt0(a: AF) -> AF {
    return af_from_ia(ia_gt0(af_bounds(a)));
}

fn af_ge0(a: AF) -> AF {
    return af_from_ia(ia_ge0(af_bounds(a)));
}

fn af_select(c: AF, t: AF, e: AF) -> AF {
    let b = af_bounds(c);
    if (b.lo > 0.5) {
        return t;
    }
    if (b.hi < 0.5) {
        return e;
    }
    return af_from_ia(ia_select(b, af_bounds(t), af_bounds(e)));
}

// x = o + t d over the input symbol t = m + r eps: o and d as mid +- rad.
fn af_coord(om: f32, orad: f32, dm: f32, drad: f32, t: AF) -> AF {
    let p = opq(dm * t.c);
    let c = opq(om + p);
    let tt = opq(dm * t.t);
    let e = acc(acc(orad, mulup(drad, acc(abs(t.c), t.t))), acc(acc(rerr(p), rerr(c)), rerr(tt)));
    return AF(c, tt, e);
}
