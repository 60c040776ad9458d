//! HyperFun programs: every library primitive against its reference definition (the
//! C code of HyperFun's `hflibrary_lib`, transcribed here independently of the
//! compiler) at random points; the language's precedence, control flow and errors;
//! soundness of conditionals over every arithmetic; never-panic on arbitrary input; and
//! a `.hf` model against the same solid written by hand, value by value and pixel by
//! pixel.

use arith_core::rfunc::{intersect, subtract, union};
use arith_core::{Range, Real};
use glam::DVec3;
use model_ir::arith::ArithKind;
use model_ir::shape::{Aabb, Shape, View};
use model_sources::formula::{parse, Tape};
use model_sources::hyperfun::{parse_hyperfun, parse_hyperfun_with, HfOptions};
use model_sources::noise::SplitMix64;
use proptest::prelude::*;
use tracer::render::{render_kind, RenderOptions};

fn hf(src: &str) -> Tape {
    match parse_hyperfun(src) {
        Ok(t) => t,
        Err(e) => panic!("{e}\n{src}"),
    }
}

fn close(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs()))
}

// ------------------------------------------------- reference definitions (from C)

const SENTINEL: f64 = -1111111111111.0;
const EPS: f64 = 1e-6;

/// One primitive: HyperFun call text (with `x` the coordinates and `c` the array
/// `[c1, c2, c3]`), and the reference value from the same numbers.
struct Prim {
    name: &'static str,
    /// Number of real parameters after the arrays.
    reals: usize,
    reference: fn(p: [f64; 3], c: [f64; 3], r: &[f64]) -> f64,
}

fn d(p: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    [p[0] - c[0], p[1] - c[1], p[2] - c[2]]
}

