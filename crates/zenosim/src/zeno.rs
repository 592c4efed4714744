//! Recognising a Zeno execution and predicting its Zeno time `τ∞`.
//!
//! Two estimates, used together:
//! - from the physics of the post-impact state: the next flight lasts `Δ̂ = 2 A q̇⁺ / |ḧ_free|`
//!   (exact for a flat floor, first order in `Δ̂` otherwise), and the flights after it shrink by
//!   `e`, so the remaining time is `Δ̂ / (1 − e)`;
//! - from the measured flight times (REFERENCE §2): their ratio `r` tends to `e` for a genuinely
//!   Zeno execution, and is reported with each Zeno point as a diagnostic.

use crate::execution::{ActiveSet, ZenoKind};

/// Flights over which the ratio is measured: a geometric mean over several flights divides the
/// timing noise of the last (shortest) ones by their number.
const RATIO_BASELINE: usize = 6;

/// The impacts of the sequence that is accumulating on one constraint.
#[derive(Clone, Debug, Default)]
pub(crate) struct ImpactSequence {
    constraint: Option<usize>,
    /// The last impact times, newest last.
    times: [f64; RATIO_BASELINE + 2],
    count: usize,
}

impl ImpactSequence {
    /// Records an impact on `constraint` at `t`; an impact on another constraint starts anew.
    pub fn record(&mut self, constraint: usize, t: f64) {
        if self.constraint != Some(constraint) {
            *self = Self {
                constraint: Some(constraint),
                ..Self::default()
            };
        }
        self.times.rotate_left(1);
        self.times[RATIO_BASELINE + 1] = t;
        self.count += 1;
    }

    /// Forgets the sequence (after a switch or a lift-off).
    pub fn clear(&mut self) {
        *self = Self::default();
    }

    /// Impacts in the sequence.
    pub fn count(&self) -> usize {
        self.count
    }

    /// The constraint the sequence is on, once it has an impact.
    pub fn constraint(&self) -> Option<usize> {
        self.constraint
    }

    /// The ratio of successive flight times: the geometric mean over the last
    /// [`RATIO_BASELINE`] flights (fewer early in a sequence), once there are three impacts.
    pub fn ratio(&self) -> Option<f64> {
        ratio_of(&self.times, self.count)
    }
}

/// The impacts of a sequence that may accumulate over several constraints (docs/contact-laws.md,
/// law 3): the walls of a groove in turn, the corners of a rocking block, or one wall while
/// another constraint holds. Unlike [`ImpactSequence`] it does not start anew when another
/// constraint is reached; the runner clears it after a switch or a lift-off.
#[derive(Clone, Debug, Default)]
pub(crate) struct Accumulation {
    /// The last impact times, newest last, with the constraint each reached.
    times: [f64; RATIO_BASELINE + 2],
    constraints: [usize; RATIO_BASELINE + 2],
    count: usize,
}

impl Accumulation {
    /// Records an impact reaching `constraint` at `t`.
    pub fn record(&mut self, constraint: usize, t: f64) {
        self.times.rotate_left(1);
        self.constraints.rotate_left(1);
        self.times[RATIO_BASELINE + 1] = t;
        self.constraints[RATIO_BASELINE + 1] = constraint;
        self.count += 1;
    }

    /// Forgets the sequence.
    pub fn clear(&mut self) {
        *self = Self::default();
    }

    /// Impacts in the sequence.
    pub fn count(&self) -> usize {
        self.count
    }

    /// The constraints reached by the last impacts (at most [`RATIO_BASELINE`] + 2 of them).
    pub fn constraints(&self) -> ActiveSet {
        let recent = self.count.min(RATIO_BASELINE + 2);
        self.constraints[RATIO_BASELINE + 2 - recent..]
            .iter()
            .fold(ActiveSet::empty(), |set, &i| set.with(i))
    }

    /// The last flight, between the last two impacts.
    pub fn last_flight(&self) -> Option<f64> {
        (self.count >= 2).then(|| self.times[RATIO_BASELINE + 1] - self.times[RATIO_BASELINE])
    }

    /// The ratio of successive flights, as [`ImpactSequence::ratio`] measures it, over the
    /// flights between any constraints' impacts.
    pub fn ratio(&self) -> Option<f64> {
        ratio_of(&self.times, self.count)
    }

    /// The rest of the sequence from the measured ratio `r < 1`: the next flight `r Δ` after the
    /// last one `Δ`, and the remaining time `r Δ / (1 − r)`. `None` without a ratio below 1.
    pub fn predict(&self) -> Option<Prediction> {
        let r = self.ratio()?;
        let last = self.last_flight()?;
        let shrinking = r < 1.0 - 1e-9;
        if !shrinking {
            return None;
        }
        let next_flight = r * last;
        Some(Prediction {
            next_flight,
            remaining: next_flight / (1.0 - r),
        })
    }
}

/// The geometric mean of the ratios of successive flights over the last [`RATIO_BASELINE`]
/// flights of `times` (newest last), once there are three impacts.
fn ratio_of(times: &[f64; RATIO_BASELINE + 2], count: usize) -> Option<f64> {
    if count < 3 {
        return None;
    }
    let span = (count - 2).min(RATIO_BASELINE);
    let newest = RATIO_BASELINE + 1;
    let last = times[newest] - times[newest - 1];
    let first = times[newest - span] - times[newest - span - 1];
    (first > 0.0 && last >= 0.0).then(|| (last / first).powf(1.0 / span as f64))
}

