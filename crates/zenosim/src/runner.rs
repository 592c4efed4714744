//! The loop that joins the integrator, the event location and the mode logic, and the record it
//! produces.
//!
//! Every event follows the same sequence (as in DifferentialEquations.jl's callbacks): locate the
//! root on the dense output, save the state before, apply the effect, save the state after,
//! restart the integrator from there (its caches are rebuilt).

use crate::contact::{self, Contacts};
use crate::derivatives::{energy, guard_along};
use crate::error::Error;
use crate::events::{first_crossing, time_resolution};
use crate::execution::{
    ActiveSet, Event, EventKind, Execution, HybridInterval, Mode, Outcome, RunStats, State,
    ZenoKind, ZenoPoint,
};
use crate::integrator::{OdeSystem, StepError, Stepper};
use crate::mechanics::{guard_scale, DynamicsError, Mechanics, Normal};
use crate::model::HybridLagrangian;
use crate::observer::{Observer, Sample};
use crate::options::{Completion, OutputGrid, ZenoStrategy};
use crate::simulation::Simulation;
use crate::zeno::{Accumulation, ImpactSequence, Prediction};

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

/// The equations of motion of one mode, as the integrator sees them: `y = (q, q̇)`.
struct Equations<'a, L> {
    mech: Mechanics<'a, L>,
    /// The constraint held, where exactly one is.
    active: Option<usize>,
    /// The constraints held, where two or more are (else empty).
    set: ActiveSet,
    n: usize,
    /// The active constraint's normal response at the end of the last trial step, and its
    /// time: after an accepted step, at the step's end ([`OdeSystem::rhs_at_end`]).
    end: Option<(f64, Normal)>,
}

