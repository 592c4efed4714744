//! Motion held on one constraint or a set: another constraint reached, and lift-off where a
//! held force vanishes (docs/contact-laws.md, law 1).

use super::equations::project_onto;
use super::{holding, interpolate, Next, Runner};
use crate::contact::{self};
use crate::error::Error;
use crate::events::first_crossing;
use crate::execution::{ActiveSet, EventKind, Mode};
use crate::mechanics::Normal;
use crate::model::HybridLagrangian;
use crate::observer::Observer;

impl<L: HybridLagrangian, O: Observer> Runner<'_, '_, L, O> {
    /// After a step on constraint `index`, whose normal response at the step's end is `end`
    /// when the step computed it.
    pub(super) fn after_constrained_step(
        &mut self,
        index: usize,
        end: Option<Normal>,
    ) -> Result<Next, Error> {
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
        let next_bound = self.lift_trend(
            ActiveSet::single(index),
            (t0, t1),
            (margin_start, margin_end),
        )?;
        let dip = matches!(next_bound, Some(None));
        let crossing = if !dip && lift_ruled_out(margin_start, margin_end) {
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
                    .normal(index, t, q, q_dot, &mut w)
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
                    .project(index, t, q, q_dot)
                    .map_err(|err| self.dynamics_error(err, t, &state.clone()))?;
            }
            return self.liftoff(index, t, state);
        }
        // (The step's end is on h = 0, ḣ = 0 already: `Equations::correct_end`.)
        self.flight_bound = next_bound.flatten().unwrap_or(f64::INFINITY);
        self.commit_step()?;
        Ok(Next::Continue)
    }

    /// What the lift-off test needs beyond the step's ends: the margin also sampled at the
    /// step's middle, and the next step bounded so that the parabola through the three margins,
    /// continued, turns by at most half the margin at the step's end (`|m″| s²/2 ≤ |m|/2`): no
    /// window where the force lets go can then fit between two ends that hold. A held force
    /// may vary faster than the held motion needs steps for: with time (a ball resting on a
    /// vibrating table, whose steps would grow without bound) or with a coordinate that moves
    /// uniformly (a rotor that modulates a floor's load, whose angle is linear in time and
    /// integrated exactly by steps of many turns). `Some(bound)`; `Some(None)` where the middle
    /// lets go (the step must be searched) and no bound is needed; `None` for a step of no
    /// length.
    fn lift_trend(
        &mut self,
        held: ActiveSet,
        (t0, t1): (f64, f64),
        (m0, m1): (f64, f64),
    ) -> Result<Option<Option<f64>>, Error> {
        if t1 <= t0 {
            return Ok(None);
        }
        self.dense()?;
        let h = t1 - t0;
        let t_mid = t0 + 0.5 * h;
        let mut y = vec![0.0; 2 * self.n];
        interpolate(&self.stepper, self.cubic, t_mid, &mut y);
        let m_mid = match held.only() {
            Some(index) => {
                let (q, q_dot) = y.split_at(self.n);
                self.normal(index, t_mid, q, q_dot)?.lift_margin()
            }
            None => self.set_margin(held, t_mid, &y)?,
        };
        if m_mid > 0.0 {
            return Ok(Some(None));
        }
        let curvature = 4.0 * (m0 - 2.0 * m_mid + m1).abs() / (h * h);
        let floor = 1e3 * self.time_resolution(t1);
        let bound = if curvature > 0.0 {
            (m1.abs() / curvature).sqrt().max(floor)
        } else {
            f64::INFINITY
        };
        Ok(Some(Some(bound)))
    }

    pub(super) fn liftoff(&mut self, index: usize, t: f64, state: Vec<f64>) -> Result<Next, Error> {
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

    /// After a restart in the current mode: the lift-off test's margins at the mode's start.
    pub(super) fn enter_mode(&mut self, t: f64) -> Result<(), Error> {
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
    pub(super) fn set_margin(&mut self, set: ActiveSet, t: f64, y: &[f64]) -> Result<f64, Error> {
        let (q, q_dot) = y.split_at(self.n);
        let mut acc = vec![0.0; self.n];
        let held = contact::held_acceleration(&self.mech, set, t, q, q_dot, &mut acc);
        let (_, hold) = held.map_err(|err| self.fail_dynamics(err, t, y))?;
        Ok(hold.margin())
    }

    /// After a step held on two or more constraints: another constraint reached (an impact on
    /// all of them), or one of them letting go (its multiplier reaching 0, where law 1 decides
    /// again which hold).
    pub(super) fn after_set_step(&mut self, set: ActiveSet) -> Result<Next, Error> {
        let (t0, t1) = (self.stepper.t_previous(), self.stepper.t());
        let n = self.n;
        if let Some((other, t)) = self.earliest_crossing(t0, t1, set)? {
            return self.reached_while_held(other, t);
        }
        let end = self.stepper.y().to_vec();
        let margin_end = self.set_margin(set, t1, &end)?;
        let margin_start = self.set_margin_start;
        let next_bound = self.lift_trend(set, (t0, t1), (margin_start, margin_end))?;
        let dip = matches!(next_bound, Some(None));
        let crossing = if !dip && lift_ruled_out(margin_start, margin_end) {
            None
        } else {
            self.dense()?;
            let (stepper, mech, cubic) = (&self.stepper, self.mech, self.cubic);
            let mut y = vec![0.0; 2 * n];
            let mut acc = vec![0.0; n];
            first_crossing(t0, t1, |t| {
                interpolate(stepper, cubic, t, &mut y);
                let (q, q_dot) = y.split_at(n);
                let margin = contact::held_acceleration(&mech, set, t, q, q_dot, &mut acc)
                    .map_or(f64::NAN, |(_, hold)| hold.margin());
                (lift_guard(margin), None)
            })
        };
        self.set_margin_start = margin_end;
        if let Some(c) = crossing {
            let t = c.t_violating;
            self.emit_grid_before(t)?;
            let mut state = self.state_at(t)?;
            let copy = state.clone();
            project_onto(&self.mech, set, t, n, &mut state)
                .map_err(|err| self.fail_dynamics(err, t, &copy))?;
            return self.set_liftoff(set, t, state);
        }
        self.flight_bound = next_bound.flatten().unwrap_or(f64::INFINITY);
        self.commit_step()?;
        Ok(Next::Continue)
    }

    /// Some constraints of `set` let go at `t`: law 1 on the set decides which still hold (at
    /// least the one whose margin is largest goes).
    pub(super) fn set_liftoff(
        &mut self,
        set: ActiveSet,
        t: f64,
        state: Vec<f64>,
    ) -> Result<Next, Error> {
        let mut held = self.held_of(set, t, &state)?;
        if held == set {
            // At the root itself law 1 may still see the force at 0: the largest margin goes.
            let (q, q_dot) = state.split_at(self.n);
            let mut acc = vec![0.0; self.n];
            let solved = contact::held_acceleration(&self.mech, set, t, q, q_dot, &mut acc)
                .map(|(c, hold)| (hold.margins, c.indices));
            let (margins, indices) = solved.map_err(|err| self.fail_dynamics(err, t, &state))?;
            let worst = (0..margins.len())
                .max_by(|&i, &j| margins[i].total_cmp(&margins[j]))
                .unwrap_or(0);
            held = set.minus(ActiveSet::single(indices[worst]));
        }
        let gone = set.minus(held);
        let index = gone.iter().next().unwrap_or(0);
        let mode = holding(held);
        let change = (gone, Vec::new());
        self.record_event(EventKind::Liftoff, index, change, t, &state, &state, mode)?;
        self.sequence.clear();
        self.accumulation.clear();
        self.restart(t, &state, None)?;
        self.enter_mode(t)?;
        Ok(Next::Continue)
    }
}

/// Whether the lift margins at a step's ends rule out a lift-off inside it without searching:
/// both negative by more than they differ.
fn lift_ruled_out(start: f64, end: f64) -> bool {
    end <= 0.0 && start.max(end) < -(end - start).abs()
}

/// The lift-off guard from a lift margin: it crosses 0 where the margin becomes positive. A
/// margin of exactly 0 (a contact without force, like two balls at rest side by side) holds.
pub(super) fn lift_guard(margin: f64) -> f64 {
    if margin == 0.0 {
        f64::MIN_POSITIVE
    } else {
        -margin
    }
}
