//! WHEN a guard is crossed: detection and location of a root on a step's dense output.
//!
//! The traps of REFERENCE §4, and what this module does about each:
//! - a whole flight inside one step (no sign change at the step's ends): the guard is sampled
//!   inside the step, and between two positive samples where `ġ` goes from − to + the minimum
//!   itself is located and tested;
//! - a guard that varies faster than the samples see (a long free flight over a wavy surface,
//!   where several dips fit between two samples): between two positive samples, the cubic
//!   through their values and slopes is checked at the midpoint, and the halves are searched
//!   in turn wherever it does not show the guard clear of 0;
//! - a step that starts on the surface (`g = −1e-17` after a reset): the start is taken as
//!   admissible, and the first admissible point after it is probed for before bracketing;
//! - the root is reported on the admissible side (`g ≥ 0` there).
//!
//! [`first_crossing`] is public so that it can be measured (the engine's benchmarks) and used
//! with an [`crate::integrator::Stepper`]'s dense output for other guards.

/// Interior samples per step (the guard is smooth on the dense output, and dips between
/// samples are caught through `ġ` and the cubic through the samples).
pub(crate) const SAMPLES_PER_STEP: usize = 4;

/// The most evaluations of the guard a step may spend on refining between samples (a guard
/// that grazes 0 at its rounding would otherwise be refined down to the time resolution).
const REFINE_BUDGET: usize = 256;

/// How far past a secant estimate [`bracket`] puts its trial, as a fraction of the secant's step
/// (guards without a slope).
const SECANT_MARGIN: f64 = 1e-3;

/// A bracketed crossing `g(t_admissible) > 0 ≥ g(t_violating)`, `t_violating − t_admissible`
/// at round-off.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// The last time on the admissible side: where the event is reported.
    pub t_admissible: f64,
    /// The first time on the other side.
    pub t_violating: f64,
}

/// The time resolution at `t` of a motion whose own time scale is `scale`: intervals shorter
/// than `64 ε max(|t|, scale)` are not told apart, and none shorter than the smallest normal
/// number. Away from `t = 0` it is what `f64` resolves at `t`; near it, a fraction of the
/// motion's own time scale (a step's width on its dense output, the run's first step for the
/// run's decisions), never of a unit of time: under `g = 1e50` a ball's flights take 1e-25 s,
/// and are resolved as finely as under `g = 9.81`. The floor keeps every loop that halves an
/// interval down to it finite where `scale` is below the normal numbers.
#[inline]
pub(crate) fn time_resolution(t: f64, scale: f64) -> f64 {
    (64.0 * f64::EPSILON * t.abs().max(scale)).max(f64::MIN_POSITIVE)
}

/// The first crossing of `g` from `> 0` to `≤ 0` in `(t0, t1]`: zenosim's event location on
/// one step's dense output.
///
/// `g(t)` returns the guard and, when known, its time derivative (`None` disables the search
/// for dips between samples). The start `t0` is taken as admissible whatever `g(t0)` says: the
/// caller only ever starts a step from an admissible state.
///
/// ```
/// use zenosim::events::first_crossing;
/// // A ball thrown up at 1 m/s from the floor: back on it at t = 2/g, inside one step.
/// let g = 9.81;
/// let crossing = first_crossing(0.0, 1.0, |t| (t - 0.5 * g * t * t, Some(1.0 - g * t))).unwrap();
/// assert!((crossing.t_admissible - 2.0 / g).abs() < 1e-14);
/// ```
pub fn first_crossing(
    t0: f64,
    t1: f64,
    g: impl FnMut(f64) -> (f64, Option<f64>),
) -> Option<Crossing> {
    first_crossing_or_touch(t0, t1, g).0
}

/// [`first_crossing`], and where there is none, the lowest point of a dip that came within
/// `10⁻⁶` of the guard's size to 0 without crossing it, if any: `(t, g(t))`. A regular surface
/// merely grazed gives one; so does a guard that touches 0 without changing sign (`h = y²`),
/// which the caller tells apart by its gradient there.
pub(crate) fn first_crossing_or_touch(
    t0: f64,
    t1: f64,
    mut g: impl FnMut(f64) -> (f64, Option<f64>),
) -> (Option<Crossing>, Option<(f64, f64)>) {
    if t1 <= t0 || t0.is_nan() || t1.is_nan() {
        return (None, None);
    }
    let n = SAMPLES_PER_STEP;
    let mut prev_t = t0;
    let mut prev = g(t0);
    let mut search = Search {
        budget: REFINE_BUDGET,
        touch: None,
        scale: t1 - t0,
    };
    for k in 1..=n {
        let t = if k == n {
            t1
        } else {
            t0 + (t1 - t0) * (k as f64 / n as f64)
        };
        let cur = g(t);
        if cur.0 <= 0.0 || cur.0.is_nan() {
            return (
                Some(first_in(prev_t, prev, t, cur, &mut g, &mut search)),
                None,
            );
        }
        if let Some(crossing) = between(prev_t, prev, t, cur, &mut g, &mut search) {
            return (Some(crossing), None);
        }
        prev_t = t;
        prev = cur;
    }
    (None, search.touch)
}

