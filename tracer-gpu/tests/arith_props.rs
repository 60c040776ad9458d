//! The WGSL arithmetic itself against a 256-bit reference: random operands are uploaded,
//! each operation runs on the device in IA, RAA* and RevAA, and at sample points of the
//! operands the exact value of the operation (the test kit's [`Mp`]) must lie in the
//! result's bounds and, for the affine forms, in `c + t eps +- e` at the same `eps`
//! (the joint inclusion that argument pruning relies on). Zero violations.
mod common;

use arith_core::testkit::mp::{Mp, Verdict};
use tracer_gpu::{codegen, GpuArith};

const OPS: &[&str] = &[
    "add", "sub", "mul", "div", "min", "max", "hypot", "neg", "sqr", "sqrt", "recip", "exp", "ln",
    "sin", "cos", "abs", "powi", "addc", "mulc", "runion", "rinter", "gt0", "ge0", "select",
];
const WORDS_IN: usize = 10;
const WORDS_OUT: usize = 5;
const LIM: f64 = (1u64 << 60) as f64;

fn kernel(arith: GpuArith) -> String {
    let mut s = String::from(
        "struct Params { zero: u32, n: u32, pad0: u32, pad1: u32 }
@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> inp: array<u32>;
@group(0) @binding(2) var<storage, read_write> outp: array<u32>;
",
    );
    s.push_str(&codegen::library(arith));
    let (ty, pre, make) = match arith {
        GpuArith::Ia => ("IA", "ia", "IA(f(b + 1u), f(b + 2u))"),
        _ => ("AF", "af", "AF(f(b + 1u), f(b + 2u), f(b + 3u))"),
    };
    let make_y = make
        .replace("1u", "4u")
        .replace("2u", "5u")
        .replace("3u", "6u");
    let mut cases = String::new();
    for (k, op) in OPS.iter().enumerate() {
        let call = match *op {
            "add" | "sub" | "mul" | "div" | "min" | "max" | "hypot" | "runion" | "rinter" => {
                format!("{pre}_{op}(x, y)")
            }
            // x > 1/2 picks y, else -y
            "select" => format!("{pre}_select(x, y, {pre}_neg(y))"),
            "powi" => format!("{pre}_powi(x, n)"),
            "addc" | "mulc" => format!("{pre}_{op}(x, klo, khi)"),
            _ => format!("{pre}_{op}(x)"),
        };
        cases.push_str(&format!("        case {k}u: {{ r = {call}; }}\n"));
    }
    let store = match arith {
        GpuArith::Ia => "outp[o] = bitcast<u32>(r.lo); outp[o + 1u] = bitcast<u32>(r.hi); outp[o + 2u] = 0u;",
        _ => "outp[o] = bitcast<u32>(r.c); outp[o + 1u] = bitcast<u32>(r.t); outp[o + 2u] = bitcast<u32>(r.e);",
    };
    s.push_str(&format!(
        "fn f(i: u32) -> f32 {{ return bitcast<f32>(inp[i]); }}
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) g: vec3<u32>) {{
    let k = g.x;
    if (k >= params.n) {{ return; }}
    let b = k * {WORDS_IN}u;
    let x = {make};
    let y = {make_y};
    let n = bitcast<i32>(inp[b + 7u]);
    let klo = f(b + 8u);
    let khi = f(b + 9u);
    var r: {ty};
    switch inp[b] {{
{cases}        default: {{ r = x; }}
    }}
    let bb = {pre}_bounds(r);
    let o = k * {WORDS_OUT}u;
    {store}
    outp[o + 3u] = bitcast<u32>(bb.lo);
    outp[o + 4u] = bitcast<u32>(bb.hi);
}}
"
    ));
    s
}

/// xorshift64*: reproducible operands.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// A value of random sign and magnitude 2^[lo, hi), sometimes 0 or a round number.
    fn val(&mut self, lo: f64, hi: f64) -> f32 {
        match self.next() % 16 {
            0 => 0.0,
            1 => (self.next() % 7) as f32 - 3.0,
            _ => {
                let m = 2f64.powf(lo + (hi - lo) * self.unit());
                (if self.next() & 1 == 0 { m } else { -m }) as f32
            }
        }
    }
}

