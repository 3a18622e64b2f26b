//! Method options from a Python dict (names already checked by nusselt.methods).
use nusselt_core::method::Options;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

pub fn options(d: &Bound<'_, PyDict>) -> PyResult<Options> {
    let mut o = Options::default();
    for (k, v) in d.iter() {
        let key: String = k.extract()?;
        match key.as_str() {
            "tol" => o.tol = v.extract()?,
            "nodes" => o.nodes = v.extract()?,
            other => return Err(PyTypeError::new_err(format!("unknown option {other:?}"))),
        }
    }
    Ok(o)
}
