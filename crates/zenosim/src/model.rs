//! WHAT moves: the hybrid Lagrangian `(Q, L, h)` a user writes once.

use num_dual::DualNum;

use crate::compiled::Compiled;

/// A number the model's functions are evaluated with: `f64`, or one of num-dual's dual numbers.
///
/// Write `L` and `h` once, generic over `D: Scalar`; zenosim evaluates them over dual numbers to
/// get every derivative exactly. `D * f64`, `D + f64`, `d.sin()`, `d.powi(2)` … all work; a literal
/// on the left (`2.0 * d`) does not, so write `d * 2.0`.
pub trait Scalar: DualNum<Primitive = f64> + Copy {}

impl<T: DualNum<Primitive = f64> + Copy> Scalar for T {}

/// Coulomb friction at a constraint's contact (docs/friction.md): a sticking contact holds while
/// its tangential force is within `μₛ` times its normal force; a slipping one is opposed by
/// `μₖ` times it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Friction {
    /// The static coefficient `μₛ ≥ μₖ`.
    pub static_coefficient: f64,
    /// The kinetic coefficient `μₖ ≥ 0`.
    pub kinetic_coefficient: f64,
}

impl Friction {
    /// Coulomb's law with one coefficient `μ`, static and kinetic alike.
    pub fn coulomb(mu: f64) -> Self {
        Self {
            static_coefficient: mu,
            kinetic_coefficient: mu,
        }
    }
}

/// One unilateral constraint `h(q) ≥ 0` of a model, with its coefficient of restitution and,
/// where its contact has friction, its friction coefficients.
#[derive(Clone, Debug, PartialEq)]
pub struct Constraint {
    /// A name, unique within the model (used in records and messages).
    pub name: String,
    /// The coefficient of restitution `e`, `0 ≤ e ≤ 1` (checked when a simulation is set up).
    pub restitution: f64,
    /// Coulomb friction at the contact; its slip velocity is
    /// [`HybridLagrangian::slip`]. `None`: frictionless.
    pub friction: Option<Friction>,
}

impl Constraint {
    /// A frictionless constraint with the given name and restitution.
    pub fn new(name: impl Into<String>, restitution: f64) -> Self {
        Self {
            name: name.into(),
            restitution,
            friction: None,
        }
    }

    /// The constraint with Coulomb friction `friction` at its contact.
    pub fn with_friction(self, friction: Friction) -> Self {
        Self {
            friction: Some(friction),
            ..self
        }
    }

    /// Whether its contact has friction: a coefficient above 0 (both 0 is frictionless,
    /// docs/friction.md).
    pub fn has_friction(&self) -> bool {
        self.friction
            .is_some_and(|f| f.static_coefficient > 0.0 || f.kinetic_coefficient > 0.0)
    }
}

/// A simple hybrid Lagrangian `(Q, L, h)` (Ames et al. 2006, Definition 1), with one or more
/// unilateral constraints.
///
/// `L` must be hyperregular: `M = ∂²L/∂q̇²` positive definite wherever the execution goes.
///
/// Mark `lagrangian` and `constraint` `#[inline]`: they are evaluated a dozen times per
/// right-hand side over different dual numbers, and inlined the compiler folds most of that
/// work away (the paper's ball runs about three times faster).
/// Everything else (the Euler–Lagrange equations, `A = ∂h/∂q`, `Ȧ q̇`, the impact map, the
/// constrained dynamics, the energy) is derived from these two functions by automatic
/// differentiation.
pub trait HybridLagrangian {
    /// The number of coordinates when the type fixes it; `None` (the default) when only
    /// [`Self::dimension`] knows it. [`Self::dimension`] must then return it (a simulation
    /// refuses a model whose two disagree).
    ///
    /// zenosim compiles its mechanics once for every dimension a model type may have: up to
    /// [`crate::MAX_DIMENSION`] times, or once where this says which. Set it on a model of
    /// fixed size to build faster.
    const DIMENSION: Option<usize> = None;

    /// The number of coordinates `n = dim Q` (at most [`crate::MAX_DIMENSION`]).
    fn dimension(&self) -> usize;

    /// The Lagrangian `L(q, q̇)`; `q` and `q_dot` have [`Self::dimension`] entries.
    fn lagrangian<D: Scalar>(&self, q: &[D], q_dot: &[D]) -> D;

    /// The unilateral constraints; `h_i(q) ≥ 0` is the admissible side of constraint `i`.
    fn constraints(&self) -> &[Constraint];

    /// The constraint function `h_index(q)`.
    fn constraint<D: Scalar>(&self, index: usize, q: &[D]) -> D;

    /// The Lagrangian `L(t, q, q̇)` at time `t`. Default: [`Self::lagrangian`], which does not
    /// depend on `t`. A model whose `L` does implements this and returns `false` from
    /// [`Self::is_autonomous`].
    #[inline]
    fn lagrangian_at<D: Scalar>(&self, _t: D, q: &[D], q_dot: &[D]) -> D {
        self.lagrangian(q, q_dot)
    }

    /// The constraint function `h_index(t, q)` of a surface that may move. Default:
    /// [`Self::constraint`]. A model whose surfaces move implements this and returns `false`
    /// from [`Self::is_autonomous`].
    #[inline]
    fn constraint_at<D: Scalar>(&self, index: usize, _t: D, q: &[D]) -> D {
        self.constraint(index, q)
    }