/// What the post-impact state predicts about the rest of a Zeno sequence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Prediction {
    /// The next flight `Δ̂ = 2 v⁺ / |ḧ|`.
    pub next_flight: f64,
    /// The time left to `τ∞`: `Δ̂/(1 − e)` (just `Δ̂` for `e = 1`, where flights do not shrink).
    pub remaining: f64,
}

impl Prediction {
    /// The prediction from the normal velocity `v⁺ = A q̇⁺ ≥ 0` and the free normal acceleration
    /// `ḧ`, each with its rounding error; `None` when the body is not brought back (`ḧ > 0`, or
    /// `ḧ = 0` while it moves away). At rest on the surface with no force either way (both at
    /// rounding level: a plastic impact on a wall parallel to gravity) the intervals are
    /// zero-length: a chattering Zeno point.
    pub fn new(v_plus: f64, h_ddot: f64, e: f64, round_off: (f64, f64)) -> Option<Self> {
        let v_plus = v_plus.max(0.0);
        let (v_round, h_ddot_round) = round_off;
        if h_ddot.abs() <= h_ddot_round {
            return (v_plus <= v_round).then_some(Self {
                next_flight: 0.0,
                remaining: 0.0,
            });
        }
        if h_ddot.is_nan() || h_ddot >= 0.0 {
            return None;
        }
        let next_flight = 2.0 * v_plus / -h_ddot;
        let remaining = if e < 1.0 - 1e-9 {
            next_flight / (1.0 - e)
        } else {
            next_flight
        };
        Some(Self {
            next_flight,
            remaining,
        })
    }

    /// Chattering when the next interval is not longer than `resolution`, the run's time
    /// resolution where it starts ([`crate::events::time_resolution`]), or `e = 0`; genuine otherwise.
    pub fn kind(&self, e: f64, resolution: f64) -> ZenoKind {
        if e > 0.0 && self.next_flight > resolution {
            ZenoKind::Genuine
        } else {
            ZenoKind::Chattering
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::events::time_resolution;

    #[test]
    fn the_prediction_is_exact_for_a_flat_floor() {
        // Ball at v⁺ = 2 m/s up, g = 9.81: next flight 2v/g, the rest a geometric series
        // with ratio e (closed form).
        let p = Prediction::new(2.0, -9.81, 0.5, (0.0, 0.0)).unwrap();
        assert!((p.next_flight - 4.0 / 9.81).abs() < 1e-15);
        assert!((p.remaining - 2.0 * 4.0 / 9.81).abs() < 1e-15);
        assert_eq!(p.kind(0.5, time_resolution(1.0, 1.0)), ZenoKind::Genuine);
    }

    #[test]
    fn no_prediction_when_the_body_is_not_pushed_back() {
        assert!(Prediction::new(1.0, 0.0, 0.5, (0.0, 0.0)).is_none());
        // At rest with no force either way: zero-length intervals; within rounding too.
        assert_eq!(
            Prediction::new(0.0, 0.0, 0.5, (0.0, 0.0))
                .unwrap()
                .remaining,
            0.0
        );
        let p = Prediction::new(1e-18, 2e-16, 0.5, (1e-17, 1e-15)).unwrap();
        assert_eq!(p.remaining, 0.0);
        // Moving away with no force: never back.
        assert!(Prediction::new(1.0, 1e-16, 0.5, (1e-17, 1e-15)).is_none());
        assert!(Prediction::new(1.0, 3.0, 0.5, (0.0, 0.0)).is_none());
        assert!(Prediction::new(1.0, f64::NAN, 0.5, (0.0, 0.0)).is_none());
    }

    #[test]
    fn a_plastic_impact_is_chattering() {
        let p = Prediction::new(0.0, -9.81, 0.0, (0.0, 0.0)).unwrap();
        assert_eq!(p.remaining, 0.0);
        assert_eq!(p.kind(0.0, time_resolution(1.0, 1.0)), ZenoKind::Chattering);
    }

    #[test]
    fn the_measured_ratio_needs_three_impacts_on_one_constraint() {
        let mut s = ImpactSequence::default();
        s.record(0, 1.0);
        s.record(0, 2.0);
        assert_eq!(s.ratio(), None);
        s.record(0, 2.5);
        assert_eq!(s.ratio(), Some(0.5));
        // Flights 1, 0.5, 0.125: the geometric mean of the ratios 0.5 and 0.25.
        s.record(0, 2.625);
        assert!((s.ratio().unwrap() - 0.125_f64.sqrt()).abs() < 1e-15);
        s.record(1, 3.0);
        assert_eq!((s.count(), s.ratio()), (1, None));
    }

    #[test]
    fn an_accumulation_alternates_between_constraints() {
        // Flights 1, 0.5, 0.25 between impacts on constraints 0 and 1 in turn: ratio 0.5, the
        // next flight 0.125 and the rest of the geometric series 0.25 (closed form).
        let mut a = Accumulation::default();
        for (k, t) in [0.0, 1.0, 1.5, 1.75].into_iter().enumerate() {
            a.record(k % 2, t);
        }
        assert_eq!(a.constraints(), ActiveSet::single(0).with(1));
        assert_eq!(a.ratio(), Some(0.5));
        let p = a.predict().unwrap();
        assert_eq!((p.next_flight, p.remaining), (0.125, 0.25));
        // Flights that do not shrink predict nothing.
        a.record(0, 2.0);
        a.record(1, 3.0);
        assert!(a.predict().is_none());
        a.clear();
        assert_eq!((a.count(), a.constraints()), (0, ActiveSet::empty()));
    }
}
