//! Zeno points: whether the impacts accumulate to one, on one constraint or several, as far as
//! the run resolves it (`Auto`, `Epsilon`, `Off`), and the switch through `R∞` there (or the
//! stall) (docs/contact-laws.md, law 3).

use super::mode::{holding, Transition};
use super::record::split;
use super::{Next, Runner, AUTO_ROUND_OFF_ULPS, OFF_ROUND_OFF_ULPS};
use crate::contact::{self};
use crate::derivatives::guard_along;
use crate::error::Error;
use crate::execution::{ActiveSet, Grips, Mode, Outcome, ZenoKind, ZenoPoint};
use crate::friction;
use crate::mechanics::guard_scale;
use crate::mechanics::DynamicsError;
use crate::model::HybridLagrangian;
use crate::observer::Observer;
use crate::options::{Completion, ZenoStrategy};
use crate::zeno::Prediction;

/// The next flight of a body leaving a constraint: the prediction, and the normal velocity and
/// acceleration it comes from (`ḣ⁺`, and `ḧ` under the motion held on the others).
pub(super) struct NextFlight {
    pub prediction: Option<Prediction>,
    pub h_dot: f64,
    pub h_ddot: f64,
}

impl<L: HybridLagrangian, O: Observer> Runner<'_, '_, L, O> {
    /// After an impact reaching `index` on `contacts` at `t`, which left `after` in the mode now
    /// current (`index` not held): whether the impacts accumulate to a Zeno point as far as the
    /// run resolves it, and if so the switch (or the stall, with `Off`); else the flight it
    /// starts, its next step bounded by the predicted flight.
    pub(super) fn after_impact(
        &mut self,
        index: usize,
        contacts: ActiveSet,
        t: f64,
        after: Vec<f64>,
        hint: f64,
    ) -> Result<Next, Error> {
        let e = self.sim.model.constraints()[index].restitution;
        if self.watch.accumulation.constraints().len() > 1 {
            // Impacts alternating between constraints (a groove's walls).
            if let Some(next) = self.accumulation_resolved(index, contacts, t, &after)? {
                return Ok(next);
            }
        }
        if self.watch.no_progress(t, self.time_resolution(t)) {
            return self.stuck_at(index, t, &after);
        }
        let held = self.held();
        if held.contains(index) {
            // Closed by the impact and held (a rocking block's new pivot): it does not fly.
            self.resume(t, &after, Some(hint))?;
            return Ok(Next::Continue);
        }
        // The sequence on `index`: its next flight from the physics.
        let flight = self.held_prediction(index, held, e, t, &after)?;
        if let Some(p) = flight.prediction {
            // R∞ onto the constraint reached, those held, and those of the impact (reached at
            // the same instant: at their surfaces too).
            let all = held.union(contacts).with(index);
            let ulps = match self.sim.options.zeno {
                ZenoStrategy::Auto => AUTO_ROUND_OFF_ULPS,
                // An ε below what f64 resolves is never met: switch where impacts stop being
                // resolvable, as Off stalls there.
                ZenoStrategy::Off | ZenoStrategy::Epsilon(_) => OFF_ROUND_OFF_ULPS,
            };
            if self.zeno_resolved(index, t, &after, &p, &flight, ulps)? {
                return match self.sim.options.zeno {
                    ZenoStrategy::Off => Ok(self.stall(index, all, t, &after, p)),
                    _ => self.switch(index, all, t, after, Some(p)),
                };
            }
        }
        let hint = match flight.prediction {
            Some(p) if p.next_flight > 0.0 => {
                self.flight_bound = 1.5 * p.next_flight;
                hint.min(self.flight_bound)
            }
            _ => hint,
        };
        self.resume(t, &after, Some(hint))?;
        Ok(Next::Continue)
    }

