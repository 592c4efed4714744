//! `zenosim.run`: one run, its trajectory kept as numpy arrays, its events, Zeno points and
//! final state as `summary.json` writes them.

use std::panic::{catch_unwind, AssertUnwindSafe};

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString};
use zenosim::{
    Execution, Grips, HybridLagrangian, Mode, Observer, OutputGrid, Sample, Simulation,
    SimulationOptions, ZenoStrategy,
};
use zenosim_model::ModelFile;
use zenosim_runs::summary::{Record, TrajectoryJson};

use crate::errors::panicked;
use crate::interrupt::Watch;
use crate::model::{overrides, type_name, Loaded, Model};

/// The settings a call gives, each `None` where the model file's own applies.
#[derive(Clone, Copy, Debug, Default)]
pub struct Settings {
    pub t_end: Option<f64>,
    pub zeno: Option<ZenoStrategy>,
    pub rtol: Option<f64>,
    pub atol: Option<f64>,
    pub dt: Option<f64>,
    pub max_events: Option<u64>,
    pub max_steps: Option<u64>,
}

impl Settings {
    /// The file's options, overridden by these settings (as the command line's flags do).
    pub fn options(&self, file: &ModelFile) -> SimulationOptions {
        let mut options = file.options();
        if let Some(t_end) = self.t_end {
            options.t_end = t_end;
        }
        if let Some(rtol) = self.rtol {
            options.tolerances.rtol = rtol;
        }
        if let Some(atol) = self.atol {
            options.tolerances.atol = atol;
        }
        if let Some(zeno) = self.zeno {
            options.zeno = zeno;
        }
        if let Some(dt) = self.dt {
            options.output = OutputGrid::Uniform(dt);
        }
        if let Some(max_events) = self.max_events {
            options.max_events = max_events;
        }
        if let Some(max_steps) = self.max_steps {
            options.max_steps = max_steps;
        }
        options
    }
}

/// `zeno=`: `"auto"`, `"off"`, a positive number ε, or None (the model file's setting).
pub fn zeno_arg(zeno: Option<&Bound<'_, PyAny>>) -> PyResult<Option<ZenoStrategy>> {
    let Some(zeno) = zeno.filter(|z| !z.is_none()) else {
        return Ok(None);
    };
    let wrong = |what: String| {
        PyValueError::new_err(format!(
            "zeno= is \"auto\", \"off\" or a positive number ε (the paper's rule |h| ≤ ε, \
             |ḣ| ≤ ε), not {what}"
        ))
    };
    if let Ok(text) = zeno.cast::<PyString>() {
        let text = text.to_cow()?;
        return match &*text {
            "auto" => Ok(Some(ZenoStrategy::Auto)),
            "off" => Ok(Some(ZenoStrategy::Off)),
            _ => Err(wrong(format!("{text:?}"))),
        };
    }
    if zeno.is_instance_of::<pyo3::types::PyBool>() {
        return Err(PyTypeError::new_err(
            "zeno= is \"auto\", \"off\" or a positive number ε, not a bool",
        ));
    }
    match zeno.extract::<f64>() {
        Ok(epsilon) if epsilon > 0.0 && epsilon.is_finite() => {
            Ok(Some(ZenoStrategy::Epsilon(epsilon)))
        }
        Ok(epsilon) => Err(wrong(epsilon.to_string())),
        Err(_) => Err(PyTypeError::new_err(format!(
            "zeno= is \"auto\", \"off\" or a positive number ε, not {}",
            type_name(zeno)
        ))),
    }
}

/// `mode` as `trajectory.csv` writes it: `free`, or `constrained:` and the names of the
/// constraints held joined by `+`, then for a model with friction the `;stick:` and `;slip:`
/// lists of the held contacts ([`zenosim_runs::summary::mode_label`]).
pub fn mode_label(mode: Mode, grips: Grips, constraints: &[String]) -> String {
    let mut label = String::new();
    zenosim_runs::summary::mode_label(&mut label, mode, grips, constraints);
    label
}

/// The energy balance's terms of [`Run::balance`], in order (docs/output.md).
const BALANCE: [&str; 5] = [
    "work_forces",
    "work_drive",
    "work_constraints",
    "impact_loss",
    "work_friction",
];

/// The observer of a run: keeps every sample, column by column, and watches for Ctrl-C.
struct Recorder {
    t: Vec<f64>,
    q: Vec<f64>,
    q_dot: Vec<f64>,
    h: Vec<f64>,
    lambda: Vec<f64>,
    friction: Vec<f64>,
    friction_across: Vec<f64>,
    energy: Vec<f64>,
    /// Per row, the energy balance's terms in [`BALANCE`]'s order.
    work: Vec<f64>,
    /// Per row, the index of its mode and its contacts' friction states in `modes`.
    mode: Vec<u32>,
    modes: Vec<(Mode, Grips)>,
    watch: Watch,
    /// The bytes the record may take (`max_output`), and what it takes so far.
    cap: u64,
    used: u64,
}

