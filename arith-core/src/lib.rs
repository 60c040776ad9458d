//! # arith-core: one trait for reliable range arithmetics
//!
//! A *range arithmetic* evaluates a function over sets of inputs instead of single
//! points, and returns an enclosure of every value the function takes there. This crate
//! holds what all of our arithmetics share:
//!
//! - [`Real`]: the operations a model is written with (`+ - * /`, `sqr`, `powi`, `sqrt`,
//!   `recip`, `exp`, `ln`, `sin`, `cos`, `abs`, `min`, `max`). `f64` implements it, so the
//!   same generic model code serves point evaluation and every range arithmetic.
//! - [`Range`]: a [`Real`] that is also a *sound enclosure*: inputs, bounds, the zero test
//!   and the linear part used for argument pruning; inputs built as affine forms of the
//!   input symbols ([`Range::from_affine`], a frustum of rays in depth and pixel
//!   coordinates) and the form's part on the first inputs ([`Range::affine_part`], one
//!   ray's share of a bundle's range).
//! - [`Arithmetic`]: a family naming the shortest form for rays ([`Arithmetic::Ray`], one
//!   input symbol) and the form for 3-D cells ([`Arithmetic::Cell`], three independent
//!   input symbols) and a pack of four ray forms evaluated together
//!   ([`Arithmetic::RayPack`], see [`pack`]).
//! - [`approx`]: the single source of affine approximations `f(x) ∈ alpha*x + zeta ± delta`
//!   of every non-affine function on `[a, b]`, used by all affine arithmetics.
//! - [`round`]: rounding helpers (outward rounding with `next_up`/`next_down`, error-free
//!   transformations), never changing the FPU rounding mode.
//! - [`lanes`] (feature `simd`): eight `f64` lanes with directed rounding through
//!   AVX-512, AVX2 or emulation, chosen once at start-up, for batched kernels.
//! - [`rfunc`]: R-function set operations and the paper's blends, written once.
//! - [`branch`]: comparisons and selections ([`Real::step`], [`Real::select`]), sound
//!   over ranges and carried through dual numbers.
//!
//! ## The soundness contract
//!
//! For every real point of the inputs, the real value of the computed function lies in
//! [`Range::bounds`], after `f64` rounding too. Domain edges never narrow a range or
//! produce NaN bounds: see [`Range`] for the exact rules.
//!
//! ## Example: swapping arithmetics by changing one type
//!
//! ```
//! use arith_core::{Range, Real};
//!
//! /// Mitchell's quartic, written once for points and for every arithmetic.
//! fn mitchell<R: Real>(x: R, y: R, z: R) -> R {
//!     let (x2, y2, z2) = (x.sqr(), y.sqr(), z.sqr());
//!     let yz = y2.clone() + z2.clone();
//!     (x2.clone() + yz.clone()) * 20.0 - (x2.sqr() + yz.sqr()) * 4.0 - x2 * yz * 17.0 - 17.0
//! }
//!
//! fn range_over_box<R: Range>() -> (f64, f64) {
//!     let x = R::input(0, 0.5, 0.6);
//!     let y = R::input(1, -0.1, 0.1);
//!     let z = R::input(2, 0.9, 1.0);
//!     mitchell(x, y, z).bounds()
//! }
//!
//! // Change the type, keep the code: `arith_ia::Interval`, `arith_aa::Aa`,
//! // `arith_raa::Raa<3>`, `arith_revaa::RevAa<3>` all implement `Range`.
//! let (lo, hi) = range_over_box::<arith_revaa::RevAa<3>>();
//! let (ilo, ihi) = range_over_box::<arith_ia::Interval>();
//! // Points use the very same model, and every point value lies in every range:
//! let v = mitchell(0.55_f64, 0.0, 0.95);
//! assert!(lo <= v && v <= hi && ilo <= v && v <= ihi);
//! ```

// `unsafe` is denied everywhere but in `lanes`' x86 module (the AVX-512 intrinsics and
// the target-feature functions), where each use states why it is sound.
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod affine_round;
pub mod approx;
pub mod branch;
pub mod dual;
#[cfg(feature = "simd")]
pub mod lanes;
pub mod pack;
pub mod reduced;
pub mod rfunc;
pub mod round;
#[cfg(feature = "simd")]
pub mod simd;
#[cfg(feature = "testkit")]
pub mod testkit;

mod real;
pub use real::{AffinePart, Arithmetic, Known, Linear, Range, Real};
