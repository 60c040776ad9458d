//! Writing images: PNG colour, depth as NPY (float32 little-endian, shape `(H, W)`) or
//! OpenEXR (a float RGB image with the depth in every channel), chosen by extension.
//! Errors name the path and say what went wrong; nothing here panics on bad paths.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

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

/// The NPY v1.0 bytes of a `float32` array of shape `(height, width)`, row-major.
pub fn npy_bytes(width: u32, height: u32, data: &[f32]) -> Vec<u8> {
    let mut header =
        format!("{{'descr': '<f4', 'fortran_order': False, 'shape': ({height}, {width}), }}");
    // magic (6) + version (2) + header length (2) + header, padded with spaces and ended
    // by a newline so the data starts on a 64-byte boundary.
    let unpadded = 10 + header.len() + 1;
    let pad = (64 - unpadded % 64) % 64;
    header.push_str(&" ".repeat(pad));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len() + data.len() * 4);
    out.extend_from_slice(b"\x93NUMPY");
    out.extend_from_slice(&[1, 0]);
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    for v in data {
        out.extend_from_slice(&v.to_le_bytes());
    }
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
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    match ext.as_deref() {
        Some("npy") => std::fs::write(path, npy_bytes(width, height, depth))
            .map_err(|e| format!("cannot write '{}': {e}", path.display())),
        Some("exr") => {
            let data: Vec<f32> = depth.iter().flat_map(|&d| [d, d, d]).collect();
            let img = image::Rgb32FImage::from_raw(width, height, data).ok_or_else(|| {
                format!(
                    "{}: depth buffer does not match {width}x{height}",
                    path.display()
                )
            })?;
            let f = File::create(path)
                .map_err(|e| format!("cannot write '{}': {e}", path.display()))?;
            let mut w = BufWriter::new(f);
            image::DynamicImage::ImageRgb32F(img)
                .write_to(&mut w, image::ImageFormat::OpenExr)
                .map_err(|e| format!("cannot write '{}': {e}", path.display()))?;
            w.flush()
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
        let b = npy_bytes(3, 2, &[1.0, 2.0, 3.0, 4.0, 5.0, f32::INFINITY]);
        assert_eq!(&b[..6], b"\x93NUMPY");
        assert_eq!(&b[6..8], &[1, 0]);
        let hl = u16::from_le_bytes([b[8], b[9]]) as usize;
        assert_eq!((10 + hl) % 64, 0);
        let h = std::str::from_utf8(&b[10..10 + hl]).unwrap();
        assert!(h.contains("'shape': (2, 3)") && h.contains("'<f4'") && h.ends_with('\n'));
        assert_eq!(b.len(), 10 + hl + 6 * 4);
        let last = f32::from_le_bytes(b[b.len() - 4..].try_into().unwrap());
        assert_eq!(last, f32::INFINITY);
        let first = f32::from_le_bytes(b[10 + hl..14 + hl].try_into().unwrap());
        assert_eq!(first, 1.0);
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
    }
}
