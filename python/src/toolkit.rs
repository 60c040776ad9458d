//! The one place where the module names the toolkit's Rust crates: every other file
//! imports from here, so a move of the libraries' modules is a change of this file
//! alone. Only the libraries' public API is used.

pub use tracer::arith::ArithKind;
pub use tracer::arith_core::{Arithmetic, Range, Real};
pub use tracer::glam::DVec3;
pub use tracer::shape::{check_domain, Aabb, Shape, View};
pub use tracer::with_arith;

/// The arithmetics' own types, one Python number type each.
pub mod forms {
    pub use tracer::arith_aa::Aa;
    pub use tracer::arith_hull::Hull;
    pub use tracer::arith_ia::Interval;
    pub use tracer::arith_raa::Raa;
    pub use tracer::arith_revaa::RevAa;
}

/// Model sources: the registry, the file formats and their readers.
pub mod models {
    pub use tracer::model_sources::formula::parse as parse_formula;
    pub use tracer::model_sources::hyperfun::parse_hyperfun;
    pub use tracer::model_sources::vm::parse as parse_vm;
    pub use tracer::model_sources::{
        builtin_names, find, format, format_of, from_text, AnyShape, Model, FORMATS,
    };
}

/// Cameras: checks, framing, orbit and zoom.
pub mod camera {
    pub use tracer::camera::{check_size, frame_box, orbit, zoom, Camera, MAX_SIDE};
}

/// The reliable tracer.
pub mod render {
    pub use tracer::render::auto_arith::render_auto;
    pub use tracer::render::downsample::downsample_render;
    pub use tracer::render::{render_kind, RenderOptions, RenderResult, RenderStats, Search};
    pub use tracer::tracer_kit::bspline_filter::{Filter, Kernel};
    pub use tracer::tracer_kit::output::{write_depth, write_png};
    pub use tracer::tracer_kit::progress::Progress;
}

/// The mesher.
pub mod mesh {
    pub use tracer_mesh::grid::MAX_DEPTH;
    pub use tracer_mesh::{
        box_text, mesh_kind, MeshError, MeshOptions, MeshStats, DEFAULT_EXTRA_DEPTH,
        DEFAULT_MERGE_ERROR, MIN_DEPTH,
    };
}
