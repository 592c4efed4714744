use super::Example;
use crate::model::{Constraint, HybridLagrangian, Scalar};
use std::f64::consts::{FRAC_PI_2, PI};

/// A spherical pendulum mounted on the ground (Ames et al. 2006, Example 3), `q = (θ, φ)`,
/// `θ` from the upward vertical: `L = ½ m l² (θ̇² + sin²θ φ̇²) − m g l cos θ`, `h = cos θ`.
///
/// `φ` appears in neither `L` nor `h`, so `p_φ = m l² sin²θ φ̇` is conserved; after the Zeno
/// point (`θ = π/2`) `φ̇ = sin²θ0 φ̇0`. `M` is singular at `θ = 0` (the coordinates' pole).
#[derive(Clone, Debug, PartialEq)]
pub struct SphericalPendulum {
    /// Bob mass `m`.
    pub mass: f64,
    /// Length `l`.
    pub length: f64,
    /// Gravity `g`.
    pub gravity: f64,
    constraints: [Constraint; 1],
}

impl SphericalPendulum {
    /// A spherical pendulum with the given parameters.
    pub fn new(mass: f64, length: f64, gravity: f64, restitution: f64) -> Self {
        Self {
            mass,
            length,
            gravity,
            constraints: [Constraint::new("ground", restitution)],
        }
    }

    /// The authors' demo `Pendulum3D`: `l = 10`, `g = 9.8`, `e = 0.9` (`m = 1`; it cancels),
    /// `(θ, φ, θ̇, φ̇)₀ = (π/10, π/6, 0, 1)`, stop time 35.
    pub fn demo() -> Example<Self> {
        Example {
            model: Self::new(1.0, 10.0, 9.8, 0.9),
            q0: vec![PI / 10.0, PI / 6.0],
            q_dot0: vec![0.0, 1.0],
            t_end: 35.0,
        }
    }

    /// The conserved momentum `p_φ = m l² sin²θ φ̇`.
    pub fn momentum_phi(&self, q: &[f64], q_dot: &[f64]) -> f64 {
        self.mass * self.length * self.length * q[0].sin().powi(2) * q_dot[1]
    }
}

impl HybridLagrangian for SphericalPendulum {
    const DIMENSION: Option<usize> = Some(2);
    fn dimension(&self) -> usize {
        2
    }

    #[inline]
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        let ml2 = self.mass * self.length * self.length;
        let s = q[0].sin();
        (v[0] * v[0] + s * s * v[1] * v[1]) * (0.5 * ml2)
            - q[0].cos() * (self.mass * self.gravity * self.length)
    }

    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }

    #[inline]
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[0].cos()
    }

    fn coordinate_names(&self) -> Vec<String> {
        vec!["theta".into(), "phi".into()]
    }

    /// The paper's map: `(π/2, φ, 0, φ̇)`.
    fn completion_map(&self, _index: usize, q: &mut [f64], q_dot: &mut [f64]) -> bool {
        q[0] = FRAC_PI_2;
        q_dot[0] = 0.0;
        true
    }
}
