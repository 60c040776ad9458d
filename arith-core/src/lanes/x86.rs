//! The one place of the crate with `unsafe` code: the AVX-512 path's intrinsics, the
//! functions compiled with a path's target features that run a [`Kernel`] there, and
//! the read of MXCSR.
//!
//! Every `unsafe` here has the same justification: an intrinsic or a target-feature
//! function may only run where the processor has the feature. [`Avx512`] and [`Avx2`]
//! values are built only by their `detect`, after `is_x86_feature_detected!` said yes,
//! so holding a token proves the features, and every unsafe call takes one.
#![allow(unsafe_code)]

use super::{Avx2, F64x8, Isa, Kernel, Path};
use core::arch::x86_64::*;

/// The AVX-512 path's token: exists only where the processor has AVX-512F (and the
/// AVX2 and FMA its kernels also use).
#[derive(Clone, Copy, Debug)]
pub struct Avx512(());

impl Avx512 {
    /// The token, where this processor has AVX-512F, AVX2 and FMA.
    pub fn detect() -> Option<Avx512> {
        let ok = std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma");
        ok.then_some(Avx512(()))
    }
}

/// Runs `k` on the AVX-512 path, compiled with its target features.
#[inline]
pub(super) fn run_avx512<K: Kernel>(t: Avx512, k: K) -> K::Output {
    #[target_feature(enable = "avx512f,avx2,fma")]
    fn inner<K: Kernel>(t: Avx512, k: K) -> K::Output {
        k.run(t)
    }
    // SAFETY: the token proves AVX-512F, AVX2 and FMA (see `Avx512::detect`).
    unsafe { inner(t, k) }
}

/// Runs `k` on the AVX2 path, compiled with its target features (the workspace's
/// baseline has them already; other builds get them here).
#[inline]
pub(super) fn run_avx2<K: Kernel>(t: Avx2, k: K) -> K::Output {
    #[target_feature(enable = "avx2,fma")]
    fn inner<K: Kernel>(t: Avx2, k: K) -> K::Output {
        k.run(t)
    }
    // SAFETY: the token proves AVX2 and FMA (see `Avx2::detect`).
    unsafe { inner(t, k) }
}

/// MXCSR's flush-to-zero (bit 15) and denormals-are-zero (bit 6) flags.
const FTZ_DAZ: u32 = (1 << 15) | (1 << 6);

/// Whether neither flush-to-zero nor denormals-are-zero is set on this thread.
pub(super) fn subnormals_kept() -> bool {
    // SAFETY: SSE is part of x86-64; reading MXCSR changes nothing.
    #[allow(deprecated)]
    let csr = unsafe { _mm_getcsr() };
    csr & FTZ_DAZ == 0
}

const UP: i32 = _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC;
const DOWN: i32 = _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC;

// SAFETY (every method below): `self` is an `Avx512` token, so the processor has
// AVX-512F; the loads and stores are of an `F64x8`, 64-byte aligned and 64 bytes long.
impl Isa for Avx512 {
    type V = __m512d;
    type M = __mmask8;
    const PATH: Path = Path::Avx512;

