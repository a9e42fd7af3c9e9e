//! `floe._floe`: the extension module behind the Python package `floe`
//! (python/floe). It holds what must run on floe's own engine: scenarios
//! read and edited with the scenario reader's checks ([`scenario`]), runs
//! and resumes through the run-loop library ([`running`]), run files read
//! through floe's reader ([`run_reader`]), gridded fields ([`gridding`]),
//! the friction laws side by side ([`comparing`]).
//! The Python side turns the arrays into xarray Datasets and plots.
#![deny(missing_docs)]

mod comparing;
mod errors;
mod gridding;
mod run_reader;
mod running;
mod scenario;
mod toml_values;

use pyo3::prelude::*;

/// The module `floe._floe`.
#[pymodule]
fn _floe(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // NumPy's C API, imported now rather than at the first array (where a
    // pending Ctrl-C would make the import fail inside rust-numpy).
    numpy::PyArray1::<f64>::zeros(m.py(), 0, false);
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("GIT_COMMIT", env!("FLOE_GIT_COMMIT"))?;
    m.add_class::<scenario::Scenario>()?;
    m.add_class::<run_reader::RunReader>()?;
    m.add_function(wrap_pyfunction!(running::run, m)?)?;
    m.add_function(wrap_pyfunction!(running::resume, m)?)?;
    m.add_function(wrap_pyfunction!(gridding::grid, m)?)?;
    m.add_function(wrap_pyfunction!(comparing::compare, m)?)?;
    m.add_function(wrap_pyfunction!(run_reader::export_xdmf, m)?)?;
    Ok(())
}
