// Plain f32 evaluation, for normals only (no bound is taken from these values).
fn pt_neg(a: f32) -> f32 { return -a; }
fn pt_sqr(a: f32) -> f32 { return a * a; }
fn pt_powi(a: f32, n: i32) -> f32 {
    var r = 1.0;
    for (var k = 0; k < abs(n); k++) { r = r * a; }
    if (n < 0) { return 1.0 / r; }
    return r;
}
fn pt_sqrt(a: f32) -> f32 { return sqrt(max(a, 0.0)); }
fn pt_recip(a: f32) -> f32 { return 1.0 / a; }
fn pt_exp(a: f32) -> f32 { return exp(min(a, 80.0)); }
fn pt_ln(a: f32) -> f32 { if (a <= 0.0) { return -BIG; } return log(a); }
fn pt_sin(a: f32) -> f32 { return sin(a); }
fn pt_cos(a: f32) -> f32 { return cos(a); }
fn pt_abs(a: f32) -> f32 { return abs(a); }
fn pt_add(a: f32, b: f32) -> f32 { return a + b; }
fn pt_sub(a: f32, b: f32) -> f32 { return a - b; }
fn pt_mul(a: f32, b: f32) -> f32 { return a * b; }
fn pt_div(a: f32, b: f32) -> f32 { return a / b; }
fn pt_min(a: f32, b: f32) -> f32 { return min(a, b); }
fn pt_max(a: f32, b: f32) -> f32 { return max(a, b); }
fn pt_hypot(a: f32, b: f32) -> f32 { return sqrt(a * a + b * b); }
// As ia_runion_at: o + o^2 / (h - m) when the smaller operand m is negative.
fn pt_runion(a: f32, b: f32) -> f32 {
    let m = min(a, b);
    let o = max(a, b);
    let h = sqrt(a * a + b * b);
    if (m >= 0.0) { return a + b + h; }
    return o + o * o / (h - m);
}
fn pt_rinter(a: f32, b: f32) -> f32 { return -pt_runion(-a, -b); }
fn pt_gt0(a: f32) -> f32 { return select(0.0, 1.0, a > 0.0); }
fn pt_ge0(a: f32) -> f32 { return select(0.0, 1.0, a >= 0.0); }
fn pt_select(c: f32, t: f32, e: f32) -> f32 { return select(e, t, c > 0.5); }
