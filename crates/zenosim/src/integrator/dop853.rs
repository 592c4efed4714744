//! DOP853 stage loop, combined 5th/3rd-order error estimate and 7th-order
//! continuous extension (HNW I, II.5–II.6; Hairer's code DOP853).

use super::control::{EvalFailure, Trial};
use super::dop853_tableau::{A, B, BHH, C, D, ER, STAGES};
use super::kernels::{all_finite, combine, correct_end, eval, eval_end, hermite_parts, stage};
use super::{OdeSystem, Stats, Tolerances};

/// Index of the stage holding `f(t + h, y_new)` (stage 13, FSAL).
pub(super) const FSAL: usize = 12;

/// Work buffers of DOP853.
#[derive(Clone, Debug)]
pub(super) struct Work {
    /// Stage derivatives `k_1 ..= k_16`; `k[0]` must hold `f(t, y)` before a trial.
    pub(super) k: [Vec<f64>; STAGES],
    /// Stage argument.
    ytmp: Vec<f64>,
    /// Continuous-extension coefficients: `diff, bspl, third, d4..d7`.
    cont: [Vec<f64>; 7],
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

/// `ytmp = y + h * sum_j A[row][j] k_j` over the listed (non-zero) columns `j`.
macro_rules! rk_stage {
    ($w:ident, $y:expr, $h:expr, $row:literal; $($j:literal),+) => {
        stage(&mut $w.ytmp, $y, $h, [$(A[$row][$j]),+], [$(&$w.k[$j][..]),+])
    };
}

/// Stages 2..=12 of a step of size `h` from `(t, y)`; `t_end = t + h`.
#[inline]
fn stages<S: OdeSystem>(
    w: &mut Work,
    sys: &mut S,
    stats: &mut Stats,
    t: f64,
    h: f64,
    t_end: f64,
    y: &[f64],
) -> Result<(), S::Error> {
    rk_stage!(w, y, h, 1; 0);
    eval(sys, stats, t + C[1] * h, &w.ytmp, &mut w.k[1])?;
    rk_stage!(w, y, h, 2; 0, 1);
    eval(sys, stats, t + C[2] * h, &w.ytmp, &mut w.k[2])?;
    rk_stage!(w, y, h, 3; 0, 2);
    eval(sys, stats, t + C[3] * h, &w.ytmp, &mut w.k[3])?;
    rk_stage!(w, y, h, 4; 0, 2, 3);
    eval(sys, stats, t + C[4] * h, &w.ytmp, &mut w.k[4])?;
    rk_stage!(w, y, h, 5; 0, 3, 4);
    eval(sys, stats, t + C[5] * h, &w.ytmp, &mut w.k[5])?;
    rk_stage!(w, y, h, 6; 0, 3, 4, 5);
    eval(sys, stats, t + C[6] * h, &w.ytmp, &mut w.k[6])?;
    rk_stage!(w, y, h, 7; 0, 3, 4, 5, 6);
    eval(sys, stats, t + C[7] * h, &w.ytmp, &mut w.k[7])?;
    rk_stage!(w, y, h, 8; 0, 3, 4, 5, 6, 7);
    eval(sys, stats, t + C[8] * h, &w.ytmp, &mut w.k[8])?;
    rk_stage!(w, y, h, 9; 0, 3, 4, 5, 6, 7, 8);
    eval(sys, stats, t + C[9] * h, &w.ytmp, &mut w.k[9])?;
    rk_stage!(w, y, h, 10; 0, 3, 4, 5, 6, 7, 8, 9);
    eval(sys, stats, t + C[10] * h, &w.ytmp, &mut w.k[10])?;
    rk_stage!(w, y, h, 11; 0, 3, 4, 5, 6, 7, 8, 9, 10);
    eval(sys, stats, t_end, &w.ytmp, &mut w.k[11])
}

/// Writes `y_new = y + h * sum b_j k_j` and returns the DOP853 error norm
/// `|h| err5^2 / sqrt(n (err5^2 + 0.01 err3^2))` (sums of squares of the
/// scaled 5th- and 3rd-order estimates).
#[inline]
#[allow(clippy::needless_range_loop)] // one fused pass over ten slices
fn solution_and_error(w: &Work, tol: Tolerances, h: f64, y: &[f64], y_new: &mut [f64]) -> f64 {
    let n = y_new.len();
    let y = &y[..n];
    let k = &w.k;
    let (k1, k6, k7, k8) = (&k[0][..n], &k[5][..n], &k[6][..n], &k[7][..n]);
    let (k9, k10, k11, k12) = (&k[8][..n], &k[9][..n], &k[10][..n], &k[11][..n]);
    let (mut s5, mut s3) = (0.0, 0.0);
    for i in 0..n {
        let bk = B[0] * k1[i]
            + B[5] * k6[i]
            + B[6] * k7[i]
            + B[7] * k8[i]
            + B[8] * k9[i]
            + B[9] * k10[i]
            + B[10] * k11[i]
            + B[11] * k12[i];
        let yn = y[i] + h * bk;
        y_new[i] = yn;
        let e3 = bk - BHH[0] * k1[i] - BHH[8] * k9[i] - BHH[11] * k12[i];
        let e5 = ER[0] * k1[i]
            + ER[5] * k6[i]
            + ER[6] * k7[i]
            + ER[7] * k8[i]
            + ER[8] * k9[i]
            + ER[9] * k10[i]
            + ER[10] * k11[i]
            + ER[11] * k12[i];
        let inv = 1.0 / (tol.atol + tol.rtol * y[i].abs().max(yn.abs()));
        let (r3, r5) = (e3 * inv, e5 * inv);
        s3 += r3 * r3;
        s5 += r5 * r5;
    }
    let mut deno = s5 + 0.01 * s3;
    if deno <= 0.0 {
        deno = 1.0;
    }
    h.abs() * s5 / (n as f64 * deno).sqrt()
}

/// One trial step of signed size `h` from `(t, y)` to `t_end` (`= t + h`, or
/// exactly the stopping time). `w.k[0]` must hold `f(t, y)`. On acceptance
/// `y_new` (as the system corrected it, [`OdeSystem::correct_end`]) and
/// `w.k[FSAL] = f(t_end, y_new)` are finite (12 evaluations; a trial rejected on
/// its error estimate costs 11).
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
    if let Err(e) = stages(w, sys, stats, t, h, t_end, y) {
        return Trial::Failed(EvalFailure::Rhs(e));
    }
    let err = solution_and_error(w, tol, h, y, y_new);
    if !err.is_finite() || !all_finite(y_new) {
        return Trial::Failed(EvalFailure::NonFinite);
    }
    if err > 1.0 {
        return Trial::Rejected(err);
    }
    // The error is the unprojected end's; the next step starts from the corrected one.
    if let Err(failure) = correct_end(sys, t_end, y_new) {
        return Trial::Failed(failure);
    }
    if let Err(e) = eval_end(sys, stats, t_end, y_new, &mut w.k[FSAL]) {
        return Trial::Failed(EvalFailure::Rhs(e));
    }
    if !all_finite(&w.k[FSAL]) {
        return Trial::Failed(EvalFailure::NonFinite);
    }
    Trial::Accepted(err)
}

