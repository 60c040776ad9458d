//! Writing images: PNG colour, depth as NPY (float32 little-endian, shape `(H, W)`) or
//! OpenEXR (one float32 channel named `Z`), chosen by extension; [`check_outputs`]
//! refuses unsupported or clashing output paths before a long render.
//! Errors name the path and say what went wrong; nothing here panics on bad paths.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// The lower-case extension of `path`, if any.
fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
}

/// Checks, before rendering, the colour output `out` (`--out`) and the depth output
/// `depth` (`--depth`): not the same file (compared by canonical parent directory and
/// file name), `out` a `.png`, `depth` a `.npy` or `.exr`, and each creatable (no file
/// is left behind where none existed). Errors are one line naming the flag and path.
pub fn check_outputs(out: &Path, depth: Option<&Path>) -> Result<(), String> {
    if let Some(d) = depth {
        if same_file(out, d) {
            return Err(format!(
                "--depth '{}': is the same file as --out '{}'",
                d.display(),
                out.display()
            ));
        }
    }
    if extension(out).as_deref() != Some("png") {
        return Err(format!(
            "--out '{}': the file must end in .png (the image is written as PNG)",
            out.display()
        ));
    }
    if let Some(d) = depth {
        if !matches!(extension(d).as_deref(), Some("npy") | Some("exr")) {
            return Err(format!(
                "--depth '{}': the file must end in .npy or .exr",
                d.display()
            ));
        }
    }
    check_writable("--out", out)?;
    if let Some(d) = depth {
        check_writable("--depth", d)?;
    }
    Ok(())
}

/// Whether `a` and `b` name one file: the same file name in the same (canonical)
/// directory; paths whose directory does not exist are compared as written.
fn same_file(a: &Path, b: &Path) -> bool {
    let key = |p: &Path| -> Option<PathBuf> {
        let name = p.file_name()?;
        let dir = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        Some(
            dir.canonicalize()
                .unwrap_or_else(|_| dir.to_path_buf())
                .join(name),
        )
    };
    a == b || matches!((key(a), key(b)), (Some(x), Some(y)) if x == y)
}

/// Errors now (with the flag's name) if `path` cannot be created; leaves no file behind
/// when it did not exist.
fn check_writable(flag: &str, path: &Path) -> Result<(), String> {
    let existed = path.exists();
    if path.is_dir() {
        return Err(format!("{flag} '{}': is a directory", path.display()));
    }
    std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(|e| format!("{flag} '{}': cannot write: {e}", path.display()))?;
    if !existed {
        let _ = std::fs::remove_file(path);
    }
    Ok(())
}

/// Writes an 8-bit RGB image as PNG.
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), String> {
    let img = image::RgbImage::from_raw(width, height, rgb.to_vec()).ok_or_else(|| {
        format!(
            "{}: image buffer does not match {width}x{height}",
            path.display()
        )
    })?;
    let f = File::create(path).map_err(|e| format!("cannot write '{}': {e}", path.display()))?;
    let mut w = BufWriter::new(f);
    img.write_to(&mut w, image::ImageFormat::Png)
        .map_err(|e| format!("cannot write '{}': {e}", path.display()))?;
    w.flush()
        .map_err(|e| format!("cannot write '{}': {e}", path.display()))
}

/// The NPY bytes (NumPy's format, written by `npyz`) of a `float32` array of shape
/// `(height, width)`, row-major.
pub fn npy_bytes(width: u32, height: u32, data: &[f32]) -> Vec<u8> {
    use npyz::WriterBuilder;
    let mut out = Vec::with_capacity(128 + data.len() * 4);
    let written = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&[u64::from(height), u64::from(width)])
        .writer(&mut out)
        .begin_nd()
        .and_then(|mut w| {
            w.extend(data.iter().copied())?;
            w.finish()
        });
    // Writing into memory cannot fail.
    debug_assert!(written.is_ok());
    out
}

