//! Cells merged where the error stays small: a simplification of the dual-contoured
//! mesh along the octree, so flat parts and chamfers take few triangles.
//!
//! From the leaf level up (at most [`MAX_LEVELS`] levels), the vertices that lie in one
//! cell of the coarser level and are joined by mesh edges (one connected piece) are
//! collapsed into one vertex, the minimiser of their QEFs summed, constrained to the
//! coarser cell (so no vertex leaves its cell, now the coarser one). A group is
//! collapsed only when all of these hold, and left as it is otherwise:
//! - the triangles touching the group form a **disk** (Euler characteristic 1) whose
//!   boundary is one simple cycle of vertices outside the group, every other vertex
//!   of those triangles being in the group: replacing the disk by a fan around the
//!   new vertex keeps the mesh a closed, consistently wound manifold of the same
//!   topology (the vertex-clustering criterion of Manifold Dual Contouring, checked
//!   on the mesh itself rather than on cell sign patterns);
//! - the new vertex lies within `max_error` of every plane of the group's crossings
//!   (their QEF's residual, a sum of squared distances, is at most `max_error^2`), so
//!   curved parts, creases at an angle and small features are not merged;
//! - no triangle of the fan turns by more than [`MAX_TURN`] from the triangle it
//!   replaces, and none is degenerate (no folds).
//!
//! This is a post-pass over the uniform mesh, not an adaptive contouring: it needs no
//! transition cells and cannot open cracks, since it only ever replaces a disk by a
//! disk with the same boundary.

use super::qef::Qef;
use glam::DVec3;
use rayon::prelude::*;
use rustc_hash::{FxHashMap, FxHashSet};

/// Levels above the leaves that groups may grow to (a vertex for up to `8^3` leaves).
pub const MAX_LEVELS: u32 = 3;

/// The largest angle between a fan triangle's normal and the normal of the triangle
/// it replaces (as its cosine).
pub const MAX_TURN: f64 = 0.5;

/// A mesh with, for each vertex, its leaf cell and the QEF that placed it.
pub struct Clustered {
    /// Vertex positions.
    pub vertices: Vec<DVec3>,
    /// Triangles (outward winding).
    pub triangles: Vec<[u32; 3]>,
    /// Each vertex's cell at the leaf level.
    pub cells: Vec<[u32; 3]>,
    /// Each vertex's QEF.
    pub qefs: Vec<Qef>,
}

/// The merged mesh and the number of vertices removed. `vertex_box(level, cell)` is
/// where a vertex of `cell` at `level` may go; `leaf` is the leaf level.
pub fn merge(
    m: Clustered,
    leaf: u32,
    max_error: f64,
    vertex_box: impl Fn(u32, [u32; 3]) -> (DVec3, DVec3),
) -> (Vec<DVec3>, Vec<[u32; 3]>, u64) {
    let mut w = Work::new(m);
    for up in 1..=MAX_LEVELS.min(leaf) {
        let level = leaf - up;
        let groups = w.groups(up);
        let limits: Vec<(DVec3, DVec3)> = groups
            .iter()
            .map(|g| vertex_box(level, w.cells[g[0] as usize].map(|x| x >> up)))
            .collect();
        // Each group's collapse planned against the mesh as the level starts, in
        // parallel; then applied in order, planned again where an earlier collapse of
        // this level changed a member's triangles (the plan reads nothing else).
        let plans: Vec<Option<Plan>> = groups
            .par_iter()
            .zip(&limits)
            .map(|(g, &(lo, hi))| w.plan(g, lo, hi, max_error))
            .collect();
        let mut dirty = vec![false; w.pos.len()];
        for ((g, &(lo, hi)), plan) in groups.iter().zip(&limits).zip(plans) {
            let plan = if g.iter().any(|&v| dirty[v as usize]) {
                w.plan(g, lo, hi, max_error)
            } else {
                plan
            };
            if let Some(p) = plan {
                w.apply(g, p, &mut dirty);
            }
        }
    }
    w.finish()
}

/// A group's collapse: the disk it replaces, the new vertex and its QEF.
struct Plan {
    disk: Disk,
    w: DVec3,
    q: Qef,
}

