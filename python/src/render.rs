//! `tracer.render`: the reliable tracer with the options of `tracer render`, an image,
//! a depth map and the counters back as numpy arrays and a dict; and the PNG writer.

use crate::args::{domain as domain_arg, value_error, vec3};
use crate::camera::PyCamera;
use crate::detached::{pool, run, Counter, Report};
use crate::shape::PyShape;
use crate::toolkit::camera::{check_size, Camera, MAX_SIDE};
use crate::toolkit::models::AnyShape;
use crate::toolkit::render::{
    downsample_render, render_auto, render_kind, write_depth, write_png, Filter, Kernel, Progress,
    RenderOptions, RenderResult, RenderStats, Search,
};
use crate::toolkit::{ArithKind, View};
use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// The render's options that are not the tracer's own: how to pick the arithmetic and
/// to filter, and the size asked for.
struct Plan {
    opts: RenderOptions,
    kind: Option<ArithKind>,
    size: (u32, u32),
    filter: Option<Filter>,
}

/// The image, the depth map and the statistics.
type RenderArrays<'py> = (
    Bound<'py, PyArray3<u8>>,
    Bound<'py, PyArray2<f32>>,
    Bound<'py, PyDict>,
);

/// Renders ``shape`` reliably: every pixel whose ray meets the surface is a hit.
///
/// Returns ``(rgb, depth, stats)``: ``rgb`` a uint8 array of shape ``(H, W, 3)``,
/// ``depth`` a float32 array of shape ``(H, W)`` (the distance from the eye along each
/// pixel's ray to the surface, ``inf`` where it misses), ``stats`` a dict of counters
/// (``wall_s``, ``hits``, ``unconfirmed``, ``arith`` the arithmetic used, ...).
///
/// The options are ``tracer render``'s: ``size=(W, H)``; ``camera`` (default: the
/// shape's) and each of ``eye``, ``look_at``, ``up``, ``fov``, ``ortho`` replacing that
/// part of it; ``arith`` (``"auto"``: ``revaa``, hits it cannot confirm searched again in ``hull``; or
/// ``ia``, ``aa``, ``raa``, ``revaa``, ``hull``); ``domain`` (the box rays are clipped
/// to; default the shape's); ``eps`` (the precision of roots along rays; default a
/// quarter pixel); ``search`` (``"slabs"``: image tiles by depth slabs; ``"paper"``:
/// Algorithm 2's culling then Algorithm 1 per ray, as the revised-affine paper;
/// ``"auto"``: slabs for shapes whose tapes specialise, else paper; all find the same
/// first roots, ``stats["search"]`` says which ran); ``culling`` (with ``search="paper"``),
/// ``pruning``, ``specialise``, ``shadows``; ``aa`` (N x N
/// rays per pixel, filtered by ``filter``: ``box``, ``tent``, ``quadratic``,
/// ``cubic``); ``threads`` (default: one per core); ``progress`` (``True`` for a line
/// on stderr, or a function ``f(done, total)`` of tiles); ``device`` (``"cpu"``).
/// The GIL is released while it runs; Ctrl-C stops it with ``KeyboardInterrupt``.
///
/// >>> rgb, depth, stats = render(Shape("1 - x^2 - y^2 - z^2"), size=(32, 24))
/// >>> rgb.shape, rgb.dtype.name, depth.shape, depth.dtype.name
/// ((24, 32, 3), 'uint8', (24, 32), 'float32')
/// >>> stats["hits"] > 0
/// True
#[pyfunction]
#[pyo3(signature = (
    shape, size=(640, 480), camera=None, arith="auto", *, eye=None, look_at=None, up=None,
    fov=None, ortho=None, domain=None, eps=None, search="auto", culling=true, pruning=true,
    specialise=true, shadows=false, aa=1, filter="quadratic", threads=None,
    progress=None, device="cpu"
), text_signature = "(shape, size=(640, 480), camera=None, arith='auto', *, eye=None, \
    look_at=None, up=None, fov=None, ortho=None, domain=None, eps=None, search='auto', \
    culling=True, \
    pruning=True, specialise=True, shadows=False, aa=1, filter='quadratic', threads=None, \
    progress=None, device='cpu')")]
