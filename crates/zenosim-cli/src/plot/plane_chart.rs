//! The configuration plane: one coordinate (or velocity) against another, the path of the run
//! over the curves `h = 0` of the constraints that depend on those two coordinates only, with
//! the start, the impacts, the lift-offs and the Zeno points marked.

use plotters::coord::Shift;
use plotters::prelude::{
    Circle, Color, DrawingArea, EmptyElement, LineSeries, Rectangle, ShapeStyle, Text,
    TriangleMarker, WHITE,
};
use plotters::style::text_anchor::{HPos, VPos};
use plotters_backend::DrawingBackend;

use super::canvas::{Drawn, Picture};
use super::chart::{axes, drawable, frame, legend, note, Entry, Sample};
use super::record::StateRecord;
use super::scene::Scene;
use super::style::{color, short, IMPACT, LIFTOFF, LINE_WIDTH, SURFACES, SWITCH};
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
    let bounds = scene.plane_box;
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

    let mut chart = frame(area, caption, &entries)
        .build_cartesian_2d(drawable(bounds.x), drawable(bounds.y))?;
    axes(&mut chart, layer, scene.name(px), scene.name(py))?;
    for (curve, &style) in scene.curves.iter().zip(&surfaces) {
        layer.set("constraint", &curve.constraint);
        for line in &curve.lines {
            chart.draw_series(LineSeries::new(line.iter().copied(), style))?;
        }
    }
    layer.set("series", "path");
    chart.draw_series(LineSeries::new(scene.trajectory.path.iter().copied(), path))?;
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
    chart.draw_series(events("impact").map(|p| Circle::new(p, 4, impact)))?;
    if !liftoffs.is_empty() {
        layer.set("liftoffs", "");
        chart.draw_series(events("liftoff").map(|p| TriangleMarker::new(p, 7, liftoff)))?;
    }
    for (k, z) in record.zeno.iter().enumerate() {
        let stalled = record.stalled() && k + 1 == record.zeno.len();
        let (class, text) = if stalled {
            ("stall", format!("stalled, t = {}", short(z.t_switch)))
        } else {
            ("switch", format!("Zeno point, t = {}", short(z.t_switch)))
        };
        layer.set(class, &z.constraint);
        // The label goes towards the middle of the plot, where there is room for it.
        let (x, y) = at(&z.point);
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
        chart.draw_series([EmptyElement::at((x, y))
            + Rectangle::new([(-5, -5), (5, 5)], zeno)
            + Text::new(text, (dx, dy), note(SWITCH, h, v))])?;
    }
    legend(area, &chart, layer, &entries)
}
