//! The run: the loop that joins the integrator, the event location and the mode logic, and the
//! record it produces.
//!
//! Every event follows the same sequence (as in DifferentialEquations.jl's callbacks): locate the
//! root on the dense output, save the state before, apply the effect, save the state after,
//! restart the integrator from there (its caches are rebuilt). The loop ([`Runner::drive`]) takes
//! a step in the current mode and hands it to the mode's logic, one file each:
//! - `equations.rs`: the equations of motion of a mode (free, held on one constraint, on a set);
//! - `flight.rs`: after a free step, a guard crossed: the event state, and the constraints
//!   closed there;
//! - `impact.rs`: the impact law on one constraint or a set, and what holds after it;
//! - `completion.rs`: the Zeno rules and the switch through `R∞` (or the stall);
//! - `held.rs`: after a step on one constraint or a set: another reached, or lift-off;
//! - `record.rs`: events, intervals and samples;
//! - `failure.rs`: errors with their context, and ending a run that keeps what it computed.
//!
//! The laws for several contacts are stated in docs/contact-laws.md.

mod completion;
mod equations;
mod failure;
mod flight;
mod held;
mod impact;
mod record;
mod work;

use crate::error::Error;
use crate::execution::{
    ActiveSet, Event, Execution, HybridInterval, Mode, Outcome, RunStats, Work, ZenoPoint,
};
use crate::integrator::{StepError, Stepper};
use crate::mechanics::{DynamicsError, Mechanics};
use crate::model::HybridLagrangian;
use crate::observer::Observer;
use crate::simulation::Simulation;
use crate::zeno::{Accumulation, ImpactSequence};
use equations::Equations;
use record::split;

/// Events in a row that may not advance time before the run treats them as chattering.
const STUCK_EVENTS: usize = 32;

/// `Auto` switches when the next bounce is within this many ulps of the guard's rounding: there
/// its height is known to about 1e-4, and the impacts after it are noise.
const AUTO_ROUND_OFF_ULPS: f64 = 1e4;

/// `Off` stalls when the next bounce is within this many ulps of the guard's rounding: impacts
/// are at round-off, the plain hybrid system cannot go on.
const OFF_ROUND_OFF_ULPS: f64 = 64.0;

/// Whether the derivatives `(q̇, q̈)` of two states of `n` coordinates have the same `q̈`, to the
/// bit: a free flight between them is a parabola.
fn same_acceleration(n: usize, a: &[f64], b: &[f64]) -> bool {
    a[n..] == b[n..]
}

/// The last step's state at `t` (inside it), off its cubic interpolant where that is exact
/// ([`Runner::cubic`]), else off its dense output (prepared: [`Runner::dense`]).
fn interpolate(stepper: &Stepper, cubic: bool, t: f64, out: &mut [f64]) {
    if cubic {
        stepper.interpolate_cubic(t, out);
    } else {
        stepper.interpolate(t, out);
    }
}

/// The mode that holds `set`: free where it is empty ([`Runner::held`] the other way).
fn holding(set: ActiveSet) -> Mode {
    if set.is_empty() {
        Mode::Free
    } else {
        Mode::Constrained(set)
    }
}

/// One run in progress.
pub(crate) struct Runner<'s, 'a, L, O> {
    sim: &'s Simulation<'a, L>,
    mech: Mechanics<'a, L>,
    observer: &'s mut O,
    stepper: Stepper,
    n: usize,
    mode: Mode,
    /// The last committed time and state.
    t: f64,
    y: Vec<f64>,
    interval_start: f64,
    intervals: Vec<HybridInterval>,
    events: Vec<Event>,
    zeno: Vec<ZenoPoint>,
    impacts: u64,
    spurious: u64,
    sequence: ImpactSequence,
    /// The impacts of a sequence that may accumulate over several constraints.
    accumulation: Accumulation,
    last_event_t: f64,
    stuck: usize,
    /// The run's own time scale: its first step, from the motion at the start (the integrator's
    /// `hinit`). Near `t = 0` the run's time resolution is a fraction of it
    /// ([`Runner::time_resolution`]).
    time_scale: f64,
    /// The largest next step, from the predicted flight after an impact.
    flight_bound: f64,
    /// [`Normal::lift_margin`] of the active constraint at the start of the current step.
    lift_margin_start: f64,
    /// On two or more constraints, the largest of their lift margins
    /// ([`crate::contact::Contacts::hold`]) at the start of the current step.
    set_margin_start: f64,
    /// The next time on a uniform output grid.
    next_output: f64,
    wants_samples: bool,
    /// Set when the observer asked to stop while a step's output grid was being written: the
    /// rest of that step's samples are skipped, and the run stops before its next step.
    interrupt_asked: bool,
    /// Whether free flight is a parabola ([`HybridLagrangian::parabolic_flight`]).
    parabolic: bool,
    /// Whether the last step is a free flight on a parabola (declared, and the acceleration the
    /// same to the bit at both its ends; a step taken in closed form, [`Runner::step_on_parabola`],
    /// always is): states inside it are then read off its cubic Hermite interpolant, exact
    /// there, instead of its dense output, and the state at an impact without stepping to it
    /// again.
    cubic: bool,
    /// The last sample sent, so that a state shared by two events is sent once.
    last_sample: (f64, Mode, Vec<f64>),
    scratch: Vec<f64>,
    w: Vec<f64>,
    h_buf: Vec<f64>,
    lambda_buf: Vec<f64>,
    /// The energy balance up to `work_t` (`work.rs`), which may run ahead of `t` inside a
    /// step, and the balance at `t` itself: the record's.
    work: Work,
    work_t: f64,
    work_at_t: Work,
    /// The loss and the work of the impact being recorded, from its law (`work.rs`).
    jump: Option<(f64, f64)>,
}

