//! The toolkit from Python (`import tracer`): shapes from formulas, model files and
//! built-in models; their ranges over boxes in every arithmetic, one at a time or in
//! numpy batches; the arithmetics as Python number types; the reliable tracer and the
//! mesher with numpy arrays out. Long work releases the GIL and stops on Ctrl-C.
//!
//! The Python package (`python/tracer/`) re-exports this module `tracer._tracer` and
//! adds the functions over numbers and number types alike; the stubs are
//! `python/tracer/_tracer.pyi`.

#![forbid(unsafe_code)]

mod args;
mod batch;
mod camera;
mod detached;
mod mesh;
mod numbers;
mod render;
mod shape;
mod sources;
mod toolkit;

use pyo3::prelude::*;

/// The names of the arithmetics, in the papers' table order: ``ia``, ``aa``, ``raa``,
/// ``revaa``, ``hull``.
#[pyfunction]
fn arithmetics() -> Vec<&'static str> {
    toolkit::ArithKind::ALL.iter().map(|k| k.name()).collect()
}

#[pymodule]
fn _tracer(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("ModelError", m.py().get_type::<sources::ModelError>())?;
    m.add_class::<shape::PyShape>()?;
    m.add_class::<camera::PyCamera>()?;
    numbers::register(m)?;
    m.add_function(wrap_pyfunction!(shape::models, m)?)?;
    m.add_function(wrap_pyfunction!(arithmetics, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(render::save_png, m)?)?;
    m.add_function(wrap_pyfunction!(render::save_depth, m)?)?;
    m.add_function(wrap_pyfunction!(mesh::mesh, m)?)?;
    Ok(())
}