    /// Whether the rest of the Zeno sequence on constraint `index` after the impact that left
    /// `y` is below what the run resolves, with `ulps` the rounding margin of the guard (see
    /// [`AUTO_ROUND_OFF_ULPS`]); `flight` is its next flight.
    ///
    /// Resolved means the next flight is not longer than the run's time resolution at `t`
    /// ([`Runner::time_resolution`]), or either:
    /// - the predicted remaining time `T_rem` is shorter than the integrator's time resolution
    ///   `1/‖ẋ‖` (in its own weighted error norm): the execution cannot move by more than the
    ///   tolerance before `τ∞`, so switching now is as accurate as the integration; or
    /// - the next bounce's height `(ḣ⁺)²/(2|ḧ|)` is within `ulps` of the rounding error of
    ///   `h` itself: no further impact can be resolved in `f64`, and what the switch changes
    ///   after `τ∞` (of order `ḣ⁺ · T_rem`) is far below the tolerance.
    fn zeno_resolved(
        &mut self,
        index: usize,
        t: f64,
        y: &[f64],
        p: &Prediction,
        flight: &NextFlight,
        ulps: f64,
    ) -> Result<bool, Error> {
        if p.next_flight <= self.time_resolution(t) {
            return Ok(true);
        }
        let n = self.n;
        let q = &y[..n];
        // Round-off floor of the guard: the rounding of h = h(q) as the coordinates round.
        let mut gradient = std::mem::take(&mut self.scratch);
        let h = self.mech.constraint_gradient(index, t, q, &mut gradient);
        let h_scale = guard_scale(h, &gradient[..n], q);
        self.scratch = gradient;
        let height = flight.h_dot.max(0.0).powi(2) / (2.0 * -flight.h_ddot);
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
    pub(super) fn resolution_rate(&mut self, t: f64, y: &[f64]) -> Result<f64, Error> {
        let n = self.n;
        let (q, q_dot) = y.split_at(n);
        let tol = self.sim.options.tolerances;
        let mut acc = std::mem::take(&mut self.scratch);
        let free = self.mech.acceleration(t, q, q_dot, None, &mut acc[..n]);
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

    /// Impacts that no longer advance time: a chattering contact. Switch, or stall with `Off`,
    /// onto every constraint of the accumulation and those held.
    pub(super) fn stuck_at(&mut self, index: usize, t: f64, y: &[f64]) -> Result<Next, Error> {
        let p = Prediction {
            next_flight: 0.0,
            remaining: 0.0,
        };
        let all = self
            .watch
            .accumulation
            .constraints()
            .union(self.held())
            .with(index);
        match self.sim.options.zeno {
            ZenoStrategy::Off => Ok(self.stall(index, all, t, y, p)),
            _ => self.switch(index, all, t, y.to_vec(), Some(p)),
        }
    }

    /// The Zeno point of an accumulation onto `set`, its last impact reaching `index`, switched
    /// or stalled at `t` in the state `point`. One constraint alone: its sequence's impacts and
    /// their ratio, and genuine where `e > 0` and the flights shrink (or the next one is still
    /// resolvable); several: the accumulation's, genuine where its flights shrink and the next
    /// one is still resolvable.
    fn zeno_point(
        &self,
        index: usize,
        set: ActiveSet,
        t: f64,
        point: &[f64],
        prediction: Option<Prediction>,
    ) -> ZenoPoint {
        let resolution = self.time_resolution(t);
        let remaining = prediction.map_or(0.0, |p| p.remaining);
        let (kind, impacts, ratio) = if set == ActiveSet::single(index) {
            let e = self.sim.model.constraints()[index].restitution;
            let ratio = self.watch.sequence.ratio();
            let kind = match prediction {
                Some(_) if e > 0.0 && ratio.is_some_and(|r| r > 0.0) => ZenoKind::Genuine,
                Some(p) => p.kind(e, resolution),
                None => ZenoKind::Chattering,
            };
            (kind, self.watch.sequence.count(), ratio)
        } else {
            let ratio = self.watch.accumulation.ratio();
            let kind = match (prediction, ratio) {
                (Some(p), Some(r)) if r > 0.0 && p.next_flight > resolution => ZenoKind::Genuine,
                _ => ZenoKind::Chattering,
            };
            (kind, self.watch.accumulation.count(), ratio)
        };
        ZenoPoint {
            constraint: index,
            constraints: set,
            kind,
            t_switch: t,
            t_zeno: t + remaining,
            impacts,
            ratio,
            point: split(point, self.n),
        }
    }

    /// `Off` at the Zeno point of an accumulation onto `set`: the plain hybrid system stops
    /// there, at `(t, y)`.
    pub(super) fn stall(
        &mut self,
        index: usize,
        set: ActiveSet,
        t: f64,
        y: &[f64],
        p: Prediction,
    ) -> Next {
        let point = self.zeno_point(index, set, t, y, Some(p));
        let (constraint, t_zeno) = (point.constraint, point.t_zeno);
        self.record.zeno.push(point);
        // Best effort: the run stops here.
        let _ = self.advance_work(t);
        self.commit_time(t, y);
        Next::Stop(Outcome::ZenoStalled { constraint, t_zeno })
    }

    /// The switch to the constrained motion through `R∞` onto every constraint of `set` at
    /// once (position onto all `hᵢ = 0`, velocity by the plastic law), its last impact reaching
    /// `index`; then law 1 decides which of them hold, and those that would have to pull let
    /// go at once.
    ///
    /// For one constraint with `completion = "model"`, the model's own map comes first: under
    /// `Auto` the switch state stands for the Zeno point, up to the bounces not taken, whose
    /// normal velocity goes plastically first, so that a map written for the point itself (the
    /// paper's keep some coordinates and solve for the others) does not turn it into a
    /// tangential error; under the paper's ε rule the map acts on the state as it is, as in the
    /// paper.
    pub(super) fn switch(
        &mut self,
        index: usize,
        set: ActiveSet,
        t: f64,
        before: Vec<f64>,
        prediction: Option<Prediction>,
    ) -> Result<Next, Error> {
        let n = self.n;
        let mut after = before.clone();
        let own_map = self.sim.options.completion == Completion::ModelMap;
        if let (Some(only), true) = (set.only(), own_map) {
            let (q, q_dot) = after.split_at_mut(n);
            if self.sim.options.zeno == ZenoStrategy::Auto {
                self.mech
                    .project(only, t, q, q_dot)
                    .map_err(|err| self.fail_dynamics(err, t, &before))?;
            }
            self.sim.model.completion_map_at(only, t, q, q_dot);
        }
        if self.mech.frictional(set) {
            // The impacts not taken stick where the cones allow stopping every contact at once;
            // else their tangential impulses are applied (docs/friction.md, Zeno points).
            let remaining = prediction.map_or(0.0, |p| p.remaining);
            let stuck = contact::stick_all(&self.mech, set, t, n, &mut after, remaining)
                .map_err(|err| self.fail_dynamics(err, t, &before))?;
            if !stuck {
                self.remaining_friction(index, set, t, &mut after, prediction)
                    .map_err(|err| self.fail_dynamics(err, t, &before))?;
            }
        }
        contact::project_onto(&self.mech, set, Grips::none(), t, n, &mut after)
            .map_err(|err| self.fail_dynamics(err, t, &before))?;
        // Law 1 there: the friction states, and a constraint that cannot hold the motion
        // (λ > 0) lets go at once.
        let (held, grips) = self.decide(set, t, &after)?;
        if !grips.stick.is_empty() {
            contact::project_onto(&self.mech, set, grips, t, n, &mut after)
                .map_err(|err| self.fail_dynamics(err, t, &before))?;
        }
        // (Only where every contact holds on: the slipping then goes on over that time.)
        if let Some(p) = prediction.filter(|_| self.mech.frictional(held) && held == set) {
            contact::unwind_slip(&self.mech, held, grips, t, n, &mut after, p.remaining)
                .map_err(|err| self.fail_dynamics(err, t, &before))?;
        }
        let point = self.zeno_point(index, set, t, &after, prediction);
        let mode = Mode::Constrained(set);
        self.apply(Transition::Zeno(point), t, &before, &after, mode, grips)?;
        self.restart(t, &after, None)?;
        if held != set {
            let gone = set.minus(held);
            let named = gone.iter().next().unwrap_or(index);
            let transition = Transition::Liftoff { named, gone };
            self.apply(transition, t, &after, &after, holding(held), grips)?;
            self.resume(t, &after, None)?;
            return Ok(Next::Continue);
        }
        self.enter_mode(t)?;
        Ok(Next::Continue)
    }

    /// At the switch onto `set` after an impact reaching `index` (its accumulation predicted by
    /// `prediction`), the tangential impulses of the impacts not taken, at once: the plastic
    /// impact with friction on `y`'s velocities, each contact of the set approaching at the
    /// normal velocity whose plastic impulse is the sum of the rest of its sequence's
    /// (`(1 + e)/(1 − e)` times the velocity it left with, for `e < 1`; as it is where it is
    /// already approaching), so that friction takes out the slip those impacts would.
    fn remaining_friction(
        &mut self,
        index: usize,
        set: ActiveSet,
        t: f64,
        y: &mut [f64],
        prediction: Option<Prediction>,
    ) -> Result<(), DynamicsError> {
        let n = self.n;
        let (q, q_dot) = y.split_at_mut(n);
        let frame = friction::Frame::of(&self.mech, set, t, q, q_dot)?;
        let constraints = self.sim.model.constraints();
        let approach: Vec<f64> = frame
            .indices
            .iter()
            .zip(&frame.normals)
            .map(|(&i, normal)| {
                let e = constraints[i].restitution;
                let leaving = normal.a_q_dot.max(0.0);
                if i == index && prediction.is_some() && e < 1.0 {
                    -(1.0 + e) / (1.0 - e) * leaving
                } else {
                    normal.a_q_dot.min(0.0)
                }
            })
            .collect();
        frame.plastic(set, &approach, q_dot)
    }

    /// The constraints of `set` within `ε` of their surfaces at `y` (`|h| ≤ ε`).
    pub(super) fn within_epsilon(&self, set: ActiveSet, t: f64, y: &[f64], eps: f64) -> ActiveSet {
        let q = &y[..self.n];
        set.iter()
            .filter(|&i| self.sim.model.constraint_at::<f64>(i, t, q).abs() <= eps)
            .fold(ActiveSet::empty(), ActiveSet::with)
    }

    /// Whether the paper's ε rule holds on every constraint of `set` at `y`.
    pub(super) fn epsilon_met(
        &mut self,
        set: ActiveSet,
        t: f64,
        y: &[f64],
        eps: f64,
    ) -> Result<bool, Error> {
        let (q, q_dot) = y.split_at(self.n);
        for index in set.iter() {
            let (h, h_dot, _) = guard_along(self.sim.model, index, t, q, q_dot);
            if !(h.abs() <= eps && h_dot.abs() <= eps) {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// After an impact reaching `index` at `t` on the constraints `involved`, which left `y`
    /// (in the mode now current), the impacts accumulating over several constraints: whether
    /// their accumulation has reached its Zeno point as far as the run resolves it
    /// (docs/contact-laws.md, law 3), and if so the switch (or the stall, with `Off`).
    ///
    /// The rest of the sequence is predicted from the measured ratio of its flights, or, where
    /// it is longer, from the flight back to the constraint just reached. It is resolved when
    /// the next flight is below what `f64` time resolves at `t`, or below the rounding of the
    /// constraints' `h`, or, under `Auto`, when the remaining time is below the integration's
    /// time resolution; in each case only where every constraint of the accumulation is
    /// within a hundred position tolerances of its surface.
    fn accumulation_resolved(
        &mut self,
        index: usize,
        involved: ActiveSet,
        t: f64,
        y: &[f64],
    ) -> Result<Option<Next>, Error> {
        let held = self.held();
        // In a wedge the flights do not shrink by one ratio (a short flight between two walls
        // may be followed by one fifty times longer), and one short flight would make the
        // ratio's prediction switch early.
        let measured = self.watch.accumulation.predict();
        let e = self.sim.model.constraints()[index].restitution;
        // (A constraint the impact closed and holds does not fly back: the ratio alone.)
        let back = if held.contains(index) {
            None
        } else {
            self.held_prediction(index, held, e, t, y)?.prediction
        };
        let prediction = match (measured, back) {
            (Some(m), Some(b)) if b.remaining > m.remaining => Some(b),
            (m, _) => m,
        };
        let Some(p) = prediction else {
            return Ok(None);
        };
        // The constraints of the last impact that are at their surfaces take part too (two
        // walls reached at once, again and again).
        let accumulating = self.watch.accumulation.constraints().union(involved);
        if !self.near(accumulating, t, y) {
            return Ok(None);
        }
        let ulps = match self.sim.options.zeno {
            ZenoStrategy::Auto => AUTO_ROUND_OFF_ULPS,
            _ => OFF_ROUND_OFF_ULPS,
        };
        let resolved = p.next_flight <= self.time_resolution(t)
            || self.below_round_off(accumulating, t, y, p.next_flight, ulps)
            || (self.sim.options.zeno == ZenoStrategy::Auto
                && p.remaining * self.resolution_rate(t, y)? <= 1.0);
        if !resolved {
            return Ok(None);
        }
        let all = accumulating.union(held);
        Ok(Some(match self.sim.options.zeno {
            ZenoStrategy::Off => self.stall(index, all, t, y, p),
            _ => self.switch(index, all, t, y.to_vec(), Some(p))?,
        }))
    }

    /// The next flight of a body leaving constraint `index` at `y`, pulled back under the
    /// motion held on `held`: `Prediction` from `ḣ⁺` and `ḧ = ḧ_free − Σ W_ih λ_h`.
    pub(super) fn held_prediction(
        &mut self,
        index: usize,
        held: ActiveSet,
        e: f64,
        t: f64,
        y: &[f64],
    ) -> Result<NextFlight, Error> {
        let (q, q_dot) = y.split_at(self.n);
        let normal = self.normal(index, t, q, q_dot)?;
        let round_off = (normal.a_q_dot_round_off, normal.h_ddot_round_off);
        let held = held.minus(ActiveSet::single(index));
        if held.is_empty() {
            return Ok(NextFlight {
                prediction: Prediction::new(normal.a_q_dot, normal.h_ddot_free, e, round_off),
                h_dot: normal.a_q_dot,
                h_ddot: normal.h_ddot_free,
            });
        }
        let mut acc = vec![0.0; self.n];
        let grips = self.grips.within(held);
        contact::acceleration(&self.mech, held, grips, t, q, q_dot, &mut acc)
            .map_err(|err| self.fail_dynamics(err, t, y))?;
        // ḧ = A q̈ + Ȧ q̇, with Ȧ q̇ = ḧ_free − A M⁻¹ f.
        let mut free = vec![0.0; self.n];
        self.mech
            .acceleration(t, q, q_dot, None, &mut free)
            .map_err(|err| self.fail_dynamics(err, t, y))?;
        let mut gradient = vec![0.0; self.n];
        self.mech.constraint_gradient(index, t, q, &mut gradient);
        let change: f64 = gradient
            .iter()
            .zip(acc.iter().zip(&free))
            .map(|(a, (held, free))| a * (held - free))
            .sum();
        let h_ddot = normal.h_ddot_free + change;
        Ok(NextFlight {
            prediction: Prediction::new(normal.a_q_dot, h_ddot, e, round_off),
            h_dot: normal.a_q_dot,
            h_ddot,
        })
    }

    /// Whether the motion of every constraint of `set` over the next flight, `|ḣ| Δ`, is within
    /// `ulps` of the rounding error of its `h`: no further impact on them can be resolved.
    fn below_round_off(
        &mut self,
        set: ActiveSet,
        t: f64,
        y: &[f64],
        flight: f64,
        ulps: f64,
    ) -> bool {
        let (q, q_dot) = y.split_at(self.n);
        set.iter().all(|index| {
            let surface = self.surface(index, t, q, q_dot);
            surface.a_q_dot.abs() * flight <= ulps * f64::EPSILON * surface.h_scale
        })
    }

    /// Whether every constraint of `set` is within a hundred position tolerances of its surface
    /// at `y`.
    fn near(&mut self, set: ActiveSet, t: f64, y: &[f64]) -> bool {
        let tol = self.sim.options.tolerances;
        let (q, q_dot) = y.split_at(self.n);
        set.iter().all(|index| {
            let surface = self.surface(index, t, q, q_dot);
            surface.h.abs() <= surface.tolerance(100.0, tol)
        })
    }
}
