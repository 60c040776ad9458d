//! Eight `f64` lanes with directed rounding at hardware speed, through one of three
//! instruction paths chosen once per process ([`Path`]):
//!
//! - [`Path::Avx512`]: AVX-512F instructions that carry their own rounding mode
//!   (`vaddpd {ru-sae}` and friends): each directed bound is one instruction and, where
//!   the operation is defined, the same number as the emulated tight bound (bit for bit
//!   but for the sign of an exact zero result, which IEEE rounding downward makes `-0`).
//! - [`Path::Avx2`]: round to nearest, then one ulp outward through the bit pattern
//!   (the rounding error is at most half an ulp, so the step always reaches past the
//!   exact result): sound, at most one ulp looser than tight, two 4-lane registers.
//! - [`Path::Emulated`]: [`crate::round::tight`] lane by lane (the rounded result, its
//!   exact error, one ulp outward by the error's sign): the reference, and the fallback
//!   on every other processor.
//!
//! No rounding mode is ever switched: the per-instruction rounding of AVX-512 leaves
//! MXCSR alone. Flush-to-zero or denormals-are-zero would break every path's proof;
//! [`dispatch`] refuses the hardware paths while either is set ([`subnormals_kept`]).
//!
//! Code written once against [`Isa`] is compiled for each path by [`dispatch`]: a
//! [`Kernel`]'s `run` (marked `#[inline(always)]`) is instantiated inside a function
//! compiled with the path's target features, so the lane operations inline to single
//! instructions. The environment variable `ARITH_LANES` (`avx512`, `avx2`, `emulated`)
//! forces a path; a path the processor lacks falls back to the best one it has.
//!
//! ## Directed operations and their edge cases
//!
//! The `_up`/`_down` operations are the ceiling/floor in `f64` of the exact result on
//! the avx512 and emulated paths, a bound at most one ulp further out on avx2. An
//! undefined result (`inf - inf`, `0 * inf`, `x / 0`, `inf / inf`, the root of a
//! negative number, NaN operands) gives `-inf` as a lower and `+inf` as an upper bound,
//! never NaN. The `_raw` forms skip that repair: they give NaN exactly where the IEEE
//! operation does (and any value for a division by zero), for kernels that detect such
//! lanes once per block and redo them on the scalar path.

use core::fmt;

mod elementary;
mod emulated;
mod wide2;
#[cfg(target_arch = "x86_64")]
mod x86;

pub use elementary::{
    cos, cos_f64, exp, exp_enclosure, exp_f64, ln, ln_enclosure, ln_f64, sin, sin_f64,
    trig_enclosure, widen, ELEMENTARY_REL, EXP_COEFFS, EXP_MAX_ARG, TRIG_ABS, TRIG_MAX_ARG,
};
pub use emulated::Emulated;
pub use wide2::Avx2;
#[cfg(target_arch = "x86_64")]
pub use x86::Avx512;

/// Number of lanes of an [`F64x8`].
pub const LANES: usize = 8;

/// Eight `f64` lanes in memory, aligned for one 512-bit load. The storage type of
/// register files and the way values enter and leave an [`Isa`]'s registers.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[repr(C, align(64))]
pub struct F64x8(pub [f64; LANES]);

impl F64x8 {
    /// `c` in every lane.
    pub const fn splat(c: f64) -> Self {
        F64x8([c; LANES])
    }
}

/// The instruction paths, fastest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Path {
    /// AVX-512F with per-instruction rounding: tight bounds, eight lanes per register.
    Avx512,
    /// AVX2 and FMA: round to nearest, then one ulp outward; two four-lane registers.
    Avx2,
    /// [`crate::round::tight`] lane by lane: tight bounds, no SIMD requirement.
    Emulated,
}

impl Path {
    /// Every path, fastest first.
    pub const ALL: [Path; 3] = [Path::Avx512, Path::Avx2, Path::Emulated];

