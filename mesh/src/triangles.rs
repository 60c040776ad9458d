//! The mesher's output: an indexed triangle mesh. What it is (watertight, manifold,
//! self-intersecting) is asked of [`crate::topology`] and [`crate::self_intersections`],
//! which add their methods to [`Mesh`].

/// An indexed triangle mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as indices into `vertices`, counter-clockwise seen from outside
    /// (`f < 0`): the right-hand normal points outward.
    pub triangles: Vec<[u32; 3]>,
}
