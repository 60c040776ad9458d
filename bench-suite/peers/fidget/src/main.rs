//! `fidget-peer MODEL.vm --size N --out img.png [--mask mask.npy] [--depth d.npy]
//! [--scale S]`:
//! renders a fidget `.vm` tape with fidget's JIT 3-D rasteriser (see [`render`]) for a
//! side-by-side comparison with our `tracer` (`scripts/peer-fidget.sh`). Prints the
//! JIT, render and shading times to stderr.
//!
//! `fidget-peer mesh MODEL.vm --depth N --out FILE.{obj,ply,stl} [--scale S]`: meshes it
//! with fidget's mesher (see [`mesh`]) over `[-1/S, 1/S]^3`, `2^N` cells along a side
//! at the finest level (`scripts/peer-fidget-mesh.sh`). Prints the JIT, octree and
//! dual-walk times and the counts to stderr.

mod mesh;
mod npy;
mod render;
mod vm_check;

use std::path::PathBuf;
use std::process::ExitCode;

const USAGE: &str = "usage: fidget-peer MODEL.vm --size N --out img.png [--mask mask.npy] \
                     [--depth depth.npy] [--scale S]";

/// Command-line arguments.
struct Args {
    model: PathBuf,
    size: u32,
    out: PathBuf,
    mask: Option<PathBuf>,
    depth: Option<PathBuf>,
    scale: f32,
}

const MESH_USAGE: &str =
    "usage: fidget-peer mesh MODEL.vm --depth N --out FILE.{obj,ply,stl} [--scale S]";

/// Arguments of the `mesh` mode.
struct MeshArgs {
    model: PathBuf,
    depth: u8,
    out: PathBuf,
    format: mesh::Format,
    scale: f32,
}

/// The deepest octree accepted (fidget's octree is `8^depth` cells where the shape
/// is everywhere ambiguous).
const MAX_MESH_DEPTH: u8 = 12;

/// The value of `--scale`: a positive finite number.
fn parse_scale(v: &str) -> Result<f32, String> {
    v.parse()
        .ok()
        .filter(|s: &f32| s.is_finite() && *s > 0.0)
        .ok_or(format!("--scale '{v}': not a positive number"))
}

fn parse_mesh_args(mut it: impl Iterator<Item = String>) -> Result<MeshArgs, String> {
    let (mut model, mut depth, mut out) = (None, None, None);
    let mut scale = 1.0f32;
    while let Some(a) = it.next() {
        let mut value = |flag: &str| it.next().ok_or(format!("{flag} needs a value"));
        match a.as_str() {
            "--depth" => {
                let v = value("--depth")?;
                let n: u8 = v.parse().map_err(|_| {
                    format!("--depth '{v}': not a whole number in 1..={MAX_MESH_DEPTH}")
                })?;
                if !(1..=MAX_MESH_DEPTH).contains(&n) {
                    return Err(format!("--depth {n}: must be in 1..={MAX_MESH_DEPTH}"));
                }
                depth = Some(n);
            }
            "--out" => out = Some(PathBuf::from(value("--out")?)),
            "--scale" => scale = parse_scale(&value("--scale")?)?,
            "-h" | "--help" => return Err(MESH_USAGE.to_owned()),
            f if f.starts_with('-') => return Err(format!("unknown flag '{f}'; {MESH_USAGE}")),
            m if model.is_none() => model = Some(PathBuf::from(m)),
            m => return Err(format!("unexpected argument '{m}'; {MESH_USAGE}")),
        }
    }
    let out = out.ok_or(format!("missing --out; {MESH_USAGE}"))?;
    Ok(MeshArgs {
        model: model.ok_or(format!("missing MODEL.vm; {MESH_USAGE}"))?,
        depth: depth.ok_or(format!("missing --depth; {MESH_USAGE}"))?,
        format: mesh::Format::of(&out)?,
        out,
        scale,
    })
}

/// The largest image side accepted (fidget holds `N^2` 16-byte pixels, 1 GiB here).
const MAX_SIZE: u32 = 8192;