    /// The name `ARITH_LANES` takes.
    pub fn name(self) -> &'static str {
        match self {
            Path::Avx512 => "avx512",
            Path::Avx2 => "avx2",
            Path::Emulated => "emulated",
        }
    }

    /// The path of this name.
    pub fn from_name(s: &str) -> Option<Path> {
        Path::ALL.into_iter().find(|p| p.name() == s)
    }

    /// Whether this processor runs the path (the emulated one runs everywhere).
    pub fn available(self) -> bool {
        match self {
            #[cfg(target_arch = "x86_64")]
            Path::Avx512 => Avx512::detect().is_some(),
            #[cfg(target_arch = "x86_64")]
            Path::Avx2 => Avx2::detect().is_some(),
            Path::Emulated => true,
            #[allow(unreachable_patterns)]
            _ => false,
        }
    }

    /// The paths this processor runs, fastest first.
    pub fn available_paths() -> Vec<Path> {
        Path::ALL.into_iter().filter(|p| p.available()).collect()
    }

    /// The fastest path this processor runs.
    pub fn best() -> Path {
        Path::ALL
            .into_iter()
            .find(|p| p.available())
            .unwrap_or(Path::Emulated)
    }

    /// The path of this process: `ARITH_LANES` if it names an available path, else
    /// [`Path::best`]. Read once; later changes of the variable are not seen.
    pub fn current() -> Path {
        static CURRENT: std::sync::OnceLock<Path> = std::sync::OnceLock::new();
        *CURRENT.get_or_init(|| Path::from_env(std::env::var("ARITH_LANES").ok().as_deref()))
    }

    /// The path `ARITH_LANES=value` selects: the named one where available, else the
    /// fastest available (an unknown name is reported once on standard error).
    pub fn from_env(value: Option<&str>) -> Path {
        let Some(v) = value.filter(|v| !v.is_empty()) else {
            return Path::best();
        };
        match Path::from_name(v) {
            Some(p) if p.available() => p,
            Some(p) => {
                eprintln!(
                    "ARITH_LANES={v}: this processor lacks {}; using {}",
                    p.name(),
                    Path::best().name()
                );
                Path::best()
            }
            None => {
                eprintln!(
                    "ARITH_LANES={v}: not one of avx512, avx2, emulated; using {}",
                    Path::best().name()
                );
                Path::best()
            }
        }
    }
}

impl fmt::Display for Path {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The lane operations of one path. A value of the type is a token: it exists only
/// where the processor runs the path, which is what makes the operations safe.
///
/// `V` holds eight lanes in registers, `M` a mask of eight lanes. Plain operations round
/// to nearest (the same bits on every path); directed ones are described in the
/// [module documentation](self).
pub trait Isa: Copy + Send + Sync + 'static {
    /// Eight lanes in registers.
    type V: Copy;
    /// A mask of eight lanes.
    type M: Copy;
    /// Which path this is.
    const PATH: Path;

    /// Lanes from memory.
    fn load(self, x: &F64x8) -> Self::V;
    /// Lanes to memory.
    fn store(self, v: Self::V) -> F64x8;
    /// `c` in every lane.
    fn splat(self, c: f64) -> Self::V;

