//! # zenosim
//!
//! Simulates Lagrangian hybrid systems with impacts and carries their executions through Zeno
//! points and on past them (Ames, Zheng, Gregg, Sastry, "Is there Life after Zeno?", 2006).
//!
//! A model is a hybrid Lagrangian `(Q, L, h)` with restitution `e` ([`HybridLagrangian`]); from
//! `L` and `h` alone, by automatic differentiation, zenosim derives
//! - the free motion `M q̈ = ∂L/∂q − (∂²L/∂q̇∂q) q̇`, `M = ∂²L/∂q̇²`, on `h(q) ≥ 0`;
//! - the impacts on `h = 0, A q̇ ≤ 0`, `A = ∂h/∂q`:
//!   `q̇⁺ = q̇ − (1+e) (A q̇)/(A M⁻¹ Aᵀ) M⁻¹ Aᵀ`;
//! - after a Zeno point, the motion constrained to `h = 0`:
//!   `M q̈ = ∂L/∂q − (∂²L/∂q̇∂q) q̇ − Aᵀ λ`, `λ = (A M⁻¹ Aᵀ)⁻¹ (A M⁻¹ f + Ȧ q̇)`
//!   (the paper prints `A q̇` for `Ȧ q̇`; this is the corrected form), left again when the
//!   contact force `−Aᵀλ` would have to pull (`λ > 0`);
//! - with several constraints closed at once, the same on the set: impacts by the generalized
//!   Newton law (an LCP over every closed constraint), resting contact by the acceleration LCP
//!   that decides which constraints hold, and Zeno points where constraints meet
//!   (docs/contact-laws.md in the repository states the laws, the signs and the choices);
//! - with time in `L` or `h`, generalized forces `Q(t, q, q̇)` or a Rayleigh dissipation function
//!   `D` (the trait's `lagrangian_at`, `constraint_at`, `generalized_force`, `dissipation`):
//!   `M q̈ = ∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t + Q − ∂D/∂q̇`, the laws acting on the normal
//!   velocity `ḣ = A q̇ + ∂ₜh` of a surface that moves, and the energy balance
//!   `E(t) − E(0) = W_forces + W_drive + W_constraints − ΔE_impacts` in [`Work`]
//!   (docs/forces-and-time.md).
//!
//! Principal types:
//! - [`HybridLagrangian`], [`Constraint`], [`Scalar`]: what a user writes;
//! - [`Simulation`] with [`SimulationOptions`] ([`ZenoStrategy`], [`Completion`], [`OutputGrid`]):
//!   a run, checked before it starts;
//! - [`Execution`]: the record (hybrid time domain, [`Event`]s, [`ZenoPoint`]s, [`Outcome`]);
//! - [`Observer`], [`Sample`], [`Trajectory`]: the trajectory, streamed as it is computed;
//! - [`Derived`]: `M`, `A`, `λ`, the energy and `R∞` at one state;
//! - [`integrator::Stepper`]: the Runge–Kutta pairs (DOP853, DOPRI5) with dense output;
//! - [`events::first_crossing`]: event location on a step's dense output;
//! - [`lcp`]: the small dense LCP solver of the contact laws (an active-set method for positive
//!   definite matrices, Lemke's method for the others);
//! - [`models`]: the paper's examples, and models with forces and a moving surface with their
//!   closed forms, written in Rust.

mod compiled;
mod cone;
mod contact;
mod derivatives;
mod derived;
mod error;
pub mod events;
mod execution;
mod friction;
pub mod integrator;
pub mod lcp;
mod mechanics;
mod model;
pub mod models;
mod motion;
mod observer;
mod options;
mod run;
mod simulation;
mod trace;
mod zeno;

pub use compiled::Compiled;
pub use derivatives::MAX_DIMENSION;
pub use derived::Derived;
pub use error::{Error, Readable};
pub use execution::{
    ActiveSet, Event, EventKind, Execution, Grips, HybridInterval, Mode, Outcome, RunStats, State,
    Work, ZenoKind, ZenoPoint,
};
pub use integrator::{Method, Tolerances};
pub use model::{Constraint, Friction, HybridLagrangian, Scalar};
pub use observer::{Observer, Point, Sample, Trajectory};
pub use options::{Completion, OutputGrid, SimulationOptions, ZenoStrategy};
pub use simulation::{admissible_start, Simulation};

/// The README's example, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
struct ReadmeDoctests;
