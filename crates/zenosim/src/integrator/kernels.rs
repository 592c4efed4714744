//! Small vector kernels shared by the Runge–Kutta stage loops.
//!
//! The number of stage vectors `M` is a const generic, so after inlining the
//! sum over the stages is fully unrolled inside a single pass over the
//! elements; every slice is cut to the output length first, which removes the
//! bounds checks of the element loop.

use super::control::EvalFailure;
use super::{OdeSystem, Stats};

/// `out = y + h * sum_j a[j] * k[j]` (an explicit Runge–Kutta stage argument).
#[inline(always)]
pub(super) fn stage<const M: usize>(
    out: &mut [f64],
    y: &[f64],
    h: f64,
    a: [f64; M],
    k: [&[f64]; M],
) {
    let n = out.len();
    let y = &y[..n];
    let k = resliced(k, n);
    for (i, (o, &yi)) in out.iter_mut().zip(y).enumerate() {
        *o = yi + h * dot_at(&a, &k, i);
    }
}

/// `out = h * sum_j a[j] * k[j]`.
#[inline(always)]
pub(super) fn combine<const M: usize>(out: &mut [f64], h: f64, a: [f64; M], k: [&[f64]; M]) {
    let k = resliced(k, out.len());
    for (i, o) in out.iter_mut().enumerate() {
        *o = h * dot_at(&a, &k, i);
    }
}

/// Every slice cut to length `n` (so that indexing below `n` needs no checks).
#[inline(always)]
fn resliced<const M: usize>(mut k: [&[f64]; M], n: usize) -> [&[f64]; M] {
    for kj in k.iter_mut() {
        *kj = &kj[..n];
    }
    k
}

/// `sum_j a[j] * k[j][i]`, accumulated in stage order.
#[inline(always)]
fn dot_at<const M: usize>(a: &[f64; M], k: &[&[f64]; M], i: usize) -> f64 {
    let mut acc = 0.0;
    for (&aj, kj) in a.iter().zip(k) {
        acc += aj * kj[i];
    }
    acc
}

/// Hermite part of the continuous extensions (II.6): with `diff = y1 - y0`,
/// writes `diff`, `bspl = h f0 - diff` and `diff - h f1 - bspl`.
#[inline]
pub(super) fn hermite_parts(
    [c_diff, c_bspl, c_third]: [&mut [f64]; 3],
    h: f64,
    y0: &[f64],
    y1: &[f64],
    f0: &[f64],
    f1: &[f64],
) {
    let n = c_diff.len();
    let (c_bspl, c_third) = (&mut c_bspl[..n], &mut c_third[..n]);
    let (y0, y1, f0, f1) = (&y0[..n], &y1[..n], &f0[..n], &f1[..n]);
    for i in 0..n {
        let diff = y1[i] - y0[i];
        let bspl = h * f0[i] - diff;
        c_diff[i] = diff;
        c_bspl[i] = bspl;
        c_third[i] = diff - h * f1[i] - bspl;
    }
}

/// `true` when every entry is finite.
#[inline]
pub(super) fn all_finite(x: &[f64]) -> bool {
    x.iter().all(|v| v.is_finite())
}

/// Calls the right-hand side and counts the call.
#[inline(always)]
pub(super) fn eval<S: OdeSystem>(
    sys: &mut S,
    stats: &mut Stats,
    t: f64,
    y: &[f64],
    dy: &mut [f64],
) -> Result<(), S::Error> {
    stats.rhs_evals += 1;
    sys.rhs(t, y, dy)
}

/// [`eval`] at the end of a trial step ([`OdeSystem::rhs_at_end`]).
#[inline(always)]
pub(super) fn eval_end<S: OdeSystem>(
    sys: &mut S,
    stats: &mut Stats,
    t: f64,
    y: &[f64],
    dy: &mut [f64],
) -> Result<(), S::Error> {
    stats.rhs_evals += 1;
    sys.rhs_at_end(t, y, dy)
}

/// The system's correction of an accepted trial's end `y` ([`OdeSystem::correct_end`]):
/// whether it changed `y`, which must still be finite.
#[inline(always)]
pub(super) fn correct_end<S: OdeSystem>(
    sys: &mut S,
    t: f64,
    y: &mut [f64],
) -> Result<bool, EvalFailure<S::Error>> {
    let changed = sys.correct_end(t, y).map_err(EvalFailure::Rhs)?;
    if changed && !all_finite(y) {
        return Err(EvalFailure::NonFinite);
    }
    Ok(changed)
}

/// Weighted RMS norm `sqrt(mean((x_i / (atol + rtol |y_i|))^2))` (used by hinit). Where the
/// sum of squares over- or underflows and the norm itself is a finite number (a derivative of
/// 10 against an `atol` of 1e-300, for a component that starts at zero, is a ratio of 1e301,
/// whose square is not), it is computed again scaled by its largest term.
#[inline]
pub(super) fn weighted_rms(x: &[f64], y: &[f64], rtol: f64, atol: f64) -> f64 {
    let ratio = |(&xi, &yi): (&f64, &f64)| xi / (atol + rtol * yi.abs());
    let sum: f64 = x.iter().zip(y).map(ratio).map(|r| r * r).sum();
    let norm = (sum / x.len() as f64).sqrt();
    if norm.is_nan() || (norm.is_finite() && norm >= f64::MIN_POSITIVE) {
        return norm;
    }
    let largest = x.iter().zip(y).map(|p| ratio(p).abs()).fold(0.0, f64::max);
    if largest == 0.0 || !largest.is_finite() {
        return largest;
    }
    let sum: f64 = x
        .iter()
        .zip(y)
        .map(|p| {
            let r = ratio(p) / largest;
            r * r
        })
        .sum();
    largest * (sum / x.len() as f64).sqrt()
}