    /// `a + b`, rounded to nearest.
    fn add(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a - b`, rounded to nearest.
    fn sub(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a * b`, rounded to nearest.
    fn mul(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a / b`, rounded to nearest.
    fn div(self, a: Self::V, b: Self::V) -> Self::V;
    /// `sqrt(a)`, rounded to nearest.
    fn sqrt(self, a: Self::V) -> Self::V;
    /// `a * b + c` with one rounding to nearest.
    fn fma(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V;
    /// `-a` (the sign bit flipped).
    fn neg(self, a: Self::V) -> Self::V;
    /// `|a|` (the sign bit cleared).
    fn abs(self, a: Self::V) -> Self::V;
    /// The bitwise or of the lanes' bit patterns.
    fn or_bits(self, a: Self::V, b: Self::V) -> Self::V;
    /// The bitwise and of the lanes' bit patterns.
    fn and_bits(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a < b ? a : b` per lane (so `b` where either is NaN, and `b` for equal zeros).
    fn min(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a > b ? a : b` per lane (so `b` where either is NaN, and `b` for equal zeros).
    fn max(self, a: Self::V, b: Self::V) -> Self::V;

    /// `a < b` (false where either is NaN).
    fn lt(self, a: Self::V, b: Self::V) -> Self::M;
    /// `a <= b` (false where either is NaN).
    fn le(self, a: Self::V, b: Self::V) -> Self::M;
    /// `a == b` (false where either is NaN; `-0 == +0`).
    fn eq(self, a: Self::V, b: Self::V) -> Self::M;
    /// Whether `a` or `b` is NaN.
    fn unord(self, a: Self::V, b: Self::V) -> Self::M;
    /// `m ? a : b` per lane.
    fn select(self, m: Self::M, a: Self::V, b: Self::V) -> Self::V;
    /// Both masks.
    fn and(self, a: Self::M, b: Self::M) -> Self::M;
    /// Either mask.
    fn or(self, a: Self::M, b: Self::M) -> Self::M;
    /// The complement.
    fn not(self, a: Self::M) -> Self::M;
    /// The mask as bits, lane `k` in bit `k`.
    fn bits(self, m: Self::M) -> u8;

    /// `a * 2^k` for integral `k` with `|k| <= 1022` where the result is a normal
    /// number (then exact); other lanes get some value.
    fn scale_pow2(self, a: Self::V, k: Self::V) -> Self::V;
    /// `(m, e)` with `x = m * 2^e` exactly, `m` in `[0.75, 1.5)` and `e` integral, for
    /// positive normal `x`; other lanes get some values.
    fn split_pow2(self, x: Self::V) -> (Self::V, Self::V);

    /// Ceiling of `a + b`; NaN where `a + b` is NaN (see the module documentation).
    fn add_up_raw(self, a: Self::V, b: Self::V) -> Self::V;
    /// Floor of `a + b` (NaN where the IEEE operation is NaN).
    fn add_down_raw(self, a: Self::V, b: Self::V) -> Self::V;
    /// Ceiling of `a - b` (NaN where the IEEE operation is NaN).
    fn sub_up_raw(self, a: Self::V, b: Self::V) -> Self::V;
    /// Floor of `a - b` (NaN where the IEEE operation is NaN).
    fn sub_down_raw(self, a: Self::V, b: Self::V) -> Self::V;
    /// Ceiling of `a * b` (NaN where the IEEE operation is NaN).
    fn mul_up_raw(self, a: Self::V, b: Self::V) -> Self::V;
    /// Floor of `a * b` (NaN where the IEEE operation is NaN).
    fn mul_down_raw(self, a: Self::V, b: Self::V) -> Self::V;
    /// Ceiling of `a / b` for `b != 0` (NaN where the IEEE operation is NaN; any
    /// value for `b == 0`).
    fn div_up_raw(self, a: Self::V, b: Self::V) -> Self::V;
    /// Floor of `a / b` for `b != 0` (NaN where the IEEE operation is NaN; any
    /// value for `b == 0`).
    fn div_down_raw(self, a: Self::V, b: Self::V) -> Self::V;
    /// Ceiling of `sqrt(a)` for `a >= 0` (NaN for `a < 0` and NaN).
    fn sqrt_up_raw(self, a: Self::V) -> Self::V;
    /// Floor of `sqrt(a)` for `a >= 0` (NaN for `a < 0` and NaN).
    fn sqrt_down_raw(self, a: Self::V) -> Self::V;

    /// NaN lanes of `a` replaced by `c`.
    #[inline(always)]
    fn nan_to(self, a: Self::V, c: f64) -> Self::V {
        self.select(self.unord(a, a), self.splat(c), a)
    }
    /// Ceiling of `a + b`, `+inf` where undefined.
    #[inline(always)]
    fn add_up(self, a: Self::V, b: Self::V) -> Self::V {
        self.nan_to(self.add_up_raw(a, b), f64::INFINITY)
    }
    /// Floor of `a + b`, `-inf` where undefined.
    #[inline(always)]
    fn add_down(self, a: Self::V, b: Self::V) -> Self::V {
        self.nan_to(self.add_down_raw(a, b), f64::NEG_INFINITY)
    }
    /// Ceiling of `a - b`, `+inf` where undefined.
    #[inline(always)]
    fn sub_up(self, a: Self::V, b: Self::V) -> Self::V {
        self.nan_to(self.sub_up_raw(a, b), f64::INFINITY)
    }
    /// Floor of `a - b`, `-inf` where undefined.
    #[inline(always)]
    fn sub_down(self, a: Self::V, b: Self::V) -> Self::V {
        self.nan_to(self.sub_down_raw(a, b), f64::NEG_INFINITY)
    }
    /// Ceiling of `a * b`, `+inf` where undefined.
    #[inline(always)]
    fn mul_up(self, a: Self::V, b: Self::V) -> Self::V {
        self.nan_to(self.mul_up_raw(a, b), f64::INFINITY)
    }
    /// Floor of `a * b`, `-inf` where undefined.
    #[inline(always)]
    fn mul_down(self, a: Self::V, b: Self::V) -> Self::V {
        self.nan_to(self.mul_down_raw(a, b), f64::NEG_INFINITY)
    }
    /// Ceiling of `a / b`, `+inf` where undefined (`b == 0` included).
    #[inline(always)]
    fn div_up(self, a: Self::V, b: Self::V) -> Self::V {
        let zero = self.eq(b, self.splat(0.0));
        let q = self.div_up_raw(a, b);
        self.select(
            self.or(zero, self.unord(q, q)),
            self.splat(f64::INFINITY),
            q,
        )
    }
    /// Floor of `a / b`, `-inf` where undefined (`b == 0` included).
    #[inline(always)]
    fn div_down(self, a: Self::V, b: Self::V) -> Self::V {
        let zero = self.eq(b, self.splat(0.0));
        let q = self.div_down_raw(a, b);
        let inf = self.splat(f64::NEG_INFINITY);
        self.select(self.or(zero, self.unord(q, q)), inf, q)
    }
    /// Ceiling of `sqrt(a)`, `+inf` where undefined (`a < 0`, NaN).
    #[inline(always)]
    fn sqrt_up(self, a: Self::V) -> Self::V {
        self.nan_to(self.sqrt_up_raw(a), f64::INFINITY)
    }
    /// Floor of `sqrt(a)`, `-inf` where undefined (`a < 0`, NaN).
    #[inline(always)]
    fn sqrt_down(self, a: Self::V) -> Self::V {
        self.nan_to(self.sqrt_down_raw(a), f64::NEG_INFINITY)
    }
}

/// Code written once against [`Isa`], run on one path by [`dispatch`].
pub trait Kernel {
    /// What the kernel returns.
    type Output;
    /// Runs on the path `isa`. Implementations mark this `#[inline(always)]`, so that
    /// it is compiled inside the path's target-feature function with every lane
    /// operation inlined.
    fn run<I: Isa>(self, isa: I) -> Self::Output;
}

/// Runs `k` on `path`, or on the emulated path where the processor lacks `path` or the
/// thread flushes subnormals to zero ([`subnormals_kept`]).
#[inline]
pub fn dispatch<K: Kernel>(path: Path, k: K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    {
        match path {
            Path::Avx512 => {
                if let Some(t) = Avx512::detect().filter(|_| subnormals_kept()) {
                    return x86::run_avx512(t, k);
                }
            }
            Path::Avx2 => {
                if let Some(t) = Avx2::detect().filter(|_| subnormals_kept()) {
                    return x86::run_avx2(t, k);
                }
            }
            Path::Emulated => {}
        }
    }
    k.run(Emulated)
}

/// Whether this thread's floating-point unit keeps subnormal numbers (neither
/// flush-to-zero nor denormals-are-zero set in MXCSR), as every path's proof assumes.
pub fn subnormals_kept() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        x86::subnormals_kept()
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        true
    }
}

#[cfg(test)]
mod tests;
