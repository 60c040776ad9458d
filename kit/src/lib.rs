//! # tracer-kit: what the renderers and the mesher share, below them all
//!
//! - [`output`]: PNG images and depth maps (NumPy `.npy`, OpenEXR), with the checks a
//!   command runs on its output paths before long work;
//! - [`bspline_filter`]: anti-aliasing by uniform B-spline filters over constant-colour
//!   samples (the previewer's samples, a render made at a multiple of its resolution);
//! - [`progress`]: progress reporting ([`progress::Progress`], told units of work as
//!   they finish) and a [`progress::Ticker`] for work whose total grows as it goes;
//! - [`interrupt`]: Ctrl-C and SIGTERM as a cancel flag long work polls;
//! - [`stdout`]: the binaries' lines on standard output ([`out!`], [`say!`]), which a
//!   closed pipe does not turn into a panic.
//!
//! Nothing here knows shapes, arithmetics or rays.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod bspline_filter;
pub mod interrupt;
pub mod output;
pub mod progress;
pub mod stdout;