const PRIMS: &[Prim] = &[
    Prim {
        name: "hfSphere",
        reals: 1,
        reference: |p, c, r| {
            let t = d(p, c);
            r[0] * r[0] - t[0] * t[0] - t[1] * t[1] - t[2] * t[2]
        },
    },
    Prim {
        name: "hfEllipsoid",
        reals: 3,
        reference: |p, c, r| {
            if r[0].abs() < EPS || r[1].abs() < EPS || r[2].abs() < EPS {
                return SENTINEL;
            }
            let t = d(p, c);
            let (x, y, z) = (t[0] / r[0], t[1] / r[1], t[2] / r[2]);
            1.0 - x * x - y * y - z * z
        },
    },
    Prim {
        name: "hfBlock",
        reals: 3,
        reference: |p, v, r| {
            if r.iter().any(|&a| a < 0.0) {
                return SENTINEL;
            }
            let t: Vec<f64> = (0..3)
                .map(|k| (p[k] - v[k]) * (v[k] + r[k] - p[k]))
                .collect();
            let f = t[0] + t[1] - (t[0] * t[0] + t[1] * t[1]).sqrt();
            f + t[2] - (f * f + t[2] * t[2]).sqrt()
        },
    },
    Prim {
        name: "hfCylinderX",
        reals: 1,
        reference: |p, c, r| {
            let t = d(p, c);
            r[0] * r[0] - t[1] * t[1] - t[2] * t[2]
        },
    },
    Prim {
        name: "hfCylinderY",
        reals: 1,
        reference: |p, c, r| {
            let t = d(p, c);
            r[0] * r[0] - t[0] * t[0] - t[2] * t[2]
        },
    },
    Prim {
        name: "hfCylinderZ",
        reals: 1,
        reference: |p, c, r| {
            let t = d(p, c);
            r[0] * r[0] - t[0] * t[0] - t[1] * t[1]
        },
    },
    Prim {
        name: "hfEllCylX",
        reals: 2,
        reference: |p, c, r| {
            if r[0].abs() < EPS || r[1].abs() < EPS {
                return SENTINEL;
            }
            let t = d(p, c);
            let (y, z) = (t[1] / r[0], t[2] / r[1]);
            1.0 - y * y - z * z
        },
    },
    Prim {
        name: "hfEllCylY",
        reals: 2,
        reference: |p, c, r| {
            if r[0].abs() < EPS || r[1].abs() < EPS {
                return SENTINEL;
            }
            let t = d(p, c);
            let (x, z) = (t[0] / r[0], t[2] / r[1]);
            1.0 - x * x - z * z
        },
    },
    Prim {
        name: "hfEllCylZ",
        reals: 2,
        reference: |p, c, r| {
            if r[0].abs() < EPS || r[1].abs() < EPS {
                return SENTINEL;
            }
            let t = d(p, c);
            let (x, y) = (t[0] / r[0], t[1] / r[1]);
            1.0 - x * x - y * y
        },
    },
    Prim {
        name: "hfConeX",
        reals: 1,
        reference: |p, c, r| {
            let t = d(p, c);
            let (y, z) = (t[1] / r[0], t[2] / r[0]);
            t[0] * t[0] - y * y - z * z
        },
    },
    Prim {
        name: "hfConeY",
        reals: 1,
        reference: |p, c, r| {
            let t = d(p, c);
            let (x, z) = (t[0] / r[0], t[2] / r[0]);
            t[1] * t[1] - x * x - z * z
        },
    },
    Prim {
        name: "hfConeZ",
        reals: 1,
        reference: |p, c, r| {
            let t = d(p, c);
            let (x, y) = (t[0] / r[0], t[1] / r[0]);
            t[2] * t[2] - x * x - y * y
        },
    },
    Prim {
        name: "hfEllConeX",
        reals: 2,
        reference: |p, c, r| {
            let t = d(p, c);
            let (y, z) = (t[1] / r[0], t[2] / r[1]);
            t[0] * t[0] - y * y - z * z
        },
    },
    Prim {
        name: "hfEllConeY",
        reals: 2,
        reference: |p, c, r| {
            let t = d(p, c);
            let (x, z) = (t[0] / r[0], t[2] / r[1]);
            t[1] * t[1] - x * x - z * z
        },
    },
    Prim {
        name: "hfEllConeZ",
        reals: 2,
        reference: |p, c, r| {
            let t = d(p, c);
            let (x, y) = (t[0] / r[0], t[1] / r[1]);
            t[2] * t[2] - x * x - y * y
        },
    },
    Prim {
        name: "hfTorusX",
        reals: 2,
        reference: |p, c, r| {
            let (big, r0) = (r[0], r[1]);
            let t = d(p, c);
            let (y2, z2) = (t[1] * t[1], t[2] * t[2]);
            r0 * r0 - t[0] * t[0] - y2 - z2 - big * big + 2.0 * big * (z2 + y2).sqrt()
        },
    },
    Prim {
        name: "hfTorusY",
        reals: 2,
        reference: |p, c, r| {
            let (big, r0) = (r[0], r[1]);
            let t = d(p, c);
            let (x2, z2) = (t[0] * t[0], t[2] * t[2]);
            r0 * r0 - x2 - t[1] * t[1] - z2 - big * big + 2.0 * big * (z2 + x2).sqrt()
        },
    },
    Prim {
        name: "hfTorusZ",
        reals: 2,
        reference: |p, c, r| {
            let (big, r0) = (r[0], r[1]);
            let t = d(p, c);
            let (x2, y2) = (t[0] * t[0], t[1] * t[1]);
            r0 * r0 - x2 - y2 - t[2] * t[2] - big * big + 2.0 * big * (x2 + y2).sqrt()
        },
    },
    Prim {
        name: "hfSuperell",
        reals: 5,
        reference: |p, c, r| {
            let (a, b, cc, s1, s2) = (r[0], r[1], r[2], r[3], r[4]);
            let t = d(p, c);
            let (x, y, z) = (t[0] / a, t[1] / b, t[2] / cc);
            let q = 2.0 / s2;
            let (xp, yp, zp) = (x.abs().powf(q), y.abs().powf(q), z.abs().powf(2.0 / s1));
            1.0 - (xp + yp).powf(s2 / s1) - zp
        },
    },
];

/// A random parameter for primitive `name`, argument `k`: sizes and radii in
/// `[0.3, 1.5]`, superellipsoid exponents in `[0.3, 2.5]`.
fn param(rng: &mut SplitMix64, name: &str, k: usize) -> f64 {
    if name == "hfSuperell" && k >= 3 {
        if rng.next_f64() < 0.3 {
            return [1.0, 2.0, 0.5][(rng.next_u64() % 3) as usize];
        }
        return rng.range(0.3, 2.5);
    }
    rng.range(0.3, 1.5)
}

