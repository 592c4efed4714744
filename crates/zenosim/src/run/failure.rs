//! Failures: the mechanics' errors with their time and constraints' names, and ending a run
//! that keeps everything computed up to the failure.

use super::Runner;
use crate::error::Error;
use crate::integrator::StepError;
use crate::mechanics::{DynamicsError, Normal};
use crate::model::HybridLagrangian;
use crate::observer::Observer;

impl<L: HybridLagrangian, O: Observer> Runner<'_, '_, L, O> {
    pub(super) fn normal(
        &mut self,
        index: usize,
        t: f64,
        q: &[f64],
        q_dot: &[f64],
    ) -> Result<Normal, Error> {
        let mut w = std::mem::take(&mut self.w);
        let normal = self.mech.normal(index, t, q, q_dot, &mut w);
        self.w = w;
        normal.map_err(|err| {
            let mut y = q.to_vec();
            y.extend_from_slice(q_dot);
            self.fail_dynamics(err, t, &y)
        })
    }

    pub(super) fn dynamics_error(&self, err: DynamicsError, t: f64, y: &[f64]) -> Error {
        let name = |i: usize| self.sim.model.constraints()[i].name.clone();
        match err {
            DynamicsError::MassMatrix => Error::SingularMassMatrix {
                t,
                q: y[..self.n].to_vec(),
                q_dot: y[self.n..].to_vec(),
            },
            DynamicsError::DegenerateConstraint { constraint } => Error::DegenerateConstraint {
                t,
                constraint: name(constraint),
            },
            DynamicsError::NonFinite => Error::NonFinite { t },
            DynamicsError::Projection {
                constraint,
                residual,
            } => Error::Projection {
                t,
                constraint: name(constraint),
                residual,
            },
            DynamicsError::NearlyDependent { constraints } => Error::NearlyDependent {
                t,
                constraints: constraints.iter().map(name).collect(),
            },
            DynamicsError::ContactProblem { constraints } => Error::ContactProblem {
                t,
                constraints: constraints.iter().map(name).collect(),
            },
            DynamicsError::Painleve { constraints } => Error::Painleve {
                t,
                constraints: constraints.iter().map(name).collect(),
            },
            DynamicsError::SpatialFriction { constraints } => Error::SpatialFriction {
                t,
                constraints: constraints.iter().map(name).collect(),
            },
            DynamicsError::ContactSolver {
                constraints,
                stop,
                conditioning,
            } => Error::ContactSolver {
                t,
                constraints: constraints.iter().map(name).collect(),
                stop,
                conditioning,
            },
        }
    }

    pub(super) fn step_error(&self, err: StepError<DynamicsError>) -> Error {
        match err {
            StepError::Rhs { t, source } => self.dynamics_error(source, t, self.stepper.y()),
            StepError::StepSizeUnderflow { t, h } => Error::StepSizeUnderflow { t, h },
            StepError::NonFinite { t } => Error::NonFinite { t },
        }
    }

    /// Ends the run at `(t, y)` with the error the mechanics reported there.
    pub(super) fn fail_dynamics(&mut self, err: DynamicsError, t: f64, y: &[f64]) -> Error {
        let error = self.dynamics_error(err, t, y);
        self.fail_at(t, y, error)
    }

    /// Ends the run at `(t, y)` with `error`, keeping the execution up to there: the output
    /// up to `t` is sent, and `(t, y)` becomes the record's last state.
    pub(super) fn fail_at(&mut self, t: f64, y: &[f64], error: Error) -> Error {
        // Best effort: the run is failing already; what can be sent is sent.
        let _ = self.emit_grid_before(t);
        let _ = self.advance_work(t);
        let _ = self.emit(t, y, self.mode, self.grips);
        self.commit_time(t, y);
        error
    }
}
