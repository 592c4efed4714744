//! The record of a run: the hybrid time domain, the events, the Zeno points and the outcome
//! (Ames et al. 2006, Definition 3, extended by the completed system's constrained intervals).

use crate::error::Error;

/// A set of constraints (a bit set over constraint indices, at most 64 constraints): the
/// constraints held in a constrained mode, or those involved in an event or a Zeno point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ActiveSet(u64);

impl ActiveSet {
    /// The largest number of constraints a model may have.
    pub const CAPACITY: usize = 64;

    /// No constraint active.
    pub const fn empty() -> Self {
        Self(0)
    }

    /// Only constraint `index` active (panics unless `index < 64`).
    pub const fn single(index: usize) -> Self {
        assert!(
            index < Self::CAPACITY,
            "ActiveSet holds constraints 0 to 63"
        );
        Self(1 << index)
    }

    /// The set with constraint `index` added (panics unless `index < 64`).
    pub const fn with(self, index: usize) -> Self {
        Self(self.0 | Self::single(index).0)
    }

    /// The constraints in either set.
    pub const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    /// The constraints of `self` not in `other`.
    pub const fn minus(self, other: Self) -> Self {
        Self(self.0 & !other.0)
    }

    /// The constraints in both sets.
    pub const fn intersection(self, other: Self) -> Self {
        Self(self.0 & other.0)
    }

    /// Whether no constraint is active.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Whether constraint `index` is active.
    pub const fn contains(self, index: usize) -> bool {
        self.0 & (1 << index) != 0
    }

    /// The number of active constraints.
    pub const fn len(self) -> usize {
        self.0.count_ones() as usize
    }

    /// The active constraint indices, in increasing order.
    pub fn iter(self) -> impl Iterator<Item = usize> {
        (0..Self::CAPACITY).filter(move |&i| self.contains(i))
    }

    /// The single active constraint, if exactly one is active.
    pub fn only(self) -> Option<usize> {
        (self.len() == 1).then(|| self.0.trailing_zeros() as usize)
    }
}

/// The friction states of the held contacts that have friction (docs/friction.md): those that
/// stick (`s = 0`), and those that slip forwards (`s > 0`) or backwards (`s < 0`). A held
/// frictional contact is in exactly one of the three; every other constraint in none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Grips {
    /// The contacts that stick.
    pub stick: ActiveSet,
    /// The contacts that slip with `s > 0` (the friction force opposes it: `fₜ = −μₖ fₙ`).
    pub forward: ActiveSet,
    /// The contacts that slip with `s < 0` (`fₜ = +μₖ fₙ`).
    pub backward: ActiveSet,
}

impl Grips {
    /// No contact sticks or slips.
    pub const fn none() -> Self {
        Self {
            stick: ActiveSet::empty(),
            forward: ActiveSet::empty(),
            backward: ActiveSet::empty(),
        }
    }

    /// The contacts that slip, either way.
    pub const fn slipping(self) -> ActiveSet {
        self.forward.union(self.backward)
    }

    /// The contacts whose friction state is recorded.
    pub const fn all(self) -> ActiveSet {
        self.stick.union(self.slipping())
    }

    /// The direction of contact `index`'s slip: `1.0` forwards, `-1.0` backwards, `0.0`
    /// otherwise.
    pub const fn direction(self, index: usize) -> f64 {
        if self.forward.contains(index) {
            1.0
        } else if self.backward.contains(index) {
            -1.0
        } else {
            0.0
        }
    }

    /// The states restricted to the contacts of `set`.
    pub const fn within(self, set: ActiveSet) -> Self {
        Self {
            stick: self.stick.intersection(set),
            forward: self.forward.intersection(set),
            backward: self.backward.intersection(set),
        }
    }
}

/// The mode of a hybrid interval.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Free flight under the Euler–Lagrange equations of `L`.
    Free,
    /// Motion constrained to `h_i = 0` for the active constraints (the completed system `D∞`).
    Constrained(ActiveSet),
}

impl Mode {
    /// `"free"` or `"constrained"`.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Free => "free",
            Mode::Constrained(_) => "constrained",
        }
    }
}

/// A point `(q, q̇)` of the state space.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// The configuration.
    pub q: Vec<f64>,
    /// The velocities.
    pub q_dot: Vec<f64>,
}

