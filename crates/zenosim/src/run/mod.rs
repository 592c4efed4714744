//! The run: the loop that joins the integrator, the event location and the mode logic, and the
//! record it produces.
//!
//! Every event follows the same sequence (as in DifferentialEquations.jl's callbacks): locate the
//! root on the dense output, save the state before, apply the effect, save the state after,
//! restart the integrator from there (its caches are rebuilt). The loop ([`Runner::drive`]) takes
//! a step in the current mode and hands it to the mode's logic, one file each:
//! - `equations.rs`: the equations of motion of a mode (free, or held on a set of constraints);
//! - `flight.rs`: after a free step, a guard crossed: the event state, and the constraints
//!   reached at that instant;
//! - `impact.rs`: the impact law on the constraints reached (and those held), and what holds
//!   after it;
//! - `completion.rs`: the Zeno rules and the switch through `R∞` (or the stall);
//! - `held.rs`: after a step held on a set: another constraint reached, or lift-off;
//! - `mode.rs`: the transitions between modes (impact, switch, lift-off), each applied in one
//!   place, and the restart after them;
//! - `watch.rs`: the impacts that may be accumulating to a Zeno point;
//! - `record.rs`, `work.rs`: events, intervals, samples and the energy balance;
//! - `failure.rs`: errors with their context, and ending a run that keeps what it computed.
//!
//! One constraint is a set of size 1 throughout: where one constraint can be asked more
//! cheaply than a set, [`crate::contact`]'s set operations do so themselves.
//!
//! The laws for several contacts are stated in docs/contact-laws.md.

mod completion;
mod equations;
mod failure;
mod flight;
mod held;
mod impact;
mod mode;
mod record;
mod watch;
mod work;

use crate::error::Error;
use crate::execution::{ActiveSet, Execution, Grips, HybridInterval, Mode, Outcome, RunStats};
use crate::integrator::{StepError, Stepper};
use crate::mechanics::{DynamicsError, Mechanics};
use crate::model::HybridLagrangian;
use crate::observer::Observer;
use crate::simulation::Simulation;
use equations::Equations;
use record::{split, Recorder};
use watch::ZenoWatch;

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

/// One run in progress: the loop's own state (the mode, the committed time and state, what
/// the next step needs), the record it writes, and the Zeno watch.
pub(crate) struct Runner<'s, 'a, L, O> {
    sim: &'s Simulation<'a, L>,
    mech: Mechanics<'a, L>,
    stepper: Stepper,
    n: usize,
    mode: Mode,
    /// The last committed time and state.
    t: f64,
    y: Vec<f64>,
    /// The run's own time scale: its first step, from the motion at the start (the integrator's
    /// `hinit`). Near `t = 0` the run's time resolution is a fraction of it
    /// ([`Runner::time_resolution`]).
    time_scale: f64,
    /// The largest next step, from the predicted flight after an impact.
    flight_bound: f64,
    /// The lift margin of the held constraints ([`crate::contact::margin`]) at the start of the
    /// current step.
    margin_start: f64,
    /// The friction states of the held contacts (docs/friction.md).
    grips: Grips,
    /// With friction, the scales of the held contacts' margins, fixed when the mode starts
    /// ([`crate::friction::Frame::scales`]).
    scales: Vec<f64>,
    /// Whether free flight is a parabola ([`HybridLagrangian::parabolic_flight`]).
    parabolic: bool,
    /// Whether the last step is a free flight on a parabola (declared, and the acceleration the
    /// same to the bit at both its ends; a step taken in closed form, [`Runner::step_on_parabola`],
    /// always is): states inside it are then read off its cubic Hermite interpolant, exact
    /// there, instead of its dense output, and the state at an impact without stepping to it
    /// again.
    cubic: bool,
    /// What the run records: events, intervals, Zeno points, samples, the energy balance.
    record: Recorder<'s, O>,
    /// The impacts that may be accumulating.
    watch: ZenoWatch,
    scratch: Vec<f64>,
    w: Vec<f64>,
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
            mech: Mechanics::new(sim.model).with_slip_floor(sim.options.tolerances.atol),
            stepper: Stepper::new(options.method, 2 * n, options.tolerances),
            n,
            mode: Mode::Free,
            t: 0.0,
            y,
            time_scale: f64::MIN_POSITIVE,
            flight_bound: f64::INFINITY,
            margin_start: 0.0,
            grips: Grips::none(),
            scales: Vec::new(),
            parabolic: sim.model.parabolic_flight(),
            cubic: false,
            record: Recorder::new(observer, n, m, in_space(sim.model)),
            watch: ZenoWatch::new(),
            scratch: vec![0.0; 2 * n],
            w: vec![0.0; n],
        }
    }

    /// Runs to the end and returns the record.
    pub fn run(mut self) -> Execution {
        let outcome = match self.drive() {
            Ok(outcome) => outcome,
            Err(error) => Outcome::Failed(error),
        };
        let record = self.record;
        let mut intervals = record.intervals;
        intervals.push(HybridInterval {
            start: record.interval_start,
            end: self.t,
            mode: self.mode,
        });
        let stats = self.stepper.stats();
        Execution {
            outcome,
            intervals,
            events: record.events,
            zeno: record.zeno,
            t_final: self.t,
            final_state: split(&self.y, self.n),
            final_mode: self.mode,
            stats: RunStats {
                steps: stats.steps,
                rejected_steps: stats.rejected_steps,
                rhs_evals: stats.rhs_evals,
                impacts: record.impacts,
                spurious_events: record.spurious,
            },
            work: record.work_at_t,
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
            if self.record.interrupt_asked || self.record.observer.interrupted() {
                // The state where it stops ends the trajectory (on a uniform output grid too).
                let (t, y) = (self.t, self.y.clone());
                self.advance_work(t)?;
                self.emit(t, &y, self.mode, self.grips)?;
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
                Mode::Constrained(held) => {
                    let end = eqs.end.filter(|&(t, _)| t == self.stepper.t());
                    self.after_held_step(held, end.map(|(_, normal)| normal))?
                }
            };
            if let Next::Stop(outcome) = next {
                return Ok(outcome);
            }
        }
        Ok(Outcome::Finished)
    }

    fn equations(&self) -> Equations<'a, L> {
        Equations::new(self.mech, self.held(), self.grips, self.n)
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

/// Whether any constraint of `model` with friction is a contact in space (two slip components).
fn in_space<L: HybridLagrangian>(model: &L) -> bool {
    model
        .constraints()
        .iter()
        .enumerate()
        .any(|(i, c)| c.has_friction() && model.slip_components(i) == 2)
}
