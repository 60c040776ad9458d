//! What a triangle mesh is, topologically: whether it is watertight and manifold and
//! consistently wound, its Euler characteristic and its connected components. The
//! mesher reports these in its statistics and the tests check them against the genus
//! of analytic shapes; they depend on the connectivity only, never on coordinates
//! (apart from [`Topology::degenerate`], triangles of zero area).

use crate::triangles::Mesh;
use glam::DVec3;
use rustc_hash::FxHashMap;

/// The topology of a triangle mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Topology {
    /// Vertices used by a triangle.
    pub vertices: u64,
    /// Distinct edges.
    pub edges: u64,
    /// Triangles.
    pub faces: u64,
    /// `V - E + F` (2 for a sphere, 0 for a torus, `2 - 2g` for genus `g`, summed over
    /// components).
    pub euler: i64,
    /// Connected components (through shared edges and vertices).
    pub components: u64,
    /// Edges used by one triangle only (holes).
    pub boundary_edges: u64,
    /// Edges used by three or more triangles.
    pub non_manifold_edges: u64,
    /// Edges used by two triangles in the same direction (inconsistent winding).
    pub misoriented_edges: u64,
    /// Vertices whose triangles do not form a single fan (a pinch), where every edge
    /// is manifold.
    pub non_manifold_vertices: u64,
    /// Triangles with a repeated vertex or zero area.
    pub degenerate: u64,
}

impl Topology {
    /// Watertight: no boundary edges.
    pub fn watertight(&self) -> bool {
        self.boundary_edges == 0
    }

    /// A closed, consistently oriented 2-manifold: every edge shared by exactly two
    /// triangles in opposite directions, every vertex a single fan.
    pub fn manifold(&self) -> bool {
        self.watertight()
            && self.non_manifold_edges == 0
            && self.misoriented_edges == 0
            && self.non_manifold_vertices == 0
    }
}

/// The topology of `mesh`.
pub fn topology(mesh: &Mesh) -> Topology {
    let mut t = Topology {
        faces: mesh.triangles.len() as u64,
        ..Topology::default()
    };
    // Per undirected edge: the number of uses and the sum of directions (+1 for
    // low-to-high, -1 for high-to-low): 2 uses and a sum of 0 is a good edge.
    let mut edges: FxHashMap<(u32, u32), (u32, i32)> = FxHashMap::default();
    edges.reserve(mesh.triangles.len() * 3 / 2 + 1);
    let mut used = vec![false; mesh.vertices.len()];
    let mut uf = UnionFind::new(mesh.vertices.len());
    for tri in &mesh.triangles {
        t.degenerate += degenerate(mesh, tri) as u64;
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            used[a as usize] = true;
            uf.union(a as usize, b as usize);
            let e = edges.entry((a.min(b), a.max(b))).or_default();
            e.0 += 1;
            e.1 += if a < b { 1 } else { -1 };
        }
    }
    t.vertices = used.iter().filter(|&&u| u).count() as u64;
    t.edges = edges.len() as u64;
    for &(n, dir) in edges.values() {
        match n {
            1 => t.boundary_edges += 1,
            2 if dir != 0 => t.misoriented_edges += 1,
            2 => {}
            _ => t.non_manifold_edges += 1,
        }
    }
    t.euler = t.vertices as i64 - t.edges as i64 + t.faces as i64;
    t.components = (0..mesh.vertices.len())
        .filter(|&v| used[v] && uf.find(v) == v)
        .count() as u64;
    if t.non_manifold_edges == 0 && t.boundary_edges == 0 {
        t.non_manifold_vertices = pinched_vertices(mesh);
    }
    t
}

/// Whether a triangle repeats a vertex or has zero area.
fn degenerate(mesh: &Mesh, t: &[u32; 3]) -> bool {
    if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
        return true;
    }
    let p = t.map(|i| DVec3::from(mesh.vertices[i as usize]));
    (p[1] - p[0]).cross(p[2] - p[0]).length_squared() == 0.0
}

