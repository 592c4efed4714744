use super::Example;
use crate::model::{Constraint, HybridLagrangian, Scalar};
use std::f64::consts::{FRAC_PI_2, PI};

/// A pendulum on a cart that may not pass through the cart (Ames et al. 2006, Example 2),
/// `q = (θ, x)`, `θ` from the upward vertical, bob at `(x + l sin θ, l cos θ)`:
/// `L = ½(M_c + m) ẋ² + m l cos θ ẋ θ̇ + ½ m l² θ̇² − m g l cos θ`, `h = cos θ`.
///
/// `x` appears in neither `L` nor `h`, so `p_x = (M_c + m) ẋ + m l cos θ θ̇` is conserved; after
/// the Zeno point (`cos θ = 0`) `ẋ = p_x / (M_c + m)`.
#[derive(Clone, Debug, PartialEq)]
pub struct CartPendulum {
    /// Cart mass `M_c`.
    pub cart_mass: f64,
    /// Bob mass `m`.
    pub bob_mass: f64,
    /// Length `l`.
    pub length: f64,
    /// Gravity `g`.
    pub gravity: f64,
    constraints: [Constraint; 1],
}

impl CartPendulum {
    /// A cart pendulum with the given parameters.
    pub fn new(cart_mass: f64, bob_mass: f64, length: f64, gravity: f64, restitution: f64) -> Self {
        Self {
            cart_mass,
            bob_mass,
            length,
            gravity,
            constraints: [Constraint::new("cart", restitution)],
        }
    }

    /// The authors' demo `CartPendulum`: `M_c = 10`, `m = 5`, `l = 10`, `g = 9.8`, `e = 0.9`,
    /// `(θ, x, θ̇, ẋ)₀ = (−π/10, 0, 0.5, −1.4)`, stop time 40.
    pub fn demo() -> Example<Self> {
        Example {
            model: Self::new(10.0, 5.0, 10.0, 9.8, 0.9),
            q0: vec![-PI / 10.0, 0.0],
            q_dot0: vec![0.5, -1.4],
            t_end: 40.0,
        }
    }

    /// The conserved momentum `p_x = (M_c + m) ẋ + m l cos θ θ̇`.
    pub fn momentum_x(&self, q: &[f64], q_dot: &[f64]) -> f64 {
        (self.cart_mass + self.bob_mass) * q_dot[1]
            + self.bob_mass * self.length * q[0].cos() * q_dot[0]
    }
}

impl HybridLagrangian for CartPendulum {
    const DIMENSION: Option<usize> = Some(2);
    fn dimension(&self) -> usize {
        2
    }

    #[inline]
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        let (m, l) = (self.bob_mass, self.length);
        let (theta, theta_dot, x_dot) = (q[0], v[0], v[1]);
        x_dot * x_dot * (0.5 * (self.cart_mass + m))
            + theta.cos() * (m * l) * x_dot * theta_dot
            + theta_dot * theta_dot * (0.5 * m * l * l)
            - theta.cos() * (m * self.gravity * l)
    }

    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }

    #[inline]
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[0].cos()
    }

    fn coordinate_names(&self) -> Vec<String> {
        vec!["theta".into(), "x".into()]
    }

    /// The paper's map: `(sign(θ) π/2, x, 0, ẋ)`.
    fn completion_map(&self, _index: usize, q: &mut [f64], q_dot: &mut [f64]) -> bool {
        q[0] = q[0].signum() * FRAC_PI_2;
        q_dot[0] = 0.0;
        true
    }
}
