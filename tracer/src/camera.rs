//! Pinhole camera with the issue's exact pixel-centre formula.
//!
//! Pixel column `i` counts from the left, row `j` from the top. For continuous pixel
//! coordinates `(px, py)` (pixel `(i, j)` covers `[i, i+1) x [j, j+1)`, its centre is
//! `(i + 0.5, j + 0.5)`):
//!
//! ```text
//! dx  = (2 px / W - 1) * tan(fov/2) * W/H
//! dy  = (1 - 2 py / H) * tan(fov/2)
//! dir = normalize(forward + dx * right + dy * up')
//! forward = normalize(look_at - eye), right = normalize(forward x up), up' = right x forward
//! ```

use crate::shape::View;
use glam::DVec3;

/// A camera for one image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: DVec3,
    pub forward: DVec3,
    pub right: DVec3,
    /// `right x forward`: the true up vector of the image plane.
    pub up: DVec3,
    pub width: u32,
    pub height: u32,
    /// `tan(fov/2)`.
    pub tan_half: f64,
}

impl Camera {
    /// A camera placed by `view` rendering a `width x height` image.
    ///
    /// A degenerate view (eye at the look-at point, up parallel to the view direction,
    /// zero size) gives NaN directions; use [`Camera::try_new`] for user input.
    pub fn new(view: View, width: u32, height: u32) -> Self {
        let forward = (view.look_at - view.eye).normalize();
        let right = forward.cross(view.up).normalize();
        let up = right.cross(forward);
        Camera {
            eye: view.eye,
            forward,
            right,
            up,
            width,
            height,
            tan_half: (view.fov_deg.to_radians() * 0.5).tan(),
        }
    }

    /// Like [`Camera::new`] but rejects degenerate views with a message.
    pub fn try_new(view: View, width: u32, height: u32) -> Result<Self, String> {
        if width == 0 || height == 0 {
            return Err(format!("image size {width}x{height} is empty"));
        }
        if !(view.fov_deg > 0.0 && view.fov_deg < 180.0) {
            return Err(format!(
                "field of view {} is not in (0, 180) degrees",
                view.fov_deg
            ));
        }
        let f = view.look_at - view.eye;
        if !f.is_finite() || f.length() == 0.0 {
            return Err("the eye and the look-at point coincide".into());
        }
        let c = f.normalize().cross(view.up);
        if !c.is_finite() || c.length() < 1e-9 * view.up.length().max(1e-300) {
            return Err("the up vector is zero or parallel to the viewing direction".into());
        }
        Ok(Camera::new(view, width, height))
    }

    /// The un-normalised direction `forward + dx*right + dy*up'` through continuous pixel
    /// coordinates `(px, py)`. Its component along `forward` is exactly 1 (up to rounding),
    /// which [`crate::search::cull`] uses: distance along `forward` parametrises a bundle.
    #[inline]
    pub fn raw_dir(&self, px: f64, py: f64) -> DVec3 {
        let w = self.width as f64;
        let h = self.height as f64;
        let dx = (2.0 * px / w - 1.0) * self.tan_half * (w / h);
        let dy = (1.0 - 2.0 * py / h) * self.tan_half;
        self.forward + self.right * dx + self.up * dy
    }

    /// The ray through continuous pixel coordinates: `(origin, normalised direction)`.
    #[inline]
    pub fn ray_at(&self, px: f64, py: f64) -> (DVec3, DVec3) {
        (self.eye, self.raw_dir(px, py).normalize())
    }

    /// The ray through the centre of pixel `(i, j)`: `(origin, normalised direction)`.
    #[inline]
    pub fn ray(&self, i: u32, j: u32) -> (DVec3, DVec3) {
        self.ray_at(i as f64 + 0.5, j as f64 + 0.5)
    }

    /// [`Camera::ray`] for four pixels at once, with what setting up their searches
    /// needs: `(direction, its reciprocal, direction . forward, 1 / (direction . forward))`
    /// per pixel, each bit for bit the scalar `ray(i, j).1`, `.recip()`, `.dot(forward)`
    /// and `1.0 / d.dot(forward)` (the same
    /// IEEE operations; the square roots and divisions run in SIMD lanes, where they
    /// were an eighth of a cheap model's render).
    pub fn rays4(&self, pixels: [(u32, u32); 4]) -> [(DVec3, DVec3, f64, f64); 4] {
        use wide::f64x4;
        let raw = pixels.map(|(i, j)| self.raw_dir(i as f64 + 0.5, j as f64 + 0.5));
        // `DVec3::normalize`: `v * (1 / sqrt(v . v))`.
        let len2 = f64x4::new(raw.map(|v| v.dot(v)));
        let r = (f64x4::splat(1.0) / len2.sqrt()).to_array();
        let d: [DVec3; 4] = core::array::from_fn(|l| raw[l] * r[l]);
        let recip = |c: [f64; 4]| (f64x4::splat(1.0) / f64x4::new(c)).to_array();
        let (ix, iy, iz) = (
            recip(d.map(|v| v.x)),
            recip(d.map(|v| v.y)),
            recip(d.map(|v| v.z)),
        );
        let c = d.map(|v| v.dot(self.forward));
        let ic = recip(c);
        core::array::from_fn(|l| (d[l], DVec3::new(ix[l], iy[l], iz[l]), c[l], ic[l]))
    }

