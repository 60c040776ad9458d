//! The library's integration tests, one binary: each module holds one concern's tests
//! (ground truth, culling invariance, model files, ...). Linked once, the renderer's
//! instances for every arithmetic and shape are compiled once rather than per file.

mod auto_arith;
mod culling_invariance;
mod expr;
mod ground_truth;
mod hyperfun;
mod mesh;
mod mesh_features;
mod model_files;
mod progressive_engine;
mod progressive_noise;
mod render_api;
mod specialise;
