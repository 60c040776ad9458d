// Outward rounding in f32 by stepping bits (see the crate doc for the per-operation
// argument). Every bound a form or interval stores is either an exact value or the
// result of `up`/`dn`/`step_up`/`step_dn`; none is subnormal (|v| < TINY snaps to
// +-TINY), so no stored value is flushed to zero when read.

const TINY: f32 = 0x1p-124f;
// Magnitudes at or above LIM mean "unbounded": products of two values below it stay
// far below f32's overflow threshold, so no operation ever overflows.
const LIM: f32 = 0x1p60f;
const BIG: f32 = 0x1p100f;
// Relative bound (with the binade slack) on one faithfully rounded operation's error.
const REL1: f32 = 0x1p-22f;
// Absolute term for a result flushed to zero (a subnormal is below 2^-126).
const ABS1: f32 = 0x1p-125f;

// `x` with its bits or-ed with a uniform zero the compiler cannot see: a value passed
// through it cannot be re-associated or fused with the operations that produced it.
fn opq(x: f32) -> f32 {
    return bitcast<f32>(bitcast<u32>(x) | params.zero);
}

// `x` moved up by `n` representable steps (`x` finite, below BIG in magnitude).
fn step_up(x: f32, n: u32) -> f32 {
    if (abs(x) < TINY) {
        return TINY;
    }
    let b = bitcast<u32>(x);
    if (x > 0.0) {
        return bitcast<f32>(b + n);
    }
    return bitcast<f32>(b - n);
}

// `x` moved down by `n` representable steps.
fn step_dn(x: f32, n: u32) -> f32 {
    return -step_up(-x, n);
}

// One step: the bounds of a faithfully rounded (+ - *) result.
fn up(x: f32) -> f32 {
    return step_up(x, 1u);
}
fn dn(x: f32) -> f32 {
    return step_dn(x, 1u);
}

// An upper bound of |exact - c| for the faithfully rounded result `c` of one + - *.
fn rerr(c: f32) -> f32 {
    return up(abs(c) * REL1 + ABS1);
}

// Upper bounds of sums and products of nonnegative values.
fn acc(a: f32, b: f32) -> f32 {
    return up(a + b);
}
fn mulup(a: f32, b: f32) -> f32 {
    return up(a * b);
}

fn is_big(v: f32) -> bool {
    return !(abs(v) < LIM);
}

// Bounds of builtins with the WGSL accuracy of each (crate doc, "Per operation").
// 1 / v for LIM^-1 <= |v| < LIM: 2.5 ULP -> 6 steps.
fn recip_dn(v: f32) -> f32 {
    return step_dn(1.0 / v, 6u);
}
fn recip_up(v: f32) -> f32 {
    return step_up(1.0 / v, 6u);
}
// sqrt: inherited from 1 / inverseSqrt (2 ULP then 2.5 ULP): 12 steps. Arguments below
// 2^-100 are not passed to the builtin.
fn sqrt_dn(v: f32) -> f32 {
    if (v < 0x1p-100f) {
        return 0.0;
    }
    return max(step_dn(sqrt(v), 12u), 0.0);
}
fn sqrt_up(v: f32) -> f32 {
    if (v < 0x1p-100f) {
        return 0x1p-50f;
    }
    return step_up(sqrt(v), 12u);
}
// exp: 3 + 2|x| ULP; used for -80 <= v <= 41 only (results normal, below LIM).
fn exp_steps(v: f32) -> u32 {
    return u32(2.0 * (3.0 + 2.0 * abs(v))) + 2u;
}
fn exp_dn(v: f32) -> f32 {
    if (v < -80.0) {
        return 0.0;
    }
    return max(step_dn(exp(v), exp_steps(v)), 0.0);
}
fn exp_up(v: f32) -> f32 {
    if (v < -80.0) {
        return 0x1p-115f;
    }
    return step_up(exp(v), exp_steps(v));
}
// log: absolute 2^-21 on [0.5, 2], 3 ULP elsewhere; for v >= LIM^-1 only.
fn ln_dn(v: f32) -> f32 {
    let c = log(v);
    if (v >= 0.5 && v <= 2.0) {
        return dn(c - 0x1p-21f);
    }
    return step_dn(c, 7u);
}
fn ln_up(v: f32) -> f32 {
    let c = log(v);
    if (v >= 0.5 && v <= 2.0) {
        return up(c + 0x1p-21f);
    }
    return step_up(c, 7u);
}
