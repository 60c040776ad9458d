//! `tracer.Shape`: a model of the registry (formula, model file, built-in) with its
//! domain and default camera, evaluated at points and over boxes, one at a time or in
//! numpy batches ([`crate::batch`]) with the GIL released.

use crate::args::{closed_box, corners, domain as domain_arg, xyz_array};
use crate::batch::{eval_boxes_kind, eval_points};
use crate::camera::PyCamera;
use crate::detached::{run, Report};
use crate::sources::Source;
use crate::toolkit::models::{builtin_names, Model};
use crate::toolkit::{with_arith, Aabb, ArithKind, Arithmetic, Range, Shape};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::AtomicBool;

/// Batches up to this many points or boxes run on the calling thread (the GIL
/// released); larger ones on a worker, Ctrl-C stopping them.
const INLINE: usize = 1 << 15;

type Corners = ((f64, f64, f64), (f64, f64, f64));

/// An implicit surface ``f(x, y, z) = 0`` (``f >= 0`` inside) with the box it lives in
/// (``domain``) and a default ``camera``.
///
/// ``Shape(formula, domain=None)`` parses a formula over ``x, y, z`` (the language of
/// ``tracer render --expr``; domain ``[-2, 2]^3`` unless given); ``Shape.file(path)``
/// reads a model file (``.expr``, ``.vm``, ``.hf``); ``Shape.builtin(name)`` is a
/// built-in model (``tracer.models()`` lists them). A reader's error raises
/// :class:`ModelError` (a ``ValueError``) with its ``line`` and ``column``.
///
/// ``shape(x, y, z)`` evaluates at floats, or over values of one number type
/// (``Interval``, ``RevAffine``, ...; floats mixed in are constants) and returns that
/// type; ``range``, ``eval`` and ``eval_boxes`` evaluate over a box, and over numpy
/// batches of points and boxes.
///
/// >>> ball = Shape("1 - x^2 - y^2 - z^2")
/// >>> ball(0.5, 0, 0)
/// 0.75
/// >>> lo, hi = ball.range(((0, 0, 0), (1, 1, 1)), arith="ia")
/// >>> (lo, hi)
/// (-2.0, 1.0)
/// >>> import numpy as np
/// >>> ball.eval(np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]]))
/// array([ 1., -1.])
#[pyclass(module = "tracer", name = "Shape", frozen)]
pub struct PyShape {
    pub model: Model,
    source: Source,
    /// The domain given when it was made (kept for pickling).
    domain: Option<Aabb>,
}

impl PyShape {
    fn make(py: Python<'_>, source: Source, domain: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        let domain = domain.map(|d| domain_arg("domain", d)).transpose()?;
        let model = source.load(py, domain)?;
        Ok(PyShape {
            model,
            source,
            domain,
        })
    }
}

#[pymethods]
impl PyShape {
    #[new]
    #[pyo3(signature = (formula, domain=None))]
    fn new(py: Python<'_>, formula: String, domain: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        PyShape::make(py, Source::Formula(formula), domain)
    }

    /// The built-in model ``name`` (see :func:`tracer.models`), over ``domain`` if
    /// given (the model keeps its camera).
    #[staticmethod]
    #[pyo3(signature = (name, domain=None))]
    fn builtin(py: Python<'_>, name: String, domain: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        PyShape::make(py, Source::Builtin(name), domain)
    }

    /// The model file at ``path``: a formula (``.expr``), a fidget tape (``.vm``) or a
    /// HyperFun program (``.hf``), the format taken from the extension unless
    /// ``format`` (``"expr"``, ``"vm"``, ``"hf"``) says. A header's ``domain:`` and
    /// ``view:`` lines are read; ``domain`` overrides the domain.
    #[staticmethod]
    #[pyo3(signature = (path, format=None, domain=None))]
    fn file(
        py: Python<'_>,
        path: std::path::PathBuf,
        format: Option<&str>,
        domain: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let path = path.to_string_lossy();
        PyShape::make(py, Source::file(&path, format)?, domain)
    }

