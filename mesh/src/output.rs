//! Mesh files, the format chosen by the extension: `.obj` (text, indexed), `.ply`
//! (binary little-endian, indexed: `double` coordinates, `uint` indices) and `.stl`
//! (binary, `float` coordinates; a triangle soup, so connectivity is recovered by
//! readers from equal coordinates only). OBJ and PLY keep the connectivity the
//! mesher's guarantees are about.
//!
//! [`write`] writes to a temporary file in the target's directory and renames it into
//! place, so an interrupted or failed write never leaves a half-written file under the
//! target's name. [`check`] refuses a path before any work: an unknown extension, a
//! directory, a directory that does not exist or cannot be written.

use crate::triangles::Mesh;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Wavefront OBJ, text.
    Obj,
    /// Stanford PLY, binary little-endian.
    Ply,
    /// STL, binary.
    Stl,
}

impl Format {
    /// The format of a path's extension (case-insensitive).
    pub fn of(path: &Path) -> Result<Format, String> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        match ext.as_deref() {
            Some("obj") => Ok(Format::Obj),
            Some("ply") => Ok(Format::Ply),
            Some("stl") => Ok(Format::Stl),
            _ => Err(format!(
                "'{}': the file must end in .obj, .ply or .stl (the format follows the extension)",
                path.display()
            )),
        }
    }
}

/// Checks, before any work, that `path` has a mesh extension and can be written: not
/// a directory, in a directory that exists and takes a new file (tried with a
/// temporary file, removed at once).
pub fn check(path: &Path) -> Result<Format, String> {
    let format = Format::of(path)?;
    if path.is_dir() {
        return Err(format!("'{}': is a directory", path.display()));
    }
    let tmp = temp_path(path);
    File::create(&tmp).map_err(|e| format!("'{}': cannot write there: {e}", path.display()))?;
    let _ = std::fs::remove_file(&tmp);
    Ok(format)
}

/// A temporary name beside `path`: `.NAME.PID.tmp` in the same directory.
fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = format!(".{name}.{}.tmp", std::process::id());
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.join(tmp),
        _ => PathBuf::from(tmp),
    }
}

/// Writes `mesh` to `path` in the format of its extension, through a temporary file
/// renamed into place.
///
/// ```
/// use tracer_mesh::{output, Mesh};
/// let m = Mesh {
///     vertices: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
///     triangles: vec![[0, 1, 2]],
/// };
/// let path = std::env::temp_dir().join("tracer-doc-mesh.ply");
/// output::write(&path, &m)?;
/// assert!(std::fs::read(&path).unwrap().starts_with(b"ply\n"));
/// # Ok::<(), String>(())
/// ```
pub fn write(path: &Path, mesh: &Mesh) -> Result<(), String> {
    let format = Format::of(path)?;
    let tmp = temp_path(path);
    let res = write_to(&tmp, format, mesh).and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = res {
        let _ = std::fs::remove_file(&tmp);
        return Err(format!("'{}': {e}", path.display()));
    }
    Ok(())
}

fn write_to(path: &Path, format: Format, mesh: &Mesh) -> std::io::Result<()> {
    let mut w = BufWriter::new(File::create(path)?);
    match format {
        Format::Obj => write_obj(&mut w, mesh)?,
        Format::Ply => write_ply(&mut w, mesh)?,
        Format::Stl => write_stl(&mut w, mesh)?,
    }
    w.into_inner().map_err(|e| e.into_error())?.sync_all()
}

/// OBJ: `v x y z` lines (shortest round-trip decimals), then `f a b c` (1-based).
pub fn write_obj(w: &mut impl Write, mesh: &Mesh) -> std::io::Result<()> {
    writeln!(
        w,
        "# tracer mesh: {} vertices, {} triangles",
        mesh.vertices.len(),
        mesh.triangles.len()
    )?;
    for v in &mesh.vertices {
        writeln!(w, "v {:?} {:?} {:?}", v[0], v[1], v[2])?;
    }
    for t in &mesh.triangles {
        writeln!(w, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
    }
    Ok(())
}

/// PLY, binary little-endian: `double` x, y, z per vertex, a `uchar` count and three
/// `uint` indices per face.
pub fn write_ply(w: &mut impl Write, mesh: &Mesh) -> std::io::Result<()> {
    write!(
        w,
        "ply\nformat binary_little_endian 1.0\ncomment tracer mesh\n\
         element vertex {}\nproperty double x\nproperty double y\nproperty double z\n\
         element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        mesh.vertices.len(),
        mesh.triangles.len()
    )?;
    for v in &mesh.vertices {
        for c in v {
            w.write_all(&c.to_le_bytes())?;
        }
    }
    for t in &mesh.triangles {
        w.write_all(&[3])?;
        for i in t {
            w.write_all(&i.to_le_bytes())?;
        }
    }
    Ok(())
}

/// Binary STL: an 80-byte header, the triangle count, and per triangle its unit normal
/// and three corners as `float`, and a zero attribute word.
pub fn write_stl(w: &mut impl Write, mesh: &Mesh) -> std::io::Result<()> {
    let mut header = [b' '; 80];
    let text = b"binary STL written by tracer mesh";
    header[..text.len()].copy_from_slice(text);
    w.write_all(&header)?;
    let n = u32::try_from(mesh.triangles.len())
        .map_err(|_| std::io::Error::other("too many triangles for STL"))?;
    w.write_all(&n.to_le_bytes())?;
    for t in &mesh.triangles {
        let p = t.map(|i| glam::DVec3::from(mesh.vertices[i as usize]));
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        for v in std::iter::once(n).chain(p) {
            for c in v.to_array() {
                w.write_all(&(c as f32).to_le_bytes())?;
            }
        }
        w.write_all(&[0, 0])?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri() -> Mesh {
        Mesh {
            vertices: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.5]],
            triangles: vec![[0, 1, 2]],
        }
    }

    #[test]
    fn sizes_follow_the_formats() {
        let mut stl = Vec::new();
        write_stl(&mut stl, &tri()).unwrap();
        assert_eq!(stl.len(), 84 + 50);
        let mut ply = Vec::new();
        write_ply(&mut ply, &tri()).unwrap();
        let body = ply.len() - (ply.windows(11).position(|w| w == b"end_header\n").unwrap() + 11);
        assert_eq!(body, 3 * 24 + 13);
        let mut obj = Vec::new();
        write_obj(&mut obj, &tri()).unwrap();
        let text = String::from_utf8(obj).unwrap();
        assert!(text.contains("v 0.0 1.0 0.5\n") && text.ends_with("f 1 2 3\n"));
    }

    #[test]
    fn unknown_extensions_are_refused() {
        for p in ["a.png", "a", "a.obj.gz"] {
            assert!(Format::of(Path::new(p)).is_err(), "{p}");
        }
        assert_eq!(Format::of(Path::new("A.STL")), Ok(Format::Stl));
    }
}
