//! The HyperFun library primitives and operations the subset supports, each written
//! from its definition in the library's C sources (`hflibrary_lib/*.c` of the HyperFun
//! interpreter) as a formula tree, in the same order of operations. Argument order is
//! the HyperFun one: `hfSphere(x, center, R)`.
//!
//! Where the C code returns the sentinel `-1111111111111` for a degenerate parameter
//! (a zero semi-axis, a negative block size) the formula does the same, with a
//! conditional that folds away when the parameter is a constant. Where the interpreter
//! refuses a parameter at run time (`hfBlendUni` with `a1 = 0`, `hfScale3D` with a zero
//! factor, a taper with a scale `<= 0`), a constant such parameter is a compile error.
//! Space mappings (rotations, shifts, scaling, twists, tapers) change their array
//! argument in place and return 1, as in HyperFun.

use super::HfError;
use crate::formula::{BinOp, Expr, Func, EPS};

/// The sentinel the library returns for degenerate parameters.
pub const SENTINEL: f64 = -1111111111111.0;

/// What an argument is: an array (passed by name) or a real value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Array,
    Real,
}

use Kind::{Array as A, Real as R};

/// The library functions: lower-case name, the name as documented, argument kinds.
pub(crate) const LIBRARY: &[(&str, &str, &[Kind])] = &[
    ("hfsphere", "hfSphere", &[A, A, R]),
    ("hfellipsoid", "hfEllipsoid", &[A, A, R, R, R]),
    ("hfblock", "hfBlock", &[A, A, R, R, R]),
    ("hfcylinderx", "hfCylinderX", &[A, A, R]),
    ("hfcylindery", "hfCylinderY", &[A, A, R]),
    ("hfcylinderz", "hfCylinderZ", &[A, A, R]),
    ("hfellcylx", "hfEllCylX", &[A, A, R, R]),
    ("hfellcyly", "hfEllCylY", &[A, A, R, R]),
    ("hfellcylz", "hfEllCylZ", &[A, A, R, R]),
    ("hfconex", "hfConeX", &[A, A, R]),
    ("hfconey", "hfConeY", &[A, A, R]),
    ("hfconez", "hfConeZ", &[A, A, R]),
    ("hfellconex", "hfEllConeX", &[A, A, R, R]),
    ("hfellconey", "hfEllConeY", &[A, A, R, R]),
    ("hfellconez", "hfEllConeZ", &[A, A, R, R]),
    ("hftorusx", "hfTorusX", &[A, A, R, R]),
    ("hftorusy", "hfTorusY", &[A, A, R, R]),
    ("hftorusz", "hfTorusZ", &[A, A, R, R]),
    ("hfsuperell", "hfSuperell", &[A, A, R, R, R, R, R]),
    ("hfblenduni", "hfBlendUni", &[R, R, R, R, R]),
    ("hfblendint", "hfBlendInt", &[R, R, R, R, R]),
    ("hfrotate3dx", "hfRotate3DX", &[A, R]),
    ("hfrotate3dy", "hfRotate3DY", &[A, R]),
    ("hfrotate3dz", "hfRotate3DZ", &[A, R]),
    ("hfscale3d", "hfScale3D", &[A, R, R, R]),
    ("hfshift3d", "hfShift3D", &[A, R, R, R]),
    ("hfstretch3d", "hfStretch3D", &[A, A, R, R, R]),
    ("hftwistx", "hfTwistX", &[A, R, R, R, R]),
    ("hftwisty", "hfTwistY", &[A, R, R, R, R]),
    ("hftwistz", "hfTwistZ", &[A, R, R, R, R]),
    ("hftaperx", "hfTaperX", &[A, R, R, R, R]),
    ("hftapery", "hfTaperY", &[A, R, R, R, R]),
    ("hftaperz", "hfTaperZ", &[A, R, R, R, R]),
    ("hfnoiseg", "hfNoiseG", &[A, R, R, R]),
];

/// What the compiler offers the library: sharing a value (so that an expansion that
/// reads it several times does not copy its tree) and its constant value, if any.
pub(crate) trait Ctx {
    /// `e` as a value that is cheap to copy (a binding, a number or a coordinate).
    fn share(&mut self, e: Expr) -> Expr;
    /// The constant `e` folds to, if it does.
    fn constant(&self, e: &Expr) -> Option<f64>;
}

