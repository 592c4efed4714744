//! Adaptive explicit Runge–Kutta integrators with dense output.
//!
//! Two embedded pairs are provided, both by Dormand and Prince, following
//! Hairer, Nørsett & Wanner, *Solving Ordinary Differential Equations I*,
//! 2nd ed., Springer 1993, sections II.4 (step-size control and the initial
//! step-size algorithm), II.5 (the embedded pairs) and II.6 (dense output):
//!
//! * [`Method::Dop853`] (the default): the 12-stage 8th-order method with the
//!   combined 5th/3rd-order error estimator of Hairer's code DOP853 and its
//!   7th-order continuous extension, which costs 3 extra right-hand-side
//!   evaluations per step (done lazily by [`Stepper::prepare_dense`]).
//! * [`Method::Dopri5`]: the 7-stage FSAL 5(4) pair with Shampine's
//!   4th-order continuous extension, which needs no extra evaluations.
//!
//! The [`Stepper`] is a low-level "one accepted step at a time" driver: it owns
//! all work buffers (allocated once in [`Stepper::new`]), never steps past the
//! requested stopping time and exposes the last accepted step (both end
//! points, their derivatives and its continuous extension), which is what an
//! event-locating simulator needs.
//!
//! Where the caller knows the solution over a step in closed form, a polynomial of degree at
//! most 3 in `t` (a body in free fall), [`Stepper::step_exact`] takes the step the integrator
//! would try with that closed form: one evaluation (at its end, which the caller checks the
//! closed form against) instead of the step's stages (twelve for DOP853, six for DOPRI5), and
//! the cubic Hermite interpolant, exact there, as its continuous extension.
//!
//! # Step-size control (II.4)
//!
//! With `sc_i = atol + rtol * max(|y_old_i|, |y_new_i|)` the error is the RMS
//! norm of `err_i / sc_i`. A trial step is accepted when that norm is `<= 1`.
//! The new step is `h * fac` with `fac = 0.9 * err^(-1/(q+1))`, where `q` is
//! the order of the error estimate (`q + 1 = 8` for DOP853, whose 5th/3rd-order
//! estimator `err5^2 / sqrt(err5^2 + 0.01 err3^2)` behaves like `h^8`, and
//! `q + 1 = 5` for DOPRI5). `fac` is clamped to `[1/3, 6]` for DOP853 and
//! `[1/5, 10]` for DOPRI5 (the defaults of Hairer's codes), and is at most 1
//! for the step accepted right after a rejection. After a step that followed
//! another at the size it tried, `fac` is also at most Gustafsson's predictive
//! ratio (HNW II, IV.8, as in RADAU5), which extrapolates the error's growth
//! from the two steps: where the solution's derivatives grow step after step,
//! the plain ratio overshoots again and again.
//!
//! Two refinements concern the step *size proposal* only: a step shortened to
//! land on `t_stop` or to respect `h_max`, and accepted without rejection with
//! `fac >= 1`, does not lower the proposal below the one it was shortened
//! from; and a trial in which the right-hand side fails or produces non-finite
//! values is rejected with `h *= 0.25`.
//!
//! The first step is the caller's hint or Hairer's `hinit` (II.4, "Starting
//! step size"). A step is a *step-size underflow* when it is smaller than
//! `16 * EPSILON * max(|t|, h0)` without landing on `t_stop`, `h0` the first step size (of the
//! last start or rewind): a floor relative to the time and to the problem's own time scale,
//! never to a unit of time.

#![warn(missing_docs)]

mod control;
mod dop853;
mod dop853_tableau;
mod dopri5;
mod kernels;
mod output;
mod stepper;

#[cfg(test)]
mod tests_accuracy;
#[cfg(test)]
mod tests_control;
#[cfg(test)]
mod tests_order;
#[cfg(test)]
mod tests_support;

pub use stepper::Stepper;

/// A first-order system `y' = f(t, y)`.
pub trait OdeSystem {
    /// Error returned by a failed right-hand-side evaluation.
    type Error;
    /// Number of components of `y`.
    fn dimension(&self) -> usize;
    /// Writes `f(t, y)` into `dy` (both of length [`OdeSystem::dimension`]).
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Self::Error>;

