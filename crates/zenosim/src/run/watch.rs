//! The Zeno watch: the impacts that may be accumulating, kept across the run's events, from
//! which law 3 (docs/contact-laws.md) predicts where an accumulation ends.

use crate::execution::ActiveSet;
use crate::zeno::{Accumulation, ImpactSequence};

/// Events in a row that may not advance time before the run treats them as chattering.
pub(super) const STUCK_EVENTS: usize = 32;

/// What the run watches for Zeno points: the sequence of impacts on one constraint, the
/// accumulation over several, and whether events still advance time.
#[derive(Default)]
pub(super) struct ZenoWatch {
    /// The impacts accumulating on one constraint (a new constraint starts it anew).
    pub sequence: ImpactSequence,
    /// The impacts of a sequence that may accumulate over several constraints.
    pub accumulation: Accumulation,
    /// The time of the last event that [`ZenoWatch::no_progress`] saw.
    last_event_t: f64,
    /// How many events in a row did not advance time.
    stuck: usize,
}

impl ZenoWatch {
    pub fn new() -> Self {
        Self {
            last_event_t: f64::NEG_INFINITY,
            ..Self::default()
        }
    }

    /// An impact reaching `constraint` at `t`.
    pub fn record(&mut self, constraint: usize, t: f64) {
        self.sequence.record(constraint, t);
        self.accumulation.record(constraint, t);
    }

    /// Whether an impact on `constraint` now would be the first of its sequence: no impact on
    /// it since the last switch or lift-off, or another constraint's since.
    pub fn first_on(&self, constraint: usize) -> bool {
        self.sequence.count() == 0 || self.sequence.constraint() != Some(constraint)
    }

    /// Forgets everything (after a lift-off).
    pub fn clear(&mut self) {
        self.sequence.clear();
        self.accumulation.clear();
    }

    /// After a Zeno point whose switch holds `held`: the sequence ends, and the accumulation
    /// ends where the switch holds all of its constraints. Where it holds only part of them (a
    /// ball in a groove that came to rest on one wall, sliding into the vertex, where it strikes
    /// the other), the wider accumulation goes on through the Zeno point of its part, and law
    /// 3 keeps its impacts to predict where it ends.
    pub fn switched(&mut self, held: ActiveSet) {
        self.sequence.clear();
        if self.accumulation.constraints().minus(held).is_empty() {
            self.accumulation.clear();
        }
    }

    /// Events that do not advance time, an event at `t` with the run's time resolution
    /// `resolution` there: after [`STUCK_EVENTS`] in a row the contact is chattering.
    pub fn no_progress(&mut self, t: f64, resolution: f64) -> bool {
        if t - self.last_event_t <= resolution {
            self.stuck += 1;
        } else {
            self.stuck = 0;
        }
        self.last_event_t = t;
        self.stuck >= STUCK_EVENTS
    }
}
