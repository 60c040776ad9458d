//! Pinhole and orthographic cameras with exact pixel-centre formulas.
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
//!
//! An orthographic view ([`View::ortho`] `= Some(width)`, `width` model units across the
//! image, `width * H / W` up it) has parallel rays starting on the image plane through
//! the eye:
//!
//! ```text
//! origin = eye + (2 px / W - 1) * width/2 * right + (1 - 2 py / H) * width/2 * H/W * up'
//! dir    = forward
//! ```
//!
//! so a ray's parameter is its distance from the image plane, and nothing behind that
//! plane is seen.

use crate::shape::{check_domain, Aabb, View};
use glam::DVec3;

/// A camera for one image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position (the origin of every ray).
    pub eye: DVec3,
    /// Unit viewing direction.
    pub forward: DVec3,
    /// Unit vector to the right in the image plane.
    pub right: DVec3,
    /// `right x forward`: the true up vector of the image plane.
    pub up: DVec3,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// `tan(fov/2)`.
    pub tan_half: f64,
    /// Orthographic: the view's width in model units ([`View::ortho`]); `None` for a
    /// pinhole.
    pub ortho: Option<f64>,
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
            ortho: view.ortho,
        }
    }

    /// Like [`Camera::new`] but rejects what would give NaN or infinite directions, with
    /// a message naming the offending value: a size outside `1..=`[`MAX_SIDE`], a field
    /// of view outside (0, 180) degrees, non-finite points, an eye at the look-at point,
    /// an up vector that is zero or parallel to the viewing direction, and points or
    /// vectors so large or so small that the differences, lengths or normalisations of
    /// the set-up overflow or underflow.
    pub fn try_new(view: View, width: u32, height: u32) -> Result<Self, String> {
        check_size(width, height)?;
        if let Some(w) = view.ortho {
            // The image plane's half extents and the origins on it must be finite.
            let half = 0.5 * w * (1.0f64).max(height as f64 / width as f64);
            let reach = view.eye.abs().max_element() + half;
            if !(w > 0.0 && w.is_finite() && reach.is_finite()) {
                return Err(format!(
                    "orthographic view width {w} is not a positive number small enough to                      place the image plane"
                ));
            }
        } else if !(view.fov_deg > 0.0 && view.fov_deg < 180.0) {
            return Err(format!(
                "field of view {} is not in (0, 180) degrees",
                view.fov_deg
            ));
        }
        check_view(&view)?;
        Ok(Camera::new(view, width, height))
    }

    /// The un-normalised direction `forward + dx*right + dy*up'` through continuous pixel
    /// coordinates `(px, py)`. Its component along `forward` is exactly 1 (up to rounding),
    /// which `tracer::search::cull` uses: distance along `forward` parametrises a bundle.
    /// Orthographic: `forward` for every pixel.
    #[inline]
    pub fn raw_dir(&self, px: f64, py: f64) -> DVec3 {
        if self.ortho.is_some() {
            return self.forward;
        }
        let w = self.width as f64;
        let h = self.height as f64;
        let dx = (2.0 * px / w - 1.0) * self.tan_half * (w / h);
        let dy = (1.0 - 2.0 * py / h) * self.tan_half;
        self.forward + self.right * dx + self.up * dy
    }

    /// Where the ray through continuous pixel coordinates `(px, py)` starts: the eye of
    /// a pinhole, the point of the image plane of an orthographic view (affine in
    /// `(px, py)`, which `tracer::search::cull` uses).
    #[inline]
    pub fn origin_at(&self, px: f64, py: f64) -> DVec3 {
        match self.ortho {
            None => self.eye,
            Some(width) => {
                let (w, h) = (self.width as f64, self.height as f64);
                let hw = 0.5 * width;
                let hh = hw * (h / w);
                let dx = (2.0 * px / w - 1.0) * hw;
                let dy = (1.0 - 2.0 * py / h) * hh;
                self.eye + self.right * dx + self.up * dy
            }
        }
    }

    /// The ray through continuous pixel coordinates: `(origin, normalised direction)`.
    #[inline]
    pub fn ray_at(&self, px: f64, py: f64) -> (DVec3, DVec3) {
        (self.origin_at(px, py), self.raw_dir(px, py).normalize())
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
    /// distance 1: the footprint of a pixel at distance `t` is about `t * pixel_angle()`
    /// (0 for an orthographic view, whose footprint is [`Camera::pixel_size`]).
    pub fn pixel_angle(&self) -> f64 {
        if self.ortho.is_some() {
            return 0.0;
        }
        2.0 * self.tan_half / self.height as f64
    }

    /// The side of a pixel's footprint in model units at every distance, for an
    /// orthographic view; 0 for a pinhole (see [`Camera::pixel_angle`]).
    pub fn pixel_size(&self) -> f64 {
        self.ortho.map_or(0.0, |w| w / self.width as f64)
    }
}

