//! A hybrid Lagrangian whose `L`, `h`, forces, dissipation and optional `R∞` are compiled
//! formulas of the time, the coordinates and the velocities.

use std::sync::OnceLock;

use zenosim::{Compiled, Constraint, HybridLagrangian, Scalar};

use crate::expr::Expression;

/// A model read from a file: a [`HybridLagrangian`] whose functions are compiled formulas.
///
/// The formulas read the coordinates from slots `0..n`, the velocities from slots `n..2n` and
/// the time `t` from slot `2n` ([`FileModel::time_slot`]); the parameters are folded into them
/// as constants. A formula that does not read `t` is evaluated exactly as it was before time
/// existed ([`Expression::eval_at`] runs it as [`Expression::eval_split`]), so an autonomous
/// model gives the same numbers, bit for bit. Their derivatives are traced once into
/// straight-line programs ([`Compiled`]), which zenosim runs instead of differentiating the
/// formulas at every step. Build one with [`crate::parse_model`].
#[derive(Clone, Debug)]
pub struct FileModel {
    pub(crate) coordinates: Vec<String>,
    pub(crate) lagrangian: Expression,
    pub(crate) constraints: Vec<Constraint>,
    pub(crate) h: Vec<Expression>,
    /// Per constraint, the user's `R∞`: (target slot, formula) pairs, evaluated together.
    pub(crate) resets: Vec<Vec<(usize, Expression)>>,
    /// Per constraint with friction, its slip velocity `s(t, q, q̇)`.
    pub(crate) slips: Vec<Option<Vec<Expression>>>,
    /// The generalized forces of `[forces]`: (coordinate index, formula), in the file's order,
    /// one per coordinate at most.
    pub(crate) forces: Vec<(usize, Expression)>,
    /// The Rayleigh dissipation function `D(t, q, q̇)`, if any.
    pub(crate) dissipation: Option<Expression>,
    /// Whether no formula reads `t` and there is no force and no dissipation
    /// ([`HybridLagrangian::is_autonomous`]), found once in [`FileModel::new`].
    pub(crate) autonomous: bool,
    /// The derivatives traced into programs ([`Compiled`]), set once the model is checked.
    pub(crate) compiled: Option<Compiled>,
    /// Whether the compiled free motion is constant ([`HybridLagrangian::parabolic_flight`]): a
    /// fact of the formulas, kept when the model is [`FileModel::interpreted`].
    pub(crate) parabolic: bool,
    /// The first formula whose evaluation took a trace past its budget, for the loader's
    /// message (a `OnceLock`, not a cell, so that the model stays `Sync`).
    pub(crate) over_budget_in: OnceLock<Formula>,
}

/// One of a [`FileModel`]'s formulas.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Formula {
    Lagrangian,
    Dissipation,
    /// Constraint `index`'s `h`.
    Constraint(usize),
    /// The force on coordinate `index`.
    Force(usize),
}

/// A `[[constraint]]` of a [`FileModel`]: the constraint, its `h`, its `zeno_reset`
/// (target slot, formula) pairs, empty when it has none, and its slip where it has friction.
pub(crate) type ConstraintParts = (
    Constraint,
    Expression,
    Vec<(usize, Expression)>,
    Option<Vec<Expression>>,
);

impl FileModel {
    /// The model of these formulas, not compiled yet (set [`FileModel::compiled`] and
    /// [`FileModel::parabolic`] once it is checked). Whether it is autonomous is found here.
    pub(crate) fn new(
        coordinates: Vec<String>,
        lagrangian: Expression,
        constraints: Vec<ConstraintParts>,
        forces: Vec<(usize, Expression)>,
        dissipation: Option<Expression>,
    ) -> Self {
        let mut model = Self {
            coordinates,
            lagrangian,
            constraints: Vec::with_capacity(constraints.len()),
            h: Vec::with_capacity(constraints.len()),
            resets: Vec::with_capacity(constraints.len()),
            slips: Vec::with_capacity(constraints.len()),
            forces,
            dissipation,
            autonomous: true,
            compiled: None,
            parabolic: false,
            over_budget_in: OnceLock::new(),
        };
        for (constraint, h, reset, slip) in constraints {
            model.constraints.push(constraint);
            model.h.push(h);
            model.resets.push(reset);
            model.slips.push(slip);
        }
        let t = model.time_slot();
        let timed = model.lagrangian.reads(t)
            || model.h.iter().any(|h| h.reads(t))
            || model.resets.iter().flatten().any(|(_, f)| f.reads(t))
            || model.slips.iter().flatten().flatten().any(|f| f.reads(t));
        model.autonomous = !timed && model.forces.is_empty() && model.dissipation.is_none();
        model
    }