#[test]
fn every_primitive_matches_its_reference_definition() {
    let mut rng = SplitMix64(7);
    for prim in PRIMS {
        for _trial in 0..8 {
            let c = [
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
            ];
            let r: Vec<f64> = (0..prim.reals)
                .map(|k| param(&mut rng, prim.name, k))
                .collect();
            let args: Vec<String> = r.iter().map(|v| format!("{v:?}")).collect();
            let src = format!(
                "my_model(x[3], a[1]) {{\n  array c[3];\n  c = [{:?}, {:?}, {:?}];\n  my_model = {}(x, c, {});\n}}",
                c[0],
                c[1],
                c[2],
                prim.name,
                args.join(", ")
            );
            let t = hf(&src);
            for _ in 0..50 {
                let p = [
                    rng.range(-2.0, 2.0),
                    rng.range(-2.0, 2.0),
                    rng.range(-2.0, 2.0),
                ];
                let (got, want) = (t.eval(p[0], p[1], p[2]), (prim.reference)(p, c, &r));
                assert!(
                    close(got, want),
                    "{}: {got} vs {want} at {p:?}\n{src}",
                    prim.name
                );
            }
        }
    }
}

#[test]
fn degenerate_parameters_give_the_sentinel() {
    let t = hf("my_model(x[3], a[1]) { array c[3]; c = [0, 0, 0]; my_model = hfEllipsoid(x, c, 1, 0, 1); }");
    assert_eq!(t.eval(0.1, 0.2, 0.3), SENTINEL);
    let t = hf(
        "my_model(x[3], a[1]) { array c[3]; c = [0, 0, 0]; my_model = hfBlock(x, c, 1, -1, 1); }",
    );
    assert_eq!(t.eval(0.1, 0.2, 0.3), SENTINEL);
    // A degenerate value that depends on the point: the sentinel exactly there.
    let t = hf(
        "my_model(x[3], a[1]) { array c[3]; c = [0, 0, 0]; my_model = hfEllCylZ(x, c, x[3], 1); }",
    );
    assert_eq!(t.eval(0.1, 0.2, 0.0), SENTINEL);
    assert!(close(t.eval(0.1, 0.2, 0.5), 1.0 - 0.04 - 0.04));
}