fn parse_args(mut it: impl Iterator<Item = String>) -> Result<Args, String> {
    let (mut model, mut size, mut out, mut mask, mut depth) = (None, None, None, None, None);
    let mut scale = 1.0f32;
    while let Some(a) = it.next() {
        let mut value = |flag: &str| it.next().ok_or(format!("{flag} needs a value"));
        match a.as_str() {
            "--size" => {
                let v = value("--size")?;
                let n: u32 = v
                    .parse()
                    .map_err(|_| format!("--size '{v}': not a whole number"))?;
                if !(1..=MAX_SIZE).contains(&n) {
                    return Err(format!("--size {n}: must be in 1..={MAX_SIZE}"));
                }
                size = Some(n);
            }
            "--out" => out = Some(PathBuf::from(value("--out")?)),
            "--mask" => mask = Some(PathBuf::from(value("--mask")?)),
            "--depth" => depth = Some(PathBuf::from(value("--depth")?)),
            "--scale" => scale = parse_scale(&value("--scale")?)?,
            "-h" | "--help" => return Err(USAGE.to_owned()),
            f if f.starts_with('-') => return Err(format!("unknown flag '{f}'; {USAGE}")),
            m if model.is_none() => model = Some(PathBuf::from(m)),
            m => return Err(format!("unexpected argument '{m}'; {USAGE}")),
        }
    }
    Ok(Args {
        model: model.ok_or(format!("missing MODEL.vm; {USAGE}"))?,
        size: size.ok_or(format!("missing --size; {USAGE}"))?,
        out: out.ok_or(format!("missing --out; {USAGE}"))?,
        mask,
        depth,
        scale,
    })
}

fn write_png(path: &std::path::Path, n: u32, rgb: &[u8]) -> Result<(), String> {
    let file = std::fs::File::create(path).map_err(|e| e.to_string())?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), n, n);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().map_err(|e| e.to_string())?;
    w.write_image_data(rgb).map_err(|e| e.to_string())
}

/// The `.vm` text of `path`, checked against fidget's grammar.
fn read_model(path: &std::path::Path) -> Result<String, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let text =
        String::from_utf8(bytes).map_err(|_| format!("{}: not UTF-8 text", path.display()))?;
    vm_check::check(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(text)
}

fn run_mesh(a: MeshArgs) -> Result<(), String> {
    let text = read_model(&a.model)?;
    let m =
        mesh::mesh(&text, a.depth, a.scale).map_err(|e| format!("{}: {e}", a.model.display()))?;
    let t = std::time::Instant::now();
    let write_err = |e: std::io::Error| format!("--out {}: {e}", a.out.display());
    let mut file = std::fs::File::create(&a.out).map_err(write_err)?;
    mesh::write(&m.mesh, a.format, &mut file).map_err(write_err)?;
    eprintln!(
        "fidget-peer: mesh {} depth {}: jit {:.1} ms, octree {:.1} ms, walk_dual {:.1} ms, \
         write {:.1} ms, vertices {}, triangles {}",
        a.model.display(),
        a.depth,
        m.jit.as_secs_f64() * 1e3,
        m.octree.as_secs_f64() * 1e3,
        m.walk.as_secs_f64() * 1e3,
        t.elapsed().as_secs_f64() * 1e3,
        m.mesh.vertices.len(),
        m.mesh.triangles.len(),
    );
    Ok(())
}

