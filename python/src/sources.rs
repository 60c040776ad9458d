//! Where a shape comes from: a formula, a model file's text in one of the registry's
//! formats (`.expr`, `.vm`, `.hf`), or a built-in model's name, read by the registry's
//! own readers. A reader's error becomes `tracer.ModelError`, a `ValueError` carrying
//! the reader's message and, where the reader gives them, its `line` and `column`.
//! The source is kept with the model, so a shape can be pickled (sent to another
//! process) and rebuilt there.

use crate::toolkit::models::{self, Model};
use crate::toolkit::Aabb;
use pyo3::prelude::*;

pyo3::create_exception!(
    tracer,
    ModelError,
    pyo3::exceptions::PyValueError,
    "A model that cannot be read: the reader's message, with ``line`` and ``column`` \
     (1-based; ``None`` where the error has no place in the text, such as an unknown \
     model name)."
);

/// What a model was made from.
#[derive(Clone, Debug)]
pub enum Source {
    /// A formula in the language of `tracer render --expr`.
    Formula(String),
    /// The text of a model file in the registry's format `format`; `path` names it in
    /// messages.
    Text {
        text: String,
        format: String,
        path: String,
    },
    /// A built-in model's name.
    Builtin(String),
}

/// A `ModelError` with the reader's message and position.
fn model_error(py: Python<'_>, message: String, at: Option<(usize, usize)>) -> PyErr {
    let e = ModelError::new_err(message);
    let v = e.value(py);
    let (line, column) = at.unzip();
    // Setting attributes on a fresh exception object cannot fail but by memory.
    let _ = v.setattr("line", line);
    let _ = v.setattr("column", column);
    e
}

/// The line and column of the error that `format`'s reader finds in `text`, if it
/// finds one (a failure elsewhere, in a header or the domain, has none).
fn error_position(text: &str, format: &str) -> Option<(usize, usize)> {
    match format {
        "expr" => models::parse_formula(text)
            .err()
            .map(|e| (e.line, e.column)),
        "vm" => models::parse_vm(text).err().map(|e| (e.line, e.column)),
        "hf" => models::parse_hyperfun(text)
            .err()
            .map(|e| (e.line, e.column)),
        _ => None,
    }
}

impl Source {
    /// The model, over `domain` where given (a formula's or file's view then frames
    /// it; a built-in keeps its view).
    pub fn load(&self, py: Python<'_>, domain: Option<Aabb>) -> PyResult<Model> {
        match self {
            Source::Formula(text) => Model::formula(text, domain)
                .map_err(|e| model_error(py, e, error_position(text, "expr"))),
            Source::Text { text, format, path } => {
                let fmt = models::format(format).map_err(|e| model_error(py, e, None))?;
                models::from_text(text, path, fmt, domain)
                    .map_err(|e| model_error(py, e, error_position(text, fmt.name)))
            }
            Source::Builtin(name) => {
                let mut m = models::find(name).map_err(|e| model_error(py, e, None))?;
                if let Some(d) = domain {
                    m.domain = d;
                }
                Ok(m)
            }
        }
    }

    /// The source of the model file `path`: its text, in `format` or the one its
    /// extension selects.
    pub fn file(path: &str, format: Option<&str>) -> PyResult<Source> {
        let format = match format {
            Some(f) => f.to_string(),
            None => match models::format_of(path) {
                Some(f) => f.name.to_string(),
                None => {
                    let names: Vec<&str> = models::FORMATS.iter().map(|f| f.name).collect();
                    return Err(pyo3::exceptions::PyValueError::new_err(format!(
                        "{path}: cannot tell the format from the file name: give \
                         format= one of {}",
                        names.join(", ")
                    )));
                }
            },
        };
        // OSError subclasses (FileNotFoundError, ...) name the path and the cause.
        let text = std::fs::read_to_string(path)?;
        Ok(Source::Text {
            text,
            format,
            path: path.to_string(),
        })
    }

    /// How `Shape.__repr__` shows it.
    pub fn repr(&self) -> String {
        match self {
            Source::Formula(t) => format!("Shape({t:?})"),
            Source::Text { path, format, .. } => {
                format!("Shape.file({path:?}, format={format:?})")
            }
            Source::Builtin(n) => format!("Shape.builtin({n:?})"),
        }
    }

    /// `(kind, text, format, path)`, the pickled form.
    pub fn to_state(&self) -> (&'static str, String, String, String) {
        match self {
            Source::Formula(t) => ("formula", t.clone(), String::new(), String::new()),
            Source::Text { text, format, path } => {
                ("text", text.clone(), format.clone(), path.clone())
            }
            Source::Builtin(n) => ("builtin", n.clone(), String::new(), String::new()),
        }
    }

    /// The inverse of [`Source::to_state`].
    pub fn from_state(kind: &str, text: String, format: String, path: String) -> PyResult<Self> {
        match kind {
            "formula" => Ok(Source::Formula(text)),
            "text" => Ok(Source::Text { text, format, path }),
            "builtin" => Ok(Source::Builtin(text)),
            k => Err(pyo3::exceptions::PyValueError::new_err(format!(
                "unknown shape source '{k}'"
            ))),
        }
    }
}
