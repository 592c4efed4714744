//! A hybrid Lagrangian whose `L`, `h` and optional `R∞` are compiled formulas.

use zenosim::{Compiled, Constraint, HybridLagrangian, Scalar};

use crate::expr::Expression;

/// A model read from a file: a [`HybridLagrangian`] whose functions are compiled formulas.
///
/// The formulas read the coordinates from slots `0..n` and the velocities from slots `n..2n`;
/// the parameters are folded into them as constants. Their derivatives are traced once into
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
    /// The derivatives traced into programs ([`Compiled`]), set once the model is checked.
    pub(crate) compiled: Option<Compiled>,
    /// Whether the compiled free motion is constant ([`HybridLagrangian::parabolic_flight`]): a
    /// fact of the formulas, kept when the model is [`FileModel::interpreted`].
    pub(crate) parabolic: bool,
}

impl FileModel {
    /// The Lagrangian's formula.
    pub fn lagrangian_formula(&self) -> &Expression {
        &self.lagrangian
    }

    /// Constraint `index`'s formula `h`.
    pub fn constraint_formula(&self, index: usize) -> &Expression {
        &self.h[index]
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
}

impl HybridLagrangian for FileModel {
    fn dimension(&self) -> usize {
        self.coordinates.len()
    }

    #[inline]
    fn lagrangian<D: Scalar>(&self, q: &[D], q_dot: &[D]) -> D {
        self.lagrangian.eval_split(q, q_dot)
    }

    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }

    #[inline]
    fn constraint<D: Scalar>(&self, index: usize, q: &[D]) -> D {
        self.h[index].eval(q)
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

    /// The file's `zeno_reset`: every formula is evaluated at the state before the map, then
    /// all are assigned; names it does not give keep their values.
    fn completion_map(&self, index: usize, q: &mut [f64], q_dot: &mut [f64]) -> bool {
        let resets = &self.resets[index];
        if resets.is_empty() {
            return false;
        }
        let values: Vec<(usize, f64)> = resets
            .iter()
            .map(|(slot, formula)| (*slot, formula.eval_split(&*q, &*q_dot)))
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
