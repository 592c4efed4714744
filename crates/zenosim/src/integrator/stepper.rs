//! The [`Stepper`]: state, step loop with error control, dense-output dispatch.

use super::control::{
    hinit, underflow_threshold, Control, EvalFailure, Trial, FAILURE_SHRINK, INITIAL_ERR_PREVIOUS,
};
use super::kernels::{all_finite, eval, eval_end};
use super::{dop853, dopri5, Method, OdeSystem, Stats, StepError, Tolerances};

/// Method-specific work buffers (one per stepper, so the size difference of
/// the variants does not matter and boxing would only add an indirection).
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub(super) enum Work {
    Dop853(dop853::Work),
    Dopri5(dopri5::Work),
}

/// State of the continuous extension of the last accepted step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Dense {
    /// Prepared (or the "last step" has length zero after a (re)start).
    Ready,
    /// The step's stages are intact; `prepare_dense` can build it.
    Pending,
    /// The stages were overwritten by the trials of a failed `step`.
    Lost,
    /// The last step was [`Stepper::step_exact`]: its extension is the cubic Hermite
    /// interpolant through its ends, exact there, with nothing to prepare.
    Cubic,
}

/// The next step's size after an accepted one of size `h_abs` with step ratio `fac`: a step
/// that `t_stop` or `h_max` shortened below the `proposal` it was tried from keeps that
/// proposal where it was easy (accepted at once, `fac ≥ 1`).
fn next_size(h_abs: f64, fac: f64, proposal: f64, rejected: bool) -> f64 {
    let h_new = h_abs * fac;
    let kept = if !rejected && h_abs < proposal && fac >= 1.0 {
        h_new.max(proposal)
    } else {
        h_new
    };
    kept.min(f64::MAX)
}

/// Adaptive explicit Runge–Kutta stepper with dense output (HNW I, II.4–II.6).
///
/// Owns every work buffer (allocated only in [`Stepper::new`]). Use:
/// [`start`](Stepper::start), then repeatedly [`step`](Stepper::step) (or
/// [`step_exact`](Stepper::step_exact) along a closed form); the last
/// accepted step is `[t_previous(), t()]`, and after
/// [`prepare_dense`](Stepper::prepare_dense) it can be evaluated anywhere in
/// between with [`interpolate`](Stepper::interpolate). Integration backwards in
/// time works by passing a `t_stop < t()`.
#[derive(Clone, Debug)]
pub struct Stepper {
    pub(super) method: Method,
    pub(super) control: Control,
    pub(super) tol: Tolerances,
    pub(super) work: Work,
    pub(super) started: bool,
    pub(super) dense: Dense,
    pub(super) t: f64,
    pub(super) t_prev: f64,
    /// Signed size of the last accepted step (0 after a (re)start).
    pub(super) h_last: f64,
    /// Proposed magnitude of the next step.
    pub(super) h_next: f64,
    /// The step size the stepper was last started or rewound with: the time scale of the
    /// step-size underflow test ([`underflow_threshold`]).
    pub(super) time_scale: f64,
    /// The error norm of the last accepted step (Hairer's `facold`), for the PI controller.
    pub(super) err_previous: f64,
    /// The size and error norm of the last step accepted by [`Stepper::step`] at the size it
    /// tried (none after a start, a rewind, an exact step or a step cut short to land on
    /// `t_stop` or by `h_max`): the history of the predictive controller
    /// ([`Control::predictive_factor`]).
    accepted: Option<(f64, f64)>,
    pub(super) y: Vec<f64>,
    pub(super) dy: Vec<f64>,
    pub(super) y_prev: Vec<f64>,
    pub(super) dy_prev: Vec<f64>,
    pub(super) y_new: Vec<f64>,
    /// End state of the last accepted step once `replace_state` replaced `y`.
    pub(super) y_end: Vec<f64>,
    /// Its derivative, once `replace_state` replaced `dy` (for the cubic interpolant).
    pub(super) dy_end: Vec<f64>,
    /// Whether `y_end` (rather than `y`) holds the end of the last step.
    pub(super) end_replaced: bool,
    pub(super) scratch: Vec<f64>,
    pub(super) stats: Stats,
}

