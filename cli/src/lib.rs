//! # tracer-cli: the `tracer` command
//!
//! One module per command, each with its arguments and its run: [`render`], [`range`],
//! [`list`], [`preview`] (its arguments in [`preview_args`], its live window in
//! [`preview_window`]), [`view`] (the GPU
//! renderer's live window), [`mesh`] and [`manual`] (shell completions, the manual
//! page). Below them: the flags the commands share ([`args`]), the progress bar
//! ([`bar`]) and the `--stats json` objects ([`stats_json`]). The binary's `main` parses
//! the command line and dispatches.
//!
//! User errors are one line on stderr and exit code 2; Ctrl-C stops `render`, `preview`
//! and `mesh` early with exit code 130 (what was computed is written where the command
//! says so).

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod args;
pub mod bar;
pub mod list;
pub mod manual;
pub mod mesh;
pub mod preview;
pub mod preview_args;
pub mod preview_window;
pub mod range;
pub mod render;
pub mod stats_json;
pub mod view;
