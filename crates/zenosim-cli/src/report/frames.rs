//! The animation's frames: the trajectory's rows thinned for playing, as they stream past.
//!
//! The run's span is cut into [`COLUMNS`] columns of time; a row is kept when it is the first
//! of its column, and both rows of every event (two rows at the same time) are kept, whatever
//! their column, so that no impact is lost. Rows further apart than a column are joined by
//! frames on the cubic through both rows' `q` and `q̇` (as the plots join them), so that a long
//! step of a free flight plays as its parabola. The page interpolates between frames.

use crate::plot::trajectory_file::{hermite, Row};

/// Columns of time over the run: a frame every 1/2000 of the run at least.
pub const COLUMNS: usize = 2000;

/// The frames kept.
pub struct Frames {
    /// The coordinates: `q` is the first `n` values of a row.
    n: usize,
    t_start: f64,
    /// Columns per unit of time (0 for a run of no length).
    scale: f64,
    /// A column's length.
    width: f64,
    /// The modes met, in order; frames refer to them by index.
    pub modes: Vec<String>,
    /// Each frame's time.
    pub t: Vec<f64>,
    /// Each frame's mode, an index into [`Frames::modes`].
    pub mode: Vec<u32>,
    /// Each frame's `q`, `n` values per frame.
    pub q: Vec<f64>,
    /// The previous row: its time, mode, values and whether it was kept.
    previous: Option<(f64, u32, Vec<f64>, bool)>,
    /// The column of the last frame kept.
    column: Option<i64>,
    between: Vec<f64>,
}

impl Frames {
    /// Frames of a run of `n` coordinates over `[t_start, t_end]`.
    pub fn new(n: usize, t_start: f64, t_end: f64) -> Self {
        let span = t_end - t_start;
        let (scale, width) = if span > 0.0 && span.is_finite() {
            (COLUMNS as f64 / span, span / COLUMNS as f64)
        } else {
            (0.0, f64::INFINITY)
        };
        Self {
            n,
            t_start,
            scale,
            width,
            modes: Vec::new(),
            t: Vec::new(),
            mode: Vec::new(),
            q: Vec::new(),
            previous: None,
            column: None,
            between: Vec::new(),
        }
    }

    /// The number of frames.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Frame `k`'s `q`.
    pub fn q(&self, k: usize) -> &[f64] {
        &self.q[k * self.n..(k + 1) * self.n]
    }

    /// Takes the next row of the trajectory.
    pub fn push(&mut self, row: &Row<'_>) {
        let mode = self.mode_index(row.mode);
        let mut previous = self.previous.take();
        let kept = match &mut previous {
            None => true,
            Some((t0, mode0, before, kept0)) => {
                let gap = row.t - *t0;
                if gap == 0.0 || gap > self.width {
                    // An event's two rows, or a long step: both ends are frames.
                    if !*kept0 {
                        self.keep(*t0, *mode0, before);
                        *kept0 = true;
                    }
                    if gap > self.width {
                        let steps = ((gap / self.width).ceil() as usize).min(COLUMNS);
                        self.between.resize(before.len(), 0.0);
                        for j in 1..steps {
                            let s = j as f64 / steps as f64;
                            hermite(before, row.values, gap, s, self.n, &mut self.between);
                            let q = std::mem::take(&mut self.between);
                            self.keep(*t0 + s * gap, *mode0, &q);
                            self.between = q;
                        }
                    }
                    true
                } else {
                    self.column_of(row.t) != self.column
                }
            }
        };
        if kept {
            self.keep(row.t, mode, row.values);
        }
        self.previous = match previous {
            Some((_, _, mut before, _)) if before.len() == row.values.len() => {
                before.copy_from_slice(row.values);
                Some((row.t, mode, before, kept))
            }
            _ => Some((row.t, mode, row.values.to_vec(), kept)),
        };
    }

    /// Ends the frames with the last row, kept whatever its column.
    pub fn finish(mut self) -> Self {
        if let Some((t, mode, values, false)) = self.previous.take() {
            self.keep(t, mode, &values);
        }
        self
    }

