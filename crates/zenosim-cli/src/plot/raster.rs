//! A bitmap backend for plotters, for the PNG plots: every shape anti-aliased (its coverage of
//! each pixel blended in), lines with round joins (no miter spikes where a decimated series
//! turns back on itself), text set from the bundled font glyph by glyph at the font's advances
//! and side bearings, and everything drawn while the [`Layer`] has a clip kept inside it (the
//! series inside the plot).
//!
//! Coordinates are pixels' indices; a point stands for its pixel's centre.

use std::convert::Infallible;

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
    FontTransform,
};

use super::svg::{Clip, Layer};

/// Subsamples per pixel side when filling polygons.
const SUBSAMPLES: i32 = 4;

/// RGB pixels drawn into, row by row.
pub struct RasterCanvas<'a> {
    pixels: &'a mut [u8],
    size: (u32, u32),
    layer: Layer,
    font: Option<FontRef<'static>>,
}

impl<'a> RasterCanvas<'a> {
    /// A `width × height` canvas over `pixels` (3 bytes a pixel), clipped by `layer`'s clip,
    /// its text set in `font` (none: no text).
    pub fn new(
        pixels: &'a mut [u8],
        size: (u32, u32),
        layer: Layer,
        font: Option<FontRef<'static>>,
    ) -> Self {
        Self {
            pixels,
            size,
            layer,
            font,
        }
    }

    /// The pixels that may be drawn: the canvas, within the layer's clip.
    fn bounds(&self) -> Clip {
        let (w, h) = (self.size.0 as i32, self.size.1 as i32);
        match self.layer.clip() {
            Some(((x0, y0), (x1, y1))) => ((x0.max(0), y0.max(0)), (x1.min(w), y1.min(h))),
            None => ((0, 0), (w, h)),
        }
    }

    /// Blends `color` at `coverage` (0 to 1) into pixel `(x, y)`, if it may be drawn.
    fn blend(&mut self, (x, y): (i32, i32), color: BackendColor, coverage: f64, bounds: Clip) {
        let ((x0, y0), (x1, y1)) = bounds;
        if x < x0 || x >= x1 || y < y0 || y >= y1 {
            return;
        }
        let a = (coverage * color.alpha).clamp(0.0, 1.0);
        if a <= 0.0 {
            return;
        }
        let i = 3 * (y as usize * self.size.0 as usize + x as usize);
        let (r, g, b) = color.rgb;
        if a >= 1.0 {
            self.pixels[i..i + 3].copy_from_slice(&[r, g, b]);
            return;
        }
        for (k, c) in [r, g, b].into_iter().enumerate() {
            let old = f64::from(self.pixels[i + k]);
            // Rounded to the nearest (the sum is within 0..=255.5).
            self.pixels[i + k] = (old + (f64::from(c) - old) * a + 0.5) as u8;
        }
    }

    /// Fills, for each pixel of the box `(x0, y0)..=(x1, y1)` (clipped), the coverage that
    /// `coverage` gives its centre, each pixel blended once with the largest coverage.
    fn cover(
        &mut self,
        (x0, y0): (i32, i32),
        (x1, y1): (i32, i32),
        color: BackendColor,
        coverage: impl Fn(f64, f64) -> f64,
    ) {
        let bounds = self.bounds();
        let ((bx0, by0), (bx1, by1)) = bounds;
        for y in y0.max(by0)..=y1.min(by1 - 1) {
            for x in x0.max(bx0)..=x1.min(bx1 - 1) {
                let c = coverage(f64::from(x), f64::from(y));
                if c > 0.0 {
                    self.blend((x, y), color, c.min(1.0), bounds);
                }
            }
        }
    }

