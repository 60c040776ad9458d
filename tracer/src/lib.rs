//! # tracer: reliable ray casting of implicit surfaces, generic over [`arith_core::Range`]
//!
//! The searches and the CPU renderers, over the model IR ([`model_ir`]: tapes, the
//! [`shape::Shape`] trait, views and the one list of arithmetics [`arith`]) and the
//! model sources ([`model_sources`]), using the kit below the renderers
//! ([`tracer_kit`]: image output, filters, progress, Ctrl-C). Every import points down:
//! - [`search`]: Algorithm 1 ([`search::ray`]), Algorithm 2 ([`search::cull`]), the
//!   hand-over from culling to rays ([`search::tile_rays`]), the Lipschitz casters
//!   ([`search::lipschitz`]) and Lipschitz cone tracing ([`search::cone`]);
//! - [`render`]: the reliable tracer, tiles in parallel, with shading;
//! - [`progressive`]: the progressive previewer, a queue of cones.
//!
//! The mesher (`tracer-mesh`), the GPU renderer (`tracer-gpu`) and the `tracer` command
//! (`tracer-cli`) are crates of their own above this one.
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
//! tracer::tracer_kit::output::write_png(&png, 64, 48, &image.rgb)?;
//! # Ok::<(), String>(())
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod progressive;
pub mod render;
pub mod search;

// The layers below, re-exported so that a user of the tracer needs no other crate.
#[doc(no_inline)]
pub use model_ir::arith::arith_core;
#[doc(no_inline)]
pub use model_ir::{arith, camera, shape};
#[doc(no_inline)]
pub use model_ir::{arith_list, with_arith};
#[doc(no_inline)]
pub use tracer_kit::{out, say};
#[doc(no_inline)]
pub use {glam, model_ir, model_sources, tracer_kit};
/// The crates of the one list of arithmetics, at the crate root too (`tracer::arith_ia`).
macro_rules! reexport_arith_crates {
    ([ $($krate:ident),* ]) => {
        $(
            #[doc(no_inline)]
            pub use model_ir::arith::$krate;
        )*
    };
}
arith_list!(@crates [reexport_arith_crates]);
