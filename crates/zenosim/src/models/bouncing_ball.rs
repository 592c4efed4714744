use crate::model::{Constraint, HybridLagrangian, Scalar};

/// The classic bouncing ball: `L = ½ m ẋ² − m g x`, `h = x`.
///
/// Dropped from rest at height `h0`, its impacts come at
/// `τ_k = t1 (1 + 2e (1 − e^(k−1))/(1 − e))` and accumulate at `τ∞ = t1 (1+e)/(1−e)`,
/// `t1 = √(2 h0/g)` (closed form, REFERENCE §3).
#[derive(Clone, Debug, PartialEq)]
pub struct BouncingBall {
    /// Mass `m`.
    pub mass: f64,
    /// Gravity `g`.
    pub gravity: f64,
    constraints: [Constraint; 1],
}

impl BouncingBall {
    /// A ball of mass `mass` under gravity `gravity` with restitution `restitution`.
    pub fn new(mass: f64, gravity: f64, restitution: f64) -> Self {
        Self {
            mass,
            gravity,
            constraints: [Constraint::new("floor", restitution)],
        }
    }

    /// The closed-form Zeno time when dropped from rest at `h0`.
    pub fn zeno_time(&self, h0: f64) -> f64 {
        let e = self.constraints[0].restitution;
        (2.0 * h0 / self.gravity).sqrt() * (1.0 + e) / (1.0 - e)
    }

    /// The closed-form time of impact `k ≥ 1` when dropped from rest at `h0`.
    pub fn impact_time(&self, h0: f64, k: u32) -> f64 {
        let e = self.constraints[0].restitution;
        let t1 = (2.0 * h0 / self.gravity).sqrt();
        t1 * (1.0 + 2.0 * e * (1.0 - e.powi(k as i32 - 1)) / (1.0 - e))
    }
}

impl HybridLagrangian for BouncingBall {
    const DIMENSION: Option<usize> = Some(1);
    fn dimension(&self) -> usize {
        1
    }

    #[inline]
    fn lagrangian<D: Scalar>(&self, q: &[D], q_dot: &[D]) -> D {
        q_dot[0] * q_dot[0] * (0.5 * self.mass) - q[0] * (self.mass * self.gravity)
    }

    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }

    #[inline]
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[0]
    }

    fn coordinate_names(&self) -> Vec<String> {
        vec!["x".into()]
    }

    /// Constant gravity on a point mass.
    fn parabolic_flight(&self) -> bool {
        true
    }
}
