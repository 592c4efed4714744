//! DOPRI5: Dormand–Prince 5(4), FSAL, with Shampine's 4th-order dense output
//! (HNW I, II.5 Table 5.2 and II.6; Hairer's code DOPRI5).

use super::control::{EvalFailure, Trial};
use super::kernels::{all_finite, combine, correct_end, eval, eval_end, hermite_parts, stage};
use super::{OdeSystem, Stats, Tolerances};

/// Number of stages including the FSAL stage 7.
pub(super) const STAGES: usize = 7;

/// Index of the stage holding `f(t + h, y_new)` (stage 7, FSAL).
pub(super) const FSAL: usize = 6;

/// Nodes `c_i` (0-based).
pub(super) const C: [f64; STAGES] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];

/// Runge–Kutta matrix `a_ij` (0-based); row 6 is the 5th-order weights `b`.
pub(super) const A: [[f64; STAGES]; STAGES] = {
    let mut a = [[0.0; STAGES]; STAGES];
    a[1][0] = 1.0 / 5.0;
    a[2][0] = 3.0 / 40.0;
    a[2][1] = 9.0 / 40.0;
    a[3][0] = 44.0 / 45.0;
    a[3][1] = -56.0 / 15.0;
    a[3][2] = 32.0 / 9.0;
    a[4][0] = 19372.0 / 6561.0;
    a[4][1] = -25360.0 / 2187.0;
    a[4][2] = 64448.0 / 6561.0;
    a[4][3] = -212.0 / 729.0;
    a[5][0] = 9017.0 / 3168.0;
    a[5][1] = -355.0 / 33.0;
    a[5][2] = 46732.0 / 5247.0;
    a[5][3] = 49.0 / 176.0;
    a[5][4] = -5103.0 / 18656.0;
    a[6][0] = 35.0 / 384.0;
    a[6][2] = 500.0 / 1113.0;
    a[6][3] = 125.0 / 192.0;
    a[6][4] = -2187.0 / 6784.0;
    a[6][5] = 11.0 / 84.0;
    a
};

/// Error weights `e = b - b_hat` (`b_hat` the 4th-order embedded weights).
pub(super) const E: [f64; STAGES] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Shampine's dense-output coefficients `d_j` (Hairer's DOPRI5).
pub(super) const D: [f64; STAGES] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// Work buffers of DOPRI5.
#[derive(Clone, Debug)]
pub(super) struct Work {
    /// Stage derivatives `k_1 ..= k_7`; `k[0]` must hold `f(t, y)` before a trial.
    pub(super) k: [Vec<f64>; STAGES],
    /// Stage argument.
    ytmp: Vec<f64>,
    /// Continuous-extension coefficients: `diff, bspl, third, d`.
    cont: [Vec<f64>; 4],
}

impl Work {
    /// Buffers for dimension `n`.
    pub(super) fn new(n: usize) -> Self {
        Self {
            k: std::array::from_fn(|_| vec![0.0; n]),
            ytmp: vec![0.0; n],
            cont: std::array::from_fn(|_| vec![0.0; n]),
        }
    }
}

/// `out = y + h * sum_j A[row][j] k_j` over the listed columns `j`.
macro_rules! rk_stage {
    ($out:expr, $w:ident, $y:expr, $h:expr, $row:literal; $($j:literal),+) => {
        stage($out, $y, $h, [$(A[$row][$j]),+], [$(&$w.k[$j][..]),+])
    };
}

/// Stages 2..=7 of a step of size `h` from `(t, y)`; writes `y_new`.
#[inline]
#[allow(clippy::too_many_arguments)]
fn stages<S: OdeSystem>(
    w: &mut Work,
    sys: &mut S,
    stats: &mut Stats,
    t: f64,
    h: f64,
    t_end: f64,
    y: &[f64],
    y_new: &mut [f64],
) -> Result<(), EvalFailure<S::Error>> {
    let rhs = EvalFailure::Rhs;
    rk_stage!(&mut w.ytmp, w, y, h, 1; 0);
    eval(sys, stats, t + C[1] * h, &w.ytmp, &mut w.k[1]).map_err(rhs)?;
    rk_stage!(&mut w.ytmp, w, y, h, 2; 0, 1);
    eval(sys, stats, t + C[2] * h, &w.ytmp, &mut w.k[2]).map_err(rhs)?;
    rk_stage!(&mut w.ytmp, w, y, h, 3; 0, 1, 2);
    eval(sys, stats, t + C[3] * h, &w.ytmp, &mut w.k[3]).map_err(rhs)?;
    rk_stage!(&mut w.ytmp, w, y, h, 4; 0, 1, 2, 3);
    eval(sys, stats, t + C[4] * h, &w.ytmp, &mut w.k[4]).map_err(rhs)?;
    rk_stage!(&mut w.ytmp, w, y, h, 5; 0, 1, 2, 3, 4);
    eval(sys, stats, t_end, &w.ytmp, &mut w.k[5]).map_err(rhs)?;
    rk_stage!(y_new, w, y, h, 6; 0, 2, 3, 4, 5);
    if !all_finite(y_new) {
        return Err(EvalFailure::NonFinite);
    }
    eval_end(sys, stats, t_end, y_new, &mut w.k[FSAL]).map_err(rhs)?;
    if !all_finite(&w.k[FSAL]) {
        return Err(EvalFailure::NonFinite);
    }
    Ok(())
}