    /// [`OdeSystem::rhs`] at the end of a trial step, where the next step starts if the trial
    /// is accepted: of the calls during a [`Stepper::step`] that returns `Ok`, the last one of
    /// these is at the step's end (`t()`, `y()`); [`Stepper::step_exact`] makes only this one.
    /// The default calls `rhs`; a system may compute more there, for use after the step.
    fn rhs_at_end(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Self::Error> {
        self.rhs(t, y, dy)
    }

    /// Corrects the end `y` of a Runge–Kutta trial step at `t` that passed its error test (the
    /// error is the uncorrected end's), before [`OdeSystem::rhs_at_end`] evaluates it at the
    /// step's end: a system whose solutions keep to a manifold puts the end back on it, so that
    /// the next step starts there and the step's dense output ends there. Returns whether it
    /// changed `y` (DOPRI5, whose error estimate takes `f` at the uncorrected end, then
    /// evaluates `f` once more). An error, or a corrected end that is not finite, fails the
    /// trial as a failed evaluation does. A step in closed form ([`Stepper::step_exact`]) is
    /// not corrected. The default leaves `y` as it is.
    fn correct_end(&mut self, _t: f64, _y: &mut [f64]) -> Result<bool, Self::Error> {
        Ok(false)
    }
}

/// The Runge–Kutta pair used by a [`Stepper`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Method {
    /// Dormand–Prince 8(5,3) with 7th-order dense output (Hairer's DOP853).
    #[default]
    Dop853,
    /// Dormand–Prince 5(4), FSAL, with 4th-order dense output (Hairer's DOPRI5).
    Dopri5,
}

impl Method {
    /// Classical order of the propagated solution (8 or 5).
    pub fn order(self) -> u32 {
        match self {
            Method::Dop853 => 8,
            Method::Dopri5 => 5,
        }
    }

    /// Order of the continuous extension (7 or 4).
    pub fn dense_order(self) -> u32 {
        match self {
            Method::Dop853 => 7,
            Method::Dopri5 => 4,
        }
    }
}

/// Scalar relative and absolute tolerances of the local error control.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// Relative tolerance (non-negative).
    pub rtol: f64,
    /// Absolute tolerance (positive, so that the error weights never vanish).
    pub atol: f64,
}

impl Default for Tolerances {
    /// `rtol = atol = 1e-10`.
    fn default() -> Self {
        Self {
            rtol: 1e-10,
            atol: 1e-10,
        }
    }
}

/// Cumulative work counters of a [`Stepper`] (kept across restarts).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected trial steps (error too large, failed or non-finite evaluation).
    pub rejected_steps: u64,
    /// Calls of [`OdeSystem::rhs`], whatever their result.
    pub rhs_evals: u64,
}

/// Failure of a [`Stepper`] operation.
///
/// It implements [`std::error::Error`] whenever `E` does (with `E` as source).
#[derive(Debug, thiserror::Error)]
pub enum StepError<E> {
    /// The right-hand side failed at an accepted state, or kept failing while
    /// the step shrank to underflow; `t` is the time of the state stepped from.
    #[error("right-hand side evaluation failed at t = {t}")]
    Rhs {
        /// Time of the accepted state from which the failing evaluation was made.
        t: f64,
        /// The error returned by [`OdeSystem::rhs`].
        #[source]
        source: E,
    },
    /// The step size fell below `16 * EPSILON * max(|t|, h0)`, `h0` the first step size.
    #[error("step size underflow at t = {t} (h = {h})")]
    StepSizeUnderflow {
        /// Time of the state stepped from.
        t: f64,
        /// The step size that was too small.
        h: f64,
    },
    /// Non-finite values (the state, its derivative or the error estimate)
    /// persisted until step-size underflow, or appeared at an accepted state.
    #[error("non-finite values at t = {t}")]
    NonFinite {
        /// Time of the state stepped from.
        t: f64,
    },
}