/// The mesh being merged: positions, QEFs, live triangles and each vertex's triangles.
struct Work {
    pos: Vec<DVec3>,
    qefs: Vec<Qef>,
    cells: Vec<[u32; 3]>,
    live: Vec<bool>,
    tris: Vec<[u32; 3]>,
    tri_live: Vec<bool>,
    star: Vec<Vec<u32>>,
    removed: u64,
}

/// The disk around a group: its triangles and its boundary as oriented edges
/// `(x, y)`, each with the normal of the triangle it comes from.
struct Disk {
    tris: Vec<u32>,
    link: Vec<(u32, u32, DVec3)>,
}

impl Work {
    fn new(m: Clustered) -> Work {
        let mut star = vec![Vec::new(); m.vertices.len()];
        for (t, tri) in m.triangles.iter().enumerate() {
            for &v in tri {
                star[v as usize].push(t as u32);
            }
        }
        Work {
            live: vec![true; m.vertices.len()],
            tri_live: vec![true; m.triangles.len()],
            pos: m.vertices,
            qefs: m.qefs,
            cells: m.cells,
            tris: m.triangles,
            star,
            removed: 0,
        }
    }

    /// The live vertices grouped by their cell `up` levels above the leaves, split
    /// into pieces joined by mesh edges; groups of one left out.
    fn groups(&self, up: u32) -> Vec<Vec<u32>> {
        let mut by_cell: FxHashMap<[u32; 3], Vec<u32>> = FxHashMap::default();
        for v in (0..self.pos.len()).filter(|&v| self.live[v]) {
            let c = self.cells[v].map(|x| x >> up);
            by_cell.entry(c).or_default().push(v as u32);
        }
        let mut cells: Vec<_> = by_cell.into_iter().filter(|(_, g)| g.len() > 1).collect();
        cells.sort_unstable_by_key(|(c, _)| *c);
        cells
            .into_par_iter()
            .flat_map_iter(|(_, g)| self.pieces(&g))
            .filter(|g| g.len() > 1)
            .collect()
    }

    /// `group` split into the classes joined by mesh edges within it.
    fn pieces(&self, group: &[u32]) -> Vec<Vec<u32>> {
        let index: FxHashMap<u32, usize> = group.iter().enumerate().map(|(i, &v)| (v, i)).collect();
        let mut parent: Vec<usize> = (0..group.len()).collect();
        fn find(p: &mut [usize], mut i: usize) -> usize {
            while p[i] != i {
                p[i] = p[p[i]];
                i = p[i];
            }
            i
        }
        for (i, &v) in group.iter().enumerate() {
            for &t in &self.star[v as usize] {
                for u in self.tris[t as usize] {
                    if let Some(&j) = index.get(&u) {
                        let (a, b) = (find(&mut parent, i), find(&mut parent, j));
                        parent[a.max(b)] = a.min(b);
                    }
                }
            }
        }
        let mut out: FxHashMap<usize, Vec<u32>> = FxHashMap::default();
        for (i, &v) in group.iter().enumerate() {
            out.entry(find(&mut parent, i)).or_default().push(v);
        }
        let mut out: Vec<Vec<u32>> = out.into_values().collect();
        out.sort_unstable();
        out
    }

    /// The collapse of `group` into one vertex in `[lo, hi]`, if that keeps the mesh a
    /// manifold of the same topology, within `max_error` of the group's planes and
    /// without folds. Reads the members' triangles (and their vertices) only.
    fn plan(&self, group: &[u32], lo: DVec3, hi: DVec3, max_error: f64) -> Option<Plan> {
        // The error first: it rejects most groups of a curved surface, and costs less
        // than the disk.
        let mut q = Qef::default();
        for &v in group {
            q.merge(&self.qefs[v as usize]);
        }
        let w = q.solve(lo, hi);
        let error = q.residual(w);
        if error.is_nan() || error > max_error * max_error {
            return None;
        }
        let members: FxHashSet<u32> = group.iter().copied().collect();
        let disk = self.disk(&members)?;
        self.unfolded(&disk, w).then_some(Plan { disk, w, q })
    }

