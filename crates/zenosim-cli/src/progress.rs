//! A progress bar for long runs: shown on stderr, only when it is a terminal, and only once a
//! run has taken a second (short runs print nothing but their report).

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

/// How long a run goes before the bar appears.
const DELAY: Duration = Duration::from_secs(1);
/// How often the bar is moved (indicatif redraws at most 20 times a second anyway).
const INTERVAL: Duration = Duration::from_millis(50);
/// The bar's resolution: its position is the fraction of `t_end` reached, in these units.
const UNITS: u64 = 10_000;

/// The fraction of `[0, t_end]` a run has covered, shown lazily.
pub struct Progress {
    t_end: f64,
    enabled: bool,
    start: Instant,
    next: Instant,
    bar: Option<ProgressBar>,
}

impl Progress {
    /// A progress display for a run to `t_end`, enabled when stderr is a terminal.
    pub fn new(t_end: f64) -> Self {
        Self::with(t_end, std::io::stderr().is_terminal())
    }

    /// A display that never shows anything.
    #[cfg(test)]
    pub fn hidden() -> Self {
        Self::with(1.0, false)
    }

    fn with(t_end: f64, enabled: bool) -> Self {
        let start = Instant::now();
        Self {
            t_end,
            enabled,
            start,
            next: start + DELAY,
            bar: None,
        }
    }

    /// The run reached `t`.
    pub fn update(&mut self, t: f64) {
        if !self.enabled {
            return;
        }
        let now = Instant::now();
        if now < self.next {
            return;
        }
        self.next = now + INTERVAL;
        let start = self.start;
        let bar = self.bar.get_or_insert_with(|| {
            let style = ProgressStyle::with_template(
                "{elapsed_precise} [{wide_bar}] {percent:>3}%  t = {msg}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar());
            // The clock shows the run's whole time, not the bar's.
            ProgressBar::new(UNITS)
                .with_style(style)
                .with_elapsed(now - start)
        });
        let fraction = (t / self.t_end).clamp(0.0, 1.0);
        bar.set_message(format!("{t:.6} / {}", self.t_end));
        bar.set_position((fraction * UNITS as f64) as u64);
    }

    /// Removes the bar, if it was shown.
    pub fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}

/// The runs done of a sweep: a bar on stderr when it is a terminal, moved from any thread.
pub struct RunsDone {
    bar: Option<ProgressBar>,
}

impl RunsDone {
    /// A bar of `total` runs, shown when stderr is a terminal.
    pub fn new(total: usize) -> Self {
        let shown = std::io::stderr().is_terminal() && total > 0;
        let bar = shown.then(|| {
            let style = ProgressStyle::with_template(
                "{elapsed_precise} [{wide_bar}] {pos}/{len} runs, {per_sec}, {eta} left",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar());
            ProgressBar::new(total as u64).with_style(style)
        });
        Self { bar }
    }

    /// `done` runs are complete.
    pub fn set(&self, done: usize) {
        if let Some(bar) = &self.bar {
            bar.set_position(done as u64);
        }
    }

    /// Removes the bar, if it was shown.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