/// An evaluated argument.
#[derive(Clone, Debug)]
pub(crate) enum Arg {
    /// The elements of an array (at least one).
    Array(Vec<Expr>),
    /// A value.
    Real(Expr),
}

/// What a call gives: its value, and the new contents of its array argument `k` for a
/// space mapping.
pub(crate) struct Out {
    pub value: Expr,
    pub update: Option<(usize, Vec<Expr>)>,
}

fn num(c: f64) -> Expr {
    Expr::Num(c)
}
fn add(a: Expr, b: Expr) -> Expr {
    Expr::bin(BinOp::Add, a, b)
}
fn sub(a: Expr, b: Expr) -> Expr {
    Expr::bin(BinOp::Sub, a, b)
}
fn mul(a: Expr, b: Expr) -> Expr {
    Expr::bin(BinOp::Mul, a, b)
}
fn div(a: Expr, b: Expr) -> Expr {
    Expr::bin(BinOp::Div, a, b)
}
/// `a * a`, as the C code squares (the tape computes `sqr` as the same product).
fn sq(a: Expr) -> Expr {
    Expr::pow(a, 2)
}
fn call(f: Func, args: Vec<Expr>) -> Expr {
    Expr::Call(f, args)
}

/// `|a| < EPS`, the library's test of a degenerate parameter.
fn tiny(a: &Expr) -> Expr {
    Expr::bin(BinOp::Lt, call(Func::Abs, vec![a.clone()]), num(EPS))
}

/// `f`, or the sentinel where one of `bad` holds (folded where they are constants).
fn guard(cx: &mut dyn Ctx, bad: Vec<Expr>, f: Expr) -> Expr {
    let mut open = Vec::new();
    for b in bad {
        match cx.constant(&b) {
            Some(v) if v != 0.0 => return num(SENTINEL),
            Some(_) => {}
            None => open.push(b),
        }
    }
    match open.into_iter().reduce(|a, b| Expr::bin(BinOp::Or, a, b)) {
        None => f,
        Some(c) => call(Func::If, vec![c, num(SENTINEL), f]),
    }
}

/// Element `k` of an array argument, shared.
fn el(cx: &mut dyn Ctx, a: &[Expr], k: usize) -> Expr {
    cx.share(a[k].clone())
}

/// `x[k] - c[k]` for the three axes, shared.
fn offsets(cx: &mut dyn Ctx, x: &[Expr], c: &[Expr]) -> [Expr; 3] {
    std::array::from_fn(|k| {
        let d = sub(x[k].clone(), c[k].clone());
        cx.share(d)
    })
}