    /// The slot formulas read the time `t` from: `2n`, after the coordinates (`0..n`) and the
    /// velocities (`n..2n`).
    pub fn time_slot(&self) -> usize {
        2 * self.coordinates.len()
    }

    /// The Lagrangian's formula.
    pub fn lagrangian_formula(&self) -> &Expression {
        &self.lagrangian
    }

    /// Constraint `index`'s formula `h`.
    pub fn constraint_formula(&self, index: usize) -> &Expression {
        &self.h[index]
    }

    /// The formula of the generalized force on coordinate `coordinate` (its index), if
    /// `[forces]` gives one (a coordinate it does not list gets none: 0).
    pub fn force_formula(&self, coordinate: usize) -> Option<&Expression> {
        self.forces
            .iter()
            .find(|(slot, _)| *slot == coordinate)
            .map(|(_, formula)| formula)
    }

    /// The formula of the Rayleigh dissipation function `D(t, q, q̇)`, if the file gives one.
    pub fn dissipation_formula(&self) -> Option<&Expression> {
        self.dissipation.as_ref()
    }

    /// The model without its compiled derivatives: zenosim then differentiates the formulas at
    /// every step, as the interpreter evaluates them (slower; for comparisons).
    pub fn interpreted(mut self) -> Self {
        self.compiled = None;
        self
    }

    /// The compiled derivatives, if any.
    pub fn compiled_derivatives(&self) -> Option<&Compiled> {
        self.compiled.as_ref()
    }

    /// Whether constraint `index` has its own `zeno_reset` map.
    pub fn has_zeno_reset(&self, index: usize) -> bool {
        !self.resets[index].is_empty()
    }

    /// Whether the free motion's forces are what the traced free motion shows: no `t` in `L`,
    /// no dissipation, and every force a constant. Only then can a constant traced free motion
    /// be a parabola ([`HybridLagrangian::parabolic_flight`]).
    pub(crate) fn forces_are_constant(&self) -> bool {
        !self.lagrangian.reads(self.time_slot())
            && self.dissipation.is_none()
            && self
                .forces
                .iter()
                .all(|(_, f)| f.constant_value().is_some())
    }
}

/// Whether a trace of the derivatives is past its budget ([`Compiled::trace_bounded`]): what
/// it still traces is discarded, so the formulas are not evaluated (a model at the limit is
/// refused within the time the budget allows, not after every remaining evaluation). Over
/// `f64` nothing is traced, and nothing is asked: `f64` is the one [`Scalar`] with no
/// derivative and its size (the traced real, which zenosim keeps private, has neither a
/// derivative nor that size), so the question is settled when the code is compiled.
#[inline(always)]
fn over_budget<D: Scalar>() -> bool {
    (D::NDERIV > 0 || size_of::<D>() != size_of::<f64>()) && Compiled::trace_exhausted()
}

impl FileModel {
    /// `value`, the result of evaluating `formula`; if that took the trace past its budget,
    /// `formula` is noted as where it did ([`FileModel::over_budget_in`]).
    #[inline(always)]
    fn noting<D: Scalar, R>(&self, formula: Formula, value: R) -> R {
        if over_budget::<D>() {
            // An earlier formula, if one was noted, keeps its place.
            let _ = self.over_budget_in.set(formula);
        }
        value
    }
}

impl HybridLagrangian for FileModel {
    fn dimension(&self) -> usize {
        self.coordinates.len()
    }

