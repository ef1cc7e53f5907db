//! `pseudorigid._native`: the Rust side of the Python package. Everything goes through the
//! library's own validated entry points (the command's scene parser and runner,
//! `flow::openfoam`); these modules only convert between Python and Rust values and map the
//! library's typed errors onto the Python exceptions of `pseudorigid.errors`.

mod adequacy;
mod drive;
mod errors;
mod foam;
mod results;
mod runs;
mod scene;
mod toml_value;

use pyo3::prelude::*;

/// The Rust side of the `pseudorigid` package.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scene::PyScene>()?;
    m.add_class::<results::Results>()?;
    m.add_class::<foam::PyFoamFlow>()?;
    m.add_function(wrap_pyfunction!(runs::run, m)?)?;
    m.add_function(wrap_pyfunction!(runs::run_in_memory, m)?)?;
    m.add_function(wrap_pyfunction!(runs::load_results, m)?)?;
    m.add_function(wrap_pyfunction!(adequacy::adequacy, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
