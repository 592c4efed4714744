//! `zenosim.sweep`: many runs of one model, in parallel on zenosim-runs' sweep core, one row
//! each, returned as columns of numpy arrays.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;

use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString};
use zenosim_model::Limits;
use zenosim_runs::sweep::{Axis, Combine, Points, Row, RunSettings, Shard, Sweep, SweepError};

use crate::errors::{model_error, panicked};
use crate::interrupt::POLL;
use crate::model::{read_file, type_name, Model};
use crate::run::{real_arg, zeno_arg};

/// The axes of `values`: a mapping of names to sequences of numbers.
fn axes(values: &Bound<'_, PyAny>) -> PyResult<Vec<Axis>> {
    let dict = values.cast::<PyDict>().map_err(|_| {
        PyTypeError::new_err(format!(
            "values is a dict of parameter or initial-value names to sequences of numbers, \
             e.g. {{\"e\": [0.5, 0.6, 0.7]}}, not {}",
            type_name(values)
        ))
    })?;
    let mut axes = Vec::with_capacity(dict.len());
    for (name, sequence) in dict.iter() {
        let name: String = name.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "values: the names are str (a parameter or an initial value), not {}",
                type_name(&name)
            ))
        })?;
        if sequence.is_instance_of::<PyString>() || sequence.hasattr("keys")? {
            return Err(PyTypeError::new_err(format!(
                "values[{name:?}] is a sequence of numbers, not {}",
                type_name(&sequence)
            )));
        }
        let items = sequence.try_iter().map_err(|_| {
            PyTypeError::new_err(format!(
                "values[{name:?}] is a sequence of numbers (a list, a tuple, a numpy array), \
                 not {}",
                type_name(&sequence)
            ))
        })?;
        let mut numbers = Vec::new();
        for item in items {
            let item = item?;
            let number = if item.is_instance_of::<PyBool>() {
                None
            } else {
                item.extract::<f64>().ok()
            };
            numbers.push(number.ok_or_else(|| {
                PyTypeError::new_err(format!(
                    "values[{name:?}]: every value is a number, not {} ({})",
                    type_name(&item),
                    item.repr().map_or_else(|_| "?".into(), |r| r.to_string())
                ))
            })?);
        }
        axes.push(Axis::new(name, numbers).map_err(sweep_error_plain)?);
    }
    Ok(axes)
}

/// A sweep's error as Python's: a model's as `ModelError`, the rest as `ValueError`.
fn sweep_error(py: Python<'_>, error: SweepError) -> PyErr {
    match error {
        SweepError::Model(error) => model_error(py, &error),
        other => sweep_error_plain(other),
    }
}

fn sweep_error_plain(error: SweepError) -> PyErr {
    PyValueError::new_err(error.to_string())
}

/// Runs `sweep` on `workers` threads with the GIL released, cancelling it when a signal
/// handler raises (Ctrl-C): the exception is returned then.
fn run_watched(py: Python<'_>, sweep: &Sweep, workers: Option<usize>) -> PyResult<Vec<Row>> {
    let (outcome, interrupt) = py.detach(|| {
        let cancel = AtomicBool::new(false);
        let (done, finished) = mpsc::channel::<()>();
        let mut interrupt: Option<PyErr> = None;
        let outcome = std::thread::scope(|scope| {
            let worker = scope.spawn(|| {
                let table = sweep.run(Shard::WHOLE, workers, |_, _| {}, &cancel);
                let _ = done.send(());
                table
            });
            // This thread waits, looking for Ctrl-C every POLL.
            while let Err(mpsc::RecvTimeoutError::Timeout) = finished.recv_timeout(POLL) {
                if interrupt.is_none() {
                    if let Err(error) = Python::attach(|py| py.check_signals()) {
                        interrupt = Some(error);
                        cancel.store(true, Ordering::Relaxed);
                    }
                }
            }
            worker.join()
        });
        (outcome, interrupt)
    });
    if let Some(error) = interrupt {
        return Err(error);
    }
    match outcome {
        Ok(Ok(table)) => Ok(table.rows),
        Ok(Err(error)) => Err(sweep_error(py, error)),
        Err(payload) => Err(panicked(payload)),
    }
}