/// The blends, the noise and the space mappings against the C code.
#[test]
fn operations_match_their_reference_definitions() {
    let blend = |f1: f64, f2: f64, a0: f64, a1: f64, a2: f64, uni: bool| {
        let dd = a0 / (1.0 + (f1 / a1) * (f1 / a1) + (f2 / a2) * (f2 / a2));
        let s = (f2 * f2 + f1 * f1).sqrt();
        if uni {
            f1 + f2 + s + dd
        } else {
            f1 + f2 - s + dd
        }
    };
    let noise = |p: [f64; 3], a1: f64, a2: f64, ph: f64| {
        let (a2x, a2y, a2z) = (a2 * p[0], a2 * p[1], a2 * p[2]);
        let (sx, sy, sz) = (a2x.sin(), a2y.sin(), a2z.sin());
        let a1d = a1 / 1.17;
        let sx2 = a1d * (a2x / 1.35 + ph * sz).sin();
        let sy2 = a1d * (a2y / 1.35 + ph * sx).sin();
        let sz2 = a1d * (a2z / 1.35 + ph * sy).sin();
        (a1 * sx + sx2) * (a1 * sy + sy2) * (a1 * sz + sz2)
    };
    let rot = |p: [f64; 3], axis: usize, th: f64| {
        let (ct, st) = (th.cos(), th.sin());
        let (i, j) = [(1, 2), (2, 0), (0, 1)][axis];
        let mut q = p;
        q[i] = p[i] * ct + p[j] * st;
        q[j] = -p[i] * st + p[j] * ct;
        q
    };
    let taper = |p: [f64; 3], axis: usize, x1: f64, x2: f64, s1: f64, s2: f64| {
        let v = p[axis];
        let mut scale = if v < x1 {
            s1
        } else if v > x2 {
            s2
        } else {
            let t = (v - x1) / (x2 - x1);
            (1.0 - t) * s1 + t * s2
        };
        if scale.abs() < EPS {
            scale = 1.0;
        }
        let mut q = p;
        for k in (0..3).filter(|&k| k != axis) {
            q[k] /= scale;
        }
        q
    };
    let sphere = |q: [f64; 3]| 0.8 - q[0] * q[0] - q[1] * q[1] - q[2] * q[2] * 0.5;
    let wrap = |body: &str| {
        format!("my_model(x[3], a[1]) {{\n array q[3];\n q = [x[1], x[2], x[3]];\n {body}\n}}")
    };
    let mut rng = SplitMix64(11);
    for _ in 0..200 {
        let p = [
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
        ];
        let (f1, f2) = (p[0] - p[1] * 0.5, p[2] + 0.25);
        for uni in [true, false] {
            let name = if uni { "hfBlendUni" } else { "hfBlendInt" };
            let t = hf(&wrap(&format!(
                "my_model = {name}(x[1] - x[2]*0.5, x[3] + 0.25, 0.7, 1.3, 0.6);"
            )));
            let want = blend(f1, f2, 0.7, 1.3, 0.6, uni);
            assert!(close(t.eval(p[0], p[1], p[2]), want), "{name}");
        }
        let t = hf(&wrap("my_model = hfNoiseG(q, 2.5, 0.7, 1.4);"));
        assert!(close(t.eval(p[0], p[1], p[2]), noise(p, 2.5, 0.7, 1.4)));
        for (axis, n) in ["X", "Y", "Z"].iter().enumerate() {
            let t = hf(&wrap(&format!(
                "r = hfRotate3D{n}(q, 0.7); my_model = q[3]*0.5 - q[1] + 0.1*q[2] + r;"
            )));
            let q = rot(p, axis, 0.7);
            assert!(
                close(
                    t.eval(p[0], p[1], p[2]),
                    q[2] * 0.5 - q[0] + 0.1 * q[1] + 1.0
                ),
                "rotate {n}"
            );
            let t = hf(&wrap(&format!(
                "r = hfTwist{n}(q, -1, 1.5, 0.2, 1.1); my_model = q[3]*0.5 - q[1] + 0.1*q[2];"
            )));
            let u = (p[axis] + 1.0) / 2.5;
            let q = rot(p, axis, (1.0 - u) * 0.2 + u * 1.1);
            assert!(
                close(t.eval(p[0], p[1], p[2]), q[2] * 0.5 - q[0] + 0.1 * q[1]),
                "twist {n}"
            );
            let t = hf(&wrap(&format!(
                "r = hfTaper{n}(q, -0.5, 1, 0.5, 1.5); my_model = 0.8 - q[1]^2 - q[2]^2 - q[3]*q[3]*0.5;"
            )));
            let q = taper(p, axis, -0.5, 1.0, 0.5, 1.5);
            assert!(close(t.eval(p[0], p[1], p[2]), sphere(q)), "taper {n}");
        }
        let t = hf(&wrap(
            "r = hfShift3D(q, 0.1, -0.2, 0.3); r = hfScale3D(q, 2, 0.5, 1.5); my_model = q[1] + 10*q[2] + 100*q[3];",
        ));
        let q = [(p[0] - 0.1) / 2.0, (p[1] + 0.2) / 0.5, (p[2] - 0.3) / 1.5];
        assert!(close(
            t.eval(p[0], p[1], p[2]),
            q[0] + 10.0 * q[1] + 100.0 * q[2]
        ));
    }
}

// ------------------------------------------------------------- the language

fn value(expr: &str, p: (f64, f64, f64)) -> f64 {
    hf(&format!("my_model(x[3], a[1]) {{ my_model = {expr}; }}")).eval(p.0, p.1, p.2)
}