    /// Angular size of one pixel (vertical), in radians-ish units of the image plane at
    /// distance 1: the footprint of a pixel at distance `t` is about `t * pixel_angle()`.
    pub fn pixel_angle(&self) -> f64 {
        2.0 * self.tan_half / self.height as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view() -> View {
        View {
            eye: DVec3::new(0.0, 0.0, 5.0),
            look_at: DVec3::ZERO,
            up: DVec3::Y,
            fov_deg: 90.0,
        }
    }

    #[test]
    fn centre_and_corners_follow_the_formula() {
        let cam = Camera::new(view(), 4, 2);
        // forward is -z, right is +x, up' is +y.
        assert!((cam.forward - DVec3::new(0.0, 0.0, -1.0)).length() < 1e-15);
        assert!((cam.right - DVec3::X).length() < 1e-15);
        assert!((cam.up - DVec3::Y).length() < 1e-15);
        // The image centre looks straight ahead.
        let (o, d) = cam.ray_at(2.0, 1.0);
        assert_eq!(o, DVec3::new(0.0, 0.0, 5.0));
        assert!((d - DVec3::new(0.0, 0.0, -1.0)).length() < 1e-15);
        // Pixel (0, 0): dx = (2*0.5/4 - 1) * 1 * 2 = -1.5, dy = (1 - 2*0.5/2) * 1 = 0.5.
        let (_, d) = cam.ray(0, 0);
        let e = DVec3::new(-1.5, 0.5, -1.0).normalize();
        assert!((d - e).length() < 1e-15, "{d:?} vs {e:?}");
    }

    /// `rays4` is the scalar set-up, bit for bit: straight views (directions with exact
    /// zero components, so infinite reciprocals), oblique ones, odd sizes, every pixel.
    #[test]
    fn four_rays_at_once_are_the_scalar_rays() {
        let oblique = View {
            eye: DVec3::new(1.3, -2.7, 4.1),
            look_at: DVec3::new(-0.2, 0.4, 0.1),
            up: DVec3::new(0.1, 1.0, 0.3),
            fov_deg: 37.0,
        };
        let bits = |v: DVec3| v.to_array().map(f64::to_bits);
        let mut checked = 0;
        for (v, w, h) in [
            (view(), 4, 2),
            (view(), 7, 5),
            (oblique, 33, 17),
            (oblique, 1, 1),
        ] {
            let cam = Camera::new(v, w, h);
            let pixels: Vec<(u32, u32)> =
                (0..h).flat_map(|j| (0..w).map(move |i| (i, j))).collect();
            for chunk in pixels.chunks(4) {
                let four = core::array::from_fn(|l| chunk[l.min(chunk.len() - 1)]);
                for (&(i, j), &(d, inv, c, ic)) in chunk.iter().zip(&cam.rays4(four)) {
                    let (_, e) = cam.ray(i, j);
                    assert_eq!(bits(d), bits(e), "pixel ({i}, {j})");
                    assert_eq!(bits(inv), bits(e.recip()), "pixel ({i}, {j})");
                    assert_eq!(c.to_bits(), e.dot(cam.forward).to_bits());
                    assert_eq!(ic.to_bits(), (1.0 / e.dot(cam.forward)).to_bits());
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 8 + 35 + 33 * 17 + 1);
        // The centre of a straight view: its direction has exact zeros.
        let cam = Camera::new(view(), 7, 5);
        let (d, inv, _, _) = cam.rays4([(3, 2); 4])[0];
        assert_eq!((d.x, d.y), (0.0, 0.0));
        assert!(inv.x.is_infinite() && inv.y.is_infinite());
    }

    #[test]
    fn degenerate_views_are_rejected() {
        let mut v = view();
        v.up = DVec3::Z;
        assert!(Camera::try_new(v, 4, 4).is_err());
        assert!(Camera::try_new(view(), 0, 4).is_err());
        let mut v = view();
        v.look_at = v.eye;
        assert!(Camera::try_new(v, 4, 4).is_err());
        assert!(Camera::try_new(view(), 4, 4).is_ok());
    }
}
