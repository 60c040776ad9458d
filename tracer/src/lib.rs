//! # tracer: reliable ray casting of implicit surfaces, generic over [`arith_core::Range`]
//!
//! Layers, every import pointing down:
//! - [`arith`]: the one list of arithmetics every command, test and bench iterates over;
//! - [`shape`] and [`camera`]: the [`shape::Shape`] trait (a function written once,
//!   generic over [`arith_core::Real`]), boxes, views and rays;
//! - [`models`]: the model sources (the papers' models, formulas) and their one registry;
//! - [`search`]: Algorithm 1 ([`search::ray`]), Algorithm 2 ([`search::cull`]), the
//!   Lipschitz casters ([`search::lipschitz`]) and Lipschitz cone tracing
//!   ([`search::cone`]);
//! - renderers: the reliable tracer ([`render`], with shading and output files) and the
//!   progressive previewer ([`progressive`], a queue of cones);
//! - the `tracer` binary (feature `cli`) on top; [`interrupt`] stops long work on Ctrl-C.

#![forbid(unsafe_code)]

pub mod arith;
pub use arith::{arith_aa, arith_core, arith_ia, arith_raa, arith_revaa};
pub use glam;
pub mod camera;
#[cfg(feature = "cli")]
pub mod cli;
pub mod interrupt;
pub mod lipschitz_bound;
pub mod models;
pub mod progressive;
pub mod render;
pub mod search;
pub mod shape;

/// `println!` for the binaries: ends the process quietly when stdout has been closed
/// (`tracer list | head -3`: the reader wanted no more) instead of panicking, and with
/// exit code 2 and a message on any other write error.
#[macro_export]
macro_rules! out {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($t)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
            eprintln!("error: cannot write to stdout: {e}");
            std::process::exit(2);
        }
    }};
}