/// The largest image side in pixels that the renderers accept (the CLI's `--size`
/// limit too): a 16384 x 16384 image already needs about 2 GB of buffers.
pub const MAX_SIDE: u32 = 16384;

/// `Ok` for an image of `width x height` pixels with each side in `1..=MAX_SIDE`.
pub fn check_size(width: u32, height: u32) -> Result<(), String> {
    if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
        return Err(format!(
            "image size {width}x{height} is out of range: each side must be 1 to {MAX_SIDE} \
             pixels"
        ));
    }
    Ok(())
}

/// A point or vector as the messages show it.
fn show(v: DVec3) -> String {
    format!("({:?}, {:?}, {:?})", v.x, v.y, v.z)
}

/// Checks the differences, lengths and normalisations [`Camera::new`] computes from
/// `view` (the field of view aside).
fn check_view(view: &View) -> Result<(), String> {
    for (name, v) in [
        ("eye", view.eye),
        ("look-at point", view.look_at),
        ("up vector", view.up),
    ] {
        if !v.is_finite() {
            return Err(format!("the {name} {} is not finite", show(v)));
        }
    }
    let (eye, at) = (show(view.eye), show(view.look_at));
    let f = view.look_at - view.eye;
    if f == DVec3::ZERO {
        return Err(format!("the eye and the look-at point coincide at {eye}"));
    }
    if !f.is_finite() || !f.length().is_finite() {
        return Err(format!(
            "the eye {eye} is too far from the look-at point {at} to set up the view: \
             their distance overflows"
        ));
    }
    let forward = f.normalize();
    if f.length() == 0.0 || !forward.is_finite() {
        return Err(format!(
            "the eye {eye} is too close to the look-at point {at} to set up the view: \
             their distance underflows"
        ));
    }
    let up = show(view.up);
    let ul = view.up.length();
    if view.up == DVec3::ZERO {
        return Err("the up vector is zero".into());
    }
    if !ul.is_finite() {
        return Err(format!(
            "the up vector {up} is too long to set up the view: its length overflows"
        ));
    }
    if ul == 0.0 {
        return Err(format!(
            "the up vector {up} is too short to set up the view: its length underflows"
        ));
    }
    let c = forward.cross(view.up);
    if c.length() < 1e-9 * ul || !c.normalize().is_finite() {
        return Err(format!(
            "the up vector {up} is parallel to the viewing direction from {eye} to {at}"
        ));
    }
    Ok(())
}

