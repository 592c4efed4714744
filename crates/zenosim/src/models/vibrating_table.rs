use super::Example;
use crate::model::{Constraint, HybridLagrangian, Scalar};

/// A ball on a table that vibrates as `y_T = a sin(ω t)`, the classic impact oscillator:
/// `L = ½ m ẏ² − m g y`, the moving surface `h(t, y) = y − a sin(ω t)`.
///
/// On the table the contact force is `m (g − a ω² sin ωt)`. With `a ω² > g` the ball, once it
/// has chattered to rest on the table, is carried by it and leaves it where the force vanishes
/// with the table decelerating: `a ω² sin ωt = g` ([`VibratingTable::liftoff_phase`]). With
/// `a ω² < g` it stays on the table after its Zeno point. (Chattering and locking of this
/// system: Mehta and Luck, Phys. Rev. Lett. 65, 1990; Budd and Dux, Phil. Trans. R. Soc. A
/// 347, 1994.)
#[derive(Clone, Debug, PartialEq)]
pub struct VibratingTable {
    /// Mass `m`.
    pub mass: f64,
    /// Gravity `g`.
    pub gravity: f64,
    /// The table's amplitude `a`.
    pub amplitude: f64,
    /// The table's angular frequency `ω`.
    pub frequency: f64,
    constraints: [Constraint; 1],
}

impl VibratingTable {
    /// A ball of mass `mass` under `gravity` on a table `a sin(ω t)` with restitution
    /// `restitution`.
    pub fn new(mass: f64, gravity: f64, amplitude: f64, frequency: f64, restitution: f64) -> Self {
        Self {
            mass,
            gravity,
            amplitude,
            frequency,
            constraints: [Constraint::new("table", restitution)],
        }
    }

    /// The example of `models/vibrating-table.toml`: `m = 1`, `g = 9.81`, `a = 3 mm`,
    /// `ω = 2π · 10 Hz` (`a ω²/g ≈ 1.21`), `e = 0.2`, dropped from rest at 1 cm.
    pub fn example() -> Example<Self> {
        Example {
            model: Self::new(1.0, 9.81, 0.003, 20.0 * std::f64::consts::PI, 0.2),
            q0: vec![0.01],
            q_dot0: vec![0.0],
            t_end: 3.0,
        }
    }

    /// The phase `ω t mod 2π` at which a ball carried by the table leaves it, where
    /// `a ω² sin ωt = g` with the table decelerating (the first quadrant); `None` where
    /// `a ω² < g` (it never leaves).
    pub fn liftoff_phase(&self) -> Option<f64> {
        let ratio = self.gravity / (self.amplitude * self.frequency * self.frequency);
        (ratio <= 1.0).then(|| ratio.asin())
    }

    /// The table's height at `t`.
    pub fn table(&self, t: f64) -> f64 {
        self.amplitude * (self.frequency * t).sin()
    }
}

impl HybridLagrangian for VibratingTable {
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

    /// The table at `t = 0`.
    #[inline]
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        q[0]
    }

    #[inline]
    fn constraint_at<D: Scalar>(&self, _index: usize, t: D, q: &[D]) -> D {
        q[0] - (t * self.frequency).sin() * self.amplitude
    }

    fn is_autonomous(&self) -> bool {
        false
    }

    fn coordinate_names(&self) -> Vec<String> {
        vec!["y".into()]
    }

    /// Constant gravity on a point mass: the table moves, the ball's flight is a parabola.
    fn parabolic_flight(&self) -> bool {
        true
    }
}
