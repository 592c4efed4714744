//! One frame of an animation: the drawing's shapes at the frame's points, in a box fixed over
//! the whole run with equal scales in x and y, the trace behind them, the held constraints'
//! surfaces in colour, and the time and mode in the top left corner.

use plotters::prelude::*;
use zenosim_model::{Drawing, Shape};

use super::animation_frames::Frames;
use super::canvas::FONT;

/// The mechanism's lines and the text.
pub const INK: [u8; 3] = [30, 30, 30];
/// A surface not held.
pub const SURFACE: [u8; 3] = [120, 120, 120];
/// A surface held (in contact).
pub const HELD: [u8; 3] = [215, 50, 30];
/// The trace.
pub const TRACE: [u8; 3] = [40, 100, 200];
/// The inside of circles.
pub const FILL: [u8; 3] = [185, 210, 240];
/// Every colour a frame is drawn in, besides white.
pub const COLOURS: [[u8; 3]; 5] = [INK, SURFACE, HELD, TRACE, FILL];

/// Pixels kept free above the box, for the time and the mode.
const HEADER: f64 = 28.0;
/// Pixels of margin around the box.
const MARGIN: f64 = 12.0;

/// Where the drawing's plane is on the frame: pixel = (x − x0, y0 − y) · scale + offset.
#[derive(Clone, Copy, Debug)]
pub struct View {
    scale: f64,
    x0: f64,
    y0: f64,
    left: f64,
    top: f64,
}

impl View {
    /// The view that shows every point of every frame, every circle and the trace in
    /// `width × height` pixels, with equal scales, centred.
    pub fn fit(drawing: &Drawing, frames: &Frames, (width, height): (u32, u32)) -> Self {
        let d = drawing.dimension();
        let (mut xmin, mut xmax, mut ymin, mut ymax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        let mut cover = |x: f64, y: f64, r: f64| {
            xmin = xmin.min(x - r);
            xmax = xmax.max(x + r);
            ymin = ymin.min(y - r);
            ymax = ymax.max(y + r);
        };
        for points in &frames.points {
            for k in 0..drawing.points().len() {
                cover(points[k * d], points[k * d + 1], 0.0);
            }
            for shape in drawing.shapes() {
                if let Shape::Circle { center, radius } = shape {
                    cover(points[center * d], points[center * d + 1], *radius);
                }
            }
        }
        for &(x, y) in &frames.trace {
            cover(x, y, 0.0);
        }
        // A box of no extent (a single point) is shown 1 unit wide.
        let pad = |lo: &mut f64, hi: &mut f64| {
            if *hi - *lo <= 0.0 {
                *lo -= 0.5;
                *hi += 0.5;
            }
        };
        pad(&mut xmin, &mut xmax);
        pad(&mut ymin, &mut ymax);
        let free_w = f64::from(width) - 2.0 * MARGIN;
        let free_h = f64::from(height) - 2.0 * MARGIN - HEADER;
        let scale = (free_w / (xmax - xmin)).min(free_h / (ymax - ymin));
        let left = MARGIN + (free_w - scale * (xmax - xmin)) / 2.0;
        let top = HEADER + MARGIN + (free_h - scale * (ymax - ymin)) / 2.0;
        Self {
            scale,
            x0: xmin,
            y0: ymax,
            left,
            top,
        }
    }

    /// The pixel of the point `(x, y)`.
    pub fn pixel(&self, x: f64, y: f64) -> (i32, i32) {
        (
            (self.left + (x - self.x0) * self.scale).round() as i32,
            (self.top + (self.y0 - y) * self.scale).round() as i32,
        )
    }

    /// Pixels per unit.
    pub fn scale(&self) -> f64 {
        self.scale
    }
}

fn colour(rgb: [u8; 3]) -> RGBColor {
    RGBColor(rgb[0], rgb[1], rgb[2])
}

/// Frame `f` of `frames` drawn into `pixels` (RGB, row by row, `size`), with `held[i]` telling
/// whether constraint `i` is held.
pub fn draw(
    pixels: &mut [u8],
    size: (u32, u32),
    view: &View,
    drawing: &Drawing,
    frames: &Frames,
    f: usize,
    held: &[bool],
) -> anyhow::Result<()> {
    let failed = |e: String| anyhow::anyhow!("cannot draw frame {f}: {e}");
    let area = BitMapBackend::with_buffer(pixels, size).into_drawing_area();
    area.fill(&WHITE).map_err(|e| failed(e.to_string()))?;
    let d = drawing.dimension();
    let points = &frames.points[f];
    let at = |k: usize| view.pixel(points[k * d], points[k * d + 1]);

    let trace = &frames.trace[..frames.trace_end[f]];
    if trace.len() > 1 {
        let path: Vec<(i32, i32)> = trace.iter().map(|&(x, y)| view.pixel(x, y)).collect();
        area.draw(&PathElement::new(path, colour(TRACE).stroke_width(1)))
            .map_err(|e| failed(e.to_string()))?;
    }
    for shape in drawing.shapes() {
        let drawn = match shape {
            Shape::Segment { from, to } => area.draw(&PathElement::new(
                vec![at(*from), at(*to)],
                colour(INK).stroke_width(2),
            )),
            Shape::Polyline { points, closed } => {
                let mut path: Vec<(i32, i32)> = points.iter().map(|&k| at(k)).collect();
                if *closed {
                    path.push(at(points[0]));
                }
                area.draw(&PathElement::new(path, colour(INK).stroke_width(2)))
            }
            Shape::Circle { center, radius } => {
                let r = ((radius * view.scale()).round() as i32).max(2);
                let c = at(*center);
                area.draw(&Circle::new(c, r, colour(FILL).filled()))
                    .and_then(|()| area.draw(&Circle::new(c, r, colour(INK).stroke_width(2))))
            }
            Shape::Surface { constraint, points } => {
                let on = held.get(*constraint).copied().unwrap_or(false);
                let style = if on {
                    colour(HELD).stroke_width(4)
                } else {
                    colour(SURFACE).stroke_width(2)
                };
                let path: Vec<(i32, i32)> = points.iter().map(|&k| at(k)).collect();
                area.draw(&PathElement::new(path, style))
            }
        };
        drawn.map_err(|e| failed(e.to_string()))?;
    }
    let label = format!("t = {:.3} s   {}", frames.times[f], frames.modes[f]);
    area.draw(&Text::new(
        label,
        (8, 6),
        (FONT, 16.0).into_font().color(&colour(INK)),
    ))
    .map_err(|e| failed(e.to_string()))?;
    area.present().map_err(|e| failed(e.to_string()))?;
    Ok(())
}