impl<L: HybridLagrangian> OdeSystem for Equations<'_, L> {
    type Error = DynamicsError;

    fn dimension(&self) -> usize {
        2 * self.n
    }

    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), DynamicsError> {
        if self.set.is_empty() {
            return self.mech.state_derivative(y, self.active, dy).map(|_| ());
        }
        let (q, q_dot) = y.split_at(self.n);
        dy[..self.n].copy_from_slice(q_dot);
        contact::held_acceleration(&self.mech, self.set, q, q_dot, &mut dy[self.n..]).map(|_| ())
    }

    /// On a constraint, the acceleration and the normal response from one evaluation of the
    /// motion: the lift-off test after the step needs the response at its end.
    fn rhs_at_end(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), DynamicsError> {
        self.end = None;
        let Some(index) = self.active else {
            return self.rhs(t, y, dy);
        };
        let (q, q_dot) = y.split_at(self.n);
        dy[..self.n].copy_from_slice(q_dot);
        let normal = self
            .mech
            .held_acceleration_and_normal(index, q, q_dot, &mut dy[self.n..])?;
        self.end = Some((t, normal));
        Ok(())
    }

    /// On a constraint, the drift of the step's end put back: `h = 0`, `A q̇ = 0`
    /// ([`Mechanics::project`]). The next step starts there, and the step's dense output ends
    /// there.
    fn correct_end(&mut self, _t: f64, y: &mut [f64]) -> Result<bool, DynamicsError> {
        let (q, q_dot) = y.split_at_mut(self.n);
        match self.active {
            Some(index) => self.mech.project(index, q, q_dot).map(|_| true),
            None if self.set.is_empty() => Ok(false),
            None => contact::project(&self.mech, self.set, q, q_dot).map(|_| true),
        }
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
    /// The largest next step, from the predicted flight after an impact.
    flight_bound: f64,
    /// [`Normal::lift_margin`] of the active constraint at the start of the current step.
    lift_margin_start: f64,
    /// On two or more constraints, the largest of their lift margins
    /// ([`Contacts::lift_margins`]) at the start of the current step.
    set_margin_start: f64,
    /// The next time on a uniform output grid.
    next_output: f64,
    wants_samples: bool,
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
        }
    }

    fn drive(&mut self) -> Result<Outcome, Error> {
        let options = self.sim.options;
        let y0 = self.y.clone();
        self.restart(0.0, &y0, None)?;
        self.emit_grid_through(0.0)?;
        if let Next::Stop(outcome) = self.contact_at_start()? {
            return Ok(outcome);
        }
        while self.t < options.t_end {
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

    /// Restarts the integrator at `(t, y)` in the current mode.
    fn restart(&mut self, t: f64, y: &[f64], hint: Option<f64>) -> Result<(), Error> {
        self.cubic = false;
        let mut eqs = self.equations();
        let started = self.stepper.start(&mut eqs, t, y, hint);
        self.t = t;
        self.y.copy_from_slice(y);
        started.map_err(|e| self.step_error(e))
    }

    // ----- free flight -------------------------------------------------------------------

    fn after_free_step(&mut self) -> Result<Next, Error> {
        let (t0, t1) = (self.stepper.t_previous(), self.stepper.t());
        // The step that found the crossing (before `state_at` steps again to it).
        let found = t1 - t0;
        let Some((index, t_event)) = self.earliest_crossing(t0, t1, ActiveSet::empty())? else {
            self.commit_step()?;
            return Ok(Next::Continue);
        };
        self.emit_grid_before(t_event)?;
        let hint = self.stepper.suggested_step();
        let before = if self.cubic {
            // The step and its interpolant are both exact on a parabola (up to rounding): the
            // interpolant gives the step's state without stepping again.
            let mut y = vec![0.0; 2 * self.n];
            self.stepper.interpolate_cubic(t_event, &mut y);
            y
        } else {
            self.state_at(t_event)?
        };
        let (t_event, before) = self.admissible_side(index, t_event, before)?;
        self.crossing(index, t_event, before, hint, found)
    }

    /// A start on a surface (`h ≤ 0`, within the rounding that [`Simulation::new`] admits) that
    /// moves into it, or rests on it pressed, is a contact at `t = 0`, decided as for a crossing
    /// found at a step's start. The search on the dense output takes a step's start as
    /// admissible and looks for dips only between positive samples: a body that moves in slowly
    /// while pulled away hard would dip in and out again before the first step's first sample,
    /// unseen.
    fn contact_at_start(&mut self) -> Result<Next, Error> {
        let n = self.n;
        let y = self.y.clone();
        let (q, q_dot) = y.split_at(n);
        // The first contact; the others at the surface join it in the impact law.
        let mut contact = None;
        for index in 0..self.sim.model.constraints().len() {
            let (h, _, _) = guard_along(self.sim.model, index, q, q_dot);
            if h > 0.0 || leaving(&self.normal(index, self.t, q, q_dot)?) {
                continue;
            }
            contact = Some(index);
            break;
        }
        match contact {
            Some(index) => {
                let hint = self.stepper.suggested_step();
                self.crossing(index, self.t, y, hint, f64::INFINITY)
            }
            None => Ok(Next::Continue),
        }
    }

    /// The guard of constraint `index` crossed at `t_event`, from the state `before` on its
    /// admissible side: an impact, or a spurious crossing of a body that is leaving. `hint` is
    /// the next step's size, `found` the size of the step that found the crossing.
    fn crossing(
        &mut self,
        index: usize,
        t_event: f64,
        before: Vec<f64>,
        hint: f64,
        found: f64,
    ) -> Result<Next, Error> {
        let (q, q_dot) = before.split_at(self.n);
        let normal = self.normal(index, t_event, q, q_dot)?;
        // A surface where ∂h/∂q vanishes (h = x³ at x = 0) has no normal to bounce along: below
        // the position tolerance, h is dominated by its curvature, not by its gradient.
        let tol = self.sim.options.tolerances;
        let q_tol = tol.atol + tol.rtol * self.constraint_scale(index, q);
        if normal.gradient_norm <= 0.5 * normal.curvature * q_tol {
            let error = Error::DegenerateConstraint {
                t: t_event,
                constraint: self.sim.model.constraints()[index].name.clone(),
            };
            return Err(self.fail_at(t_event, &before, error));
        }
        if leaving(&normal) {
            // Moving away at the root (or at rest and accelerating away): a round-off crossing,
            // not an impact (REFERENCE §4).
            self.spurious += 1;
            if self.no_progress(t_event) {
                return self.stuck_at(index, t_event, &before);
            }
            // Pulled back, it lands after the flight 2 A q̇/|ḧ|: bound the next step by it, as
            // after an impact, so that no step carries the body into the surface and out again
            // between the samples of its dense output. A flight below the time resolution (a
            // body at rest on the surface and pressed into it, found again at the same time
            // until it is stuck) bounds nothing: then the step that found this crossing does,
            // so that the retries do not grow past the body (a ball resting on a cylinder would
            // otherwise be carried through it by a step whose first sample is beyond it).
            let e = self.sim.model.constraints()[index].restitution;
            let round_off = (normal.a_q_dot_round_off, normal.h_ddot_round_off);
            let hint = match Prediction::new(normal.a_q_dot, normal.h_ddot_free, e, round_off) {
                Some(p) if p.next_flight > time_resolution(t_event) => {
                    self.flight_bound = 1.5 * p.next_flight;
                    hint.min(self.flight_bound)
                }
                _ => hint.min(found),
            };
            self.restart(t_event, &before, Some(hint))?;
            self.enter_mode(t_event)?;
            return Ok(Next::Continue);
        }
        let closed = self.closed_set(index, t_event, &before)?;
        if closed.len() > 1 {
            return self.impact_set(index, closed, t_event, before, hint);
        }
        self.impact(index, t_event, before, normal, hint)
    }

    /// The constraints in the impact law when constraint `index` is reached at `t` in the state
    /// `y` (docs/contact-laws.md, law 2): `index`, the constraints held, and every other
    /// constraint closed or closing there, with `h` within the position tolerance and `A q̇`
    /// not positive beyond its rounding.
    fn closed_set(&mut self, index: usize, t: f64, y: &[f64]) -> Result<ActiveSet, Error> {
        let mut set = self.held().with(index);
        let m = self.sim.model.constraints().len();
        let tol = self.sim.options.tolerances;
        let (q, q_dot) = y.split_at(self.n);
        let start = set;
        for other in (0..m).filter(|&i| !start.contains(i)) {
            let mut gradient = std::mem::take(&mut self.scratch);
            let h = self.mech.constraint_gradient(other, q, &mut gradient);
            let norm = gradient[..self.n].iter().map(|a| a * a).sum::<f64>().sqrt();
            let scale = guard_scale(h, &gradient[..self.n], q) / norm;
            self.scratch = gradient;
            let q_tol = tol.atol + tol.rtol * if scale.is_finite() { scale } else { 0.0 };
            let close = h <= q_tol * norm;
            if !close {
                continue;
            }
            let normal = self.normal(other, t, q, q_dot)?;
            if normal.a_q_dot <= normal.a_q_dot_round_off {
                set = set.with(other);
            }
        }
        Ok(set)
    }

    /// The size of the coordinates as constraint `index` weighs them, `(|h| + Σ|A_i q_i|)/|A|`,
    /// for scaling position tolerances: a coordinate `h` ignores or barely depends on (like the
    /// ball's `x1`) must not loosen them.
    fn constraint_scale(&mut self, index: usize, q: &[f64]) -> f64 {
        let mut gradient = std::mem::take(&mut self.scratch);
        let h = self.mech.constraint_gradient(index, q, &mut gradient);
        let norm = gradient[..self.n].iter().map(|a| a * a).sum::<f64>().sqrt();
        let scale = guard_scale(h, &gradient[..self.n], q) / norm;
        self.scratch = gradient;
        if scale.is_finite() {
            scale
        } else {
            0.0
        }
    }

    /// The event state on the admissible side: the state at the root may be a little past the
    /// surface (the root was found on the interpolant, and the state may come from a refining
    /// step); Newton steps in time on the last step's dense output bring it back to `h ≥ 0`
    /// (REFERENCE §4).
    fn admissible_side(
        &mut self,
        index: usize,
        t: f64,
        mut y: Vec<f64>,
    ) -> Result<(f64, Vec<f64>), Error> {
        let n = self.n;
        let (h, _, _) = guard_along(self.sim.model, index, &y[..n], &y[n..]);
        let in_last_step = self.stepper.t_previous() < t && t <= self.stepper.t();
        if h >= 0.0 || !in_last_step {
            return Ok((t, y));
        }
        self.dense()?;
        let cubic = self.cubic;
        let mut t_new = t;
        for _ in 0..8 {
            let (h, h_dot, _) = guard_along(self.sim.model, index, &y[..n], &y[n..]);
            if h >= 0.0 || h_dot >= 0.0 || h.is_nan() {
                break;
            }
            // h + ḣ δ = 0, δ = −h/ḣ < 0, with a margin so that the next try lands on h ≥ 0.
            let back = (h / h_dot) * 1.001 + f64::EPSILON * t_new.abs();
            t_new = (t_new - back).max(self.stepper.t_previous());
            interpolate(&self.stepper, cubic, t_new, &mut y);
        }
        Ok((t_new, y))
    }

    /// The state at `t` inside the last accepted step, by Runge–Kutta steps from the step's
    /// start rather than from the dense output: an event restarts the integration from this
    /// state, so it must carry the step's local error, not the (lower-order) interpolant's.
    /// Leaves the stepper at `t`.
    fn state_at(&mut self, t: f64) -> Result<Vec<f64>, Error> {
        let t0 = self.stepper.t_previous();
        if t <= t0 {
            return Ok(self.stepper.y_previous().to_vec());
        }
        self.cubic = false;
        let mut eqs = self.equations();
        let h = t - t0;
        self.stepper.rewind(h);
        while self.stepper.t() < t {
            self.check_step_limit()?;
            let stepped = self.stepper.step(&mut eqs, t, h);
            stepped.map_err(|e| self.step_error(e))?;
        }
        Ok(self.stepper.y().to_vec())
    }

    /// The earliest crossing of any guard (except those `held`) in `[t0, t1]`, on the dense
    /// output, its samples put back onto the held constraints. Other constraints at the surface
    /// there join the impact law ([`Runner::closed_set`]).
    fn earliest_crossing(
        &mut self,
        t0: f64,
        t1: f64,
        held: ActiveSet,
    ) -> Result<Option<(usize, f64)>, Error> {
        let m = self.sim.model.constraints().len();
        if (0..m).all(|i| held.contains(i)) {
            return Ok(None);
        }
        self.dense()?;
        let cubic = self.cubic;
        let mut found: Option<(usize, f64)> = None;
        for index in (0..m).filter(|&i| !held.contains(i)) {
            let (stepper, mech, n) = (&self.stepper, self.mech, self.n);
            let mut y = std::mem::take(&mut self.scratch);
            let crossing = first_crossing(t0, t1, |t| {
                interpolate(stepper, cubic, t, &mut y);
                // Best effort: a failed projection just leaves the sample as it is.
                let _ = project_onto(&mech, held, n, &mut y);
                let (h, h_dot, _) = guard_along(mech.model(), index, &y[..n], &y[n..]);
                (h, Some(h_dot))
            });
            self.scratch = y;
            if let Some(c) = crossing {
                let t = c.t_admissible;
                if found.is_none_or(|(_, t_other)| t < t_other) {
                    found = Some((index, t));
                }
            }
        }
        Ok(found)
    }

    fn impact(
        &mut self,
        index: usize,
        t: f64,
        before: Vec<f64>,
        normal: Normal,
        hint: f64,
    ) -> Result<Next, Error> {
        let e = self.sim.model.constraints()[index].restitution;
        let h: f64 = self.sim.model.constraint(index, &before[..self.n]);
        if let ZenoStrategy::Epsilon(eps) = self.sim.options.zeno {
            // The paper's rule, on the state just before the impact.
            // The crossing is replaced by R∞: it is no impact, and not counted as one.
            let candidates = self.accumulation.constraints().with(index);
            let near = self.within_epsilon(candidates, &before, eps);
            if near.len() > 1 && near.contains(index) {
                // An accumulation over several constraints: the rule on all of them that are
                // within ε of their surfaces.
                if self.epsilon_met(near, &before, eps)? {
                    let p = self.accumulation.predict();
                    return self.switch_set(index, near, t, before, p);
                }
            } else if h.abs() <= eps && normal.a_q_dot.abs() <= eps {
                let round_off = (e * normal.a_q_dot_round_off, normal.h_ddot_round_off);
                let prediction =
                    Prediction::new(-e * normal.a_q_dot, normal.h_ddot_free, e, round_off);
                return self.switch(index, t, before, prediction, e);
            }
        }
        let mut after = before.clone();
        {
            let (q, q_dot) = after.split_at_mut(self.n);
            self.mech
                .impact(index, e, q, q_dot)
                .map_err(|err| self.fail_dynamics(err, t, &before))?;
        }
        let impulse = -(1.0 + e) * normal.a_q_dot / normal.s;
        let contacts = ActiveSet::single(index);
        let change = (contacts, vec![impulse]);
        self.record_event(
            EventKind::Impact,
            index,
            change,
            t,
            &before,
            &after,
            Mode::Free,
        )?;
        self.impacts += 1;
        self.sequence.record(index, t);
        self.accumulation.record(index, t);
        if self.accumulation.constraints().len() > 1 {
            // Impacts alternating between constraints (a groove's walls).
            let involved = ActiveSet::single(index);
            if let Some(next) = self.accumulation_resolved(index, involved, t, &after)? {
                return Ok(next);
            }
        }
        let (q, q_dot) = after.split_at(self.n);
        let post = self.normal(index, t, q, q_dot)?;
        let round_off = (post.a_q_dot_round_off, post.h_ddot_round_off);
        let prediction = Prediction::new(post.a_q_dot, post.h_ddot_free, e, round_off);
        let stuck = self.no_progress(t);
        if stuck {
            return self.stuck_at(index, t, &after);
        }
        if let Some(p) = prediction {
            match self.sim.options.zeno {
                ZenoStrategy::Auto => {
                    if self.zeno_resolved(index, t, &after, &p, &post, AUTO_ROUND_OFF_ULPS)? {
                        return self.switch(index, t, after, Some(p), e);
                    }
                }
                ZenoStrategy::Off => {
                    if self.zeno_resolved(index, t, &after, &p, &post, OFF_ROUND_OFF_ULPS)? {
                        return Ok(self.stall(index, t, &after, p, e));
                    }
                }
                // An ε below what f64 resolves is never met: switch where impacts stop being
                // resolvable, as Off stalls there.
                ZenoStrategy::Epsilon(_) => {
                    if self.zeno_resolved(index, t, &after, &p, &post, OFF_ROUND_OFF_ULPS)? {
                        return self.switch(index, t, after, Some(p), e);
                    }
                }
            }
        }
        let hint = match prediction {
            Some(p) if p.next_flight > 0.0 => {
                self.flight_bound = 1.5 * p.next_flight;
                hint.min(self.flight_bound)
            }
            _ => hint,
        };
        self.restart(t, &after, Some(hint))?;
        Ok(Next::Continue)
    }

    /// Whether the rest of the Zeno sequence after the impact that left `y` is below what the
    /// run resolves, with `ulps` the rounding margin of the guard (see [`Self::round_off_floor`]).
    ///
    /// Resolved means the next flight is shorter than `f64` time resolves at `t`, or either:
    /// - the predicted remaining time `T_rem` is shorter than the integrator's time resolution
    ///   `1/‖ẋ‖` (in its own weighted error norm): the execution cannot move by more than the
    ///   tolerance before `τ∞`, so switching now is as accurate as the integration; or
    /// - the next bounce's height `(A q̇⁺)²/(2|ḧ|)` is within `ulps` of the rounding error of
    ///   `h` itself: no further impact can be resolved in `f64`, and what the switch changes
    ///   after `τ∞` (of order `A q̇⁺ · T_rem`) is far below the tolerance.
    fn zeno_resolved(
        &mut self,
        index: usize,
        t: f64,
        y: &[f64],
        p: &Prediction,
        normal: &Normal,
        ulps: f64,
    ) -> Result<bool, Error> {
        if p.next_flight <= time_resolution(t) {
            return Ok(true);
        }
        let n = self.n;
        let q = &y[..n];
        // Round-off floor of the guard: the rounding of h = h(q) as the coordinates round.
        let mut gradient = std::mem::take(&mut self.scratch);
        let h = self.mech.constraint_gradient(index, q, &mut gradient);
        let h_scale = guard_scale(h, &gradient[..n], q);
        self.scratch = gradient;
        let height = normal.a_q_dot.max(0.0).powi(2) / (2.0 * -normal.h_ddot_free);
        if height <= ulps * f64::EPSILON * h_scale {
            return Ok(true);
        }
        if ulps < AUTO_ROUND_OFF_ULPS {
            return Ok(false);
        }
        Ok(p.remaining * self.resolution_rate(t, y)? <= 1.0)
    }

    /// The rate `‖ẋ‖` of the state `y` in the integrator's own weighted error norm: motion for
    /// less than `1/rate` moves the state by less than the tolerance.
    fn resolution_rate(&mut self, t: f64, y: &[f64]) -> Result<f64, Error> {
        let n = self.n;
        let (q, q_dot) = y.split_at(n);
        let tol = self.sim.options.tolerances;
        let mut acc = std::mem::take(&mut self.scratch);
        let free = self.mech.acceleration(q, q_dot, None, &mut acc[..n]);
        let acc_rate: f64 = (0..n)
            .map(|i| {
                let sq = tol.atol + tol.rtol * q[i].abs();
                let sv = tol.atol + tol.rtol * q_dot[i].abs();
                (q_dot[i] / sq).powi(2) + (acc[i] / sv).powi(2)
            })
            .sum();
        self.scratch = acc;
        free.map_err(|err| self.dynamics_error(err, t, y))?;
        Ok((acc_rate / (2 * n) as f64).sqrt())
    }

    /// Genuine when the flights measured so far shrink geometrically (positive intervals), or
    /// when the next one is still resolvable; chattering otherwise (zero-length intervals).
    fn zeno_kind(&self, p: &Prediction, e: f64, t: f64) -> ZenoKind {
        if e > 0.0 && self.sequence.ratio().is_some_and(|r| r > 0.0) {
            ZenoKind::Genuine
        } else {
            p.kind(e, t)
        }
    }

    /// Events that do not advance time: after [`STUCK_EVENTS`] in a row the contact is chattering.
    fn no_progress(&mut self, t: f64) -> bool {
        if t - self.last_event_t <= time_resolution(t) {
            self.stuck += 1;
        } else {
            self.stuck = 0;
        }
        self.last_event_t = t;
        self.stuck >= STUCK_EVENTS
    }

    /// Impacts that no longer advance time: a chattering contact. Switch, or stall with `Off`;
    /// onto every constraint of the accumulation and those held, where that is more than one.
    fn stuck_at(&mut self, index: usize, t: f64, y: &[f64]) -> Result<Next, Error> {
        let e = self.sim.model.constraints()[index].restitution;
        let p = Prediction {
            next_flight: 0.0,
            remaining: 0.0,
        };
        let all = self
            .accumulation
            .constraints()
            .union(self.held())
            .with(index);
        if all.len() > 1 {
            return match self.sim.options.zeno {
                ZenoStrategy::Off => Ok(self.stall_set(index, all, t, y, p)),
                _ => self.switch_set(index, all, t, y.to_vec(), Some(p)),
            };
        }
        match self.sim.options.zeno {
            ZenoStrategy::Off => Ok(self.stall(index, t, y, p, e)),
            _ => self.switch(index, t, y.to_vec(), Some(p), e),
        }
    }

    fn stall(&mut self, index: usize, t: f64, y: &[f64], p: Prediction, e: f64) -> Next {
        let t_zeno = t + p.remaining;
        self.zeno.push(ZenoPoint {
            constraint: index,
            constraints: ActiveSet::single(index),
            kind: self.zeno_kind(&p, e, t),
            t_switch: t,
            t_zeno,
            impacts: self.sequence.count(),
            ratio: self.sequence.ratio(),
            point: split(y, self.n),
        });
        self.t = t;
        self.y.copy_from_slice(y);
        Next::Stop(Outcome::ZenoStalled {
            constraint: index,
            t_zeno,
        })
    }

    /// The switch to the constrained motion through `R∞`.
    fn switch(
        &mut self,
        index: usize,
        t: f64,
        before: Vec<f64>,
        prediction: Option<Prediction>,
        e: f64,
    ) -> Result<Next, Error> {
        let mut after = before.clone();
        {
            let (q, q_dot) = after.split_at_mut(self.n);
            if self.sim.options.completion == Completion::ModelMap {
                // Under `Auto` the switch state stands for the Zeno point, up to the bounces not
                // taken: their normal velocity goes plastically first, so that a map written for
                // the point itself (the paper's keep some coordinates and solve for the others)
                // does not turn it into a tangential error. Under the paper's ε rule the map
                // acts on the state as it is, as in the paper.
                if self.sim.options.zeno == ZenoStrategy::Auto {
                    self.mech
                        .project(index, q, q_dot)
                        .map_err(|err| self.fail_dynamics(err, t, &before))?;
                }
                self.sim.model.completion_map(index, q, q_dot);
            }
            self.mech
                .project(index, q, q_dot)
                .map_err(|err| self.fail_dynamics(err, t, &before))?;
        }
        let (kind, remaining) = match prediction {
            Some(p) => (self.zeno_kind(&p, e, t), p.remaining),
            None => (ZenoKind::Chattering, 0.0),
        };
        self.zeno.push(ZenoPoint {
            constraint: index,
            constraints: ActiveSet::single(index),
            kind,
            t_switch: t,
            t_zeno: t + remaining,
            impacts: self.sequence.count(),
            ratio: self.sequence.ratio(),
            point: split(&after, self.n),
        });
        self.sequence.clear();
        self.accumulation.clear();
        self.record_event(
            EventKind::Zeno,
            index,
            (ActiveSet::single(index), Vec::new()),
            t,
            &before,
            &after,
            Mode::Constrained(ActiveSet::single(index)),
        )?;
        self.restart(t, &after, None)?;
        // A constraint that cannot hold the motion (λ > 0) lets go at once.
        let (q, q_dot) = after.split_at(self.n);
        self.lift_margin_start = self.normal(index, t, q, q_dot)?.lift_margin();
        if self.lift_margin_start > 0.0 {
            return self.liftoff(index, t, after);
        }
        Ok(Next::Continue)
    }

    // ----- constrained motion ------------------------------------------------------------

    /// After a step on constraint `index`, whose normal response at the step's end is `end`
    /// when the step computed it.
    fn after_constrained_step(&mut self, index: usize, end: Option<Normal>) -> Result<Next, Error> {
        let (t0, t1) = (self.stepper.t_previous(), self.stepper.t());
        let n = self.n;
        // Another constraint reached while this one holds: an impact on both.
        if let Some((other, t)) = self.earliest_crossing(t0, t1, ActiveSet::single(index))? {
            return self.reached_while_held(other, t);
        }
        // Lift-off: the constraint lets go where it would have to pull (λ above its rounding
        // error; a contact without force holds), reported on the side where it pulls, where free
        // flight is admissible. λ is sampled on the dense output as it is (within the tolerance
        // of the constraint); inside the step only when its ends do not rule a crossing out.
        let margin_start = self.lift_margin_start;
        let margin_end = match end {
            Some(normal) => normal.lift_margin(),
            None => {
                let end = self.stepper.y().to_vec();
                self.normal(index, t1, &end[..n], &end[n..])?.lift_margin()
            }
        };
        let crossing = if margin_end <= 0.0
            && margin_start.max(margin_end) < -(margin_end - margin_start).abs()
        {
            None
        } else {
            self.dense()?;
            let (stepper, mech, cubic) = (&self.stepper, self.mech, self.cubic);
            let mut y = std::mem::take(&mut self.scratch);
            let mut w = std::mem::take(&mut self.w);
            let crossing = first_crossing(t0, t1, |t| {
                interpolate(stepper, cubic, t, &mut y);
                let (q, q_dot) = y.split_at(n);
                let margin = mech
                    .normal(index, q, q_dot, &mut w)
                    .map_or(f64::NAN, |normal| normal.lift_margin());
                (lift_guard(margin), None)
            });
            self.scratch = y;
            self.w = w;
            crossing
        };
        self.lift_margin_start = margin_end;
        if let Some(c) = crossing {
            let t = c.t_violating;
            self.emit_grid_before(t)?;
            let mut state = self.state_at(t)?;
            {
                let (q, q_dot) = state.split_at_mut(n);
                self.mech
                    .project(index, q, q_dot)
                    .map_err(|err| self.dynamics_error(err, t, &state.clone()))?;
            }
            return self.liftoff(index, t, state);
        }
        // (The step's end is on h = 0, A q̇ = 0 already: `Equations::correct_end`.)
        self.commit_step()?;
        Ok(Next::Continue)
    }

    fn liftoff(&mut self, index: usize, t: f64, state: Vec<f64>) -> Result<Next, Error> {
        let change = (ActiveSet::single(index), Vec::new());
        self.record_event(
            EventKind::Liftoff,
            index,
            change,
            t,
            &state,
            &state,
            Mode::Free,
        )?;
        self.sequence.clear();
        self.accumulation.clear();
        self.restart(t, &state, None)?;
        Ok(Next::Continue)
    }

    // ----- several contacts --------------------------------------------------------------

    /// After a restart in the current mode: the lift-off test's margins at the mode's start.
    fn enter_mode(&mut self, t: f64) -> Result<(), Error> {
        let held = self.held();
        let y = self.y.clone();
        let (q, q_dot) = y.split_at(self.n);
        if let Some(index) = held.only() {
            self.lift_margin_start = self.normal(index, t, q, q_dot)?.lift_margin();
        } else if !held.is_empty() {
            self.set_margin_start = self.set_margin(held, t, &y)?;
        }
        Ok(())
    }

    /// The largest lift margin of the constraints held in `set` at `(t, y)`: positive where one
    /// of them would have to pull.
    fn set_margin(&mut self, set: ActiveSet, t: f64, y: &[f64]) -> Result<f64, Error> {
        let (q, q_dot) = y.split_at(self.n);
        let mut acc = vec![0.0; self.n];
        let held = contact::held_acceleration(&self.mech, set, q, q_dot, &mut acc);
        let (contacts, lambda) = held.map_err(|err| self.fail_dynamics(err, t, y))?;
        let factor = contacts
            .factor()
            .map_err(|err| self.fail_dynamics(err, t, y))?;
        let margins = contacts.lift_margins(&factor, &lambda);
        Ok(margins.into_iter().fold(f64::NEG_INFINITY, f64::max))
    }

    /// Constraint `other` reached at about `t` while the current mode holds others: the state
    /// there, on the held constraints and on `other`'s admissible side, is a crossing.
    fn reached_while_held(&mut self, other: usize, t: f64) -> Result<Next, Error> {
        let found = self.stepper.t() - self.stepper.t_previous();
        self.emit_grid_before(t)?;
        let hint = self.stepper.suggested_step();
        let before = self.state_at(t)?;
        let (t, mut before) = self.admissible_side(other, t, before)?;
        // Best effort: the interpolated state is within the tolerance of the held constraints.
        let _ = project_onto(&self.mech, self.held(), self.n, &mut before);
        self.crossing(other, t, before, hint, found)
    }

    /// An impact reaching constraint `index` at `t` with the other constraints of `set` closed
    /// (docs/contact-laws.md, law 2): the impulses solve the generalized Newton law on the whole
    /// set; then law 1 decides which of the constraints left at rest hold.
    fn impact_set(
        &mut self,
        index: usize,
        set: ActiveSet,
        t: f64,
        before: Vec<f64>,
        hint: f64,
    ) -> Result<Next, Error> {
        let n = self.n;
        let accumulating = self.accumulation.constraints().with(index);
        if let ZenoStrategy::Epsilon(eps) = self.sim.options.zeno {
            // The paper's rule on every constraint of the accumulation and of the impact that
            // is within ε of its surface (the held ones are on theirs).
            let near = self.within_epsilon(accumulating.union(set), &before, eps);
            if near.contains(index) && self.epsilon_met(near, &before, eps)? {
                let p = self.accumulation.predict();
                return self.switch_set(index, near, t, before, p);
            }
        }
        let restitution: Vec<f64> = set
            .iter()
            .map(|i| self.sim.model.constraints()[i].restitution)
            .collect();
        let (q, q_dot) = before.split_at(n);
        let contacts = Contacts::at(&self.mech, set, q, q_dot)
            .map_err(|(err, _)| self.fail_dynamics(err, t, &before))?;
        let mut after = before.clone();
        let impulses = contacts
            .impact(&restitution, &mut after[n..])
            .map_err(|err| self.fail_dynamics(err, t, &before))?;
        let mode = self.settle(set, t, &mut after)?;
        self.record_event(
            EventKind::Impact,
            index,
            (set, impulses),
            t,
            &before,
            &after,
            mode,
        )?;
        self.impacts += 1;
        self.sequence.record(index, t);
        self.accumulation.record(index, t);
        if self.no_progress(t) {
            // Impacts that no longer advance time: chattering on every constraint involved.
            let all = self.accumulation.constraints().union(set);
            let p = Prediction {
                next_flight: 0.0,
                remaining: 0.0,
            };
            return match self.sim.options.zeno {
                ZenoStrategy::Off => Ok(self.stall_set(index, all, t, &after, p)),
                _ => self.switch_set(index, all, t, after, Some(p)),
            };
        }
        if let Some(next) = self.accumulation_resolved(index, set, t, &after)? {
            return Ok(next);
        }
        self.restart(t, &after, Some(hint))?;
        self.enter_mode(t)?;
        Ok(Next::Continue)
    }

    /// The mode after an impact on `set` that left `y`: the constraints of the set at rest
    /// (`|A q̇| within rounding`) are closed, and law 1 picks those that hold; `y` is put onto
    /// them.
    fn settle(&mut self, set: ActiveSet, t: f64, y: &mut [f64]) -> Result<Mode, Error> {
        let (q, q_dot) = y.split_at(self.n);
        let mut closed = ActiveSet::empty();
        for index in set.iter() {
            let normal = self.normal(index, t, q, q_dot)?;
            if normal.a_q_dot.abs() <= normal.a_q_dot_round_off {
                closed = closed.with(index);
            }
        }
        let held = self.held_of(closed, t, y)?;
        if held.is_empty() {
            return Ok(Mode::Free);
        }
        let state = y.to_vec();
        project_onto(&self.mech, held, self.n, y)
            .map_err(|err| self.fail_dynamics(err, t, &state))?;
        Ok(Mode::Constrained(held))
    }

    /// The constraints of `closed` that hold at `(t, y)` (docs/contact-laws.md, law 1).
    fn held_of(&mut self, closed: ActiveSet, t: f64, y: &[f64]) -> Result<ActiveSet, Error> {
        if closed.is_empty() {
            return Ok(closed);
        }
        let (q, q_dot) = y.split_at(self.n);
        if let Some(index) = closed.only() {
            let normal = self.normal(index, t, q, q_dot)?;
            return Ok(if normal.lift_margin() > 0.0 {
                ActiveSet::empty()
            } else {
                closed
            });
        }
        let contacts = Contacts::at(&self.mech, closed, q, q_dot)
            .map_err(|(err, _)| self.fail_dynamics(err, t, y))?;
        contacts
            .held_set()
            .map_err(|err| self.fail_dynamics(err, t, y))
    }

    /// The constraints of `set` within `ε` of their surfaces at `y` (`|h| ≤ ε`).
    fn within_epsilon(&self, set: ActiveSet, y: &[f64], eps: f64) -> ActiveSet {
        let q = &y[..self.n];
        set.iter()
            .filter(|&i| self.sim.model.constraint::<f64>(i, q).abs() <= eps)
            .fold(ActiveSet::empty(), ActiveSet::with)
    }

    /// Whether the paper's ε rule holds on every constraint of `set` at `y`.
    fn epsilon_met(&mut self, set: ActiveSet, y: &[f64], eps: f64) -> Result<bool, Error> {
        let (q, q_dot) = y.split_at(self.n);
        for index in set.iter() {
            let (h, h_dot, _) = guard_along(self.sim.model, index, q, q_dot);
            if !(h.abs() <= eps && h_dot.abs() <= eps) {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// After an impact reaching `index` at `t` on the constraints `involved`, which left `y` (in
    /// the mode now current): whether the
    /// accumulation it belongs to has reached its Zeno point as far as the run resolves it
    /// (docs/contact-laws.md, law 3), and if so the switch (or the stall, with `Off`).
    ///
    /// The rest of the sequence is predicted from the physics where its impacts all reach one
    /// constraint (the flight `2 A q̇⁺/|ḧ|`, `ḧ` under the motion held on the others), else from
    /// the measured ratio of its flights. It is resolved when the next flight is below what
    /// `f64` time resolves at `t` or, under `Auto`, when the remaining time is below the
    /// integration's time resolution; in either case only where every constraint of the
    /// accumulation is within a hundred position tolerances of its surface.
    fn accumulation_resolved(
        &mut self,
        index: usize,
        involved: ActiveSet,
        t: f64,
        y: &[f64],
    ) -> Result<Option<Next>, Error> {
        let held = self.held();
        let accumulating = self.accumulation.constraints();
        let prediction = if accumulating.len() == 1 {
            if held.contains(index) {
                // Closed by the impact (plastic): nothing bounces, nothing accumulates.
                return Ok(None);
            }
            let e = self.sim.model.constraints()[index].restitution;
            self.held_prediction(index, held, e, t, y)?
        } else {
            self.accumulation.predict()
        };
        let Some(p) = prediction else {
            return Ok(None);
        };
        // The constraints of the last impact that are at their surfaces take part too (two
        // walls reached at once, again and again).
        let accumulating = accumulating.union(involved);
        if !self.near(accumulating, y) {
            return Ok(None);
        }
        let ulps = match self.sim.options.zeno {
            ZenoStrategy::Auto => AUTO_ROUND_OFF_ULPS,
            _ => OFF_ROUND_OFF_ULPS,
        };
        let resolved = p.next_flight <= time_resolution(t)
            || self.below_round_off(accumulating, y, p.next_flight, ulps)
            || (self.sim.options.zeno == ZenoStrategy::Auto
                && p.remaining * self.resolution_rate(t, y)? <= 1.0);
        if !resolved {
            return Ok(None);
        }
        let all = accumulating.union(held);
        Ok(Some(match self.sim.options.zeno {
            ZenoStrategy::Off => self.stall_set(index, all, t, y, p),
            _ => self.switch_set(index, all, t, y.to_vec(), Some(p))?,
        }))
    }

    /// The next flight of a body leaving constraint `index` at `y`, pulled back under the
    /// motion held on `held`: `Prediction` from `A q̇⁺` and `ḧ = ḧ_free − Σ W_ih λ_h`.
    fn held_prediction(
        &mut self,
        index: usize,
        held: ActiveSet,
        e: f64,
        t: f64,
        y: &[f64],
    ) -> Result<Option<Prediction>, Error> {
        let (q, q_dot) = y.split_at(self.n);
        let normal = self.normal(index, t, q, q_dot)?;
        let round_off = (normal.a_q_dot_round_off, normal.h_ddot_round_off);
        let held = held.minus(ActiveSet::single(index));
        if held.is_empty() {
            return Ok(Prediction::new(
                normal.a_q_dot,
                normal.h_ddot_free,
                e,
                round_off,
            ));
        }
        let mut acc = vec![0.0; self.n];
        let motion = if held.len() == 1 {
            self.mech
                .acceleration(q, q_dot, held.only(), &mut acc)
                .map(|_| ())
        } else {
            contact::held_acceleration(&self.mech, held, q, q_dot, &mut acc).map(|_| ())
        };
        motion.map_err(|err| self.fail_dynamics(err, t, y))?;
        // ḧ = A q̈ + Ȧ q̇, with Ȧ q̇ = ḧ_free − A M⁻¹ f.
        let mut free = vec![0.0; self.n];
        self.mech
            .acceleration(q, q_dot, None, &mut free)
            .map_err(|err| self.fail_dynamics(err, t, y))?;
        let mut gradient = vec![0.0; self.n];
        self.mech.constraint_gradient(index, q, &mut gradient);
        let change: f64 = gradient
            .iter()
            .zip(acc.iter().zip(&free))
            .map(|(a, (held, free))| a * (held - free))
            .sum();
        let h_ddot = normal.h_ddot_free + change;
        Ok(Prediction::new(normal.a_q_dot, h_ddot, e, round_off))
    }

    /// Whether the motion of every constraint of `set` over the next flight, `|A q̇| Δ`, is within
    /// `ulps` of the rounding error of its `h`: no further impact on them can be resolved.
    fn below_round_off(&mut self, set: ActiveSet, y: &[f64], flight: f64, ulps: f64) -> bool {
        let (q, q_dot) = y.split_at(self.n);
        set.iter().all(|index| {
            let mut gradient = std::mem::take(&mut self.scratch);
            let h = self.mech.constraint_gradient(index, q, &mut gradient);
            let h_scale = guard_scale(h, &gradient[..self.n], q);
            let a_q_dot: f64 = gradient[..self.n]
                .iter()
                .zip(q_dot)
                .map(|(a, v)| a * v)
                .sum();
            self.scratch = gradient;
            a_q_dot.abs() * flight <= ulps * f64::EPSILON * h_scale
        })
    }

    /// Whether every constraint of `set` is within a hundred position tolerances of its surface
    /// at `y`.
    fn near(&mut self, set: ActiveSet, y: &[f64]) -> bool {
        let tol = self.sim.options.tolerances;
        let q = &y[..self.n];
        set.iter().all(|index| {
            let mut gradient = std::mem::take(&mut self.scratch);
            let h = self.mech.constraint_gradient(index, q, &mut gradient);
            let norm = gradient[..self.n].iter().map(|a| a * a).sum::<f64>().sqrt();
            self.scratch = gradient;
            let scale = self.constraint_scale(index, q);
            h.abs() <= 100.0 * (tol.atol + tol.rtol * scale) * norm
        })
    }

    /// The switch through `R∞` onto every constraint of `set` at once (position onto all
    /// `hᵢ = 0`, velocity by the plastic law), after which law 1 picks those that hold.
    fn switch_set(
        &mut self,
        index: usize,
        set: ActiveSet,
        t: f64,
        before: Vec<f64>,
        prediction: Option<Prediction>,
    ) -> Result<Next, Error> {
        let mut after = before.clone();
        project_onto(&self.mech, set, self.n, &mut after)
            .map_err(|err| self.fail_dynamics(err, t, &before))?;
        let held = self.held_of(set, t, &after)?;
        let remaining = prediction.map_or(0.0, |p| p.remaining);
        let ratio = self.accumulation.ratio();
        let kind = match (prediction, ratio) {
            (Some(p), Some(r)) if r > 0.0 && p.next_flight > time_resolution(t) => {
                ZenoKind::Genuine
            }
            _ => ZenoKind::Chattering,
        };
        self.zeno.push(ZenoPoint {
            constraint: index,
            constraints: set,
            kind,
            t_switch: t,
            t_zeno: t + remaining,
            impacts: self.accumulation.count(),
            ratio,
            point: split(&after, self.n),
        });
        self.sequence.clear();
        self.accumulation.clear();
        let mode = if held.is_empty() {
            Mode::Free
        } else {
            Mode::Constrained(held)
        };
        let change = (set, Vec::new());
        self.record_event(EventKind::Zeno, index, change, t, &before, &after, mode)?;
        self.restart(t, &after, None)?;
        self.enter_mode(t)?;
        Ok(Next::Continue)
    }

    /// `Off` on an accumulation over `set`: the plain hybrid system stops there.
    fn stall_set(
        &mut self,
        index: usize,
        set: ActiveSet,
        t: f64,
        y: &[f64],
        p: Prediction,
    ) -> Next {
        let t_zeno = t + p.remaining;
        self.zeno.push(ZenoPoint {
            constraint: index,
            constraints: set,
            kind: ZenoKind::Genuine,
            t_switch: t,
            t_zeno,
            impacts: self.accumulation.count(),
            ratio: self.accumulation.ratio(),
            point: split(y, self.n),
        });
        self.t = t;
        self.y.copy_from_slice(y);
        Next::Stop(Outcome::ZenoStalled {
            constraint: index,
            t_zeno,
        })
    }

    /// After a step held on two or more constraints: another constraint reached (an impact on
    /// all of them), or one of them letting go (its multiplier reaching 0, where law 1 decides
    /// again which hold).
    fn after_set_step(&mut self, set: ActiveSet) -> Result<Next, Error> {
        let (t0, t1) = (self.stepper.t_previous(), self.stepper.t());
        let n = self.n;
        if let Some((other, t)) = self.earliest_crossing(t0, t1, set)? {
            return self.reached_while_held(other, t);
        }
        let end = self.stepper.y().to_vec();
        let margin_end = self.set_margin(set, t1, &end)?;
        let margin_start = self.set_margin_start;
        let crossing = if margin_end <= 0.0
            && margin_start.max(margin_end) < -(margin_end - margin_start).abs()
        {
            None
        } else {
            self.dense()?;
            let (stepper, mech, cubic) = (&self.stepper, self.mech, self.cubic);
            let mut y = vec![0.0; 2 * n];
            let mut acc = vec![0.0; n];
            first_crossing(t0, t1, |t| {
                interpolate(stepper, cubic, t, &mut y);
                let (q, q_dot) = y.split_at(n);
                let margin = contact::held_acceleration(&mech, set, q, q_dot, &mut acc)
                    .and_then(|(contacts, lambda)| {
                        let factor = contacts.factor()?;
                        let margins = contacts.lift_margins(&factor, &lambda);
                        Ok(margins.into_iter().fold(f64::NEG_INFINITY, f64::max))
                    })
                    .unwrap_or(f64::NAN);
                (lift_guard(margin), None)
            })
        };
        self.set_margin_start = margin_end;
        if let Some(c) = crossing {
            let t = c.t_violating;
            self.emit_grid_before(t)?;
            let mut state = self.state_at(t)?;
            let copy = state.clone();
            project_onto(&self.mech, set, n, &mut state)
                .map_err(|err| self.fail_dynamics(err, t, &copy))?;
            return self.set_liftoff(set, t, state);
        }
        self.commit_step()?;
        Ok(Next::Continue)
    }

    /// Some constraints of `set` let go at `t`: law 1 on the set decides which still hold (at
    /// least the one whose margin is largest goes).
    fn set_liftoff(&mut self, set: ActiveSet, t: f64, state: Vec<f64>) -> Result<Next, Error> {
        let mut held = self.held_of(set, t, &state)?;
        if held == set {
            // At the root itself law 1 may still see the force at 0: the largest margin goes.
            let (q, q_dot) = state.split_at(self.n);
            let mut acc = vec![0.0; self.n];
            let solved = contact::held_acceleration(&self.mech, set, q, q_dot, &mut acc)
                .and_then(|(c, lambda)| Ok((c.lift_margins(&c.factor()?, &lambda), c.indices)));
            let (margins, indices) = solved.map_err(|err| self.fail_dynamics(err, t, &state))?;
            let worst = (0..margins.len())
                .max_by(|&i, &j| margins[i].total_cmp(&margins[j]))
                .unwrap_or(0);
            held = set.minus(ActiveSet::single(indices[worst]));
        }
        let gone = set.minus(held);
        let index = gone.iter().next().unwrap_or(0);
        let mode = if held.is_empty() {
            Mode::Free
        } else {
            Mode::Constrained(held)
        };
        let change = (gone, Vec::new());
        self.record_event(EventKind::Liftoff, index, change, t, &state, &state, mode)?;
        self.sequence.clear();
        self.accumulation.clear();
        self.restart(t, &state, None)?;
        self.enter_mode(t)?;
        Ok(Next::Continue)
    }

    // ----- records and output ------------------------------------------------------------

    /// Records an event at `t` from `before` (in the current mode) to `after` (in `new_mode`),
    /// with its samples, and closes the current interval of the hybrid time domain.
    /// `change` is the constraints involved and, for an impact, their impulses.
    #[allow(clippy::too_many_arguments)]
    fn record_event(
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
        self.emit(t, before, self.mode)?;
        let (contacts, impulses) = change;
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
    fn commit_step(&mut self) -> Result<(), Error> {
        let t1 = self.stepper.t();
        match self.sim.options.output {
            // (An observer that takes no samples costs no copy of the state.)
            OutputGrid::Steps if self.wants_samples => {
                let y = self.stepper.y().to_vec();
                self.emit(t1, &y, self.mode)?;
            }
            OutputGrid::Steps => {}
            OutputGrid::Uniform(_) => self.emit_grid_through(t1)?,
        }
        self.t = t1;
        self.y.copy_from_slice(self.stepper.y());
        Ok(())
    }

    /// Uniform grid points strictly before `t` (the states around an event come next).
    fn emit_grid_before(&mut self, t: f64) -> Result<(), Error> {
        self.emit_grid(t, false)
    }

    /// Uniform grid points up to and including `t` (and the initial point at `t = 0`).
    fn emit_grid_through(&mut self, t: f64) -> Result<(), Error> {
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

    fn emit_grid(&mut self, t: f64, inclusive: bool) -> Result<(), Error> {
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
        while self.next_output < t || (inclusive && self.next_output == t) {
            let to = self.next_output;
            interpolate(&self.stepper, self.cubic, to, &mut y);
            project_onto(&self.mech, self.held(), self.n, &mut y)
                .map_err(|err| self.dynamics_error(err, to, &self.y.clone()))?;
            self.emit(to, &y, self.mode)?;
            let k = (to / dt).round() + 1.0;
            self.next_output = k * dt;
        }
        Ok(())
    }

    /// Sends one sample to the observer.
    fn emit(&mut self, t: f64, y: &[f64], mode: Mode) -> Result<(), Error> {
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
            *h = model.constraint(i, q);
        }
        self.lambda_buf.iter_mut().for_each(|l| *l = 0.0);
        if let Mode::Constrained(active) = mode {
            if let Some(index) = active.only() {
                let mut w = std::mem::take(&mut self.w);
                let normal = self.mech.normal(index, q, q_dot, &mut w);
                self.w = w;
                self.lambda_buf[index] = normal
                    .map_err(|err| self.dynamics_error(err, t, y))?
                    .lambda();
            } else {
                let mut acc = vec![0.0; self.n];
                let held = contact::held_acceleration(&self.mech, active, q, q_dot, &mut acc);
                let (contacts, lambda) = held.map_err(|err| self.dynamics_error(err, t, y))?;
                for (&index, l) in contacts.indices.iter().zip(lambda) {
                    self.lambda_buf[index] = l;
                }
            }
        }
        let sample = Sample {
            t,
            mode,
            q,
            q_dot,
            h: &self.h_buf,
            lambda: &self.lambda_buf,
            energy: energy(model, q, q_dot),
        };
        self.observer.sample(&sample);
        Ok(())
    }

    // ----- errors ------------------------------------------------------------------------

    fn normal(&mut self, index: usize, t: f64, q: &[f64], q_dot: &[f64]) -> Result<Normal, Error> {
        let mut w = std::mem::take(&mut self.w);
        let normal = self.mech.normal(index, q, q_dot, &mut w);
        self.w = w;
        normal.map_err(|err| {
            let mut y = q.to_vec();
            y.extend_from_slice(q_dot);
            self.fail_dynamics(err, t, &y)
        })
    }

    fn dynamics_error(&self, err: DynamicsError, t: f64, y: &[f64]) -> Error {
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
            DynamicsError::DependentConstraints { constraints } => Error::DependentConstraints {
                t,
                constraints: constraints.iter().map(name).collect(),
            },
            DynamicsError::ContactProblem { constraints } => Error::ContactProblem {
                t,
                constraints: constraints.iter().map(name).collect(),
            },
        }
    }

    fn step_error(&self, err: StepError<DynamicsError>) -> Error {
        match err {
            StepError::Rhs { t, source } => self.dynamics_error(source, t, self.stepper.y()),
            StepError::StepSizeUnderflow { t, h } => Error::StepSizeUnderflow { t, h },
            StepError::NonFinite { t } => Error::NonFinite { t },
        }
    }

    /// Ends the run at `(t, y)` with the error the mechanics reported there.
    fn fail_dynamics(&mut self, err: DynamicsError, t: f64, y: &[f64]) -> Error {
        let error = self.dynamics_error(err, t, y);
        self.fail_at(t, y, error)
    }

    /// Ends the run at `(t, y)` with `error`, keeping the execution up to there: the output
    /// up to `t` is sent, and `(t, y)` becomes the record's last state.
    fn fail_at(&mut self, t: f64, y: &[f64], error: Error) -> Error {
        // Best effort: the run is failing already; what can be sent is sent.
        let _ = self.emit_grid_before(t);
        let _ = self.emit(t, y, self.mode);
        self.t = t;
        self.y.copy_from_slice(y);
        error
    }
}

/// Whether a body at a constraint's surface is leaving it: moving away, or at rest (a normal
/// velocity within its rounding has no sign) and accelerating away. Otherwise it is in contact
/// (moving in, or pressed onto the surface at rest, however `A q̇` happened to round).
fn leaving(normal: &Normal) -> bool {
    normal.a_q_dot > normal.a_q_dot_round_off
        || (normal.a_q_dot.abs() <= normal.a_q_dot_round_off
            && normal.h_ddot_free > normal.h_ddot_round_off)
}

/// `R∞` onto the constraints of `set` at `y = (q, q̇)` (nothing where the set is empty): the
/// single-constraint projection for one, the projection onto the set for several.
fn project_onto<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    n: usize,
    y: &mut [f64],
) -> Result<(), DynamicsError> {
    let (q, q_dot) = y.split_at_mut(n);
    match set.only() {
        _ if set.is_empty() => Ok(()),
        Some(index) => mech.project(index, q, q_dot).map(|_| ()),
        None => contact::project(mech, set, q, q_dot),
    }
}

/// The lift-off guard from a lift margin: it crosses 0 where the margin becomes positive. A
/// margin of exactly 0 (a contact without force, like two balls at rest side by side) holds.
fn lift_guard(margin: f64) -> f64 {
    if margin == 0.0 {
        f64::MIN_POSITIVE
    } else {
        -margin
    }
}

fn split(y: &[f64], n: usize) -> State {
    State {
        q: y[..n].to_vec(),
        q_dot: y[n..].to_vec(),
    }
}
