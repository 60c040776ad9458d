//! WGSL from a [`Program`]: one shader per model and arithmetic. The program becomes
//! three straight-line functions over the same operations: `model_ia` (intervals: the
//! IA search and every arithmetic's sign checks at points), `model_af` (the reduced
//! affine forms of RAA* or RevAA, absent for IA) and `model_pt` (plain `f32`, for
//! normals only: no bound is taken from it). Constants appear as the bit patterns of
//! their outward-rounded `f32` bounds, so no WGSL literal parsing can round them.

use crate::convert;
use crate::program::{Op, Program};
use crate::GpuArith;
use std::fmt::Write;

const ROUND: &str = include_str!("wgsl/round.wgsl");
const IA: &str = include_str!("wgsl/ia.wgsl");
const AFFINE: &str = include_str!("wgsl/affine.wgsl");
const MUL_RAA: &str = include_str!("wgsl/affine_mul_raa.wgsl");
const MUL_REVAA: &str = include_str!("wgsl/affine_mul_revaa.wgsl");
const PLAIN: &str = include_str!("wgsl/plain.wgsl");
const SEARCH: &str = include_str!("wgsl/search.wgsl");

/// The WGSL library of `arith` (rounding, intervals, and the affine forms with the
/// arithmetic's product), without any model or entry point: the property tests wrap
/// their own kernels around it. It expects a `params` uniform with a `zero: u32` field.
pub fn library(arith: GpuArith) -> String {
    let mut s = String::new();
    s.push_str(ROUND);
    s.push_str(IA);
    match arith {
        GpuArith::Ia => {}
        GpuArith::Raa => {
            s.push_str(AFFINE);
            s.push_str(MUL_RAA);
        }
        GpuArith::RevAa => {
            s.push_str(AFFINE);
            s.push_str(MUL_REVAA);
        }
    }
    s
}

/// The whole shader for `program` in `arith`: library, model functions, the search.
pub fn shader(program: &Program, arith: GpuArith) -> Result<String, String> {
    program.check()?;
    let mut s = library(arith);
    s.push_str(PLAIN);
    s.push_str(&model_fn(program, Flavour::Ia));
    s.push_str(&model_fn(program, Flavour::Pt));
    match arith {
        GpuArith::Ia => s.push_str(
            "fn seg_range(j: Job, a: f32, b: f32) -> Seg {
    let x = ia_coord(j.o_mid.x, j.o_rad.x, j.d_mid.x, j.d_rad.x, a, b);
    let y = ia_coord(j.o_mid.y, j.o_rad.y, j.d_mid.y, j.d_rad.y, a, b);
    let z = ia_coord(j.o_mid.z, j.o_rad.z, j.d_mid.z, j.d_rad.z, a, b);
    let f = ia_bounds(model_ia(x, y, z));
    return Seg(f.lo, f.hi, 0.0, 0.0, 0.0, 0.0, 0.0, false);
}
",
        ),
        GpuArith::Raa | GpuArith::RevAa => {
            s.push_str(&model_fn(program, Flavour::Af));
            s.push_str(
                "fn seg_range(j: Job, a: f32, b: f32) -> Seg {
    let t = af_input(a, b);
    let x = af_coord(j.o_mid.x, j.o_rad.x, j.d_mid.x, j.d_rad.x, t);
    let y = af_coord(j.o_mid.y, j.o_rad.y, j.d_mid.y, j.d_rad.y, t);
    let z = af_coord(j.o_mid.z, j.o_rad.z, j.d_mid.z, j.d_rad.z, t);
    let f = model_af(x, y, z);
    let fb = af_bounds(f);
    return Seg(fb.lo, fb.hi, f.c, f.t, f.e, t.c, t.t, !af_ent(f));
}
",
            );
        }
    }
    s.push_str(SEARCH);
    Ok(s)
}

/// Which of the three model functions.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Flavour {
    Ia,
    Af,
    Pt,
}

impl Flavour {
    fn prefix(self) -> &'static str {
        match self {
            Flavour::Ia => "ia",
            Flavour::Af => "af",
            Flavour::Pt => "pt",
        }
    }
    fn ty(self) -> &'static str {
        match self {
            Flavour::Ia => "IA",
            Flavour::Af => "AF",
            Flavour::Pt => "f32",
        }
    }
}

/// `bitcast<f32>(0x...u)`: the exact bits of `v`.
fn lit(v: f32) -> String {
    format!("bitcast<f32>({:#010x}u)", v.to_bits())
}

/// The enclosure of `c` as an operand list `lo, hi` (or `None`: unbounded).
fn bounds(c: f64) -> Option<String> {
    convert::constant(c).map(|(lo, hi)| format!("{}, {}", lit(lo), lit(hi)))
}

/// `1 / c` enclosed: the `f64` quotient widened by one `f64` step each way first.
fn recip_bounds(c: f64) -> Option<String> {
    let q = 1.0 / c;
    if c == 0.0 || !q.is_finite() {
        return None;
    }
    let lo = convert::constant(f64::from_bits_step(q, -1))?.0;
    let hi = convert::constant(f64::from_bits_step(q, 1))?.1;
    Some(format!("{}, {}", lit(lo), lit(hi)))
}

