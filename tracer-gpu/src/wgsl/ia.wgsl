// Interval arithmetic in f32 with outward rounding. An interval with a bound at or
// beyond LIM is the whole line.

struct IA {
    lo: f32,
    hi: f32,
}

const IA_ENTIRE = IA(-BIG, BIG);
const PI_LO: f32 = 3.1415925;
const PI_HI: f32 = 3.141593;
const PIH_LO: f32 = 1.5707963;
const PIH_HI: f32 = 1.5707964;

fn ia_ent(a: IA) -> bool {
    return !(a.lo > -LIM && a.hi < LIM);
}

fn ia_point(v: f32) -> IA {
    return IA(v, v);
}

fn ia_iv(lo: f32, hi: f32) -> IA {
    return IA(lo, hi);
}

fn ia_neg(a: IA) -> IA {
    return IA(-a.hi, -a.lo);
}

fn ia_add(a: IA, b: IA) -> IA {
    if (ia_ent(a) || ia_ent(b)) {
        return IA_ENTIRE;
    }
    return IA(dn(a.lo + b.lo), up(a.hi + b.hi));
}

fn ia_sub(a: IA, b: IA) -> IA {
    return ia_add(a, ia_neg(b));
}

fn ia_mul(a: IA, b: IA) -> IA {
    if (ia_ent(a) || ia_ent(b)) {
        return IA_ENTIRE;
    }
    let p1 = a.lo * b.lo;
    let p2 = a.lo * b.hi;
    let p3 = a.hi * b.lo;
    let p4 = a.hi * b.hi;
    return IA(dn(min(min(p1, p2), min(p3, p4))), up(max(max(p1, p2), max(p3, p4))));
}

fn ia_addc(a: IA, lo: f32, hi: f32) -> IA {
    return ia_add(a, IA(lo, hi));
}

fn ia_mulc(a: IA, lo: f32, hi: f32) -> IA {
    return ia_mul(a, IA(lo, hi));
}

fn ia_mig(a: IA) -> f32 {
    if (a.lo > 0.0) {
        return a.lo;
    }
    if (a.hi < 0.0) {
        return -a.hi;
    }
    return 0.0;
}

fn ia_mag(a: IA) -> f32 {
    return max(-a.lo, a.hi);
}

fn ia_sqr(a: IA) -> IA {
    if (ia_ent(a)) {
        return IA_ENTIRE;
    }
    let m = ia_mig(a);
    let g = ia_mag(a);
    return IA(max(dn(m * m), 0.0), up(g * g));
}

// Powers of m >= 0 rounded down / up, one rounding per product.
fn pow_dn(m: f32, n: u32) -> f32 {
    var r = m;
    for (var k = 1u; k < n; k++) {
        r = max(dn(r * m), 0.0);
        if (r >= LIM) {
            return LIM;
        }
    }
    return r;
}
fn pow_up(m: f32, n: u32) -> f32 {
    var r = m;
    for (var k = 1u; k < n; k++) {
        r = up(r * m);
        if (r >= LIM) {
            return BIG;
        }
    }
    return r;
}

fn ia_recip(a: IA) -> IA {
    if (ia_ent(a) || !(a.lo >= 1.0 / LIM || a.hi <= -1.0 / LIM)) {
        return IA_ENTIRE;
    }
    return IA(recip_dn(a.hi), recip_up(a.lo));
}

fn ia_powi(a: IA, n: i32) -> IA {
    if (n == 0) {
        return IA(1.0, 1.0);
    }
    if (ia_ent(a)) {
        return IA_ENTIRE;
    }
    let k = u32(abs(n));
    var r: IA;
    if (k % 2u == 0u) {
        r = IA(pow_dn(ia_mig(a), k), pow_up(ia_mag(a), k));
    } else {
        // Odd powers are increasing: the sign follows each bound.
        var lo: f32;
        var hi: f32;
        if (a.lo >= 0.0) {
            lo = pow_dn(a.lo, k);
        } else {
            lo = -pow_up(-a.lo, k);
        }
        if (a.hi >= 0.0) {
            hi = pow_up(a.hi, k);
        } else {
            hi = -pow_dn(-a.hi, k);
        }
        r = IA(lo, hi);
    }
    if (n < 0) {
        return ia_recip(r);
    }
    return r;
}

fn ia_div(a: IA, b: IA) -> IA {
    return ia_mul(a, ia_recip(b));
}

fn ia_sqrt(a: IA) -> IA {
    if (ia_ent(a)) {
        return IA(0.0, BIG);
    }
    if (a.hi <= 0.0) {
        return IA(0.0, 0.0);
    }
    return IA(sqrt_dn(max(a.lo, 0.0)), sqrt_up(a.hi));
}

fn ia_hypot(a: IA, b: IA) -> IA {
    return ia_sqrt(ia_add(ia_sqr(a), ia_sqr(b)));
}

// g(a, b) = a + b + sqrt(a^2 + b^2) at the exact point (a, b), enclosed. With m < 0
// the smaller operand and o the other, m + sqrt(o^2 + m^2) = o^2 / (h - m), where
// h - m >= -m > 0: no cancellation, however far below o the operand m lies.
fn ia_runion_at(a: f32, b: f32) -> IA {
    let m = min(a, b);
    let o = max(a, b);
    let h = ia_hypot(ia_point(a), ia_point(b));
    if (m >= 0.0) {
        return ia_add(ia_add(ia_point(a), ia_point(b)), h);
    }
    return ia_add(ia_point(o), ia_div(ia_sqr(ia_point(o)), ia_sub(h, ia_point(m))));
}

