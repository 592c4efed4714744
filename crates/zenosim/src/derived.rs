//! Quantities derived from a model at one state: for checks, reports and tests.

use crate::derivatives::{checked_dimension, energy, guard_along};
use crate::error::Error;
use crate::mechanics::Mechanics;
use crate::model::HybridLagrangian;

/// What zenosim derives from a model's `L` and `h` at a state `(q, q̇)`, by automatic
/// differentiation. The slices must have the model's dimension (the methods panic otherwise).
///
/// ```
/// # use zenosim::{Derived, models::BallOnSine};
/// let ball = BallOnSine::paper().model;
/// let d = Derived::new(&ball).unwrap();
/// let (h, a) = d.constraint(0, &[0.0, 0.0, 1.0]);
/// assert_eq!((h, a), (1.0, vec![0.0, -1.0, 1.0])); // h = x3 − sin x2, A = (0, −cos x2, 1)
/// ```
pub struct Derived<'a, L> {
    mech: Mechanics<'a, L>,
    n: usize,
    t: f64,
}

impl<L> Clone for Derived<'_, L> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<L> Copy for Derived<'_, L> {}

impl<'a, L: HybridLagrangian> Derived<'a, L> {
    /// The derived quantities of `model` (an error if its dimension is 0 or above
    /// [`MAX_DIMENSION`](crate::MAX_DIMENSION), or not the [`HybridLagrangian::DIMENSION`] its
    /// type declares).
    pub fn new(model: &'a L) -> Result<Self, Error> {
        let n = checked_dimension(model)?;
        Ok(Self {
            mech: Mechanics::new(model),
            n,
            t: 0.0,
        })
    }

    /// The same quantities at time `t` (0 until set): for a model whose `L`, `h` or forces
    /// depend on time.
    pub fn at_time(mut self, t: f64) -> Self {
        self.t = t;
        self
    }

    /// The powers that change the energy between impacts, `(Q·q̇, −∂L/∂t)`: the generalized
    /// forces' (with the dissipation function's) and the time dependence of `L`'s
    /// (docs/forces-and-time.md).
    pub fn powers(&self, q: &[f64], q_dot: &[f64]) -> (f64, f64) {
        crate::derivatives::powers(self.mech.model(), self.t, q, q_dot)
    }

    /// The energy `q̇ᵀ ∂L/∂q̇ − L`.
    pub fn energy(&self, q: &[f64], q_dot: &[f64]) -> f64 {
        energy(self.mech.model(), self.t, q, q_dot)
    }

    /// The mass matrix `M = ∂²L/∂q̇²`, row by row (it is symmetric), and whether it is positive
    /// definite.
    pub fn mass_matrix(&self, q: &[f64], q_dot: &[f64]) -> (Vec<f64>, bool) {
        let mut m = vec![0.0; self.n * self.n];
        let positive = self.mech.mass_matrix(self.t, q, q_dot, &mut m).is_ok();
        (m, positive)
    }

    /// `q̈` of the free motion.
    pub fn acceleration(&self, q: &[f64], q_dot: &[f64]) -> Option<Vec<f64>> {
        let mut acc = vec![0.0; self.n];
        self.write_acceleration(None, q, q_dot, &mut acc)?;
        Some(acc)
    }

    /// `q̈` into `q_ddot` without allocating, as the engine evaluates it at every stage of a
    /// step: of the free motion (`active` is `None`), or of the motion constrained to
    /// `h_active = 0`, then returning the multiplier `λ` (0 for the free motion). `None` where
    /// the mechanics fail (`M` not positive definite, `A` vanishing, a value not finite).
    pub fn write_acceleration(
        &self,
        active: Option<usize>,
        q: &[f64],
        q_dot: &[f64],
        q_ddot: &mut [f64],
    ) -> Option<f64> {
        self.mech
            .acceleration(self.t, q, q_dot, active, q_ddot)
            .ok()
    }

    /// `h(t, q)` and `A = ∂h/∂q` of constraint `index`.
    pub fn constraint(&self, index: usize, q: &[f64]) -> (f64, Vec<f64>) {
        let mut a = vec![0.0; self.n];
        let h = self.mech.constraint_gradient(index, self.t, q, &mut a);
        (h, a)
    }

    /// `ḣ = A q̇ + ∂h/∂t`: the rate of `h` (the normal velocity).
    pub fn normal_velocity(&self, index: usize, q: &[f64], q_dot: &[f64]) -> f64 {
        guard_along(self.mech.model(), index, self.t, q, q_dot).1
    }

    /// The multiplier `λ` that holds the motion on constraint `index` (the constraint pushes
    /// while `λ ≤ 0`), or `None` where the mechanics fail (singular `M` or `A`).
    pub fn multiplier(&self, index: usize, q: &[f64], q_dot: &[f64]) -> Option<f64> {
        let mut w = vec![0.0; self.n];
        self.mech
            .normal(index, self.t, q, q_dot, &mut w)
            .ok()
            .map(|normal| normal.lambda())
    }

    /// The general completion `R∞` onto constraint `index`, in place; returns `(|h|, |A q̇|)`
    /// after it, or `None` if it failed.
    pub fn project(&self, index: usize, q: &mut [f64], q_dot: &mut [f64]) -> Option<(f64, f64)> {
        self.mech
            .project(index, self.t, q, q_dot)
            .ok()
            .map(|r| (r.h, r.a_q_dot))
    }
}
