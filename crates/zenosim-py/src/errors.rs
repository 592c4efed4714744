//! `zenosim.ModelError`, raised with where the mistake is and the command line's message.

use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyRuntimeError};
use pyo3::prelude::*;
use zenosim_model::Location;

create_exception!(
    zenosim,
    ModelError,
    PyException,
    "A model file (or an override of it) that zenosim refuses.\n\n\
     str(error) is the command line's message: the file, the line and column or the key, what \
     is wrong, the line with a caret under the place, and what to do. The attributes `file`, \
     `line`, `column` (1-based, in characters) and `key` (the key path, e.g. \
     'constraint[1].restitution', or the name an override sets) say where; each is None where it does \
     not apply."
);

/// The `ModelError` of `error`, its attributes set.
pub fn model_error(py: Python<'_>, error: &zenosim_model::ModelError) -> PyErr {
    let err = ModelError::new_err(error.to_string());
    let (line, column) = error.position().unzip();
    let key = match &error.location {
        // `--set e=2` is about `e`.
        Location::Override(arg) => arg.split_once('=').map(|(name, _)| name.trim()),
        _ => error.key(),
    };
    let value = err.value(py);
    let set = || -> PyResult<()> {
        value.setattr("file", &*error.file)?;
        value.setattr("line", line)?;
        value.setattr("column", column)?;
        value.setattr("key", key)?;
        Ok(())
    };
    match set() {
        Ok(()) => err,
        Err(failure) => failure,
    }
}

/// The class defaults of `ModelError`'s attributes (None), for an error raised by hand.
pub fn init_model_error(py: Python<'_>) -> PyResult<()> {
    let class = py.get_type::<ModelError>();
    for name in ["file", "line", "column", "key"] {
        class.setattr(name, py.None())?;
    }
    Ok(())
}

/// The error raised when the engine panics: a bug in zenosim, never a crash of Python.
pub fn panicked(payload: Box<dyn std::any::Any + Send>) -> PyErr {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown".to_string());
    PyRuntimeError::new_err(format!(
        "internal error in zenosim (a bug, please report it with the model): {what}"
    ))
}