    fn keep(&mut self, t: f64, mode: u32, values: &[f64]) {
        self.t.push(t);
        self.mode.push(mode);
        self.q.extend_from_slice(&values[..self.n]);
        self.column = self.column_of(t);
    }

    fn column_of(&self, t: f64) -> Option<i64> {
        Some(((t - self.t_start) * self.scale).floor() as i64)
    }

    fn mode_index(&mut self, mode: &str) -> u32 {
        match self.modes.iter().position(|m| m == mode) {
            Some(k) => k as u32,
            None => {
                self.modes.push(mode.to_string());
                (self.modes.len() - 1) as u32
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pushes rows `(t, mode, [x, x_dot, energy])` of one coordinate.
    fn frames_of(rows: &[(f64, &str, [f64; 3])], t_end: f64) -> Frames {
        let mut frames = Frames::new(1, 0.0, t_end);
        for (t, mode, values) in rows {
            frames.push(&Row {
                t: *t,
                mode,
                values,
            });
        }
        frames.finish()
    }

    #[test]
    fn dense_rows_keep_one_per_column_and_the_last() {
        let rows: Vec<(f64, &str, [f64; 3])> = (0..=100_000)
            .map(|k| {
                let t = k as f64 * 1e-5;
                (t, "free", [t, 1.0, 0.0])
            })
            .collect();
        let frames = frames_of(&rows, 1.0);
        assert!(
            (COLUMNS..=COLUMNS + 2).contains(&frames.len()),
            "{}",
            frames.len()
        );
        assert_eq!(frames.t[0], 0.0);
        assert_eq!(*frames.t.last().unwrap(), 1.0);
        assert!(frames.t.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(frames.modes, ["free"]);
    }

    #[test]
    fn both_rows_of_every_event_are_kept() {
        // Rows every 1e-5, and events (two rows at one time) 1e-4 apart: many per column.
        let mut rows = Vec::new();
        for k in 0..=10_000 {
            let t = k as f64 * 1e-5;
            rows.push((t, "free", [1.0, -1.0, 0.0]));
            if k % 10 == 5 {
                rows.push((t, "free", [1.0, 1.0, 0.0]));
            }
        }
        rows.push((0.1, "constrained:floor", [0.0, 0.0, 0.0]));
        let frames = frames_of(&rows, 0.1);
        let pairs = frames.t.windows(2).filter(|w| w[0] == w[1]).count();
        assert_eq!(pairs, 1000 + 1, "every event and the last switch");
        // The pair's rows in order: before (−1) then after (+1) is not kept in q, but the
        // mode of the last pair is.
        assert_eq!(frames.modes, ["free", "constrained:floor"]);
        assert_eq!(*frames.mode.last().unwrap(), 1);
    }

    #[test]
    fn a_long_step_is_joined_along_its_parabola() {
        // x = 1 − g t²/2 from t = 0 to 0.4, one step, then a bounce.
        let g = 9.81;
        let x = |t: f64| 1.0 - 0.5 * g * t * t;
        let rows = [
            (0.0, "free", [x(0.0), 0.0, 0.0]),
            (0.4, "free", [x(0.4), -g * 0.4, 0.0]),
            (0.4, "free", [x(0.4), g * 0.2, 0.0]),
        ];
        let frames = frames_of(&rows, 0.4);
        // A frame every column of 0.4/2000 at least.
        assert!(frames.len() >= COLUMNS, "{}", frames.len());
        for k in 0..frames.len() - 1 {
            let t = frames.t[k];
            assert!((frames.q(k)[0] - x(t)).abs() < 1e-12, "t = {t}");
        }
        let last = frames.len() - 1;
        assert_eq!(frames.t[last - 1], frames.t[last]);
    }

    #[test]
    fn a_run_of_no_length_keeps_its_rows() {
        let frames = frames_of(&[(0.0, "free", [1.0, 0.0, 0.0])], 0.0);
        assert_eq!(frames.t, [0.0]);
        assert_eq!(frames.q(0), [1.0]);
    }
}