/// A three-quarter view of `domain` (up +y, 35 degree field of view) from far enough
/// to see its whole bounding sphere; an error when the box is not finite, empty, or so
/// large that its diagonal or the eye's distance overflows.
pub fn frame_box(domain: &Aabb) -> Result<View, String> {
    check_domain(domain)?;
    let c = (domain.min + domain.max) * 0.5;
    let r = (domain.max - domain.min).length() * 0.5;
    let fov: f64 = 35.0;
    let dist = r / (fov.to_radians() * 0.5).sin() * 1.05;
    let view = View {
        eye: c + DVec3::new(1.0, 0.8, 1.6).normalize() * dist,
        look_at: c,
        up: DVec3::Y,
        fov_deg: fov,
        ortho: None,
    };
    if !(c.is_finite() && dist.is_finite()) || check_view(&view).is_err() {
        return Err(
            "the box is too large to frame a view of it: the eye's distance overflows".into(),
        );
    }
    Ok(view)
}

/// Closest angle, in radians, that [`orbit`] lets the viewing direction come to `up` or
/// to `-up` (there the image's up direction is undefined).
pub const ORBIT_POLE_MARGIN: f64 = 0.05;

/// `view` turned about its point looked at: by `yaw` radians about its up vector, then
/// by `pitch` radians about the image's right vector (positive: the eye rises), stopping
/// [`ORBIT_POLE_MARGIN`] short of the up vector's poles. The distance to the point looked
/// at is kept. The window's drag with the right button.
pub fn orbit(view: &View, yaw: f64, pitch: f64) -> View {
    let up = view.up.normalize_or_zero();
    let off = view.eye - view.look_at;
    let (r, dir) = (off.length(), off.normalize_or_zero());
    if up == DVec3::ZERO || dir == DVec3::ZERO || !(yaw.is_finite() && pitch.is_finite()) {
        return *view;
    }
    // Polar angle from up, and the direction around it.
    let polar = dir.dot(up).clamp(-1.0, 1.0).acos();
    let flat = (dir - up * dir.dot(up)).normalize_or_zero();
    let flat = if flat == DVec3::ZERO {
        up.any_orthonormal_vector()
    } else {
        flat
    };
    let side = up.cross(flat);
    let (s, c) = yaw.sin_cos();
    let flat = flat * c + side * s;
    let polar = (polar - pitch).clamp(ORBIT_POLE_MARGIN, std::f64::consts::PI - ORBIT_POLE_MARGIN);
    let dir = up * polar.cos() + flat * polar.sin();
    View {
        eye: view.look_at + dir * r,
        ..*view
    }
}

