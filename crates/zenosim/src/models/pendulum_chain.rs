use super::Example;
use crate::model::{Constraint, HybridLagrangian, Scalar};

/// A planar chain of `n` pendulums whose tip is stopped by a wall: `n` equal links of length
/// `l`, hinged end to end from a fixed pivot at the origin, with a point mass `m` at the end of
/// each link (joints 1 to `n`; joint `n` is the tip).
///
/// `q = (θ_1, …, θ_n)`, the links' absolute angles from the downward vertical, counterclockwise
/// positive; joint `k` is at `x_k = l Σ_{i≤k} sin θ_i`, `y_k = −l Σ_{i≤k} cos θ_i`:
/// `L = ½ m Σ_k (ẋ_k² + ẏ_k²) − m g Σ_k y_k`, with
/// `ẋ_k = l Σ_{i≤k} cos θ_i θ̇_i`, `ẏ_k = l Σ_{i≤k} sin θ_i θ̇_i`;
/// `M_ij = m (n + 1 − max(i, j)) l² cos(θ_i − θ_j)`.
///
/// The wall is the vertical plane `x = w` (`0 < w < n l`), and it stops the tip only:
/// `h = x_n − w = l Σ sin θ_i − w ≥ 0` (the links pass the wall's plane, as through a slot, like
/// the pendulum through the cart's deck in [`super::CartPendulum`]). The chain's hanging rest
/// (`x_n = 0`) is behind the wall, so gravity holds the tip against it: dropped onto it, the tip
/// bounces with shrinking flights to a Zeno point and then slides on the wall, while the links
/// above it go on swinging; where the contact force would have to pull, the tip lifts off.
///
/// No coordinate is absent from `L`: the conserved quantity is the energy
/// `E = ½ q̇ᵀ M q̇ + m g Σ_k y_k` between events and on the wall (each impact removes
/// `½(1−e²)(A q̇)²/(A M⁻¹ Aᵀ)` of it).
///
/// On the wall the chain rests where the wall's horizontal push `F` on the tip and the weights
/// below each link balance the link's tension: `tan θ_i = F / (m g (n + 1 − i))`, `F` such that
/// `x_n = w` ([`Self::wall_rest`]); there `λ = −F` (the contact force `−Aᵀλ` is `F` along `x`).
#[derive(Clone, Debug, PartialEq)]
pub struct PendulumChain {
    /// The number of links `n` (and of masses).
    pub links: usize,
    /// The length of each link `l`.
    pub link_length: f64,
    /// The mass at the end of each link `m`.
    pub joint_mass: f64,
    /// Gravity `g`.
    pub gravity: f64,
    /// The wall's distance `w` from the pivot, along `x`.
    pub wall: f64,
    constraints: [Constraint; 1],
}

impl PendulumChain {
    /// A chain of `links` links of length `link_length` with a mass `joint_mass` at the end of
    /// each, under gravity `gravity`, its tip stopped by a wall at `x = wall` with restitution
    /// `restitution`.
    pub fn new(
        links: usize,
        link_length: f64,
        joint_mass: f64,
        gravity: f64,
        wall: f64,
        restitution: f64,
    ) -> Self {
        Self {
            links,
            link_length,
            joint_mass,
            gravity,
            wall,
            constraints: [Constraint::new("wall", restitution)],
        }
    }

    /// A chain of `n` links, 2 m and 2 kg in all (links of `2/n` m, masses of `2/n` kg),
    /// `g = 9.81`, the wall at `w = 1` (where the straight chain would touch it at 30° from
    /// the vertical), `e = 0.5`; it starts from rest in its rest shape on the wall
    /// ([`Self::wall_rest`]) turned by 0.5 rad away from the wall about the pivot; stop time 4.
    ///
    /// The tip's impacts accumulate at a Zeno point within about 2 s, and the tip slides on the
    /// wall; from `n` = 4 or so the links above it swing hard enough to pull it off the wall
    /// (it lands again, through another Zeno point). Sensible for every `n` from 1 to
    /// [`crate::MAX_DIMENSION`] (a longer chain is refused when a simulation is set up).
    ///
    /// # Panics
    /// If `n` is 0.
    pub fn example(n: usize) -> Example<Self> {
        assert!(n >= 1, "a chain has at least one link");
        let model = Self::new(n, 2.0 / n as f64, 2.0 / n as f64, 9.81, 1.0, 0.5);
        let q0 = model.wall_rest().iter().map(|theta| theta + 0.5).collect();
        Example {
            model,
            q0,
            q_dot0: vec![0.0; n],
            t_end: 4.0,
        }
    }

