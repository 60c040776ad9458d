//! # bench-suite: the paper's Table 1 and the measurements past it
//!
//! - [`counter`]: operation counting over the real model code.
//! - [`paper`]: the paper's Table 1, to print beside ours.
//! - [`chart`]: the log-scale bar chart.
//! - [`table1`]: the paper's Table 1 regenerated.
//! - [`tightness`]: computed range width over sampled true width.
//! - [`progressive`]: the progressive-refinement paper's Table 1 and Fig. 9.
//! - [`scaling`]: cost as the resolution doubles, with and without culling.
//! - [`rng`]: a small reproducible generator for sampling.

#![forbid(unsafe_code)]
#![warn(missing_docs)]
pub mod chart;
pub mod counter;
pub mod paper;
pub mod progressive;
pub mod scaling;
pub mod table1;
#[cfg(feature = "gpu")]
pub mod table2;
pub mod tightness;
