//! `zenosim.Model`: a model file read and checked, with its text kept to be read again with
//! overrides (`set=`), which apply where the file is parsed.

use std::path::PathBuf;

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString, PyTuple};
use zenosim::HybridLagrangian;
use zenosim_model::{ModelFile, Override, ReadError};

use crate::errors::model_error;

/// The name a model read from a string goes by in messages (`ModelError.file`).
pub const STRING_FILE: &str = "<string>";

/// A hybrid Lagrangian read from a model file (TOML) and checked.
#[pyclass(module = "zenosim", name = "Model", frozen)]
pub struct Model {
    /// The file's name as given, for messages.
    pub file: String,
    /// The file's text, to read again with overrides.
    pub source: String,
    /// The model as the file writes it.
    pub parsed: ModelFile,
}

impl Model {
    /// Reads `source` (named `file`) with no override.
    pub fn parse(py: Python<'_>, file: String, source: String) -> PyResult<Self> {
        let parsed = parse_with(py, &file, &source, &[])?;
        Ok(Self {
            file,
            source,
            parsed,
        })
    }

    /// Reads the model file at `path`, named as `path` writes it.
    pub fn read(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<Self> {
        let (file, source) = read_file(py, path)?;
        Self::parse(py, file, source)
    }

    /// The model with `overrides` applied, read again from its text.
    pub fn with_overrides(&self, py: Python<'_>, overrides: &[Override]) -> PyResult<ModelFile> {
        parse_with(py, &self.file, &self.source, overrides)
    }
}

/// The name and the text of the model file at `path`.
pub fn read_file(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<(String, String)> {
    let path: PathBuf = fspath(path)?;
    let file = path.display().to_string();
    match zenosim_model::read_source(&path, &file) {
        Ok(source) => Ok((file, source)),
        Err(ReadError::Io(error)) => Err(io_error(py, error, &file)),
        Err(ReadError::Invalid(error)) => Err(model_error(py, &error)),
    }
}

/// `source` (named `file`) parsed with `overrides`.
pub fn parse_with(
    py: Python<'_>,
    file: &str,
    source: &str,
    overrides: &[Override],
) -> PyResult<ModelFile> {
    py.detach(|| zenosim_model::parse_model(file, source, overrides))
        .map_err(|error| model_error(py, &error))
}

/// The model of a call: a `Model` as it is, or read anew (from its text, or from a path) with
/// the overrides of `set=`.
pub enum Loaded {
    /// A `Model` without overrides, shared.
    Shared(Py<Model>),
    /// A model read for this call.
    Own(Box<ModelFile>),
}

impl Loaded {
    /// `model` (a `Model`, or the path of a model file) with `overrides`.
    pub fn new(py: Python<'_>, model: &Bound<'_, PyAny>, overrides: &[Override]) -> PyResult<Self> {
        if let Ok(model) = model.cast::<Model>() {
            return Ok(if overrides.is_empty() {
                Self::Shared(model.clone().unbind())
            } else {
                Self::Own(Box::new(model.get().with_overrides(py, overrides)?))
            });
        }
        let (file, source) = read_file(py, model)?;
        Ok(Self::Own(Box::new(parse_with(
            py, &file, &source, overrides,
        )?)))
    }

    /// The model file.
    pub fn file(&self) -> &ModelFile {
        match self {
            Self::Shared(model) => &model.get().parsed,
            Self::Own(file) => file,
        }
    }
}

/// The `OSError` of the right subclass (`FileNotFoundError`, `IsADirectoryError`, ...), as
/// `open(path)` raises it: `[Errno 2] No such file or directory: 'm.toml'`.
fn io_error(py: Python<'_>, error: std::io::Error, file: &str) -> PyErr {
    let Some(code) = error.raw_os_error() else {
        return PyErr::from(error);
    };
    let err = PyErr::from(error);
    let raised = || -> PyResult<PyErr> {
        let strerror = py.import("os")?.getattr("strerror")?.call1((code,))?;
        let value = err.get_type(py).call1((code, strerror, file))?;
        Ok(PyErr::from_value(value))
    };
    raised().unwrap_or(err)
}

/// `os.fspath(path)` as a path: a `str` or an `os.PathLike` naming one.
pub fn fspath(path: &Bound<'_, PyAny>) -> PyResult<PathBuf> {
    let py = path.py();
    let fspath = py.import("os")?.getattr("fspath")?;
    let value = fspath.call1((path,)).map_err(|_| {
        PyTypeError::new_err(format!(
            "a model is a zenosim.Model or the path of a model file (str or os.PathLike), not {}",
            type_name(path)
        ))
    })?;
    match value.cast::<PyString>() {
        Ok(s) => Ok(PathBuf::from(s.to_cow()?.into_owned())),
        Err(_) => Err(PyTypeError::new_err(
            "the path of a model file must be text (str or os.PathLike of str), not bytes",
        )),
    }
}

/// The Python type name of `value`, for messages.
pub fn type_name(value: &Bound<'_, PyAny>) -> String {
    value
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string())
}

#[pymethods]
impl Model {
    /// Reads and checks the model file at `path` (a str or an os.PathLike).
    #[staticmethod]
    fn from_file(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<Self> {
        Self::read(py, path)
    }

    /// Reads and checks a model from the text of a model file.
    #[staticmethod]
    fn from_toml(py: Python<'_>, text: &Bound<'_, PyAny>) -> PyResult<Self> {
        let text = text.cast::<PyString>().map_err(|_| {
            PyTypeError::new_err(format!(
                "from_toml takes the text of a model file (str), not {}; \
                 to read a file use Model.from_file(path)",
                type_name(text)
            ))
        })?;
        Self::parse(py, STRING_FILE.to_string(), text.to_cow()?.to_string())
    }

    /// A model read again from its text and file name (pickling).
    #[staticmethod]
    fn _from_source(py: Python<'_>, source: String, file: String) -> PyResult<Self> {
        Self::parse(py, file, source)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let this = slf.get();
        let constructor = slf.get_type().getattr("_from_source")?;
        let args = PyTuple::new(py, [this.source.as_str(), this.file.as_str()])?;
        PyTuple::new(py, [constructor, args.into_any()])
    }

    /// The model's `name`.
    #[getter]
    fn name(&self) -> &str {
        &self.parsed.name
    }

    /// The model's `description`, or None.
    #[getter]
    fn description(&self) -> Option<&str> {
        self.parsed.description.as_deref()
    }

    /// The file the model was read from (`"<string>"` for `from_toml`).
    #[getter]
    fn file(&self) -> &str {
        &self.file
    }

    /// The coordinates' names, in order.
    #[getter]
    fn coordinates(&self) -> Vec<String> {
        self.parsed.model.coordinate_names()
    }

    /// The velocities' names (`<coordinate>_dot`), in order.
    #[getter]
    fn velocities(&self) -> Vec<String> {
        self.parsed.velocity_names()
    }

    /// The parameters and their values, in the file's order.
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dict = PyDict::new(py);
        for (name, value) in &self.parsed.parameters {
            dict.set_item(name, value)?;
        }
        Ok(dict)
    }

