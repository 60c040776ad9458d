//! WGSL from a tape of the model IR ([`model_ir::Tape`]): one shader per model and
//! arithmetic. The tape is first lowered ([`lower`]: blends written out, R-functions
//! fused), then becomes three straight-line functions over the same operations: `model_ia` (intervals: the
//! IA search and every arithmetic's sign checks at points), `model_af` (the reduced
//! affine forms of RAA* or RevAA, absent for IA) and `model_pt` (plain `f32`, for
//! normals only: no bound is taken from it). Constants appear as the bit patterns of
//! their outward-rounded `f32` bounds, so no WGSL literal parsing can round them.

use crate::convert;
use crate::GpuArith;
use model_ir::{Instr, Op, Tape};
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

/// `tape` as the generated code evaluates it: recorded through its own evaluation
/// ([`Tape::record`]), so that the blends become the operations of
/// [`model_ir::arith_core::rfunc`] they are made of, and with its R-functions fused
/// ([`Tape::fuse_rfunctions`]: in `f32` the written-out form cancels).
pub fn lower(tape: &Tape) -> Tape {
    Tape::record(|x, y, z| tape.eval(x, y, z)).fuse_rfunctions()
}

/// The whole shader for `tape` in `arith`: library, model functions, the search.
pub fn shader(tape: &Tape, arith: GpuArith) -> Result<String, String> {
    let program = &lower(tape);
    if let Some(i) = program
        .instructions()
        .iter()
        .find(|i| matches!(i.op, Op::BlendUnion | Op::BlendIntersect))
    {
        // `lower` writes blends out; nothing else reaches here.
        return Err(format!("the GPU has no instruction for '{i}'"));
    }
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

fn model_fn(p: &Tape, fl: Flavour) -> String {
    let (pre, ty) = (fl.prefix(), fl.ty());
    let mut s = format!("fn model_{pre}(x: {ty}, y: {ty}, z: {ty}) -> {ty} {{\n");
    for (k, i) in p.instructions().iter().enumerate() {
        let _ = writeln!(s, "    let r{k} = {};", expression(i, fl));
    }
    let _ = writeln!(s, "    return r{};\n}}", p.len() - 1);
    s
}

/// The WGSL expression of instruction `i` in the flavour `fl`.
fn expression(i: &Instr, fl: Flavour) -> String {
    let pre = fl.prefix();
    let entire = match fl {
        Flavour::Ia => "IA_ENTIRE".to_string(),
        Flavour::Af => "AF_ENTIRE".to_string(),
        Flavour::Pt => "0.0".to_string(),
    };
    // Plain f32 constants: the nearest value (normals only).
    let near = |c: f64| lit(c as f32);
    let r = |a: u32| format!("r{a}");
    let un = |name: &str, a: u32| format!("{pre}_{name}({})", r(a));
    let bin = |name: &str, a: u32, b: u32| format!("{pre}_{name}({}, {})", r(a), r(b));
    let with_c = |name: &str, a: &str, c: Option<String>| match c {
        Some(c) => format!("{pre}_{name}({a}, {c})"),
        None => entire.clone(),
    };
    let (a, b, c) = (i.a, i.b, i.c);
    match (i.op, fl) {
        (Op::X, _) => "x".to_string(),
        (Op::Y, _) => "y".to_string(),
        (Op::Z, _) => "z".to_string(),
        (Op::Const, Flavour::Pt) => near(c),
        (Op::Const, _) => match bounds(c) {
            Some(b) => format!("{pre}_iv({b})"),
            None => entire.clone(),
        },
        (Op::AddC, Flavour::Pt) => format!("{} + {}", r(a), near(c)),
        (Op::SubC, Flavour::Pt) => format!("{} + {}", r(a), near(-c)),
        (Op::MulC, Flavour::Pt) => format!("{} * {}", r(a), near(c)),
        (Op::DivC, Flavour::Pt) => format!("{} / {}", r(a), near(c)),
        (Op::RSubC, Flavour::Pt) => format!("{} - {}", near(c), r(a)),
        (Op::RDivC, Flavour::Pt) => format!("{} / {}", near(c), r(a)),
        (Op::AddC, _) => with_c("addc", &r(a), bounds(c)),
        (Op::SubC, _) => with_c("addc", &r(a), bounds(-c)),
        (Op::MulC, _) => with_c("mulc", &r(a), bounds(c)),
        (Op::DivC, _) => with_c("mulc", &r(a), recip_bounds(c)),
        (Op::RSubC, _) => with_c("addc", &un("neg", a), bounds(c)),
        (Op::RDivC, _) => with_c("mulc", &un("recip", a), bounds(c)),
        (Op::Neg, _) => un("neg", a),
        (Op::Sqr, _) => un("sqr", a),
        (Op::Powi, _) => format!("{pre}_powi({}, {})", r(a), i.n),
        (Op::Sqrt, _) => un("sqrt", a),
        (Op::Recip, _) => un("recip", a),
        (Op::Exp, _) => un("exp", a),
        (Op::Ln, _) => un("ln", a),
        (Op::Sin, _) => un("sin", a),
        (Op::Cos, _) => un("cos", a),
        (Op::Abs, _) => un("abs", a),
        (Op::Add, _) => bin("add", a, b),
        (Op::Sub, _) => bin("sub", a, b),
        (Op::Mul, _) => bin("mul", a, b),
        (Op::Div, _) => bin("div", a, b),
        (Op::Min, _) => bin("min", a, b),
        (Op::Max, _) => bin("max", a, b),
        (Op::Hypot, _) => bin("hypot", a, b),
        (Op::Union, _) => bin("runion", a, b),
        (Op::Intersect, _) => bin("rinter", a, b),
        (Op::Subtract, _) => format!("{pre}_rinter({}, {pre}_neg({}))", r(a), r(b)),
        (Op::Gt0, _) => un("gt0", a),
        (Op::Ge0, _) => un("ge0", a),
        (Op::Select, _) => format!("{pre}_select({}, {}, {})", r(a), r(b), r(i.e)),
        // `shader` refuses tapes with blends: `lower` writes them out.
        (Op::BlendUnion | Op::BlendIntersect, _) => entire.clone(),
    }
}
