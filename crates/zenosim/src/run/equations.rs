//! The equations of motion of one mode, as the integrator sees them.

use crate::contact::{self};
use crate::execution::ActiveSet;
use crate::integrator::OdeSystem;
use crate::mechanics::{DynamicsError, Mechanics, Normal};
use crate::model::HybridLagrangian;

/// The equations of motion of one mode, as the integrator sees them: `y = (q, q̇)`.
pub(super) struct Equations<'a, L> {
    pub(super) mech: Mechanics<'a, L>,
    /// The constraint held, where exactly one is.
    pub(super) active: Option<usize>,
    /// The constraints held, where two or more are (else empty).
    pub(super) set: ActiveSet,
    pub(super) n: usize,
    /// The active constraint's normal response at the end of the last trial step, and its
    /// time: after an accepted step, at the step's end ([`OdeSystem::rhs_at_end`]).
    pub(super) end: Option<(f64, Normal)>,
}

impl<L: HybridLagrangian> Equations<'_, L> {
    /// The right-hand side held on two or more constraints (docs/contact-laws.md, law 1).
    #[inline(never)]
    fn rhs_on_set(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), DynamicsError> {
        let (q, q_dot) = y.split_at(self.n);
        dy[..self.n].copy_from_slice(q_dot);
        contact::held_acceleration(&self.mech, self.set, t, q, q_dot, &mut dy[self.n..]).map(|_| ())
    }
}

impl<L: HybridLagrangian> OdeSystem for Equations<'_, L> {
    type Error = DynamicsError;

    fn dimension(&self) -> usize {
        2 * self.n
    }

    /// Free or on one constraint, the mechanics' right-hand side, inlined into the stages;
    /// on a set, [`Equations::rhs_on_set`], kept out of line so that it does not stop that.
    #[inline(always)]
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), DynamicsError> {
        if self.set.is_empty() {
            self.mech
                .state_derivative(t, y, self.active, dy)
                .map(|_| ())
        } else {
            self.rhs_on_set(t, y, dy)
        }
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
        let normal =
            self.mech
                .held_acceleration_and_normal(index, t, q, q_dot, &mut dy[self.n..])?;
        self.end = Some((t, normal));
        Ok(())
    }

    /// On a constraint, the drift of the step's end put back: `h = 0`, `ḣ = 0`
    /// ([`Mechanics::project`]). The next step starts there, and the step's dense output ends
    /// there.
    fn correct_end(&mut self, t: f64, y: &mut [f64]) -> Result<bool, DynamicsError> {
        let (q, q_dot) = y.split_at_mut(self.n);
        match self.active {
            Some(index) => self.mech.project(index, t, q, q_dot).map(|_| true),
            None if self.set.is_empty() => Ok(false),
            None => contact::project(&self.mech, self.set, t, q, q_dot).map(|_| true),
        }
    }
}

/// `R∞` onto the constraints of `set` at `y = (q, q̇)` (nothing where the set is empty): the
/// single-constraint projection for one, the projection onto the set for several.
pub(super) fn project_onto<L: HybridLagrangian>(
    mech: &Mechanics<'_, L>,
    set: ActiveSet,
    t: f64,
    n: usize,
    y: &mut [f64],
) -> Result<(), DynamicsError> {
    let (q, q_dot) = y.split_at_mut(n);
    match set.only() {
        _ if set.is_empty() => Ok(()),
        Some(index) => mech.project(index, t, q, q_dot).map(|_| ()),
        None => contact::project(mech, set, t, q, q_dot),
    }
}
