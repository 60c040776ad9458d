//! # bench-suite: the paper's Table 1 and the measurements past it
//!
//! - [`counter`]: operation counting over the real model code.
//! - [`paper`]: the paper's Table 1, to print beside ours.
//! - [`chart`]: the log-scale bar chart.
//! - [`table1`]: the paper's Table 1 regenerated.
//! - [`tightness`]: computed range width over sampled true width.
//! - [`gm_table1`]: the progressive-refinement paper's Table 1 and Fig. 9, over the
//!   previewer's benchmark rows ([`gm_rows`]).
//! - [`formulas`]: random formulas over random boxes, each arithmetic against intervals
//!   and revised affine forms.
//! - [`kernel`]: the cost of one tape instruction per lane of batched evaluation, by
//!   arithmetic and lane path (AVX-512, AVX2, emulated).
//! - [`gm_study`]: why our Mitchell counts differ from the paper's, one factor at a time.
//! - [`fig10`]: that paper's Fig. 10, a landscape refined with a region of interest.
//! - [`scaling`]: cost as the resolution doubles, with and without culling.
//! - [`scenes`]: cost as the model grows (scenes of N balls), with and without region
//!   specialisation.
//! - [`rng`]: a small reproducible generator for sampling.

#![forbid(unsafe_code)]
#![warn(missing_docs)]
pub mod chart;
pub mod counter;
pub mod fig10;
pub mod formulas;
pub mod gm_rows;
pub mod gm_study;
pub mod gm_table1;
pub mod kernel;
pub mod paper;
pub mod scaling;
pub mod scenes;
pub mod table1;
#[cfg(feature = "gpu")]
pub mod table2;
pub mod tightness;
