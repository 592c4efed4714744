//! Step-size controller and initial step-size selection (HNW I, II.4).

use super::kernels::{all_finite, eval, weighted_rms};
use super::{Method, OdeSystem, Stats, Tolerances};

/// Safety factor of the step-size controller.
const SAFETY: f64 = 0.9;

/// The previous error norm assumed at a start (Hairer's initial `facold`), and its floor.
pub(super) const INITIAL_ERR_PREVIOUS: f64 = 1e-4;

/// The floor of the earlier error norm in [`Control::predictive_factor`] (RADAU5's): an
/// earlier step far more accurate than asked says little about the error's growth.
pub(super) const PREDICTIVE_ERR_FLOOR: f64 = 1e-2;

/// Step-size reduction applied after a failed or non-finite trial.
pub(super) const FAILURE_SHRINK: f64 = 0.25;

/// Per-method controller constants.
#[derive(Clone, Copy, Debug)]
pub(super) struct Control {
    /// `1 / (q + 1)`, `q` the order of the error estimate (1/8 is done with
    /// three square roots instead of `powf`).
    expo: f64,
    /// Smallest step ratio `h_new / h`.
    fac_min: f64,
    /// Largest step ratio `h_new / h`.
    fac_max: f64,
    /// Exponent denominator of the `hinit` formula (Hairer's `iord`).
    hinit_order: f64,
    /// PI ("stabilised") control, HNW II, IV.2 and Hairer's codes: the step ratio is
    /// `SAFETY · err^(−(expo − beta_weight·beta)) · err_previous^beta`.
    beta: f64,
    /// The weight of `beta` in the exponent of `err` (0.2 in DOP853, 0.75 in DOPRI5).
    beta_weight: f64,
}

impl Control {
    /// Constants of Hairer's codes: DOP853 ratio in `[1/3, 6]` with exponent
    /// 1/8, DOPRI5 ratio in `[1/5, 10]` with exponent 1/5; `beta = 0.04` (the value Hairer
    /// recommends for DOPRI5; with DOP853's plain control a third of the steps of the
    /// ball-on-sine's constrained phase were rejected while the step size fell).
    pub(super) fn for_method(method: Method) -> Self {
        match method {
            Method::Dop853 => Self {
                expo: 1.0 / 8.0,
                fac_min: 1.0 / 3.0,
                fac_max: 6.0,
                hinit_order: 8.0,
                beta: 0.04,
                beta_weight: 0.2,
            },
            Method::Dopri5 => Self {
                expo: 1.0 / 5.0,
                fac_min: 0.2,
                fac_max: 10.0,
                hinit_order: 5.0,
                beta: 0.04,
                beta_weight: 0.75,
            },
        }
    }

    /// Step ratio after an accepted step with error norm `err <= 1` (`err == 0` gives the
    /// largest ratio), the last accepted step having had `err_previous`.
    #[inline]
    pub(super) fn accept_factor(&self, err: f64, err_previous: f64) -> f64 {
        let exponent = self.expo - self.beta_weight * self.beta;
        let fac = SAFETY * err_previous.powf(self.beta) / err.powf(exponent);
        if fac.is_nan() {
            return self.fac_max;
        }
        fac.clamp(self.fac_min, self.fac_max)
    }

    /// Gustafsson's predictive step ratio (HNW II, IV.8, as in Hairer's RADAU5) after an
    /// accepted step of size `h` and error norm `err`, the accepted step before it having had
    /// size `h_before` and error norm `err_before`: the error's growth from one step to the
    /// next, `err / err_before` at the ratio `h / h_before`, is taken to go on. Where the
    /// solution's derivatives grow from step to step (a body sliding down into a well), the
    /// plain ratio overshoots again and again, and each overshoot is a rejected trial.
    pub(super) fn predictive_factor(
        &self,
        err: f64,
        h: f64,
        err_before: f64,
        h_before: f64,
    ) -> f64 {
        let err_before = err_before.max(PREDICTIVE_ERR_FLOOR);
        // An error of 0 gives an infinite ratio, clamped to the largest.
        let fac = SAFETY * (h / h_before) * (err_before / (err * err)).powf(self.expo);
        fac.clamp(self.fac_min, self.fac_max)
    }

    /// Step ratio after a trial rejected with error norm `err > 1` (< 0.9).
    #[inline]
    pub(super) fn reject_factor(&self, err: f64) -> f64 {
        (SAFETY / self.root(err)).max(self.fac_min)
    }

    /// `err^expo` (`err >= 0`; 0 maps to 0, whose reciprocal gives the largest ratio).
    #[inline]
    fn root(&self, err: f64) -> f64 {
        if self.expo == 0.125 {
            err.sqrt().sqrt().sqrt()
        } else {
            err.powf(self.expo)
        }
    }
}