/// What the post-step logic decided.
enum Next {
    Continue,
    Stop(Outcome),
}

impl<'s, 'a, L: HybridLagrangian, O: Observer> Runner<'s, 'a, L, O> {
    pub fn new(sim: &'s Simulation<'a, L>, observer: &'s mut O) -> Self {
        let n = sim.q0.len();
        let m = sim.model.constraints().len();
        let options = &sim.options;
        let mut y = sim.q0.clone();
        y.extend_from_slice(&sim.q_dot0);
        Self {
            sim,
            mech: Mechanics::new(sim.model),
            wants_samples: observer.wants_samples(),
            interrupt_asked: false,
            observer,
            stepper: Stepper::new(options.method, 2 * n, options.tolerances),
            n,
            mode: Mode::Free,
            t: 0.0,
            y,
            interval_start: 0.0,
            intervals: Vec::new(),
            events: Vec::new(),
            zeno: Vec::new(),
            impacts: 0,
            spurious: 0,
            sequence: ImpactSequence::default(),
            accumulation: Accumulation::default(),
            last_event_t: f64::NEG_INFINITY,
            stuck: 0,
            time_scale: f64::MIN_POSITIVE,
            flight_bound: f64::INFINITY,
            lift_margin_start: 0.0,
            set_margin_start: 0.0,
            next_output: 0.0,
            parabolic: sim.model.parabolic_flight(),
            cubic: false,
            last_sample: (f64::NAN, Mode::Free, vec![f64::NAN; 2 * n]),
            scratch: vec![0.0; 2 * n],
            w: vec![0.0; n],
            h_buf: vec![0.0; m],
            lambda_buf: vec![0.0; m],
            work: Work::default(),
            work_t: 0.0,
            work_at_t: Work::default(),
            jump: None,
        }
    }

    /// Runs to the end and returns the record.
    pub fn run(mut self) -> Execution {
        let outcome = match self.drive() {
            Ok(outcome) => outcome,
            Err(error) => Outcome::Failed(error),
        };
        self.intervals.push(HybridInterval {
            start: self.interval_start,
            end: self.t,
            mode: self.mode,
        });
        let stats = self.stepper.stats();
        Execution {
            outcome,
            intervals: self.intervals,
            events: self.events,
            zeno: self.zeno,
            t_final: self.t,
            final_state: split(&self.y, self.n),
            final_mode: self.mode,
            stats: RunStats {
                steps: stats.steps,
                rejected_steps: stats.rejected_steps,
                rhs_evals: stats.rhs_evals,
                impacts: self.impacts,
                spurious_events: self.spurious,
            },
            work: self.work_at_t,
        }
    }

    fn drive(&mut self) -> Result<Outcome, Error> {
        let options = self.sim.options;
        let y0 = self.y.clone();
        self.restart(0.0, &y0, None)?;
        self.time_scale = self.stepper.suggested_step();
        self.rest_at_start()?;
        self.emit_grid_through(0.0)?;
        if let Next::Stop(outcome) = self.contact_at_start()? {
            return Ok(outcome);
        }
        while self.t < options.t_end {
            if self.interrupt_asked || self.observer.interrupted() {
                // The state where it stops ends the trajectory (on a uniform output grid too).
                let (t, y) = (self.t, self.y.clone());
                self.advance_work(t)?;
                self.emit(t, &y, self.mode)?;
                return Ok(Outcome::Interrupted);
            }
            self.check_step_limit()?;
            let h_max = options.max_step.min(self.flight_bound);
            self.flight_bound = f64::INFINITY;
            let mut eqs = self.equations();
            let stepped = if self.parabolic && self.mode == Mode::Free {
                self.step_on_parabola(&mut eqs, options.t_end, h_max)
            } else {
                self.stepper.step(&mut eqs, options.t_end, h_max)
            };
            stepped.map_err(|e| self.step_error(e))?;
            self.cubic = self.parabolic_step();
            let next = match self.mode {
                Mode::Free => self.after_free_step()?,
                Mode::Constrained(active) => match active.only() {
                    Some(index) => {
                        let end = eqs.end.filter(|&(t, _)| t == self.stepper.t());
                        self.after_constrained_step(index, end.map(|(_, normal)| normal))?
                    }
                    None => self.after_set_step(active)?,
                },
            };
            if let Next::Stop(outcome) = next {
                return Ok(outcome);
            }
        }
        Ok(Outcome::Finished)
    }