/// A case: op, x (three words), y (three words), n, constant bounds.
fn case(rng: &mut Rng, op: usize, arith: GpuArith) -> [u32; WORDS_IN] {
    let name = OPS[op];
    let (lo, hi) = match name {
        "exp" => (-6.0, 6.0),
        "sin" | "cos" => (-4.0, 8.0),
        _ => (-30.0, 30.0),
    };
    let form = |rng: &mut Rng| {
        let c = rng.val(lo, hi);
        let t = rng.val(lo - 4.0, hi - 1.0) * rng.unit() as f32;
        let e = (rng.val(lo - 12.0, hi - 3.0) * rng.unit() as f32).abs();
        let (c, t, e) = if rng.next() & 3 == 0 {
            (c, 0.0, 0.0)
        } else {
            (c, t, e)
        };
        match arith {
            // IA: [c, c + |t| + e]
            GpuArith::Ia => [c, ((c as f64) + (t.abs() as f64) + e as f64) as f32, 0.0],
            _ => [c, t, e],
        }
    };
    let x = form(rng);
    let y = form(rng);
    let n = (rng.next() % 9) as i32 - 4;
    let k = rng.val(-10.0, 10.0);
    let (klo, khi) = if rng.next() & 1 == 0 {
        (k, k)
    } else {
        (k, f32::from_bits(k.to_bits() + 3).max(k))
    };
    let (klo, khi) = (klo.min(khi), klo.max(khi));
    let b = |v: f32| v.to_bits();
    [
        op as u32,
        b(x[0]),
        b(x[1]),
        b(x[2]),
        b(y[0]),
        b(y[1]),
        b(y[2]),
        n as u32,
        b(klo),
        b(khi),
    ]
}

fn mp(x: f64) -> Mp {
    Mp::point(x).expect("finite")
}

/// The exact value of the operation at the operands `x`, `y` (given as exact Mp
/// values with f64 approximations), or `None` where the test does not decide it.
fn exact(name: &str, x: &Mp, xf: f64, y: &Mp, yf: f64, n: i32, k: f64) -> Option<Mp> {
    let near0 = |v: f64| v.abs() < 1e-30;
    Some(match name {
        "add" => x.add(y)?,
        "sub" => x.sub(y)?,
        "mul" => x.mul(y)?,
        "div" => {
            if near0(yf) {
                return None;
            }
            x.div(y)?
        }
        "min" => x.min(y),
        "max" => x.max(y),
        "hypot" => x.sqr()?.add(&y.sqr()?)?.sqrt()?,
        "neg" => x.neg(),
        "sqr" => x.sqr()?,
        "sqrt" => {
            if near0(xf) {
                return None;
            }
            if xf < 0.0 {
                mp(0.0)
            } else {
                x.sqrt()?
            }
        }
        "recip" => {
            if near0(xf) {
                return None;
            }
            x.recip()?
        }
        "exp" => x.exp()?,
        "ln" => {
            if xf <= 1e-30 {
                return None;
            }
            x.ln()?
        }
        "sin" => x.sin()?,
        "cos" => x.cos()?,
        "abs" => x.abs(),
        "powi" => {
            if n < 0 && near0(xf) {
                return None;
            }
            x.powi(n)?
        }
        "addc" => x.add(&mp(k))?,
        "runion" => x.add(y)?.add(&x.sqr()?.add(&y.sqr()?)?.sqrt()?)?,
        "rinter" => x.add(y)?.sub(&x.sqr()?.add(&y.sqr()?)?.sqrt()?)?,
        "gt0" | "ge0" => {
            let pos = x.verdict(f64::NEG_INFINITY, 0.0) == Verdict::Outside;
            let neg = x.verdict(0.0, f64::INFINITY) == Verdict::Outside;
            mp(f64::from(u8::from(pos || (!neg && name == "ge0"))))
        }
        "select" => {
            if x.verdict(f64::NEG_INFINITY, 0.5) == Verdict::Outside {
                y.clone()
            } else if x.verdict(0.5, f64::INFINITY) == Verdict::Outside {
                y.neg()
            } else {
                return None; // x exactly 1/2
            }
        }
        "mulc" => x.mul(&mp(k))?,
        _ => unreachable!(),
    })
}