/// What a search of one step carries: the evaluations of `g` it may still spend refining, the
/// closest approach to 0 of a dip without a crossing, and the step's width: the time scale of
/// its resolution ([`time_resolution`]).
struct Search {
    budget: usize,
    touch: Option<(f64, f64)>,
    scale: f64,
}

impl Search {
    /// The time resolution at `t` in this step.
    fn resolution(&self, t: f64) -> f64 {
        time_resolution(t, self.scale)
    }

    /// A dip of `g` to `value` at `t`, not below 0, between samples of size up to `size`.
    fn dipped(&mut self, t: f64, value: f64, size: f64) {
        if value <= 1e-6 * size && self.touch.is_none_or(|(_, lowest)| value < lowest) {
            self.touch = Some((t, value));
        }
    }
}

/// The first crossing between two samples `a` and `b` where `g` is positive (or `a` is the
/// step's start, admissible), each with its slope if known.
///
/// Where `ġ` goes from − to +, the dip is located ([`dip`]). Then the cubic `H` through the
/// values and slopes at `a` and `b` is checked at the midpoint: it matches `g` at both ends,
/// and its error grows like `s²(1−s)²` (`s` the fraction of the interval) to its largest near
/// the midpoint, where the misfit measures it. Where `H` minus twice that error profile stays
/// positive, `g` is clear of 0; elsewhere the halves are searched in turn, within `budget`
/// evaluations of `g`. Without slopes, only the sign at the samples counts.
fn between(
    a: f64,
    ga: (f64, Option<f64>),
    b: f64,
    gb: (f64, Option<f64>),
    g: &mut impl FnMut(f64) -> (f64, Option<f64>),
    search: &mut Search,
) -> Option<Crossing> {
    let (Some(da), Some(db)) = (ga.1, gb.1) else {
        return None;
    };
    if da < 0.0 && db > 0.0 && ga.0 > 0.0 {
        match dip(a, b, g, search.scale) {
            Ok(crossing) => return Some(crossing),
            Err((t, value)) => search.dipped(t, value, ga.0.max(gb.0)),
        }
    }
    let width = b - a;
    // A start on the surface (`g` at its rounding, after an event) that does not clearly leave
    // it (a grazing start, after a lift-off) is left to the samples: near it the guard is
    // rounding noise, and the refinement would find crossings in the noise (the caller takes
    // such a start as admissible). One that leaves it clearly (a rebound: `ġ` there accounts
    // for a thousandth or more of the change up to `b`, and for a thousand times the start's
    // offset from 0, so that halving towards the start stops before its rounding counts) is
    // searched as any other interval: after a rebound the body may come back and go through
    // the surface before the next sample (a ball bouncing off a cylinder, where no return is
    // predicted to bound the step).
    let scale = gb.0 + width * db.abs();
    let rise = da * width;
    let leaving = rise >= 1e-3 * scale && rise >= 1e3 * ga.0.abs();
    let on_surface = ga.0 <= 1e-9 * scale && !leaving;
    if on_surface || search.budget == 0 || width <= search.resolution(b) {
        return None;
    }
    search.budget -= 1;
    let m = a + 0.5 * width;
    let gm = g(m);
    if gm.0 <= 0.0 || gm.0.is_nan() {
        return Some(first_in(a, ga, m, gm, g, search));
    }
    let fit = Fit::new(ga.0, gb.0, da * width, db * width, gm.0);
    if fit.clear_up_to(1.0, search.resolution(b) / width) {
        return None;
    }
    between(a, ga, m, gm, g, search).or_else(|| between(m, gm, b, gb, g, search))
}

