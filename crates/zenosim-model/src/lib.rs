//! Read and check zenosim model files.
//!
//! A model file describes a hybrid Lagrangian system in TOML: its coordinates, parameters,
//! Lagrangian, unilateral constraints with their restitutions, optional generalized forces and
//! dissipation, initial state and run settings, the functions written as formulas:
//!
//! ```toml
//! name = "ball-on-sine"
//! coordinates = ["x1", "x2", "x3"]            # velocities are x1_dot, x2_dot, x3_dot
//! lagrangian = "0.5*m*(x1_dot^2 + x2_dot^2 + x3_dot^2) - m*g*x3"
//! # dissipation = "0.5*c*x1_dot^2"            # optional Rayleigh function D(t, q, q_dot)
//!
//! [parameters]                                # numbers or formulas of other parameters
//! m = 1.0
//! g = 9.81
//!
//! # [forces]                                  # optional generalized forces, 0 if not listed
//! # x1 = "0.1*sin(2*t)"
//!
//! [[constraint]]                              # one or more; the admissible side is h >= 0
//! name = "surface"
//! h = "x3 - sin(x2)"
//! restitution = 0.6
//! # zeno_reset = { x3 = "sin(x2)", x3_dot = "cos(x2)*x2_dot" }   # optional own R∞
//!
//! [initial]                                   # omitted values are 0
//! x2 = "pi/3"
//! x3 = 2.0
//! x1_dot = 0.5
//!
//! [simulation]                                # all optional
//! t_end = 6.0
//! rtol = 1e-10
//! atol = 1e-10
//! zeno = "auto"                               # "auto" | "off" | { epsilon = 1e-3 }
//!
//! [drawing]                                   # optional: how the mechanism looks
//! points = { contact = ["x2", "x3"] }         # formulas of t, the coordinates, the parameters
//! surfaces = [{ constraint = "surface", curve = ["s", "sin(s)"], s = [-4, 2] }]
//! circles = [{ at = "contact", radius = 0.06 }]
//! ```
//!
//! The time `t` may appear in `lagrangian`, in `h`, in `zeno_reset`, in `[forces]` and in
//! `dissipation` (runs start at `t = 0`); the motion is then
//! `M q̈ = ∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t + Q` with `Q = [forces] − ∂D/∂q̇`, and a moving
//! constraint `h(t, q)` has the normal velocity `ḣ = A q̇ + ∂h/∂t`. A model without `t`, forces
//! or dissipation is autonomous ([`zenosim::HybridLagrangian::is_autonomous`]).
//!
//! [`parse_model`] turns such a file into a [`ModelFile`]: a [`FileModel`] that implements
//! [`zenosim::HybridLagrangian`] (its formulas compiled once and evaluated over `f64` and
//! dual numbers, so file models get exact derivatives), the initial state and the settings.
//! Every mistake is a [`ModelError`] that names the file, the line and column or the key, and
//! says what to do. The formula language is described in [`expr`]; the optional `[drawing]`
//! becomes a [`Drawing`] (docs/drawing.md).

#![warn(missing_docs)]

mod drawing;
mod error;
pub mod expr;
mod file_model;
mod load;
#[cfg(test)]
mod property_tests;
mod source;

pub use drawing::{Drawing, DrawingError, Shape};
pub use error::{Location, ModelError};
pub use expr::Limits;
pub use file_model::FileModel;
pub use load::{parse_model, parse_model_with, parse_zeno, ModelFile, Override, Settings};
pub use source::{read_source, ReadError, MAX_FILE_BYTES};