#[allow(clippy::too_many_arguments)]
pub fn render<'py>(
    py: Python<'py>,
    shape: &PyShape,
    size: (u32, u32),
    camera: Option<&PyCamera>,
    arith: &str,
    eye: Option<&Bound<'py, PyAny>>,
    look_at: Option<&Bound<'py, PyAny>>,
    up: Option<&Bound<'py, PyAny>>,
    fov: Option<f64>,
    ortho: Option<f64>,
    domain: Option<&Bound<'py, PyAny>>,
    eps: Option<f64>,
    search: &str,
    culling: bool,
    pruning: bool,
    specialise: bool,
    shadows: bool,
    aa: u32,
    filter: &str,
    threads: Option<usize>,
    progress: Option<&Bound<'py, PyAny>>,
    device: &str,
) -> PyResult<RenderArrays<'py>> {
    if device != "cpu" {
        return Err(value_error(
            "device",
            format!("'{device}': this package renders on the CPU only (device=\"cpu\")"),
        ));
    }
    let kind = match arith {
        "auto" => None,
        a => Some(crate::args::arith(a).map_err(|_| {
            value_error(
                "arith",
                format!(
                    "unknown arithmetic '{a}' (expected auto or one of: {})",
                    ArithKind::names()
                ),
            )
        })?),
    };
    let view = view_of(shape, camera, [eye, look_at, up], fov, ortho)?;
    let (vw, vh) = rays_size(size, aa)?;
    Camera::try_new(view, vw, vh).map_err(|e| value_error("camera", e))?;
    let kernel: Kernel = filter.parse().map_err(|e| value_error("filter", e))?;
    let dom = match domain {
        Some(d) => domain_arg("domain", d)?,
        None => shape.model.domain,
    };
    if let Some(e) = eps {
        if !(e > 0.0 && e.is_finite()) {
            return Err(value_error(
                "eps",
                format!("{e}: expected a positive number"),
            ));
        }
    }
    let search: Search = search.parse().map_err(|e| value_error("search", e))?;
    let mut opts = RenderOptions::for_view(view, dom, vw, vh);
    opts.search = search;
    opts.eps = eps;
    opts.culling = culling;
    opts.pruning = pruning;
    opts.specialise = specialise;
    opts.shadows = shadows;
    let plan = Plan {
        opts,
        kind,
        size,
        filter: (aa > 1).then(|| Filter::new(kernel, aa)),
    };
    let report = Report::from_arg(progress, "render (tiles)")?;
    let pool = pool(threads)?;
    let model = &shape.model.shape;
    let res = run(py, &report, pool.as_ref(), |cancel, counter| {
        plan.trace(model, cancel, counter)
    })?
    .map_err(|e| value_error("render", e))?;
    let search = plan.opts.search.resolve(model, plan.opts.specialise);
    let run = (plan.kind.map_or("auto", |k| k.name()), search);
    let stats = stats_dict(py, &res.stats, run)?;
    warn_unconfirmed(py, &res.stats)?;
    let (rgb, depth) = arrays(py, res)?;
    Ok((rgb, depth, stats))
}

impl Plan {
    /// The render (in the default arithmetic where `kind` is `None`), filtered down
    /// where anti-aliased.
    fn trace(
        &self,
        model: &AnyShape,
        cancel: &Arc<AtomicBool>,
        counter: &Arc<Counter>,
    ) -> Result<RenderResult, String> {
        let mut opts = self.opts.clone();
        opts.cancel = Some(cancel.clone());
        opts.progress = Some(counter.clone() as Arc<dyn Progress>);
        let res = match self.kind {
            Some(k) => render_kind(k, model, &opts)?,
            None => render_auto(model, &opts)?,
        };
        let res = match &self.filter {
            Some(f) => downsample_render(&res, self.size.0, self.size.1, f),
            None => res,
        };
        Ok(res)
    }
}