    /// Strokes the polyline `points` `width` pixels wide with round joins and caps, each pixel
    /// blended once.
    fn stroke(&mut self, points: &[(f64, f64)], width: f64, color: BackendColor) {
        let half = width.max(1.0) / 2.0;
        let Some(((x0, y0), (x1, y1))) = bbox(points, half + 1.0) else {
            return;
        };
        let bounds = self.bounds();
        let ((bx0, by0), (bx1, by1)) = bounds;
        let (x0, y0, x1, y1) = (x0.max(bx0), y0.max(by0), x1.min(bx1 - 1), y1.min(by1 - 1));
        if x0 > x1 || y0 > y1 {
            return;
        }
        // The largest coverage of each pixel of the box, over the segments.
        let w = (x1 - x0 + 1) as usize;
        let mut cover = vec![0f32; w * (y1 - y0 + 1) as usize];
        let segments: Vec<((f64, f64), (f64, f64))> = if points.len() == 1 {
            vec![(points[0], points[0])]
        } else {
            points.windows(2).map(|s| (s[0], s[1])).collect()
        };
        let inner = if half > 0.5 {
            (half - 0.5).powi(2)
        } else {
            -1.0
        };
        let outer = (half + 0.5).powi(2);
        for (a, b) in segments {
            let Some(((sx0, sy0), (sx1, sy1))) = bbox(&[a, b], half + 1.0) else {
                continue;
            };
            // Along each row, only across the band within reach of the segment's line.
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let reach = (half + 1.0) * dx.hypot(dy) / dy.abs();
            for y in sy0.max(y0)..=sy1.min(y1) {
                let (from, to) = if dy.abs() > 1e-9 && reach.is_finite() {
                    let centre = a.0 + (f64::from(y) - a.1) * dx / dy;
                    let clamp = |v: f64| v.clamp(f64::from(sx0), f64::from(sx1)) as i32;
                    (
                        clamp((centre - reach).floor()),
                        clamp((centre + reach).ceil()),
                    )
                } else {
                    (sx0, sx1)
                };
                for x in from.max(x0)..=to.min(x1) {
                    // Squared distances first: the square root only on the edge.
                    let d2 = distance_squared((f64::from(x), f64::from(y)), a, b);
                    let c = if d2 <= inner {
                        1.0
                    } else if d2 >= outer {
                        continue;
                    } else {
                        (half + 0.5 - d2.sqrt()).clamp(0.0, 1.0) as f32
                    };
                    let k = (y - y0) as usize * w + (x - x0) as usize;
                    if c > cover[k] {
                        cover[k] = c;
                    }
                }
            }
        }
        for (k, &c) in cover.iter().enumerate() {
            if c > 0.0 {
                let (x, y) = (x0 + (k % w) as i32, y0 + (k / w) as i32);
                self.blend((x, y), color, f64::from(c), bounds);
            }
        }
    }
}

/// The box of whole pixels around `points`, widened by `margin`; `None` for no point or a
/// coordinate out of any canvas.
fn bbox(points: &[(f64, f64)], margin: f64) -> Option<Clip> {
    let first = points.first()?;
    let (mut x0, mut y0, mut x1, mut y1) = (first.0, first.1, first.0, first.1);
    for p in points {
        (x0, y0, x1, y1) = (x0.min(p.0), y0.min(p.1), x1.max(p.0), y1.max(p.1));
    }
    let limit = f64::from(i32::MAX / 2);
    let clamp = |v: f64| v.clamp(-limit, limit) as i32;
    Some((
        (clamp((x0 - margin).floor()), clamp((y0 - margin).floor())),
        (clamp((x1 + margin).ceil()), clamp((y1 + margin).ceil())),
    ))
}

/// The squared distance from `p` to the segment `a`–`b`.
fn distance_squared(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let length = dx * dx + dy * dy;
    let s = if length > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / length).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (ex, ey) = (p.0 - a.0 - s * dx, p.1 - a.1 - s * dy);
    ex * ex + ey * ey
}

/// A backend coordinate as a point.
fn point((x, y): BackendCoord) -> (f64, f64) {
    (f64::from(x), f64::from(y))
}

/// Whether `p` is inside `polygon` (even–odd).
fn inside(p: (f64, f64), polygon: &[(f64, f64)]) -> bool {
    let mut inside = false;
    let mut j = polygon.len() - 1;
    for i in 0..polygon.len() {
        let (a, b) = (polygon[i], polygon[j]);
        if (a.1 > p.1) != (b.1 > p.1) && p.0 < a.0 + (p.1 - a.1) / (b.1 - a.1) * (b.0 - a.0) {
            inside = !inside;
        }
        j = i;
    }
    inside
}

