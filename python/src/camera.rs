//! `tracer.Camera`: a camera placement (the tracer's `View`), pinhole or orthographic,
//! with the orbit and zoom of the previewer's window.

use crate::args::vec3;
use crate::toolkit::camera::{frame_box, orbit, zoom};
use crate::toolkit::{DVec3, View};
use pyo3::prelude::*;

type Vec3 = (f64, f64, f64);

/// A camera placement: the eye, the point looked at (the image's centre), the up
/// direction, the vertical field of view in degrees, and ``ortho``: ``None`` for a
/// pinhole at the eye, or the width in model units of an orthographic view (parallel
/// rays from the image plane through the eye).
///
/// >>> cam = Camera((0, 0, 5), fov=30)
/// >>> cam.look_at
/// (0.0, 0.0, 0.0)
/// >>> side = cam.orbit(90)  # a quarter turn about the up direction
/// >>> [round(c, 9) + 0.0 for c in side.eye]
/// [5.0, 0.0, 0.0]
#[pyclass(module = "tracer", name = "Camera", frozen)]
#[derive(Clone)]
pub struct PyCamera {
    pub view: View,
}

#[pymethods]
impl PyCamera {
    #[new]
    #[pyo3(signature = (eye, look_at=None, up=None, fov=35.0, ortho=None))]
    fn new(
        eye: &Bound<'_, PyAny>,
        look_at: Option<&Bound<'_, PyAny>>,
        up: Option<&Bound<'_, PyAny>>,
        fov: f64,
        ortho: Option<f64>,
    ) -> PyResult<Self> {
        let view = View {
            eye: vec3("eye", eye)?,
            look_at: look_at
                .map(|v| vec3("look_at", v))
                .transpose()?
                .unwrap_or(DVec3::ZERO),
            up: up.map(|v| vec3("up", v)).transpose()?.unwrap_or(DVec3::Y),
            fov_deg: fov,
            ortho,
        };
        Ok(PyCamera { view })
    }

    /// The camera that frames ``domain`` (six numbers or two corners) as a model's
    /// default view does: a three-quarter view, up +y, 35 degrees.
    #[staticmethod]
    fn framing(domain: &Bound<'_, PyAny>) -> PyResult<Self> {
        let d = crate::args::domain("domain", domain)?;
        let view = frame_box(&d).map_err(|e| crate::args::value_error("domain", e))?;
        Ok(PyCamera { view })
    }

    /// The eye position.
    #[getter]
    fn eye(&self) -> Vec3 {
        self.view.eye.into()
    }

    /// The point at the image's centre.
    #[getter]
    fn look_at(&self) -> Vec3 {
        self.view.look_at.into()
    }

    /// The up direction (need not be orthogonal to the viewing direction).
    #[getter]
    fn up(&self) -> Vec3 {
        self.view.up.into()
    }

    /// The vertical field of view in degrees (unused by an orthographic view).
    #[getter]
    fn fov(&self) -> f64 {
        self.view.fov_deg
    }

    /// The orthographic view's width in model units, or ``None`` for a pinhole.
    #[getter]
    fn ortho(&self) -> Option<f64> {
        self.view.ortho
    }

    /// The camera turned about the point looked at: ``yaw`` degrees about the up
    /// direction, then ``pitch`` degrees up (stopping short of the poles); the
    /// distance is kept.
    #[pyo3(signature = (yaw, pitch=0.0))]
    fn orbit(&self, yaw: f64, pitch: f64) -> Self {
        PyCamera {
            view: orbit(&self.view, yaw.to_radians(), pitch.to_radians()),
        }
    }

    /// The camera moved towards the point looked at to ``factor`` times the distance
    /// (an orthographic width scales alike): below 1 zooms in.
    fn zoom(&self, factor: f64) -> Self {
        PyCamera {
            view: zoom(&self.view, factor),
        }
    }

    fn __repr__(&self) -> String {
        let v = &self.view;
        let p = |d: DVec3| format!("({:?}, {:?}, {:?})", d.x, d.y, d.z);
        let ortho = v.ortho.map_or("None".into(), |w| format!("{w:?}"));
        format!(
            "Camera(eye={}, look_at={}, up={}, fov={:?}, ortho={ortho})",
            p(v.eye),
            p(v.look_at),
            p(v.up),
            v.fov_deg
        )
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyCamera>()
            .is_ok_and(|o| o.get().view == self.view)
    }

    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, (Vec3, Vec3, Vec3, f64, Option<f64>))> {
        let v = slf.get().view;
        Ok((
            slf.get_type().into_any(),
            (
                v.eye.into(),
                v.look_at.into(),
                v.up.into(),
                v.fov_deg,
                v.ortho,
            ),
        ))
    }
}
