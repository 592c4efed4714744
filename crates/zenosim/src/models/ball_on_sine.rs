use super::Example;
use crate::model::{Constraint, HybridLagrangian, Scalar};
use std::f64::consts::FRAC_PI_3;

/// A ball bouncing on the surface `x3 = sin(x2)` (Ames et al. 2006, Examples 1 and 6):
/// `L = ½ m |ẋ|² − m g x3`, `h = x3 − sin(x2)`.
///
/// `x1` appears in neither `L` nor `h`, so `ẋ1` is conserved: `x1 = ẋ1(0) t` throughout.
#[derive(Clone, Debug, PartialEq)]
pub struct BallOnSine {
    /// Mass `m`.
    pub mass: f64,
    /// Gravity `g`.
    pub gravity: f64,
    constraints: [Constraint; 1],
}

impl BallOnSine {
    /// A ball of mass `mass` under gravity `gravity` with restitution `restitution`.
    pub fn new(mass: f64, gravity: f64, restitution: f64) -> Self {
        Self {
            mass,
            gravity,
            constraints: [Constraint::new("surface", restitution)],
        }
    }

    /// The paper's Example 6: `e = 0.6`, `x0 = (0, π/3, 2, 0.5, 0, 0)`, stop time 6
    /// (the paper gives no `g`; 9.81).
    pub fn paper() -> Example<Self> {
        Example {
            model: Self::new(1.0, 9.81, 0.6),
            q0: vec![0.0, FRAC_PI_3, 2.0],
            q_dot0: vec![0.5, 0.0, 0.0],
            t_end: 6.0,
        }
    }

    /// The authors' demo `SinuBouncingBall`: `e = 0.9`, `g = 9.8`, the same `x0`, stop time 20.
    pub fn demo() -> Example<Self> {
        Example {
            model: Self::new(1.0, 9.8, 0.9),
            t_end: 20.0,
            ..Self::paper()
        }
    }
}

impl HybridLagrangian for BallOnSine {
    const DIMENSION: Option<usize> = Some(3);
    fn dimension(&self) -> usize {
        3
    }

    #[inline]
    fn lagrangian<D: Scalar>(&self, q: &[D], v: &[D]) -> D {
        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * (0.5 * self.mass)
            - q[2] * (self.mass * self.gravity)
    }

    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }

    #[inline]
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[2] - q[1].sin()
    }

    fn coordinate_names(&self) -> Vec<String> {
        vec!["x1".into(), "x2".into(), "x3".into()]
    }

    /// Constant gravity on a point mass.
    fn parabolic_flight(&self) -> bool {
        true
    }

    /// The paper's map: `(x1, x2, sin x2, ẋ1, ẋ2, cos(x2) ẋ2)`.
    fn completion_map(&self, _index: usize, q: &mut [f64], q_dot: &mut [f64]) -> bool {
        q[2] = q[1].sin();
        q_dot[2] = q[1].cos() * q_dot[1];
        true
    }
}
