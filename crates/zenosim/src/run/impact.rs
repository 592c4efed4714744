//! Impacts: the generalized Newton law on the constraints reached and those held
//! (docs/contact-laws.md, law 2; for one constraint the paper's map `P`), what holds after it
//! (law 1), and whether the impacts accumulate to a Zeno point (law 3, `completion.rs`).

use super::mode::{holding, Transition};
use super::{Next, Runner};
use crate::contact::{self};
use crate::error::Error;
use crate::execution::{ActiveSet, Grips};
use crate::mechanics::Normal;
use crate::model::HybridLagrangian;
use crate::observer::Observer;
use crate::options::ZenoStrategy;
use crate::zeno::Prediction;

impl<L: HybridLagrangian, O: Observer> Runner<'_, '_, L, O> {
    /// An impact reaching constraint `index` at `t`, on the constraints `contacts` (`index`,
    /// those held, and those reached at the same instant), from the state `before`, whose
    /// normal response on `index` is `normal`; `hint` is the next step's size.
    ///
    /// In turn: the paper's ε rule (`zeno = { epsilon = ε }`) on the state before it; the
    /// impact law; which constraints it leaves held (where it is the first impact of its
    /// sequence: a later one leaves the constraint reached to the Zeno rules); the event; then
    /// the Zeno rules on the sequence it continues, and the flight it starts.
    pub(super) fn impact(
        &mut self,
        index: usize,
        contacts: ActiveSet,
        t: f64,
        before: Vec<f64>,
        normal: Normal,
        hint: f64,
    ) -> Result<Next, Error> {
        let n = self.n;
        let e = self.sim.model.constraints()[index].restitution;
        if let ZenoStrategy::Epsilon(eps) = self.sim.options.zeno {
            // The paper's rule, on the state just before the impact, on every constraint of
            // the accumulation and of the impact that is within ε of its surface (the held
            // ones are on theirs). The crossing is replaced by R∞: it is no impact, and not
            // counted as one.
            let candidates = self.watch.accumulation.constraints().union(contacts);
            let near = self.within_epsilon(candidates, t, &before, eps);
            if near.len() > 1 && near.contains(index) {
                if self.epsilon_met(near, t, &before, eps)? {
                    let p = self.watch.accumulation.predict();
                    return self.switch(index, near, t, before, p);
                }
            } else {
                let h: f64 = self.sim.model.constraint_at(index, t, &before[..n]);
                if h.abs() <= eps && normal.a_q_dot.abs() <= eps {
                    let round_off = (e * normal.a_q_dot_round_off, normal.h_ddot_round_off);
                    let p = Prediction::new(-e * normal.a_q_dot, normal.h_ddot_free, e, round_off);
                    return self.switch(index, ActiveSet::single(index), t, before, p);
                }
            }
        }
        let mut after = before.clone();
        let law = {
            let (q, q_dot) = after.split_at_mut(n);
            let constraints = self.sim.model.constraints();
            contact::impact_law(&self.mech, contacts, &normal, constraints, t, q, q_dot)
        };
        let law = law.map_err(|(err, _)| self.fail_dynamics(err, t, &before))?;
        // The loss and the work of the impact, from its law (`work.rs`).
        self.record.jump = Some((law.loss, law.work));
        // The first impact of a sequence that leaves its constraints at rest (plastic, or at
        // the rounding of ḣ) is an impact into the motion held on them, where law 1 holds
        // them: no sequence has accumulated, so no Zeno point. A later impact of a sequence
        // leaves the constraint reached to the Zeno rules below.
        let settled = if self.watch.first_on(index) {
            contacts
        } else {
            contacts.minus(ActiveSet::single(index))
        };
        let (held, grips) = self.settle(settled, t, &mut after)?;
        let transition = Transition::Impact {
            reached: index,
            contacts,
            impulses: law.impulses,
            tangential: law.tangential,
        };
        self.apply(transition, t, &before, &after, holding(held), grips)?;
        let alone = self.watch.accumulation.constraints() == ActiveSet::single(index);
        if held.contains(index) && alone {
            // Closed by the impact: nothing bounces, nothing accumulates.
            self.resume(t, &after, Some(hint))?;
            return Ok(Next::Continue);
        }
        self.after_impact(index, contacts, t, after, hint)
    }

    /// The constraints of `closed` that the impact left at rest (`|ḣ|` within its rounding)
    /// and that law 1 holds at `(t, y)`, with the friction states of those with friction; `y`
    /// is put onto them.
    pub(super) fn settle(
        &mut self,
        closed: ActiveSet,
        t: f64,
        y: &mut [f64],
    ) -> Result<(ActiveSet, Grips), Error> {
        let (q, q_dot) = y.split_at(self.n);
        let mut at_rest = ActiveSet::empty();
        for index in closed.iter() {
            let normal = self.normal(index, t, q, q_dot)?;
            if normal.a_q_dot.abs() <= normal.a_q_dot_round_off {
                at_rest = at_rest.with(index);
            }
        }
        let (held, grips) = self.decide(at_rest, t, y)?;
        if held.is_empty() {
            return Ok((held, grips));
        }
        let state = y.to_vec();
        contact::project_onto(&self.mech, held, grips, t, self.n, y)
            .map_err(|err| self.fail_dynamics(err, t, &state))?;
        Ok((held, grips))
    }

    /// The constraints of `closed` that hold at `(t, y)`, and the friction states of those
    /// with friction (docs/contact-laws.md, law 1; docs/friction.md).
    pub(super) fn decide(
        &mut self,
        closed: ActiveSet,
        t: f64,
        y: &[f64],
    ) -> Result<(ActiveSet, Grips), Error> {
        let (q, q_dot) = y.split_at(self.n);
        let mut w = std::mem::take(&mut self.w);
        let decided = contact::decide(&self.mech, closed, t, q, q_dot, &mut w);
        self.w = w;
        decided.map_err(|(err, _)| self.fail_dynamics(err, t, y))
    }
}
