//! The equations of motion of one mode, as the integrator sees them.

use crate::contact::{self};
use crate::execution::{ActiveSet, Grips};
use crate::integrator::OdeSystem;
use crate::mechanics::{DynamicsError, Mechanics, Normal};
use crate::model::HybridLagrangian;

/// The equations of motion of one mode, as the integrator sees them: `y = (q, q̇)`, free or
/// held on a set of constraints (docs/contact-laws.md, law 1).
pub(super) struct Equations<'a, L> {
    pub(super) mech: Mechanics<'a, L>,
    /// The constraints held (empty in free flight).
    held: ActiveSet,
    /// Free (`None`) or held on one constraint: the mechanics' own right-hand side, inlined
    /// into the stages. Held on two or more, `contact::held_acceleration` (`None` too).
    single: Option<usize>,
    /// Whether the motion is held on two or more constraints, or on any with friction.
    several: bool,
    /// The friction states of the held contacts.
    grips: Grips,
    pub(super) n: usize,
    /// The held constraint's normal response at the end of the last trial step, and its
    /// time, where one constraint is held: after an accepted step, at the step's end
    /// ([`OdeSystem::rhs_at_end`]).
    pub(super) end: Option<(f64, Normal)>,
}

impl<'a, L: HybridLagrangian> Equations<'a, L> {
    pub(super) fn new(mech: Mechanics<'a, L>, held: ActiveSet, grips: Grips, n: usize) -> Self {
        let frictional = mech.frictional(held);
        Self {
            mech,
            held,
            single: held.only().filter(|_| !frictional),
            several: held.len() >= 2 || frictional,
            grips,
            n,
            end: None,
        }
    }

    /// The right-hand side held on two or more constraints, or on any with friction.
    #[inline(never)]
    fn rhs_on_set(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), DynamicsError> {
        let (q, q_dot) = y.split_at(self.n);
        dy[..self.n].copy_from_slice(q_dot);
        let q_ddot = &mut dy[self.n..];
        contact::acceleration(&self.mech, self.held, self.grips, t, q, q_dot, q_ddot)
    }
}

impl<L: HybridLagrangian> OdeSystem for Equations<'_, L> {
    type Error = DynamicsError;

    fn dimension(&self) -> usize {
        2 * self.n
    }

    /// Free or on one constraint, the mechanics' right-hand side, inlined into the stages;
    /// on two or more, [`Equations::rhs_on_set`], kept out of line so that it does not stop
    /// that.
    #[inline(always)]
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), DynamicsError> {
        if self.several {
            self.rhs_on_set(t, y, dy)
        } else {
            self.mech
                .state_derivative(t, y, self.single, dy)
                .map(|_| ())
        }
    }

    /// On one constraint, the acceleration and the normal response from one evaluation of the
    /// motion: the lift-off test after the step needs the response at its end.
    fn rhs_at_end(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), DynamicsError> {
        self.end = None;
        let Some(index) = self.single else {
            return self.rhs(t, y, dy);
        };
        let (q, q_dot) = y.split_at(self.n);
        dy[..self.n].copy_from_slice(q_dot);
        let normal =
            self.mech
                .held_acceleration_and_normal(index, t, q, q_dot, &mut dy[self.n..])?;
        self.end = Some((t, normal));
        Ok(())
    }

    /// Held, the drift of the step's end put back: `h = 0`, `ḣ = 0` on every held constraint
    /// ([`contact::project_onto`]). The next step starts there, and the step's dense output
    /// ends there.
    fn correct_end(&mut self, t: f64, y: &mut [f64]) -> Result<bool, DynamicsError> {
        if self.held.is_empty() {
            return Ok(false);
        }
        contact::project_onto(&self.mech, self.held, self.grips, t, self.n, y).map(|()| true)
    }
}