/// The camera: `camera` or the shape's, with each of `eye, look_at, up`, `fov` and
/// `ortho` given replacing that part.
fn view_of(
    shape: &PyShape,
    camera: Option<&PyCamera>,
    points: [Option<&Bound<'_, PyAny>>; 3],
    fov: Option<f64>,
    ortho: Option<f64>,
) -> PyResult<View> {
    let mut view = camera.map_or(shape.model.view, |c| c.view);
    let [eye, look_at, up] = points;
    if let Some(v) = eye {
        view.eye = vec3("eye", v)?;
    }
    if let Some(v) = look_at {
        view.look_at = vec3("look_at", v)?;
    }
    if let Some(v) = up {
        view.up = vec3("up", v)?;
    }
    if let Some(f) = fov {
        view.fov_deg = f;
    }
    if ortho.is_some() {
        view.ortho = ortho;
    }
    Ok(view)
}

/// The rays across and down: the image `size` at `aa x aa` rays per pixel, each side
/// within the camera's limit.
fn rays_size(size: (u32, u32), aa: u32) -> PyResult<(u32, u32)> {
    let (w, h) = size;
    check_size(w, h).map_err(|e| value_error("size", e))?;
    if aa == 0 || aa > 16 {
        return Err(value_error("aa", format!("{aa}: must be in 1..=16")));
    }
    let (vw, vh) = (w as u64 * aa as u64, h as u64 * aa as u64);
    if vw > MAX_SIDE as u64 || vh > MAX_SIDE as u64 {
        return Err(value_error(
            "aa",
            format!(
                "{w}x{h} at {aa} rays per pixel side is {vw}x{vh} rays; each side must be at \
                 most {MAX_SIDE}"
            ),
        ));
    }
    Ok((vw as u32, vh as u32))
}

/// A `RuntimeWarning` where over a quarter of the hits are unconfirmed.
fn warn_unconfirmed(py: Python<'_>, s: &RenderStats) -> PyResult<()> {
    let (hits, unconfirmed) = (s.hits, s.unconfirmed);
    if unconfirmed * 4 <= hits {
        return Ok(());
    }
    let msg = format!(
        "{unconfirmed} of {hits} hit pixels are unconfirmed (no sign change of f within the \
         precision): f may be infinite or NaN on a region (a division by 0, ln of values \
         <= 0) or touch 0 without crossing it"
    );
    let category = py.get_type::<pyo3::exceptions::PyRuntimeWarning>();
    PyErr::warn(py, category.as_any(), &std::ffi::CString::new(msg)?, 2)
}

/// The image and depth of `res` as numpy arrays of shapes `(H, W, 3)` and `(H, W)`.
#[allow(clippy::type_complexity)]
fn arrays(
    py: Python<'_>,
    res: RenderResult,
) -> PyResult<(Bound<'_, PyArray3<u8>>, Bound<'_, PyArray2<f32>>)> {
    let (w, h) = (res.width as usize, res.height as usize);
    let rgb = PyArray1::from_vec(py, res.rgb).reshape([h, w, 3])?;
    let depth = PyArray1::from_vec(py, res.depth).reshape([h, w])?;
    Ok((rgb, depth))
}

/// Every counter of `s` under its field name, `wall_s`, and the arithmetic and search
/// used.
fn stats_dict<'py>(
    py: Python<'py>,
    s: &RenderStats,
    (arith, search): (&str, Search),
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("arith", arith)?;
    d.set_item("search", search.name())?;
    d.set_item("wall_s", s.wall.as_secs_f64())?;
    d.set_item("cut", s.cut)?;
    for (k, v) in s.counters() {
        d.set_item(k, v)?;
    }
    d.set_item("mean_evals_per_hit", s.mean_evals_per_hit())?;
    Ok(d)
}

/// Writes ``rgb``, a C-contiguous uint8 array of shape ``(H, W, 3)`` (as
/// :func:`render` returns), to the PNG file ``path``.
#[pyfunction]
pub fn save_png(path: std::path::PathBuf, rgb: &Bound<'_, PyAny>) -> PyResult<()> {
    let a = rgb
        .cast::<PyArray3<u8>>()
        .map_err(|_| value_error("rgb", "expected a uint8 numpy array of shape (H, W, 3)"))?;
    let shape = a.shape().to_vec();
    if shape[2] != 3 {
        return Err(value_error(
            "rgb",
            format!("expected shape (H, W, 3), got {shape:?}"),
        ));
    }
    let ro = a.readonly();
    let data = ro
        .as_slice()
        .map_err(|_| value_error("rgb", "the array is not C-contiguous"))?;
    write_png(&path, shape[1] as u32, shape[0] as u32, data).map_err(|e| value_error("path", e))
}

/// Writes ``depth``, a C-contiguous float32 array of shape ``(H, W)`` (as
/// :func:`render` returns), to ``path``: ``.npy`` or ``.exr`` (one channel Z).
#[pyfunction]
pub fn save_depth(path: std::path::PathBuf, depth: &Bound<'_, PyAny>) -> PyResult<()> {
    let a = depth
        .cast::<PyArray2<f32>>()
        .map_err(|_| value_error("depth", "expected a float32 numpy array of shape (H, W)"))?;
    let shape = a.shape().to_vec();
    let ro = a.readonly();
    let data = ro
        .as_slice()
        .map_err(|_| value_error("depth", "the array is not C-contiguous"))?;
    write_depth(&path, shape[1] as u32, shape[0] as u32, data).map_err(|e| value_error("path", e))
}
