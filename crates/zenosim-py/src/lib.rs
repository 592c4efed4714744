//! The `zenosim` Python package's native module, `zenosim._zenosim`: model files, runs
//! returning numpy arrays, and parallel sweeps, over the zenosim crates.
//!
//! It only translates: the models are read by `zenosim-model`, run by `zenosim`, and reported
//! in `summary.json`'s words by `zenosim-runs`. The GIL is released while simulating; a run or
//! a sweep looks for Ctrl-C every 50 ms of wall time and raises `KeyboardInterrupt`. No Rust
//! panic reaches Python as a crash: it is a `RuntimeError`.

mod errors;
mod interrupt;
mod model;
mod run;
mod sweep;
mod topy;

use pyo3::prelude::*;

/// The native part of the `zenosim` package (import `zenosim`, not this module).
#[pymodule]
fn _zenosim(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    // numpy's C API is looked up on first use, by importing numpy. Done here, at import time:
    // looked up later, after a run, a Ctrl-C pending at that moment made the import raise
    // KeyboardInterrupt, which the numpy crate turns into a panic.
    let _ = numpy::PyArray1::<f64>::from_vec(py, Vec::new());
    m.add_class::<model::Model>()?;
    m.add_class::<run::Run>()?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep, m)?)?;
    errors::init_model_error(py)?;
    m.add("ModelError", py.get_type::<errors::ModelError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
