//! A run's trajectory sampled into an animation's frames: uniformly in time, never across an
//! event's two rows, each frame the drawing's points, its mode, and the path of the trace point
//! up to it.
//!
//! Between two rows the state is the cubic through both rows' `q` and `q̇` (Hermite
//! interpolation), as the plots join rows: exact for a free flight under constant gravity, where
//! the integrator takes long steps and a straight line between rows would cut through the
//! parabola (and through the surface). The trace follows the same cubic between rows.

use std::fs::File;
use std::path::Path;

use anyhow::{anyhow, bail, Context};
use zenosim_model::Drawing;

use super::trajectory_file::{hermite_basis, quote, LineLimit};

/// The most points of the trace kept between two frames (the rows of a burst of bounces).
const TRACE_PER_FRAME: usize = 512;
/// The points of the trace between two rows.
const TRACE_BETWEEN: usize = 8;

/// The frames of an animation.
pub struct Frames {
    /// Each frame's time.
    pub times: Vec<f64>,
    /// Each frame's mode, as `trajectory.csv` writes it (`free`, `constrained:floor`).
    pub modes: Vec<String>,
    /// Each frame's points: `points[f][k * dimension + j]`.
    pub points: Vec<Vec<f64>>,
    /// The trace point's path (empty when the drawing has no trace point).
    pub trace: Vec<(f64, f64)>,
    /// How much of [`Frames::trace`] each frame shows.
    pub trace_end: Vec<usize>,
    /// Why the frames end before the trajectory does, if they do.
    pub note: Option<String>,
}

/// When the frames are: the first at the trajectory's first row, then every `step` seconds of
/// simulated time, `count` in all.
#[derive(Clone, Copy, Debug)]
pub struct Timing {
    /// Simulated seconds between frames.
    pub step: f64,
    /// The number of frames.
    pub count: usize,
}

/// One row of the trajectory: its time, mode, coordinates and velocities.
struct Row {
    t: f64,
    mode: String,
    q: Vec<f64>,
    v: Vec<f64>,
}

/// The coordinates at `t` on the cubic through rows `a` and `b` (`a.t < b.t`).
fn between(a: &Row, b: &Row, t: f64) -> Vec<f64> {
    let h = b.t - a.t;
    let [h00, h10, h01, h11] = hermite_basis((t - a.t) / h);
    (0..a.q.len())
        .map(|i| h00 * a.q[i] + h10 * h * a.v[i] + h01 * b.q[i] + h11 * h * b.v[i])
        .collect()
}