    /// The disk of triangles around `members`, if it is one (see the module doc).
    fn disk(&self, members: &FxHashSet<u32>) -> Option<Disk> {
        let mut tris: Vec<u32> = members
            .iter()
            .flat_map(|&v| self.star[v as usize].iter().copied())
            .collect();
        tris.sort_unstable();
        tris.dedup();
        let mut link = Vec::new();
        for &t in &tris {
            let tri = self.tris[t as usize];
            let inside: Vec<usize> = (0..3).filter(|&k| members.contains(&tri[k])).collect();
            if let [k] = inside[..] {
                let (x, y) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
                link.push((x, y, self.normal(tri)));
            }
        }
        let ok = one_cycle(&link) && self.euler(&tris) == 1 && self.all_on(&tris, members, &link);
        ok.then_some(Disk { tris, link })
    }

    /// Whether every vertex of `tris` is a member or on the link.
    fn all_on(&self, tris: &[u32], members: &FxHashSet<u32>, link: &[(u32, u32, DVec3)]) -> bool {
        let on: FxHashSet<u32> = link.iter().map(|e| e.0).collect();
        tris.iter()
            .flat_map(|&t| self.tris[t as usize])
            .all(|v| members.contains(&v) || on.contains(&v))
    }

    /// `V - E + F` of the triangles `tris`.
    fn euler(&self, tris: &[u32]) -> i64 {
        let mut vs = FxHashSet::default();
        let mut es = FxHashSet::default();
        for &t in tris {
            let tri = self.tris[t as usize];
            for k in 0..3 {
                vs.insert(tri[k]);
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                es.insert((a.min(b), a.max(b)));
            }
        }
        vs.len() as i64 - es.len() as i64 + tris.len() as i64
    }

    fn normal(&self, tri: [u32; 3]) -> DVec3 {
        let [a, b, c] = tri.map(|v| self.pos[v as usize]);
        (b - a).cross(c - a)
    }

    /// Whether each fan triangle `(w, x, y)` is proper and turns by at most
    /// [`MAX_TURN`] from the triangle it replaces.
    fn unfolded(&self, disk: &Disk, w: DVec3) -> bool {
        disk.link.iter().all(|&(x, y, n)| {
            let (px, py) = (self.pos[x as usize], self.pos[y as usize]);
            let m = (px - w).cross(py - w);
            let (lm, ln) = (m.length(), n.length());
            lm > 1e-12 * (px - py).length_squared() && m.dot(n) >= MAX_TURN * lm * ln
        })
    }

    /// Replaces the disk by a fan around the first member, moved to `w`; marks in
    /// `dirty` every vertex whose triangles change.
    fn apply(&mut self, group: &[u32], p: Plan, dirty: &mut [bool]) {
        for &t in &p.disk.tris {
            self.tri_live[t as usize] = false;
            for v in self.tris[t as usize] {
                self.star[v as usize].retain(|&s| s != t);
                dirty[v as usize] = true;
            }
        }
        let keep = group[0];
        for &v in &group[1..] {
            self.live[v as usize] = false;
            self.removed += 1;
        }
        self.pos[keep as usize] = p.w;
        self.qefs[keep as usize] = p.q;
        for (x, y, _) in p.disk.link {
            let t = self.tris.len() as u32;
            self.tris.push([keep, x, y]);
            self.tri_live.push(true);
            for v in [keep, x, y] {
                self.star[v as usize].push(t);
                dirty[v as usize] = true;
            }
        }
    }

    /// The live vertices and triangles, renumbered.
    fn finish(self) -> (Vec<DVec3>, Vec<[u32; 3]>, u64) {
        let mut index = vec![u32::MAX; self.pos.len()];
        let mut vertices = Vec::new();
        for (v, &p) in self.pos.iter().enumerate() {
            if self.live[v] {
                index[v] = vertices.len() as u32;
                vertices.push(p);
            }
        }
        let triangles = self
            .tris
            .iter()
            .zip(&self.tri_live)
            .filter(|(_, l)| **l)
            .map(|(t, _)| t.map(|v| index[v as usize]))
            .collect();
        (vertices, triangles, self.removed)
    }
}

