//! A sweep's row: one run, as the table reports it.

use zenosim::Execution;

use crate::message::message;
use crate::Status;

/// What one run of a sweep reports (no trajectory is kept).
/// (No `PartialEq`: NaN marks what a run did not reach; compare rows by their `Debug` text.)
#[derive(Clone, Debug)]
pub struct Row {
    /// The point's index in the whole sweep (from 0), whatever the shard.
    pub index: usize,
    /// The point's values, one per axis in order.
    pub values: Vec<f64>,
    /// How the run ended, or [`Status::Invalid`] for values the model refuses.
    pub status: Status,
    /// What happened, in a sentence (for an invalid point: why the model refuses it).
    pub message: String,
    /// The number of impacts.
    pub impacts: u64,
    /// The estimate of `τ∞` of the first Zeno point; NaN where there is none.
    pub t_zeno: f64,
    /// When the run switched to the constrained motion at the first Zeno point (or stalled
    /// there, with `zeno = off`); NaN where there is none.
    pub t_switch: f64,
    /// The time the run ended at; NaN for an invalid point.
    pub t_final: f64,
    /// The final coordinates; NaN for an invalid point.
    pub q: Vec<f64>,
    /// The final velocities; NaN for an invalid point.
    pub q_dot: Vec<f64>,
}

impl Row {
    /// The row of `run`, made at point `index` of `values`, of a model whose constraints are
    /// named `constraints`.
    pub fn of(index: usize, values: Vec<f64>, run: &Execution, constraints: &[String]) -> Self {
        let first = run.zeno.first();
        Self {
            index,
            values,
            status: Status::of(&run.outcome),
            message: message(run, constraints),
            impacts: run.stats.impacts,
            t_zeno: first.map_or(f64::NAN, |z| z.t_zeno),
            t_switch: first.map_or(f64::NAN, |z| z.t_switch),
            t_final: run.t_final,
            q: run.final_state.q.clone(),
            q_dot: run.final_state.q_dot.clone(),
        }
    }

    /// The row of a point never run, of `status` ([`Status::Invalid`], or [`Status::Failed`]
    /// for a run that could not complete at all), with `message` saying why, for a model of
    /// `dimension` coordinates.
    pub fn not_run(
        index: usize,
        values: Vec<f64>,
        status: Status,
        message: String,
        dimension: usize,
    ) -> Self {
        Self {
            index,
            values,
            status,
            message,
            impacts: 0,
            t_zeno: f64::NAN,
            t_switch: f64::NAN,
            t_final: f64::NAN,
            q: vec![f64::NAN; dimension],
            q_dot: vec![f64::NAN; dimension],
        }
    }

    /// The number in column `column` of [`super::Sweep::columns`]: the index, a value, the
    /// impacts, a time or a final coordinate or velocity; `None` for `status` and `message`
    /// (and past the last column).
    pub fn number(&self, column: usize) -> Option<f64> {
        let axes = self.values.len();
        let n = self.q.len();
        match column {
            0 => Some(self.index as f64),
            c if c <= axes => Some(self.values[c - 1]),
            c => match c - axes {
                1 => None,
                2 => Some(self.impacts as f64),
                3 => Some(self.t_zeno),
                4 => Some(self.t_switch),
                5 => Some(self.t_final),
                k if k < 6 + n => Some(self.q[k - 6]),
                k if k < 6 + 2 * n => Some(self.q_dot[k - 6 - n]),
                _ => None,
            },
        }
    }
}
