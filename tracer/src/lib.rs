//! # tracer: reliable ray casting of implicit surfaces, generic over [`arith_core::Range`]
//!
//! Layers (shape → evaluator → renderer):
//! - [`shape`]: the [`shape::Shape`] trait (a function written once, generic over
//!   [`arith_core::Real`]) and [`shape::Model`] (a shape with its domain box and view).
//! - [`models`]: the paper's Appendix A models; [`gm_models`]: the progressive-refinement
//!   paper's models; [`expr`]: formulas parsed from text into a tape.
//! - [`arith`]: the one list of arithmetics the CLI, the tests and the benches iterate over.
//! - [`camera`], [`ray`] (Algorithm 1), [`cull`] (Algorithm 2), [`shade`], [`render`],
//!   [`output`] (PNG, depth as NPY/EXR).
//! - [`lipschitz`], [`progressive`], [`noise`]: the second paper's Lipschitz ray casters,
//!   cone tracing and progressive refinement previewer.

pub mod arith;
pub mod camera;
pub mod cull;
pub mod expr;
pub mod gm_models;
pub mod interrupt;
pub mod lipschitz;
pub mod models;
pub mod noise;
pub mod output;
pub mod progressive;
pub mod ray;
pub mod render;
pub mod shade;
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
