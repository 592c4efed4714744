//! Parameter sweeps: many runs of one model file, each with other values of some of its
//! parameters or initial values, in parallel, reported one row per run.
//!
//! ```no_run
//! use std::sync::atomic::AtomicBool;
//! use zenosim_runs::sweep::{Axis, Combine, Points, RunSettings, Shard, Sweep};
//!
//! let source = std::fs::read_to_string("models/bouncing-ball.toml").unwrap();
//! let points = Points::new(vec!["e=0.1:0.9:9".parse().unwrap()], Combine::Product).unwrap();
//! let sweep = Sweep::new(
//!     "models/bouncing-ball.toml",
//!     &source,
//!     Default::default(),
//!     points,
//!     RunSettings::default(),
//! )
//! .unwrap();
//! let table = sweep
//!     .run(Shard::WHOLE, None, |_done, _total| {}, &AtomicBool::new(false))
//!     .unwrap();
//! for row in &table.rows {
//!     println!("e = {}: τ∞ = {}", row.values[0], row.t_zeno);
//! }
//! ```

mod axis;
mod error;
mod points;
mod row;
mod settings;
mod shard;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use rayon::prelude::*;
use zenosim::{Derived, HybridLagrangian, Observer, Simulation};
use zenosim_model::{FileModel, Limits, ModelError, ModelFile, Override};

pub use axis::{Axis, MAX_VALUES};
pub use error::SweepError;
pub use points::{Combine, Points};
pub use row::Row;
pub use settings::RunSettings;
pub use shard::Shard;

use crate::summary::constraint_names;

/// The most runs of one process (one shard): their rows, about 500 bytes each, are held until
/// the table is complete (1 GB at most).
pub const MAX_RUNS: usize = 2_000_000;
use crate::Status;

/// A sweep over a model file: its points, and the settings of every run.
#[derive(Clone, Debug)]
pub struct Sweep {
    file: String,
    source: String,
    limits: Limits,
    model: String,
    coordinates: Vec<String>,
    velocities: Vec<String>,
    points: Points,
    settings: RunSettings,
    /// The file read without changes.
    base: ModelFile,
    /// Its constraints' names.
    constraints: Vec<String>,
    /// Where each axis goes in the initial state, when every axis is an initial value of a
    /// model without forces or dissipation: then a point's model is the base's, and only its
    /// initial state changes ([`Sweep::run_point`]).
    state_slots: Option<Vec<Slot>>,
}

/// An entry of the initial state.
#[derive(Clone, Copy, Debug)]
enum Slot {
    /// A coordinate.
    Q(usize),
    /// A velocity.
    QDot(usize),
}

/// The rows of a sweep (or of a shard of it), in the order of their points.
#[derive(Clone, Debug)]
pub struct Table {
    /// One row per point run, in point order.
    pub rows: Vec<Row>,
    /// How many points the sweep (or shard) has: `rows.len()` unless interrupted.
    pub total: usize,
    /// Whether the sweep was cancelled: points not started then have no row, and the runs under
    /// way stopped with [`Status::Interrupted`].
    pub interrupted: bool,
}

/// The table's columns that are not axes, in order: `index` (before the axes), then `status`,
/// `impacts`, `t_zeno`, `t_switch`, `t_final`, `final_<name>` for each coordinate and velocity,
/// and `message`.
fn result_columns(coordinates: &[String], velocities: &[String]) -> Vec<String> {
    [
        "index", "status", "impacts", "t_zeno", "t_switch", "t_final",
    ]
    .into_iter()
    .map(str::to_string)
    .chain(
        coordinates
            .iter()
            .chain(velocities)
            .map(|name| format!("final_{name}")),
    )
    .chain(std::iter::once("message".to_string()))
    .collect()
}

/// The most worker threads a sweep starts: each holds a stack, and starting a million of them
/// took 22 s before the system refused.
pub const MAX_WORKERS: usize = 1024;

