//! Every path against the emulated reference, on random lanes of every kind of float:
//! AVX-512 gives the tight bounds (the same numbers, bit for bit but for the sign of a
//! zero), AVX2 encloses them within one ulp, and plain operations agree bit for bit.

use super::*;
use proptest::prelude::*;

/// One lane operation, for the tests.
#[derive(Clone, Copy, Debug)]
enum Op {
    AddUp,
    AddDown,
    SubUp,
    SubDown,
    MulUp,
    MulDown,
    DivUp,
    DivDown,
    SqrtUp,
    SqrtDown,
    Add,
    Sub,
    Mul,
    Div,
    Sqrt,
    Fma,
    Min,
    Max,
}

const DIRECTED: [(Op, bool); 10] = [
    (Op::AddUp, true),
    (Op::AddDown, false),
    (Op::SubUp, true),
    (Op::SubDown, false),
    (Op::MulUp, true),
    (Op::MulDown, false),
    (Op::DivUp, true),
    (Op::DivDown, false),
    (Op::SqrtUp, true),
    (Op::SqrtDown, false),
];

const PLAIN: [Op; 8] = [
    Op::Add,
    Op::Sub,
    Op::Mul,
    Op::Div,
    Op::Sqrt,
    Op::Fma,
    Op::Min,
    Op::Max,
];

struct Apply(Op, F64x8, F64x8, F64x8);

impl Kernel for Apply {
    type Output = (F64x8, u8, u8);
    #[inline(always)]
    fn run<I: Isa>(self, s: I) -> Self::Output {
        let (a, b, c) = (s.load(&self.1), s.load(&self.2), s.load(&self.3));
        let r = match self.0 {
            Op::AddUp => s.add_up(a, b),
            Op::AddDown => s.add_down(a, b),
            Op::SubUp => s.sub_up(a, b),
            Op::SubDown => s.sub_down(a, b),
            Op::MulUp => s.mul_up(a, b),
            Op::MulDown => s.mul_down(a, b),
            Op::DivUp => s.div_up(a, b),
            Op::DivDown => s.div_down(a, b),
            Op::SqrtUp => s.sqrt_up(a),
            Op::SqrtDown => s.sqrt_down(a),
            Op::Add => s.add(a, b),
            Op::Sub => s.sub(a, b),
            Op::Mul => s.mul(a, b),
            Op::Div => s.div(a, b),
            Op::Sqrt => s.sqrt(a),
            Op::Fma => s.fma(a, b, c),
            Op::Min => s.min(a, b),
            Op::Max => s.max(a, b),
        };
        (s.store(r), s.bits(s.lt(a, b)), s.bits(s.unord(a, b)))
    }
}

/// Floats of every kind: zeros of both signs, subnormals, the extremes, infinities,
/// NaN, random bit patterns (every exponent) and ordinary numbers.
fn float() -> impl Strategy<Value = f64> {
    prop_oneof![
        prop::sample::select(vec![
            0.0,
            -0.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            f64::from_bits(1),
            -f64::from_bits(1),
            1.0,
            -1.0,
            3.0,
            0.1,
        ]),
        any::<u64>().prop_map(f64::from_bits),
        (1u64..(1 << 52), any::<bool>()).prop_map(|(m, s)| {
            let x = f64::from_bits(m);
            if s {
                -x
            } else {
                x
            }
        }),
        -1e3..1e3f64,
        -1e-300..1e-300f64,
    ]
}

fn lanes() -> impl Strategy<Value = F64x8> {
    prop::array::uniform8(float()).prop_map(F64x8)
}

/// Every path but the emulated one, with a note on standard error for each path this
/// processor lacks.
fn hardware_paths() -> Vec<Path> {
    [Path::Avx512, Path::Avx2]
        .into_iter()
        .filter(|p| {
            let ok = p.available();
            if !ok {
                eprintln!("lanes: skipped the {p} path (this processor lacks it)");
            }
            ok
        })
        .collect()
}

fn same_number(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a == 0.0 && b == 0.0) || (a.is_nan() && b.is_nan())
}