    /// The same chain with restitution `e`.
    pub fn with_restitution(mut self, e: f64) -> Self {
        self.constraints[0].restitution = e;
        self
    }

    /// The rest shape on the wall: `θ_i = atan(f / (n + 1 − i))` with `f = F/(m g)`, the wall's
    /// push in weights of one mass, found by bisection so that `x_n = w` (to round-off).
    ///
    /// # Panics
    /// Unless `0 < w < n l` (else the tip cannot rest on the wall).
    pub fn wall_rest(&self) -> Vec<f64> {
        assert!(
            self.wall > 0.0 && self.wall < self.links as f64 * self.link_length,
            "the wall must lie between the pivot and the chain's reach"
        );
        let shape = |f: f64| -> Vec<f64> {
            (0..self.links)
                .map(|i| (f / (self.links - i) as f64).atan())
                .collect()
        };
        // x_n grows with f from 0 (hanging) towards n l (horizontal).
        let reach = |f: f64| self.link_length * shape(f).iter().map(|t| t.sin()).sum::<f64>();
        let mut high = 1.0;
        while reach(high) < self.wall {
            high *= 2.0;
        }
        let mut low = 0.0;
        while high - low > f64::EPSILON * high {
            let mid = 0.5 * (low + high);
            if reach(mid) < self.wall {
                low = mid;
            } else {
                high = mid;
            }
        }
        shape(0.5 * (low + high))
    }

    /// The wall's push `F` on the tip in the rest shape (`F = f m g`, see [`Self::wall_rest`]).
    pub fn wall_rest_force(&self) -> f64 {
        let rest = self.wall_rest();
        // tan θ_n = F / (m g) for the last link, which carries the tip's weight only.
        rest[self.links - 1].tan() * self.joint_mass * self.gravity
    }

    /// The tip's position `(x_n, y_n)`.
    pub fn tip(&self, q: &[f64]) -> (f64, f64) {
        let x: f64 = q.iter().map(|t| t.sin()).sum();
        let y: f64 = q.iter().map(|t| -t.cos()).sum();
        (self.link_length * x, self.link_length * y)
    }
}

impl HybridLagrangian for PendulumChain {
    fn dimension(&self) -> usize {
        self.links
    }

    /// One pass down the chain, accumulating the joints' velocities and heights (in units of
    /// `l`): `O(n)` per evaluation.
    #[inline]
    fn lagrangian<D: Scalar>(&self, q: &[D], q_dot: &[D]) -> D {
        let (l, m) = (self.link_length, self.joint_mass);
        let (mut vx, mut vy, mut y) = (D::zero(), D::zero(), D::zero());
        let (mut speeds, mut heights) = (D::zero(), D::zero());
        for (theta, theta_dot) in q.iter().zip(q_dot) {
            let (sin, cos) = theta.sin_cos();
            vx += cos * *theta_dot;
            vy += sin * *theta_dot;
            y -= cos;
            speeds += vx * vx + vy * vy;
            heights += y;
        }
        speeds * (0.5 * m * l * l) - heights * (m * self.gravity * l)
    }

    fn constraints(&self) -> &[Constraint] {
        &self.constraints
    }

    #[inline]
    fn constraint<D: Scalar>(&self, _index: usize, q: &[D]) -> D {
        let mut x = D::zero();
        for theta in q {
            x += theta.sin();
        }
        x * self.link_length - self.wall
    }

    fn coordinate_names(&self) -> Vec<String> {
        (1..=self.links).map(|i| format!("theta{i}")).collect()
    }
}
