use super::first_root::{first_root, vanishing};
use super::Example;
use crate::model::{Constraint, HybridLagrangian, Scalar};

/// A ball with linear air drag bouncing on a floor: `L = ½ m ẏ² − m g y`, the Rayleigh
/// dissipation function `D = ½ c ẏ²` (force `−c ẏ`), `h = y`.
///
/// Its flights have a closed form ([`DraggedBall::impacts`]): with `k = c/m`, a flight from
/// `y0` at speed `v0` is `y(t) = y0 + (v0 + g/k)(1 − e^{−kt})/k − (g/k) t`. The flights do not
/// shrink by exactly `e` (the drag takes more from the higher ones), yet accumulate.
#[derive(Clone, Debug, PartialEq)]
pub struct DraggedBall {
    /// Mass `m`.
    pub mass: f64,
    /// Gravity `g`.
    pub gravity: f64,
    /// Drag coefficient `c`.
    pub drag: f64,
    constraints: [Constraint; 1],
}

impl DraggedBall {
    /// A ball of mass `mass` under `gravity` with drag `drag` and restitution `restitution`.
    pub fn new(mass: f64, gravity: f64, drag: f64, restitution: f64) -> Self {
        Self {
            mass,
            gravity,
            drag,
            constraints: [Constraint::new("floor", restitution)],
        }
    }

    /// The example of `models/dragged-ball.toml`: `m = 1`, `g = 9.81`, `c = 0.8`, `e = 0.6`,
    /// dropped from rest at 1.
    pub fn example() -> Example<Self> {
        Example {
            model: Self::new(1.0, 9.81, 0.8, 0.6),
            q0: vec![1.0],
            q_dot0: vec![0.0],
            t_end: 2.5,
        }
    }

    /// The impact times when dropped from rest at `h0`, and their limit, the Zeno time, from
    /// the closed-form flights: each landing is a root of `y(t)`, its speed
    /// `(v0 + g/k) e^{−kT} − g/k`, and the next flight starts at `−e` times it.
    pub fn impacts(&self, h0: f64) -> (Vec<f64>, f64) {
        let (g, k) = (self.gravity, self.drag / self.mass);
        let e = self.constraints[0].restitution;
        let (mut t, mut y0, mut v0) = (0.0, h0, 0.0);
        let mut impacts = Vec::new();
        loop {
            // (1 − e^{−ks}) as −expm1(−ks): exact to rounding for the shortest flights.
            let y = |s: f64| y0 - (v0 + g / k) * (-k * s).exp_m1() / k - (g / k) * s;
            let scale = if v0 > 0.0 {
                2.0 * v0 / g
            } else {
                (2.0 * y0 / g).sqrt()
            };
            if vanishing(scale, t) {
                return (impacts, t);
            }
            let flight = first_root(y, scale / 64.0);
            t += flight;
            impacts.push(t);
            let landing = (v0 + g / k) * (-k * flight).exp() - g / k;
            (y0, v0) = (0.0, -e * landing);
        }
    }
}

impl HybridLagrangian for DraggedBall {
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

    #[inline]
    fn dissipation<D: Scalar>(&self, _t: D, _q: &[D], q_dot: &[D]) -> D {
        q_dot[0] * q_dot[0] * (0.5 * self.drag)
    }

    fn is_autonomous(&self) -> bool {
        false
    }

    fn coordinate_names(&self) -> Vec<String> {
        vec!["y".into()]
    }
}