/// What a run's record may take by default, as the command line's `--max-output`: 1 GiB.
const MAX_OUTPUT: u64 = 1 << 30;

/// What an event takes in the record, besides its two states (an estimate that errs high: its
/// entry in `Run.events` is built from it).
const EVENT_BYTES: u64 = 512;

impl Recorder {
    fn new(cap: u64) -> Self {
        Self {
            t: Vec::new(),
            q: Vec::new(),
            q_dot: Vec::new(),
            h: Vec::new(),
            lambda: Vec::new(),
            friction: Vec::new(),
            friction_across: Vec::new(),
            energy: Vec::new(),
            work: Vec::new(),
            mode: Vec::new(),
            modes: Vec::new(),
            watch: Watch::new(),
            cap,
            used: 0,
        }
    }

    /// Whether the record reached its cap: the run then stops at its next step.
    fn full(&self) -> bool {
        self.used > self.cap
    }
}

impl Observer for Recorder {
    fn sample(&mut self, s: &Sample<'_>) {
        let numbers = 2 + 2 * s.q.len() + 2 * s.h.len() + s.friction.len();
        let numbers = numbers + s.friction_across.len() + BALANCE.len();
        self.used += 8 * numbers as u64 + 4;
        self.t.push(s.t);
        self.q.extend_from_slice(s.q);
        self.q_dot.extend_from_slice(s.q_dot);
        self.h.extend_from_slice(s.h);
        self.lambda.extend_from_slice(s.lambda);
        self.friction.extend_from_slice(s.friction);
        self.friction_across.extend_from_slice(s.friction_across);
        self.energy.push(s.energy);
        let w = &s.work;
        self.work
            .extend_from_slice(&[w.forces, w.drive, w.constraints, w.impact_loss, w.friction]);
        let mode = (s.mode, s.grips);
        let index = match self.modes.iter().position(|m| *m == mode) {
            Some(index) => index,
            None => {
                self.modes.push(mode);
                self.modes.len() - 1
            }
        };
        self.mode.push(index as u32);
    }

    fn event(&mut self, event: &zenosim::Event) {
        self.used += EVENT_BYTES + 16 * (event.before.q.len() + event.after.q.len()) as u64;
    }

    fn interrupted(&mut self) -> bool {
        self.full() || self.watch.interrupted()
    }
}

/// The record of a run.
#[pyclass(module = "zenosim", name = "Run", frozen)]
pub struct Run {
    /// `"finished"`, `"zeno_stalled"` or `"failed"` (summary.json's words).
    #[pyo3(get)]
    status: String,
    /// What happened, in a sentence (summary.json's `message`).
    #[pyo3(get)]
    message: String,
    /// The times of the rows.
    #[pyo3(get)]
    t: Py<PyAny>,
    /// The coordinates, rows × coordinates.
    #[pyo3(get)]
    q: Py<PyAny>,
    /// The velocities, rows × coordinates.
    #[pyo3(get)]
    q_dot: Py<PyAny>,
    /// Each constraint's `h`, rows × constraints.
    #[pyo3(get)]
    h: Py<PyAny>,
    /// Each constraint's multiplier `λ` (trajectory.csv's `lambda_<name>`), rows × constraints.
    #[pyo3(get)]
    multipliers: Py<PyAny>,
    /// The tangential forces (trajectory.csv's `f_<name>`, and `f2_<name>` for the second
    /// component of a contact in space), rows × `friction_columns`.
    #[pyo3(get)]
    friction: Py<PyAny>,
    /// The names of the constraints with friction.
    #[pyo3(get)]
    friction_constraints: Vec<String>,
    /// The names of the columns of `friction`: `f_<name>` for each constraint with friction,
    /// followed by `f2_<name>` for a contact in space.
    #[pyo3(get)]
    friction_columns: Vec<String>,
    /// The energy of each row.
    #[pyo3(get)]
    energy: Py<PyAny>,
    /// The energy balance from the start to each row: a dict of arrays, `work_forces`,
    /// `work_drive`, `work_constraints`, `impact_loss`, `work_friction` (docs/output.md).
    #[pyo3(get)]
    balance: Py<PyAny>,
    /// The run's energy balance, as summary.json's `energy_balance`.
    #[pyo3(get)]
    energy_balance: Py<PyAny>,
    /// Each row's mode, as trajectory.csv writes it.
    #[pyo3(get)]
    mode: Py<PyAny>,
    /// Every event, as summary.json lists them.
    #[pyo3(get)]
    events: Py<PyAny>,
    /// Every Zeno point, as summary.json lists them.
    #[pyo3(get)]
    zeno: Py<PyAny>,
    /// Where the run ended, as summary.json's `final`.
    #[pyo3(get, name = "final")]
    final_: Py<PyAny>,
    /// The coordinates' names.
    #[pyo3(get)]
    coordinates: Vec<String>,
    /// The constraints' names.
    #[pyo3(get)]
    constraints: Vec<String>,
    impacts: u64,
    t_final: f64,
}

