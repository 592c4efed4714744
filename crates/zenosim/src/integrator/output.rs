//! Read access to the [`Stepper`] state and its continuous extension (HNW I, II.6).

use super::control::EvalFailure;
use super::stepper::{Dense, Work};
use super::{dop853, dopri5, Method, OdeSystem, Stats, StepError, Stepper, Tolerances};

impl Stepper {
    /// End of the last accepted step (the current time).
    #[inline]
    pub fn t(&self) -> f64 {
        self.t
    }

    /// Start of the last accepted step (equals [`t`](Stepper::t) after a (re)start).
    #[inline]
    pub fn t_previous(&self) -> f64 {
        self.t_prev
    }

    /// Current state `y(t)`.
    #[inline]
    pub fn y(&self) -> &[f64] {
        &self.y
    }

    /// `f(t, y)` at the current state.
    #[inline]
    pub fn dy(&self) -> &[f64] {
        &self.dy
    }

    /// State at the start of the last accepted step.
    #[inline]
    pub fn y_previous(&self) -> &[f64] {
        &self.y_prev
    }

    /// `f` at the start of the last accepted step.
    #[inline]
    pub fn dy_previous(&self) -> &[f64] {
        &self.dy_prev
    }

    /// Magnitude of the step the controller proposes next (before `h_max` and `t_stop`).
    #[inline]
    pub fn suggested_step(&self) -> f64 {
        self.h_next
    }

    /// Cumulative work counters.
    #[inline]
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// The Runge–Kutta pair in use.
    #[inline]
    pub fn method(&self) -> Method {
        self.method
    }

    /// Tolerances of the error control.
    #[inline]
    pub fn tolerances(&self) -> Tolerances {
        self.tol
    }

    /// Prepare the continuous extension of the last accepted step (DOP853: the 3 extra evaluations; done at most once per step; DOPRI5, and after [`step_exact`](Stepper::step_exact): nothing to evaluate).
    ///
    /// Failures are reported with `t = t_previous()`; the extension then stays
    /// unprepared.
    ///
    /// # Panics
    /// If the last call of [`step`](Stepper::step) failed before the
    /// extension of the step preceding it was prepared (its stages are lost).
    pub fn prepare_dense<S: OdeSystem>(&mut self, sys: &mut S) -> Result<(), StepError<S::Error>> {
        match self.dense {
            Dense::Ready | Dense::Cubic => return Ok(()),
            Dense::Lost => panic!(
                "Stepper::prepare_dense: the stages of the last accepted step were \
                 overwritten by a failed step; prepare the extension before stepping on"
            ),
            Dense::Pending => {}
        }
        let (t0, h) = (self.t_prev, self.h_last);
        // The field-wise form of `step_end()` (the work buffers are borrowed mutably).
        let y1 = if self.end_replaced {
            &self.y_end
        } else {
            &self.y
        };
        match &mut self.work {
            Work::Dop853(w) => {
                dop853::prepare_dense(w, sys, &mut self.stats, t0, h, &self.y_prev, y1).map_err(
                    |failure| match failure {
                        EvalFailure::Rhs(source) => StepError::Rhs { t: t0, source },
                        EvalFailure::NonFinite => StepError::NonFinite { t: t0 },
                    },
                )?
            }
            Work::Dopri5(w) => dopri5::prepare_dense(w, h, &self.y_prev, y1),
        }
        self.dense = Dense::Ready;
        Ok(())
    }

    /// The cubic Hermite interpolant of the last accepted step at `t`, into `out`: through the
    /// states and derivatives at the step's two ends, with no evaluation and no
    /// [`prepare_dense`](Stepper::prepare_dense).
    ///
    /// Exact (up to rounding) where the solution is a polynomial of degree at most 3 in `t`,
    /// such as `y = (q, q̇)` under a constant `q̈`; elsewhere of order 3 only. It reproduces
    /// `y_previous()` and `y()` exactly at the ends (after
    /// [`replace_state`](Stepper::replace_state): the step's end before the replacement). After
    /// a (re)start the step has length zero and `out` is set to `y()`.
    ///
    /// # Panics
    /// In debug builds, if `out.len()` is not the dimension.
    pub fn interpolate_cubic(&self, t: f64, out: &mut [f64]) {
        debug_assert_eq!(out.len(), self.y.len());
        let width = self.t - self.t_prev;
        if width == 0.0 {
            out.copy_from_slice(&self.y);
            return;
        }
        let s = (t - self.t_prev) / width;
        let s1 = 1.0 - s;
        // p(s) = y0 + s Δ + s(1−s) [(1−s)(h f0 − Δ) + s(Δ − h f1)], Δ = y1 − y0, written from
        // the nearer end (as the dense output is), so that a component that does not move
        // stays exactly what it is.
        let (near_start, cd) = (s <= 0.5, if s <= 0.5 { s } else { -s1 });
        let h = self.h_last;
        let ss1 = s * s1;
        let dy_end = if self.end_replaced {
            &self.dy_end
        } else {
            &self.dy
        };
        let ends = self.y_prev.iter().zip(self.step_end());
        let slopes = self.dy_prev.iter().zip(dy_end);
        for ((o, (&y0, &y1)), (&f0, &f1)) in out.iter_mut().zip(ends).zip(slopes) {
            let diff = y1 - y0;
            let bend = s1 * (h * f0 - diff) + s * (diff - h * f1);
            let base = if near_start { y0 } else { y1 };
            *o = base + cd * diff + ss1 * bend;
        }
    }

    /// Evaluate the continuous extension of the last accepted step at `t` into `out`.
    ///
    /// Meant for `t` in `[t_previous(), t()]`, where it is of order 7 (DOP853)
    /// or 4 (DOPRI5) and reproduces `y_previous()` and `y()` exactly at the end
    /// points (after [`replace_state`](Stepper::replace_state): the end state
    /// before the replacement); outside it extrapolates the polynomial. After a
    /// (re)start the step has length zero and `out` is set to `y()`. After
    /// [`step_exact`](Stepper::step_exact) it is the cubic Hermite interpolant
    /// ([`interpolate_cubic`](Stepper::interpolate_cubic)), exact there.
    ///
    /// # Panics
    /// If [`prepare_dense`](Stepper::prepare_dense) was not called since the
    /// last accepted step (checked in release builds too: one branch), or, in
    /// debug builds, if `out.len()` is not the dimension.
    #[inline]
    pub fn interpolate(&self, t: f64, out: &mut [f64]) {
        if self.dense == Dense::Cubic {
            return self.interpolate_cubic(t, out);
        }
        assert!(
            self.dense == Dense::Ready,
            "Stepper::interpolate: call prepare_dense after each accepted step first"
        );
        debug_assert_eq!(out.len(), self.y.len());
        let width = self.t - self.t_prev;
        if width == 0.0 {
            out.copy_from_slice(&self.y);
            return;
        }
        let theta = (t - self.t_prev) / width;
        let (y0, y1) = (&self.y_prev[..], self.step_end());
        match &self.work {
            Work::Dop853(w) => dop853::interpolate(w, theta, y0, y1, out),
            Work::Dopri5(w) => dopri5::interpolate(w, theta, y0, y1, out),
        }
    }
}
