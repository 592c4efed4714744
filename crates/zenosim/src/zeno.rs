//! Recognising a Zeno execution and predicting its Zeno time `τ∞`.
//!
//! Two estimates, used together:
//! - from the physics of the post-impact state: the next flight lasts `Δ̂ = 2 A q̇⁺ / |ḧ_free|`
//!   (exact for a flat floor, first order in `Δ̂` otherwise), and the flights after it shrink by
//!   `e`, so the remaining time is `Δ̂ / (1 − e)`;
//! - from the measured flight times (REFERENCE §2): their ratio `r` tends to `e` for a genuinely
//!   Zeno execution, and is reported with each Zeno point as a diagnostic.

use crate::events::time_resolution;
use crate::execution::ZenoKind;

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

    /// The ratio of successive flight times: the geometric mean over the last
    /// [`RATIO_BASELINE`] flights (fewer early in a sequence), once there are three impacts.
    pub fn ratio(&self) -> Option<f64> {
        if self.count < 3 {
            return None;
        }
        let span = (self.count - 2).min(RATIO_BASELINE);
        let newest = RATIO_BASELINE + 1;
        let last = self.times[newest] - self.times[newest - 1];
        let first = self.times[newest - span] - self.times[newest - span - 1];
        (first > 0.0 && last >= 0.0).then(|| (last / first).powf(1.0 / span as f64))
    }
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

    /// Chattering when the next interval is below what `f64` time resolves at `t` (or `e = 0`),
    /// genuine otherwise.
    pub fn kind(&self, e: f64, t: f64) -> ZenoKind {
        if e > 0.0 && self.next_flight > time_resolution(t) {
            ZenoKind::Genuine
        } else {
            ZenoKind::Chattering
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_prediction_is_exact_for_a_flat_floor() {
        // Ball at v⁺ = 2 m/s up, g = 9.81: next flight 2v/g, the rest a geometric series
        // with ratio e (closed form).
        let p = Prediction::new(2.0, -9.81, 0.5, (0.0, 0.0)).unwrap();
        assert!((p.next_flight - 4.0 / 9.81).abs() < 1e-15);
        assert!((p.remaining - 2.0 * 4.0 / 9.81).abs() < 1e-15);
        assert_eq!(p.kind(0.5, 1.0), ZenoKind::Genuine);
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
        assert_eq!(p.kind(0.0, 1.0), ZenoKind::Chattering);
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
}