#[test]
fn precedence_is_hyperfuns() {
    let p = (0.5, 2.0, -1.5);
    // Unary minus binds tighter than '^', '^' is left-associative.
    assert_eq!(value("-x[1]^2", p), 0.25);
    assert_eq!(value("2^3^2", p), 64.0);
    // '+ - & | \\' share one level, left to right.
    assert_eq!(value("x[1] + x[2] & x[3]", p), intersect(2.5, -1.5));
    assert_eq!(value("x[1] | x[2] - x[3]", p), union(0.5, 2.0) + 1.5);
    assert_eq!(value("x[1] \\ x[2] * 2", p), subtract(0.5, 4.0));
    assert_eq!(value("x[1] @ x[2]", p), intersect(0.5, 2.0));
    assert_eq!(value("~x[1] * 3", p), -1.5);
    // Real and integral powers; an exponent computed from constants.
    assert!(close(value("x[2]^1.5", p), 2f64.powf(1.5)));
    assert_eq!(value("x[3]^(1+1)", p), 2.25);
    assert_eq!(value("x[3]^-1", p), -1.0 / 1.5);
    // Names are case-insensitive; '--' starts a comment; built-ins.
    assert!(close(
        value("SQRT(x[2]) -- the root\n + Log(x[2]) + logd(100)", p),
        2f64.sqrt() + 2f64.ln() + 2.0
    ));
    assert!(close(
        value("sinh(x[1]) + cosh(x[1]) + tanh(x[1])", p),
        0.5f64.sinh() + 0.5f64.cosh() + 0.5f64.tanh()
    ));
    assert!(close(
        value("tan(x[1]) + tan(x[3])", p),
        0.5f64.tan() + (-1.5f64).tan()
    ));
    assert_eq!(value("sign(x[3]) + sign(x[2])", p), 0.0);
    assert_eq!(value("max(x[1], x[2]) + min(x[1], x[3])", p), 0.5);
    // A parenthesised condition is a value 0 or 1.
    assert_eq!(
        value("(x[1] < x[2]) + (x[1] = 0.5000000001) + (not x[1] > 0)", p),
        2.0
    );
}

#[test]
fn parameters_objects_and_bodies() {
    let src = "inner(x[3], a[2]) { inner = a[1] - x[1]*x[1] - a[2]; }
               my_model(x[3], a[1]) {
                 array xt[3], p[2];
                 xt = [x[1] - 1, x[2], x[3]];
                 p = [a[1] + 1, 0];
                 my_model = inner(xt, p);
               }";
    let t = hf(src);
    assert_eq!(t.eval(1.5, 0.0, 0.0), 1.0 - 0.25);
    let opts = HfOptions {
        object: None,
        params: vec![2.0],
    };
    let t = parse_hyperfun_with(src, &opts).unwrap();
    assert_eq!(t.eval(1.5, 0.0, 0.0), 3.0 - 0.25);
    let opts = HfOptions {
        object: Some("INNER".into()),
        params: vec![4.0, 1.0],
    };
    assert_eq!(
        parse_hyperfun_with(src, &opts).unwrap().eval(1.0, 0.0, 0.0),
        2.0
    );
    let e = parse_hyperfun_with(
        src,
        &HfOptions {
            object: Some("nope".into()),
            params: vec![],
        },
    )
    .unwrap_err();
    assert!(e.message.contains("inner, my_model"), "{e}");
    // Without my_model, the first body.
    assert_eq!(
        hf("b(x[3], a[1]) { b = x[1]; } c(x[3], a[1]) { c = x[2]; }").eval(1.0, 2.0, 3.0),
        1.0
    );
}

#[test]
fn loops_unroll_and_conditions_fold() {
    // A sum of spheres built by a loop over a counter.
    let src = "my_model(x[3], a[1]) {
        array c[3];
        i = 0; f = -1;
        while i < 3 loop
          c[1] = i; c[2] = 0; c[3] = 0;
          f = f | hfSphere(x, c, 0.4);
          i = i + 1;
        endloop;
        if i = 3 then g = f; else g = 0; endif;
        my_model = g;
      }";
    let t = hf(src);
    assert!(
        t.eval(2.0, 0.0, 0.0) > 0.0 && t.eval(1.0, 0.0, 0.0) > 0.0 && t.eval(3.0, 0.0, 0.0) < 0.0
    );
    assert!(!t.has_branches(), "constant conditions fold:\n{t}");
    let e = parse_hyperfun(
        "my_model(x[3], a[1]) { i = 0; while i < 1 loop i = i - 1; endloop; my_model = i; }",
    )
    .unwrap_err();
    assert!(e.message.contains("more than 100000 iterations"), "{e}");
    assert_eq!((e.line, e.column), (1, 31));
    let e = parse_hyperfun(
        "my_model(x[3], a[1]) { k = 1; while x[1]*k < 1 loop k = k*2; endloop; my_model = k; }",
    )
    .unwrap_err();
    assert!(e.message.contains("depends on the point"), "{e}");
    // A loop whose condition depends on the point but ends for every point.
    let t = hf("my_model(x[3], a[1]) { k = 0; i = 0; while i < 4 and x[1] > i loop k = k + 1; i = i + 1; endloop; my_model = k; }");
    for (x, want) in [(-1.0, 0.0), (0.5, 1.0), (2.5, 3.0), (9.0, 4.0)] {
        assert_eq!(t.eval(x, 0.0, 0.0), want, "at {x}");
    }
}

