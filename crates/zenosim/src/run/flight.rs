//! Free flight and event location: a guard crossed on a step's dense output, the event state on
//! the admissible side, a spurious crossing or an impact, and which constraints are closed there.

use super::mode::holding;
use super::{interpolate, Next, Runner};
use crate::contact::project_onto;
use crate::derivatives::guard_along;
use crate::error::Error;
use crate::events::first_crossing_or_touch;
use crate::execution::ActiveSet;
use crate::integrator::Tolerances;
use crate::mechanics::{guard_scale, Normal};
use crate::model::HybridLagrangian;
use crate::observer::Observer;
use crate::zeno::Prediction;

impl<L: HybridLagrangian, O: Observer> Runner<'_, '_, L, O> {
    pub(super) fn after_free_step(&mut self) -> Result<Next, Error> {
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
    pub(super) fn contact_at_start(&mut self) -> Result<Next, Error> {
        let n = self.n;
        let y = self.y.clone();
        let (q, q_dot) = y.split_at(n);
        // The first contact; the others at the surface join it in the impact law.
        let mut contact = None;
        let held = self.held();
        for index in 0..self.sim.model.constraints().len() {
            if held.contains(index) {
                // Held from the start ([`Runner::rest_at_start`]).
                continue;
            }
            let (h, _, _) = guard_along(self.sim.model, index, self.t, q, q_dot);
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

    /// A start at rest on surfaces (`h` and `ḣ` within their rounding) that hold the body (docs/contact-laws.md, law 1) is no impact and no Zeno
    /// point: the run starts in the constrained motion on them, its first interval held from
    /// `t = 0`. (It was an impact of zero impulse at `t = 0` and a Zeno point "after 1 impact"
    /// with no ratio.)
    pub(super) fn rest_at_start(&mut self) -> Result<(), Error> {
        let (n, t) = (self.n, self.t);
        let mut y = self.y.clone();
        let mut resting = ActiveSet::empty();
        {
            let (q, q_dot) = y.split_at(n);
            for index in 0..self.sim.model.constraints().len() {
                let (h, _, _) = guard_along(self.sim.model, index, t, q, q_dot);
                // On the surface to its rounding, not to the position tolerance (rtol·|q|, tens
                // of metres for coordinates of 1e11: a body that high above its surface falls).
                // Away from it the normal is not asked for (it may be degenerate there, and is
                // found so at the contact).
                let surface = self.surface(index, t, q, q_dot);
                if h.abs() > START_ROUND_OFF * surface.h_scale {
                    continue;
                }
                let normal = self.normal(index, t, q, q_dot)?;
                if normal.a_q_dot.abs() <= normal.a_q_dot_round_off {
                    resting = resting.with(index);
                }
            }
        }
        let (held, grips) = self.decide(resting, t, &y)?;
        if held.is_empty() {
            return Ok(());
        }
        let start = y.clone();
        project_onto(&self.mech, held, grips, t, n, &mut y)
            .map_err(|err| self.fail_dynamics(err, t, &start))?;
        self.mode = holding(held);
        self.grips = grips;
        self.y.copy_from_slice(&y);
        self.resume(t, &y, None)
    }

    /// The guard of constraint `index` crossed at `t_event`, from the state `before` on its
    /// admissible side: an impact, or a spurious crossing of a body that is leaving. `hint` is
    /// the next step's size, `found` the size of the step that found the crossing.
    pub(super) fn crossing(
        &mut self,
        index: usize,
        t_event: f64,
        before: Vec<f64>,
        hint: f64,
        found: f64,
    ) -> Result<Next, Error> {
        let (q, q_dot) = before.split_at(self.n);
        let normal = self.normal(index, t_event, q, q_dot)?;
        let surface = self.surface(index, t_event, q, q_dot);
        let q_tol = surface.position_tolerance(self.sim.options.tolerances);
        self.refuse_flat(index, t_event, &before, &normal, q_tol)?;
        if leaving(&normal) {
            // Moving away at the root (or at rest and accelerating away): a round-off crossing,
            // not an impact (REFERENCE §4).
            self.record.spurious += 1;
            if self
                .watch
                .no_progress(t_event, self.time_resolution(t_event))
            {
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
                Some(p) if p.next_flight > self.time_resolution(t_event) => {
                    self.flight_bound = 1.5 * p.next_flight;
                    hint.min(self.flight_bound)
                }
                _ => hint.min(found),
            };
            self.resume(t_event, &before, Some(hint))?;
            return Ok(Next::Continue);
        }
        let contacts = self.closed_set(index, t_event, &before)?;
        let leading = self.leading(index, contacts.minus(self.held()), t_event, &before)?;
        let normal = if leading == index {
            normal
        } else {
            let (q, q_dot) = before.split_at(self.n);
            self.normal(leading, t_event, q, q_dot)?
        };
        self.impact(leading, contacts, t_event, before, normal, hint)
    }

    /// The constraints in the impact law when constraint `index` is reached at `t` in the state
    /// `y` (docs/contact-laws.md, law 2): `index`, the constraints held, and every other
    /// constraint reached at the same instant as `index`, to the run's time resolution, and not
    /// leaving. How long each constraint still takes to reach its surface from `y` is
    /// `max(h, 0) / −ḣ` (the event state may lie a little before the root, by the accuracy of
    /// its location: two corners of a flat block landing together are both `1e-11` above the
    /// floor there); another constraint joins where its time is within the resolution of that
    /// of `index`, or where it is at its surface to the rounding of `h`. A constraint near in
    /// position but reached later is a later impact of its own.
    pub(super) fn closed_set(
        &mut self,
        index: usize,
        t: f64,
        y: &[f64],
    ) -> Result<ActiveSet, Error> {
        let mut set = self.held().with(index);
        let m = self.sim.model.constraints().len();
        let (q, q_dot) = y.split_at(self.n);
        let reached = self.surface(index, t, q, q_dot);
        // The time at which `index` is reached, from `y`: 0 where it is reached already.
        let lead = if reached.h > 0.0 && reached.a_q_dot < 0.0 {
            reached.h / -reached.a_q_dot
        } else {
            0.0
        };
        let within = lead + self.time_resolution(t);
        let start = set;
        for other in (0..m).filter(|&i| !start.contains(i)) {
            let surface = self.surface(other, t, q, q_dot);
            let approach = (-surface.a_q_dot).max(0.0);
            let reach = approach * within + START_ROUND_OFF * surface.h_scale;
            if surface.h > reach || surface.h.is_nan() {
                continue;
            }
            let normal = self.normal(other, t, q, q_dot)?;
            if normal.a_q_dot <= normal.a_q_dot_round_off {
                set = set.with(other);
            }
        }
        Ok(set)
    }

    /// The constraint an impact on several at once is named after: of those `reached` (the
    /// impact's constraints not held before it), the one approached fastest in its own
    /// metric, `−ḣ / √(A M⁻¹ Aᵀ)`; among speeds equal to their rounding (a symmetric impact:
    /// a ball dropped onto the vertex of a symmetric groove), the first in the model's order,
    /// not whichever crossing the search happened to find first. `found` where none is.
    fn leading(
        &mut self,
        found: usize,
        reached: ActiveSet,
        t: f64,
        y: &[f64],
    ) -> Result<usize, Error> {
        if reached.len() <= 1 {
            return Ok(reached.iter().next().unwrap_or(found));
        }
        let (q, q_dot) = y.split_at(self.n);
        let mut best: Option<(usize, f64, f64)> = None;
        for index in reached.iter() {
            let normal = self.normal(index, t, q, q_dot)?;
            let scale = normal.s.sqrt();
            let speed = -normal.a_q_dot / scale;
            let round_off = normal.a_q_dot_round_off / scale;
            let faster = match best {
                None => true,
                Some((_, fastest, fastest_round_off)) => {
                    speed - fastest > round_off + fastest_round_off
                }
            };
            if faster && speed.is_finite() {
                best = Some((index, speed, round_off));
            }
        }
        Ok(best.map_or(found, |(index, _, _)| index))
    }

    /// Constraint `index` at `(q, q̇)`: `h`, `|A|`, the size of `h`'s terms and `A q̇`.
    pub(super) fn surface(&mut self, index: usize, t: f64, q: &[f64], q_dot: &[f64]) -> Surface {
        let mut gradient = std::mem::take(&mut self.scratch);
        let h = self.mech.constraint_gradient(index, t, q, &mut gradient);
        let a = &gradient[..self.n];
        let a_q_dot: f64 = a.iter().zip(q_dot).map(|(a, v)| a * v).sum();
        let surface = Surface {
            h,
            norm: a.iter().map(|a| a * a).sum::<f64>().sqrt(),
            h_scale: guard_scale(h, a, q),
            a_q_dot: if self.sim.model.is_autonomous() {
                a_q_dot
            } else {
                guard_along(self.sim.model, index, t, q, q_dot).1
            },
        };
        self.scratch = gradient;
        surface
    }

    /// The event state on the admissible side: the state at the root may be a little past the
    /// surface (the root was found on the interpolant, and the state may come from a refining
    /// step); Newton steps in time on the last step's dense output bring it back to `h ≥ 0`
    /// (REFERENCE §4).
    pub(super) fn admissible_side(
        &mut self,
        index: usize,
        t: f64,
        mut y: Vec<f64>,
    ) -> Result<(f64, Vec<f64>), Error> {
        let n = self.n;
        let (h, _, _) = guard_along(self.sim.model, index, t, &y[..n], &y[n..]);
        let in_last_step = self.stepper.t_previous() < t && t <= self.stepper.t();
        if h >= 0.0 || !in_last_step {
            return Ok((t, y));
        }
        self.dense()?;
        let cubic = self.cubic;
        let mut t_new = t;
        for _ in 0..8 {
            let (h, h_dot, _) = guard_along(self.sim.model, index, t_new, &y[..n], &y[n..]);
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
    pub(super) fn state_at(&mut self, t: f64) -> Result<Vec<f64>, Error> {
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
            self.advance_work(self.stepper.t())?;
        }
        Ok(self.stepper.y().to_vec())
    }

    /// The earliest crossing of any guard (except those `held`) in `[t0, t1]`, on the dense
    /// output, its samples put back onto the held constraints. Other constraints at the surface
    /// there join the impact law ([`Runner::closed_set`]).
    pub(super) fn earliest_crossing(
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
            let (stepper, mech, n, grips) = (&self.stepper, self.mech, self.n, self.grips);
            let mut y = std::mem::take(&mut self.scratch);
            // A close approach without a crossing may be a constraint that touches 0 without
            // changing sign ([`Runner::touched`]).
            // Sampled a thousand times per run: inlined into the search, as a call it costs
            // a fifth of the sample (the search's own calls to it are in six places).
            let (crossing, touch) = first_crossing_or_touch(
                t0,
                t1,
                #[inline(always)]
                |t| {
                    interpolate(stepper, cubic, t, &mut y);
                    // Best effort: a failed projection just leaves the sample as it is.
                    let _ = project_onto(&mech, held, grips, t, n, &mut y);
                    let (h, h_dot, _) = guard_along(mech.model(), index, t, &y[..n], &y[n..]);
                    (h, Some(h_dot))
                },
            );
            self.scratch = y;
            if let Some(c) = crossing {
                let t = c.t_admissible;
                if found.is_none_or(|(_, t_other)| t < t_other) {
                    found = Some((index, t));
                }
            } else if let Some((t, _)) = touch {
                self.touched(index, t, held)?;
            }
        }
        Ok(found)
    }

    /// Constraint `index` came close to 0 at `t` in the last step without crossing it: an error
    /// if it touched `h = 0` where `∂h/∂q` vanishes (`h = y²`, `h = (x² + y² − 1)²`), which no
    /// sign change reveals, so that the body would pass through the surface unseen. A graze of
    /// a regular surface (`∂h/∂q` away from 0) is no error. The test is the one an impact makes
    /// ([`Runner::refuse_flat`]).
    ///
    /// The state there is read off the step's dense output (prepared), not stepped to: the
    /// search goes on over the same step for the other constraints.
    fn touched(&mut self, index: usize, t: f64, held: ActiveSet) -> Result<(), Error> {
        let n = self.n;
        let mut y = vec![0.0; 2 * n];
        interpolate(&self.stepper, self.cubic, t, &mut y);
        // Best effort, as for the samples of the guard.
        let _ = project_onto(&self.mech, held, self.grips, t, n, &mut y);
        let (q, q_dot) = y.split_at(n);
        let surface = self.surface(index, t, q, q_dot);
        let q_tol = surface.position_tolerance(self.sim.options.tolerances);
        if surface.h > q_tol * surface.norm.max(f64::MIN_POSITIVE) {
            return Ok(());
        }
        let normal = self.normal(index, t, q, q_dot)?;
        self.refuse_flat(index, t, &y, &normal, q_tol)
    }

    /// Fails the run at `(t, y)` where constraint `index` has no normal to act along: a surface
    /// where `∂h/∂q` vanishes (`h = x³` at `x = 0`), where below the position tolerance `q_tol`
    /// `h` is dominated by its curvature along the motion, not by its gradient.
    fn refuse_flat(
        &mut self,
        index: usize,
        t: f64,
        y: &[f64],
        normal: &Normal,
        q_tol: f64,
    ) -> Result<(), Error> {
        if normal.gradient_norm <= 0.5 * normal.curvature * q_tol {
            let error = Error::DegenerateConstraint {
                t,
                constraint: self.sim.model.constraints()[index].name.clone(),
            };
            return Err(self.fail_at(t, y, error));
        }
        Ok(())
    }

    /// Constraint `other` reached at about `t` while the current mode holds others: the state
    /// there, on the held constraints and on `other`'s admissible side, is a crossing.
    pub(super) fn reached_while_held(&mut self, other: usize, t: f64) -> Result<Next, Error> {
        let found = self.stepper.t() - self.stepper.t_previous();
        self.emit_grid_before(t)?;
        let hint = self.stepper.suggested_step();
        let before = self.state_at(t)?;
        let (t, mut before) = self.admissible_side(other, t, before)?;
        // Best effort: the interpolated state is within the tolerance of the held constraints.
        let _ = project_onto(&self.mech, self.held(), self.grips, t, self.n, &mut before);
        self.crossing(other, t, before, hint, found)
    }
}

/// Whether a body at a constraint's surface is leaving it: moving away, or at rest (a normal
/// velocity within its rounding has no sign) and accelerating away. Otherwise it is in contact
/// (moving in, or pressed onto the surface at rest, however `A q̇` happened to round).
pub(super) fn leaving(normal: &Normal) -> bool {
    normal.a_q_dot > normal.a_q_dot_round_off
        || (normal.a_q_dot.abs() <= normal.a_q_dot_round_off
            && normal.h_ddot_free > normal.h_ddot_round_off)
}

/// How far from a surface, in units of `h`'s rounding scale `|h| + Σ|A_i q_i|`, a start counts
/// as on it ([`Runner::rest_at_start`]).
const START_ROUND_OFF: f64 = 64.0 * f64::EPSILON;

/// A constraint at one state: [`Runner::surface`].
pub(super) struct Surface {
    /// `h(q)`.
    pub h: f64,
    /// `|A|`.
    pub norm: f64,
    /// `|h| + Σ|A_i q_i|`: rounding the coordinates changes `h` by about `ε` times this.
    pub h_scale: f64,
    /// `ḣ = A q̇ + ∂ₜh`.
    pub a_q_dot: f64,
}

impl Surface {
    /// The size of the coordinates as the constraint weighs them, `(|h| + Σ|A_i q_i|)/|A|`,
    /// for scaling position tolerances: a coordinate `h` ignores or barely depends on (like the
    /// ball's `x1`) must not loosen them. 0 where it is not finite.
    pub fn q_scale(&self) -> f64 {
        let scale = self.h_scale / self.norm;
        if scale.is_finite() {
            scale
        } else {
            0.0
        }
    }

    /// The position tolerance here, in the coordinates' units: `atol + rtol q_scale`.
    pub fn position_tolerance(&self, tol: Tolerances) -> f64 {
        tol.atol + tol.rtol * self.q_scale()
    }

    /// `factor` position tolerances, in `h`'s units: `factor (atol + rtol q_scale) |A|`.
    pub fn tolerance(&self, factor: f64, tol: Tolerances) -> f64 {
        factor * self.position_tolerance(tol) * self.norm
    }
}