/// Vertices of a closed edge-manifold mesh whose triangles form more than one fan:
/// around each vertex, the link edges `b -> c` of its triangles `(v, b, c)` must form
/// a single cycle. The links are laid out one vertex after another in one array.
fn pinched_vertices(mesh: &Mesh) -> u64 {
    let n = mesh.vertices.len();
    let mut start = vec![0usize; n + 1];
    for t in &mesh.triangles {
        for &v in t {
            start[v as usize + 1] += 1;
        }
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut link = vec![(0u32, 0u32); start[n]];
    for t in &mesh.triangles {
        for k in 0..3 {
            let v = t[k] as usize;
            link[fill[v]] = (t[(k + 1) % 3], t[(k + 2) % 3]);
            fill[v] += 1;
        }
    }
    (0..n)
        .filter(|&v| start[v] < start[v + 1] && !single_cycle(&link[start[v]..start[v + 1]]))
        .count() as u64
}

/// The link edge leaving `v` (the first one, and whether it is the only one).
fn next_of(l: &[(u32, u32)], v: u32) -> Option<(u32, bool)> {
    let mut it = l.iter().filter(|e| e.0 == v);
    let first = it.next()?.1;
    Some((first, it.next().is_none()))
}

/// Whether the directed edges `l` form one cycle through all of them.
fn single_cycle(l: &[(u32, u32)]) -> bool {
    if l.len() > 64 {
        return single_cycle_hashed(l);
    }
    let start = l[0].0;
    let mut v = start;
    for steps in 1..=l.len() {
        match next_of(l, v) {
            Some((w, true)) => v = w,
            _ => return false,
        }
        if v == start {
            return steps == l.len();
        }
    }
    false
}

/// [`single_cycle`] over a hash map, for large links.
fn single_cycle_hashed(l: &[(u32, u32)]) -> bool {
    let next: FxHashMap<u32, u32> = l.iter().copied().collect();
    if next.len() != l.len() {
        return false;
    }
    let start = l[0].0;
    let mut v = start;
    for steps in 1..=l.len() {
        match next.get(&v) {
            Some(&w) => v = w,
            None => return false,
        }
        if v == start {
            return steps == l.len();
        }
    }
    false
}

/// Union-find over `0..n` with path halving.
pub(crate) struct UnionFind(Vec<usize>);

impl UnionFind {
    pub(crate) fn new(n: usize) -> Self {
        UnionFind((0..n).collect())
    }
    pub(crate) fn find(&mut self, mut x: usize) -> usize {
        while self.0[x] != x {
            self.0[x] = self.0[self.0[x]];
            x = self.0[x];
        }
        x
    }
    pub(crate) fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra.max(rb)] = ra.min(rb);
        }
    }
}

impl Mesh {
    /// Watertightness, manifoldness, winding, Euler characteristic, components.
    pub fn topology(&self) -> Topology {
        topology(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> Mesh {
        Mesh {
            vertices: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ],
            // Outward winding.
            triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        }
    }

    #[test]
    fn a_tetrahedron_is_a_sphere() {
        let t = topology(&tetrahedron());
        assert!(t.manifold(), "{t:?}");
        assert_eq!((t.euler, t.components, t.degenerate), (2, 1, 0));
    }

    #[test]
    fn flips_and_holes_are_seen() {
        let mut m = tetrahedron();
        m.triangles[0] = [0, 1, 2];
        let t = topology(&m);
        assert_eq!(t.misoriented_edges, 3);
        m.triangles.pop();
        let t = topology(&m);
        assert_eq!(t.boundary_edges, 3);
        assert!(!t.manifold());
    }

    #[test]
    fn two_tetrahedra_at_one_vertex_are_pinched() {
        let mut m = tetrahedron();
        let n = m.vertices.len() as u32;
        m.vertices
            .extend([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]);
        // A mirrored tetrahedron sharing vertex 0.
        m.triangles.extend([
            [0, n, n + 1],
            [0, n + 2, n],
            [0, n + 1, n + 2],
            [n, n + 2, n + 1],
        ]);
        let t = topology(&m);
        assert_eq!(t.non_manifold_edges, 0);
        assert_eq!(t.non_manifold_vertices, 1);
        assert_eq!(t.components, 1);
    }
}