#[test]
fn point_dependent_conditions_select() {
    let src = "my_model(x[3], a[1]) {
        if x[1] > 0 and x[2] > 0 then f = x[1] + x[2]; else f = -x[1]*x[2]; endif;
        if not (x[3] <= 1) or x[3] /= x[3] then f = f - 10; endif;
        my_model = f;
      }";
    let t = hf(src);
    assert!(t.has_branches() && !t.packs());
    assert_eq!(t.eval(1.0, 2.0, 0.0), 3.0);
    assert_eq!(t.eval(-1.0, 2.0, 0.0), 2.0);
    assert_eq!(t.eval(1.0, 2.0, 2.0), -7.0);
    let e = parse_hyperfun("my_model(x[3], a[1]) { if x[1] > 0 then g = 1; endif; my_model = g; }")
        .unwrap_err();
    assert!(
        e.message.contains("may be unassigned") && e.message.contains("line 1, column 24"),
        "{e}"
    );
}

/// Over every arithmetic, the range of a program with a point-dependent branch
/// encloses its values at points of the box, also where the condition is undecided.
fn ranges_enclose<A: arith_core::Arithmetic>(t: &Tape) {
    let mut rng = SplitMix64(3);
    for _ in 0..200 {
        let c = [
            rng.range(-1.5, 1.5),
            rng.range(-1.5, 1.5),
            rng.range(-1.5, 1.5),
        ];
        let h = rng.range(0.0, 0.6);
        let r = t.eval(
            A::Cell::input(0, c[0] - h, c[0] + h),
            A::Cell::input(1, c[1] - h, c[1] + h),
            A::Cell::input(2, c[2] - h, c[2] + h),
        );
        let (lo, hi) = r.bounds();
        for _ in 0..30 {
            let p: Vec<f64> = (0..3).map(|k| rng.range(c[k] - h, c[k] + h)).collect();
            let v = t.eval(p[0], p[1], p[2]);
            assert!(lo <= v && v <= hi, "{v} outside [{lo}, {hi}] ({})", A::NAME);
        }
    }
}

#[test]
fn conditional_ranges_enclose_both_branches_in_every_arithmetic() {
    let t = hf("my_model(x[3], a[1]) {
        array q[3];
        q = [x[1], x[2], x[3]];
        r = hfTaperY(q, -0.5, 0.5, 0.6, 1.4);
        if x[1] < x[2] then f = x[1]*x[3] - 0.2; else f = 0.5 - x[2]^2 + x[3]; endif;
        i = 0;
        while i < 3 and f > 0.9 loop f = f - 0.25; i = i + 1; endloop;
        my_model = hfBlendUni(f, hfSphere(q, q, 1) - q[1]^2, 0.5, 1, 1) + sign(x[3]);
      }");
    for kind in ArithKind::ALL {
        model_ir::with_arith!(kind, A => ranges_enclose::<A>(&t));
    }
}