/// The first crossing in `(a, b]`, where `g(a) > 0 ≥ g(b)` (or `a` is the step's start,
/// admissible).
///
/// The sign change brackets a crossing, but not always the first: over a crest, `g` may dip
/// below 0 and come back before it falls for good, and [`bracket`] may close on either. The
/// midpoint tells: where the cubic through the ends' values and slopes, with the error profile
/// its misfit there measures (see [`between`]), shows the first half clear of 0, the crossing
/// is in the second: bracketed there where the cubic does not turn in it, else searched like
/// the whole. Elsewhere the first half is searched, then the second. Without slopes, from a
/// start on the surface, or out of `budget`, it brackets `(a, b]` at once.
fn first_in(
    a: f64,
    ga: (f64, Option<f64>),
    b: f64,
    gb: (f64, Option<f64>),
    g: &mut impl FnMut(f64) -> (f64, Option<f64>),
    search: &mut Search,
) -> Crossing {
    let width = b - a;
    let (Some(da), Some(db)) = (ga.1, gb.1) else {
        return bracket(a, ga, b, gb, g);
    };
    // As in `between`: near a start on the surface the guard is rounding noise.
    let on_surface = ga.0 <= 1e-9 * (ga.0 - gb.0 + width * db.abs());
    if on_surface || search.budget == 0 || width <= search.resolution(b) {
        return bracket(a, ga, b, gb, g);
    }
    search.budget -= 1;
    let m = a + 0.5 * width;
    let gm = g(m);
    if gm.0 <= 0.0 || gm.0.is_nan() {
        return first_in(a, ga, m, gm, g, search);
    }
    let fit = Fit::new(ga.0, gb.0, da * width, db * width, gm.0);
    if fit.clear_up_to(0.5, search.resolution(b) / width) {
        // Where the cubic turns in the second half, so may the guard: search it likewise.
        return if fit.monotone_from(0.5) {
            bracket(m, gm, b, gb, g)
        } else {
            first_in(m, gm, b, gb, g, search)
        };
    }
    match between(a, ga, m, gm, g, search) {
        Some(crossing) => crossing,
        // Out of evaluations before the first half was shown clear: any crossing in (a, b].
        None if search.budget == 0 => bracket(a, ga, b, gb, g),
        None => first_in(m, gm, b, gb, g, search),
    }
}

/// The cubic Hermite interpolant `H` of `g` on an interval (`s ∈ [0, 1]`) through the values
/// `p0`, `p1` and slopes `m0`, `m1` (per unit `s`) at its ends, and how far `g` at the midpoint
/// is from it.
struct Fit {
    p0: f64,
    p1: f64,
    m0: f64,
    m1: f64,
    misfit: f64,
}

impl Fit {
    fn new(p0: f64, p1: f64, m0: f64, m1: f64, g_mid: f64) -> Self {
        let misfit = (g_mid - hermite(p0, p1, m0, m1, 0.5).0).abs();
        Self {
            p0,
            p1,
            m0,
            m1,
            misfit,
        }
    }

    /// Whether `H` has no turning point on `(from, 1)`: `H'` keeps its sign there.
    fn monotone_from(&self, from: f64) -> bool {
        let Fit { p0, p1, m0, m1, .. } = *self;
        let (alpha, beta) = slope_coefficients(p0, p1, m0, m1);
        let slope = |s: f64| (3.0 * alpha * s + 2.0 * beta) * s + m0;
        // A quadratic changes sign on (from, 1) only at a root there: test the ends and its
        // vertex (where it may touch 0 without a sign change at the ends).
        let (at_from, at_end) = (slope(from), slope(1.0));
        let vertex = -beta / (3.0 * alpha);
        let turns_inside = alpha != 0.0
            && vertex > from
            && vertex < 1.0
            && slope(vertex).signum() != at_from.signum();
        at_from.signum() == at_end.signum() && !turns_inside
    }

    /// Whether `g` is clear of 0 on `[0, upto]` (`upto` in `(0, 1]`): `H` matches `g` at both
    /// ends, and its error grows like `s²(1−s)²` to its largest near the midpoint, where the
    /// misfit measures it. Clear where `H` minus twice the error profile `16 misfit s²(1−s)²`
    /// stays positive: sampled finely (`H` is a cubic) and at `H`'s interior minimum, where a
    /// near miss would be (unless it is within `resolution` of an end: a start on the surface
    /// whose `ġ` rounds to −1e-17).
    fn clear_up_to(&self, upto: f64, resolution: f64) -> bool {
        let Fit {
            p0,
            p1,
            m0,
            m1,
            misfit,
        } = *self;
        let cubic = |s: f64| hermite(p0, p1, m0, m1, s).0;
        let clear = |s: f64| cubic(s) - 32.0 * misfit * (s * (1.0 - s)).powi(2) > 0.0;
        let minimum = cubic_minimum(p0, p1, m0, m1).filter(|&s| s < upto);
        // At once where H's least value on [0, upto] (at an end or at its one interior minimum)
        // exceeds the profile's largest, 2 misfit at s = ½: then every sample below is clear
        // too. (Each compared on its own: a NaN anywhere fails the test.)
        let profile = 2.0 * misfit;
        if p0 > profile && cubic(upto) > profile && minimum.is_none_or(|s| cubic(s) > profile) {
            return true;
        }
        let minimum = minimum.filter(|s| s.min(1.0 - s) > resolution);
        let samples = (1..32).map(|k| upto * f64::from(k) / 32.0);
        samples.chain(minimum).all(clear)
    }
}

