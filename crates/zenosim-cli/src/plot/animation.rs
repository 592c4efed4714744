//! `zenosim animate DIR --out FILE.gif`: the run's mechanism, as its model's `[drawing]` shows
//! it, frame by frame into an animated GIF.

use std::io::{BufWriter, Write};

use anyhow::{anyhow, Context};
use zenosim::HybridLagrangian;

use super::animation_frames::{self, Timing};
use super::animation_render::{self, View, COLOURS};
use super::canvas::register_font;
use super::gif_file::GifWriter;
use super::record::Record;
use crate::cli::AnimateArgs;
use crate::output::{split, OutputDir};
use crate::run::{MODEL, SUMMARY, TRAJECTORY};
use crate::{print_report, Classify, Failure, EXIT_OK};

/// The most coordinates of points kept over all frames (160 MB).
const MAX_VALUES: usize = 20_000_000;
/// The most operations evaluating the drawing at every frame may take (seconds).
const MAX_OPERATIONS: u64 = 2_000_000_000;

/// `zenosim animate`: writes the GIF; the exit status.
pub fn animate(args: &AnimateArgs) -> Result<u8, Failure> {
    let dir = &args.dir;
    let gif = args
        .out
        .extension()
        .is_some_and(|extension| extension.eq_ignore_ascii_case("gif"));
    if !gif {
        return Err(anyhow!(
            "--out {}: animate writes a GIF; give the file a .gif name",
            args.out.display()
        ))
        .bad_input();
    }
    let record = Record::read(&dir.join(SUMMARY)).bad_input()?;
    let model_path = match &args.model {
        Some(path) => path.clone(),
        None => {
            let path = dir.join(MODEL);
            if !path.exists() {
                return Err(anyhow!(
                    "{}: no {MODEL}: the run was written by a zenosim that did not keep the \
                     model beside its results; give the model file with --model MODEL.toml",
                    dir.display()
                ))
                .bad_input();
            }
            path
        }
    };
    let file = crate::input::load_for_run(&model_path, &record, args.formulas.limits())
        .map_err(|error| anyhow!("{error:#}; give the model that was run with --model MODEL.toml"))
        .bad_input()?;
    let model_name = model_path.display();
    let drawing = file
        .drawing
        .as_ref()
        .ok_or_else(|| {
            anyhow!(
                "{model_name}: the model has no [drawing], which animate draws: add one, \
                 points and the shapes between them (docs/drawing.md; every model in models/ \
                 has one)"
            )
        })
        .bad_input()?;

    // The frames: every step/fps seconds of simulated time, fewer if they would be too many.
    let delay = (100.0 / f64::from(args.fps)).round().max(2.0) as u16;
    let fps = 100.0 / f64::from(delay);
    let (start, end) = record.time_span();
    let end = record.final_.t.filter(|t| t.is_finite()).unwrap_or(end);
    let duration = (end - start).max(0.0);
    let mut step = args.speed / fps;
    let max_frames = args.max_frames as usize;
    // (3 s in steps of 0.02 is 150 steps, not the 149.99… that division rounds to.) Counted in
    // floating point first: a tiny --speed makes more frames than a usize holds, which wrapped
    // to none and was then blamed on trajectory.csv.
    let steps = (duration / step * (1.0 + 1e-12)).floor();
    let capped = !steps.is_finite() || steps + 1.0 > max_frames as f64;
    let count = if capped {
        step = duration / (max_frames - 1) as f64;
        max_frames
    } else {
        steps as usize + 1
    };
    // Every frame's points are kept (to fix the box) and each costs an evaluation of the whole
    // drawing: bounded, so that a drawing of many points cannot take unbounded memory or time.
    let values = drawing.points().len() * drawing.dimension();
    if count.saturating_mul(values) > MAX_VALUES
        || (count as u64).saturating_mul(drawing.operations() as u64) > MAX_OPERATIONS
    {
        return Err(anyhow!(
            "{model_name}: {count} frames of a drawing of {} points ({} operations each) is \
             more than animate draws (at most {MAX_VALUES} coordinates and {MAX_OPERATIONS} \
             operations in all): lower --max-frames, or draw fewer points",
            drawing.points().len(),
            drawing.operations()
        ))
        .bad_input();
    }
    let frames = animation_frames::read(
        &dir.join(TRAJECTORY),
        &record.coordinates,
        drawing,
        Timing { step, count },
    )
    .with_context(|| format!("drawing the mechanism of {model_name}"))
    .bad_input()?;

    register_font().output()?;
    let size = (args.size.width, args.size.height);
    let view = View::fit(drawing, &frames, size);
    let names: Vec<&str> = file
        .model
        .constraints()
        .iter()
        .map(|c| c.name.as_str())
        .collect();

    let (out_dir, name) = split(&args.out).output()?;
    let out = OutputDir::prepare(&out_dir).output()?;
    let (partial, handle) = out.create(&name).output()?;
    let target = partial.target().to_path_buf();
    let write_error = |e: anyhow::Error| e.context(format!("cannot write {}", target.display()));
    let mut gif = GifWriter::new(
        BufWriter::new(handle),
        (size.0 as u16, size.1 as u16),
        delay,
        &COLOURS,
    )
    .map_err(write_error)
    .output()?;
    let mut pixels = vec![0u8; size.0 as usize * size.1 as usize * 3];
    for f in 0..frames.times.len() {
        let held = held(&frames.modes[f], &names);
        animation_render::draw(&mut pixels, size, &view, drawing, &frames, f, &held).output()?;
        gif.frame(&pixels).map_err(write_error).output()?;
    }
    let handle = gif
        .finish()
        .and_then(|mut w| {
            w.flush()?;
            w.into_inner().map_err(|e| anyhow!(e.into_error()))
        })
        .map_err(write_error)
        .output()?;
    partial.commit(handle).output()?;

    let bytes = std::fs::metadata(&target).map(|m| m.len()).unwrap_or(0);
    let played = step * fps;
    let mut report =
        format!(
        "wrote {}: {} frames of {}x{}, {} fps, t from {} to {} s at {} simulated s per s{}; {} \
         KB\n",
        target.display(),
        frames.times.len(),
        size.0,
        size.1,
        fps,
        short(frames.times[0]),
        short(frames.times[frames.times.len() - 1]),
        short(played),
        if capped {
            format!(" (faster than --speed {}: --max-frames {max_frames} caps it)", args.speed)
        } else {
            String::new()
        },
        bytes.div_ceil(1024),
    );
    if let Some(note) = &frames.note {
        report.push_str(&format!("note: {note}\n"));
    }
    print_report(&report);
    Ok(EXIT_OK)
}

/// Which constraints the mode `constrained:a+b` holds (none for `free`); the friction states
/// after it (`;stick:a;slip:b`) are left aside.
fn held(mode: &str, names: &[&str]) -> Vec<bool> {
    let held_part = mode.split(';').next().unwrap_or(mode);
    let held: Vec<&str> = held_part
        .strip_prefix("constrained:")
        .map(|list| list.split('+').collect())
        .unwrap_or_default();
    names.iter().map(|n| held.contains(n)).collect()
}

/// A number in few digits for the report.
fn short(value: f64) -> String {
    let text = format!("{value:.4}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    text.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_say_which_constraints_are_held() {
        let names = ["floor", "wall", "ramp"];
        assert_eq!(held("free", &names), [false, false, false]);
        assert_eq!(held("constrained:wall", &names), [false, true, false]);
        assert_eq!(held("constrained:floor+ramp", &names), [true, false, true]);
        // With friction, the contacts' states follow: they name no held constraint.
        assert_eq!(
            held("constrained:floor+ramp;stick:floor;slip:ramp", &names),
            [true, false, true]
        );
        assert_eq!(
            held("constrained:wall;slip:wall", &names),
            [false, true, false]
        );
    }
}
