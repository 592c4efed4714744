//! The record: events with their states, the hybrid time domain, and the samples sent to the
//! observer (every step, or a uniform grid off the dense output).

use super::equations::project_onto;
use super::{interpolate, Runner};
use crate::contact::{self};
use crate::derivatives::energy;
use crate::error::Error;
use crate::execution::{ActiveSet, Event, EventKind, HybridInterval, Mode, State};
use crate::model::HybridLagrangian;
use crate::observer::{Observer, Sample};
use crate::options::OutputGrid;

impl<L: HybridLagrangian, O: Observer> Runner<'_, '_, L, O> {
    /// Records an event at `t` from `before` (in the current mode) to `after` (in `new_mode`),
    /// with its samples, and closes the current interval of the hybrid time domain.
    /// `change` is the constraints involved and, for an impact, their impulses.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn record_event(
        &mut self,
        kind: EventKind,
        constraint: usize,
        change: (ActiveSet, Vec<f64>),
        t: f64,
        before: &[f64],
        after: &[f64],
        new_mode: Mode,
    ) -> Result<(), Error> {
        let limit = self.sim.options.max_events;
        if self.events.len() as u64 >= limit {
            // How quickly the last events came, to tell a storm from a long Zeno sequence.
            let count = self.events.len().min(100);
            let recent = self.events[self.events.len() - count..]
                .first()
                .map(|first| (count as u64, t - first.t));
            let error = Error::Limit {
                t,
                what: "events",
                limit,
                recent,
            };
            return Err(self.fail_at(t, before, error));
        }
        self.advance_work(t)?;
        self.emit(t, before, self.mode)?;
        let (contacts, impulses) = change;
        self.record_jump(kind, contacts, t, before, after)?;
        let event = Event {
            kind,
            t,
            constraint,
            contacts,
            impulses,
            before: split(before, self.n),
            after: split(after, self.n),
        };
        self.observer.event(&event);
        self.events.push(event);
        self.intervals.push(HybridInterval {
            start: self.interval_start,
            end: t,
            mode: self.mode,
        });
        self.interval_start = t;
        self.mode = new_mode;
        self.emit(t, after, new_mode)?;
        Ok(())
    }

    /// Accepts the stepper's step as the execution's: output, and the committed state.
    pub(super) fn commit_step(&mut self) -> Result<(), Error> {
        let t1 = self.stepper.t();
        self.advance_work(t1)?;
        match self.sim.options.output {
            // (An observer that takes no samples costs no copy of the state.)
            OutputGrid::Steps if self.wants_samples => {
                let y = self.stepper.y().to_vec();
                self.emit(t1, &y, self.mode)?;
            }
            OutputGrid::Steps => {}
            OutputGrid::Uniform(_) => self.emit_grid_through(t1)?,
        }
        // (`commit_time`, without copying the state first.)
        self.t = t1;
        self.y.copy_from_slice(self.stepper.y());
        if self.work_t == t1 {
            self.work_at_t = self.work;
        }
        Ok(())
    }

    /// Uniform grid points strictly before `t` (the states around an event come next).
    pub(super) fn emit_grid_before(&mut self, t: f64) -> Result<(), Error> {
        self.emit_grid(t, false)
    }

    /// Uniform grid points up to and including `t` (and the initial point at `t = 0`).
    pub(super) fn emit_grid_through(&mut self, t: f64) -> Result<(), Error> {
        if t == 0.0 {
            let y0 = self.y.clone();
            self.emit(0.0, &y0, self.mode)?;
            if let OutputGrid::Uniform(dt) = self.sim.options.output {
                self.next_output = dt;
            }
            return Ok(());
        }
        self.emit_grid(t, true)
    }

    pub(super) fn emit_grid(&mut self, t: f64, inclusive: bool) -> Result<(), Error> {
        let OutputGrid::Uniform(dt) = self.sim.options.output else {
            return Ok(());
        };
        if !self.wants_samples {
            return Ok(());
        }
        if self.next_output > t || (!inclusive && self.next_output == t) {
            return Ok(());
        }
        self.dense()?;
        let mut y = vec![0.0; 2 * self.n];
        let mut written = 0_u32;
        while self.next_output < t || (inclusive && self.next_output == t) {
            // One step may hold millions of grid points (a body at rest, a fine `dt`): the
            // observer is asked every few thousand whether to stop, as before every step.
            written = written.wrapping_add(1);
            if written.is_multiple_of(4096) && self.observer.interrupted() {
                self.interrupt_asked = true;
                return Ok(());
            }
            let to = self.next_output;
            interpolate(&self.stepper, self.cubic, to, &mut y);
            project_onto(&self.mech, self.held(), to, self.n, &mut y)
                .map_err(|err| self.dynamics_error(err, to, &self.y.clone()))?;
            self.emit(to, &y, self.mode)?;
            let k = (to / dt).round() + 1.0;
            self.next_output = k * dt;
        }
        Ok(())
    }

    /// Sends one sample to the observer.
    pub(super) fn emit(&mut self, t: f64, y: &[f64], mode: Mode) -> Result<(), Error> {
        if !self.wants_samples {
            return Ok(());
        }
        let (last_t, last_mode, last_y) = &mut self.last_sample;
        if *last_t == t && *last_mode == mode && last_y.as_slice() == y {
            return Ok(());
        }
        (*last_t, *last_mode) = (t, mode);
        last_y.copy_from_slice(y);
        let (q, q_dot) = y.split_at(self.n);
        let model = self.sim.model;
        for (i, h) in self.h_buf.iter_mut().enumerate() {
            *h = model.constraint_at(i, t, q);
        }
        self.lambda_buf.iter_mut().for_each(|l| *l = 0.0);
        if let Mode::Constrained(active) = mode {
            if let Some(index) = active.only() {
                let mut w = std::mem::take(&mut self.w);
                let normal = self.mech.normal(index, t, q, q_dot, &mut w);
                self.w = w;
                self.lambda_buf[index] = normal
                    .map_err(|err| self.dynamics_error(err, t, y))?
                    .lambda();
            } else {
                let mut acc = vec![0.0; self.n];
                let held = contact::held_acceleration(&self.mech, active, t, q, q_dot, &mut acc);
                let (contacts, hold) = held.map_err(|err| self.dynamics_error(err, t, y))?;
                for (&index, l) in contacts.indices.iter().zip(hold.lambda) {
                    self.lambda_buf[index] = l;
                }
            }
        }
        let work = self.work_at(t)?;
        let sample = Sample {
            t,
            mode,
            q,
            q_dot,
            h: &self.h_buf,
            lambda: &self.lambda_buf,
            energy: energy(model, t, q, q_dot),
            work,
        };
        self.observer.sample(&sample);
        Ok(())
    }
}

pub(super) fn split(y: &[f64], n: usize) -> State {
    State {
        q: y[..n].to_vec(),
        q_dot: y[n..].to_vec(),
    }
}
