//! The one place where core errors become Python exceptions, and where a Rust panic is
//! caught before it can cross into Python.
use nusselt_core::Error;
use pyo3::exceptions::{PyKeyboardInterrupt, PyMemoryError, PyRuntimeError, PyValueError};
use pyo3::PyErr;

pub fn to_py(err: Error) -> PyErr {
    match err {
        Error::Geometry { .. } | Error::InvalidArgument(_) | Error::Budget { .. } => {
            PyValueError::new_err(err.to_string())
        }
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
