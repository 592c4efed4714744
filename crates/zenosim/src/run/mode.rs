//! The mode logic's transitions: which constraints are free and which held, and in which
//! friction states, and every change of that applied in one place ([`Runner::apply`]), then
//! the integrator restarted in the new mode ([`Runner::resume`]).
//!
//! The decisions (which law acts, whether a Zeno point is reached, which constraints hold,
//! stick or slip) are made by the files of each situation (`impact.rs`, `completion.rs`,
//! `held.rs`); they end in a [`Transition`], which this file records: the event with the states
//! before and after, the interval it ends, the Zeno watch, the new mode.

use super::record::Change;
use super::Runner;
use crate::error::Error;
use crate::execution::{ActiveSet, EventKind, Grips, Mode, ZenoPoint};
use crate::model::HybridLagrangian;
use crate::observer::Observer;

/// A change of mode, with what it records.
pub(super) enum Transition {
    /// An impact reaching constraint `reached`, acting on `contacts` with the impulses
    /// `impulses` (pushing, in the set's order) and, with friction, the tangential impulses
    /// `tangential`; its loss and work are set aside from the law
    /// ([`crate::contact::ImpactLaw`]).
    Impact {
        reached: usize,
        contacts: ActiveSet,
        impulses: Vec<f64>,
        tangential: Vec<[f64; 2]>,
    },
    /// The switch through `R∞` at a Zeno point (the point, with the set it puts the state on).
    Zeno(ZenoPoint),
    /// The constraints `gone` let go (the one `named` first among them).
    Liftoff { named: usize, gone: ActiveSet },
    /// Held contacts changed their friction state (docs/friction.md): `kind` is
    /// [`EventKind::Stick`] where they stopped slipping, [`EventKind::Slip`] where they started
    /// (or reversed); `changed` are those contacts, `named` the first.
    Grip {
        kind: EventKind,
        named: usize,
        changed: ActiveSet,
    },
}

/// The mode that holds `set`: free where it is empty.
pub(super) fn holding(set: ActiveSet) -> Mode {
    if set.is_empty() {
        Mode::Free
    } else {
        Mode::Constrained(set)
    }
}

impl<L: HybridLagrangian, O: Observer> Runner<'_, '_, L, O> {
    /// Applies `transition` at `t`, from `before` (in the current mode) to `after` (in `mode`,
    /// its held contacts in the friction states `grips`): records the event, closes the
    /// current interval, keeps the Zeno watch and the counts, and makes `mode` current. The
    /// integrator is restarted by [`Runner::resume`].
    pub(super) fn apply(
        &mut self,
        transition: Transition,
        t: f64,
        before: &[f64],
        after: &[f64],
        mode: Mode,
        grips: Grips,
    ) -> Result<(), Error> {
        let grips = grips.within(self.held_in(mode));
        match transition {
            Transition::Impact {
                reached,
                contacts,
                impulses,
                tangential,
            } => {
                let change = Change {
                    contacts,
                    impulses,
                    tangential,
                };
                let kind = EventKind::Impact;
                self.record_event(kind, reached, change, t, before, after, mode, grips)?;
                self.record.impacts += 1;
                self.watch.record(reached, t);
            }
            Transition::Zeno(point) => {
                let (constraint, set) = (point.constraint, point.constraints);
                self.record.zeno.push(point);
                self.watch.switched(self.held_in(mode));
                let change = Change::of(set);
                let kind = EventKind::Zeno;
                self.record_event(kind, constraint, change, t, before, after, mode, grips)?;
            }
            Transition::Liftoff { named, gone } => {
                let change = Change::of(gone);
                let kind = EventKind::Liftoff;
                self.record_event(kind, named, change, t, before, after, mode, grips)?;
                self.watch.clear();
            }
            Transition::Grip {
                kind,
                named,
                changed,
            } => {
                let change = Change::of(changed);
                self.record_event(kind, named, change, t, before, after, mode, grips)?;
            }
        }
        Ok(())
    }

    /// Restarts the integrator at `(t, y)` in the current mode (with the first step `hint`, or
    /// its own choice), and takes the lift-off test's margin at the mode's start.
    pub(super) fn resume(&mut self, t: f64, y: &[f64], hint: Option<f64>) -> Result<(), Error> {
        self.restart(t, y, hint)?;
        self.enter_mode(t)
    }

    /// The constraints `mode` holds.
    pub(super) fn held_in(&self, mode: Mode) -> ActiveSet {
        match mode {
            Mode::Free => ActiveSet::empty(),
            Mode::Constrained(set) => set,
        }
    }
}