impl Sweep {
    /// A sweep of the model file `source` (named `file` in messages, formulas bounded by
    /// `limits`) over `points`, every run with the file's settings changed by `settings`.
    ///
    /// The file is read once without changes: its errors, names that are neither parameters nor
    /// initial values, and settings the engine refuses are errors here. A point whose values the
    /// model refuses is no error: its row says [`Status::Invalid`].
    pub fn new(
        file: &str,
        source: &str,
        limits: Limits,
        points: Points,
        settings: RunSettings,
    ) -> Result<Self, SweepError> {
        let base = zenosim_model::parse_model_with(file, source, &[], limits)?;
        let coordinates = base.model.coordinate_names();
        let velocities = base.velocity_names();
        let known: Vec<&str> = base
            .parameters
            .iter()
            .map(|(name, _)| name.as_str())
            .chain(coordinates.iter().map(String::as_str))
            .chain(velocities.iter().map(String::as_str))
            .collect();
        if let Some(name) = points.names().into_iter().find(|n| !known.contains(n)) {
            return Err(SweepError::UnknownName {
                file: file.to_string(),
                name: name.to_string(),
                known: known.join(", "),
            });
        }
        // The table has a column per axis, then the results: none may share a name.
        let results = result_columns(&coordinates, &velocities);
        if let Some(name) = points
            .names()
            .into_iter()
            .find(|n| results.iter().any(|r| r == n))
        {
            return Err(SweepError::ColumnClash {
                file: file.to_string(),
                name: name.to_string(),
                columns: "index, status, impacts, t_zeno, t_switch, t_final, final_<coordinate>, \
                          final_<coordinate>_dot, message"
                    .to_string(),
            });
        }
        settings
            .apply(base.options())
            .validate()
            .map_err(|source| SweepError::Settings {
                file: file.to_string(),
                source,
            })?;
        let slot = |name: &str| {
            let q = coordinates.iter().position(|c| c == name).map(Slot::Q);
            q.or_else(|| velocities.iter().position(|c| c == name).map(Slot::QDot))
        };
        let state_slots = if base.model.is_autonomous() {
            points.names().into_iter().map(slot).collect()
        } else {
            None
        };
        Ok(Self {
            file: file.to_string(),
            source: source.to_string(),
            limits,
            model: base.name.clone(),
            coordinates,
            velocities,
            points,
            settings,
            constraints: constraint_names(&base),
            base,
            state_slots,
        })
    }

    /// The model's name.
    pub fn model(&self) -> &str {
        &self.model
    }

    /// The model file's source.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The model's coordinates.
    pub fn coordinates(&self) -> &[String] {
        &self.coordinates
    }

    /// The model's velocities, `<coordinate>_dot`.
    pub fn velocities(&self) -> &[String] {
        &self.velocities
    }

    /// The points.
    pub fn points(&self) -> &Points {
        &self.points
    }

    /// The settings every run changes.
    pub fn settings(&self) -> &RunSettings {
        &self.settings
    }

    /// The names of a row's columns, as the table reports them: `index`, the axes' names,
    /// `status`, `impacts`, `t_zeno`, `t_switch`, `t_final`, `final_<coordinate>` for each
    /// coordinate, `final_<coordinate>_dot` for each velocity, and `message`.
    pub fn columns(&self) -> Vec<String> {
        let results = result_columns(&self.coordinates, &self.velocities);
        let (index, rest) = results.split_first().expect("the index comes first");
        std::iter::once(index.clone())
            .chain(self.points.names().into_iter().map(str::to_string))
            .chain(rest.iter().cloned())
            .collect()
    }

    /// Runs point `index` (< `self.points().len()`); it stops at its next step once `cancel` is
    /// set. Never panics: a run that cannot complete at all is a [`Status::Failed`] row.
    pub fn run_point(&self, index: usize, cancel: &AtomicBool) -> Row {
        let values = self.points.point(index);
        let dimension = self.coordinates.len();
        let ran = catch_unwind(AssertUnwindSafe(|| self.try_point(index, &values, cancel)));
        match ran {
            Ok(Ok(row)) => row,
            Ok(Err(why)) => Row::not_run(index, values, Status::Invalid, why, dimension),
            Err(panic) => {
                let what = panic
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_default();
                let message = format!(
                    "failed: zenosim itself failed on this point ({what}); this is a bug in \
                     zenosim: please report it with the model file and the point's values"
                );
                Row::not_run(index, values, Status::Failed, message, dimension)
            }
        }
    }

    /// The run of point `index`, or why the model refuses its values.
    ///
    /// Where only initial values vary (of a model without forces or dissipation), the model
    /// file is the same at every point but for its initial state, which the file's own checks
    /// of an initial state (admissible, finite, a positive definite mass matrix) accept or not:
    /// a point they accept runs the model read once, and gives the same row as reading the file
    /// with the point's values would (tested); a point they refuse is read in full, for the
    /// file's own message.
    fn try_point(&self, index: usize, values: &[f64], cancel: &AtomicBool) -> Result<Row, String> {
        if let Some(slots) = &self.state_slots {
            let (mut q, mut q_dot) = (self.base.initial.q.clone(), self.base.initial.q_dot.clone());
            for (slot, &value) in slots.iter().zip(values) {
                match *slot {
                    Slot::Q(i) => q[i] = value,
                    Slot::QDot(i) => q_dot[i] = value,
                }
            }
            if file_accepts(&self.base.model, &q, &q_dot) {
                let options = self.settings.apply(self.base.options());
                let simulation = Simulation::new(&self.base.model, &q, &q_dot, options)
                    .map_err(|error| format!("invalid: cannot simulate this point: {error}"))?;
                let run = simulation.run(&mut Cancel(cancel));
                return Ok(Row::of(index, values.to_vec(), &run, &self.constraints));
            }
        }
        self.try_point_read(index, values, cancel)
    }

