//! A zenosim model file's runs and what they report.
//!
//! Both the `zenosim` command and the Python package build on this crate, so that a run says
//! the same things in the same words wherever it is made:
//!
//! - [`summary`]: the record of a run as `summary.json` lays it out (the serde structures,
//!   [`summary::Record`] that builds them from a run, the status words of [`summary::status`]);
//! - [`json_layout`]: the JSON layout `summary.json` is written in (one event per line);
//! - [`message`]: what happened in a run, in a sentence;
//! - [`number`]: numbers in their shortest round-trip form, as the CSV files write them;
//! - [`Status`]: how a run ended, in those files' words;
//! - [`sweep`]: many runs of a model file over a grid of parameters or initial values, in
//!   parallel, one row per run.
//!
//! Serialising a summary's `events` or `zeno` with `serde_json` gives exactly the keys of
//! `summary.json` (docs/output.md documents them).

#![warn(missing_docs)]

pub mod json_layout;
pub mod message;
pub mod number;
mod status;
pub mod summary;
pub mod sweep;

pub use status::Status;
