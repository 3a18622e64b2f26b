//! The one place where core errors become Python exceptions, and where a Rust panic is
//! caught before it can cross into Python.
use nusselt_core::Error;
use pyo3::exceptions::{PyKeyboardInterrupt, PyMemoryError, PyRuntimeError, PyValueError};
use pyo3::PyErr;

pyo3::create_exception!(
    _core,
    GeometryError,
    PyValueError,
    "A polygon failed validation. args: (message, index, kind, reason, degenerate); index is the \
     polygon's position in the list the core was given, and the Python package names the face from it."
);

pub fn to_py(err: Error) -> PyErr {
    match err {
        Error::Geometry { index, ref source } => {
            let args = (err.to_string(), index, source.kind(), source.to_string(), source.is_degenerate());
            GeometryError::new_err(args)
        }
        Error::InvalidArgument(_) | Error::Budget { .. } => PyValueError::new_err(err.to_string()),
        Error::OutOfMemory { .. } => PyMemoryError::new_err(err.to_string()),
        Error::Cancelled => PyKeyboardInterrupt::new_err("interrupted"),
    }
}

/// Runs `f`, turning a panic into a RuntimeError (an internal bug, reported as such) instead
/// of letting it unwind into the interpreter.
pub fn guard<T>(f: impl FnOnce() -> Result<T, Error>) -> Result<T, PyErr> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(r) => r.map_err(to_py),
        Err(payload) => {
            let msg = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(PyRuntimeError::new_err(format!("internal error in nusselt core (please report): {msg}")))
        }
    }
}
