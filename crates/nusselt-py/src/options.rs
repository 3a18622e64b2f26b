//! Methods and options across the boundary: the core's registry as plain dicts
//! (`methods()`), and a Python option dict turned into the core's method and option structs
//! by the registry (names, types, ranges and defaults all come from it).
use nusselt_core::registry::{self, Default, OptionType, Value};
use nusselt_core::scene::AnyMethod;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString};

fn default_py<'py>(py: Python<'py>, ty: OptionType, d: Default) -> PyResult<Bound<'py, PyAny>> {
    Ok(match d {
        Default::Float(x) => x.into_pyobject(py)?.into_any(),
        Default::Int(x) => x.into_pyobject(py)?.into_any(),
        Default::Bool(x) => PyBool::new(py, x).to_owned().into_any(),
        Default::Keyword(s) => {
            let _ = ty;
            PyString::new(py, s).into_any()
        }
    })
}

/// Every method of the core's registry: a list of dicts {name, kind, obstructed, doc,
/// options: [{name, type, default, lo, hi, keywords, doc}]}; `lo`/`hi` are ints for int and
/// source options, floats for float options, None for bool.
#[pyfunction]
pub fn methods(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let out = PyList::empty(py);
    for m in registry::METHODS {
        let d = PyDict::new(py);
        d.set_item("name", m.name)?;
        d.set_item("kind", m.kind.name())?;
        d.set_item("obstructed", m.obstructed)?;
        d.set_item("doc", m.doc)?;
        let opts = PyList::empty(py);
        for o in m.options {
            let od = PyDict::new(py);
            od.set_item("name", o.name)?;
            od.set_item("type", o.ty.name())?;
            od.set_item("default", default_py(py, o.ty, o.default)?)?;
            match o.ty {
                OptionType::Float => {
                    od.set_item("lo", o.lo)?;
                    od.set_item("hi", o.hi)?;
                }
                OptionType::Int | OptionType::Source => {
                    od.set_item("lo", o.lo as u64)?;
                    od.set_item("hi", o.hi as u64)?;
                }
                OptionType::Bool => {
                    od.set_item("lo", py.None())?;
                    od.set_item("hi", py.None())?;
                }
            }
            od.set_item("keywords", o.keywords.to_vec())?;
            od.set_item("doc", o.doc)?;
            opts.append(od)?;
        }
        d.set_item("options", opts)?;
        out.append(d)?;
    }
    Ok(out)
}

/// The value of option `key` of `method` as the registry's type of it.
fn value(method: &str, key: &str, v: &Bound<'_, PyAny>) -> PyResult<Value> {
    let spec = registry::find(method).map_err(crate::errors::to_py)?;
    let Some(o) = spec.option(key) else {
        // the registry names the allowed options in its message
        return Err(crate::errors::to_py(
            registry::configure(method, &[(key.to_string(), Value::Bool(false))]).unwrap_err(),
        ));
    };
    let wrong =
        || PyTypeError::new_err(format!("method {method:?}: option {key} must be of type {}, got {v}", o.ty.name()));
    Ok(match o.ty {
        OptionType::Float => Value::Float(v.extract().map_err(|_| wrong())?),
        OptionType::Int => {
            if v.is_instance_of::<PyBool>() {
                return Err(wrong());
            }
            let x: i128 = v.extract().map_err(|_| wrong())?;
            Value::Int(u64::try_from(x).map_err(|_| {
                pyo3::exceptions::PyValueError::new_err(format!(
                    "method {method:?}: option {key}={x} is outside [{}, {}]",
                    o.lo as u64, o.hi as u64
                ))
            })?)
        }
        OptionType::Bool => Value::Bool(v.cast::<PyBool>().map_err(|_| wrong())?.is_true()),
        OptionType::Source => match v.cast::<PyString>() {
            Ok(s) => Value::Keyword(s.to_str()?.to_string()),
            Err(_) if !v.is_instance_of::<PyBool>() => {
                let x: i128 = v.extract().map_err(|_| wrong())?;
                Value::Int(u64::try_from(x).unwrap_or(u64::MAX))
            }
            Err(_) => return Err(wrong()),
        },
    })
}

/// The method `method` with its options from the dict `d` (missing options take the
/// registry's defaults).
pub fn options(method: &str, d: &Bound<'_, PyDict>) -> PyResult<AnyMethod> {
    let mut given = Vec::with_capacity(d.len());
    for (k, v) in d.iter() {
        let key: String = k.extract()?;
        given.push((key.clone(), value(method, &key, &v)?));
    }
    registry::configure(method, &given).map_err(crate::errors::to_py)
}