    #[inline(always)]
    fn load(self, x: &F64x8) -> __m512d {
        unsafe { _mm512_load_pd(x.0.as_ptr()) }
    }
    #[inline(always)]
    fn store(self, v: __m512d) -> F64x8 {
        let mut out = F64x8::default();
        unsafe { _mm512_store_pd(out.0.as_mut_ptr(), v) };
        out
    }
    #[inline(always)]
    fn splat(self, c: f64) -> __m512d {
        unsafe { _mm512_set1_pd(c) }
    }
    #[inline(always)]
    fn add(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_add_pd(a, b) }
    }
    #[inline(always)]
    fn sub(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_sub_pd(a, b) }
    }
    #[inline(always)]
    fn mul(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_mul_pd(a, b) }
    }
    #[inline(always)]
    fn div(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_div_pd(a, b) }
    }
    #[inline(always)]
    fn sqrt(self, a: __m512d) -> __m512d {
        unsafe { _mm512_sqrt_pd(a) }
    }
    #[inline(always)]
    fn fma(self, a: __m512d, b: __m512d, c: __m512d) -> __m512d {
        unsafe { _mm512_fmadd_pd(a, b, c) }
    }
    #[inline(always)]
    fn neg(self, a: __m512d) -> __m512d {
        unsafe {
            let sign = _mm512_set1_epi64(i64::MIN);
            _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(a), sign))
        }
    }
    #[inline(always)]
    fn abs(self, a: __m512d) -> __m512d {
        unsafe { _mm512_abs_pd(a) }
    }
    #[inline(always)]
    fn or_bits(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe {
            let (a, b) = (_mm512_castpd_si512(a), _mm512_castpd_si512(b));
            _mm512_castsi512_pd(_mm512_or_si512(a, b))
        }
    }
    #[inline(always)]
    fn and_bits(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe {
            let (a, b) = (_mm512_castpd_si512(a), _mm512_castpd_si512(b));
            _mm512_castsi512_pd(_mm512_and_si512(a, b))
        }
    }
    #[inline(always)]
    fn min(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_min_pd(a, b) }
    }
    #[inline(always)]
    fn max(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_max_pd(a, b) }
    }
    #[inline(always)]
    fn lt(self, a: __m512d, b: __m512d) -> __mmask8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_LT_OQ>(a, b) }
    }
    #[inline(always)]
    fn le(self, a: __m512d, b: __m512d) -> __mmask8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_LE_OQ>(a, b) }
    }
    #[inline(always)]
    fn eq(self, a: __m512d, b: __m512d) -> __mmask8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(a, b) }
    }
    #[inline(always)]
    fn unord(self, a: __m512d, b: __m512d) -> __mmask8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_UNORD_Q>(a, b) }
    }
    #[inline(always)]
    fn select(self, m: __mmask8, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_mask_blend_pd(m, b, a) }
    }
    #[inline(always)]
    fn and(self, a: __mmask8, b: __mmask8) -> __mmask8 {
        a & b
    }
    #[inline(always)]
    fn or(self, a: __mmask8, b: __mmask8) -> __mmask8 {
        a | b
    }
    #[inline(always)]
    fn not(self, a: __mmask8) -> __mmask8 {
        !a
    }
    #[inline(always)]
    fn bits(self, m: __mmask8) -> u8 {
        m
    }
    #[inline(always)]
    fn scale_pow2(self, a: __m512d, k: __m512d) -> __m512d {
        unsafe { _mm512_scalef_pd(a, k) }
    }
    #[inline(always)]
    fn split_pow2(self, x: __m512d) -> (__m512d, __m512d) {
        unsafe {
            // The significand in [0.75, 1.5) and floor(log2(x)); a significand below 1
            // is the bits' one halved, so its exponent is one more.
            let m = _mm512_getmant_pd::<_MM_MANT_NORM_P75_1P5, _MM_MANT_SIGN_SRC>(x);
            let e = _mm512_getexp_pd(x);
            let below = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(m, _mm512_set1_pd(1.0));
            let e = _mm512_mask_add_pd(e, below, e, _mm512_set1_pd(1.0));
            (m, e)
        }
    }
    #[inline(always)]
    fn add_up_raw(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_add_round_pd::<UP>(a, b) }
    }
    #[inline(always)]
    fn add_down_raw(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_add_round_pd::<DOWN>(a, b) }
    }
    #[inline(always)]
    fn sub_up_raw(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_sub_round_pd::<UP>(a, b) }
    }
    #[inline(always)]
    fn sub_down_raw(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_sub_round_pd::<DOWN>(a, b) }
    }
    #[inline(always)]
    fn mul_up_raw(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_mul_round_pd::<UP>(a, b) }
    }
    #[inline(always)]
    fn mul_down_raw(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_mul_round_pd::<DOWN>(a, b) }
    }
    #[inline(always)]
    fn div_up_raw(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_div_round_pd::<UP>(a, b) }
    }
    #[inline(always)]
    fn div_down_raw(self, a: __m512d, b: __m512d) -> __m512d {
        unsafe { _mm512_div_round_pd::<DOWN>(a, b) }
    }
    #[inline(always)]
    fn sqrt_up_raw(self, a: __m512d) -> __m512d {
        unsafe { _mm512_sqrt_round_pd::<UP>(a) }
    }
    #[inline(always)]
    fn sqrt_down_raw(self, a: __m512d) -> __m512d {
        unsafe { _mm512_sqrt_round_pd::<DOWN>(a) }
    }
}