// The R-union. dg/da = 1 + a / sqrt(a^2 + b^2) >= 0 and likewise in b (g is continuous
// at the origin), so g is nondecreasing in both operands: its range over a box lies
// between its values at the lower and the upper corner.
fn ia_runion(a: IA, b: IA) -> IA {
    if (ia_ent(a) || ia_ent(b)) {
        return IA_ENTIRE;
    }
    return IA(ia_runion_at(a.lo, b.lo).lo, ia_runion_at(a.hi, b.hi).hi);
}

// The R-intersection: a + b - sqrt(a^2 + b^2) = -g(-a, -b).
fn ia_rinter(a: IA, b: IA) -> IA {
    return ia_neg(ia_runion(ia_neg(a), ia_neg(b)));
}

fn ia_exp(a: IA) -> IA {
    if (ia_ent(a) || a.hi > 41.0) {
        return IA(exp_dn(max(a.lo, -100.0)), BIG);
    }
    return IA(exp_dn(a.lo), exp_up(a.hi));
}

fn ia_ln(a: IA) -> IA {
    if (ia_ent(a)) {
        return IA_ENTIRE;
    }
    // ln is increasing; below LIM^-1 (and at or below 0, where ln = -inf) unbounded.
    var lo = -BIG;
    if (a.lo >= 1.0 / LIM) {
        lo = ln_dn(a.lo);
    }
    var hi = -41.0;
    if (a.hi >= 1.0 / LIM) {
        hi = ln_up(a.hi);
    }
    return IA(lo, hi);
}

// sin on [-pi, pi] has an absolute error of at most 2^-11; arguments are reduced by
// k pi (sin(x) = (-1)^k sin(x - k pi), k pi enclosed) and only used when the reduced
// interval lies in [-pi, pi].
fn ia_sin(a: IA) -> IA {
    if (ia_ent(a) || !(a.hi - a.lo <= 3.0) || abs(a.lo) > 0x1p20f || abs(a.hi) > 0x1p20f) {
        return IA(-1.0, 1.0);
    }
    let k = round((0.5 * a.lo + 0.5 * a.hi) * 0.31830987);
    let r = ia_sub(a, ia_mul(IA(k, k), IA(PI_LO, PI_HI)));
    if (r.lo < -PI_LO || r.hi > PI_LO) {
        return IA(-1.0, 1.0);
    }
    let s0 = sin(r.lo);
    let s1 = sin(r.hi);
    var lo = dn(min(s0, s1) - 0x1p-11f);
    var hi = up(max(s0, s1) + 0x1p-11f);
    if (r.lo <= PIH_HI && r.hi >= PIH_LO) {
        hi = 1.0;
    }
    if (r.lo <= -PIH_LO && r.hi >= -PIH_HI) {
        lo = -1.0;
    }
    lo = max(lo, -1.0);
    hi = min(hi, 1.0);
    if ((i32(k) & 1) != 0) {
        return IA(-hi, -lo);
    }
    return IA(lo, hi);
}

fn ia_cos(a: IA) -> IA {
    return ia_sin(ia_add(a, IA(PIH_LO, PIH_HI)));
}

fn ia_abs(a: IA) -> IA {
    if (a.lo >= 0.0) {
        return a;
    }
    if (a.hi <= 0.0) {
        return ia_neg(a);
    }
    return IA(0.0, max(-a.lo, a.hi));
}

fn ia_min(a: IA, b: IA) -> IA {
    return IA(min(a.lo, b.lo), min(a.hi, b.hi));
}

fn ia_max(a: IA, b: IA) -> IA {
    return IA(max(a.lo, b.lo), max(a.hi, b.hi));
}

// Truth values: exact 0 or 1 where the bounds decide the comparison, else [0, 1]. The
// bounds enclose the value, so a decided comparison holds at every point.
fn ia_gt0(a: IA) -> IA {
    if (a.lo > 0.0) {
        return IA(1.0, 1.0);
    }
    if (a.hi <= 0.0) {
        return IA(0.0, 0.0);
    }
    return IA(0.0, 1.0);
}

fn ia_ge0(a: IA) -> IA {
    if (a.lo >= 0.0) {
        return IA(1.0, 1.0);
    }
    if (a.hi < 0.0) {
        return IA(0.0, 0.0);
    }
    return IA(0.0, 1.0);
}

// The branch the truth value c picks at every point (c > 1/2: t), else the hull of both.
fn ia_select(c: IA, t: IA, e: IA) -> IA {
    if (c.lo > 0.5) {
        return t;
    }
    if (c.hi < 0.5) {
        return e;
    }
    return IA(min(t.lo, e.lo), max(t.hi, e.hi));
}

fn ia_bounds(a: IA) -> IA {
    if (ia_ent(a)) {
        return IA_ENTIRE;
    }
    return a;
}

// x = o + t d on the segment [a, b] of the ray: origin and direction as mid +- rad.
fn ia_coord(om: f32, orad: f32, dm: f32, drad: f32, a: f32, b: f32) -> IA {
    let o = IA(dn(om - orad), up(om + orad));
    let d = IA(dn(dm - drad), up(dm + drad));
    return ia_add(o, ia_mul(IA(a, b), d));
}
