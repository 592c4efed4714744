//! The record: events with their states, the hybrid time domain, and the samples sent to the
//! observer (every step, or a uniform grid off the dense output).

use super::{interpolate, Runner};
use crate::contact::{self};
use crate::derivatives::energy;
use crate::error::Error;
use crate::execution::{
    ActiveSet, Event, EventKind, Grips, HybridInterval, Mode, State, Work, ZenoPoint,
};
use crate::model::HybridLagrangian;
use crate::observer::{Observer, Sample};
use crate::options::OutputGrid;

/// What an event changed: the constraints involved and, for an impact, their normal and
/// tangential impulses (the latter empty without friction).
pub(super) struct Change {
    pub contacts: ActiveSet,
    pub impulses: Vec<f64>,
    /// In the model's slip components (the second 0 in a plane).
    pub tangential: Vec<[f64; 2]>,
}

impl Change {
    /// A change of the constraints `contacts` without impulses.
    pub fn of(contacts: ActiveSet) -> Self {
        Self {
            contacts,
            impulses: Vec::new(),
            tangential: Vec::new(),
        }
    }
}

/// What a run records, and where it sends it: the hybrid time domain, the events, the Zeno
/// points and the counts the execution reports; the samples sent to the observer; the energy
/// balance (`work.rs`).
pub(super) struct Recorder<'s, O> {
    pub observer: &'s mut O,
    pub wants_samples: bool,
    /// Set when the observer asked to stop while a step's output grid was being written: the
    /// rest of that step's samples are skipped, and the run stops before its next step.
    pub interrupt_asked: bool,
    /// The next time on a uniform output grid.
    pub next_output: f64,
    /// Where the current interval of the hybrid time domain began.
    pub interval_start: f64,
    pub intervals: Vec<HybridInterval>,
    pub events: Vec<Event>,
    pub zeno: Vec<ZenoPoint>,
    pub impacts: u64,
    pub spurious: u64,
    /// The last sample sent, so that a state shared by two events is sent once.
    pub last_sample: (f64, Mode, Grips, Vec<f64>),
    pub h_buf: Vec<f64>,
    pub lambda_buf: Vec<f64>,
    pub friction_buf: Vec<f64>,
    /// The second component of the tangential forces (contacts in space).
    pub across_buf: Vec<f64>,
    /// The energy balance up to `work_t` (`work.rs`), which may run ahead of `t` inside a
    /// step, and the balance at `t` itself: the record's.
    pub work: Work,
    pub work_t: f64,
    pub work_at_t: Work,
    /// The loss and the work of the impact being recorded, from its law (`work.rs`).
    pub jump: Option<(f64, f64)>,
}

impl<'s, O: Observer> Recorder<'s, O> {
    /// The record of a run of `n` coordinates and `m` constraints, sent to `observer`; with
    /// the second components of the tangential forces where the model has a contact in space
    /// (`in_space`; else its samples' `friction_across` is empty).
    pub fn new(observer: &'s mut O, n: usize, m: usize, in_space: bool) -> Self {
        Self {
            wants_samples: observer.wants_samples(),
            observer,
            interrupt_asked: false,
            next_output: 0.0,
            interval_start: 0.0,
            intervals: Vec::new(),
            events: Vec::new(),
            zeno: Vec::new(),
            impacts: 0,
            spurious: 0,
            last_sample: (f64::NAN, Mode::Free, Grips::none(), vec![f64::NAN; 2 * n]),
            h_buf: vec![0.0; m],
            lambda_buf: vec![0.0; m],
            friction_buf: vec![0.0; m],
            across_buf: vec![0.0; if in_space { m } else { 0 }],
            work: Work::default(),
            work_t: 0.0,
            work_at_t: Work::default(),
            jump: None,
        }
    }
}

