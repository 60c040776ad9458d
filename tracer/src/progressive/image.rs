//! The previewer's image buffer (Gamito and Maddock 2007, Section 3.5): the refinement
//! thread paints samples into it while a display thread reads whole frames, without
//! locks, and a PNG of it is the headless preview's output.

use std::path::Path;
use std::sync::atomic::{AtomicU32, Ordering};

/// The image buffer shared by the refinement and the display threads (Section 3.5):
/// `0x00RRGGBB` per pixel in relaxed atomics, so a torn frame is possible (and erased at
/// the next refresh) but there are no locks and no data races.
pub struct SharedImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    pixels: Vec<AtomicU32>,
}

impl SharedImage {
    /// A `width x height` image filled with one colour.
    pub fn new(width: u32, height: u32, rgb: [u8; 3]) -> Self {
        let c = pack(rgb);
        SharedImage {
            width,
            height,
            pixels: (0..width as usize * height as usize)
                .map(|_| AtomicU32::new(c))
                .collect(),
        }
    }
    /// Pixel `(i, j)` as `0x00RRGGBB`.
    pub fn get(&self, i: u32, j: u32) -> u32 {
        self.pixels[(j * self.width + i) as usize].load(Ordering::Relaxed)
    }
    pub(super) fn set(&self, i: u32, j: u32, c: u32) {
        self.pixels[(j * self.width + i) as usize].store(c, Ordering::Relaxed);
    }
    /// A copy as `0x00RRGGBB` words (what minifb displays).
    pub fn snapshot(&self) -> Vec<u32> {
        self.pixels
            .iter()
            .map(|p| p.load(Ordering::Relaxed))
            .collect()
    }
    /// A copy as an RGB image.
    pub fn to_rgb(&self) -> image::RgbImage {
        image::RgbImage::from_fn(self.width, self.height, |i, j| {
            image::Rgb(unpack(self.get(i, j)))
        })
    }
}

/// An RGB colour as a `0RGB` word (the window's pixel format).
pub fn pack(c: [u8; 3]) -> u32 {
    (c[0] as u32) << 16 | (c[1] as u32) << 8 | c[2] as u32
}
fn unpack(c: u32) -> [u8; 3] {
    [(c >> 16) as u8, (c >> 8) as u8, c as u8]
}

/// Writes the shared image as a PNG.
pub fn write_png(img: &SharedImage, path: &Path) -> Result<(), String> {
    if let Some(dir) = path.parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir)
                .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        }
    }
    img.to_rgb()
        .save(path)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}
