//! # bench-suite: the paper's Table 1 and the measurements past it
//!
//! - [`counter`]: operation counting over the real model code.
pub mod counter;
