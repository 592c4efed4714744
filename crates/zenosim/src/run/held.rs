//! Motion held on a set of constraints: another constraint reached, and lift-off where a held
//! force vanishes (docs/contact-laws.md, law 1).

use super::mode::{holding, Transition};
use super::{interpolate, Next, Runner};
use crate::contact::{self};
use crate::error::Error;
use crate::events::first_crossing;
use crate::execution::{ActiveSet, EventKind, Grips};
use crate::mechanics::Normal;
use crate::model::HybridLagrangian;
use crate::observer::Observer;

impl<L: HybridLagrangian, O: Observer> Runner<'_, '_, L, O> {
    /// After a step held on `held`; `end` is the held constraint's normal response at the
    /// step's end where the step computed it (one constraint held).
    pub(super) fn after_held_step(
        &mut self,
        held: ActiveSet,
        end: Option<Normal>,
    ) -> Result<Next, Error> {
        let (t0, t1) = (self.stepper.t_previous(), self.stepper.t());
        let n = self.n;
        // Another constraint reached while these hold: an impact on all of them, unless a held
        // contact lets go or changes its friction state before (below).
        let reached = self.earliest_crossing(t0, t1, held)?;
        // Lift-off: a constraint lets go where it would have to pull (λ above its rounding
        // error; a contact without force holds), reported on the side where it pulls, where
        // the motion without it is admissible. The margin is sampled on the dense output as it
        // is (within the tolerance of the constraints); inside the step only when its ends and
        // middle do not rule a crossing out.
        let margin_start = self.margin_start;
        let margin_end = match end {
            // (With friction the margin is the friction states' too.)
            Some(normal) if !self.mech.frictional(held) => normal.lift_margin(),
            _ => {
                let end = self.stepper.y().to_vec();
                self.margin_of(held, t1, &end)?
            }
        };
        let next_bound = self.lift_trend(held, (t0, t1), (margin_start, margin_end))?;
        let dip = matches!(next_bound, Some(None));
        let crossing = if !dip && lift_ruled_out(margin_start, margin_end) {
            None
        } else {
            self.dense()?;
            let (stepper, mech, cubic) = (&self.stepper, self.mech, self.cubic);
            let (grips, scales) = (self.grips, &self.scales);
            let mut y = std::mem::take(&mut self.scratch);
            let mut w = std::mem::take(&mut self.w);
            let mut acc = vec![0.0; n];
            let crossing = first_crossing(t0, t1, |t| {
                interpolate(stepper, cubic, t, &mut y);
                let (q, q_dot) = y.split_at(n);
                let margin =
                    contact::margin(&mech, held, grips, scales, t, q, q_dot, &mut w, &mut acc)
                        .unwrap_or(f64::NAN);
                (lift_guard(margin), None)
            });
            self.scratch = y;
            self.w = w;
            crossing
        };
        self.margin_start = margin_end;
        if let Some((other, t)) = reached {
            if crossing.as_ref().is_none_or(|c| c.t_violating > t) {
                return self.reached_while_held(other, t);
            }
        }
        if let Some(c) = crossing {
            let t = c.t_violating;
            // The dense output's state there, where the margin is past 0: it says which
            // margin crossed where the step to `t` itself still sees the old states.
            let mut seen = vec![0.0; 2 * n];
            interpolate(&self.stepper, self.cubic, t, &mut seen);
            self.emit_grid_before(t)?;
            let mut state = self.state_at(t)?;
            let copy = state.clone();
            contact::project_onto(&self.mech, held, self.grips, t, n, &mut state)
                .map_err(|err| self.fail_dynamics(err, t, &copy))?;
            return self.transition(held, t, state, &seen);
        }
        // (The step's end is on h = 0, ḣ = 0 already: `Equations::correct_end`.)
        if self.mech.frictional(held) {
            let end = self.stepper.y().to_vec();
            let (q, q_dot) = end.split_at(n);
            let grips = self.grips;
            contact::renew_slip_directions(&self.mech, held, grips, t1, q, q_dot, &mut self.scales)
                .map_err(|err| self.fail_dynamics(err, t1, &end))?;
        }
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
        let h = t1 - t0;
        let t_mid = t0 + 0.5 * h;
        // The middle off the cubic through the step's ends (their states and derivatives), not
        // its dense output, which would cost three more evaluations of the motion per held
        // step: the sample only bounds the next step and decides whether to search this one
        // (a search reads the dense output).
        let mut y = vec![0.0; 2 * self.n];
        self.stepper.interpolate_cubic(t_mid, &mut y);
        let m_mid = self.margin_of(held, t_mid, &y)?;
        if m_mid > 0.0 {
            return Ok(Some(None));
        }
        // A second difference within the cubic's own error (about the tolerance, relative to
        // the margins) says nothing of the margin's turn: no bound.
        let second = (m0 - 2.0 * m_mid + m1).abs();
        let size = m0.abs().max(m_mid.abs()).max(m1.abs());
        let noise = CUBIC_NOISE * self.sim.options.tolerances.rtol * size;
        let curvature = if second > noise {
            4.0 * second / (h * h)
        } else {
            0.0
        };
        let floor = 1e3 * self.time_resolution(t1);
        let bound = if curvature > 0.0 {
            (m1.abs() / curvature).sqrt().max(floor)
        } else {
            f64::INFINITY
        };
        Ok(Some(Some(bound)))
    }