    /// A model file's text in ``format`` (``"expr"``, ``"vm"``, ``"hf"``); ``name``
    /// stands for the file in messages.
    #[staticmethod]
    #[pyo3(signature = (text, format="expr", domain=None, name="<text>"))]
    fn from_text(
        py: Python<'_>,
        text: String,
        format: &str,
        domain: Option<&Bound<'_, PyAny>>,
        name: &str,
    ) -> PyResult<Self> {
        let source = Source::Text {
            text,
            format: format.to_string(),
            path: name.to_string(),
        };
        PyShape::make(py, source, domain)
    }

    /// The model's name (``expr`` for a formula, the file's stem for a file).
    #[getter]
    fn name(&self) -> &str {
        &self.model.name
    }

    /// A one-line description.
    #[getter]
    fn description(&self) -> &str {
        &self.model.description
    }

    /// The function as a formula, where the model has one (noise models have none).
    #[getter]
    fn formula(&self) -> Option<String> {
        self.model.shape.formula()
    }

    /// The box the function is considered in, ``((xmin, ymin, zmin), (xmax, ymax,
    /// zmax))``: renders clip rays to it, meshes are closed by it.
    #[getter]
    fn domain(&self) -> Corners {
        corners(&self.model.domain)
    }

    /// The default camera, framing the domain (or the model's own view).
    #[getter]
    fn camera(&self) -> PyCamera {
        PyCamera {
            view: self.model.view,
        }
    }

    /// A Lipschitz bound of ``f`` over the domain, where one is known.
    #[getter]
    fn lipschitz(&self) -> Option<f64> {
        self.model.lipschitz
    }

    /// ``f(x, y, z)`` at floats, or over values of one number type (``Interval``,
    /// ``RevAffine``, ...; floats mixed in are constants), returning that type.
    fn __call__(
        &self,
        py: Python<'_>,
        x: &Bound<'_, PyAny>,
        y: &Bound<'_, PyAny>,
        z: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        crate::numbers::eval_at(py, &self.model.shape, [x, y, z])?.ok_or_else(|| {
            PyTypeError::new_err(
                "shape(x, y, z): expected floats, or values of one number type \
                 (Interval, Affine, ReducedAffine, RevAffine, Hull) mixed with floats",
            )
        })
    }