    /// [`Sweep::try_point`], the model file read with the point's values.
    fn try_point_read(
        &self,
        index: usize,
        values: &[f64],
        cancel: &AtomicBool,
    ) -> Result<Row, String> {
        let overrides: Vec<Override> = self
            .points
            .names()
            .into_iter()
            .zip(values)
            .map(|(name, value)| Override {
                name: name.to_string(),
                value: exact(*value),
            })
            .collect();
        let file =
            zenosim_model::parse_model_with(&self.file, &self.source, &overrides, self.limits)
                .map_err(|error| refused(&error))?;
        let options = self.settings.apply(file.options());
        let simulation =
            Simulation::new(&file.model, &file.initial.q, &file.initial.q_dot, options)
                .map_err(|error| format!("invalid: cannot simulate this point: {error}"))?;
        let run = simulation.run(&mut Cancel(cancel));
        Ok(Row::of(index, values.to_vec(), &run, &self.constraints))
    }

    /// Whether `shard` of this sweep fits in one process: at most [`MAX_RUNS`] runs, whose rows
    /// are held until the table is complete. Checked by [`Sweep::run`] before anything runs.
    pub fn check_runs(&self, shard: Shard) -> Result<(), SweepError> {
        let runs = shard.len_of(self.points.len());
        if runs > MAX_RUNS {
            let shards = self.points.len().div_ceil(MAX_RUNS).max(shard.count() + 1);
            return Err(SweepError::TooManyRuns {
                runs,
                max: MAX_RUNS,
                shards,
            });
        }
        Ok(())
    }

    /// Runs the points of `shard` on `workers` threads (`None`: one per core, rayon's global
    /// pool), and returns their rows in point order, however they were scheduled.
    /// `progress(done, total)` is called from the worker threads as each row completes. Once
    /// `cancel` is set, points not started are not run and the runs under way stop at their next
    /// step; the rows made are kept and the table says it was interrupted.
    pub fn run<P>(
        &self,
        shard: Shard,
        workers: Option<usize>,
        progress: P,
        cancel: &AtomicBool,
    ) -> Result<Table, SweepError>
    where
        P: Fn(usize, usize) + Sync,
    {
        self.check_runs(shard)?;
        let indices: Vec<usize> = shard.indices(self.points.len()).collect();
        let total = indices.len();
        let done = AtomicUsize::new(0);
        let work = || {
            indices
                .par_iter()
                .map(|&index| {
                    if cancel.load(Ordering::Relaxed) {
                        return None;
                    }
                    let row = self.run_point(index, cancel);
                    progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
                    Some(row)
                })
                .collect::<Vec<Option<Row>>>()
        };
        let rows = match workers {
            None => work(),
            Some(0) => return Err(SweepError::NoWorkers),
            Some(workers) if workers > MAX_WORKERS => {
                return Err(SweepError::TooManyWorkers {
                    workers,
                    max: MAX_WORKERS,
                })
            }
            // No more threads than points: the others would have nothing to do.
            Some(workers) => rayon::ThreadPoolBuilder::new()
                .num_threads(workers.min(total.max(1)))
                .build()
                .map_err(|error| SweepError::ThreadPool {
                    workers,
                    reason: error.to_string(),
                })?
                .install(work),
        };
        let rows: Vec<Row> = rows.into_iter().flatten().collect();
        let interrupted =
            rows.len() < total || rows.iter().any(|r| r.status == Status::Interrupted);
        Ok(Table {
            rows,
            total,
            interrupted,
        })
    }
}

/// Whether a model file accepts `(q, q̇)` as its initial state: the checks `zenosim_model` makes
/// of `[initial]` (every `h` and its gradient finite, `h` admissible by
/// [`zenosim::admissible_start`], the energy and the mass matrix finite, the mass matrix
/// positive definite), for a model without forces or dissipation (whose forces it would check
/// too). They must never accept what the loader refuses: keep them in step with its
/// `check_initial_state` (a point they refuse is read in full, so being stricter is safe).
fn file_accepts(model: &FileModel, q: &[f64], q_dot: &[f64]) -> bool {
    let Ok(derived) = Derived::new(model) else {
        return false;
    };
    let admissible = (0..model.constraints().len()).all(|index| {
        let (h, gradient) = derived.constraint(index, q);
        h.is_finite()
            && gradient.iter().all(|a| a.is_finite())
            && zenosim::admissible_start(h, &gradient, q)
    });
    if !admissible {
        return false;
    }
    let (mass, positive) = derived.mass_matrix(q, q_dot);
    let energy = derived.energy(q, q_dot);
    energy.is_finite() && mass.iter().all(|m| m.is_finite()) && positive
}