/// The glyphs of `text` in `font` at `scale`, placed along a baseline from 0 (advances and
/// kerning), and the text's advance.
pub fn layout(font: &FontRef<'_>, scale: PxScale, text: &str) -> (Vec<ab_glyph::Glyph>, f32) {
    let scaled = font.as_scaled(scale);
    let mut caret = 0.0;
    let mut previous = None;
    let mut glyphs = Vec::with_capacity(text.len());
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(previous) = previous {
            caret += scaled.kern(previous, id);
        }
        glyphs.push(id.with_scale_and_position(scale, ab_glyph::point(caret, 0.0)));
        caret += scaled.h_advance(id);
        previous = Some(id);
    }
    (glyphs, caret)
}

/// The scale of `font` for plotters' text size `size` (its line height): an em of `size / 1.24`
/// pixels, as the SVG sets it.
pub fn scale_for(font: &FontRef<'_>, size: f64) -> PxScale {
    let em = (size / 1.24) as f32;
    let units = font.units_per_em().unwrap_or(2048.0);
    PxScale::from(em * font.height_unscaled() / units)
}

impl DrawingBackend for RasterCanvas<'_> {
    type ErrorType = Infallible;

    fn get_size(&self) -> (u32, u32) {
        self.size
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Infallible>> {
        Ok(())
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Infallible>> {
        Ok(())
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Infallible>> {
        let bounds = self.bounds();
        self.blend(point, color, 1.0, bounds);
        Ok(())
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Infallible>> {
        let width = f64::from(style.stroke_width());
        if from.0 == to.0 || from.1 == to.1 {
            // Along the pixels: whole pixels, crisp, as many rows (or columns) as it is wide.
            let w = style.stroke_width().max(1) as i32;
            let (lo, hi) = (-(w - 1) / 2, w / 2);
            let (x0, x1) = (from.0.min(to.0), from.0.max(to.0));
            let (y0, y1) = (from.1.min(to.1), from.1.max(to.1));
            let (a, b) = if from.1 == to.1 {
                ((x0, y0 + lo), (x1, y1 + hi))
            } else {
                ((x0 + lo, y0), (x1 + hi, y1))
            };
            self.cover(a, b, style.color(), |_, _| 1.0);
            return Ok(());
        }
        self.stroke(&[point(from), point(to)], width, style.color());
        Ok(())
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        a: BackendCoord,
        b: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Infallible>> {
        let (x0, x1) = (a.0.min(b.0), a.0.max(b.0));
        let (y0, y1) = (a.1.min(b.1), a.1.max(b.1));
        if fill {
            self.cover((x0, y0), (x1, y1), style.color(), |_, _| 1.0);
        } else {
            for (p, q) in [
                ((x0, y0), (x1, y0)),
                ((x1, y0), (x1, y1)),
                ((x1, y1), (x0, y1)),
                ((x0, y1), (x0, y0)),
            ] {
                self.draw_line(p, q, style)?;
            }
        }
        Ok(())
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Infallible>> {
        let points: Vec<(f64, f64)> = path.into_iter().map(point).collect();
        if points.len() == 2 {
            let to = |p: (f64, f64)| (p.0 as i32, p.1 as i32);
            return self.draw_line(to(points[0]), to(points[1]), style);
        }
        self.stroke(&points, f64::from(style.stroke_width()), style.color());
        Ok(())
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        centre: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Infallible>> {
        let (cx, cy) = point(centre);
        let r = f64::from(radius);
        let half = f64::from(style.stroke_width().max(1)) / 2.0;
        let reach = (r + half + 1.0).ceil() as i32;
        self.cover(
            (centre.0 - reach, centre.1 - reach),
            (centre.0 + reach, centre.1 + reach),
            style.color(),
            |x, y| {
                let d = ((x - cx) * (x - cx) + (y - cy) * (y - cy)).sqrt();
                if fill {
                    r + 0.5 - d
                } else {
                    half + 0.5 - (d - r).abs()
                }
            },
        );
        Ok(())
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vertices: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Infallible>> {
        let polygon: Vec<(f64, f64)> = vertices.into_iter().map(point).collect();
        let Some((a, b)) = bbox(&polygon, 1.0) else {
            return Ok(());
        };
        if polygon.len() < 3 {
            return Ok(());
        }
        // The share of a pixel's subsamples inside.
        let n = SUBSAMPLES;
        let step = 1.0 / f64::from(n);
        self.cover(a, b, style.color(), |x, y| {
            let mut hits = 0;
            for i in 0..n {
                for j in 0..n {
                    let p = (
                        x - 0.5 + step * (f64::from(i) + 0.5),
                        y - 0.5 + step * (f64::from(j) + 0.5),
                    );
                    hits += i32::from(inside(p, &polygon));
                }
            }
            f64::from(hits) / f64::from(n * n)
        });
        Ok(())
    }

    fn draw_text<TStyle: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &TStyle,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Infallible>> {
        let Some(font) = self.font.clone() else {
            return Ok(());
        };
        let color = style.color();
        let scale = scale_for(&font, style.size());
        let (glyphs, advance) = layout(&font, scale, text);
        let em = (style.size() / 1.24) as f32;
        let dx = match style.anchor().h_pos {
            HPos::Left => 0.0,
            HPos::Center => -advance / 2.0,
            HPos::Right => -advance,
        };
        // The baseline below the anchor, as the SVG places it.
        let baseline = match style.anchor().v_pos {
            VPos::Top => 0.8 * em,
            VPos::Center => 0.35 * em,
            VPos::Bottom => -0.2 * em,
        };
        let (dx, baseline) = (dx.round(), baseline.round());
        let transform = style.transform();
        let bounds = self.bounds();
        for glyph in glyphs {
            let Some(outline) = font.outline_glyph(glyph) else {
                continue;
            };
            let at = outline.px_bounds().min;
            outline.draw(|gx, gy, coverage| {
                let x = (at.x + dx) as i32 + gx as i32;
                let y = (at.y + baseline) as i32 + gy as i32;
                let (x, y) = match transform {
                    FontTransform::None => (x, y),
                    FontTransform::Rotate90 => (-y, x),
                    FontTransform::Rotate180 => (-x, -y),
                    FontTransform::Rotate270 => (y, -x),
                };
                self.blend((pos.0 + x, pos.1 + y), color, f64::from(coverage), bounds);
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::*;

    fn canvas_pixels(
        size: (u32, u32),
        draw: impl FnOnce(&DrawingArea<RasterCanvas, plotters::coord::Shift>),
    ) -> Vec<u8> {
        let mut pixels = vec![255; size.0 as usize * size.1 as usize * 3];
        {
            let font = FontRef::try_from_slice(super::super::canvas::FONT_FILE).ok();
            let area =
                RasterCanvas::new(&mut pixels, size, Layer::default(), font).into_drawing_area();
            draw(&area);
        }
        pixels
    }

    #[test]
    fn lines_are_anti_aliased_and_rows_crisp() {
        let pixels = canvas_pixels((40, 40), |area| {
            area.draw(&PathElement::new(
                vec![(2, 2), (37, 20)],
                Color::stroke_width(&BLACK, 2),
            ))
            .unwrap();
            area.draw(&PathElement::new(
                vec![(2, 30), (37, 30)],
                Color::stroke_width(&BLACK, 1),
            ))
            .unwrap();
        });
        let at = |x: usize, y: usize| pixels[3 * (y * 40 + x)];
        // A sloped line has pixels between black and white along its edges.
        let grey = (0..40)
            .flat_map(|x| (0..25).map(move |y| (x, y)))
            .filter(|&(x, y)| (30..225).contains(&at(x, y)))
            .count();
        assert!(grey > 20, "{grey} grey pixels");
        // A horizontal line one pixel wide is one row of black.
        assert_eq!((at(20, 29), at(20, 30), at(20, 31)), (255, 0, 255));
    }
}