#[test]
fn wgsl_operations_enclose_the_exact_values() {
    let Some(gpu) = common::gpu() else { return };
    let per_op = 120;
    let mut checked = 0u64;
    let mut violations = Vec::new();
    for arith in GpuArith::ALL {
        let src = kernel(arith);
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15 ^ arith as u64);
        let cases: Vec<[u32; WORDS_IN]> = (0..OPS.len())
            .flat_map(|op| (0..per_op).map(move |_| op))
            .map(|op| case(&mut rng, op, arith))
            .collect();
        let input: Vec<u32> = cases.iter().flatten().copied().collect();
        let out = gpu
            .compute(
                &src,
                "main",
                &input,
                cases.len() * WORDS_OUT,
                cases.len() as u32,
            )
            .unwrap();
        for (ci, (c, o)) in cases.iter().zip(out.chunks_exact(WORDS_OUT)).enumerate() {
            let f = |w: u32| f32::from_bits(w) as f64;
            let name = OPS[c[0] as usize];
            let (r0, r1, r2, blo, bhi) = (f(o[0]), f(o[1]), f(o[2]), f(o[3]), f(o[4]));
            if !(blo > -LIM && bhi < LIM) {
                continue; // unbounded: encloses everything
            }
            let (n, k) = (c[7] as i32, f(c[8]));
            let kc = if c[8] == c[9] {
                vec![k]
            } else {
                vec![k, f(c[9])]
            };
            // Sample points of the operands.
            let samples: Vec<(f64, [f64; 2], [f64; 2])> = match arith {
                GpuArith::Ia => {
                    let pts = |lo: f64, hi: f64| [lo, hi, 0.5 * lo + 0.5 * hi];
                    let (xs, ys) = (pts(f(c[1]), f(c[2])), pts(f(c[4]), f(c[5])));
                    xs.iter()
                        .flat_map(|&a| ys.iter().map(move |&b| (0.0, [a, 0.0], [b, 0.0])))
                        .collect()
                }
                _ => {
                    let mut v = Vec::new();
                    for eps in [-1.0, 0.5, 1.0] {
                        for ux in [-1.0, 1.0] {
                            for uy in [-1.0, 0.25] {
                                v.push((eps, [eps, ux], [eps, uy]));
                            }
                        }
                    }
                    v
                }
            };
            for (eps, xs, ys) in samples {
                let point = |w: usize, s: [f64; 2]| -> (Mp, f64) {
                    match arith {
                        GpuArith::Ia => (mp(s[0]), s[0]),
                        _ => {
                            let (cc, tt, ee) = (f(c[w]), f(c[w + 1]), f(c[w + 2]));
                            let v = mp(cc)
                                .add(&mp(tt * s[0]))
                                .and_then(|a| a.add(&mp(ee * s[1])))
                                .expect("finite");
                            (v, cc + tt * s[0] + ee * s[1])
                        }
                    }
                };
                let (x, xf) = point(1, xs);
                let (y, yf) = point(4, ys);
                for &kk in &kc {
                    let Some(v) = exact(name, &x, xf, &y, yf, n, kk) else {
                        continue;
                    };
                    checked += 1;
                    let mut bad = v.verdict(blo, bhi) == Verdict::Outside;
                    if arith != GpuArith::Ia {
                        // v - (c + t eps) in [-e, e]
                        let lin = mp(r0).add(&mp(r1 * eps)).expect("finite");
                        if let Some(d) = v.sub(&lin) {
                            bad |= d.verdict(-r2, r2) == Verdict::Outside;
                        }
                    }
                    if bad {
                        violations.push(format!(
                            "{arith:?} {name} case {ci} (x words {:?}, y {:?}, n {n}, k {kk}) at \
                             eps {eps} {xs:?} {ys:?}: exact {} not in result ({r0}, {r1}, {r2}) \
                             bounds [{blo}, {bhi}]",
                            &c[1..4],
                            &c[4..7],
                            v.describe()
                        ));
                    }
                }
            }
        }
    }
    assert!(checked > 20_000, "only {checked} checks ran");
    assert!(
        violations.is_empty(),
        "{} violations of {checked} checks, first ones:\n{}",
        violations.len(),
        violations[..violations.len().min(8)].join("\n")
    );
}
