//! The configuration plane: one coordinate (or velocity) against another, the path of the run
//! over the curves `h = 0` of the constraints that depend on those two coordinates only, with
//! the start, the impacts, the lift-offs and the Zeno points marked.

use plotters::coord::Shift;
use plotters::prelude::{
    Circle, Color, DrawingArea, EmptyElement, IntoFont, LineSeries, Rectangle, ShapeStyle, Text,
    TextStyle, TriangleMarker, WHITE,
};
use plotters::style::text_anchor::{HPos, VPos};
use plotters_backend::DrawingBackend;

use super::canvas::FONT;
use super::canvas::{Drawn, Picture};
use super::chart::{axes, drawable, frame, legend, note, Entry, Sample};
use super::decimate::Bounds;
use super::record::StateRecord;
use super::scene::{PlaneScale, Scene};
use super::style::{
    color, short, IMPACT, LIFTOFF, LINE_WIDTH, SURFACES, SWITCH, TEXT_SIZE, TITLE_SIZE,
};
use super::svg::Layer;

/// The plane plot as a picture of its own.
pub struct PlaneChart<'a> {
    /// The run.
    pub scene: &'a Scene,
}

impl Picture for PlaneChart<'_> {
    fn size(&self) -> (u32, u32) {
        (1000, 640)
    }

    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, layer: &Layer) -> Drawn<DB> {
        area.fill(&WHITE)?;
        let caption = format!("{}: {}", self.scene.record.model, plane_title(self.scene));
        draw_plane(area, layer, self.scene, &caption)
    }
}

/// `configuration plane, y against x`.
pub fn plane_title(scene: &Scene) -> String {
    format!(
        "configuration plane, {} against {}",
        scene.name(scene.plane.1),
        scene.name(scene.plane.0)
    )
}

