//! # bench-suite: the paper's Table 1 and the measurements past it
//!
//! - [`counter`]: operation counting over the real model code.
//! - [`paper`]: the paper's Table 1, to print beside ours.
//! - [`chart`]: the log-scale bar chart.
//! - [`rng`]: a small reproducible generator for sampling.
pub mod chart;
pub mod counter;
pub mod paper;
pub mod rng;
