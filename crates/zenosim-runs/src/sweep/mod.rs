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
use zenosim::{HybridLagrangian, Observer, Simulation};
use zenosim_model::{Limits, ModelError, Override};

pub use axis::Axis;
pub use error::SweepError;
pub use points::{Combine, Points};
pub use row::Row;
pub use settings::RunSettings;
pub use shard::Shard;

use crate::summary::constraint_names;
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
        settings
            .apply(base.options())
            .validate()
            .map_err(|source| SweepError::Settings {
                file: file.to_string(),
                source,
            })?;
        Ok(Self {
            file: file.to_string(),
            source: source.to_string(),
            limits,
            model: base.name,
            coordinates,
            velocities,
            points,
            settings,
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
    fn try_point(&self, index: usize, values: &[f64], cancel: &AtomicBool) -> Result<Row, String> {
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
        Ok(Row::of(
            index,
            values.to_vec(),
            &run,
            &constraint_names(&file),
        ))
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
            Some(workers) => rayon::ThreadPoolBuilder::new()
                .num_threads(workers)
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