/// Calls library function `name` (lower case) on evaluated arguments whose kinds match
/// its signature and whose arrays have at least 3 elements.
pub(crate) fn apply(
    cx: &mut dyn Ctx,
    name: &str,
    args: &[Arg],
    line: usize,
    col: usize,
) -> Result<Out, HfError> {
    let arr = |k: usize| match &args[k] {
        Arg::Array(v) => v.clone(),
        Arg::Real(e) => vec![e.clone()],
    };
    let real = |cx: &mut dyn Ctx, k: usize| match &args[k] {
        Arg::Real(e) => cx.share(e.clone()),
        Arg::Array(v) => v[0].clone(),
    };
    let refuse = |what: &str| Err(HfError::new(line, col, what.to_string()));
    let value = |e: Expr| {
        Ok(Out {
            value: e,
            update: None,
        })
    };
    let mapped = |k: usize, v: Vec<Expr>| {
        Ok(Out {
            value: num(1.0),
            update: Some((k, v)),
        })
    };
    let axis = |name: &str| match name.as_bytes().last() {
        Some(b'x') => 0,
        Some(b'y') => 1,
        _ => 2,
    };
    match name {
        "hfsphere" => {
            let (x, c) = (arr(0), arr(1));
            let r = real(cx, 2);
            let [dx, dy, dz] = offsets(cx, &x, &c);
            value(sub(sub(sub(mul(r.clone(), r), sq(dx)), sq(dy)), sq(dz)))
        }
        "hfellipsoid" => {
            let (x, c) = (arr(0), arr(1));
            let (a, b, cc) = (real(cx, 2), real(cx, 3), real(cx, 4));
            let t: Vec<Expr> = (0..3)
                .map(|k| {
                    let s = [&a, &b, &cc][k];
                    let d = div(sub(x[k].clone(), c[k].clone()), s.clone());
                    cx.share(d)
                })
                .collect();
            let f = sub(
                sub(sub(num(1.0), sq(t[0].clone())), sq(t[1].clone())),
                sq(t[2].clone()),
            );
            value(guard(cx, vec![tiny(&a), tiny(&b), tiny(&cc)], f))
        }
        "hfblock" => {
            let (x, v) = (arr(0), arr(1));
            let d = [real(cx, 2), real(cx, 3), real(cx, 4)];
            let t: Vec<Expr> = (0..3)
                .map(|k| {
                    let xk = el(cx, &x, k);
                    let vk = el(cx, &v, k);
                    let e = mul(sub(xk.clone(), vk.clone()), sub(add(vk, d[k].clone()), xk));
                    cx.share(e)
                })
                .collect();
            let f = Expr::bin(
                BinOp::Intersect,
                Expr::bin(BinOp::Intersect, t[0].clone(), t[1].clone()),
                t[2].clone(),
            );
            let neg = |e: &Expr| Expr::bin(BinOp::Lt, e.clone(), num(0.0));
            value(guard(cx, vec![neg(&d[0]), neg(&d[1]), neg(&d[2])], f))
        }
        "hfcylinderx" | "hfcylindery" | "hfcylinderz" => {
            let (x, c) = (arr(0), arr(1));
            let r = real(cx, 2);
            let skip = axis(name);
            let [d0, d1, d2] = offsets(cx, &x, &c);
            let ds: Vec<Expr> = [d0, d1, d2]
                .into_iter()
                .enumerate()
                .filter(|(k, _)| *k != skip)
                .map(|(_, d)| d)
                .collect();
            value(sub(
                sub(mul(r.clone(), r), sq(ds[0].clone())),
                sq(ds[1].clone()),
            ))
        }
        "hfellcylx" | "hfellcyly" | "hfellcylz" => {
            let (x, c) = (arr(0), arr(1));
            let (a, b) = (real(cx, 2), real(cx, 3));
            let skip = axis(name);
            let ks: Vec<usize> = (0..3).filter(|k| *k != skip).collect();
            let t0 = div(sub(x[ks[0]].clone(), c[ks[0]].clone()), a.clone());
            let t1 = div(sub(x[ks[1]].clone(), c[ks[1]].clone()), b.clone());
            let (t0, t1) = (cx.share(t0), cx.share(t1));
            let f = sub(sub(num(1.0), sq(t0)), sq(t1));
            value(guard(cx, vec![tiny(&a), tiny(&b)], f))
        }
        "hfconex" | "hfconey" | "hfconez" | "hfellconex" | "hfellconey" | "hfellconez" => {
            let (x, c) = (arr(0), arr(1));
            let ell = name.starts_with("hfell");
            let (a, b) = if ell {
                (real(cx, 2), real(cx, 3))
            } else {
                let r = real(cx, 2);
                (r.clone(), r)
            };
            let apex = axis(name);
            let ks: Vec<usize> = (0..3).filter(|k| *k != apex).collect();
            let d = cx.share(sub(x[apex].clone(), c[apex].clone()));
            let t0 = div(sub(x[ks[0]].clone(), c[ks[0]].clone()), a);
            let t1 = div(sub(x[ks[1]].clone(), c[ks[1]].clone()), b);
            let (t0, t1) = (cx.share(t0), cx.share(t1));
            value(sub(sub(sq(d), sq(t0)), sq(t1)))
        }
        "hftorusx" | "hftorusy" | "hftorusz" => {
            let (x, c) = (arr(0), arr(1));
            let (big, r0) = (real(cx, 2), real(cx, 3));
            let ax = axis(name);
            let [d0, d1, d2] = offsets(cx, &x, &c);
            let d = [d0, d1, d2];
            let s: Vec<Expr> = (0..3).map(|k| cx.share(sq(d[k].clone()))).collect();
            // The two axes around the torus's own, in the C code's order.
            let (p, q) = match ax {
                0 => (2, 1),
                1 => (2, 0),
                _ => (0, 1),
            };
            let f = sub(
                sub(
                    sub(sub(mul(r0.clone(), r0), s[0].clone()), s[1].clone()),
                    s[2].clone(),
                ),
                mul(big.clone(), big.clone()),
            );
            let ring = mul(
                mul(num(2.0), big),
                call(Func::Sqrt, vec![add(s[p].clone(), s[q].clone())]),
            );
            value(add(f, ring))
        }
        "hfsuperell" => {
            let (x, c) = (arr(0), arr(1));
            let (a, b, cc) = (real(cx, 2), real(cx, 3), real(cx, 4));
            let (s1, s2) = (real(cx, 5), real(cx, 6));
            let (Some(e1), Some(e2)) = (cx.constant(&s1), cx.constant(&s2)) else {
                return refuse("hfSuperell: the shape exponents s1 and s2 must be constants");
            };
            if e1.abs() < EPS || e2.abs() < EPS {
                return value(num(SENTINEL));
            }
            let t: Vec<Expr> = (0..3)
                .map(|k| {
                    let s = [&a, &b, &cc][k];
                    let d = div(sub(x[k].clone(), c[k].clone()), s.clone());
                    let d = call(Func::Abs, vec![d]);
                    cx.share(d)
                })
                .collect();
            let p = 2.0 / e2;
            let xp = power(t[0].clone(), p);
            let yp = power(t[1].clone(), p);
            let zp = power(t[2].clone(), 2.0 / e1);
            let xyp = power(add(xp, yp), e2 / e1);
            let f = sub(sub(num(1.0), xyp), zp);
            value(guard(cx, vec![tiny(&a), tiny(&b), tiny(&cc)], f))
        }
        "hfblenduni" | "hfblendint" => {
            let v: Vec<Expr> = (0..5).map(|k| real(cx, k)).collect();
            for k in [3, 4] {
                if cx.constant(&v[k]).is_some_and(|a| a.abs() < EPS) {
                    return refuse("hfBlendUni/hfBlendInt: a1 and a2 must not be 0");
                }
            }
            let f = if name == "hfblenduni" {
                Func::HfBlendUnion
            } else {
                Func::HfBlendIntersect
            };
            value(call(f, v))
        }
        "hfrotate3dx" | "hfrotate3dy" | "hfrotate3dz" => {
            let x = arr(0);
            let th = real(cx, 1);
            let ct = cx.share(call(Func::Cos, vec![th.clone()]));
            let st = cx.share(call(Func::Sin, vec![th]));
            mapped(0, rotate(cx, &x, axis(name), &ct, &st))
        }
        "hfscale3d" | "hfshift3d" => {
            let mut x = arr(0);
            let s = [real(cx, 1), real(cx, 2), real(cx, 3)];
            let scale = name == "hfscale3d";
            if scale
                && s.iter()
                    .any(|v| cx.constant(v).is_some_and(|a| a.abs() < EPS))
            {
                return refuse("hfScale3D: a scale factor must not be 0");
            }
            for k in 0..3 {
                let e = if scale {
                    div(x[k].clone(), s[k].clone())
                } else {
                    sub(x[k].clone(), s[k].clone())
                };
                x[k] = cx.share(e);
            }
            mapped(0, x)
        }
        "hfstretch3d" => {
            let (mut x, x0) = (arr(0), arr(1));
            let s = [real(cx, 2), real(cx, 3), real(cx, 4)];
            if s.iter()
                .any(|v| cx.constant(v).is_some_and(|a| a.abs() < EPS))
            {
                return refuse("hfStretch3D: a stretch factor must not be 0");
            }
            for k in 0..3 {
                let e = add(
                    x0[k].clone(),
                    div(sub(x[k].clone(), x0[k].clone()), s[k].clone()),
                );
                x[k] = cx.share(e);
            }
            mapped(0, x)
        }
        "hftwistx" | "hftwisty" | "hftwistz" => {
            let x = arr(0);
            let ax = axis(name);
            let (u1, u2, th1, th2) = (real(cx, 1), real(cx, 2), real(cx, 3), real(cx, 4));
            let t = cx.share(div(sub(x[ax].clone(), u1.clone()), sub(u2, u1)));
            let th = add(mul(sub(num(1.0), t.clone()), th1), mul(t, th2));
            let th = cx.share(th);
            let ct = cx.share(call(Func::Cos, vec![th.clone()]));
            let st = cx.share(call(Func::Sin, vec![th]));
            mapped(0, rotate(cx, &x, ax, &ct, &st))
        }
        "hftaperx" | "hftapery" | "hftaperz" => {
            let mut x = arr(0);
            let ax = axis(name);
            let (u1, u2, s1, s2) = (real(cx, 1), real(cx, 2), real(cx, 3), real(cx, 4));
            let (c1, c2) = (cx.constant(&s1), cx.constant(&s2));
            if c1.is_some_and(|v| v <= 0.0) || c2.is_some_and(|v| v <= 0.0) {
                return refuse("hfTaperX/Y/Z: the scales s1 and s2 must be positive");
            }
            let xa = x[ax].clone();
            let t = cx.share(div(
                sub(xa.clone(), u1.clone()),
                sub(u2.clone(), u1.clone()),
            ));
            let lerp = add(
                mul(sub(num(1.0), t.clone()), s1.clone()),
                mul(t, s2.clone()),
            );
            let inner = call(
                Func::If,
                vec![Expr::bin(BinOp::Gt, xa.clone(), u2), s2, lerp],
            );
            let scale = call(Func::If, vec![Expr::bin(BinOp::Lt, xa, u1), s1, inner]);
            let mut scale = cx.share(scale);
            let safe = matches!((c1, c2), (Some(a), Some(b)) if a >= EPS && b >= EPS);
            if !safe {
                // The C code's guard: a scale below EPS counts as 1.
                scale = cx.share(call(Func::If, vec![tiny(&scale), num(1.0), scale]));
            }
            for k in (0..3).filter(|k| *k != ax) {
                x[k] = cx.share(div(x[k].clone(), scale.clone()));
            }
            mapped(0, x)
        }
        "hfnoiseg" => {
            let x = arr(0);
            let (a1, a2, phase) = (real(cx, 1), real(cx, 2), real(cx, 3));
            let a2x: Vec<Expr> = (0..3)
                .map(|k| cx.share(mul(a2.clone(), x[k].clone())))
                .collect();
            let s: Vec<Expr> = (0..3)
                .map(|k| cx.share(call(Func::Sin, vec![a2x[k].clone()])))
                .collect();
            let a1d = cx.share(div(a1.clone(), num(1.17)));
            // sx2 uses sz, sy2 uses sx, sz2 uses sy.
            let other = [2, 0, 1];
            let ser: Vec<Expr> = (0..3)
                .map(|k| {
                    let arg = add(
                        div(a2x[k].clone(), num(1.35)),
                        mul(phase.clone(), s[other[k]].clone()),
                    );
                    let s2 = mul(a1d.clone(), call(Func::Sin, vec![arg]));
                    cx.share(add(mul(a1.clone(), s[k].clone()), s2))
                })
                .collect();
            value(mul(mul(ser[0].clone(), ser[1].clone()), ser[2].clone()))
        }
        _ => refuse(&format!("internal: no library function '{name}'")),
    }
}