    fn equations(&self) -> Equations<'a, L> {
        let held = self.held();
        Equations {
            mech: self.mech,
            active: held.only(),
            set: if held.len() >= 2 {
                held
            } else {
                ActiveSet::empty()
            },
            n: self.n,
            end: None,
        }
    }

    /// The constraints held in the current mode.
    fn held(&self) -> ActiveSet {
        match self.mode {
            Mode::Free => ActiveSet::empty(),
            Mode::Constrained(set) => set,
        }
    }

    /// The step limit, before every step (those that refine an event's state included).
    fn check_step_limit(&self) -> Result<(), Error> {
        let limit = self.sim.options.max_steps;
        if self.stepper.stats().steps >= limit {
            return Err(Error::Limit {
                t: self.t,
                what: "steps",
                limit,
                recent: None,
            });
        }
        Ok(())
    }

    /// One step of free flight on a parabola, its end in closed form
    /// ([`Stepper::step_exact`]: `q + h (q̇ + h q̈ / 2)`, `q̇ + h q̈`), for one evaluation instead
    /// of a Runge–Kutta step's stages (twelve for DOP853). The acceleration at the end must be
    /// the one at the start, to the bit (as [`Runner::parabolic_step`] asks of any step); where
    /// it is not, or the end cannot be evaluated, the integrator takes the step instead.
    fn step_on_parabola(
        &mut self,
        eqs: &mut Equations<'a, L>,
        t_stop: f64,
        h_max: f64,
    ) -> Result<(), StepError<DynamicsError>> {
        let n = self.n;
        let advance = |y: &[f64], dy: &[f64], h: f64, end: &mut [f64]| {
            let (q, q_dot, q_ddot) = (&y[..n], &y[n..], &dy[n..]);
            for i in 0..n {
                end[i] = q[i] + h * (q_dot[i] + 0.5 * h * q_ddot[i]);
                end[n + i] = q_dot[i] + h * q_ddot[i];
            }
        };
        let holds = |start: &[f64], end: &[f64]| same_acceleration(n, start, end);
        match self.stepper.step_exact(eqs, t_stop, h_max, advance, holds) {
            Ok(true) => Ok(()),
            Ok(false) | Err(_) => self.stepper.step(eqs, t_stop, h_max),
        }
    }

    /// Whether the last step is a free flight on a parabola (see [`Runner::cubic`]).
    fn parabolic_step(&self) -> bool {
        let n = self.n;
        self.parabolic
            && self.mode == Mode::Free
            && same_acceleration(n, self.stepper.dy_previous(), self.stepper.dy())
    }

    /// Prepares the dense output of the last step (at most once per step; the stepper keeps
    /// track), unless its states are read off the cubic interpolant.
    fn dense(&mut self) -> Result<(), Error> {
        if self.cubic {
            return Ok(());
        }
        let mut eqs = self.equations();
        let prepared = self.stepper.prepare_dense(&mut eqs);
        prepared.map_err(|e| self.step_error(e))
    }

    /// The run's time resolution at `t`: intervals shorter than this are not told apart (flights
    /// to the Zeno point, events that do not advance time). On the run's own time scale, not in
    /// seconds: a problem whose times are all scaled by `1/λ` is resolved alike.
    fn time_resolution(&self, t: f64) -> f64 {
        crate::events::time_resolution(t, self.time_scale)
    }

    /// Restarts the integrator at `(t, y)` in the current mode.
    fn restart(&mut self, t: f64, y: &[f64], hint: Option<f64>) -> Result<(), Error> {
        self.advance_work(t)?;
        self.cubic = false;
        let mut eqs = self.equations();
        let started = self.stepper.start(&mut eqs, t, y, hint);
        self.commit_time(t, y);
        started.map_err(|e| self.step_error(e))
    }
}
