//! Impacts: the paper's map `P` on one constraint, the generalized Newton law on a set
//! (docs/contact-laws.md, law 2), and which constraints hold after it (law 1).

use super::equations::project_onto;
use super::{Next, Runner, AUTO_ROUND_OFF_ULPS, OFF_ROUND_OFF_ULPS};
use crate::contact::Contacts;
use crate::error::Error;
use crate::execution::{ActiveSet, EventKind, Mode};
use crate::mechanics::Normal;
use crate::model::HybridLagrangian;
use crate::observer::Observer;
use crate::options::ZenoStrategy;
use crate::zeno::Prediction;

impl<L: HybridLagrangian, O: Observer> Runner<'_, '_, L, O> {
    pub(super) fn impact(
        &mut self,
        index: usize,
        t: f64,
        before: Vec<f64>,
        normal: Normal,
        hint: f64,
    ) -> Result<Next, Error> {
        let e = self.sim.model.constraints()[index].restitution;
        let h: f64 = self.sim.model.constraint_at(index, t, &before[..self.n]);
        if let ZenoStrategy::Epsilon(eps) = self.sim.options.zeno {
            // The paper's rule, on the state just before the impact.
            // The crossing is replaced by R∞: it is no impact, and not counted as one.
            let candidates = self.accumulation.constraints().with(index);
            let near = self.within_epsilon(candidates, t, &before, eps);
            if near.len() > 1 && near.contains(index) {
                // An accumulation over several constraints: the rule on all of them that are
                // within ε of their surfaces.
                if self.epsilon_met(near, t, &before, eps)? {
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
                .impact(index, e, t, q, q_dot)
                .map_err(|err| self.fail_dynamics(err, t, &before))?;
        }
        // Pushing, so not below 0 (at rest, `A q̇` may round to either side of it).
        let impulse = -(1.0 + e) * normal.a_q_dot / normal.s;
        let impulse = if impulse > 0.0 { impulse } else { 0.0 };
        // The law's own normal velocity after it: ḣ⁺ = ḣ⁻ + s Λ.
        let h_dot_after = normal.a_q_dot + normal.s * impulse;
        self.impact_jump(&[impulse], &[normal.a_q_dot], &[h_dot_after], &[normal.h_t]);
        let contacts = ActiveSet::single(index);
        // The first impact of a sequence that leaves the contact at rest (plastic, or at the
        // rounding of ḣ) is an impact into the motion held on it, where law 1 holds it: no
        // sequence has accumulated, so no Zeno point.
        let first = self.sequence.count() == 0 || self.sequence.constraint() != Some(index);
        let mode = if first {
            self.settle(contacts, t, &mut after)?
        } else {
            Mode::Free
        };
        let change = (contacts, vec![impulse]);
        self.record_event(EventKind::Impact, index, change, t, &before, &after, mode)?;
        self.impacts += 1;
        self.sequence.record(index, t);
        self.accumulation.record(index, t);
        if mode != Mode::Free {
            self.restart(t, &after, Some(hint))?;
            self.enter_mode(t)?;
            return Ok(Next::Continue);
        }
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

    /// An impact reaching constraint `index` at `t` with the other constraints of `set` closed
    /// (docs/contact-laws.md, law 2): the impulses solve the generalized Newton law on the whole
    /// set; then law 1 decides which of the constraints left at rest hold.
    pub(super) fn impact_set(
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
            let near = self.within_epsilon(accumulating.union(set), t, &before, eps);
            if near.contains(index) && self.epsilon_met(near, t, &before, eps)? {
                let p = self.accumulation.predict();
                return self.switch_set(index, near, t, before, p);
            }
        }
        let restitution: Vec<f64> = set
            .iter()
            .map(|i| self.sim.model.constraints()[i].restitution)
            .collect();
        let (q, q_dot) = before.split_at(n);
        let contacts = Contacts::at(&self.mech, set, t, q, q_dot)
            .map_err(|(err, _)| self.fail_dynamics(err, t, &before))?;
        let mut after = before.clone();
        let impulses = contacts
            .impact(&restitution, &mut after[n..])
            .map_err(|err| self.fail_dynamics(err, t, &before))?;
        // The law's own normal velocities after it: ḣ⁺ = ḣ⁻ + W Λ.
        let k = contacts.len();
        let h_dot_before: Vec<f64> = contacts.normals.iter().map(|c| c.a_q_dot).collect();
        let h_t: Vec<f64> = contacts.normals.iter().map(|c| c.h_t).collect();
        let h_dot_after: Vec<f64> = (0..k)
            .map(|i| {
                let row = &contacts.delassus[i * k..(i + 1) * k];
                h_dot_before[i] + row.iter().zip(&impulses).map(|(w, l)| w * l).sum::<f64>()
            })
            .collect();
        self.impact_jump(&impulses, &h_dot_before, &h_dot_after, &h_t);
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
    /// (`|ḣ|` within rounding) are closed, and law 1 picks those that hold; `y` is put onto
    /// them.
    pub(super) fn settle(&mut self, set: ActiveSet, t: f64, y: &mut [f64]) -> Result<Mode, Error> {
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
        project_onto(&self.mech, held, t, self.n, y)
            .map_err(|err| self.fail_dynamics(err, t, &state))?;
        Ok(Mode::Constrained(held))
    }

    /// The constraints of `closed` that hold at `(t, y)` (docs/contact-laws.md, law 1).
    pub(super) fn held_of(
        &mut self,
        closed: ActiveSet,
        t: f64,
        y: &[f64],
    ) -> Result<ActiveSet, Error> {
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
        let contacts = Contacts::at(&self.mech, closed, t, q, q_dot)
            .map_err(|(err, _)| self.fail_dynamics(err, t, y))?;
        contacts
            .held_set()
            .map_err(|err| self.fail_dynamics(err, t, y))
    }
}