/// One interval `I_i = [τ_i, τ_{i+1}]` of the hybrid time domain and its mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HybridInterval {
    /// `τ_i`.
    pub start: f64,
    /// `τ_{i+1}` (the stop time for the last interval).
    pub end: f64,
    /// The dynamics on this interval.
    pub mode: Mode,
}

/// What happened at an event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventKind {
    /// An impact: `q̇⁺ = P(q, q̇⁻)`.
    Impact,
    /// The switch to the constrained motion at (an approximation of) the Zeno point: `R∞`.
    Zeno,
    /// The contact force vanished (`λ` reached 0): back to free motion.
    Liftoff,
    /// Held contacts with friction stopped slipping and stick (docs/friction.md).
    Stick,
    /// Held contacts with friction started to slip (their tangential force reached the cone),
    /// or reversed their slip.
    Slip,
}

impl EventKind {
    /// `"impact"`, `"zeno"`, `"liftoff"`, `"stick"` or `"slip"`.
    pub fn name(self) -> &'static str {
        match self {
            EventKind::Impact => "impact",
            EventKind::Zeno => "zeno",
            EventKind::Liftoff => "liftoff",
            EventKind::Stick => "stick",
            EventKind::Slip => "slip",
        }
    }
}

/// A discrete transition, with the states just before and just after it.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// Its kind.
    pub kind: EventKind,
    /// When it happened.
    pub t: f64,
    /// The constraint that caused it: the one reached (impact), whose accumulation ended
    /// (Zeno), or that let go (lift-off).
    pub constraint: usize,
    /// Every constraint involved: for an impact, those in the impact law (the one reached, and
    /// every other closed one: `h = 0`, `A q̇⁻ ≤ 0`); for a switch, those `R∞` projects onto;
    /// for a lift-off, those that let go.
    pub contacts: ActiveSet,
    /// For an impact, the impulse `Λᵢ ≥ 0` (pushing) on each constraint of `contacts`, in
    /// increasing index order: `M (q̇⁺ − q̇⁻) = Σ Aᵢᵀ Λᵢ + Sᵢᵀ Λₜ,ᵢ`. Empty for other events.
    pub impulses: Vec<f64>,
    /// For an impact with friction, the tangential impulse `Λₜ,ᵢ` on each constraint of
    /// `contacts` (0 on those without friction; docs/friction.md). Empty where no constraint
    /// of the impact has friction, and for other events. For a contact in space, the first
    /// component (in the model's slip components).
    pub tangential: Vec<f64>,
    /// For an impact on a contact in space, the second component of each tangential impulse,
    /// as [`Self::tangential`]; empty where no contact of the impact is in space.
    pub tangential_across: Vec<f64>,
    /// The friction states of the held contacts after the event (docs/friction.md).
    pub grips: Grips,
    /// The state just before.
    pub before: State,
    /// The state just after.
    pub after: State,
}

/// The two kinds of Zeno execution (Ames et al. 2006, Section III).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ZenoKind {
    /// Zero-length intervals from some impact on (e.g. `e = 0`, or a contact reached at rest).
    Chattering,
    /// Positive intervals shrinking geometrically (ratio → `e`).
    Genuine,
}

impl ZenoKind {
    /// `"chattering"` or `"genuine"`.
    pub fn name(self) -> &'static str {
        match self {
            ZenoKind::Chattering => "chattering",
            ZenoKind::Genuine => "genuine",
        }
    }
}

/// A Zeno point that the execution reached and passed (or stalled at, with `ZenoStrategy::Off`).
#[derive(Clone, Debug, PartialEq)]
pub struct ZenoPoint {
    /// The constraint of the accumulation's last impact.
    pub constraint: usize,
    /// Every constraint of the accumulation (the constraints whose impacts accumulate, and
    /// those held meanwhile): `R∞` puts the state onto all of them.
    pub constraints: ActiveSet,
    /// Chattering or genuinely Zeno.
    pub kind: ZenoKind,
    /// When the simulation switched to the constrained motion (or stopped).
    pub t_switch: f64,
    /// The estimate of the Zeno time `τ∞`.
    pub t_zeno: f64,
    /// Impacts in the accumulating sequence.
    pub impacts: usize,
    /// The measured ratio of successive flight times: the geometric mean over the last six
    /// flights of the sequence (→ `e` for a genuine Zeno execution).
    pub ratio: Option<f64>,
    /// The state after `R∞` (or the last state reached, when stalled).
    pub point: State,
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// It reached the stop time.
    Finished,
    /// `ZenoStrategy::Off`: the plain hybrid system cannot go past the Zeno point.
    ZenoStalled {
        /// The constraint whose impacts accumulate.
        constraint: usize,
        /// The estimate of `τ∞`.
        t_zeno: f64,
    },
    /// A numerical failure; everything up to it is kept.
    Failed(Error),
    /// The observer asked to stop ([`crate::Observer::interrupted`]); everything up to the
    /// current time is kept.
    Interrupted,
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Outcome::Finished => write!(f, "finished"),
            Outcome::ZenoStalled { t_zeno, .. } => {
                write!(f, "stalled at the Zeno point, τ∞ ≈ {t_zeno}")
            }
            Outcome::Failed(error) => write!(f, "failed: {error}"),
            Outcome::Interrupted => write!(f, "interrupted"),
        }
    }
}

