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
//!   previewer's baseline and reference.
//!
//! Only [`engine`] is a public module; the others' items are re-exported here (a
//! public `image` module would shadow the `image` crate in `use tracer::progressive::*`).
//!
//! The live window and the `tracer preview` command are in `tracer-cli`; the benchmark
//! rows of the paper's Table 1 and Fig. 9 in `bench-suite`.

pub mod engine;
mod image;
mod plan;
mod raycast;

pub use engine::{
    auto_bound, Bound, ChildStart, Engine, Options, Rect, Stats, Step, DEFAULT_BOUND,
};
pub use image::{pack, write_png, SharedImage};
pub use plan::{prime_factors_desc, Plan};
pub use raycast::{raycast, Caster};