    /// `L` at `t = 0` (the same at every `t` for a Lagrangian without `t`).
    #[inline]
    fn lagrangian<D: Scalar>(&self, q: &[D], q_dot: &[D]) -> D {
        self.lagrangian_at(D::from(0.0), q, q_dot)
    }

    #[inline]
    fn lagrangian_at<D: Scalar>(&self, t: D, q: &[D], q_dot: &[D]) -> D {
        if over_budget::<D>() {
            return D::from(f64::NAN);
        }
        self.noting::<D, _>(Formula::Lagrangian, self.lagrangian.eval_at(q, q_dot, t))
    }

    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }

    /// `h` at `t = 0` (the same at every `t` for a constraint without `t`).
    #[inline]
    fn constraint<D: Scalar>(&self, index: usize, q: &[D]) -> D {
        self.constraint_at(index, D::from(0.0), q)
    }

    /// `h` reads no velocity: with `q` alone before it, its time slot `2n` is past the end.
    #[inline]
    fn constraint_at<D: Scalar>(&self, index: usize, t: D, q: &[D]) -> D {
        if over_budget::<D>() {
            return D::from(f64::NAN);
        }
        self.noting::<D, _>(Formula::Constraint(index), self.h[index].eval_at(q, &[], t))
    }

    /// Adds each formula of `[forces]` to its coordinate's entry.
    #[inline]
    fn generalized_force<D: Scalar>(&self, t: D, q: &[D], q_dot: &[D], force: &mut [D]) {
        if over_budget::<D>() {
            return;
        }
        for (slot, formula) in &self.forces {
            force[*slot] +=
                self.noting::<D, _>(Formula::Force(*slot), formula.eval_at(q, q_dot, t));
        }
    }

    #[inline]
    fn dissipation<D: Scalar>(&self, t: D, q: &[D], q_dot: &[D]) -> D {
        if over_budget::<D>() {
            return D::from(f64::NAN);
        }
        match &self.dissipation {
            Some(formula) => {
                self.noting::<D, _>(Formula::Dissipation, formula.eval_at(q, q_dot, t))
            }
            None => D::from(0.0),
        }
    }

    /// Component `component` of the file's `slip` of constraint `index` (0 where it has none).
    #[inline]
    fn slip<D: Scalar>(&self, index: usize, component: usize, t: D, q: &[D], q_dot: &[D]) -> D {
        match self.slips[index].as_ref().and_then(|s| s.get(component)) {
            Some(formula) => formula.eval_at(q, q_dot, t),
            None => D::from(0.0),
        }
    }

    fn slip_components(&self, index: usize) -> usize {
        self.slips[index].as_ref().map_or(1, Vec::len)
    }

    fn is_autonomous(&self) -> bool {
        self.autonomous
    }

    fn compiled(&self) -> Option<&Compiled> {
        self.compiled.as_ref()
    }

    fn parabolic_flight(&self) -> bool {
        self.parabolic
    }

    fn coordinate_names(&self) -> Vec<String> {
        self.coordinates.clone()
    }

    /// The file's `zeno_reset` at `t = 0`.
    fn completion_map(&self, index: usize, q: &mut [f64], q_dot: &mut [f64]) -> bool {
        self.completion_map_at(index, 0.0, q, q_dot)
    }

    /// The file's `zeno_reset` at the time `t`: every formula is evaluated at the state before
    /// the map, then all are assigned; names it does not give keep their values.
    fn completion_map_at(&self, index: usize, t: f64, q: &mut [f64], q_dot: &mut [f64]) -> bool {
        let resets = &self.resets[index];
        if resets.is_empty() {
            return false;
        }
        let values: Vec<(usize, f64)> = resets
            .iter()
            .map(|(slot, formula)| (*slot, formula.eval_at(&*q, &*q_dot, t)))
            .collect();
        let n = q.len();
        for (slot, value) in values {
            if slot < n {
                q[slot] = value;
            } else {
                q_dot[slot - n] = value;
            }
        }
        true
    }
}