trait Step {
    fn from_bits_step(x: f64, k: i64) -> f64;
}

impl Step for f64 {
    /// `x` moved by one representable step up (`k = 1`) or down (`k = -1`).
    fn from_bits_step(x: f64, k: i64) -> f64 {
        if x == 0.0 {
            return k as f64 * f64::from_bits(1);
        }
        let b = x.to_bits() as i64;
        let towards_larger_magnitude = (x > 0.0) == (k > 0);
        f64::from_bits(if towards_larger_magnitude {
            b + 1
        } else {
            b - 1
        } as u64)
    }
}

fn model_fn(p: &Program, fl: Flavour) -> String {
    let (pre, ty) = (fl.prefix(), fl.ty());
    let mut s = format!("fn model_{pre}(x: {ty}, y: {ty}, z: {ty}) -> {ty} {{\n");
    let entire = match fl {
        Flavour::Ia => "IA_ENTIRE".to_string(),
        Flavour::Af => "AF_ENTIRE".to_string(),
        Flavour::Pt => "0.0".to_string(),
    };
    // Plain f32 constants: the nearest value (normals only).
    let near = |c: f64| lit(c as f32);
    for (k, op) in p.ops.iter().enumerate() {
        let r = |a: u32| format!("r{a}");
        let un = |name: &str, a: u32| format!("{pre}_{name}({})", r(a));
        let bin = |name: &str, a: u32, b: u32| format!("{pre}_{name}({}, {})", r(a), r(b));
        let with_c = |name: &str, a: &str, c: Option<String>| match (fl, c) {
            (Flavour::Pt, _) => unreachable!(),
            (_, Some(c)) => format!("{pre}_{name}({a}, {c})"),
            (_, None) => entire.clone(),
        };
        let e = match (*op, fl) {
            (Op::X, _) => "x".to_string(),
            (Op::Y, _) => "y".to_string(),
            (Op::Z, _) => "z".to_string(),
            (Op::Const(c), Flavour::Pt) => near(c),
            (Op::Const(c), _) => match bounds(c) {
                Some(b) => format!("{pre}_iv({b})"),
                None => entire.clone(),
            },
            (Op::AddC(a, c), Flavour::Pt) => format!("{} + {}", r(a), near(c)),
            (Op::MulC(a, c), Flavour::Pt) => format!("{} * {}", r(a), near(c)),
            (Op::DivC(a, c), Flavour::Pt) => format!("{} / {}", r(a), near(c)),
            (Op::RSubC(a, c), Flavour::Pt) => format!("{} - {}", near(c), r(a)),
            (Op::RDivC(a, c), Flavour::Pt) => format!("{} / {}", near(c), r(a)),
            (Op::AddC(a, c), _) => with_c("addc", &r(a), bounds(c)),
            (Op::MulC(a, c), _) => with_c("mulc", &r(a), bounds(c)),
            (Op::DivC(a, c), _) => with_c("mulc", &r(a), recip_bounds(c)),
            (Op::RSubC(a, c), _) => with_c("addc", &un("neg", a), bounds(c)),
            (Op::RDivC(a, c), _) => with_c("mulc", &un("recip", a), bounds(c)),
            (Op::Neg(a), _) => un("neg", a),
            (Op::Sqr(a), _) => un("sqr", a),
            (Op::Powi(a, n), _) => format!("{pre}_powi({}, {n})", r(a)),
            (Op::Sqrt(a), _) => un("sqrt", a),
            (Op::Recip(a), _) => un("recip", a),
            (Op::Exp(a), _) => un("exp", a),
            (Op::Ln(a), _) => un("ln", a),
            (Op::Sin(a), _) => un("sin", a),
            (Op::Cos(a), _) => un("cos", a),
            (Op::Abs(a), _) => un("abs", a),
            (Op::Add(a, b), _) => bin("add", a, b),
            (Op::Sub(a, b), _) => bin("sub", a, b),
            (Op::Mul(a, b), _) => bin("mul", a, b),
            (Op::Div(a, b), _) => bin("div", a, b),
            (Op::Min(a, b), _) => bin("min", a, b),
            (Op::Max(a, b), _) => bin("max", a, b),
            (Op::Hypot(a, b), _) => bin("hypot", a, b),
            (Op::RUnion(a, b), _) => bin("runion", a, b),
            (Op::RIntersect(a, b), _) => bin("rinter", a, b),
            (Op::RSubtract(a, b), _) => format!("{pre}_rinter({}, {pre}_neg({}))", r(a), r(b)),
            (Op::Gt0(a), _) => un("gt0", a),
            (Op::Ge0(a), _) => un("ge0", a),
            (Op::Select(c, t, e), _) => format!("{pre}_select({}, {}, {})", r(c), r(t), r(e)),
        };
        let _ = writeln!(s, "    let r{k} = {e};");
    }
    let _ = writeln!(s, "    return r{};\n}}", p.ops.len() - 1);
    s
}