    /// A held force or friction state reached its limit at `t`: law 1 on the set decides anew
    /// which constraints hold and, with friction, which stick or slip (docs/friction.md). At
    /// the root itself it may still see the old states (the margin at 0): then the contact
    /// whose margin is largest in `seen`, the dense output's state at `t` where the search
    /// found the margin past 0, changes (it lets go, starts to slip, or sticks). (The step to
    /// `t` and the dense output differ by the tolerance: a slip that reversed in the one may
    /// not have in the other, and a contact far from letting go must not be taken for it.)
    pub(super) fn transition(
        &mut self,
        held: ActiveSet,
        t: f64,
        mut state: Vec<f64>,
        seen: &[f64],
    ) -> Result<Next, Error> {
        // A slip that reached 0 is set to 0 (the root leaves it a rounding past), so that law 1
        // sees the contact at rest and decides with the static cone.
        let copy = state.clone();
        contact::stop_reached_slips(
            &self.mech,
            held,
            self.grips,
            &self.scales,
            t,
            self.n,
            &mut state,
        )
        .map_err(|err| self.fail_dynamics(err, t, &copy))?;
        let (mut still, mut grips) = self.decide(held, t, &state)?;
        if still == held && grips == self.grips {
            // (Without friction, the exact state's margins, as before friction came.)
            let at = if self.mech.frictional(held) {
                seen
            } else {
                &state
            };
            (still, grips) = self.forced_change(held, t, at)?;
            let stopped = grips.stick.minus(self.grips.stick);
            if still == held && !stopped.is_empty() {
                // A slip that stopped in the dense output but not yet in the step: stopped
                // here too, law 1 decides from rest (it may slip on the other way).
                let copy = state.clone();
                contact::project_onto(&self.mech, held, grips, t, self.n, &mut state)
                    .map_err(|err| self.fail_dynamics(err, t, &copy))?;
                let (after, after_grips) = self.decide(held, t, &state)?;
                if after != held || after_grips != self.grips {
                    (still, grips) = (after, after_grips);
                }
            }
        }
        let gone = held.minus(still);
        if !gone.is_empty() {
            let named = gone.iter().next().unwrap_or(0);
            let transition = Transition::Liftoff { named, gone };
            self.apply(transition, t, &state, &state, holding(still), grips)?;
        } else {
            // Only friction states changed: a stick event where contacts stopped slipping and
            // none started, a slip event otherwise.
            let old = self.grips;
            let started = grips.slipping().minus(old.slipping());
            let reversed = grips
                .forward
                .intersection(old.backward)
                .union(grips.backward.intersection(old.forward));
            let stuck = grips.stick.minus(old.stick);
            let (kind, changed) = if started.union(reversed).is_empty() {
                (EventKind::Stick, stuck)
            } else {
                (EventKind::Slip, started.union(reversed).union(stuck))
            };
            if !grips.stick.is_empty() {
                let copy = state.clone();
                contact::project_onto(&self.mech, held, grips, t, self.n, &mut state)
                    .map_err(|err| self.fail_dynamics(err, t, &copy))?;
            }
            let named = changed.iter().next().unwrap_or(0);
            let transition = Transition::Grip {
                kind,
                named,
                changed,
            };
            self.apply(transition, t, &state, &state, holding(still), grips)?;
        }
        self.resume(t, &state, None)?;
        Ok(Next::Continue)
    }

    /// The change at a root where law 1 still sees the old states: the constraint with the
    /// largest margin lets go (without friction, or where that is a normal force), or the
    /// contact whose friction state reached its limit changes it.
    fn forced_change(
        &mut self,
        held: ActiveSet,
        t: f64,
        state: &[f64],
    ) -> Result<(ActiveSet, Grips), Error> {
        let (q, q_dot) = state.split_at(self.n);
        if self.mech.frictional(held) {
            let grips = self.grips;
            let worst = contact::worst_change(&self.mech, held, grips, &self.scales, t, q, q_dot)
                .map_err(|err| self.fail_dynamics(err, t, state))?;
            return Ok(worst);
        }
        let margins = contact::margins(&self.mech, held, t, q, q_dot)
            .map_err(|err| self.fail_dynamics(err, t, state))?;
        let worst = margins
            .iter()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map_or(0, |&(index, _)| index);
        Ok((held.minus(ActiveSet::single(worst)), Grips::none()))
    }

    /// After a restart in the current mode: the lift-off test's margin at the mode's start
    /// (with friction, and the scales of its margins, fixed through the mode).
    pub(super) fn enter_mode(&mut self, t: f64) -> Result<(), Error> {
        let held = self.held();
        if held.is_empty() {
            return Ok(());
        }
        let y = self.y.clone();
        if self.mech.frictional(held) {
            let (q, q_dot) = y.split_at(self.n);
            let scales = contact::scales(&self.mech, held, self.grips, t, q, q_dot)
                .map_err(|err| self.fail_dynamics(err, t, &y))?;
            self.scales = scales;
        }
        self.margin_start = self.margin_of(held, t, &y)?;
        Ok(())
    }

    /// The largest lift margin of the constraints held in `set` at `(t, y)`: positive where one
    /// of them would have to pull ([`contact::margin`]).
    pub(super) fn margin_of(&mut self, set: ActiveSet, t: f64, y: &[f64]) -> Result<f64, Error> {
        let (q, q_dot) = y.split_at(self.n);
        let mut w = std::mem::take(&mut self.w);
        let mut acc = vec![0.0; self.n];
        let (grips, scales) = (self.grips.within(set), &self.scales);
        let margin = contact::margin(
            &self.mech, set, grips, scales, t, q, q_dot, &mut w, &mut acc,
        );
        self.w = w;
        margin.map_err(|err| self.fail_dynamics(err, t, y))
    }
}

/// How many relative tolerances of the margins a held step's second difference of its margins
/// must exceed to bound the next step ([`Runner::lift_trend`]): below, it is the error of the
/// cubic through the step's ends.
const CUBIC_NOISE: f64 = 1e3;

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