/// Draws the plane plot of `scene` on `area`, under `caption`.
pub fn draw_plane<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    layer: &Layer,
    scene: &Scene,
    caption: &str,
) -> Drawn<DB> {
    let (px, py) = scene.plane;
    let mut bounds = scene.plane_box;
    let record = &scene.record;
    let surfaces: Vec<ShapeStyle> = (0..scene.curves.len())
        .map(|k| SURFACES[k % SURFACES.len()].stroke_width(4))
        .collect();
    let path = color(0).stroke_width(LINE_WIDTH);
    let start = color(2).filled();
    let impact = IMPACT.stroke_width(2);
    let liftoff = LIFTOFF.filled();
    let zeno = SWITCH.filled();
    let (impacts, liftoffs) = (record.times("impact"), record.times("liftoff"));
    let mut entries: Vec<Entry> = scene
        .curves
        .iter()
        .zip(&surfaces)
        .map(|(curve, &style)| {
            let label = format!("{}: h = 0", curve.constraint);
            Entry::new(label, Sample::Line(style))
        })
        .collect();
    entries.push(Entry::new("path", Sample::Line(path)));
    entries.push(Entry::new("start", Sample::Dot(start, 6)));
    entries.push(Entry::new(
        format!("impact ({})", impacts.len()),
        Sample::Dot(impact, 4),
    ));
    if !liftoffs.is_empty() {
        let label = format!("lift-off ({})", liftoffs.len());
        entries.push(Entry::new(label, Sample::Triangle(liftoff)));
    }
    if !record.zeno.is_empty() {
        entries.push(Entry::new("Zeno point", Sample::Square(zeno)));
    }

    // The caption as plotters' chart builder places it; the plot below it.
    let body = area.titled(caption, (FONT, TITLE_SIZE))?;
    let n = record.coordinates.len();
    let mut redrawn = None;
    if scene.scale == PlaneScale::Equal && px < n && py < n {
        // Two coordinates: a unit is as long on both axes (a 45° wall looks it), the box
        // widened about its middle along the axis that has room to spare.
        let probe = frame(&body, "", &entries)
            .build_cartesian_2d(drawable(bounds.x), drawable(bounds.y))?;
        let (w, h) = probe.plotting_area().dim_in_pixel();
        let equal = equal_scales(bounds, (w, h));
        if equal != bounds {
            bounds = equal;
            redrawn = Some(super::scene::curves(record, scene.plane, bounds));
        }
    }
    let curves = redrawn.as_ref().unwrap_or(&scene.curves);
    let mut chart =
        frame(&body, "", &entries).build_cartesian_2d(drawable(bounds.x), drawable(bounds.y))?;
    axes(&mut chart, layer, scene.name(px), scene.name(py))?;
    layer.clip_to(&chart.plotting_area().strip_coord_spec());
    for (curve, &style) in curves.iter().zip(&surfaces) {
        layer.set("constraint", &curve.constraint);
        for line in &curve.lines {
            chart.draw_series(LineSeries::new(line.iter().copied(), style))?;
        }
    }
    layer.set("series", "path");
    chart.draw_series(LineSeries::new(scene.trajectory.path.iter().copied(), path))?;
    layer.unclip();
    if let Some(&first) = scene.trajectory.path.first() {
        layer.set("start", "");
        chart.draw_series([Circle::new(first, 6, start)])?;
    }

    let at = |state: &StateRecord| (state.value(px), state.value(py));
    let events = |kind: &'static str| {
        record
            .events
            .iter()
            .filter(move |e| e.kind == kind)
            .map(|e| at(&e.before))
    };
    layer.set("impacts", "");
    // Marks on a pixel already marked add nothing but size (the table's 32 000 impacts).
    let pixel = |p: &(f64, f64)| chart.backend_coord(p);
    let impacts: Vec<(f64, f64)> = events("impact").collect();
    let thin = impacts.len() > 500;
    let mut seen = std::collections::HashSet::new();
    let shown: Vec<(f64, f64)> = impacts
        .into_iter()
        .filter(|p| !thin || seen.insert(pixel(p)))
        .collect();
    chart.draw_series(shown.into_iter().map(|p| Circle::new(p, 4, impact)))?;
    if !liftoffs.is_empty() {
        layer.set("liftoffs", "");
        let all: Vec<(f64, f64)> = events("liftoff").collect();
        let thin = all.len() > 500;
        let mut seen = std::collections::HashSet::new();
        let shown: Vec<(f64, f64)> = all
            .into_iter()
            .filter(|p| !thin || seen.insert(chart.backend_coord(p)))
            .collect();
        chart.draw_series(
            shown
                .into_iter()
                .map(|p| TriangleMarker::new(p, 7, liftoff)),
        )?;
    }
    // The labels placed, as pixel boxes: a label that would overprint one is left out (the
    // table's thousands of Zeno points), as is a mark on the pixel of the one before.
    let mut placed: Vec<(i32, i32, i32, i32)> = Vec::new();
    let mut last_mark = None;
    let style = TextStyle::from((FONT, TEXT_SIZE).into_font());
    for (k, z) in record.zeno.iter().enumerate() {
        let stalled = record.stalled() && k + 1 == record.zeno.len();
        let (class, text) = if stalled {
            ("stall", format!("stalled, t = {}", short(z.t_switch)))
        } else {
            ("switch", format!("Zeno point, t = {}", short(z.t_switch)))
        };
        layer.set(class, &z.constraint);
        // The label goes towards the middle of the plot, where there is room for it.
        let (x, y) = at(z.point());
        let (dx, h) = if x > bounds.x.0 + 0.7 * (bounds.x.1 - bounds.x.0) {
            (-9, HPos::Right)
        } else {
            (9, HPos::Left)
        };
        let (dy, v) = if y < bounds.y.0 + 0.5 * (bounds.y.1 - bounds.y.0) {
            (-8, VPos::Bottom)
        } else {
            (8, VPos::Top)
        };
        let (px, py) = chart.backend_coord(&(x, y));
        if last_mark != Some((px, py)) || stalled {
            chart.draw_series([
                EmptyElement::at((x, y)) + Rectangle::new([(-5, -5), (5, 5)], zeno)
            ])?;
            last_mark = Some((px, py));
        }
        let width = area
            .estimate_text_size(&text, &style)
            .map_or(8 * text.chars().count() as i32, |size| size.0 as i32);
        let height = TEXT_SIZE as i32;
        let left = if dx < 0 { px + dx - width } else { px + dx };
        let top = if dy < 0 { py + dy - height } else { py + dy };
        let label = (left, top, left + width, top + height);
        let apart = |b: &(i32, i32, i32, i32)| {
            label.2 + 4 < b.0 || b.2 + 4 < label.0 || label.3 + 2 < b.1 || b.3 + 2 < label.1
        };
        if placed.iter().all(apart) {
            placed.push(label);
            chart.draw_series([
                EmptyElement::at((x, y)) + Text::new(text, (dx, dy), note(SWITCH, h, v))
            ])?;
        }
    }
    legend(area, &chart, layer, &entries)
}

/// `bounds` widened about their middle so that a unit is as many pixels on both axes of a plot
/// of `(width, height)` pixels.
pub fn equal_scales(bounds: Bounds, (width, height): (u32, u32)) -> Bounds {
    let (w, h) = (f64::from(width.max(1)), f64::from(height.max(1)));
    let (dx, dy) = (bounds.x.1 - bounds.x.0, bounds.y.1 - bounds.y.0);
    let scale = (dx / w).max(dy / h);
    if !(scale.is_finite() && scale > 0.0) {
        return bounds;
    }
    let widen = |(low, high): (f64, f64), pixels: f64| {
        let (middle, half) = (low / 2.0 + high / 2.0, scale * pixels / 2.0);
        if half > (high - low) / 2.0 && (middle - half).is_finite() && (middle + half).is_finite() {
            (middle - half, middle + half)
        } else {
            (low, high)
        }
    };
    Bounds {
        x: widen(bounds.x, w),
        y: widen(bounds.y, h),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_scales_widen_the_narrow_axis() {
        let b = Bounds {
            x: (0.0, 10.0),
            y: (0.0, 1.0),
        };
        let e = equal_scales(b, (500, 250));
        assert_eq!(e.x, (0.0, 10.0));
        assert_eq!(e.y, (-2.0, 3.0));
        let e = equal_scales(
            Bounds {
                x: (0.0, 1.0),
                y: (0.0, 4.0),
            },
            (100, 100),
        );
        assert_eq!((e.x, e.y), ((-1.5, 2.5), (0.0, 4.0)));
    }
}