/// Steps below this magnitude (at time `t`) are a step-size underflow: `16 ε max(|t|, scale)`,
/// with `scale` the first step size the stepper was started with (the problem's own time
/// scale, from its derivatives: [`hinit`]), and no less than the smallest normal number. It
/// has no unit of time: a model whose motion takes 1e-25 s (a ball under g = 1e50) steps as
/// finely as it needs, and a step that fails where it starts still gives up within a few
/// dozen trials.
#[inline]
pub(super) fn underflow_threshold(t: f64, scale: f64) -> f64 {
    (16.0 * f64::EPSILON * t.abs().max(scale)).max(f64::MIN_POSITIVE)
}

/// Why a trial step could not be used.
pub(super) enum EvalFailure<E> {
    /// The right-hand side returned an error.
    Rhs(E),
    /// A stage, the new state or the error estimate was not finite.
    NonFinite,
}

/// Outcome of one trial step.
pub(super) enum Trial<E> {
    /// Error norm `<= 1`; the new state and its derivative are finite.
    Accepted(f64),
    /// Error norm `> 1`.
    Rejected(f64),
    /// The trial could not be completed.
    Failed(EvalFailure<E>),
}

/// Hairer's `hinit` (HNW I, II.4, "Starting step size"), forward in time.
///
/// `f0 = f(t, y)`; `y1` and `f1` are scratch buffers. If the probe evaluation
/// fails or is non-finite the first guess `h0` is returned instead.
#[allow(clippy::too_many_arguments)]
pub(super) fn hinit<S: OdeSystem>(
    sys: &mut S,
    stats: &mut Stats,
    control: &Control,
    tol: Tolerances,
    t: f64,
    y: &[f64],
    f0: &[f64],
    y1: &mut [f64],
    f1: &mut [f64],
) -> f64 {
    let (rtol, atol) = (tol.rtol, tol.atol);
    // Hairer's fallbacks for a state at rest take 1e-6 s; far from t = 0 that is below what
    // f64 resolves at t (at t = 4e10, 16 ε t is 1.4e-4 s), so they are at least 1024 ε |t|,
    // beyond the step-size floor. Nearer to t = 0 than 4.4e6 s nothing changes.
    let fallback = 1e-6_f64.max(1024.0 * f64::EPSILON * t.abs());
    let d0 = weighted_rms(y, y, rtol, atol);
    let d1 = weighted_rms(f0, y, rtol, atol);
    let h0 = if d0 < 1e-5 || d1 < 1e-5 {
        fallback
    } else if d1.is_finite() {
        // A step that moves the state by a hundredth of its size; of the tolerance, where the
        // state is smaller than that (a body at rest to within 1e-5 of its tolerances, near
        // the origin, would otherwise start at 1e-16 s, below what f64 resolves in time).
        0.01 * d0.max(1.0) / d1
    } else {
        // The weighted derivative overflows (a tiny atol, a large derivative: g = 1e11 with
        // atol = 1e-300). The ratio d0 / d1 does not depend on the weights' common scale:
        // taken with weights 2^512 times larger, it is finite. Where it is still 0 (g = 1e60
        // with atol = 1e-300: about 1e-350 s), no step f64 holds is small enough: the guess is
        // 0, and the run stops at once saying that the tolerances ask too much (the fallback,
        // a step for a state at rest, gave a wrong run that ended as if well).
        let s = 2f64.powi(512);
        let ratio =
            weighted_rms(y, y, rtol * s, atol * s) / weighted_rms(f0, y, rtol * s, atol * s);
        if ratio.is_finite() && ratio > 0.0 {
            0.01 * ratio
        } else {
            return 0.0;
        }
    };
    for ((y1i, &yi), &fi) in y1.iter_mut().zip(y).zip(f0) {
        *y1i = yi + h0 * fi;
    }
    if eval(sys, stats, t + h0, y1, f1).is_err() || !all_finite(f1) {
        return h0;
    }
    for (f1i, &fi) in f1.iter_mut().zip(f0) {
        *f1i -= fi;
    }
    let d2 = weighted_rms(f1, y, rtol, atol) / h0;
    let der = d1.max(d2);
    let h1 = if der <= 1e-15 {
        (h0 * 1e-3).max(fallback)
    } else {
        (0.01 / der).powf(1.0 / control.hinit_order)
    };
    let h = (100.0 * h0).min(h1);
    let h = if h.is_finite() && h > 0.0 { h } else { h0 };
    // Weights of 1e-308 on a component at 0 make the guess 1e-309 or less, below the normal
    // numbers and so below every step-size floor: a thousand normal numbers' worth at least,
    // from which the step grows (nothing changes for a guess of 2.3e-305 s or more).
    h.max(1024.0 * f64::MIN_POSITIVE)
}