/// Writes a depth map; the format follows the extension (`.npy` or `.exr`).
pub fn write_depth(path: &Path, width: u32, height: u32, depth: &[f32]) -> Result<(), String> {
    if depth.len() != width as usize * height as usize {
        return Err(format!(
            "{}: depth buffer does not match {width}x{height}",
            path.display()
        ));
    }
    match extension(path).as_deref() {
        Some("npy") => std::fs::write(path, npy_bytes(width, height, depth))
            .map_err(|e| format!("cannot write '{}': {e}", path.display())),
        Some("exr") => {
            use exr::prelude::{Encoding, Image, SpecificChannels, Vec2, WritableImage};
            let w = width as usize;
            let z = SpecificChannels::build()
                .with_channel("Z")
                .with_pixel_fn(|Vec2(x, y)| (depth[y * w + x],));
            Image::from_encoded_channels((w, height as usize), Encoding::SMALL_LOSSLESS, z)
                .write()
                .to_file(path)
                .map_err(|e| format!("cannot write '{}': {e}", path.display()))
        }
        _ => Err(format!(
            "depth file '{}' must end in .npy or .exr",
            path.display()
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn npy_header_is_valid() {
        let data = [1.0, 2.0, 3.0, 4.0, 5.0, f32::INFINITY];
        let b = npy_bytes(3, 2, &data);
        assert_eq!(&b[..6], b"\x93NUMPY");
        let npy = npyz::NpyFile::new(&b[..]).unwrap();
        assert_eq!(npy.shape(), &[2, 3]);
        assert_eq!(npy.order(), npyz::Order::C);
        assert_eq!(npy.into_vec::<f32>().unwrap(), data);
        // Little-endian float32, the data last.
        let last = f32::from_le_bytes(b[b.len() - 4..].try_into().unwrap());
        assert_eq!(last, f32::INFINITY);
    }

    #[test]
    fn bad_paths_give_errors() {
        let p = Path::new("/nonexistent-dir-xyz/a.png");
        assert!(write_png(p, 1, 1, &[0, 0, 0])
            .unwrap_err()
            .contains("/nonexistent-dir-xyz/a.png"));
        assert!(write_depth(Path::new("/tmp/d.txt"), 1, 1, &[0.0])
            .unwrap_err()
            .contains(".npy"));
        assert!(write_depth(Path::new("/nonexistent-dir-xyz/d.npy"), 1, 1, &[0.0]).is_err());
        assert!(write_depth(Path::new("/nonexistent-dir-xyz/d.exr"), 1, 1, &[0.0]).is_err());
    }

    fn tmp(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("tracer-output-test-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d.join(name)
    }

    /// The EXR depth map holds one float32 channel named `Z`, row-major from the top.
    #[test]
    fn exr_depth_is_one_z_channel() {
        let p = tmp("depth.exr");
        let depth = [1.0, 2.5, f32::INFINITY, 4.0, 0.125, 6.0];
        write_depth(&p, 3, 2, &depth).unwrap();
        let img = exr::prelude::read_all_flat_layers_from_file(&p).unwrap();
        assert_eq!(img.layer_data.len(), 1);
        let layer = &img.layer_data[0];
        assert_eq!((layer.size.0, layer.size.1), (3, 2));
        let channels = &layer.channel_data.list;
        assert_eq!(channels.len(), 1);
        assert_eq!(channels[0].name.to_string(), "Z");
        match &channels[0].sample_data {
            exr::prelude::FlatSamples::F32(v) => assert_eq!(v, &depth),
            other => panic!("not float32: {other:?}"),
        }
    }

    #[test]
    fn output_paths_are_checked() {
        let (png, npy) = (tmp("a.png"), tmp("a.npy"));
        assert!(check_outputs(&png, Some(&npy)).is_ok());
        assert!(check_outputs(&png, Some(&tmp("a.EXR"))).is_ok());
        assert!(
            !png.exists() && !npy.exists(),
            "the checks leave no file behind"
        );
        let e = check_outputs(&tmp("a.jpg"), None).unwrap_err();
        assert!(e.starts_with("--out '") && e.contains(".png"), "{e}");
        let e = check_outputs(&png, Some(&tmp("a.tif"))).unwrap_err();
        assert!(e.starts_with("--depth '"), "{e}");
        // One file under two spellings.
        let dir = npy.parent().unwrap();
        let other = dir.join("..").join(dir.file_name().unwrap()).join("a.npy");
        for (o, d) in [(&npy, &npy), (&npy, &other), (&png, &png)] {
            let e = check_outputs(o, Some(d)).unwrap_err();
            assert!(e.contains("the same file as --out"), "{e}");
        }
        let e = check_outputs(Path::new("x.png"), Some(Path::new("./x.png"))).unwrap_err();
        assert!(e.contains("the same file"), "{e}");
        assert!(check_outputs(Path::new("/nonexistent-dir-xyz/a.png"), None)
            .unwrap_err()
            .starts_with("--out '/nonexistent-dir-xyz/a.png': cannot write"));
    }
}