/// Builds the 7th-order continuous extension of the accepted step
/// `(t0, y0) -> (t0 + h, y1)` from its stages (3 extra evaluations).
pub(super) fn prepare_dense<S: OdeSystem>(
    w: &mut Work,
    sys: &mut S,
    stats: &mut Stats,
    t0: f64,
    h: f64,
    y0: &[f64],
    y1: &[f64],
) -> Result<(), EvalFailure<S::Error>> {
    rk_stage!(w, y0, h, 13; 0, 6, 7, 8, 9, 10, 11, 12);
    eval(sys, stats, t0 + C[13] * h, &w.ytmp, &mut w.k[13]).map_err(EvalFailure::Rhs)?;
    rk_stage!(w, y0, h, 14; 0, 5, 6, 7, 10, 11, 12, 13);
    eval(sys, stats, t0 + C[14] * h, &w.ytmp, &mut w.k[14]).map_err(EvalFailure::Rhs)?;
    rk_stage!(w, y0, h, 15; 0, 5, 6, 7, 8, 12, 13, 14);
    eval(sys, stats, t0 + C[15] * h, &w.ytmp, &mut w.k[15]).map_err(EvalFailure::Rhs)?;
    if !w.k[13..].iter().all(|k| all_finite(k)) {
        return Err(EvalFailure::NonFinite);
    }
    let [diff, bspl, third, rest @ ..] = &mut w.cont;
    hermite_parts([diff, bspl, third], h, y0, y1, &w.k[0], &w.k[FSAL]);
    for (d, out) in D.iter().zip(rest.iter_mut()) {
        let k = &w.k;
        combine(
            out,
            h,
            [
                d[0], d[5], d[6], d[7], d[8], d[9], d[10], d[11], d[12], d[13], d[14], d[15],
            ],
            [
                &k[0], &k[5], &k[6], &k[7], &k[8], &k[9], &k[10], &k[11], &k[12], &k[13], &k[14],
                &k[15],
            ],
        );
    }
    Ok(())
}

/// Evaluates the continuous extension at `theta = (t - t0) / h` into `out`
/// (anchored at `y0` for `theta <= 1/2` and at `y1` beyond, so that both end
/// points are reproduced exactly).
#[allow(clippy::needless_range_loop)] // one fused pass over nine slices
pub(super) fn interpolate(w: &Work, theta: f64, y0: &[f64], y1: &[f64], out: &mut [f64]) {
    let n = out.len();
    let s = theta;
    let s1 = 1.0 - s;
    let (base, cd) = if s <= 0.5 { (y0, s) } else { (y1, -s1) };
    let base = &base[..n];
    let c = &w.cont;
    let (diff, bspl, third, r4) = (&c[0][..n], &c[1][..n], &c[2][..n], &c[3][..n]);
    let (r5, r6, r7) = (&c[4][..n], &c[5][..n], &c[6][..n]);
    let ss1 = s * s1;
    for i in 0..n {
        let poly = bspl[i] + s * (third[i] + s1 * (r4[i] + s * (r5[i] + s1 * (r6[i] + s * r7[i]))));
        out[i] = base[i] + cd * diff[i] + ss1 * poly;
    }
}
