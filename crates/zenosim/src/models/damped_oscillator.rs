use super::first_root::{first_root, vanishing};
use super::Example;
use crate::model::{Constraint, HybridLagrangian, Scalar};

/// A damped oscillator against a wall: a mass on a spring whose rest point `x_eq < 0` lies
/// beyond the wall `h = x`, with a damper as a generalized force:
/// `L = ½ m ẋ² − ½ k (x − x_eq)²`, `Q = −c ẋ`.
///
/// Its flights have a closed form ([`DampedOscillator::impacts`]): with `u = x − x_eq`,
/// `α = c/2m`, `ω = √(k/m − α²)`, a flight from `(u0, v0)` is
/// `u(t) = e^{−αt}(u0 cos ωt + (v0 + α u0)/ω sin ωt)`, and reaches the wall where `u = −x_eq`.
/// Pressed against the wall by the spring, it chatters to rest there.
#[derive(Clone, Debug, PartialEq)]
pub struct DampedOscillator {
    /// Mass `m`.
    pub mass: f64,
    /// Spring constant `k`.
    pub stiffness: f64,
    /// Damping `c`.
    pub damping: f64,
    /// The spring's rest point `x_eq` (negative: beyond the wall).
    pub rest: f64,
    constraints: [Constraint; 1],
}

impl DampedOscillator {
    /// A mass `mass` on a spring `stiffness` at rest at `rest`, damping `damping`, against a
    /// wall at 0 with restitution `restitution`.
    pub fn new(mass: f64, stiffness: f64, damping: f64, rest: f64, restitution: f64) -> Self {
        Self {
            mass,
            stiffness,
            damping,
            rest,
            constraints: [Constraint::new("wall", restitution)],
        }
    }

    /// The example of `models/damped-oscillator.toml`: `m = 1.5`, `k = 40`, `c = 0.9`,
    /// `x_eq = −0.3`, `e = 0.7`, released at rest at `x = 0.5`.
    pub fn example() -> Example<Self> {
        Example {
            model: Self::new(1.5, 40.0, 0.9, -0.3, 0.7),
            q0: vec![0.5],
            q_dot0: vec![0.0],
            t_end: 3.0,
        }
    }

    /// The impact times when released at rest at `x0 > 0`, and their limit, the Zeno time.
    pub fn impacts(&self, x0: f64) -> (Vec<f64>, f64) {
        let (m, k, c, x_eq) = (self.mass, self.stiffness, self.damping, self.rest);
        let e = self.constraints[0].restitution;
        let alpha = c / (2.0 * m);
        let omega = (k / m - alpha * alpha).sqrt();
        let (mut t, mut u0, mut v0) = (0.0, x0 - x_eq, 0.0);
        let mut impacts = Vec::new();
        loop {
            let b = (v0 + alpha * u0) / omega;
            // x(s) = u(s) + x_eq, with e^{−αs} cos ωs − 1 = expm1(−αs) cos ωs − 2 sin²(ωs/2):
            // exact to rounding for the shortest flights (u0 = −x_eq there).
            let x = |s: f64| {
                let (sin, cos) = (omega * s).sin_cos();
                let half = (0.5 * omega * s).sin();
                u0 * ((-alpha * s).exp_m1() * cos - 2.0 * half * half)
                    + (u0 + x_eq)
                    + b * (-alpha * s).exp() * sin
            };
            let u_dot = |s: f64| {
                let (sin, cos) = (omega * s).sin_cos();
                (-alpha * s).exp()
                    * ((b * omega - alpha * u0) * cos - (u0 * omega + alpha * b) * sin)
            };
            // The flight's scale: the free fall 2 v0/|ẍ| at the wall, or a quarter period.
            let scale = if v0 > 0.0 {
                2.0 * v0 * m / (k * -x_eq)
            } else {
                0.5 / omega
            };
            if vanishing(scale, t) {
                return (impacts, t);
            }
            let flight = first_root(x, scale / 64.0);
            t += flight;
            impacts.push(t);
            (u0, v0) = (-x_eq, -e * u_dot(flight));
        }
    }
}

impl HybridLagrangian for DampedOscillator {
    const DIMENSION: Option<usize> = Some(1);
    fn dimension(&self) -> usize {
        1
    }

    #[inline]
    fn lagrangian<D: Scalar>(&self, q: &[D], q_dot: &[D]) -> D {
        let u = q[0] - self.rest;
        q_dot[0] * q_dot[0] * (0.5 * self.mass) - u * u * (0.5 * self.stiffness)
    }

    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }

    #[inline]
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[0]
    }

    #[inline]
    fn generalized_force<D: Scalar>(&self, _t: D, _q: &[D], q_dot: &[D], force: &mut [D]) {
        force[0] -= q_dot[0] * self.damping;
    }

    fn is_autonomous(&self) -> bool {
        false
    }

    fn coordinate_names(&self) -> Vec<String> {
        vec!["x".into()]
    }
}
