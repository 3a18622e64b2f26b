//! Thin PyO3 binding of nusselt-core: array conversion, error mapping (errors.rs), GIL
//! release around every heavy call, a fork-safe worker pool (threads.rs). No numerics here.
use pyo3::prelude::*;

mod convert;
mod errors;
mod options;
mod pair;
mod scene;
mod threads;

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<scene::SceneCore>()?;
    m.add_function(wrap_pyfunction!(pair::view_factor, m)?)?;
    m.add_function(wrap_pyfunction!(pair::point_view_factor, m)?)?;
    Ok(())
}
