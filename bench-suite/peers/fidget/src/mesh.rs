//! One mesh with fidget's own mesher (`fidget::mesh`, Manifold Dual Contouring over an
//! octree): the `.vm` text read by `Context::from_text`, compiled by the JIT, an
//! [`Octree`] built to `depth` over world `[-1, 1]^3`, then `walk_dual` to an indexed
//! mesh, written as OBJ, binary PLY or binary STL.
//!
//! The frame is the render mode's: the model scaled by `1/scale`, so the octree's root
//! cell is the model box `[-1/scale, 1/scale]^3` and a cell at `depth` has side
//! `2 / (scale * 2^depth)` in model units. fidget evaluates the octree's corners at
//! world `-1 + 2i/2^depth` and maps its vertices back to model units.
//!
//! fidget collapses leaves whose merged quadratic error stays small (Ju et al.'s
//! topology tests), so its mesh is adaptive: `depth` is its finest level.

use fidget::context::Context;
use fidget::jit::JitShape;
use fidget::mesh::{Mesh, Octree, Settings};
use fidget::render::ThreadPool;
use fidget::shape::BoundShape;
use std::io::Write;
use std::path::Path;
use std::time::{Duration, Instant};

/// What one mesh run produced.
pub struct Meshed {
    /// fidget's indexed mesh, vertices in model units.
    pub mesh: Mesh,
    /// Time to build the JIT shape.
    pub jit: Duration,
    /// Time of `Octree::build`.
    pub octree: Duration,
    /// Time of `walk_dual`.
    pub walk: Duration,
}

/// Meshes the `.vm` tape `text` to `depth` over the model box `[-1/scale, 1/scale]^3`.
pub fn mesh(text: &str, depth: u8, scale: f32) -> Result<Meshed, String> {
    let (ctx, root) = Context::from_text(text.as_bytes()).map_err(|e| format!("{e}"))?;
    let t = Instant::now();
    let shape = JitShape::new(&ctx, root).map_err(|e| format!("JIT: {e}"))?;
    let jit = t.elapsed();
    let shape = BoundShape::try_from(shape).map_err(|e| format!("variables: {e}"))?;

    let s = 1.0 / scale;
    let settings = Settings {
        depth,
        world_to_model: nalgebra::Scale3::new(s, s, s).to_homogeneous(),
        threads: Some(&ThreadPool::Global),
        ..Default::default()
    };
    let t = Instant::now();
    let octree = Octree::build(&shape, &settings).ok_or("meshing was cancelled")?;
    let octree_time = t.elapsed();
    let t = Instant::now();
    let mesh = octree.walk_dual();
    let walk = t.elapsed();
    Ok(Meshed {
        mesh,
        jit,
        octree: octree_time,
        walk,
    })
}

/// The output formats, from the file's extension.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Format {
    Obj,
    Ply,
    Stl,
}

impl Format {
    /// The format of `path` from its extension, or a message naming the accepted ones.
    pub fn of(path: &Path) -> Result<Format, String> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("obj") => Ok(Format::Obj),
            Some("ply") => Ok(Format::Ply),
            Some("stl") => Ok(Format::Stl),
            _ => Err(format!(
                "--out {}: the extension must be .obj, .ply or .stl",
                path.display()
            )),
        }
    }
}

/// Writes `mesh` to `out` in `format`: OBJ and PLY (binary little-endian) keep the
/// indexed connectivity, STL (binary, fidget's writer) repeats the vertices per triangle.
pub fn write(mesh: &Mesh, format: Format, out: &mut impl Write) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::new(out);
    match format {
        Format::Stl => mesh.write_stl(&mut w)?,
        Format::Obj => {
            writeln!(w, "# fidget-peer mesh (fidget's Manifold Dual Contouring)")?;
            for v in &mesh.vertices {
                writeln!(w, "v {} {} {}", v.x, v.y, v.z)?;
            }
            for t in &mesh.triangles {
                writeln!(w, "f {} {} {}", t.x + 1, t.y + 1, t.z + 1)?;
            }
        }
        Format::Ply => {
            write!(
                w,
                "ply\nformat binary_little_endian 1.0\ncomment fidget-peer mesh\n\
                 element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
                 element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
                mesh.vertices.len(),
                mesh.triangles.len()
            )?;
            for v in &mesh.vertices {
                for c in [v.x, v.y, v.z] {
                    w.write_all(&c.to_le_bytes())?;
                }
            }
            for t in &mesh.triangles {
                w.write_all(&[3u8])?;
                for i in [t.x, t.y, t.z] {
                    let i = u32::try_from(i).map_err(|_| {
                        std::io::Error::other("more than 2^32 vertices for a PLY index")
                    })?;
                    w.write_all(&i.to_le_bytes())?;
                }
            }
        }
    }
    w.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPHERE: &str = "_x var-x\n_y var-y\n_z var-z\n_x2 square _x\n_y2 square _y\n\
                          _z2 square _z\n_s add _x2 _y2\n_t add _s _z2\n_r sqrt _t\n\
                          _c const 0.5\n_f sub _r _c\n";

    /// Every edge used by two triangles in opposite directions.
    fn closed(m: &Mesh) -> bool {
        let mut edges = std::collections::HashMap::new();
        for t in &m.triangles {
            for (a, b) in [(t.x, t.y), (t.y, t.z), (t.z, t.x)] {
                *edges.entry((a, b)).or_insert(0) += 1;
            }
        }
        edges
            .iter()
            .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
    }

    #[test]
    fn meshes_a_sphere_in_model_units() {
        // scale 0.5: the box [-2, 2]^3; the sphere of radius 0.5 is a quarter of it.
        let m = mesh(SPHERE, 5, 0.5).unwrap().mesh;
        assert!(!m.triangles.is_empty());
        assert!(closed(&m));
        for t in &m.triangles {
            for i in [t.x, t.y, t.z] {
                let r = m.vertices[i].norm();
                // Within a cell (4 / 32) of the sphere.
                assert!((r - 0.5).abs() < 0.125, "vertex at radius {r}");
            }
        }
    }

    #[test]
    fn writes_indexed_formats() {
        let m = mesh(SPHERE, 3, 1.0).unwrap().mesh;
        let mut obj = vec![];
        write(&m, Format::Obj, &mut obj).unwrap();
        let obj = String::from_utf8(obj).unwrap();
        let faces = obj.lines().filter(|l| l.starts_with("f ")).count();
        let verts = obj.lines().filter(|l| l.starts_with("v ")).count();
        assert_eq!((faces, verts), (m.triangles.len(), m.vertices.len()));

        let mut ply = vec![];
        write(&m, Format::Ply, &mut ply).unwrap();
        let end = b"end_header\n";
        let at = ply.windows(end.len()).position(|w| w == end).unwrap() + end.len();
        assert_eq!(
            ply.len() - at,
            12 * m.vertices.len() + 13 * m.triangles.len()
        );

        let mut stl = vec![];
        write(&m, Format::Stl, &mut stl).unwrap();
        assert_eq!(stl.len(), 84 + 50 * m.triangles.len());
    }

    #[test]
    fn format_from_extension() {
        assert_eq!(Format::of(Path::new("a.OBJ")), Ok(Format::Obj));
        assert_eq!(Format::of(Path::new("a.ply")), Ok(Format::Ply));
        assert_eq!(Format::of(Path::new("a.stl")), Ok(Format::Stl));
        assert!(Format::of(Path::new("a.off"))
            .unwrap_err()
            .contains(".obj, .ply or .stl"));
        assert!(Format::of(Path::new("a")).is_err());
    }
}
