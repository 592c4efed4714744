//! The run settings a sweep may change for all its runs.

use zenosim::{SimulationOptions, ZenoStrategy};

/// Changes to a model file's own `[simulation]` settings, the same for every run of a sweep;
/// `None` keeps the file's.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RunSettings {
    /// The stop time.
    pub t_end: Option<f64>,
    /// How Zeno points are passed.
    pub zeno: Option<ZenoStrategy>,
    /// The relative tolerance.
    pub rtol: Option<f64>,
    /// The absolute tolerance.
    pub atol: Option<f64>,
}

impl RunSettings {
    /// `options` with these changes.
    pub fn apply(&self, mut options: SimulationOptions) -> SimulationOptions {
        if let Some(t_end) = self.t_end {
            options.t_end = t_end;
        }
        if let Some(zeno) = self.zeno {
            options.zeno = zeno;
        }
        if let Some(rtol) = self.rtol {
            options.tolerances.rtol = rtol;
        }
        if let Some(atol) = self.atol {
            options.tolerances.atol = atol;
        }
        options
    }
}
