//! Progressive refinement previewer (Gamito and Maddock 2007): Lipschitz cone tracing
//! over a queue of square image samples, subdivided by the prime factors of the image
//! size, finished per pixel by the overshooting Lipschitz ray caster, with regions of
//! interest, a live window and a headless mode.
//!
//! - [`engine`]: the renderer ([`Engine`]): the sample queue, child cones, regions of
//!   interest; the cones themselves are traced by [`crate::search::cone`];
//! - `plan.rs`: the prime-factor subdivision of eq. (7) ([`Plan`]);
//! - `image.rs`: the lock-free image buffer shared with the display ([`SharedImage`]);
//! - `raycast.rs`: the conventional ray casters over a whole image ([`raycast`]), the
//!   previewer's baseline and reference;
//! - `bench.rs`: the benchmark rows of the paper's Table 1 and Fig. 9 ([`bench_table`]).
//!
//! Only [`engine`] is a public module; the others' items are re-exported here (a
//! public `image` module would shadow the `image` crate in `use tracer::progressive::*`).
//!
//! The live window and the `tracer preview` command are in `crate::cli` (feature `cli`).

mod bench;
pub mod engine;
mod image;
mod plan;
mod raycast;

pub use bench::{bench_methods, bench_rounds, bench_table, previewer_method, BenchRow, Method};
pub use engine::{
    auto_bound, Bound, ChildStart, Engine, Options, Rect, Stats, Step, DEFAULT_BOUND,
};
#[cfg(all(feature = "cli", feature = "gpu"))]
pub(crate) use image::pack;
pub use image::{write_png, SharedImage};
pub use plan::{prime_factors_desc, Plan};
pub use raycast::{raycast, Caster};
