//! Zeno points: whether an accumulation of impacts, on one constraint or several, is resolved
//! as far as the run resolves it (`Auto`, `Epsilon`, `Off`), and the switch through `R∞` (or the
//! stall) there (docs/contact-laws.md, law 3).

use super::equations::project_onto;
use super::record::split;
use super::{holding, Next, Runner, AUTO_ROUND_OFF_ULPS, OFF_ROUND_OFF_ULPS, STUCK_EVENTS};
use crate::contact::{self};
use crate::derivatives::guard_along;
use crate::error::Error;
use crate::execution::{ActiveSet, EventKind, Mode, Outcome, ZenoKind, ZenoPoint};
use crate::mechanics::{guard_scale, Normal};
use crate::model::HybridLagrangian;
use crate::observer::Observer;
use crate::options::{Completion, ZenoStrategy};
use crate::zeno::Prediction;

impl<L: HybridLagrangian, O: Observer> Runner<'_, '_, L, O> {
    /// Whether the rest of the Zeno sequence after the impact that left `y` is below what the
    /// run resolves, with `ulps` the rounding margin of the guard (see [`Self::round_off_floor`]).
    ///
    /// Resolved means the next flight is not longer than the run's time resolution at `t`
    /// ([`Runner::time_resolution`]), or either:
    /// - the predicted remaining time `T_rem` is shorter than the integrator's time resolution
    ///   `1/‖ẋ‖` (in its own weighted error norm): the execution cannot move by more than the
    ///   tolerance before `τ∞`, so switching now is as accurate as the integration; or
    /// - the next bounce's height `(A q̇⁺)²/(2|ḧ|)` is within `ulps` of the rounding error of
    ///   `h` itself: no further impact can be resolved in `f64`, and what the switch changes
    ///   after `τ∞` (of order `A q̇⁺ · T_rem`) is far below the tolerance.
    pub(super) fn zeno_resolved(
        &mut self,
        index: usize,
        t: f64,
        y: &[f64],
        p: &Prediction,
        normal: &Normal,
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

    /// Genuine when the flights measured so far shrink geometrically (positive intervals), or
    /// when the next one is still resolvable; chattering otherwise (zero-length intervals).
    pub(super) fn zeno_kind(&self, p: &Prediction, e: f64, t: f64) -> ZenoKind {
        if e > 0.0 && self.sequence.ratio().is_some_and(|r| r > 0.0) {
            ZenoKind::Genuine
        } else {
            p.kind(e, self.time_resolution(t))
        }
    }

    /// Events that do not advance time: after [`STUCK_EVENTS`] in a row the contact is chattering.
    pub(super) fn no_progress(&mut self, t: f64) -> bool {
        if t - self.last_event_t <= self.time_resolution(t) {
            self.stuck += 1;
        } else {
            self.stuck = 0;
        }
        self.last_event_t = t;
        self.stuck >= STUCK_EVENTS
    }

    /// Impacts that no longer advance time: a chattering contact. Switch, or stall with `Off`;
    /// onto every constraint of the accumulation and those held, where that is more than one.
    pub(super) fn stuck_at(&mut self, index: usize, t: f64, y: &[f64]) -> Result<Next, Error> {
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

    pub(super) fn stall(&mut self, index: usize, t: f64, y: &[f64], p: Prediction, e: f64) -> Next {
        let point = ZenoPoint {
            constraint: index,
            constraints: ActiveSet::single(index),
            kind: self.zeno_kind(&p, e, t),
            t_switch: t,
            t_zeno: t + p.remaining,
            impacts: self.sequence.count(),
            ratio: self.sequence.ratio(),
            point: split(y, self.n),
        };
        self.stop_at(point, y)
    }

    /// Ends the run at the Zeno point `point`, reached in the state `y` (`Off`).
    fn stop_at(&mut self, point: ZenoPoint, y: &[f64]) -> Next {
        let (constraint, t, t_zeno) = (point.constraint, point.t_switch, point.t_zeno);
        self.zeno.push(point);
        // Best effort: the run stops here.
        let _ = self.advance_work(t);
        self.commit_time(t, y);
        Next::Stop(Outcome::ZenoStalled { constraint, t_zeno })
    }

    /// The switch to the constrained motion through `R∞`.
    pub(super) fn switch(
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
                        .project(index, t, q, q_dot)
                        .map_err(|err| self.fail_dynamics(err, t, &before))?;
                }
                self.sim.model.completion_map_at(index, t, q, q_dot);
            }
            self.mech
                .project(index, t, q, q_dot)
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
        self.end_accumulation_held(ActiveSet::single(index));
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
    pub(super) fn accumulation_resolved(
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
            // Impacts alternating between constraints: the measured ratio, unless the physics
            // of the constraint just reached says the rest takes longer. In a wedge the flights
            // do not shrink by one ratio (a short flight between two walls may be followed by
            // one fifty times longer), and one short flight would make the ratio's prediction
            // switch early.
            let measured = self.accumulation.predict();
            let e = self.sim.model.constraints()[index].restitution;
            let back = self.held_prediction(index, held, e, t, y)?;
            match (measured, back) {
                (Some(m), Some(b)) if b.remaining > m.remaining => Some(b),
                (m, _) => m,
            }
        };
        let Some(p) = prediction else {
            return Ok(None);
        };
        // The constraints of the last impact that are at their surfaces take part too (two
        // walls reached at once, again and again).
        let accumulating = accumulating.union(involved);
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
            ZenoStrategy::Off => self.stall_set(index, all, t, y, p),
            _ => self.switch_set(index, all, t, y.to_vec(), Some(p))?,
        }))
    }

    /// The next flight of a body leaving constraint `index` at `y`, pulled back under the
    /// motion held on `held`: `Prediction` from `A q̇⁺` and `ḧ = ḧ_free − Σ W_ih λ_h`.
    pub(super) fn held_prediction(
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
                .acceleration(t, q, q_dot, held.only(), &mut acc)
                .map(|_| ())
        } else {
            contact::held_acceleration(&self.mech, held, t, q, q_dot, &mut acc).map(|_| ())
        };
        motion.map_err(|err| self.fail_dynamics(err, t, y))?;
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
        Ok(Prediction::new(normal.a_q_dot, h_ddot, e, round_off))
    }

    /// Whether the motion of every constraint of `set` over the next flight, `|A q̇| Δ`, is within
    /// `ulps` of the rounding error of its `h`: no further impact on them can be resolved.
    pub(super) fn below_round_off(
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
    pub(super) fn near(&mut self, set: ActiveSet, t: f64, y: &[f64]) -> bool {
        let tol = self.sim.options.tolerances;
        let (q, q_dot) = y.split_at(self.n);
        set.iter().all(|index| {
            let surface = self.surface(index, t, q, q_dot);
            surface.h.abs() <= surface.tolerance(100.0, tol)
        })
    }

    /// The switch through `R∞` onto every constraint of `set` at once (position onto all
    /// `hᵢ = 0`, velocity by the plastic law), after which law 1 picks those that hold.
    pub(super) fn switch_set(
        &mut self,
        index: usize,
        set: ActiveSet,
        t: f64,
        before: Vec<f64>,
        prediction: Option<Prediction>,
    ) -> Result<Next, Error> {
        let mut after = before.clone();
        project_onto(&self.mech, set, t, self.n, &mut after)
            .map_err(|err| self.fail_dynamics(err, t, &before))?;
        let held = self.held_of(set, t, &after)?;
        let remaining = prediction.map_or(0.0, |p| p.remaining);
        let ratio = self.accumulation.ratio();
        let kind = match (prediction, ratio) {
            (Some(p), Some(r)) if r > 0.0 && p.next_flight > self.time_resolution(t) => {
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
        self.end_accumulation_held(held);
        let mode = holding(held);
        let change = (set, Vec::new());
        self.record_event(EventKind::Zeno, index, change, t, &before, &after, mode)?;
        self.restart(t, &after, None)?;
        self.enter_mode(t)?;
        Ok(Next::Continue)
    }

    /// After a Zeno point whose switch holds `held`: the accumulation ends where it holds all
    /// of the accumulation's constraints. Where it holds only part of them (a ball in a groove
    /// that came to rest on one wall, sliding into the vertex, where it strikes the other), the
    /// wider accumulation goes on through the Zeno point of its part, and law 3 keeps its
    /// impacts to predict where it ends.
    fn end_accumulation_held(&mut self, held: ActiveSet) {
        if self.accumulation.constraints().minus(held).is_empty() {
            self.accumulation.clear();
        }
    }

    /// `Off` on an accumulation over `set`: the plain hybrid system stops there.
    pub(super) fn stall_set(
        &mut self,
        index: usize,
        set: ActiveSet,
        t: f64,
        y: &[f64],
        p: Prediction,
    ) -> Next {
        let point = ZenoPoint {
            constraint: index,
            constraints: set,
            kind: ZenoKind::Genuine,
            t_switch: t,
            t_zeno: t + p.remaining,
            impacts: self.accumulation.count(),
            ratio: self.accumulation.ratio(),
            point: split(y, self.n),
        };
        self.stop_at(point, y)
    }
}