/// Whether the oriented edges form one simple cycle (of at least three edges).
fn one_cycle(link: &[(u32, u32, DVec3)]) -> bool {
    let mut next: FxHashMap<u32, u32> = FxHashMap::default();
    for &(x, y, _) in link {
        if next.insert(x, y).is_some() {
            return false;
        }
    }
    if link.len() < 3 {
        return false;
    }
    let start = link[0].0;
    let mut v = start;
    for step in 1..=link.len() {
        let Some(&n) = next.get(&v) else {
            return false;
        };
        v = n;
        if v == start {
            return step == link.len();
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat square grid of `n x n` quads in z = 0 closed by one apex below, each
    /// vertex in its own unit cell.
    fn pyramid(n: u32) -> Clustered {
        let mut vertices = Vec::new();
        let mut cells = Vec::new();
        let mut qefs = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let p = DVec3::new(i as f64 + 0.5, j as f64 + 0.5, 0.5);
                let mut q = Qef::default();
                q.add(p, DVec3::Z);
                vertices.push(p);
                cells.push([i, j, 0]);
                qefs.push(q);
            }
        }
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        // The apex, joined to the border (counter-clockwise seen from above).
        let apex = vertices.len() as u32;
        vertices.push(DVec3::new(n as f64 / 2.0, n as f64 / 2.0, -5.0));
        cells.push([1 << 20, 0, 0]);
        qefs.push(Qef::default());
        let mut border = Vec::new();
        border.extend((0..n).map(|i| id(i, 0)));
        border.extend((0..n).map(|j| id(n, j)));
        border.extend((0..n).map(|i| id(n - i, n)));
        border.extend((0..n).map(|j| id(0, n - j)));
        for k in 0..border.len() {
            triangles.push([apex, border[(k + 1) % border.len()], border[k]]);
        }
        Clustered {
            vertices,
            triangles,
            cells,
            qefs,
        }
    }

    fn unit_box(level: u32, c: [u32; 3], leaf: u32) -> (DVec3, DVec3) {
        let s = (1u32 << (leaf - level)) as f64;
        let lo = DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64) * s;
        (lo + 1e-3, lo + s - 1e-3)
    }

    #[test]
    fn a_flat_patch_merges_and_stays_closed() {
        let m = pyramid(8);
        let before = m.triangles.len();
        let (v, t, removed) = merge(m, 4, 0.01, |l, c| unit_box(l, c, 4));
        assert!(removed > 0 && t.len() < before, "{} -> {}", before, t.len());
        let mesh = crate::Mesh {
            vertices: v.iter().map(|p| p.to_array()).collect(),
            triangles: t,
        };
        let topo = mesh.topology();
        assert!(topo.manifold() && topo.watertight(), "{topo:?}");
        assert_eq!(topo.euler, 2);
        // The border is kept, the flat part stays flat.
        for p in v.iter().filter(|p| p.z > -1.0) {
            assert!((p.z - 0.5).abs() < 1e-9, "{p}");
        }
    }

    #[test]
    fn a_bent_patch_does_not_merge() {
        let mut m = pyramid(4);
        for (p, q) in m.vertices.iter_mut().zip(&mut m.qefs).take(25) {
            // A fold along x = 2.5: planes with normals tilted either way.
            let n = if p.x < 2.5 {
                DVec3::new(0.6, 0.0, 0.8)
            } else {
                DVec3::new(-0.6, 0.0, 0.8)
            };
            p.z = 0.5 - 0.75 * (p.x - 2.5).abs();
            *q = Qef::default();
            q.add(*p, n);
        }
        let (_, _, removed) = merge(m, 2, 0.01, |l, c| unit_box(l, c, 2));
        // Only groups on one side of the fold are flat.
        let (_, _, flat) = merge(pyramid(4), 2, 0.01, |l, c| unit_box(l, c, 2));
        assert!(removed < flat, "{removed} vs {flat}");
    }

    #[test]
    fn cycles_are_checked() {
        let e = |x, y| (x, y, DVec3::Z);
        assert!(one_cycle(&[e(1, 2), e(2, 3), e(3, 1)]));
        assert!(!one_cycle(&[e(1, 2), e(2, 1)]));
        assert!(!one_cycle(&[
            e(1, 2),
            e(2, 3),
            e(3, 1),
            e(4, 5),
            e(5, 6),
            e(6, 4)
        ]));
        assert!(!one_cycle(&[e(1, 2), e(2, 3), e(3, 4)]));
    }
}