/// Whether `x` is `t` or the next float beyond it (outward: up for an upper bound).
fn within_one_ulp(x: f64, t: f64, up: bool) -> bool {
    if up {
        x >= t && (x == t || x <= t.next_up())
    } else {
        x <= t && (x == t || x >= t.next_down())
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// AVX-512 gives the emulated tight bounds, AVX2 encloses them within one ulp;
    /// neither ever gives NaN.
    #[test]
    fn directed_bounds_match_the_reference(a in lanes(), b in lanes()) {
        for (op, up) in DIRECTED {
            let (want, _, _) = dispatch(Path::Emulated, Apply(op, a, b, b));
            for path in hardware_paths() {
                let (got, _, _) = dispatch(path, Apply(op, a, b, b));
                for k in 0..LANES {
                    let (g, t) = (got.0[k], want.0[k]);
                    prop_assert!(!g.is_nan() && !t.is_nan(), "{op:?} {path}: NaN");
                    let ok = match path {
                        Path::Avx512 => same_number(g, t),
                        _ => within_one_ulp(g, t, up),
                    };
                    prop_assert!(ok, "{op:?} on {path}: {g:e} vs tight {t:e} for ({:e}, {:e})",
                        a.0[k], b.0[k]);
                }
            }
        }
    }

    /// Plain operations, comparisons and masks are the same bits on every path.
    #[test]
    fn plain_ops_agree(a in lanes(), b in lanes(), c in lanes()) {
        for op in PLAIN {
            let want = dispatch(Path::Emulated, Apply(op, a, b, c));
            for path in hardware_paths() {
                let got = dispatch(path, Apply(op, a, b, c));
                prop_assert_eq!((got.1, got.2), (want.1, want.2), "{:?} {}", op, path);
                for k in 0..LANES {
                    prop_assert!(same_bits_or_nan(got.0 .0[k], want.0 .0[k]),
                        "{op:?} on {path}: {:e} vs {:e}", got.0 .0[k], want.0 .0[k]);
                }
            }
        }
    }
}

fn same_bits_or_nan(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// The emulated reference itself: each bound is the floor or ceiling (checked against
/// the exact error-free transformations where they apply, and on known cases).
#[test]
fn emulated_sqrt_is_floor_and_ceiling() {
    use super::emulated::{sqrt_hi, sqrt_lo};
    for x in [4.0, 2.0, 0.5, 1e-310, 5e-324, 1e300, f64::MAX, 3.0, 1e-200] {
        let (lo, hi) = (sqrt_lo(x), sqrt_hi(x));
        assert!(lo <= hi && (lo == hi || lo.next_up() == hi), "{x:e}");
        // lo^2 <= x <= hi^2, exactly (scaled near underflow so the squares are exact
        // in their sign).
        let s = if x < 1e-250 { 2f64.powi(500) } else { 1.0 };
        let (l, h, xs) = (lo * s, hi * s, x * s * s);
        assert!(
            l.mul_add(l, -xs) <= 0.0 && h.mul_add(h, -xs) >= 0.0,
            "{x:e}"
        );
    }
    assert_eq!((sqrt_lo(4.0), sqrt_hi(4.0)), (2.0, 2.0));
    assert_eq!(
        (sqrt_lo(-1.0), sqrt_hi(-1.0)),
        (f64::NEG_INFINITY, f64::INFINITY)
    );
    assert_eq!((sqrt_lo(f64::INFINITY), sqrt_hi(0.0)), (f64::INFINITY, 0.0));
}

#[test]
fn undefined_results_are_infinite_bounds_on_every_path() {
    let inf = f64::INFINITY;
    let a = F64x8([inf, 0.0, inf, 1.0, f64::NAN, -1.0, 0.0, -inf]);
    let b = F64x8([-inf, inf, inf, 0.0, 1.0, 0.0, -0.0, -inf]);
    for path in Path::available_paths() {
        for (op, up) in DIRECTED {
            let (r, _, _) = dispatch(path, Apply(op, a, b, b));
            let (want, _, _) = dispatch(Path::Emulated, Apply(op, a, b, b));
            for k in 0..LANES {
                if want.0[k].is_infinite() && want.0[k] == if up { inf } else { -inf } {
                    assert_eq!(r.0[k], want.0[k], "{op:?} {path} lane {k}");
                }
                assert!(!r.0[k].is_nan(), "{op:?} {path} lane {k}");
            }
        }
    }
}

#[test]
fn the_environment_picks_a_path() {
    assert_eq!(Path::from_env(Some("emulated")), Path::Emulated);
    assert_eq!(Path::from_env(None), Path::best());
    assert_eq!(Path::from_env(Some("no-such-path")), Path::best());
    for p in Path::ALL {
        assert_eq!(Path::from_name(p.name()), Some(p));
        if p.available() {
            assert_eq!(Path::from_env(Some(p.name())), p);
        }
    }
    assert!(Path::Emulated.available());
}

#[test]
fn subnormals_are_kept() {
    assert!(
        subnormals_kept(),
        "flush-to-zero or denormals-are-zero is set"
    );
    let t = std::hint::black_box(f64::MIN_POSITIVE);
    assert!(t / 2.0 > 0.0);
}

/// The paths differ where they should: AVX-512 keeps exact results and rounds inexact
/// ones to the neighbouring float, AVX2 steps one ulp outward from the rounded result.
#[test]
fn each_path_rounds_its_own_way() {
    let a = F64x8([1.0, 0.1, -0.1, 1e308, 5e-324, 2.0, -3.0, 0.5]);
    let b = F64x8([2.0, 0.2, -0.2, 1e308, 5e-324, 3.0, 7.0, 0.25]);
    let exact = F64x8([3.0, 0.0, 0.0, 0.0, 1e-323, 5.0, 4.0, 0.75]);
    for path in Path::available_paths() {
        let (up, _, _) = dispatch(path, Apply(Op::AddUp, a, b, b));
        let (down, _, _) = dispatch(path, Apply(Op::AddDown, a, b, b));
        for k in [0, 4, 5, 6, 7] {
            let x = exact.0[k];
            match path {
                Path::Avx2 => assert_eq!((down.0[k], up.0[k]), (x.next_down(), x.next_up())),
                _ => assert_eq!((down.0[k], up.0[k]), (x, x), "{path} lane {k}"),
            }
        }
        // 0.1 + 0.2 is inexact: tight bounds are adjacent floats around it.
        let s = 0.1 + 0.2;
        assert!(down.0[1] < up.0[1] && (down.0[1] == s || up.0[1] == s) || path == Path::Avx2);
        // An overflow of finite operands: `f64::MAX` below, `+inf` above.
        assert_eq!((down.0[3], up.0[3]), (f64::MAX, f64::INFINITY), "{path}");
    }
}

/// [`Isa::scale_pow2`] and [`Isa::split_pow2`] over eight lanes.
struct Pow2(F64x8, F64x8);

impl Kernel for Pow2 {
    type Output = (F64x8, F64x8, F64x8);
    #[inline(always)]
    fn run<I: Isa>(self, s: I) -> Self::Output {
        let (a, k) = (s.load(&self.0), s.load(&self.1));
        let (m, e) = s.split_pow2(a);
        (s.store(s.scale_pow2(a, k)), s.store(m), s.store(e))
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// `scale_pow2` is the exact product and `split_pow2` the exact split with the
    /// significand in `[0.75, 1.5)`, the same bits on every path, over positive normal
    /// numbers of every exponent (the significands 0.75 and 1.5 included).
    #[test]
    fn powers_of_two_are_exact(
        bits in prop::array::uniform8(
            prop_oneof![
                (1u64..0x7ff, 0u64..(1 << 52)).prop_map(|(e, m)| (e << 52) | m),
                (1u64..0x7ff, prop::sample::select(vec![0u64, 1 << 51, (1 << 51) - 1]))
                    .prop_map(|(e, m)| (e << 52) | m),
            ]
        ),
        ks in prop::array::uniform8(-60i32..60),
    ) {
        let a = F64x8(bits.map(f64::from_bits));
        // Powers that keep `a 2^k` normal.
        let k = F64x8(core::array::from_fn(|l| {
            let e = ((bits[l] >> 52) as i32) - 1023;
            f64::from(ks[l].clamp(-1021 - e, 1022 - e))
        }));
        let want = dispatch(Path::Emulated, Pow2(a, k));
        for l in 0..LANES {
            let (x, m, e) = (a.0[l], want.1 .0[l], want.2 .0[l]);
            prop_assert!((0.75..1.5).contains(&m) && e == e.trunc(), "{x:e}: {m} {e}");
            // m 2^e without an intermediate overflow or underflow.
            let back = if e >= 0.0 {
                m * 2f64.powi(e as i32 - 1) * 2.0
            } else {
                m * 2f64.powi(e as i32 + 1) / 2.0
            };
            prop_assert_eq!(back, x);
            let p = want.0 .0[l];
            prop_assert_eq!(p / 2f64.powi(k.0[l] as i32), x, "{:e} 2^{}", x, k.0[l]);
        }
        for path in hardware_paths() {
            let got = dispatch(path, Pow2(a, k));
            prop_assert_eq!(got, want, "{}", path);
        }
    }
}