/// `b^p` as C's `pow` for `b >= 0`: an integer power where `p` is an integer, else
/// `exp(p ln b)`.
fn power(b: Expr, p: f64) -> Expr {
    if p.fract() == 0.0 && p.abs() <= 1024.0 {
        Expr::pow(b, p as i32)
    } else {
        Expr::PowF(Box::new(b), p)
    }
}

/// The array `x` rotated about axis `ax` by the angle with cosine `ct` and sine `st`,
/// as `hfRotate3DX/Y/Z`: for the axis pair `(i, j)` = (y, z), (z, x), (x, y),
/// `x_i' = x_i ct + x_j st` and `x_j' = -x_i st + x_j ct`.
fn rotate(cx: &mut dyn Ctx, x: &[Expr], ax: usize, ct: &Expr, st: &Expr) -> Vec<Expr> {
    let (i, j) = match ax {
        0 => (1, 2),
        1 => (2, 0),
        _ => (0, 1),
    };
    let mut out = x.to_vec();
    let (xi, xj) = (x[i].clone(), x[j].clone());
    out[i] = cx.share(add(
        mul(xi.clone(), ct.clone()),
        mul(xj.clone(), st.clone()),
    ));
    out[j] = cx.share(add(mul(Expr::neg(xi), st.clone()), mul(xj, ct.clone())));
    out
}
