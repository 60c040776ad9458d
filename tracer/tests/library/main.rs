//! The library's integration tests, one binary: each module holds one concern's tests
//! (ground truth, culling invariance, models rendered, ...). Linked once, the renderer's
//! instances for every arithmetic and shape are compiled once rather than per file.

mod auto_arith;
mod culling_invariance;
mod ground_truth;
mod hyperfun;
mod model_files;
mod progressive_engine;
mod render_api;
mod slab_search;
mod specialise;
