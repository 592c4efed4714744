//! The mechanism's drawing: the `[drawing]` section of the run's model file (`model.toml`,
//! which `zenosim run` writes beside its other files), read with the run's parameters and
//! evaluated at each frame of the animation.

use std::path::Path;

use anyhow::anyhow;
use serde::Serialize;
use serde_json::{json, Value};
use zenosim_model::{Drawing, Limits, Shape};

use super::frames::Frames;
use crate::plot::record::Record;
use crate::run::MODEL;

/// The most operations evaluating the drawing at every frame may take (seconds of work): a
/// drawing of many points over a run of many events is refused past it.
const MAX_OPERATIONS: u64 = 2_000_000_000;
/// The most point coordinates kept over all frames (80 MB).
const MAX_VALUES: usize = 20_000_000;

/// The mechanism as the page draws it: the points, the shapes between them, and each point's
/// position (x, y: a 3-D drawing's projection on the x–y plane) at every frame, given once for
/// the points that never move.
#[derive(Serialize)]
pub struct Drawn {
    dimension: usize,
    points: Vec<String>,
    shapes: Vec<Value>,
    trace: Option<usize>,
    /// Each point's position if it is the same at every frame, else `null`.
    fixed: Vec<Option<[f32; 2]>>,
    /// The points that move, in order.
    moving: Vec<usize>,
    /// The moving points' x, y at each frame, frame after frame.
    positions: Vec<f32>,
}

/// The drawing of the run in `dir`, from its `model.toml` with the run's parameters (as
/// `summary.json` gives them, so that `--set` is honoured); `Ok(Err(note))` when there is none
/// to draw, the note saying how to get one. A model file that cannot be read, or that does
/// not belong to the run, is an error.
pub fn load(
    dir: &Path,
    record: &Record,
    limits: Limits,
) -> anyhow::Result<Result<Drawing, String>> {
    let path = dir.join(MODEL);
    if !path.exists() {
        return Ok(Err(format!(
            "No mechanism: this folder has no {MODEL} (zenosim run writes the model file there). \
             Run the model again with this version of zenosim to see it drawn."
        )));
    }
    let file = crate::input::load_for_run(&path, record, limits).map_err(|error| {
        anyhow!(
            "{error:#}; fix it, run the model again, or remove it to write the report without \
             the mechanism"
        )
    })?;
    Ok(file.drawing.ok_or_else(|| {
        "No mechanism: the model file has no [drawing] section. Add one (see docs/drawing.md: \
         points as formulas of the coordinates, and the segments, circles and surfaces between \
         them) and run the model again to see it move."
            .to_string()
    }))
}

/// `drawing` evaluated at every frame; an error names the model file (in `dir`) and the time.
pub fn draw(drawing: &Drawing, frames: &Frames, dir: &Path) -> anyhow::Result<Drawn> {
    let count = drawing.points().len();
    let dimension = drawing.dimension();
    let operations = drawing.operations() as u64 * frames.len() as u64;
    let values = frames.len() * count * 2;
    if operations > MAX_OPERATIONS || values > MAX_VALUES {
        return Err(anyhow!(
            "{}: drawing its {count} points at the animation's {} frames would take {operations} \
             operations and {values} values, more than the report allows ({MAX_OPERATIONS} and \
             {MAX_VALUES}): draw fewer points (fewer samples of a surface), or remove the file \
             to write the report without the mechanism",
            dir.join(MODEL).display(),
            frames.len()
        ));
    }
    let mut out = vec![0.0; count * dimension];
    // x, y of every point at every frame.
    let mut all = Vec::with_capacity(values);
    for k in 0..frames.len() {
        // A state that is not finite (a run that diverged) keeps the last drawing.
        if !frames.q(k).iter().all(|q| q.is_finite()) {
            let last = all.len().saturating_sub(2 * count);
            match k {
                0 => all.extend(std::iter::repeat_n(0.0, 2 * count)),
                _ => all.extend_from_within(last..last + 2 * count),
            }
            continue;
        }
        drawing
            .evaluate(frames.t[k], frames.q(k), &mut out)
            .map_err(|error| {
                anyhow!(
                    "{}: {error}; change the drawing's formulas so that they are finite all \
                     along the run",
                    dir.join(MODEL).display()
                )
            })?;
        for p in 0..count {
            all.push(out[p * dimension] as f32);
            all.push(out[p * dimension + 1] as f32);
        }
    }
    let at = |frame: usize, p: usize| {
        [
            all[(frame * count + p) * 2],
            all[(frame * count + p) * 2 + 1],
        ]
    };
    let fixed: Vec<Option<[f32; 2]>> = (0..count)
        .map(|p| {
            let first = at(0, p);
            (0..frames.len())
                .all(|f| at(f, p) == first)
                .then_some(first)
        })
        .collect();
    let moving: Vec<usize> = (0..count).filter(|&p| fixed[p].is_none()).collect();
    let mut positions = Vec::with_capacity(frames.len() * moving.len() * 2);
    for f in 0..frames.len() {
        for &p in &moving {
            positions.extend(at(f, p));
        }
    }
    Ok(Drawn {
        dimension,
        points: drawing.points().to_vec(),
        shapes: drawing.shapes().iter().map(shape).collect(),
        trace: drawing.trace(),
        fixed,
        moving,
        positions,
    })
}

/// A shape as the page reads it.
fn shape(shape: &Shape) -> Value {
    match shape {
        Shape::Segment { from, to } => json!({ "segment": [from, to] }),
        Shape::Polyline { points, closed } => json!({ "polyline": points, "closed": closed }),
        Shape::Circle { center, radius } => json!({ "circle": center, "radius": radius }),
        Shape::Surface { constraint, points } => {
            json!({ "surface": points, "constraint": constraint })
        }
    }
}
