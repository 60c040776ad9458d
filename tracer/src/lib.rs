//! # tracer: reliable ray casting of implicit surfaces, generic over [`arith_core::Range`]
//!
//! Layers, every import pointing down:
//! - [`arith`]: the one list of arithmetics every command, test and bench iterates over;
//! - [`shape`] and [`camera`]: the [`shape::Shape`] trait (a function written once,
//!   generic over [`arith_core::Real`]), boxes, views and rays;
//! - [`models`]: the model sources (the papers' models; the formula, HyperFun and `.vm`
//!   readers, which compile into tapes of the model IR, [`model_ir`]) and their one
//!   registry;
//! - [`search`]: Algorithm 1 ([`search::ray`]), Algorithm 2 ([`search::cull`]), the
//!   Lipschitz casters ([`search::lipschitz`]) and Lipschitz cone tracing
//!   ([`search::cone`]);
//! - renderers: the reliable tracer ([`render`], with shading and output files) and the
//!   progressive previewer ([`progressive`], a queue of cones); the mesher ([`mesh`]:
//!   an octree pruned by range arithmetic, dual contouring, OBJ/PLY/STL files);
//! - the `tracer` binary (feature `cli`) on top; [`interrupt`] stops long work on Ctrl-C.
//!
//! ## Example: render a model of your own
//!
//! A shape is a function written once over [`arith_core::Real`]; the renderer takes it
//! with the arithmetic chosen at run time ([`arith::ArithKind`]) and never misses a
//! root: every pixel whose ray meets the surface is reported as a hit.
//!
//! ```
//! use tracer::arith::ArithKind;
//! use tracer::arith_core::Real;
//! use tracer::glam::DVec3;
//! use tracer::render::{render_kind, RenderOptions};
//! use tracer::shape::{Aabb, Shape, View};
//!
//! /// A torus of radii 1 and 0.3 around the y axis (`f >= 0` inside).
//! struct Torus;
//! impl Shape for Torus {
//!     fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
//!         let ring = (x.sqr() + z.sqr()).sqrt().rsub(1.0);
//!         (ring.sqr() + y.sqr()).rsub(0.09)
//!     }
//! }
//!
//! let view = View {
//!     eye: DVec3::new(0.0, 2.5, 2.5),
//!     look_at: DVec3::ZERO,
//!     up: DVec3::Y,
//!     fov_deg: 45.0,
//!     ortho: None,
//! };
//! let opts = RenderOptions::for_view(view, Aabb::cube(1.5), 64, 48);
//! let image = render_kind(ArithKind::Revaa, &Torus, &opts)?;
//! assert_eq!(image.rgb.len(), 64 * 48 * 3);
//! // Depth from the eye per pixel, +inf where the ray misses.
//! let hits = image.depth.iter().filter(|d| d.is_finite()).count();
//! assert!(hits > 0);
//! let png = std::env::temp_dir().join("tracer-doc-torus.png");
//! tracer::render::output::write_png(&png, 64, 48, &image.rgb)?;
//! # Ok::<(), String>(())
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod arith;
pub use arith::arith_core;
/// The crates of the one list of arithmetics, at the crate root too (`tracer::arith_ia`).
macro_rules! reexport_arith_crates {
    ([ $($krate:ident),* ]) => {
        $(
            #[doc(no_inline)]
            pub use arith::$krate;
        )*
    };
}
arith_list!(@crates [reexport_arith_crates]);
pub use glam;
pub use model_ir;
pub mod camera;
#[cfg(feature = "cli")]
pub mod cli;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod interrupt;
pub mod lipschitz_bound;
pub mod mesh;
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

/// Set once [`say!`] has met a write error: the process's progress lines stop.
#[doc(hidden)]
pub static SAY_SILENT: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// `println!` for progress lines of long work (the previewer's levels): a closed stdout
/// (`tracer preview ... | head -1`) only stops the lines, the work goes on and writes
/// its files; another write error is reported once on stderr, then the lines stop too.
#[macro_export]
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let silent = &$crate::SAY_SILENT;
        if !silent.load(std::sync::atomic::Ordering::Relaxed) {
            if let Err(e) = writeln!(std::io::stdout(), $($t)*) {
                silent.store(true, std::sync::atomic::Ordering::Relaxed);
                if e.kind() != std::io::ErrorKind::BrokenPipe {
                    eprintln!("warning: cannot write to stdout: {e}; going on without progress lines");
                }
            }
        }
    }};
}