/// RMS norm of `h * sum e_j k_j` scaled by `atol + rtol max(|y|, |y_new|)`.
#[inline]
#[allow(clippy::needless_range_loop)] // one fused pass over eight slices
fn error_norm(w: &Work, tol: Tolerances, h: f64, y: &[f64], y_new: &[f64]) -> f64 {
    let n = y_new.len();
    let y = &y[..n];
    let k = &w.k;
    let (k1, k3, k4) = (&k[0][..n], &k[2][..n], &k[3][..n]);
    let (k5, k6, k7) = (&k[4][..n], &k[5][..n], &k[6][..n]);
    let mut sum = 0.0;
    for i in 0..n {
        let e =
            E[0] * k1[i] + E[2] * k3[i] + E[3] * k4[i] + E[4] * k5[i] + E[5] * k6[i] + E[6] * k7[i];
        let r = h * e / (tol.atol + tol.rtol * y[i].abs().max(y_new[i].abs()));
        sum += r * r;
    }
    (sum / n as f64).sqrt()
}

/// One trial step of signed size `h` from `(t, y)` to `t_end` (`= t + h`, or
/// exactly the stopping time). `w.k[0]` must hold `f(t, y)`. On acceptance
/// `y_new` (as the system corrected it, [`OdeSystem::correct_end`]) and
/// `w.k[FSAL] = f(t_end, y_new)` are finite (6 evaluations, 7 where the system
/// corrected the end).
#[allow(clippy::too_many_arguments)]
pub(super) fn trial<S: OdeSystem>(
    w: &mut Work,
    sys: &mut S,
    stats: &mut Stats,
    tol: Tolerances,
    t: f64,
    h: f64,
    t_end: f64,
    y: &[f64],
    y_new: &mut [f64],
) -> Trial<S::Error> {
    if let Err(failure) = stages(w, sys, stats, t, h, t_end, y, y_new) {
        return Trial::Failed(failure);
    }
    let err = error_norm(w, tol, h, y, y_new);
    if !err.is_finite() {
        return Trial::Failed(EvalFailure::NonFinite);
    } else if err > 1.0 {
        return Trial::Rejected(err);
    }
    // The error estimate takes `f` at the unprojected end (the seventh stage); where the system
    // corrects the end, `f` there is evaluated again, at the corrected one (7 evaluations).
    match correct_end(sys, t_end, y_new) {
        Err(failure) => return Trial::Failed(failure),
        Ok(false) => {}
        Ok(true) => {
            if let Err(e) = eval_end(sys, stats, t_end, y_new, &mut w.k[FSAL]) {
                return Trial::Failed(EvalFailure::Rhs(e));
            }
            if !all_finite(&w.k[FSAL]) {
                return Trial::Failed(EvalFailure::NonFinite);
            }
        }
    }
    Trial::Accepted(err)
}

/// Builds the 4th-order continuous extension of the accepted step
/// `(t0, y0) -> (t0 + h, y1)` (no evaluations).
pub(super) fn prepare_dense(w: &mut Work, h: f64, y0: &[f64], y1: &[f64]) {
    let [diff, bspl, third, d] = &mut w.cont;
    hermite_parts([diff, bspl, third], h, y0, y1, &w.k[0], &w.k[FSAL]);
    let k = &w.k;
    combine(
        d,
        h,
        [D[0], D[2], D[3], D[4], D[5], D[6]],
        [&k[0], &k[2], &k[3], &k[4], &k[5], &k[6]],
    );
}

/// Evaluates the continuous extension at `theta = (t - t0) / h` into `out`
/// (anchored at `y0` for `theta <= 1/2` and at `y1` beyond, so that both end
/// points are reproduced exactly).
#[allow(clippy::needless_range_loop)] // one fused pass over six slices
pub(super) fn interpolate(w: &Work, theta: f64, y0: &[f64], y1: &[f64], out: &mut [f64]) {
    let n = out.len();
    let s = theta;
    let s1 = 1.0 - s;
    let (base, cd) = if s <= 0.5 { (y0, s) } else { (y1, -s1) };
    let base = &base[..n];
    let c = &w.cont;
    let (diff, bspl, third, d) = (&c[0][..n], &c[1][..n], &c[2][..n], &c[3][..n]);
    let ss1 = s * s1;
    for i in 0..n {
        out[i] = base[i] + cd * diff[i] + ss1 * (bspl[i] + s * (third[i] + s1 * d[i]));
    }
}