/// `view` moved towards its point looked at so that the distance (and an orthographic
/// view's width) is `factor` times what it was: `factor < 1` zooms in. The window's
/// mouse wheel. A factor that is not positive and finite changes nothing.
pub fn zoom(view: &View, factor: f64) -> View {
    if !(factor.is_finite() && factor > 0.0) {
        return *view;
    }
    View {
        eye: view.look_at + (view.eye - view.look_at) * factor,
        ortho: view.ortho.map(|w| w * factor),
        ..*view
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_keeps_the_distance_and_stops_short_of_the_poles() {
        let v = View {
            eye: DVec3::new(1.0, 2.0, 3.0),
            look_at: DVec3::new(0.5, -1.0, 0.0),
            ..view()
        };
        let r = (v.eye - v.look_at).length();
        // A quarter turn about +y moves the eye from +z towards +x.
        let q = orbit(&view(), std::f64::consts::FRAC_PI_2, 0.0);
        assert!(
            (q.eye - DVec3::new(5.0, 0.0, 0.0)).length() < 1e-12,
            "{:?}",
            q.eye
        );
        for (yaw, pitch) in [(0.3, 0.2), (-2.0, 1.0), (0.0, 10.0), (1.0, -10.0)] {
            let o = orbit(&v, yaw, pitch);
            assert_eq!((o.look_at, o.up, o.fov_deg), (v.look_at, v.up, v.fov_deg));
            assert!(((o.eye - o.look_at).length() - r).abs() < 1e-12 * r);
            let polar = (o.eye - o.look_at).normalize().dot(DVec3::Y).acos();
            assert!(polar >= ORBIT_POLE_MARGIN - 1e-12);
            assert!(polar <= std::f64::consts::PI - ORBIT_POLE_MARGIN + 1e-12);
            check_view(&o).unwrap();
        }
        // Turning up and down again comes back (off the poles).
        let back = orbit(&orbit(&v, 0.0, 0.4), 0.0, -0.4);
        assert!((back.eye - v.eye).length() < 1e-12 * r);
        // Nothing to turn about: unchanged.
        assert_eq!(
            orbit(
                &View {
                    eye: v.look_at,
                    ..v
                },
                1.0,
                1.0
            )
            .eye,
            v.look_at
        );
    }

    #[test]
    fn zoom_scales_the_distance_and_the_ortho_width() {
        let v = View {
            ortho: Some(2.0),
            ..view()
        };
        let z = zoom(&v, 0.5);
        assert_eq!(z.eye, DVec3::new(0.0, 0.0, 2.5));
        assert_eq!(z.ortho, Some(1.0));
        assert_eq!(zoom(&v, 0.0), v);
        assert_eq!(zoom(&v, f64::NAN), v);
    }

    fn view() -> View {
        View {
            eye: DVec3::new(0.0, 0.0, 5.0),
            look_at: DVec3::ZERO,
            up: DVec3::Y,
            fov_deg: 90.0,
            ortho: None,
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
            ortho: None,
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

    /// Overflowing or underflowing differences and lengths are named as such, not as a
    /// coincident eye or a parallel up vector.
    #[test]
    fn overflowing_views_say_what_overflows() {
        let err = |v: View| Camera::try_new(v, 4, 4).unwrap_err();
        let mut v = view();
        v.eye = DVec3::splat(1e308);
        let e = err(v);
        assert!(
            e.contains("too far") && e.contains("(1e308, 1e308, 1e308)"),
            "{e}"
        );
        let mut v = view();
        v.eye = DVec3::new(-1e308, 0.0, 0.0);
        v.look_at = DVec3::new(1e308, 0.0, 0.0);
        assert!(err(v).contains("too far"));
        let mut v = view();
        v.eye = DVec3::new(0.0, 0.0, 1e-200);
        assert!(err(v).contains("too close"));
        let mut v = view();
        v.up = DVec3::new(1e300, 1e300, 0.0);
        assert!(err(v).contains("too long"));
        let mut v = view();
        v.up = DVec3::new(1e-200, 1e-200, 0.0);
        assert!(err(v).contains("too short"));
        let mut v = view();
        v.up = DVec3::new(0.0, 0.0, 1e100);
        assert!(err(v).contains("parallel"));
        assert!(err(View {
            up: DVec3::ZERO,
            ..view()
        })
        .contains("zero"));
        // Far but representable views still work.
        let mut v = view();
        v.eye = DVec3::new(0.0, 0.0, 1e150);
        v.up = DVec3::new(0.0, 1e150, 0.0);
        assert!(Camera::try_new(v, 4, 4).is_ok());
    }

    #[test]
    fn sizes_up_to_the_limit() {
        assert!(check_size(MAX_SIDE, MAX_SIDE).is_ok() && check_size(1, 1).is_ok());
        for (w, h) in [(0, 1), (1, 0), (MAX_SIDE + 1, 1), (1, 100_000)] {
            assert!(check_size(w, h).unwrap_err().contains(&format!("{w}x{h}")));
            assert!(Camera::try_new(view(), w, h).is_err());
        }
    }

    #[test]
    fn framing_a_box() {
        let v = frame_box(&Aabb::cube(2.0)).unwrap();
        assert_eq!(v.look_at, DVec3::ZERO);
        assert!(Camera::try_new(v, 4, 4).is_ok());
        assert!(frame_box(&Aabb::cube(1e300))
            .unwrap_err()
            .contains("diagonal overflows"));
        assert!(frame_box(&Aabb::cube(3e153))
            .unwrap_err()
            .contains("eye's distance overflows"));
        assert!(frame_box(&Aabb::new(DVec3::ONE, DVec3::ZERO)).is_err());
    }
}