#[pymethods]
impl Run {
    fn __repr__(&self, py: Python<'_>) -> String {
        let rows = self.t.bind(py).len().unwrap_or(0);
        let zeno = self.zeno.bind(py).len().unwrap_or(0);
        format!(
            "zenosim.Run(status={:?}, t_final={}, rows={rows}, impacts={}, zeno_points={zeno})",
            self.status, self.t_final, self.impacts
        )
    }
}

/// `value` as Python objects: what `json.loads` makes of serde_json's text, summary.json's
/// keys and numbers (NaN and infinities are None, as summary.json's `null`).
pub fn json_value<T: serde::Serialize>(py: Python<'_>, value: &T) -> PyResult<Py<PyAny>> {
    Ok(crate::topy::to_python(py, value)?.unbind())
}

/// Runs `model` (a `Model` or a path) once, keeping its trajectory.
#[pyfunction]
#[pyo3(signature = (model, *, t_end=None, zeno=None, rtol=None, atol=None, dt=None, set=None, max_events=None, max_steps=None, max_output=None))]
#[allow(clippy::too_many_arguments)]
pub fn run(
    py: Python<'_>,
    model: &Bound<'_, PyAny>,
    t_end: Option<&Bound<'_, PyAny>>,
    zeno: Option<&Bound<'_, PyAny>>,
    rtol: Option<&Bound<'_, PyAny>>,
    atol: Option<&Bound<'_, PyAny>>,
    dt: Option<&Bound<'_, PyAny>>,
    set: Option<&Bound<'_, PyAny>>,
    max_events: Option<&Bound<'_, PyAny>>,
    max_steps: Option<&Bound<'_, PyAny>>,
    max_output: Option<&Bound<'_, PyAny>>,
) -> PyResult<Run> {
    let settings = Settings {
        t_end: real_arg("t_end", t_end)?,
        zeno: zeno_arg(zeno)?,
        rtol: real_arg("rtol", rtol)?,
        atol: real_arg("atol", atol)?,
        dt: real_arg("dt", dt)?,
        max_events: count_arg("max_events", max_events)?,
        max_steps: count_arg("max_steps", max_steps)?,
    };
    let cap = count_arg("max_output", max_output)?.unwrap_or(MAX_OUTPUT);
    let loaded = Loaded::new(py, model, &overrides(set)?)?;
    let file = loaded.file();
    let options = settings.options(file);
    let constraints = zenosim_runs::summary::constraint_names(file);
    let outcome = py.detach(|| {
        catch_unwind(AssertUnwindSafe(|| {
            let simulation =
                Simulation::new(&file.model, &file.initial.q, &file.initial.q_dot, options)?;
            let mut recorder = Recorder::new(cap);
            let execution = simulation.run(&mut recorder);
            Ok::<_, zenosim::Error>((execution, recorder))
        }))
    });
    let (execution, mut recorder) = match outcome {
        Ok(Ok(done)) => done,
        Ok(Err(error)) => {
            return Err(PyValueError::new_err(format!(
                "{}: cannot simulate this model: {error}",
                model_name(model)
            )))
        }
        Err(payload) => return Err(panicked(payload)),
    };
    if let Some(interrupt) = recorder.watch.take() {
        return Err(interrupt);
    }
    let capped = recorder.full().then_some(cap);
    record(
        py,
        file,
        &options,
        &execution,
        recorder,
        constraints,
        capped,
    )
}

