//! WHEN a guard is crossed: detection and location of a root on a step's dense output.
//!
//! The traps of REFERENCE §4, and what this module does about each:
//! - a whole flight inside one step (no sign change at the step's ends): the guard is sampled
//!   inside the step, and between two positive samples where `ġ` goes from − to + the minimum
//!   itself is located and tested;
//! - a step that starts on the surface (`g = −1e-17` after a reset): the start is taken as
//!   admissible, and the first admissible point after it is probed for before bracketing;
//! - the root is reported on the admissible side (`g ≥ 0` there).

/// Interior samples per step (the guard is smooth on the dense output, and dips between
/// samples are caught through `ġ`).
pub(crate) const SAMPLES_PER_STEP: usize = 4;

/// A bracketed crossing `g(t_admissible) > 0 ≥ g(t_violating)`, `t_violating − t_admissible`
/// at round-off.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Crossing {
    /// The last time on the admissible side: where the event is reported.
    pub t_admissible: f64,
    /// The first time on the other side.
    pub t_violating: f64,
}

/// The time resolution of `f64` at `t`: intervals shorter than this cannot be told apart.
pub(crate) fn time_resolution(t: f64) -> f64 {
    64.0 * f64::EPSILON * t.abs().max(1.0)
}

/// The first crossing of `g` from `> 0` to `≤ 0` in `(t0, t1]`.
///
/// `g(t)` returns the guard and, when known, its time derivative (`None` disables the search
/// for dips between samples). The start `t0` is taken as admissible whatever `g(t0)` says: the
/// caller only ever starts a step from an admissible state.
pub(crate) fn first_crossing(
    t0: f64,
    t1: f64,
    mut g: impl FnMut(f64) -> (f64, Option<f64>),
) -> Option<Crossing> {
    if t1 <= t0 {
        return None;
    }
    let n = SAMPLES_PER_STEP;
    let mut prev_t = t0;
    let mut prev = g(t0);
    for k in 1..=n {
        let t = if k == n {
            t1
        } else {
            t0 + (t1 - t0) * (k as f64 / n as f64)
        };
        let cur = g(t);
        if cur.0 <= 0.0 || cur.0.is_nan() {
            return Some(bracket(prev_t, prev.0, t, &mut g));
        }
        // Both ends positive: a dip in between shows as ġ going from − to +.
        if let (Some(d0), Some(d1)) = (prev.1, cur.1) {
            if d0 < 0.0 && d1 > 0.0 && prev.0 > 0.0 {
                if let Some(crossing) = dip(prev_t, t, &mut g) {
                    return Some(crossing);
                }
            }
        }
        prev_t = t;
        prev = cur;
    }
    None
}

/// Locates the minimum of `g` between `a` (`ġ < 0`) and `b` (`ġ > 0`) and brackets a crossing
/// before it if the minimum is `≤ 0`.
fn dip(a: f64, b: f64, g: &mut impl FnMut(f64) -> (f64, Option<f64>)) -> Option<Crossing> {
    let (mut lo, mut hi) = (a, b);
    for _ in 0..200 {
        if hi - lo <= time_resolution(hi) {
            break;
        }
        let mid = 0.5 * (lo + hi);
        let (value, slope) = g(mid);
        if value <= 0.0 {
            return Some(bracket(a, g(a).0, mid, g));
        }
        match slope {
            Some(s) if s < 0.0 => lo = mid,
            _ => hi = mid,
        }
    }
    let (value, _) = g(hi);
    (value <= 0.0).then(|| bracket(a, g(a).0, hi, g))
}

/// Narrows `[a, b]` with `g(b) ≤ 0` to a crossing at round-off width. If `g(a) ≤ 0` too (a start
/// on the surface), it first probes towards `a` for an admissible point; with none, the crossing
/// is at `a` itself.
fn bracket(a: f64, ga: f64, b: f64, g: &mut impl FnMut(f64) -> (f64, Option<f64>)) -> Crossing {
    let (mut a, mut ga, mut b) = (a, ga, b);
    if ga <= 0.0 {
        let mut probe = b;
        let mut found = false;
        for _ in 0..80 {
            probe = a + 0.5 * (probe - a);
            if probe <= a {
                break;
            }
            let gp = g(probe).0;
            if gp > 0.0 {
                // The crossing is after this admissible point; search (probe, b].
                a = probe;
                ga = gp;
                found = true;
                break;
            }
            b = probe;
        }
        if !found {
            return Crossing {
                t_admissible: a,
                t_violating: a,
            };
        }
    }
    let mut gb = g(b).0;
    // Illinois (modified regula falsi); a bisection whenever two steps did not halve the bracket.
    let mut side = 0i8;
    let mut width_before = b - a;
    for iteration in 0..300 {
        // Down to adjacent floats: short flights near a Zeno point are timed to an ulp.
        let mid = 0.5 * (a + b);
        if mid <= a || mid >= b {
            break;
        }
        let secant = b - gb * (b - a) / (gb - ga);
        let bisect = iteration % 2 == 1 && b - a > 0.5 * width_before;
        if iteration % 2 == 1 {
            width_before = b - a;
        }
        let t = if !bisect && secant > a && secant < b {
            secant
        } else {
            0.5 * (a + b)
        };
        let gt = g(t).0;
        if gt > 0.0 {
            a = t;
            ga = gt;
            if side == 1 {
                gb *= 0.5;
            }
            side = 1;
        } else {
            b = t;
            gb = gt;
            if side == -1 {
                ga *= 0.5;
            }
            side = -1;
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
}