#[test]
fn errors_name_line_and_column() {
    let cases: &[(&str, usize, usize, &str)] = &[
        ("my_model(x[3], a[1]) { my_model = hfFoo(x); }", 1, 35, "unknown function 'hffoo'"),
        ("my_model(x[3], a[1]) {\n  array c[3];\n  my_model = hfSphere(x, c);\n}", 3, 14, "hfSphere takes 3 arguments but was given 2"),
        ("my_model(x[3], a[1]) { my_model = sqrt(x[1], 2); }", 1, 35, "sqrt takes 1 argument but was given 2"),
        ("my_model(x[3], a[1]) { my_model = atan(x[1]); }", 1, 35, "not in the HyperFun subset"),
        ("my_model(x[3], a[1]) { my_model = y + 1; }", 1, 35, "unknown variable 'y'"),
        ("my_model(x[3], a[1]) { my_model = x[4]; }", 1, 35, "out of range"),
        ("my_model(x[3], a[1]) { my_model = x[1] + ; }", 1, 42, "expected an expression"),
        ("my_model(x[3], a[1]) { f = 1 }", 1, 30, "expected ';'"),
        ("my_model(x[3], a[1]) { my_model = x[1]^x[2]; }", 1, 39, "exponent of '^'"),
        ("my_model(x[3], a[1]) { array c[3]; my_model = c[2]; }", 1, 47, "used before it is assigned"),
        ("my_model(x[3], a[1]) { my_model = hfSphere(x, x, 1); } my_model(x[3], a[1]) { my_model = 1; }", 1, 56, "already defined"),
        ("a(x[3], a[1]) { a = b(x, a); } b(x[3], a[1]) { b = 1; }", 1, 21, "defined after this body"),
        ("my_model(x[2], a[1]) { my_model = x[1]; }", 1, 10, "must be x[3]"),
        ("my_model(x[3], a[1]) { x[1] = 2; my_model = 1; }", 1, 24, "cannot be assigned"),
        ("my_model(x[3], a[1]) { r = hfRotate3DZ(x, 1); my_model = 1; }", 1, 28, "copy it into a local array"),
        ("my_model(x[3], a[1]) { my_model = hfBlendUni(x[1], x[2], 1, 0, 1); }", 1, 35, "must not be 0"),
        ("my_model(x[3], a[1]) { my_model = 1 $ 2; }", 1, 37, "unexpected character"),
        ("", 1, 1, "expected a body"),
    ];
    for &(src, line, col, msg) in cases {
        let e = parse_hyperfun(src).unwrap_err();
        assert!(e.message.contains(msg), "{src}: {e}");
        assert_eq!((e.line, e.column), (line, col), "{src}: {e}");
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let deep = format!(
        "my_model(x[3], a[1]) {{ my_model = {}x[1]{}; }}",
        "(".repeat(5000),
        ")".repeat(5000)
    );
    assert!(parse_hyperfun(&deep)
        .unwrap_err()
        .message
        .contains("nested too deeply"));
    let long = format!(
        "my_model(x[3], a[1]) {{ my_model = x[1]{}; }}",
        " + x[1]".repeat(5000)
    );
    assert!(parse_hyperfun(&long)
        .unwrap_err()
        .message
        .contains("too long or deep"));
    let ifs = format!(
        "my_model(x[3], a[1]) {{ f = 0; {} my_model = f; }}",
        "if x[1] > 0 then f = f + 1; ".repeat(300)
    );
    assert!(parse_hyperfun(&ifs)
        .unwrap_err()
        .message
        .contains("nested too deeply"));
    // Long flat programs are fine.
    let flat = format!(
        "my_model(x[3], a[1]) {{ f = 0; {} my_model = f; }}",
        "f = f + x[1]*0.5; ".repeat(3000)
    );
    assert!(close(hf(&flat).eval(1.0, 0.0, 0.0), 1500.0));
}

const VALID: &str = "my_model(x[3], a[1]) {
  array c[3], q[3];
  c = [0, 0.1, 0];
  q = [x[1], x[2], x[3]];
  r = hfRotate3DZ(q, 0.3);
  s = hfSphere(q, c, 0.8) \\ hfBlock(x, c, 1, 1, 1);
  i = 0;
  while i < 2 loop s = s | hfTorusY(x, c, 0.5, 0.1); i = i + 1; endloop;
  if x[2] > 0 then s = hfBlendUni(s, hfCylinderZ(x, c, 0.2), 0.1, 1, 1); endif;
  my_model = s & (1 - x[3]^2);
}";

