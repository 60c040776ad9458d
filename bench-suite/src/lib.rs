//! # bench-suite: the paper's Table 1 and the measurements past it
//!
//! - [`counter`]: operation counting over the real model code.
//! - [`paper`]: the paper's Table 1, to print beside ours.
//! - [`chart`]: the log-scale bar chart.
//! - [`tightness`]: computed range width over sampled true width.
//! - [`rng`]: a small reproducible generator for sampling.
pub mod chart;
pub mod counter;
pub mod paper;
pub mod rng;
pub mod tightness;