/// Work counters of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RunStats {
    /// Accepted integration steps.
    pub steps: u64,
    /// Rejected integration steps.
    pub rejected_steps: u64,
    /// Evaluations of the right-hand side.
    pub rhs_evals: u64,
    /// Impacts applied.
    pub impacts: u64,
    /// Guard crossings rejected as spurious (`A q̇ > 0` at the root).
    pub spurious_events: u64,
}

/// The execution `(Λ, J, C)` of the completed hybrid system, as far as it went.
#[derive(Clone, Debug, PartialEq)]
pub struct Execution {
    /// How the run ended.
    pub outcome: Outcome,
    /// The hybrid time domain: one interval per mode between events.
    pub intervals: Vec<HybridInterval>,
    /// Every event, in time order.
    pub events: Vec<Event>,
    /// Every Zeno point reached.
    pub zeno: Vec<ZenoPoint>,
    /// The last time reached.
    pub t_final: f64,
    /// The last state reached.
    pub final_state: State,
    /// The mode at the end.
    pub final_mode: Mode,
    /// Work counters.
    pub stats: RunStats,
    /// The energy's balance from the start to [`Execution::t_final`].
    pub work: Work,
}

/// The energy balance of a run up to some time (docs/forces-and-time.md):
/// `E(t) − E(0) = forces + drive + constraints − impact_loss`, to the integration tolerance.
///
/// Between events the three works are integrated along the trajectory (Gauss–Legendre on each
/// step's dense output); at an impact its impulses' work and its loss are added from the law.
/// Autonomous, conservative models do no work: only `impact_loss` grows.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Work {
    /// `∫ Q·q̇ dt`: the work of the generalized forces, the dissipation function's included
    /// (negative where they dissipate).
    pub forces: f64,
    /// `−∫ ∂L/∂t dt`: the energy put in by the explicit time dependence of `L` (a prescribed
    /// motion written into the Lagrangian).
    pub drive: f64,
    /// The work of the constraint forces and impulses on surfaces that move: `−∫ λᵢ Aᵢq̇ dt`
    /// while held, and `−Σ Λᵢ ∂ₜhᵢ` at impacts (0 where no surface moves).
    pub constraints: f64,
    /// The energy taken out by impacts, `−½ Σ Λᵢ (ḣᵢ⁺ + ḣᵢ⁻) − ½ Σ Λₜ,ᵢ (sᵢ⁺ + sᵢ⁻) ≥ 0`, and by
    /// the switches at Zeno points (their measured change).
    pub impact_loss: f64,
    /// `∫ Σ fₜ,ᵢ sᵢ dt ≤ 0`: the work of friction at slipping contacts (docs/friction.md).
    pub friction: f64,
}

impl Work {
    /// `forces + drive + constraints + friction − impact_loss`: what `E(t) − E(0)` should be.
    pub fn balance(&self) -> f64 {
        self.forces + self.drive + self.constraints + self.friction - self.impact_loss
    }
}

impl Execution {
    /// The times of the events of `kind`, in order (the lift-offs of a ball on a vibrating
    /// table, its Zeno switches).
    pub fn times_of(&self, kind: EventKind) -> Vec<f64> {
        self.events
            .iter()
            .filter(|e| e.kind == kind)
            .map(|e| e.t)
            .collect()
    }

    /// The times of the impacts that reached constraint `index` (the constraints held at an
    /// impact take part in it too, in [`Event::contacts`], but do not count here).
    pub fn impact_times(&self, index: usize) -> Vec<f64> {
        self.events
            .iter()
            .filter(|e| e.kind == EventKind::Impact && e.constraint == index)
            .map(|e| e.t)
            .collect()
    }
}
