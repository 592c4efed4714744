//! Watching a run: the trajectory is streamed to an [`Observer`] as it is computed, so memory
//! stays flat however long the run; [`Trajectory`] keeps it in memory instead.

use crate::execution::{Event, Grips, Mode, Work};

/// One point of the trajectory, with what the mechanics says there.
#[derive(Clone, Copy, Debug)]
pub struct Sample<'a> {
    /// The time.
    pub t: f64,
    /// The mode.
    pub mode: Mode,
    /// The configuration.
    pub q: &'a [f64],
    /// The velocities.
    pub q_dot: &'a [f64],
    /// `h_i(q)` of every constraint.
    pub h: &'a [f64],
    /// `λ_i` of every constraint (0 where inactive; the contact force is `−A_iᵀ λ_i`).
    pub lambda: &'a [f64],
    /// The tangential force `fₜ,ᵢ` of every constraint (0 where inactive or frictionless; it
    /// acts along `Sᵢᵀ`, positive along increasing slip: docs/friction.md).
    pub friction: &'a [f64],
    /// The second component of the tangential force of every constraint whose contact is in
    /// space (docs/friction.md; 0 elsewhere), one per constraint; empty where the model has no
    /// contact in space.
    pub friction_across: &'a [f64],
    /// The friction states of the held contacts.
    pub grips: Grips,
    /// The energy `q̇ᵀ ∂L/∂q̇ − L`.
    pub energy: f64,
    /// The energy balance from the start to `t` ([`Work`]).
    pub work: Work,
}

/// Receives the trajectory and the events of a run as they happen.
pub trait Observer {
    /// A point of the trajectory: at every accepted step (or output time), and just before and
    /// just after every event.
    fn sample(&mut self, _sample: &Sample<'_>) {}

    /// An event, once it has happened.
    fn event(&mut self, _event: &Event) {}

    /// Whether [`Observer::sample`] wants to be called at all (samples cost some work). Default true.
    fn wants_samples(&self) -> bool {
        true
    }

    /// Whether the caller wants the run to stop now (Ctrl-C, a cancelled sweep), asked before
    /// every step, and every 4096 points of a uniform output grid within a step (one step of a
    /// body at rest may hold millions). When it says yes, the run ends with
    /// [`crate::Outcome::Interrupted`] before its next step (the rest of the current step's
    /// grid points are skipped, and the state where it stops is the last sample), keeping
    /// everything computed up to there. Default false.
    fn interrupted(&mut self) -> bool {
        false
    }
}

/// An observer that ignores everything (for benchmarks and callers that need only the record).
impl Observer for () {
    fn wants_samples(&self) -> bool {
        false
    }
}

/// One stored point of a [`Trajectory`].
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// The time.
    pub t: f64,
    /// The mode.
    pub mode: Mode,
    /// The configuration.
    pub q: Vec<f64>,
    /// The velocities.
    pub q_dot: Vec<f64>,
    /// `h_i(q)` of every constraint.
    pub h: Vec<f64>,
    /// `λ_i` of every constraint.
    pub lambda: Vec<f64>,
    /// The tangential force `fₜ,ᵢ` of every constraint.
    pub friction: Vec<f64>,
    /// The second component of the tangential force of every constraint in space.
    pub friction_across: Vec<f64>,
    /// The friction states of the held contacts.
    pub grips: Grips,
    /// The energy.
    pub energy: f64,
    /// The energy balance from the start ([`Work`]).
    pub work: Work,
}

/// An observer that keeps the whole trajectory in memory.
#[derive(Clone, Debug, Default)]
pub struct Trajectory {
    /// The points, in time order.
    pub points: Vec<Point>,
}

impl Trajectory {
    /// The worst residual of the energy balance over the samples,
    /// `|E(t) − E(0) − work.balance()|` relative to the size of the energies and works
    /// involved (docs/forces-and-time.md): of the order of the integration tolerance, at most;
    /// 0 without samples.
    pub fn balance_residual(&self) -> f64 {
        let Some(first) = self.points.first() else {
            return 0.0;
        };
        let e0 = first.energy;
        self.points
            .iter()
            .map(|p| {
                let w = &p.work;
                let size = e0.abs()
                    + p.energy.abs()
                    + w.forces.abs()
                    + w.drive.abs()
                    + w.constraints.abs()
                    + w.friction.abs()
                    + w.impact_loss.abs();
                let residual = (p.energy - e0 - w.balance()).abs();
                if residual == 0.0 {
                    0.0
                } else {
                    residual / size
                }
            })
            .fold(0.0, f64::max)
    }
}

impl Point {
    /// The sample `s`, kept past the call that delivered it.
    pub fn of(s: &Sample<'_>) -> Point {
        Point {
            t: s.t,
            mode: s.mode,
            q: s.q.to_vec(),
            q_dot: s.q_dot.to_vec(),
            h: s.h.to_vec(),
            lambda: s.lambda.to_vec(),
            friction: s.friction.to_vec(),
            friction_across: s.friction_across.to_vec(),
            grips: s.grips,
            energy: s.energy,
            work: s.work,
        }
    }

    /// Becomes the sample `s`, reusing its vectors.
    pub fn set(&mut self, s: &Sample<'_>) {
        (self.t, self.mode, self.energy, self.work) = (s.t, s.mode, s.energy, s.work);
        self.grips = s.grips;
        for (mine, theirs) in [
            (&mut self.q, s.q),
            (&mut self.q_dot, s.q_dot),
            (&mut self.h, s.h),
            (&mut self.lambda, s.lambda),
            (&mut self.friction, s.friction),
            (&mut self.friction_across, s.friction_across),
        ] {
            mine.clear();
            mine.extend_from_slice(theirs);
        }
    }

    /// The point as a [`Sample`].
    pub fn sample(&self) -> Sample<'_> {
        Sample {
            t: self.t,
            mode: self.mode,
            q: &self.q,
            q_dot: &self.q_dot,
            h: &self.h,
            lambda: &self.lambda,
            friction: &self.friction,
            friction_across: &self.friction_across,
            grips: self.grips,
            energy: self.energy,
            work: self.work,
        }
    }
}

impl Observer for Trajectory {
    fn sample(&mut self, s: &Sample<'_>) {
        self.points.push(Point::of(s));
    }
}