/// Reads `path`, the trajectory of a run of a model with the `coordinates` and `drawing`,
/// into frames at `timing`; errors name the file and the line.
pub fn read(
    path: &Path,
    coordinates: &[String],
    drawing: &Drawing,
    timing: Timing,
) -> anyhow::Result<Frames> {
    let display = path.display();
    let file = File::open(path).with_context(|| {
        format!("cannot read {display}: animate a directory that `zenosim run` wrote")
    })?;
    let longest = 4096 + 64 * (coordinates.len() + 2) * 8;
    let mut csv = csv::ReaderBuilder::new()
        .buffer_capacity(1 << 16)
        .from_reader(LineLimit::new(file, longest.max(1 << 16)));
    let header = csv
        .headers()
        .map_err(|e| anyhow!("{display}:1: cannot read the header: {e}"))?
        .clone();
    let column = |name: &str| {
        header.iter().position(|h| h == name).ok_or_else(|| {
            anyhow!(
                "{display}:1: no column `{}`: is it the trajectory of this model?",
                quote(name)
            )
        })
    };
    let t_column = column("t")?;
    let mode_column = column("mode")?;
    let q_columns = coordinates
        .iter()
        .map(|c| column(c))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let v_columns = coordinates
        .iter()
        .map(|c| column(&format!("{c}_dot")))
        .collect::<anyhow::Result<Vec<_>>>()?;

    let mut frames = Frames {
        times: Vec::with_capacity(timing.count),
        modes: Vec::with_capacity(timing.count),
        points: Vec::with_capacity(timing.count),
        trace: Vec::new(),
        trace_end: Vec::with_capacity(timing.count),
        note: None,
    };
    let mut placer = Placer {
        drawing,
        out: vec![0.0; drawing.points().len() * drawing.dimension()],
        trace: drawing.trace(),
        since_frame: 0,
    };
    let mut previous: Option<Row> = None;
    let mut start = None;
    // The time the trace has reached.
    let mut traced = f64::MIN;
    let mut record = csv::StringRecord::new();
    let mut line = 1;
    while frames.times.len() < timing.count {
        line += 1;
        let more = csv
            .read_record(&mut record)
            .map_err(|e| anyhow!("{display}:{line}: {e}"))?;
        if !more {
            break;
        }
        let number = |i: usize| -> anyhow::Result<f64> {
            let text = record.get(i).unwrap_or("");
            text.trim().parse::<f64>().map_err(|_| {
                anyhow!(
                    "{display}:{line}: `{}` is not a number, in column `{}`",
                    quote(text),
                    &header[i]
                )
            })
        };
        let row = Row {
            t: number(t_column)?,
            mode: record.get(mode_column).unwrap_or("").to_string(),
            q: q_columns
                .iter()
                .map(|&i| number(i))
                .collect::<anyhow::Result<_>>()?,
            v: v_columns
                .iter()
                .map(|&i| number(i))
                .collect::<anyhow::Result<_>>()?,
        };
        if !row.t.is_finite() || row.q.iter().chain(&row.v).any(|v| !v.is_finite()) {
            frames.note = Some(format!(
                "the trajectory is not finite from t = {} on (line {line}): the animation ends \
                 there",
                row.t
            ));
            break;
        }
        if let Some(p) = &previous {
            if row.t < p.t {
                bail!("{display}:{line}: t = {} comes after t = {}", row.t, p.t);
            }
        }
        let t0 = *start.get_or_insert(row.t);
        let gap = previous.as_ref().filter(|p| row.t > p.t);
        // The frames up to this row, between the previous row and this one (none between an
        // event's two rows, at the same time).
        loop {
            let k = frames.times.len();
            if k >= timing.count {
                break;
            }
            let tf = t0 + k as f64 * timing.step;
            if tf > row.t {
                break;
            }
            if let Some(p) = gap {
                placer.trace_between(&mut frames, &mut traced, p, &row, tf)?;
            }
            let q = match gap {
                Some(p) if tf < row.t => between(p, &row, tf),
                _ => row.q.clone(),
            };
            let mode = match gap {
                Some(p) if tf < row.t => p.mode.clone(),
                _ => row.mode.clone(),
            };
            let points = placer.place(&mut frames, tf, &q)?;
            traced = tf;
            frames.times.push(tf);
            frames.modes.push(mode);
            frames.points.push(points);
            frames.trace_end.push(frames.trace.len());
            placer.since_frame = 0;
        }
        // The row itself, and the way to it, on the trace.
        if let Some(p) = gap {
            placer.trace_between(&mut frames, &mut traced, p, &row, row.t)?;
        }
        if placer.tracing() && row.t > traced {
            placer.trace_point(&mut frames, row.t, &row.q)?;
            placer.since_frame += 1;
            traced = row.t;
        }
        previous = Some(row);
    }
    if frames.times.is_empty() {
        bail!("{display}: no rows to animate: is it the trajectory of a run?");
    }
    Ok(frames)
}

/// Places the drawing's points, adding the trace point's to the trace.
struct Placer<'d> {
    drawing: &'d Drawing,
    out: Vec<f64>,
    trace: Option<usize>,
    /// The trace's points since the last frame.
    since_frame: usize,
}

impl Placer<'_> {
    /// The points at `t` and `q`, the trace point added to the trace.
    fn place(&mut self, frames: &mut Frames, t: f64, q: &[f64]) -> anyhow::Result<Vec<f64>> {
        self.drawing
            .evaluate(t, q, &mut self.out)
            .map_err(|e| anyhow!("cannot draw the mechanism at t = {t}: {e}"))?;
        if let Some(k) = self.trace {
            let d = self.drawing.dimension();
            frames.trace.push((self.out[k * d], self.out[k * d + 1]));
        }
        Ok(self.out.clone())
    }

    /// The trace point alone at `t` and `q`, added to the trace.
    fn trace_point(&mut self, frames: &mut Frames, t: f64, q: &[f64]) -> anyhow::Result<()> {
        if let Some(k) = self.trace {
            let mut p = [0.0; 3];
            self.drawing
                .evaluate_point(k, t, q, &mut p)
                .map_err(|e| anyhow!("cannot draw the mechanism at t = {t}: {e}"))?;
            frames.trace.push((p[0], p[1]));
        }
        Ok(())
    }

    /// Whether the trace takes another point before the next frame.
    fn tracing(&self) -> bool {
        self.trace.is_some() && self.since_frame < TRACE_PER_FRAME
    }

    /// The trace from `traced` up to (not including) `to`, along the cubic from row `a` to row
    /// `b`, at [`TRACE_BETWEEN`] evenly spaced times.
    fn trace_between(
        &mut self,
        frames: &mut Frames,
        traced: &mut f64,
        a: &Row,
        b: &Row,
        to: f64,
    ) -> anyhow::Result<()> {
        for i in 1..TRACE_BETWEEN {
            let t = a.t + (b.t - a.t) * i as f64 / TRACE_BETWEEN as f64;
            if t > *traced && t < to && self.tracing() {
                self.trace_point(frames, t, &between(a, b, t))?;
                self.since_frame += 1;
                *traced = t;
            }
        }
        Ok(())
    }
}
