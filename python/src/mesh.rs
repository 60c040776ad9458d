//! `tracer.mesh`: the mesher with the options of `tracer mesh`, the mesh back as numpy
//! arrays and its statistics as a dict.

use crate::args::{domain as domain_arg, value_error};
use crate::detached::{pool, run, Report};
use crate::shape::PyShape;
use crate::toolkit::mesh::{
    box_text, mesh_kind, MeshError, MeshOptions, MeshStats, DEFAULT_EXTRA_DEPTH,
    DEFAULT_MERGE_ERROR, MAX_DEPTH, MIN_DEPTH,
};
use crate::toolkit::render::Progress;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Arc;

/// The vertices, the triangles and the statistics.
type MeshArrays<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<u32>>,
    Bound<'py, PyDict>,
);

/// Meshes ``shape`` over its domain: an octree pruned by range arithmetic, then dual
/// contouring with each vertex kept in its cell. The mesh is closed (clipped to the
/// domain), wound outward (counter-clockwise seen from outside).
///
/// Returns ``(vertices, triangles, stats)``: float64 ``(V, 3)``, uint32 ``(T, 3)``
/// (indices into ``vertices``) and a dict (``euler``, ``watertight``, ``manifold``,
/// ``components``, ``self_intersections``, ``certified_share``, counters, ``wall_s``).
///
/// The options are ``tracer mesh``'s: ``depth`` (``2**depth`` cells along the domain's
/// longest side), ``max_depth`` (how deep to look for features thinner than a cell;
/// default ``depth + 4``), ``arith``, ``domain`` (default the shape's), ``threads``,
/// ``check`` (count self-intersecting triangle pairs), ``merge`` (merge cells where
/// one vertex fits their planes: ``True``, ``False``, or the largest distance in
/// leaf cells), ``branch_planes`` (keep CSG creases and corners), ``certify`` (the
/// Plantinga-Vegter topology test per cell), ``progress`` (``True`` or ``f(done,
/// total)``). The GIL is released while it runs; Ctrl-C stops it with
/// ``KeyboardInterrupt``.
///
/// >>> v, t, stats = mesh(Shape("1 - x^2 - y^2 - z^2"), depth=4)
/// >>> v.shape[1], t.shape[1], t.dtype.name, stats["euler"], stats["watertight"]
/// (3, 3, 'uint32', 2, True)
#[pyfunction]
#[pyo3(signature = (
    shape, depth=6, *, max_depth=None, arith="revaa", domain=None, threads=None,
    check=true, merge=None, branch_planes=true, certify=true, progress=None
))]
#[allow(clippy::too_many_arguments)]
pub fn mesh<'py>(
    py: Python<'py>,
    shape: &PyShape,
    depth: u32,
    max_depth: Option<u32>,
    arith: &str,
    domain: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
    check: bool,
    merge: Option<&Bound<'py, PyAny>>,
    branch_planes: bool,
    certify: bool,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<MeshArrays<'py>> {
    let kind = crate::args::arith(arith)?;
    let dom = match domain {
        Some(d) => domain_arg("domain", d)?,
        None => shape.model.domain,
    };
    let in_range = |what: &str, d: u32| {
        if (MIN_DEPTH..=MAX_DEPTH).contains(&d) {
            Ok(d)
        } else {
            Err(value_error(
                what,
                format!("{d}: expected a whole number from {MIN_DEPTH} to {MAX_DEPTH}"),
            ))
        }
    };
    let depth = in_range("depth", depth)?;
    let max_depth = match max_depth {
        Some(m) if m < depth => {
            return Err(value_error(
                "max_depth",
                format!("{m}: must be at least depth ({depth})"),
            ))
        }
        Some(m) => in_range("max_depth", m)?,
        None => (depth + DEFAULT_EXTRA_DEPTH).min(MAX_DEPTH),
    };
    let mut opts = MeshOptions::new(dom, depth);
    opts.max_depth = max_depth;
    opts.check_self_intersections = check;
    opts.branch_planes = branch_planes;
    opts.certify = certify;
    opts.merge = merge_error(merge)?;
    opts.memory_limit = available_memory();
    opts.check().map_err(|e| match e {
        MeshError::TooLarge { .. } => value_error("depth", e),
        e => value_error("mesh", e),
    })?;
    let report = Report::from_arg(progress, "mesh (parts)")?;
    let pool = pool(threads)?;
    let model = &shape.model.shape;
    let res = run(py, &report, pool.as_ref(), |cancel, counter| {
        let mut opts = opts.clone();
        opts.cancel = Some(cancel.clone());
        opts.progress = Some(counter.clone() as Arc<dyn Progress>);
        mesh_kind(kind, model, &opts)
    })?
    .map_err(|e| value_error("mesh", e))?;
    let stats = stats_dict(py, &res.stats, kind.name())?;
    warn(py, &res.stats)?;
    let (nv, nt) = (res.mesh.vertices.len(), res.mesh.triangles.len());
    let v: Vec<f64> = res.mesh.vertices.into_iter().flatten().collect();
    let t: Vec<u32> = res.mesh.triangles.into_iter().flatten().collect();
    let v = PyArray1::from_vec(py, v).reshape([nv, 3])?;
    let t = PyArray1::from_vec(py, t).reshape([nt, 3])?;
    Ok((v, t, stats))
}