fn run() -> Result<(), String> {
    let mut args = std::env::args().skip(1).peekable();
    if args.peek().map(String::as_str) == Some("mesh") {
        return run_mesh(parse_mesh_args(args.skip(1))?);
    }
    let a = parse_args(args)?;
    let text = read_model(&a.model)?;
    let r = render::render(&text, a.size, a.scale)
        .map_err(|e| format!("{}: {e}", a.model.display()))?;
    write_png(&a.out, a.size, &r.rgb).map_err(|e| format!("--out {}: {e}", a.out.display()))?;
    let n = a.size as usize;
    if let Some(m) = &a.mask {
        npy::write(m, &npy::encode_u8(n, n, &r.mask))
            .map_err(|e| format!("--mask {}: {e}", m.display()))?;
    }
    if let Some(d) = &a.depth {
        npy::write(d, &npy::encode_f32(n, n, &r.depth))
            .map_err(|e| format!("--depth {}: {e}", d.display()))?;
    }
    let hits = r.mask.iter().filter(|&&m| m == 1).count();
    eprintln!(
        "fidget-peer: {} {n}x{n}: jit {:.1} ms, render {:.1} ms, shade {:.1} ms, hits {hits} ({:.4})",
        a.model.display(),
        r.jit.as_secs_f64() * 1e3,
        r.render.as_secs_f64() * 1e3,
        r.shade.as_secs_f64() * 1e3,
        hits as f64 / r.mask.len() as f64,
        n = a.size,
    );
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("fidget-peer: error: {e}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{parse_args, parse_mesh_args};

    fn mesh_args(s: &str) -> Result<super::MeshArgs, String> {
        parse_mesh_args(s.split_whitespace().map(str::to_owned))
    }

    #[test]
    fn reads_every_mesh_flag() {
        let a = mesh_args("m.vm --depth 7 --out o.ply --scale 0.25").unwrap();
        assert_eq!((a.depth, a.scale), (7, 0.25));
        assert_eq!(a.model.to_str(), Some("m.vm"));
        assert_eq!(a.out.to_str(), Some("o.ply"));
        assert_eq!(a.format, super::mesh::Format::Ply);
        assert_eq!(mesh_args("m.vm --depth 3 --out o.obj").unwrap().scale, 1.0);
    }

    #[test]
    fn mesh_refuses_bad_input() {
        for (s, want) in [
            ("m.vm --depth 0 --out o.obj", "--depth 0: must be in 1..=12"),
            ("m.vm --depth 13 --out o.obj", "--depth 13: must be in"),
            (
                "m.vm --depth x --out o.obj",
                "--depth 'x': not a whole number",
            ),
            ("m.vm --depth 4 --out o.off", "--out o.off: the extension"),
            (
                "m.vm --depth 4 --out o.obj --scale 0",
                "--scale '0': not a positive",
            ),
            ("m.vm --out o.obj", "missing --depth"),
            ("m.vm --depth 4", "missing --out"),
            ("--depth 4 --out o.obj", "missing MODEL.vm"),
            (
                "m.vm --depth 4 --out o.obj --size 3",
                "unknown flag '--size'",
            ),
            ("m.vm n.vm", "unexpected argument 'n.vm'"),
            ("m.vm --depth", "--depth needs a value"),
        ] {
            let e = mesh_args(s).err().unwrap_or_default();
            assert!(e.starts_with(want), "{s}: {e}");
        }
    }

    fn args(s: &str) -> Result<super::Args, String> {
        parse_args(s.split_whitespace().map(str::to_owned))
    }

    #[test]
    fn reads_every_flag() {
        let a = args("m.vm --size 64 --out o.png --mask m.npy --depth d.npy --scale 0.5").unwrap();
        assert_eq!((a.size, a.scale), (64, 0.5));
        assert_eq!(a.model.to_str(), Some("m.vm"));
        assert_eq!(a.mask.unwrap().to_str(), Some("m.npy"));
        assert_eq!(a.depth.unwrap().to_str(), Some("d.npy"));
    }

    #[test]
    fn refuses_bad_input() {
        for (s, want) in [
            ("m.vm --size 0 --out o.png", "--size 0: must be in"),
            (
                "m.vm --size x --out o.png",
                "--size 'x': not a whole number",
            ),
            (
                "m.vm --size 8 --out o.png --scale -1",
                "--scale '-1': not a positive",
            ),
            ("m.vm --out o.png", "missing --size"),
            ("m.vm --size 8", "missing --out"),
            (
                "m.vm --size 8 --out o.png --bogus",
                "unknown flag '--bogus'",
            ),
            ("m.vm --size", "--size needs a value"),
        ] {
            let e = args(s).err().unwrap_or_default();
            assert!(e.starts_with(want), "{s}: {e}");
        }
    }
}