    /// The bounds ``(lo, hi)`` of ``f`` over ``box`` (six numbers or two corners;
    /// default: the domain) in the arithmetic ``arith`` (``ia``, ``aa``, ``raa``,
    /// ``revaa``, ``hull``), or a dict of every arithmetic's bounds for ``"all"``.
    #[pyo3(signature = (r#box=None, arith="ia"))]
    fn range(
        &self,
        py: Python<'_>,
        r#box: Option<&Bound<'_, PyAny>>,
        arith: &str,
    ) -> PyResult<Py<PyAny>> {
        let b = match r#box {
            Some(b) => closed_box("box", b)?,
            None => self.model.domain,
        };
        let over = |k: ArithKind| with_arith!(k, A => range_over::<A, _>(&self.model.shape, &b));
        if arith.eq_ignore_ascii_case("all") {
            let d = PyDict::new(py);
            for k in ArithKind::ALL {
                d.set_item(k.name(), over(k))?;
            }
            return Ok(d.into_any().unbind());
        }
        let k = crate::args::arith(arith)?;
        Ok(over(k).into_pyobject(py)?.into_any().unbind())
    }

    /// ``f`` at each row of ``xyz``, a C-contiguous float64 array of shape ``(N, 3)``:
    /// an array of shape ``(N,)``. Evaluated in batches over all cores, the GIL
    /// released.
    fn eval<'py>(
        &self,
        py: Python<'py>,
        xyz: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let xyz = xyz_array("xyz", xyz)?;
        let p = xyz.as_slice()?;
        let n = p.len() / 3;
        let shape = &self.model.shape;
        let work = |cancel: &AtomicBool| {
            let mut out = vec![0.0; n];
            eval_points(shape, p, &mut out, cancel);
            out
        };
        let out = if n <= INLINE {
            py.detach(|| work(&AtomicBool::new(false)))
        } else {
            run(py, &Report::Quiet, None, |c, _| work(c))?
        };
        Ok(PyArray1::from_vec(py, out))
    }

    /// Sound bounds of ``f`` over each box ``lo[k]`` to ``hi[k]`` (C-contiguous float64
    /// arrays of shape ``(N, 3)``, finite, ``lo <= hi``) in the arithmetic ``arith``:
    /// an array of shape ``(N, 2)``, the lower and upper bounds. Every value ``f``
    /// takes in box ``k`` lies in row ``k``.
    #[pyo3(signature = (lo, hi, arith="ia"))]
    fn eval_boxes<'py>(
        &self,
        py: Python<'py>,
        lo: &Bound<'py, PyAny>,
        hi: &Bound<'py, PyAny>,
        arith: &str,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let kind = crate::args::arith(arith)?;
        let (lo, hi) = (xyz_array("lo", lo)?, xyz_array("hi", hi)?);
        let (a, b) = (lo.as_slice()?, hi.as_slice()?);
        if a.len() != b.len() {
            return Err(crate::args::value_error(
                "lo, hi",
                format!("{} and {} boxes' corners", a.len() / 3, b.len() / 3),
            ));
        }
        if let Some(k) =
            (0..a.len()).find(|&k| !(a[k] <= b[k] && a[k].is_finite() && b[k].is_finite()))
        {
            return Err(crate::args::value_error(
                "lo, hi",
                format!(
                    "box {} axis {}: [{}, {}] is not a finite range with lo <= hi",
                    k / 3,
                    k % 3,
                    a[k],
                    b[k]
                ),
            ));
        }
        let n = a.len() / 3;
        let shape = &self.model.shape;
        let work = |cancel: &AtomicBool| {
            let mut out = vec![0.0; 2 * n];
            eval_boxes_kind(kind, shape, a, b, &mut out, cancel);
            out
        };
        let out = if n <= INLINE / 8 {
            py.detach(|| work(&AtomicBool::new(false)))
        } else {
            run(py, &Report::Quiet, None, |c, _| work(c))?
        };
        PyArray1::from_vec(py, out).reshape([n, 2])
    }

    fn __repr__(&self) -> String {
        self.source.repr()
    }

    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(
        Bound<'py, PyAny>,
        ((&'static str, String, String, String), Option<Corners>),
    )> {
        let s = slf.get();
        let restore = slf.get_type().getattr("_restore")?;
        Ok((
            restore,
            (s.source.to_state(), s.domain.as_ref().map(corners)),
        ))
    }

    /// Rebuilds a pickled shape.
    #[staticmethod]
    fn _restore(
        py: Python<'_>,
        state: (String, String, String, String),
        domain: Option<Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let (kind, text, format, path) = state;
        PyShape::make(
            py,
            Source::from_state(&kind, text, format, path)?,
            domain.as_ref(),
        )
    }
}

/// The bounds of `shape` over the box `b` in `A`'s cell form.
fn range_over<A: Arithmetic, S: Shape>(shape: &S, b: &Aabb) -> (f64, f64) {
    let x = A::Cell::input(0, b.min.x, b.max.x);
    let y = A::Cell::input(1, b.min.y, b.max.y);
    let z = A::Cell::input(2, b.min.z, b.max.z);
    shape.eval(x, y, z).bounds()
}

/// The names of the built-in models, for :meth:`Shape.builtin`.
#[pyfunction]
pub fn models() -> Vec<String> {
    builtin_names()
}