/// `merge=`: `None`/`True` the default error, `False` none, a number that error.
fn merge_error(arg: Option<&Bound<'_, PyAny>>) -> PyResult<Option<f64>> {
    let Some(a) = arg.filter(|a| !a.is_none()) else {
        return Ok(Some(DEFAULT_MERGE_ERROR));
    };
    if let Ok(b) = a.cast::<pyo3::types::PyBool>() {
        return Ok(b.is_true().then_some(DEFAULT_MERGE_ERROR));
    }
    match a.extract::<f64>() {
        Ok(e) if e >= 0.0 && e.is_finite() => Ok(Some(e)),
        _ => Err(value_error(
            "merge",
            "expected True, False or a distance in leaf cells >= 0",
        )),
    }
}

/// The memory available to this process (`MemAvailable` of `/proc/meminfo`), where
/// known: the mesher refuses a depth whose estimate exceeds it.
fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib.saturating_mul(1024))
}

/// Python warnings where the mesh may miss thin parts of the surface.
fn warn(py: Python<'_>, s: &MeshStats) -> PyResult<()> {
    let say = |m: String| {
        PyErr::warn(
            py,
            py.get_type::<pyo3::exceptions::PyRuntimeWarning>().as_any(),
            &std::ffi::CString::new(m)?,
            2,
        )
    };
    if s.unresolved_at_max_depth > 0 {
        let place = s
            .unresolved_box
            .map_or(String::new(), |b| format!(" in {}", box_text(&b)));
        let held = if s.level_wanted > s.level {
            format!(
                "; features there asked for leaf level {}, held at {} by the work and \
                 memory budget",
                s.level_wanted, s.level
            )
        } else {
            String::new()
        };
        say(format!(
            "{} cells stayed unresolved{place} (max_depth {} or the probe budget \
             reached{held}): surface thinner than a cell may be missing there",
            s.unresolved_at_max_depth, s.max_depth
        ))?;
    }
    Ok(())
}

/// The statistics of a meshing, as `tracer mesh --stats json` gives them.
fn stats_dict<'py>(py: Python<'py>, s: &MeshStats, arith: &str) -> PyResult<Bound<'py, PyDict>> {
    let t = &s.topology;
    let d = PyDict::new(py);
    d.set_item("arith", arith)?;
    d.set_item("wall_s", s.wall.as_secs_f64())?;
    for (k, v) in s.counters() {
        d.set_item(k, v)?;
    }
    d.set_item("euler", t.euler)?;
    d.set_item("watertight", t.watertight())?;
    d.set_item("manifold", t.manifold())?;
    d.set_item("certified_cells", s.certified_cells)?;
    d.set_item("certified_share", s.certified_share())?;
    d.set_item("self_intersections", s.self_intersections)?;
    Ok(d)
}