/// `value` written so that the model file's formulas read it back exactly (Rust's `Debug` of
/// an `f64` is its shortest round-trip form, with a decimal point or an exponent).
fn exact(value: f64) -> String {
    format!("{value:?}")
}

/// Why the model refuses a point's values, on one line.
fn refused(error: &ModelError) -> String {
    let text = error.to_string();
    let first = text.lines().next().unwrap_or_default();
    match &error.help {
        Some(help) => format!("invalid: {first} ({help})"),
        None => format!("invalid: {first}"),
    }
}

/// The observer of a sweep's runs: no samples, and a stop once the sweep is cancelled.
struct Cancel<'a>(&'a AtomicBool);

impl Observer for Cancel<'_> {
    fn wants_samples(&self) -> bool {
        false
    }

    fn interrupted(&mut self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model(name: &str) -> String {
        let path = format!("{}/../../models/{name}.toml", env!("CARGO_MANIFEST_DIR"));
        std::fs::read_to_string(path).unwrap()
    }

    fn sweep_of(name: &str, axes: &[&str]) -> Sweep {
        let axes = axes.iter().map(|a| a.parse().unwrap()).collect();
        let points = Points::new(axes, Combine::Product).unwrap();
        let settings = RunSettings {
            t_end: Some(2.5),
            ..Default::default()
        };
        Sweep::new(name, &model(name), Limits::default(), points, settings).unwrap()
    }

    #[test]
    fn initial_values_run_the_model_read_once_with_the_same_rows() {
        // The paper's ball over its start: x3 = sin(1) − 1e-15 is within round-off of the
        // surface at x2 = 1 (admitted), −1e-9 below it is not; x3 = −0.5 is far below.
        let sin = 1.0f64.sin();
        let x3 = format!("x3={},{},{},2,-0.5", sin, sin - 1e-15, sin - 1e-9);
        let sweep = sweep_of("ball-on-sine", &["x2=1,1.5", &x3, "x1_dot=0,0.5"]);
        assert!(sweep.state_slots.is_some());
        let never = AtomicBool::new(false);
        let mut invalid = 0;
        for index in 0..sweep.points().len() {
            let values = sweep.points().point(index);
            let fast = sweep.try_point(index, &values, &never);
            let read = sweep.try_point_read(index, &values, &never);
            assert_eq!(format!("{fast:?}"), format!("{read:?}"), "point {values:?}");
            invalid += usize::from(read.is_err());
        }
        // Below the surface, for both velocities: at x2 = 1, x3 = sin(1) − 1e-9 and −0.5; at
        // x2 = 1.5 (sin 1.5 > sin 1), all but x3 = 2.
        assert_eq!(invalid, 12);
        // A parameter, or a model with forces: every point is read.
        assert!(sweep_of("ball-on-sine", &["g=9,10"]).state_slots.is_none());
        assert!(sweep_of("ball-on-sine", &["g=9", "x3=2"])
            .state_slots
            .is_none());
        assert!(sweep_of("dragged-ball", &["y=1,2"]).state_slots.is_none());
    }

    #[test]
    fn values_are_written_to_read_back_exactly() {
        let source = "name = \"ball\"\ncoordinates = [\"y\"]\nlagrangian = \"0.5*y_dot^2 - g*y\"\n\
                      [parameters]\ng = 9.81\np = 0.0\n[[constraint]]\nname = \"floor\"\n\
                      h = \"y\"\nrestitution = 0.5\n[initial]\ny = 1.0\n";
        for value in [
            0.1 + 0.2,
            -0.0,
            -2.5,
            1e-7,
            -3.2e-300,
            5e-324,
            1e300,
            f64::MAX,
            123_456_789.123_456_79,
            std::f64::consts::PI,
        ] {
            let o = Override {
                name: "p".to_string(),
                value: exact(value),
            };
            let file = zenosim_model::parse_model("m.toml", source, &[o]).unwrap();
            let read = file.parameters[1].1;
            assert_eq!(
                read.to_bits(),
                value.to_bits(),
                "{value:?} read as {read:?}"
            );
        }
    }
}