    /// The initial state: each coordinate and velocity by name.
    #[getter]
    fn initial<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dict = PyDict::new(py);
        let initial = &self.parsed.initial;
        for (name, value) in self.coordinates().iter().zip(&initial.q) {
            dict.set_item(name, value)?;
        }
        for (name, value) in self.velocities().iter().zip(&initial.q_dot) {
            dict.set_item(name, value)?;
        }
        Ok(dict)
    }

    /// The constraints' names, in order.
    #[getter]
    fn constraints(&self) -> Vec<String> {
        zenosim_runs::summary::constraint_names(&self.parsed)
    }

    fn __repr__(&self) -> String {
        format!(
            "zenosim.Model({:?}, coordinates={:?}, constraints={:?})",
            self.parsed.name,
            self.coordinates(),
            self.constraints()
        )
    }
}

/// The overrides of a `set=` dict: name → number or formula string.
pub fn overrides(set: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<Override>> {
    let Some(set) = set.filter(|s| !s.is_none()) else {
        return Ok(Vec::new());
    };
    let dict = set.cast::<PyDict>().map_err(|_| {
        PyTypeError::new_err(format!(
            "set= takes a dict of parameter or initial-value names to numbers or formulas, \
             e.g. set={{\"e\": 0.8, \"x2_dot\": \"2*pi\"}}, not {}",
            type_name(set)
        ))
    })?;
    let mut overrides = Vec::with_capacity(dict.len());
    for (name, value) in dict.iter() {
        let name: String = name.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "set=: the names are str (a parameter or an initial value), not {}",
                type_name(&name)
            ))
        })?;
        let value = value_text(&name, &value, "set=")?;
        overrides.push(Override { name, value });
    }
    Ok(overrides)
}

/// A value of `set=` (or of a sweep) as the model file would write it: a finite number, or a
/// formula string.
pub fn value_text(name: &str, value: &Bound<'_, PyAny>, what: &str) -> PyResult<String> {
    if value.is_instance_of::<PyBool>() {
        return Err(PyTypeError::new_err(format!(
            "{what} {name}: a value is a number or a formula string, not a bool"
        )));
    }
    if let Ok(text) = value.cast::<PyString>() {
        let text = text.to_cow()?.trim().to_string();
        if text.is_empty() {
            return Err(PyValueError::new_err(format!(
                "{what} {name}: the formula is empty"
            )));
        }
        return Ok(text);
    }
    if value.is_instance_of::<PyInt>() || value.is_instance_of::<PyFloat>() || is_real(value) {
        let x: f64 = value.extract()?;
        return number_text(name, x, what);
    }
    Err(PyTypeError::new_err(format!(
        "{what} {name}: a value is a number or a formula string, not {}",
        type_name(value)
    )))
}

/// A finite number written so that it reads back to the same `f64`.
pub fn number_text(name: &str, x: f64, what: &str) -> PyResult<String> {
    if !x.is_finite() {
        return Err(PyValueError::new_err(format!(
            "{what} {name}: {x} is not a finite number"
        )));
    }
    // Rust's shortest round-trip form, in the exponent form past the ranges where the
    // positional one spells out many zeros.
    Ok(if x != 0.0 && !(1e-5..1e16).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    })
}

/// Whether `value` is a real number of another kind (numpy's float64 and int64 are
/// `numbers.Real`).
fn is_real(value: &Bound<'_, PyAny>) -> bool {
    let py = value.py();
    py.import("numbers")
        .and_then(|m| m.getattr("Real"))
        .and_then(|real| value.is_instance(&real))
        .unwrap_or(false)
}