impl Stepper {
    /// Allocates a stepper for systems of the given dimension.
    ///
    /// # Panics
    /// If `dimension == 0`, `atol` is not positive, or a tolerance is not
    /// finite or negative.
    pub fn new(method: Method, dimension: usize, tolerances: Tolerances) -> Self {
        let Tolerances { rtol, atol } = tolerances;
        assert!(dimension > 0, "Stepper::new: dimension must be positive");
        assert!(
            rtol.is_finite() && atol.is_finite() && rtol >= 0.0 && atol > 0.0,
            "Stepper::new: invalid tolerances {tolerances:?}"
        );
        let n = dimension;
        let work = match method {
            Method::Dop853 => Work::Dop853(dop853::Work::new(n)),
            Method::Dopri5 => Work::Dopri5(dopri5::Work::new(n)),
        };
        Self {
            method,
            control: Control::for_method(method),
            tol: tolerances,
            work,
            started: false,
            dense: Dense::Ready,
            t: 0.0,
            t_prev: 0.0,
            h_last: 0.0,
            h_next: 0.0,
            time_scale: 1.0,
            err_previous: INITIAL_ERR_PREVIOUS,
            accepted: None,
            y: vec![0.0; n],
            dy: vec![0.0; n],
            y_prev: vec![0.0; n],
            dy_prev: vec![0.0; n],
            y_new: vec![0.0; n],
            y_end: vec![0.0; n],
            dy_end: vec![0.0; n],
            end_replaced: false,
            scratch: vec![0.0; n],
            stats: Stats::default(),
        }
    }