/// The cubic Hermite interpolant on `s ∈ [0, 1]` with values `p0`, `p1` and slopes `m0`, `m1`
/// at 0 and 1: its value and slope at `s`.
fn hermite(p0: f64, p1: f64, m0: f64, m1: f64, s: f64) -> (f64, f64) {
    let (s2, s3) = (s * s, s * s * s);
    let value = (2.0 * s3 - 3.0 * s2 + 1.0) * p0
        + (s3 - 2.0 * s2 + s) * m0
        + (-2.0 * s3 + 3.0 * s2) * p1
        + (s3 - s2) * m1;
    let slope = (6.0 * s2 - 6.0 * s) * p0
        + (3.0 * s2 - 4.0 * s + 1.0) * m0
        + (-6.0 * s2 + 6.0 * s) * p1
        + (3.0 * s2 - 2.0 * s) * m1;
    (value, slope)
}

/// The root in `(a, b)` of the cubic Hermite interpolant with values `ga > 0 ≥ gb` and slopes
/// `da`, `db` at `a` and `b` (it has one: it changes sign), by Newton's method kept inside the
/// sign change.
fn cubic_root(a: f64, ga: f64, da: f64, b: f64, gb: f64, db: f64) -> f64 {
    let w = b - a;
    let quarter_ulp = 0.25 * (b.next_up() - b);
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut s = ga / (ga - gb);
    // Newton converges quadratically from the secant's start: a few steps reach rounding.
    for _ in 0..8 {
        let (value, slope) = hermite(ga, gb, da * w, db * w, s);
        if value > 0.0 {
            lo = s;
        } else {
            hi = s;
        }
        let newton = s - value / slope;
        let next = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        // Done when the step moves the time by under a quarter of an ulp.
        let done = (next - s).abs() * w <= quarter_ulp;
        s = next;
        if done {
            break;
        }
    }
    a + s * w
}

/// `(α, β)` of the slope `H'(s) = 3α s² + 2β s + m0` of the cubic Hermite interpolant with
/// values `p0`, `p1` and slopes `m0`, `m1` at 0 and 1.
fn slope_coefficients(p0: f64, p1: f64, m0: f64, m1: f64) -> (f64, f64) {
    let alpha = 2.0 * p0 + m0 - 2.0 * p1 + m1;
    let beta = -3.0 * p0 - 2.0 * m0 + 3.0 * p1 - m1;
    (alpha, beta)
}

/// The interior local minimum `s ∈ (0, 1)` of the cubic Hermite interpolant with values `p0`,
/// `p1` and slopes `m0`, `m1` at 0 and 1, if it has one.
fn cubic_minimum(p0: f64, p1: f64, m0: f64, m1: f64) -> Option<f64> {
    let (alpha, beta) = slope_coefficients(p0, p1, m0, m1);
    let (qa, qb, qc) = (3.0 * alpha, 2.0 * beta, m0);
    let roots = if qa.abs() <= 1e-12 * (qb.abs() + qc.abs()) {
        [(qb != 0.0).then(|| -qc / qb), None]
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc < 0.0 {
            [None, None]
        } else {
            let r = disc.sqrt();
            [Some((-qb - r) / (2.0 * qa)), Some((-qb + r) / (2.0 * qa))]
        }
    };
    // A minimum where H'' = 6α s + 2β > 0.
    roots
        .into_iter()
        .flatten()
        .find(|&s| s > 0.0 && s < 1.0 && 6.0 * alpha * s + 2.0 * beta > 0.0)
}

/// Locates the minimum of `g` between `a` (`ġ < 0`) and `b` (`ġ > 0`), to the time resolution
/// on the time scale `scale`, and brackets a crossing before it if the minimum is `≤ 0`; else
/// the minimum found, `(t, g(t))`.
fn dip(
    a: f64,
    b: f64,
    g: &mut impl FnMut(f64) -> (f64, Option<f64>),
    scale: f64,
) -> Result<Crossing, (f64, f64)> {
    let (mut lo, mut hi) = (a, b);
    for _ in 0..200 {
        if hi - lo <= time_resolution(hi, scale) {
            break;
        }
        let mid = 0.5 * (lo + hi);
        let (value, slope) = g(mid);
        if value <= 0.0 {
            return Ok(bracket(a, g(a), mid, (value, slope), g));
        }
        match slope {
            Some(s) if s < 0.0 => lo = mid,
            _ => hi = mid,
        }
    }
    let last = g(hi);
    if last.0 <= 0.0 {
        Ok(bracket(a, g(a), hi, last, g))
    } else {
        Err((hi, last.0))
    }
}

