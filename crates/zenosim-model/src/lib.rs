//! Parse and validate zenosim model files.
//!
//! A model file describes a hybrid Lagrangian system: its coordinates, parameters, Lagrangian
//! and unilateral constraints, written as formulas. Today this crate holds the formula part, the
//! expression language of [`expr`]: it parses a formula once, reports mistakes with their line
//! and column and what to do about them, and evaluates the compiled formula quickly over `f64`
//! and over the dual numbers zenosim differentiates with.

#![warn(missing_docs)]

pub mod expr;