/// A number given for `name` (`None`: the model file's): an int or a float, not a bool
/// (`t_end=True` was taken as 1.0) nor anything else; its range is the options' check.
pub fn real_arg(name: &str, value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<f64>> {
    let Some(value) = value.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    if value.is_instance_of::<pyo3::types::PyBool>() {
        return Err(PyTypeError::new_err(format!(
            "{name} must be a number, not a bool"
        )));
    }
    value.extract::<f64>().map(Some).map_err(|_| {
        PyTypeError::new_err(format!("{name} must be a number, not {}", type_name(value)))
    })
}

/// A positive whole number given for `name` (`None`: the default): refused, naming the
/// argument, where it is not one (a bool, a float, 0 or less).
fn count_arg(name: &str, value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<u64>> {
    let Some(value) = value.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    if value.is_instance_of::<pyo3::types::PyBool>()
        || !value.is_instance_of::<pyo3::types::PyInt>()
    {
        return Err(PyTypeError::new_err(format!(
            "{name} must be a whole number (an int), not {}",
            type_name(value)
        )));
    }
    match value.extract::<u64>() {
        Ok(n) if n > 0 => Ok(Some(n)),
        _ => Err(PyValueError::new_err(format!(
            "{name} must be a whole number > 0 (at most 2**64 - 1), not {value}"
        ))),
    }
}

/// The name of the model a call was given, for messages.
fn model_name(model: &Bound<'_, PyAny>) -> String {
    match model.cast::<Model>() {
        Ok(model) => model.get().file.clone(),
        Err(_) => model.str().map_or_else(|_| "?".into(), |s| s.to_string()),
    }
}

/// The `Run` of `execution` from what `recorder` kept; `capped` where the record reached its
/// cap (the run then stopped as if interrupted: it is a failure, and says so).
fn record(
    py: Python<'_>,
    file: &ModelFile,
    options: &SimulationOptions,
    execution: &Execution,
    recorder: Recorder,
    constraints: Vec<String>,
    capped: Option<u64>,
) -> PyResult<Run> {
    let n = file.model.dimension();
    let m = constraints.len();
    let rows = recorder.t.len();
    let matrix = |values: Vec<f64>, columns: usize| -> PyResult<Py<PyAny>> {
        let array = Array2::from_shape_vec((rows, columns), values)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
        Ok(array.into_pyarray(py).into_any().unbind())
    };
    let labels: Vec<Bound<'_, PyString>> = recorder
        .modes
        .iter()
        .map(|&(mode, grips)| PyString::new(py, &mode_label(mode, grips, &constraints)))
        .collect();
    let mode = PyList::new(py, recorder.mode.iter().map(|&i| &labels[i as usize]))?;
    let frictional = zenosim_runs::summary::friction_indices(&file.model);
    let columns = zenosim_runs::summary::friction_columns(&file.model);
    // (The second components are recorded only where the model has a contact in space.)
    let (first, second) = (&recorder.friction, &recorder.friction_across);
    let mut friction: Vec<f64> = Vec::with_capacity(recorder.t.len() * columns.len());
    for row in 0..recorder.t.len() {
        for &(i, k) in &columns {
            let values = if k == 0 { first } else { second };
            friction.push(values.get(row * m + i).copied().unwrap_or(0.0));
        }
    }
    let balance = PyDict::new(py);
    for (k, name) in BALANCE.iter().enumerate() {
        let column: Vec<f64> = recorder
            .work
            .iter()
            .skip(k)
            .step_by(BALANCE.len())
            .copied()
            .collect();
        balance.set_item(name, PyArray1::from_vec(py, column))?;
    }
    let message = match capped {
        None => zenosim_runs::message::message(execution, &constraints),
        Some(cap) => format!(
            "failed: at t = {}: the run's record reached max_output = {cap} bytes, which stopped \
             the run; its rows and events up to there are kept; raise max_output, or keep fewer \
             rows: a coarser dt or an earlier t_end",
            zenosim_runs::number::number(execution.t_final)
        ),
    };
    let summary = Record {
        file,
        options,
        run: execution,
        constraint_names: &constraints,
        message: message.clone(),
        trajectory: TrajectoryJson {
            file: "",
            rows: rows as u64,
        },
    }
    .summary();
    Ok(Run {
        status: if capped.is_some() {
            "failed".to_string()
        } else {
            summary.status.to_string()
        },
        message,
        t: PyArray1::from_vec(py, recorder.t).into_any().unbind(),
        q: matrix(recorder.q, n)?,
        q_dot: matrix(recorder.q_dot, n)?,
        h: matrix(recorder.h, m)?,
        multipliers: matrix(recorder.lambda, m)?,
        friction: matrix(friction, columns.len())?,
        friction_constraints: frictional.iter().map(|&i| constraints[i].clone()).collect(),
        friction_columns: columns
            .iter()
            .map(|&(i, k)| zenosim_runs::summary::force_column(&constraints[i], k))
            .collect(),
        energy: PyArray1::from_vec(py, recorder.energy).into_any().unbind(),
        balance: balance.into_any().unbind(),
        energy_balance: json_value(py, &summary.energy_balance)?,
        mode: mode.into_any().unbind(),
        events: json_value(py, &summary.events)?,
        zeno: json_value(py, &summary.zeno)?,
        final_: json_value(py, &summary.final_)?,
        coordinates: file.model.coordinate_names(),
        constraints: constraints.clone(),
        impacts: execution.stats.impacts,
        t_final: execution.t_final,
    })
}