/// Narrows `[a, b]` with `gb = g(b) ≤ 0` to a crossing at round-off width. If `g(a) ≤ 0` too (a
/// start on the surface), it first probes towards `a` for an admissible point; with none, the
/// crossing is at `a` itself.
///
/// Each trial is the root of the cubic through the values and slopes at both ends, moved an ulp
/// past it away from the latest trial (where `g` has no finite slope: the secant through the
/// last two trials, moved past its root by [`SECANT_MARGIN`] of its step). The cubic is accurate
/// to the fourth power of the bracket's width, so the bracket closes from both sides in a few
/// evaluations instead of creeping in from one (Illinois' regula falsi, used before, took two to
/// four times as many). It bisects when a pair of trials did not halve the bracket, or when
/// trials land a few ulps from an end twice running. Where `g(b)` is exactly 0 (a guard flat at
/// its rounding, or at 0 over a stretch), it searches back from `b`, doubling the distance at
/// each further zero at `b`, up to the midpoint.
fn bracket(
    a: f64,
    ga: (f64, Option<f64>),
    b: f64,
    gb: (f64, Option<f64>),
    g: &mut impl FnMut(f64) -> (f64, Option<f64>),
) -> Crossing {
    let (mut a, mut ga, mut b, mut gb) = (a, ga, b, gb);
    if ga.0 <= 0.0 {
        let mut probe = b;
        let mut found = false;
        for _ in 0..80 {
            probe = a + 0.5 * (probe - a);
            if probe <= a {
                break;
            }
            let gp = g(probe);
            if gp.0 > 0.0 {
                // The crossing is after this admissible point; search (probe, b].
                a = probe;
                ga = gp;
                found = true;
                break;
            }
            b = probe;
            gb = gp;
        }
        if !found {
            return Crossing {
                t_admissible: a,
                t_violating: a,
            };
        }
    }
    // The latest point and the one before it, for the secant.
    let (mut p, mut gp) = if gb.0.abs() <= ga.0.abs() {
        (b, gb)
    } else {
        (a, ga)
    };
    let (mut r, mut gr) = if p == b { (a, ga.0) } else { (b, gb.0) };
    let mut width_before = b - a;
    // A trial within a few ulps of an end at the last iteration (the estimates crawl there), and
    // how many violating trials in a row gave exactly 0.
    let mut crawled = false;
    let mut zeros: i32 = 0;
    for iteration in 0..300 {
        // Down to adjacent floats: short flights near a Zeno point are timed to an ulp.
        let mid = 0.5 * (a + b);
        if mid <= a || mid >= b || mid.is_nan() {
            break;
        }
        let bisect = iteration % 2 == 1 && b - a > 0.5 * width_before;
        if iteration % 2 == 1 {
            width_before = b - a;
        }
        let (estimate, margin) = match (ga.1, gb.1) {
            _ if bisect => (mid, 0.0),
            // `g(b)` is exactly 0, and may be so over a stretch (rounding, or a guard flat at 0):
            // the last admissible time is before it. Search back from `b` (or from where the
            // slope at `a` puts the root, if before), doubling the distance at each zero.
            _ if gb.0 == 0.0 => {
                let from = match ga.1 {
                    Some(da) if da < 0.0 => b.min(a - ga.0 / da),
                    _ => b,
                };
                let back = (b.next_up() - b) * 2f64.powi(zeros.min(1000));
                ((from - back).max(mid), 0.0)
            }
            (Some(da), Some(db)) if (da * (b - a)).is_finite() && (db * (b - a)).is_finite() => {
                (cubic_root(a, ga.0, da, b, gb.0, db), 0.0)
            }
            _ => {
                let secant = p - gp.0 * (p - r) / (gp.0 - gr);
                (secant, SECANT_MARGIN * (secant - p).abs())
            }
        };
        let estimate = if estimate.is_nan() {
            mid
        } else {
            estimate.clamp(a.next_up(), b.next_down())
        };
        // Past the estimate, away from the latest point: a good estimate then closes the
        // bracket from the other side too.
        let past = if estimate > p {
            (estimate + margin).max(estimate.next_up())
        } else {
            (estimate - margin).min(estimate.next_down())
        };
        let t = if past > a && past < b { past } else { estimate };
        let crawl = gb.0 != 0.0 && (t - a).min(b - t) <= 4.0 * (b.next_up() - b);
        let t = if crawl && crawled { mid } else { t };
        crawled = crawl && t != mid;
        let gt = g(t);
        (r, gr, p, gp) = (p, gp.0, t, gt);
        if gt.0 > 0.0 {
            a = t;
            ga = gt;
        } else {
            b = t;
            gb = gt;
            zeros = if gt.0 == 0.0 { zeros + 1 } else { 0 };
        }
    }
    Crossing {
        t_admissible: a,
        t_violating: b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parabola(t0: f64, v: f64, acc: f64) -> impl FnMut(f64) -> (f64, Option<f64>) {
        move |t| {
            let s = t - t0;
            (v * s + 0.5 * acc * s * s, Some(v + acc * s))
        }
    }

    #[test]
    fn finds_a_sign_change_at_round_off() {
        // g = 1 - t², root at 1 (closed form).
        let c = first_crossing(0.0, 3.0, |t| (1.0 - t * t, Some(-2.0 * t))).unwrap();
        assert!(c.t_admissible <= 1.0 && c.t_violating >= 1.0);
        assert!((c.t_admissible - 1.0).abs() < 1e-14);
        assert!(1.0 - c.t_admissible * c.t_admissible >= 0.0);
    }

    #[test]
    fn finds_a_whole_flight_inside_one_step() {
        // Starts at 0 on the surface moving out, lands at 2v/g = 0.2, and is up again by t1.
        // Sign at the ends: g(0) = 0, g(1) > 0 after a second "flight" through the floor.
        let g = |t: f64| {
            let (v, a) = (1.0, -10.0);
            let land = 2.0 * v / -a;
            if t <= land {
                (v * t + 0.5 * a * t * t, Some(v + a * t))
            } else {
                // A mirror image: without the dip search this crossing is invisible.
                let s = t - land;
                (-v * s + 0.5 * 20.0 * s * s, Some(-v + 20.0 * s))
            }
        };
        let c = first_crossing(0.0, 1.0, g).expect("the landing at t = 0.2 must be found");
        assert!((c.t_admissible - 0.2).abs() < 1e-13, "{c:?}");
    }

    #[test]
    fn a_step_that_starts_just_below_the_surface_is_not_an_event_at_its_start() {
        // After a reset: g(t0) = −1e-17 but moving out; the real landing is at t0 + 2v/|a|.
        let t0 = 2.0;
        let mut g = parabola(t0, 1e-3, -9.81);
        let mut shifted = move |t: f64| {
            let (v, d) = g(t);
            (v - 1e-17, d)
        };
        let c = first_crossing(t0, t0 + 1.0, &mut shifted).unwrap();
        let landing = t0 + 2.0 * 1e-3 / 9.81;
        assert!(
            (c.t_admissible - landing).abs() < 1e-12,
            "{c:?} vs {landing}"
        );
    }

    #[test]
    fn a_start_moving_into_the_surface_is_an_event_at_the_start() {
        let c = first_crossing(1.0, 2.0, parabola(1.0, -1.0, -1.0)).unwrap();
        assert_eq!(c.t_admissible, 1.0);
    }

    #[test]
    fn no_crossing_no_event() {
        assert!(first_crossing(0.0, 1.0, |t| (1.0 + t, Some(1.0))).is_none());
        // A dip that stays positive.
        assert!(first_crossing(0.0, 1.0, |t| (
            (t - 0.5).powi(2) + 1e-6,
            Some(2.0 * (t - 0.5))
        ))
        .is_none());
    }

    /// `g = 0.05 + 0.3 t − 0.2 sin(2π t/0.3)` dips to −0.128 near t = 0.07, between the
    /// samples at 0 and 0.25 of the step [0, 1], where `ġ` is −3.9 and −1.8: no sign change of
    /// `g` or `ġ` shows it (the guard of a long flight over a wavy surface).
    #[test]
    fn finds_a_dip_between_two_samples_whose_slopes_agree() {
        let w = 2.0 * std::f64::consts::PI / 0.3;
        let g = |t: f64| {
            let value = 0.05 + 0.3 * t - 0.2 * (w * t).sin();
            (value, Some(0.3 - 0.2 * w * (w * t).cos()))
        };
        assert!(g(0.25).0 > 0.0 && g(0.25).1.unwrap() < 0.0);
        let c = first_crossing(0.0, 1.0, g).expect("the dip must be found");
        assert!(
            g(c.t_admissible).0 > 0.0 && g(c.t_violating).0 <= 0.0,
            "{c:?}"
        );
        assert!(c.t_violating - c.t_admissible <= time_resolution(1.0, 1.0));
        // The first root, 0.0131 by a scan: g is positive on [0, t] before it.
        assert!((c.t_admissible - 0.0131).abs() < 1e-3, "{c:?}");
        assert!((0..1000).all(|k| g(c.t_admissible * f64::from(k) / 1000.0).0 > 0.0));
    }

    /// `g = −100 (t − r1)(t − r2)(t − r3)` with its slope: positive before `r1`, below 0 on
    /// `(r1, r2)`, positive again until `r3`.
    fn three_roots(r1: f64, r2: f64, r3: f64) -> impl Fn(f64) -> (f64, Option<f64>) {
        move |t| {
            let value = -100.0 * (t - r1) * (t - r2) * (t - r3);
            let slope = -100.0 * ((t - r2) * (t - r3) + (t - r1) * (t - r3) + (t - r1) * (t - r2));
            (value, Some(slope))
        }
    }

    /// The first crossing of [`three_roots`] on the step [0, 1] is at `r1`, to an ulp.
    fn first_of_three_roots(r1: f64, r2: f64, r3: f64) {
        let g = three_roots(r1, r2, r3);
        let c = first_crossing(0.0, 1.0, &g).expect("a crossing");
        assert!(
            g(c.t_admissible).0 > 0.0 && g(c.t_violating).0 <= 0.0,
            "{c:?}"
        );
        assert!((c.t_admissible - r1).abs() <= 4.0 * f64::EPSILON, "{c:?}");
    }

    /// Roots 0.53, 0.56, 0.72: the guard is positive at the samples 0, 0.25 and 0.5 of the
    /// step [0, 1] and negative at 0.75, but dips below 0 on (0.53, 0.56) before its last fall
    /// at 0.72. The sign change between 0.5 and 0.75 brackets three roots, and the first
    /// crossing is the first of them (a flight over a crest that touches the slope beyond it).
    #[test]
    fn a_dip_before_the_sign_change_is_the_first_crossing() {
        let g = three_roots(0.53, 0.56, 0.72);
        assert!([0.0, 0.25, 0.5].iter().all(|&t| g(t).0 > 0.0) && g(0.75).0 < 0.0);
        first_of_three_roots(0.53, 0.56, 0.72);
    }

    /// The same with the three roots in the second half of the bracketing interval (0.66,
    /// 0.68, 0.74 between the samples 0.5 and 0.75): its first half is clear, and the cubic
    /// turns in the second (bracketing that half at once closed on 0.74).
    #[test]
    fn a_dip_in_the_second_half_is_the_first_crossing_too() {
        let g = three_roots(0.66, 0.68, 0.74);
        assert!(g(0.5).0 > 0.0 && g(0.625).0 > 0.0 && g(0.75).0 < 0.0);
        first_of_three_roots(0.66, 0.68, 0.74);
    }

    #[test]
    fn a_guard_clear_of_zero_costs_one_more_evaluation_per_sample() {
        // Rising from 1, and from 1e-9 (the cubic fits a quadratic exactly): each interval needs
        // its midpoint only, 5 samples and 4 midpoints.
        for offset in [1.0, 1e-9] {
            let mut evaluations = 0;
            let crossing = first_crossing(0.0, 1.0, |t| {
                evaluations += 1;
                (offset + t + t * t, Some(1.0 + 2.0 * t))
            });
            assert!(crossing.is_none());
            assert_eq!(evaluations, 9, "from {offset}");
        }
    }

    #[test]
    fn the_root_is_on_the_admissible_side_for_tiny_flights() {
        // A flight of 1e-12 s at t ≈ 2: the root must bracket the landing and stay admissible.
        let t0 = 2.0;
        let v = 4.905e-12;
        let mut g = parabola(t0, v, -9.81);
        let c = first_crossing(t0, t0 + 1e-9, &mut g).unwrap();
        assert!(g(c.t_admissible).0 >= 0.0);
        assert!((c.t_admissible - (t0 + 1e-12)).abs() < 1e-15);
    }

    /// Evaluations of `g` by [`first_crossing`] on `[t0, t1]`, and the crossing.
    fn counted(
        t0: f64,
        t1: f64,
        mut g: impl FnMut(f64) -> (f64, Option<f64>),
    ) -> (usize, Crossing) {
        let mut evaluations = 0;
        let crossing = first_crossing(t0, t1, |t| {
            evaluations += 1;
            g(t)
        })
        .expect("a crossing");
        (evaluations, crossing)
    }

    /// The evaluations of a search that finds no crossing.
    fn counted_none(t0: f64, t1: f64, mut g: impl FnMut(f64) -> (f64, Option<f64>)) -> usize {
        let mut evaluations = 0;
        let crossing = first_crossing(t0, t1, |t| {
            evaluations += 1;
            g(t)
        });
        assert!(crossing.is_none(), "{crossing:?}");
        evaluations
    }

    fn adjacent(c: Crossing) -> bool {
        c.t_violating == c.t_admissible.next_up()
    }

    /// A landing of a ball over a sine (the paper's surface): `g = y(t) − sin x(t)`, located to
    /// adjacent floats with a handful of evaluations after the samples, the bracket closing from
    /// both sides of the root.
    #[test]
    fn a_smooth_landing_is_closed_from_both_sides_in_a_few_evaluations() {
        for (x_dot, y0) in [(0.3, 1.5), (2.0, 0.9), (-1.2, 1.1)] {
            let g = move |t: f64| {
                let (x, y, y_dot) = (1.0 + x_dot * t, y0 - 4.905 * t * t, -9.81 * t);
                (y - x.sin(), Some(y_dot - x.cos() * x_dot))
            };
            let (evaluations, c) = counted(0.0, 1.0, g);
            assert!(g(c.t_admissible).0 > 0.0 && g(c.t_violating).0 <= 0.0);
            assert!(adjacent(c), "{c:?}");
            // Samples included; Illinois' regula falsi took 14, 36 and 14 here.
            assert!(evaluations <= 13, "{evaluations} evaluations for {c:?}");
        }
    }

    /// A rebound off the surface that comes back through it before the step's first sample
    /// (`g = t (t − 0.1) (t − 0.15)` from `g(0) = 0`, `ġ(0) > 0`; the samples at 1/4, 1/2, 3/4
    /// and 1 are all positive): the first interval is searched like the others.
    #[test]
    fn a_rebound_that_comes_back_before_the_first_sample_is_found() {
        let g = |t: f64| {
            let value = t * (t - 0.1) * (t - 0.15);
            let slope = (t - 0.1) * (t - 0.15) + t * (t - 0.15) + t * (t - 0.1);
            (value, Some(slope))
        };
        let (_, c) = counted(0.0, 1.0, g);
        assert!((c.t_admissible - 0.1).abs() < 1e-14, "{c:?}");
        assert!(
            g(c.t_admissible).0 > 0.0 && g(c.t_violating).0 <= 0.0,
            "{c:?}"
        );
        // The same from just below the surface (a start at its rounding): found all the same,
        // and not at the start.
        let below = |t: f64| {
            let (value, slope) = g(t);
            (value - 1e-17, slope)
        };
        let (_, c) = counted(0.0, 1.0, below);
        assert!((c.t_admissible - 0.1).abs() < 1e-14, "{c:?}");
        // A rebound that does not come back before the step ends is no crossing, and costs at
        // most one evaluation more than the samples and their clearance checks.
        let rebound = |t: f64| (1e-3 * t - 0.5 * 9.81 * t * t - 1e-17, Some(1e-3 - 9.81 * t));
        let evaluations = counted_none(0.0, 1e-4, rebound);
        assert!(evaluations <= 5 + 3 + 1, "{evaluations} evaluations");
    }

    /// The same without slopes (the lift-off guard has none): the secant, pushed past its root.
    #[test]
    fn a_guard_without_slopes_is_closed_to_adjacent_floats() {
        let (evaluations, c) = counted(0.0, 1.0, |t| (0.7 - t * t - 0.1 * t.sin(), None));
        assert!(adjacent(c), "{c:?}");
        // The root of 0.7 − t² − 0.1 sin t, by bisection in f64 (Python) to adjacent floats.
        assert!((c.t_admissible - 0.7929425397263993).abs() < 1e-15);
        assert!(evaluations <= 5 + 12, "{evaluations}");
    }

    /// A guard that is exactly 0 past a kink (a constraint met at its rounding over a stretch):
    /// the last admissible time is the kink, found by searching back from the zeros, halving at
    /// the midpoint.
    #[test]
    fn a_guard_flat_at_zero_is_bisected_to_its_edge() {
        let edge = 0.4;
        let g = |t: f64| {
            let d = (edge - t).max(0.0);
            (d * d, Some(-2.0 * d))
        };
        let (evaluations, c) = counted(0.0, 1.0, g);
        assert!(adjacent(c), "{c:?}");
        assert!((c.t_admissible - edge).abs() < 1e-15, "{c:?}");
        // Bisection from the samples' width 1/4 down to an ulp of 0.4 is 53 halvings.
        assert!(evaluations <= 5 + 2 * 53, "{evaluations}");
    }

    /// Slopes that are NaN or infinite say nothing: the secant takes over, and the bracket still
    /// closes to adjacent floats (a root at 1e-12, where the ulp is 2e-28).
    #[test]
    fn a_guard_with_useless_slopes_is_closed_by_the_secant() {
        for slope in [f64::NAN, f64::INFINITY] {
            let (_, c) = counted(0.0, 1.0, |t| (1e-12 - t, Some(slope)));
            assert!(adjacent(c), "{c:?}");
            assert!(c.t_admissible < 1e-12 && c.t_violating >= 1e-12, "{c:?}");
        }
    }

    /// A NaN start is no time: no crossing from it, and no panic.
    #[test]
    fn a_nan_start_does_not_panic() {
        let guard = |t: f64| (if t >= 1.0 { 0.0 } else { 1.0 }, None);
        assert_eq!(first_crossing(f64::NAN, 1.0, guard), None);
        // An infinite start makes NaN samples: it ends without a panic either.
        let _ = first_crossing(f64::NEG_INFINITY, 1.0, guard);
    }
}
