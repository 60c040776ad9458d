//! Python arguments into the toolkit's types, each refusal one clear exception naming
//! the argument: `TypeError` for a wrong type or dtype, `ValueError` for a wrong shape,
//! memory layout or value.

use crate::toolkit::{check_domain, Aabb, ArithKind, DVec3};
use numpy::{PyArrayDescrMethods, PyReadonlyArray2, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// `what: message` as a `ValueError`.
pub fn value_error(what: &str, message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{what}: {message}"))
}

/// An arithmetic by name (`ia`, `aa`, `raa`, `revaa`, `hull`).
pub fn arith(name: &str) -> PyResult<ArithKind> {
    name.parse().map_err(|e| value_error("arith", e))
}

/// Three finite numbers.
pub fn vec3(what: &str, v: &Bound<'_, PyAny>) -> PyResult<DVec3> {
    let p: Vec<f64> = v
        .extract()
        .map_err(|_| PyTypeError::new_err(format!("{what}: expected three numbers (x, y, z)")))?;
    match p[..] {
        [x, y, z] if p.iter().all(|c| c.is_finite()) => Ok(DVec3::new(x, y, z)),
        [_, _, _] => Err(value_error(what, "the numbers must be finite")),
        _ => Err(value_error(
            what,
            format!("expected three numbers, got {}", p.len()),
        )),
    }
}

/// A box given as six numbers `(xmin, ymin, zmin, xmax, ymax, zmax)` or as two corners
/// `((xmin, ymin, zmin), (xmax, ymax, zmax))`: finite, each minimum at most its maximum.
pub fn closed_box(what: &str, b: &Bound<'_, PyAny>) -> PyResult<Aabb> {
    let expected = || {
        PyTypeError::new_err(format!(
            "{what}: expected six numbers (xmin, ymin, zmin, xmax, ymax, zmax) or two \
             corners ((xmin, ymin, zmin), (xmax, ymax, zmax))"
        ))
    };
    let (lo, hi) = if let Ok(v) = b.extract::<Vec<f64>>() {
        if v.len() != 6 {
            return Err(expected());
        }
        (DVec3::new(v[0], v[1], v[2]), DVec3::new(v[3], v[4], v[5]))
    } else if let Ok((lo, hi)) = b.extract::<(Bound<'_, PyAny>, Bound<'_, PyAny>)>() {
        (vec3(what, &lo)?, vec3(what, &hi)?)
    } else {
        return Err(expected());
    };
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(value_error(what, "the box must be finite"));
    }
    if !lo.cmple(hi).all() {
        return Err(value_error(
            what,
            "each minimum must be at most its maximum",
        ));
    }
    Ok(Aabb::new(lo, hi))
}

/// A domain box ([`closed_box`], and one the renderers and the mesher can work in:
/// each minimum below its maximum).
pub fn domain(what: &str, b: &Bound<'_, PyAny>) -> PyResult<Aabb> {
    let d = closed_box(what, b)?;
    check_domain(&d).map_err(|e| value_error(what, e))?;
    Ok(d)
}

/// A box as the two corners `((xmin, ymin, zmin), (xmax, ymax, zmax))`.
pub fn corners(b: &Aabb) -> ((f64, f64, f64), (f64, f64, f64)) {
    (b.min.into(), b.max.into())
}

/// A C-contiguous float64 numpy array of shape `(N, 3)`, read-only.
pub fn xyz_array<'py>(what: &str, a: &Bound<'py, PyAny>) -> PyResult<PyReadonlyArray2<'py, f64>> {
    let arr = a.cast::<PyUntypedArray>().map_err(|_| {
        PyTypeError::new_err(format!(
            "{what}: expected a numpy array of shape (N, 3) and dtype float64, got {}",
            a.get_type()
                .name()
                .map_or_else(|_| "another type".into(), |n| n.to_string())
        ))
    })?;
    let dtype = arr.dtype();
    if !dtype.is_equiv_to(&numpy::dtype::<f64>(a.py())) {
        return Err(PyTypeError::new_err(format!(
            "{what}: expected dtype float64, got {dtype} (convert with .astype(numpy.float64))"
        )));
    }
    let shape = arr.shape();
    if shape.len() != 2 || shape[1] != 3 {
        return Err(value_error(
            what,
            format!("expected shape (N, 3), got {shape:?}"),
        ));
    }
    if !arr.is_c_contiguous() {
        return Err(value_error(
            what,
            "the array is not C-contiguous (a strided view): pass numpy.ascontiguousarray(...)",
        ));
    }
    a.extract::<PyReadonlyArray2<'py, f64>>()
        .map_err(|e| value_error(what, e))
}