    /// (Re)start at (t, y): evaluates f(t, y); the first step is `h_hint` if given, else chosen by hinit. Keeps the statistics.
    ///
    /// A hint that is zero or not finite is ignored; only its magnitude is used.
    /// `hinit` (HNW I, II.4) probes forward in time and costs one more
    /// evaluation; if that probe fails, its first guess is used. Afterwards
    /// `t_previous() == t()` and the "last step" has length zero.
    ///
    /// On error the stepper is not started (a new `start` is needed).
    ///
    /// # Panics
    /// If `y.len()` or `sys.dimension()` differs from the stepper's dimension,
    /// or `t` is not finite.
    pub fn start<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
        h_hint: Option<f64>,
    ) -> Result<(), StepError<S::Error>> {
        assert_eq!(y.len(), self.y.len(), "Stepper::start: wrong state length");
        assert_eq!(
            sys.dimension(),
            self.y.len(),
            "Stepper::start: wrong system dimension"
        );
        assert!(t.is_finite(), "Stepper::start: t must be finite");
        self.started = false;
        self.t = t;
        self.y.copy_from_slice(y);
        eval(sys, &mut self.stats, t, &self.y, &mut self.dy)
            .map_err(|source| StepError::Rhs { t, source })?;
        if !all_finite(&self.y) || !all_finite(&self.dy) {
            return Err(StepError::NonFinite { t });
        }
        self.err_previous = INITIAL_ERR_PREVIOUS;
        self.h_next = match h_hint {
            Some(h) if h.is_finite() && h != 0.0 => h.abs(),
            _ => hinit(
                sys,
                &mut self.stats,
                &self.control,
                self.tol,
                t,
                &self.y,
                &self.dy,
                &mut self.y_new,
                &mut self.scratch,
            ),
        };
        self.time_scale = self.h_next;
        self.restart_here();
        self.started = true;
        Ok(())
    }

    /// Restarts at the start of the last accepted step, `(t_previous(), y_previous())`, with
    /// the next step size `h`: the same as [`Stepper::start`] there with the hint `h`, without
    /// evaluating `f` again (its value there is known).
    ///
    /// # Panics
    /// If the stepper was not started, or `h` is not positive and finite.
    pub fn rewind(&mut self, h: f64) {
        assert!(self.started, "Stepper::rewind before a successful start");
        assert!(
            h.is_finite() && h > 0.0,
            "Stepper::rewind: h must be positive and finite"
        );
        self.t = self.t_prev;
        self.y.copy_from_slice(&self.y_prev);
        self.dy.copy_from_slice(&self.dy_prev);
        self.err_previous = INITIAL_ERR_PREVIOUS;
        self.h_next = h;
        self.time_scale = h;
        self.restart_here();
    }

    /// Replace the current state (same t) after an external projection; re-evaluates f; keeps the step size.
    ///
    /// The last accepted step is kept as computed: `t_previous()`,
    /// `y_previous()` and its continuous extension (also if it is prepared
    /// only afterwards) still describe the step ending at the state before the
    /// replacement; the next step starts from the new state. On error the
    /// stepper is left unchanged.
    ///
    /// # Panics
    /// If the stepper was not started or `y` has the wrong length.
    pub fn replace_state<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        y: &[f64],
    ) -> Result<(), StepError<S::Error>> {
        assert!(
            self.started,
            "Stepper::replace_state before a successful start"
        );
        assert_eq!(
            y.len(),
            self.y.len(),
            "Stepper::replace_state: wrong state length"
        );
        let t = self.t;
        self.y_new.copy_from_slice(y);
        eval(sys, &mut self.stats, t, &self.y_new, &mut self.scratch)
            .map_err(|source| StepError::Rhs { t, source })?;
        if !all_finite(&self.y_new) || !all_finite(&self.scratch) {
            return Err(StepError::NonFinite { t });
        }
        let first = !self.end_replaced;
        if first {
            std::mem::swap(&mut self.y_end, &mut self.y);
            self.end_replaced = true;
        }
        std::mem::swap(&mut self.y, &mut self.y_new);
        std::mem::swap(&mut self.dy, &mut self.scratch);
        if first {
            // The step's own end derivative, now in `scratch`, for its cubic interpolant.
            std::mem::swap(&mut self.dy_end, &mut self.scratch);
        }
        Ok(())
    }

    /// Take one accepted step of size at most h_max that never goes past t_stop (lands exactly on t_stop when it would pass it).
    /// Rejected trials are retried internally. A rhs error or non-finite values during a trial count as a rejection (h *= 0.25);
    /// the error is returned only when h underflows (see the module documentation).
    ///
    /// The direction of integration is the sign of `t_stop - t()`; `t_stop`
    /// may be infinite, and `t_stop == t()` is a no-op. A step within 1% of the
    /// remaining distance (and not longer than `h_max`) is stretched to land on
    /// `t_stop`. The landing step itself is exempt from the underflow test, so
    /// a `t_stop` arbitrarily close to `t()` can be reached. On error the
    /// state is unchanged (the continuous extension of the previous step
    /// survives only if it had been prepared).
    ///
    /// # Panics
    /// If the stepper was not started, `h_max` is not positive, or `t_stop` is NaN.
    pub fn step<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t_stop: f64,
        h_max: f64,
    ) -> Result<(), StepError<S::Error>> {
        assert!(self.started, "Stepper::step before a successful start");
        assert!(h_max > 0.0, "Stepper::step: h_max must be positive");
        assert!(!t_stop.is_nan(), "Stepper::step: t_stop is NaN");
        debug_assert_eq!(sys.dimension(), self.y.len());
        let span = t_stop - self.t;
        if span == 0.0 {
            return Ok(());
        }
        let dir = span.signum();
        if self.dense == Dense::Pending {
            self.dense = Dense::Lost;
        }
        match &mut self.work {
            Work::Dop853(w) => w.k[0].copy_from_slice(&self.dy),
            Work::Dopri5(w) => w.k[0].copy_from_slice(&self.dy),
        }
        let proposal = self.h_next;
        let mut h = proposal.min(h_max);
        let mut rejected = false;
        let mut last_failure = None;
        loop {
            let (h_abs, t_end, landing) = self.trial_span(h, t_stop, h_max);
            if !landing && h_abs < underflow_threshold(self.t, self.time_scale) {
                let t = self.t;
                return Err(match last_failure {
                    Some(EvalFailure::Rhs(source)) => StepError::Rhs { t, source },
                    Some(EvalFailure::NonFinite) => StepError::NonFinite { t },
                    None => StepError::StepSizeUnderflow { t, h: h_abs },
                });
            }
            let hs = dir * h_abs;
            let (t, tol, y, y_new) = (self.t, self.tol, &self.y[..], &mut self.y_new[..]);
            let stats = &mut self.stats;
            let outcome = match &mut self.work {
                Work::Dop853(w) => dop853::trial(w, sys, stats, tol, t, hs, t_end, y, y_new),
                Work::Dopri5(w) => dopri5::trial(w, sys, stats, tol, t, hs, t_end, y, y_new),
            };
            match outcome {
                Trial::Accepted(err) => {
                    let mut fac = self.control.accept_factor(err, self.err_previous);
                    // A step cut short (landing on `t_stop`, or by `h_max`) has an error that
                    // says nothing of the error's growth: no prediction from it, nor after it.
                    let cut = h_abs < h;
                    if let (false, Some((h_before, err_before))) = (cut, self.accepted) {
                        let predicted = self
                            .control
                            .predictive_factor(err, h_abs, err_before, h_before);
                        fac = fac.min(predicted);
                    }
                    self.accepted = (!cut).then_some((h_abs, err));
                    self.err_previous = err.max(INITIAL_ERR_PREVIOUS);
                    if rejected {
                        fac = fac.min(1.0);
                    }
                    self.accept(t_end, hs, next_size(h_abs, fac, proposal, rejected));
                    return Ok(());
                }
                Trial::Rejected(err) => {
                    h = h_abs * self.control.reject_factor(err);
                    last_failure = None;
                }
                Trial::Failed(failure) => {
                    h = h_abs * FAILURE_SHRINK;
                    last_failure = Some(failure);
                }
            }
            self.stats.rejected_steps += 1;
            rejected = true;
        }
    }

    /// Takes one step along a solution known in closed form over it, a polynomial of degree at
    /// most 3 in `t` (a body in free fall under a constant force): `advance(y, dy, h, y_new)`
    /// writes the state a signed time `h` after the current one `(y, dy = f(t, y))`, and
    /// `holds(dy, dy_new)` says, from `f` at both ends, whether the closed form holds over the
    /// step. Returns whether the step was taken: where `holds` says no (or the step would be a
    /// step-size underflow), the stepper is unchanged (its step-size control and the last
    /// step's extension too), and [`Stepper::step`] is the way on.
    ///
    /// The step's size is the one [`Stepper::step`] would try first (at most `h_max`, landing
    /// on `t_stop`), and the next one grows as after a step of zero error. It costs one
    /// evaluation, `f` at the new state ([`OdeSystem::rhs_at_end`]), and has no error estimate
    /// (the closed form is the caller's to vouch for). Its continuous extension is
    /// the cubic Hermite interpolant ([`interpolate_cubic`](Stepper::interpolate_cubic), also
    /// what [`interpolate`](Stepper::interpolate) gives, with nothing to prepare). On error
    /// (`f` fails or is not finite at the new state) the stepper is unchanged.
    ///
    /// # Panics
    /// As [`Stepper::step`].
    pub fn step_exact<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t_stop: f64,
        h_max: f64,
        advance: impl FnOnce(&[f64], &[f64], f64, &mut [f64]),
        holds: impl FnOnce(&[f64], &[f64]) -> bool,
    ) -> Result<bool, StepError<S::Error>> {
        assert!(
            self.started,
            "Stepper::step_exact before a successful start"
        );
        assert!(h_max > 0.0, "Stepper::step_exact: h_max must be positive");
        assert!(!t_stop.is_nan(), "Stepper::step_exact: t_stop is NaN");
        let span = t_stop - self.t;
        if span == 0.0 {
            return Ok(true);
        }
        let proposal = self.h_next;
        let (h_abs, t_end, landing) = self.trial_span(proposal.min(h_max), t_stop, h_max);
        if !landing && h_abs < underflow_threshold(self.t, self.time_scale) {
            // Left to `step`, which reports the underflow.
            return Ok(false);
        }
        let hs = span.signum() * h_abs;
        advance(&self.y, &self.dy, hs, &mut self.y_new);
        eval_end(sys, &mut self.stats, t_end, &self.y_new, &mut self.scratch)
            .map_err(|source| StepError::Rhs { t: self.t, source })?;
        if !all_finite(&self.y_new) || !all_finite(&self.scratch) {
            return Err(StepError::NonFinite { t: self.t });
        }
        if !holds(&self.dy, &self.scratch) {
            return Ok(false);
        }
        let fac = self.control.accept_factor(0.0, self.err_previous);
        self.err_previous = INITIAL_ERR_PREVIOUS;
        self.accepted = None;
        self.advance_to(t_end, hs, next_size(h_abs, fac, proposal, false));
        std::mem::swap(&mut self.dy, &mut self.scratch);
        self.dense = Dense::Cubic;
        Ok(true)
    }

    /// The trial of size `h` (magnitude) towards `t_stop`: its size, its end, and whether it
    /// lands on `t_stop` (one within 1% of the distance, and not longer than `h_max`, is
    /// stretched to land there).
    fn trial_span(&self, h: f64, t_stop: f64, h_max: f64) -> (f64, f64, bool) {
        let span = t_stop - self.t;
        let dist = span.abs();
        let landing = h >= dist || (1.01 * h >= dist && dist <= h_max);
        if landing {
            (dist, t_stop, true)
        } else {
            (h, self.t + span.signum() * h, false)
        }
    }

    /// Commits the trial in `y_new` / the FSAL stage as the new state.
    #[inline]
    fn accept(&mut self, t_end: f64, hs: f64, h_next: f64) {
        self.advance_to(t_end, hs, h_next);
        match &self.work {
            Work::Dop853(w) => self.dy.copy_from_slice(&w.k[dop853::FSAL]),
            Work::Dopri5(w) => self.dy.copy_from_slice(&w.k[dopri5::FSAL]),
        }
        self.dense = Dense::Pending;
    }

    /// Makes the state in `y_new` at `t_end` (a step of signed size `hs`) the current one, the
    /// current one the step's start, and `h_next` the next step's size; the caller writes the
    /// derivative at the new state into `dy` and says what the step's extension is.
    #[inline]
    fn advance_to(&mut self, t_end: f64, hs: f64, h_next: f64) {
        self.stats.steps += 1;
        self.t_prev = self.t;
        self.t = t_end;
        self.h_last = hs;
        self.h_next = h_next;
        std::mem::swap(&mut self.y_prev, &mut self.y);
        std::mem::swap(&mut self.y, &mut self.y_new);
        self.end_replaced = false;
        std::mem::swap(&mut self.dy_prev, &mut self.dy);
    }

    /// End state of the last accepted step (differs from `y` after `replace_state`).
    #[inline]
    pub(super) fn step_end(&self) -> &[f64] {
        if self.end_replaced {
            &self.y_end
        } else {
            &self.y
        }
    }

    /// Makes the current state the (zero-length) last step.
    fn restart_here(&mut self) {
        self.t_prev = self.t;
        self.y_prev.copy_from_slice(&self.y);
        self.dy_prev.copy_from_slice(&self.dy);
        self.h_last = 0.0;
        self.accepted = None;
        self.end_replaced = false;
        self.dense = Dense::Ready;
    }
}