fn survives(src: &str) -> Result<(), TestCaseError> {
    match parse_hyperfun(src) {
        Ok(t) => {
            let _ = t.eval(0.3, -0.7, 1.1);
            let _ = t.eval(
                arith_ia::Interval::input(0, -1.0, 1.0),
                arith_ia::Interval::input(1, -1.0, 1.0),
                arith_ia::Interval::input(2, -1.0, 1.0),
            );
        }
        Err(e) => {
            prop_assert!(e.line >= 1 && e.column >= 1, "{e}");
            prop_assert!(e.line <= src.split('\n').count(), "{e}");
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..200)) {
        survives(&String::from_utf8_lossy(&bytes))?;
    }

    #[test]
    fn random_programs_never_panic(src in "[a-z_(){}\\[\\];,=<>/+*^&|@~ .0-9\n-]{0,120}") {
        survives(&format!("my_model(x[3], a[1]) {{ {src}"))?;
    }

    /// A valid program with one cut, insertion or change anywhere.
    #[test]
    fn mutated_programs_never_panic(at in 0usize..400, len in 0usize..6, kind in 0u8..3, ch in "[a-z0-9(){}\\[\\];,=<>+*^&|@ -]") {
        let chars: Vec<char> = VALID.chars().collect();
        let at = at.min(chars.len());
        let end = (at + len).min(chars.len());
        let mut m: Vec<char> = chars[..at].to_vec();
        match kind {
            0 => {}
            1 => m.extend(ch.chars()),
            _ => m.extend(ch.chars().cycle().take(len)),
        }
        if kind != 1 { m.extend(&chars[end..]); } else { m.extend(&chars[at..]); }
        survives(&m.into_iter().collect::<String>())?;
    }
}

// ------------------------------------------------- a .hf file against a hand-written model

const SPHERE_MINUS_BOX: &str = "-- A ball with a corner cut away, blended onto a slab.
my_model(x[3], a[1]) {
  array centre[3], corner[3];
  centre = [0, 0, 0];
  corner = [0, 0, 0];
  ball = hfSphere(x, centre, 0.8) \\ hfBlock(x, corner, 1, 1, 1);
  slab = 0.1 - x[2]*x[2];
  my_model = hfBlendUni(ball, slab, 0.2, 1, 1);
}";

/// The same solid by hand, with the library's definitions.
struct Hand;
impl Shape for Hand {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        // In the library's order of operations, so that even the last bits agree.
        let ball = R::constant(0.8) * 0.8 - x.sqr() - y.sqr() - z.sqr();
        let t = |v: &R| v.clone() * v.clone().rsub(1.0);
        let block = intersect(intersect(t(&x), t(&y)), t(&z));
        let ball = subtract(ball, block);
        let slab = y.sqr().rsub(0.1);
        let s = (ball.clone() / 1.0).sqr() + 1.0 + (slab.clone() / 1.0).sqr();
        union(ball, slab) + s.rdiv(0.2)
    }
}

#[test]
fn hf_file_formula_and_hand_written_model_agree() {
    let t = hf(SPHERE_MINUS_BOX);
    let f = parse(
        "b = (0.64 - x^2 - y^2 - z^2) \\ ((x*(1 - x)) & (y*(1 - y)) & (z*(1 - z))); s = 0.1 - y^2;
                   hf_blend_union(b, s, 0.2, 1, 1)",
    )
    .unwrap();
    let mut rng = SplitMix64(5);
    for _ in 0..2000 {
        let (x, y, z) = (
            rng.range(-1.2, 1.2),
            rng.range(-1.2, 1.2),
            rng.range(-1.2, 1.2),
        );
        let (a, b, c) = (t.eval(x, y, z), f.eval(x, y, z), Hand.eval(x, y, z));
        assert!(close(a, c) && close(b, c), "{a} {b} {c} at ({x}, {y}, {z})");
    }
    // Rendered: the same hits and depths in every arithmetic.
    let view = View {
        eye: DVec3::new(2.0, 1.6, 3.0),
        look_at: DVec3::ZERO,
        up: DVec3::Y,
        fov_deg: 40.0,
        ortho: None,
    };
    let mut o = RenderOptions::for_view(view, Aabb::cube(1.3), 48, 36);
    o.eps = Some(1e-6);
    for kind in ArithKind::ALL {
        let a = render_kind(kind, &t, &o).unwrap();
        let b = render_kind(kind, &Hand, &o).unwrap();
        assert!(a.stats.hits > 300, "{} hits", a.stats.hits);
        assert_eq!(a.hit, b.hit, "{}", kind.name());
        for (k, (da, db)) in a.depth.iter().zip(&b.depth).enumerate() {
            if a.hit[k] {
                assert!(
                    (da - db).abs() <= 1e-4,
                    "pixel {k}: {da} vs {db} ({})",
                    kind.name()
                );
            }
        }
    }
}
