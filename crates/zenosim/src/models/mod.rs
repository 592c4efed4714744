//! The paper's examples, written in Rust, with the parameters of REFERENCE §3, a chain of
//! `n` pendulums on a wall ([`PendulumChain`], `n` up to [`crate::MAX_DIMENSION`]) for scaling,
//! and three models with forces or a moving surface whose flights have closed forms
//! ([`DraggedBall`], [`DampedOscillator`], [`VibratingTable`]; docs/forces-and-time.md).
//!
//! Each model comes with constructors for the paper's and the authors' demo parameters (or, for
//! the chain, its own) and the matching initial state and stop time ([`Example`]).

mod ball_on_sine;
mod bouncing_ball;
mod cart_pendulum;
mod damped_oscillator;
mod dragged_ball;
mod first_root;
mod pendulum_chain;
mod spherical_pendulum;
mod vibrating_table;

pub use ball_on_sine::BallOnSine;
pub use bouncing_ball::BouncingBall;
pub use cart_pendulum::CartPendulum;
pub use damped_oscillator::DampedOscillator;
pub use dragged_ball::DraggedBall;
pub use pendulum_chain::PendulumChain;
pub use spherical_pendulum::SphericalPendulum;
pub use vibrating_table::VibratingTable;

/// A model with the initial state and stop time it is published with.
#[derive(Clone, Debug, PartialEq)]
pub struct Example<M> {
    /// The model.
    pub model: M,
    /// `q(0)`.
    pub q0: Vec<f64>,
    /// `q̇(0)`.
    pub q_dot0: Vec<f64>,
    /// The stop time.
    pub t_end: f64,
}