/// Runs `model` at every point of `values`, keeping no trajectory; the columns of the table.
#[pyfunction]
#[pyo3(signature = (model, values, *, t_end=None, zeno=None, rtol=None, atol=None, product=true, workers=None))]
#[allow(clippy::too_many_arguments)]
pub fn sweep<'py>(
    py: Python<'py>,
    model: &Bound<'py, PyAny>,
    values: &Bound<'py, PyAny>,
    t_end: Option<&Bound<'py, PyAny>>,
    zeno: Option<&Bound<'py, PyAny>>,
    rtol: Option<&Bound<'py, PyAny>>,
    atol: Option<&Bound<'py, PyAny>>,
    product: bool,
    workers: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let settings = RunSettings {
        t_end: real_arg("t_end", t_end)?,
        zeno: zeno_arg(zeno)?,
        rtol: real_arg("rtol", rtol)?,
        atol: real_arg("atol", atol)?,
    };
    let workers = match workers.filter(|w| !w.is_none()) {
        None => None,
        Some(w) if w.is_instance_of::<PyBool>() => {
            return Err(PyTypeError::new_err(
                "workers= is a whole number ≥ 1, or None",
            ))
        }
        Some(w) => match w.extract::<i64>() {
            Ok(n) if n >= 1 => Some(n as usize),
            Ok(n) => {
                return Err(PyValueError::new_err(format!(
                    "workers= is at least 1 (or None: one per core), not {n}"
                )))
            }
            Err(_) => {
                return Err(PyTypeError::new_err(format!(
                    "workers= is a whole number ≥ 1, or None, not {}",
                    type_name(w)
                )))
            }
        },
    };
    let combine = if product {
        Combine::Product
    } else {
        Combine::Zip
    };
    let points = Points::new(axes(values)?, combine).map_err(sweep_error_plain)?;
    let (file, source) = match model.cast::<Model>() {
        Ok(model) => (model.get().file.clone(), model.get().source.clone()),
        Err(_) => read_file(py, model)?,
    };
    let sweep = py
        .detach(|| Sweep::new(&file, &source, Limits::default(), points, settings))
        .map_err(|error| sweep_error(py, error))?;
    let rows = run_watched(py, &sweep, workers)?;
    table(py, &sweep, &rows)
}

/// The columns: each swept name, `status`, `impacts`, `t_zeno`, `t_switch`, `t_final`, the
/// final `final_<coordinate>` and `final_<coordinate>_dot`, and `message` (the names of
/// `zenosim sweep`'s CSV, without its `index`).
fn table<'py>(py: Python<'py>, sweep: &Sweep, rows: &[Row]) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    let floats = |f: &dyn Fn(&Row) -> f64| PyArray1::from_iter(py, rows.iter().map(f));
    for (k, name) in sweep.points().names().into_iter().enumerate() {
        dict.set_item(name, floats(&|r| r.values[k]))?;
    }
    let strings = |f: &dyn Fn(&Row) -> String| -> PyResult<Bound<'py, PyAny>> {
        let list = PyList::new(py, rows.iter().map(f))?;
        py.import("numpy")?.getattr("asarray")?.call1((list,))
    };
    dict.set_item("status", strings(&|r| r.status.word().to_string())?)?;
    let impacts: Vec<i64> = rows.iter().map(|r| r.impacts as i64).collect();
    dict.set_item("impacts", impacts.into_pyarray(py))?;
    dict.set_item("t_zeno", floats(&|r| r.t_zeno))?;
    dict.set_item("t_switch", floats(&|r| r.t_switch))?;
    dict.set_item("t_final", floats(&|r| r.t_final))?;
    for (i, name) in sweep.coordinates().iter().enumerate() {
        dict.set_item(format!("final_{name}"), floats(&|r| r.q[i]))?;
    }
    for (i, name) in sweep.velocities().iter().enumerate() {
        dict.set_item(format!("final_{name}"), floats(&|r| r.q_dot[i]))?;
    }
    dict.set_item("message", strings(&|r| r.message.clone())?)?;
    Ok(dict)
}
