//! The compiled part of the `telescopic` Python package (PyO3): scenes, and the library's
//! entry points returning plain data; `telescopic/__init__.py` wraps them in NumPy, pandas and
//! python-control objects (docs/python.md). It wraps the Rust library, never the CLI.

mod animation;
mod background;
mod calls;
mod environment;
mod errors;
mod identification;
mod planning;
mod scene;

use pyo3::prelude::*;

/// The compiled module `telescopic._telescopic`.
#[pymodule]
fn _telescopic(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<scene::PyScene>()?;
    m.add_class::<animation::PyMovie>()?;
    m.add_function(wrap_pyfunction!(animation::animate, m)?)?;
    m.add_function(wrap_pyfunction!(animation::animate_modes_of, m)?)?;
    m.add_function(wrap_pyfunction!(planning::plan, m)?)?;
    m.add_function(wrap_pyfunction!(identification::identify, m)?)?;
    m.add_function(wrap_pyfunction!(scene::read_input, m)?)?;
    m.add_function(wrap_pyfunction!(calls::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(calls::modes, m)?)?;
    m.add_function(wrap_pyfunction!(calls::linearize, m)?)?;
    m.add_function(wrap_pyfunction!(calls::design, m)?)?;
    m.add_function(wrap_pyfunction!(calls::check_controller, m)?)?;
    m.add_function(wrap_pyfunction!(calls::sweep, m)?)?;
    m.add_function(wrap_pyfunction!(calls::equations, m)?)?;
    m.add_function(wrap_pyfunction!(calls::_time_simulate, m)?)?;
    m.add("TelescopicError", py.get_type::<errors::TelescopicError>())?;
    m.add("SceneError", py.get_type::<errors::SceneError>())?;
    m.add("OptionError", py.get_type::<errors::OptionError>())?;
    m.add("SolverError", py.get_type::<errors::SolverError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
