//! Searches: the algorithms that find where a surface is, each asking a shape for one
//! range or point value at a time, so scalar, packed and (later) GPU drivers share them.
//! [`ray`] is the revised-affine paper's Algorithm 1 (range test, dichotomy, argument
//! pruning), [`cull`] its Algorithm 2 (cell culling in frustum form), [`lipschitz`] the
//! progressive-refinement paper's Lipschitz ray casters and automatic Lipschitz bounds,
//! [`cone`] that paper's Lipschitz cone tracing (eqs. 3-6, Fig. 3), [`cone_range`] the
//! same cones tested with a range arithmetic over their frustum instead; [`windows`]
//! holds a cell's shape specialised to slices of its depths; [`slabs`] is the
//! renderer's default search, image tiles by depth slabs down to Algorithm 1 on short
//! pieces of the rays; [`batch`] evaluates the
//! ranges that many searches in lock-step ask for in one call.

pub mod cone;
pub mod cone_range;
pub mod cull;
pub mod lipschitz;
pub mod ray;
pub mod slabs;
pub mod tile_rays;
pub mod windows;