impl<L: HybridLagrangian, O: Observer> Runner<'_, '_, L, O> {
    /// Records an event at `t` from `before` (in the current mode) to `after` (in `new_mode`,
    /// its held contacts in the friction states `grips`), with its samples, and closes the
    /// current interval of the hybrid time domain. `change` is the constraints involved and,
    /// for an impact, their impulses.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn record_event(
        &mut self,
        kind: EventKind,
        constraint: usize,
        change: Change,
        t: f64,
        before: &[f64],
        after: &[f64],
        new_mode: Mode,
        grips: Grips,
    ) -> Result<(), Error> {
        let limit = self.sim.options.max_events;
        if self.record.events.len() as u64 >= limit {
            // How quickly the last events came, to tell a storm from a long Zeno sequence.
            let count = self.record.events.len().min(100);
            let recent = self.record.events[self.record.events.len() - count..]
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
        self.emit(t, before, self.mode, self.grips)?;
        let Change {
            contacts,
            impulses,
            tangential,
        } = change;
        self.record_jump(kind, contacts, t, before, after)?;
        let model = self.sim.model;
        let in_space = contacts
            .iter()
            .any(|i| model.constraints()[i].has_friction() && model.slip_components(i) == 2);
        let tangential_across = if in_space {
            tangential.iter().map(|f| f[1]).collect()
        } else {
            Vec::new()
        };
        let tangential = tangential.iter().map(|f| f[0]).collect();
        let event = Event {
            kind,
            t,
            constraint,
            contacts,
            impulses,
            tangential,
            tangential_across,
            grips,
            before: split(before, self.n),
            after: split(after, self.n),
        };
        self.record.observer.event(&event);
        self.record.events.push(event);
        self.record.intervals.push(HybridInterval {
            start: self.record.interval_start,
            end: t,
            mode: self.mode,
        });
        self.record.interval_start = t;
        self.mode = new_mode;
        self.grips = grips;
        self.emit(t, after, new_mode, grips)?;
        Ok(())
    }

    /// Accepts the stepper's step as the execution's: output, and the committed state.
    pub(super) fn commit_step(&mut self) -> Result<(), Error> {
        let t1 = self.stepper.t();
        self.advance_work(t1)?;
        match self.sim.options.output {
            // (An observer that takes no samples costs no copy of the state.)
            OutputGrid::Steps if self.record.wants_samples => {
                let y = self.stepper.y().to_vec();
                self.emit(t1, &y, self.mode, self.grips)?;
            }
            OutputGrid::Steps => {}
            OutputGrid::Uniform(_) => self.emit_grid_through(t1)?,
        }
        // (`commit_time`, without copying the state first.)
        self.t = t1;
        self.y.copy_from_slice(self.stepper.y());
        if self.record.work_t == t1 {
            self.record.work_at_t = self.record.work;
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
            self.emit(0.0, &y0, self.mode, self.grips)?;
            if let OutputGrid::Uniform(dt) = self.sim.options.output {
                self.record.next_output = dt;
            }
            return Ok(());
        }
        self.emit_grid(t, true)
    }

    pub(super) fn emit_grid(&mut self, t: f64, inclusive: bool) -> Result<(), Error> {
        let OutputGrid::Uniform(dt) = self.sim.options.output else {
            return Ok(());
        };
        if !self.record.wants_samples {
            return Ok(());
        }
        if self.record.next_output > t || (!inclusive && self.record.next_output == t) {
            return Ok(());
        }
        self.dense()?;
        let mut y = vec![0.0; 2 * self.n];
        let mut written = 0_u32;
        while self.record.next_output < t || (inclusive && self.record.next_output == t) {
            // One step may hold millions of grid points (a body at rest, a fine `dt`): the
            // observer is asked every few thousand whether to stop, as before every step.
            written = written.wrapping_add(1);
            if written.is_multiple_of(4096) && self.record.observer.interrupted() {
                self.record.interrupt_asked = true;
                return Ok(());
            }
            let to = self.record.next_output;
            interpolate(&self.stepper, self.cubic, to, &mut y);
            contact::project_onto(&self.mech, self.held(), self.grips, to, self.n, &mut y)
                .map_err(|err| self.dynamics_error(err, to, &self.y.clone()))?;
            self.emit(to, &y, self.mode, self.grips)?;
            let k = (to / dt).round() + 1.0;
            self.record.next_output = k * dt;
        }
        Ok(())
    }

    /// Sends one sample to the observer: `(t, y)` in `mode`, its held contacts in the friction
    /// states `grips`.
    pub(super) fn emit(
        &mut self,
        t: f64,
        y: &[f64],
        mode: Mode,
        grips: Grips,
    ) -> Result<(), Error> {
        if !self.record.wants_samples {
            return Ok(());
        }
        // A sample is sent once, but for a change of the friction states alone (a stick or
        // slip event: same time, mode and state), whose row after the event has its own.
        let (last_t, last_mode, last_grips, last_y) = &mut self.record.last_sample;
        if *last_t == t && *last_mode == mode && *last_grips == grips && last_y.as_slice() == y {
            return Ok(());
        }
        (*last_t, *last_mode, *last_grips) = (t, mode, grips);
        last_y.copy_from_slice(y);
        let (q, q_dot) = y.split_at(self.n);
        let model = self.sim.model;
        for (i, h) in self.record.h_buf.iter_mut().enumerate() {
            *h = model.constraint_at(i, t, q);
        }
        self.record.lambda_buf.iter_mut().for_each(|l| *l = 0.0);
        self.record.friction_buf.iter_mut().for_each(|f| *f = 0.0);
        self.record.across_buf.iter_mut().for_each(|f| *f = 0.0);
        if let Mode::Constrained(held) = mode {
            let mut w = std::mem::take(&mut self.w);
            let record = &mut self.record;
            let (lambda, friction, across) = (
                &mut record.lambda_buf,
                &mut record.friction_buf,
                &mut record.across_buf,
            );
            let found = contact::multipliers(
                &self.mech,
                held,
                grips,
                t,
                q,
                q_dot,
                &mut w,
                |i, l, _, f, _, _| {
                    lambda[i] = l;
                    friction[i] = f[0];
                    if let Some(a) = across.get_mut(i) {
                        *a = f[1];
                    }
                },
            );
            self.w = w;
            found.map_err(|err| self.dynamics_error(err, t, y))?;
        }
        let work = self.work_at(t)?;
        let sample = Sample {
            t,
            mode,
            q,
            q_dot,
            h: &self.record.h_buf,
            lambda: &self.record.lambda_buf,
            friction: &self.record.friction_buf,
            friction_across: &self.record.across_buf,
            grips,
            energy: energy(model, t, q, q_dot),
            work,
        };
        self.record.observer.sample(&sample);
        Ok(())
    }
}

pub(super) fn split(y: &[f64], n: usize) -> State {
    State {
        q: y[..n].to_vec(),
        q_dot: y[n..].to_vec(),
    }
}
