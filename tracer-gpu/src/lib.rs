//! Sound reliable ray casting of implicit surfaces on the GPU (the revised-affine
//! paper's Section 5.3): wgpu compute shaders generated per model ([`codegen`]) that
//! search every pixel's ray for its first root in `f32` interval arithmetic (IA),
//! reduced affine arithmetic (RAA*) or revised affine arithmetic (RevAA) on the ray form
//! (one input symbol), with argument pruning, the coarse-grid cell culling of 5.3.2 as
//! a compute pass, normals and depths ([`engine`]). The model comes as a tape of the
//! model IR ([`Tape`]: the tracer's formulas compile into one, its generic models are
//! recorded into one); the host prepares the rays in `f64`
//! ([`Frame`]) and the crate rounds them outward to `f32` ([`convert`]). [`render`] is
//! the renderer on top: a model's rays and cells prepared exactly as the CPU tracer's,
//! the hits shaded as its are, a [`tracer::render::RenderResult`] out
//! (`tracer render --device gpu`).
//!
//! # Soundness in `f32` on a GPU
//!
//! The claim: for every ray of a pixel's [`Bundle`] (the `f64` ray the CPU tracer
//! searches included), a root of `f` in the searched range is never reported as a miss.
//! It rests on every range being an enclosure after `f32` rounding, which WGSL makes
//! harder than IEEE 754 (WGSL §15.7, "Floating Point Evaluation"):
//!
//! - **No rounding mode.** `+ - *` are "correctly rounded", which WGSL defines as
//!   either representable neighbour of the exact result (faithful rounding, at most one
//!   ulp off). The shaders never rely on round-to-nearest: every bound is the computed
//!   value stepped outward by whole representable steps, by integer arithmetic on its
//!   bits (`bitcast`, `step_up` / `step_dn` in `wgsl/round.wgsl`).
//! - **Looser built-ins** (§15.7.4.1, f32): `x / y` 2.5 ULP for `|y|` in
//!   `[2^-126, 2^126]`; `inverseSqrt` 2 ULP and `sqrt` "inherited from
//!   `1.0 / inverseSqrt(x)`"; `exp` `3 + 2|x|` ULP; `log` absolute error `2^-21` on
//!   `[0.5, 2]`, 3 ULP elsewhere; `sin`, `cos` absolute error `2^-11` on `[-pi, pi]`
//!   only (undefined outside). A result `k` ULP off the exact value is at most `2k`
//!   representable steps away (the spacing halves at most once within a few ulps), so:
//!   `+ - *` step 1; `1 / y` steps 6 (used only for `2^-60 <= |y| < 2^60`); `sqrt`
//!   steps 12 (`(1 + 2u)(1 + 2.5u)` is 4.5 ULP; arguments below `2^-100` are bounded by
//!   `[0, 2^-50]` instead); `exp(v)` steps `2(3 + 2|v|) + 2` (for `-80 <= v <= 41`;
//!   below, `[0, 2^-115]`; above, unbounded); `log(v)` steps the result by `2^-21` and
//!   then one on `[0.5, 2]`, 7 steps elsewhere (only for `v >= 2^-60`); `sin` and `cos`
//!   reduce the argument by `k pi` in interval arithmetic (`pi` between two `f32`
//!   neighbours; `sin(x) = (-1)^k sin(x - k pi)`), use the built-in only when the
//!   reduced interval lies in `[-pi, pi]` (else `[-1, 1]`), widen by `2^-11` and one
//!   step, and take the extremes `+-1` when the interval may hold `+-pi/2`. `abs`,
//!   `min`, `max`, negation and comparisons are exact.
//! - **Flushed subnormals.** "Any inputs or outputs" of these operations may be
//!   flushed to zero. No stored bound is subnormal: stepping a value below `2^-124` in
//!   magnitude gives `+-2^-124` (outward), so no operation reads a subnormal; an output
//!   flushed from a subnormal exact value is within `2^-126` of the truth, which is
//!   covered by the same snap for bounds and by the absolute term `2^-125` of `rerr`
//!   for affine centres and coefficients.
//! - **Reassociation and fusion** are allowed ("An implementation may reassociate
//!   operations. An implementation may fuse operations if the transformed expression is
//!   at least as accurate as the original", §15.7.5), and SPIR-V from naga carries no
//!   `NoContraction`. Fusion only removes roundings, so it can only tighten the error
//!   each bound accounts for. Reassociation could change what a stored value is, so no
//!   rounded value that a bound depends on is left as an open expression: interval
//!   bounds pass through `step_up`/`step_dn` (integer operations on the bits, opaque to
//!   floating-point rewriting), and every affine centre and coefficient passes through
//!   `opq`, which ors its bits with a uniform zero the compiler cannot see. Each float
//!   operation is therefore evaluated on its own, on the operands the bound was
//!   computed from.
//! - **Finite math assumption**: implementations may assume no overflow, infinity or
//!   NaN. None is ever produced: magnitudes at or above `LIM = 2^60` mean "unbounded"
//!   (the whole line, stored as `2^100`), every operation checks its operands first,
//!   and products of values below `2^60` stay below `2^120`.
//!
//! Each affine form `c + t eps +- e` absorbs its own rounding: every operation adds to
//! `e` a bound `rerr` (`|v| 2^-22 + 2^-125`, rounded up) of the error of each rounded
//! centre and coefficient it computes, and sums `e` with upward steps. Non-affine unary
//! operations use min-range approximations `alpha x + zeta +- delta`, with `alpha`
//! rounded so that `f - alpha x` stays monotone on the operand's range and its
//! end values bounded by the outward built-ins above; `sin`, `cos`, `abs` across 0 and
//! overlapping `min`/`max` become intervals (`alpha = 0`). RAA* and RevAA differ only in
//! their product, as on the CPU (`arith-raa`, `arith-revaa`). The host's `f64` inputs
//! (ray origins, directions, segment ends, constants) are enclosed outward
//! ([`convert`]): each origin and direction as an `f32` midpoint and a radius rounded
//! up, so the bundle holds the `f64` ray exactly. Every job carries its own origin, so
//! a pinhole's rays (one eye) and an orthographic view's (parallel rays from the image
//! plane; a culling cell is then a box of origins with one direction) run alike.
//!
//! The R-functions are single operations ([`model_ir::Op::Union`],
//! [`model_ir::Op::Intersect`], fused by [`codegen::lower`]): written
//! out, `a + b + sqrt(a^2 + b^2)` with `a` small and `b` far below zero (a union with a
//! distant part of a scene) cancels to the rounding of `b`'s size, which in `f32` is
//! larger than any value near the surface, and no pixel could be confirmed. With
//! `m < 0` the smaller operand and `o` the other, `m + sqrt(o^2 + m^2) = o^2 / (h - m)`
//! with `h - m >= -m > 0`, so the union is `o + o^2 / (h - m)`, free of cancellation;
//! the intersection is `-union(-a, -b)`. IA evaluates it at the two corners of the
//! operands' box (the union is nondecreasing in both operands, since
//! `1 + a / sqrt(a^2 + b^2) >= 0`), each corner in outward-rounded IA; the affine forms
//! use the rewritten form where `m` is proved negative and at least as large in
//! magnitude as `o`, and the written-out one elsewhere (both are compositions of sound
//! operations).
//!
//! **Far from the origin** the `f32` ranges get wide: a segment then stops being split
//! when its midpoint no longer lies strictly inside it, and the pixel is reported as
//! [`Status::Unconfirmed`] (a hit that may be spurious), never as a miss; coordinates at
//! or beyond `2^60` are unbounded and every pixel whose ray reaches them is unconfirmed.
//! A hit is [`Status::Hit`] only when the ranges at the two ends of a segment within the
//! precision have opposite signs for every ray of the bundle.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod codegen;
pub mod convert;
pub mod engine;
pub mod render;

pub use engine::{Bundle, Cells, Frame, Gpu, Output, Prepared, Status, Tracer};
pub use model_ir::Tape;

/// The arithmetics the GPU evaluates in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum GpuArith {
    /// Interval arithmetic.
    Ia,
    /// Reduced affine arithmetic extended to non-affine operations (AF1's product).
    Raa,
    /// Revised affine arithmetic.
    RevAa,
}

impl GpuArith {
    /// Every GPU arithmetic, in the paper's Table 2 order.
    pub const ALL: [GpuArith; 3] = [GpuArith::Ia, GpuArith::Raa, GpuArith::RevAa];

    /// The name the tracer's `--arith` uses (`ia`, `raa`, `revaa`).
    pub fn name(self) -> &'static str {
        match self {
            GpuArith::Ia => "ia",
            GpuArith::Raa => "raa",
            GpuArith::RevAa => "revaa",
        }
    }

    /// The arithmetic named `name`; `None` for others (affine arithmetic with one symbol
    /// per operation has no fixed-size GPU form).
    pub fn from_name(name: &str) -> Option<GpuArith> {
        GpuArith::ALL.into_iter().find(|a| a.name() == name)
    }
}
