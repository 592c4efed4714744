//! What can be wrong with a sweep before it runs: each error says what to do.

use thiserror::Error;

/// Why a sweep cannot run. Points whose values the model refuses are no error: their rows say
/// [`crate::Status::Invalid`].
#[derive(Debug, Error)]
pub enum SweepError {
    /// An axis written on the command line that cannot be read.
    #[error(
        "`{spec}`: {reason}; write NAME=START:STOP:COUNT (COUNT evenly spaced values from START \
         to STOP, both included) or NAME=V1,V2,... (e.g. e=0.1:0.9:9 or x_dot=0,0.5,1)"
    )]
    AxisSyntax {
        /// The axis as written.
        spec: String,
        /// What is wrong with it.
        reason: String,
    },
    /// An axis with no values.
    #[error("`{name}` is given no values to take: give it at least one")]
    EmptyAxis {
        /// The axis' name.
        name: String,
    },
    /// A value that is not a finite number.
    #[error("`{name}` would take the value {value}: every value must be a finite number")]
    NotFinite {
        /// The axis' name.
        name: String,
        /// The value.
        value: f64,
    },
    /// Nothing varies.
    #[error("a sweep needs at least one name to vary (e.g. --vary e=0.1:0.9:9)")]
    NoAxes,
    /// A name given twice.
    #[error("`{name}` is varied twice: give each name once, with all its values")]
    Duplicate {
        /// The name.
        name: String,
    },
    /// A name that is neither a parameter nor an initial value of the model.
    #[error(
        "{file}: `{name}` is not a parameter or an initial value of the model; the names that \
         may be varied are: {known}"
    )]
    UnknownName {
        /// The model file.
        file: String,
        /// The name.
        name: String,
        /// The names that may be varied, comma-separated.
        known: String,
    },
    /// A varied name that is also the name of a column of results in the sweep's table.
    #[error(
        "{file}: `{name}` is varied, but the sweep's table also has a column of results named \
         `{name}` ({columns}): its values and the results would share one column. Rename the \
         parameter or coordinate in the model file (e.g. to `{name}_`)"
    )]
    ColumnClash {
        /// The model file.
        file: String,
        /// The name.
        name: String,
        /// The table's result columns, as a reader sees them.
        columns: String,
    },
    /// Zipped axes of different lengths.
    #[error(
        "zipped axes must have the same number of values, but {lengths}: give them equal \
         lengths, or combine them as a product"
    )]
    ZipLengths {
        /// Each axis with its length (`e has 3 values, h0 has 4`).
        lengths: String,
    },
    /// More points than can be counted, or an axis of more than [`super::axis::MAX_VALUES`].
    #[error(
        "the sweep has more points than can be counted, or an axis of more than 10 000 000 \
         values: vary fewer values"
    )]
    TooManyPoints,
    /// More runs in one process than its rows fit in memory.
    #[error(
        "this sweep runs {runs} points in one process, more than the {max} whose rows it holds \
         at once: split it into {shards} or more shards (--shard K/{shards}, joined by \
         `zenosim merge`)"
    )]
    TooManyRuns {
        /// The points of the sweep (or shard).
        runs: usize,
        /// [`super::MAX_RUNS`].
        max: usize,
        /// The fewest shards that fit.
        shards: usize,
    },
    /// A shard that cannot be read or does not exist.
    #[error("shard `{spec}`: {reason}; write K/N with 1 ≤ K ≤ N (e.g. 2/3: the second of three)")]
    Shard {
        /// The shard as written.
        spec: String,
        /// What is wrong with it.
        reason: String,
    },
    /// Settings the engine refuses (a non-positive stop time or tolerance).
    #[error("{file}: the run settings are refused: {source}")]
    Settings {
        /// The model file.
        file: String,
        /// The engine's reason.
        source: zenosim::Error,
    },
    /// The model file itself, before any value is changed.
    #[error(transparent)]
    Model(#[from] zenosim_model::ModelError),
    /// A thread count of 0.
    #[error("workers must be at least 1 (or unset: one per core)")]
    NoWorkers,
    /// More worker threads than a sweep starts.
    #[error(
        "{workers} workers is more than the {max} threads a sweep starts: give at most {max} \
         (or leave workers unset: one per core)"
    )]
    TooManyWorkers {
        /// How many were asked for.
        workers: usize,
        /// [`super::MAX_WORKERS`].
        max: usize,
    },
    /// The worker threads could not be started.
    #[error("cannot start {workers} worker threads: {reason}")]
    ThreadPool {
        /// How many were asked for.
        workers: usize,
        /// The system's reason.
        reason: String,
    },
}
