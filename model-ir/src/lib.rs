//! # model-ir: the one instruction set of reliable implicit-surface rendering
//!
//! A model `f(x, y, z)` (FRep: `f >= 0` inside, `f = 0` on the surface) as a **tape**:
//! a flat list of SSA instructions ([`Instr`], [`Op`]), the last one's register the
//! function's value. Every model source compiles into it (the formula, HyperFun and `.vm`
//! readers of `model-sources` through the [`Builder`]; generic Rust models by being evaluated
//! over a [`Recorder`]), and every evaluator runs it: the interpreter here, over any
//! [`arith_core::Real`] (points, every range arithmetic, dual numbers), and the GPU's
//! generated WGSL (`tracer-gpu`). Nothing above this crate defines an instruction.
//!
//! Layers, every import pointing down:
//! - [`instr`]: the instruction set;
//! - [`fold`]: exact constant folding and the builder's operators ([`Bin`]);
//! - [`builder`]: the hash-consing [`Builder`] and dead-code removal;
//! - [`eval`] (private): the interpreter, behind [`Tape::eval`];
//! - [`specialise`]'s rules, then [`tape`] ([`Tape`]) and region specialisation
//!   ([`Tape::specialise`], with its [proofs](specialise::proofs));
//! - [`batch`] ([`Tape::eval_batch`]: one tape over many inputs per call);
//! - [`record`] ([`Tape::record`]) and [`fuse`] ([`Tape::fuse_rfunctions`]).
//!
//! and, beside the tape, what every consumer of a model shares:
//! - [`arith`]: the one list of arithmetics ([`arith::ArithKind`], [`with_arith!`]) that
//!   every command, test and benchmark iterates over;
//! - [`shape`]: the [`shape::Shape`] trait (a function written once over
//!   [`arith_core::Real`]), its box ([`shape::Aabb`]) and a camera placement
//!   ([`shape::View`]); [`tape_shape`]: the tape as a shape;
//! - [`shape_batch`]: the ranges of many inputs of one shape per call, for the drivers
//!   that run many searches in lock-step;
//! - [`gradient_bound`]: Lipschitz bounds of a shape from the range of its gradient;
//! - [`camera`]: views and the pixel rays of pinhole and orthographic cameras.
//!
//! ## Example: a model recorded, evaluated and specialised
//!
//! ```
//! use arith_core::{Range, Real};
//! use arith_ia::Interval;
//! use model_ir::Tape;
//!
//! /// Four balls in a row, united by `max`.
//! fn balls<R: Real>(x: R, y: R, z: R) -> R {
//!     let ball = |cx: f64| ((x.clone() - cx).sqr() + y.sqr() + z.sqr()).rsub(0.25);
//!     ball(0.0).max(&ball(2.0)).max(&ball(4.0).max(&ball(6.0)))
//! }
//! let t = Tape::record(balls);
//! assert_eq!(t.eval(0.1_f64, 0.2, 0.3), balls(0.1_f64, 0.2, 0.3));
//! // Around the first ball only the first ball decides the sign.
//! let i = |lo, hi| Interval::from_interval(lo, hi);
//! let s = t.specialise(&[[i(-0.6, 0.6), i(-0.6, 0.6), i(-0.6, 0.6)]]).unwrap();
//! assert!(s.len() * 3 < t.len());
//! assert_eq!(s.eval(0.1_f64, 0.2, 0.3), t.eval(0.1_f64, 0.2, 0.3));
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod arith;
pub mod batch;
pub mod builder;
pub mod camera;
mod eval;
pub mod fold;
pub mod fuse;
pub mod gradient_bound;
pub mod instr;
pub mod record;
pub mod shape;
pub mod shape_batch;
pub mod specialise;
pub mod tape;
pub mod tape_shape;

pub use arith_core;
pub use builder::{Builder, Val};
pub use fold::{Bin, EPS};
pub use glam;
pub use instr::{Instr, Op};
pub use record::Recorder;
pub use specialise::{Trace, CACHE_LIMIT, MIN_SPECIALISE_LEN};
pub use tape::Tape;