    /// Adds the generalized force `Q(t, q, q̇)` (motor torques, feedback laws, drives, drag) to
    /// `force` (`n` entries): `M q̈ = ∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t + Q`. Default: none. A
    /// model with forces returns `false` from [`Self::is_autonomous`].
    #[inline]
    fn generalized_force<D: Scalar>(&self, _t: D, _q: &[D], _q_dot: &[D], _force: &mut [D]) {}

    /// A Rayleigh dissipation function `D(t, q, q̇)`, whose force `−∂D/∂q̇` zenosim derives and
    /// adds to [`Self::generalized_force`]. Default: none (zero). A model with one returns
    /// `false` from [`Self::is_autonomous`].
    #[inline]
    fn dissipation<D: Scalar>(&self, _t: D, _q: &[D], _q_dot: &[D]) -> D {
        D::zero()
    }

    /// Component `component` of the slip velocity `s(t, q, q̇)` of constraint `index`'s contact
    /// (docs/friction.md): the relative tangential velocity of the contact points, affine in
    /// `q̇` (`s = S(t, q) q̇ + s₀(t, q)`), one component for a contact in a plane, two for a
    /// contact in space ([`Self::slip_components`]; along two orthonormal tangent directions,
    /// so that the isotropic cone is `|fₜ| ≤ μ fₙ` in them). Only constraints with
    /// [`Constraint::friction`] are asked. Default: 0 (no friction anywhere).
    #[inline]
    fn slip<D: Scalar>(
        &self,
        _index: usize,
        _component: usize,
        _t: D,
        _q: &[D],
        _q_dot: &[D],
    ) -> D {
        D::zero()
    }

    /// How many components constraint `index`'s slip has: 1 for a contact in a plane (the
    /// default), 2 for a contact in space.
    #[inline]
    fn slip_components(&self, _index: usize) -> usize {
        1
    }

    /// Whether the model is an autonomous, conservative hybrid Lagrangian: no `t` in `L` or in
    /// any `h`, no generalized force, no dissipation (the default, `true`). Return `false`
    /// when any of those is present: zenosim then takes the time derivatives of the
    /// constraints, adds the forces, and accounts for the work done (a simulation checks at
    /// its start that an autonomous model's functions do not depend on `t` and that it has no
    /// force, and refuses one that does).
    fn is_autonomous(&self) -> bool {
        true
    }

    /// The coordinates' names, for records and messages. Default: `q1, q2, …`.
    fn coordinate_names(&self) -> Vec<String> {
        (1..=self.dimension()).map(|i| format!("q{i}")).collect()
    }

    /// The model's own completion map `R∞` for constraint `index` (the paper writes one per
    /// example), applied in place. Return `false` (the default) when the model has none.
    ///
    /// It is used only with [`crate::Completion::ModelMap`]; zenosim then still projects the
    /// result onto `h = 0, A q̇ = 0` so that the constrained phase starts on the constraint.
    fn completion_map(&self, _index: usize, _q: &mut [f64], _q_dot: &mut [f64]) -> bool {
        false
    }

    /// [`Self::completion_map`] at time `t`, for a map that depends on it. Default: the map
    /// without `t`.
    fn completion_map_at(&self, index: usize, _t: f64, q: &mut [f64], q_dot: &mut [f64]) -> bool {
        self.completion_map(index, q, q_dot)
    }

    /// The model's derivatives traced ahead of time, which zenosim then runs instead of
    /// differentiating `lagrangian` and `constraint` at every step; `None` (the default)
    /// differentiates.
    ///
    /// Worth it for a model whose functions are expensive over dual numbers (interpreted
    /// formulas): build one [`Compiled::trace`] when the model is made and return it here. The
    /// results are the same, bit for bit (up to the sign of a zero).
    fn compiled(&self) -> Option<&Compiled> {
        None
    }

    /// Whether free flight is a parabola in time: the free motion's acceleration `M⁻¹ f` is the
    /// same at every state (a constant `M` and constant forces, such as a point mass in
    /// Cartesian coordinates under gravity).
    ///
    /// zenosim then steps free flight on the parabola in closed form (`q + h (q̇ + h q̈ / 2)`,
    /// `q̇ + h q̈`: one evaluation, at the step's end, instead of twelve for a DOP853 step), and
    /// reads the states inside a step off its cubic Hermite interpolant, which is exact on a
    /// parabola (instead of preparing the dense output and stepping again to each impact). It
    /// checks at every step that the acceleration is the same, to the bit, at both of its ends,
    /// and takes the general route where it is not: there, a wrong declaration costs one
    /// evaluation per free step and changes nothing else. The check sees the ends only: a
    /// force that is the same at both ends of a step but not between them (piecewise constant,
    /// left and met again within the step) would pass it, so declare this only where it holds.
    ///
    /// Default: what the [`Compiled`] derivatives show (the free motion traced to constants);
    /// `false` without them. Declare it on a Rust model whose free flight is a parabola so that
    /// it runs as its model file does.
    fn parabolic_flight(&self) -> bool {
        self.compiled().is_some_and(Compiled::constant_free_motion)
    }
}
