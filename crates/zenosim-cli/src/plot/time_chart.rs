//! Quantities against time (the velocities, the displacements, the energy), one line per
//! series, with the run's events marked: impacts and lift-offs along the time axis, and each
//! switch to the constrained motion (or the stall at a Zeno point) as a labelled vertical line.
//! Beside the energy, when the trajectory has the energy balance, `E(0) + work − impact loss`
//! dashed over it: where the balance holds, the two coincide.

use plotters::chart::ChartContext;
use plotters::coord::cartesian::Cartesian2d;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::{
    Circle, Color, DashedLineSeries, DrawingArea, EmptyElement, LineSeries, PathElement, RGBColor,
    ShapeStyle, Text, TriangleMarker, WHITE,
};
use plotters::style::text_anchor::{HPos, VPos};
use plotters_backend::DrawingBackend;

use super::canvas::{Drawn, Picture};
use super::chart::{axes, drawable, frame, legend, note, Entry, Sample};
use super::scene::{pad, Scene};
use super::style::{color, short, IMPACT, LIFTOFF, LINE_WIDTH, SWITCH};
use super::svg::Layer;

/// The label of the energy balance's curve on the energy chart.
pub const BALANCE: &str = "E(0) + work − impact loss";
/// Its dashes and the gaps between them, in pixels.
const DASH: (u32, u32) = (7, 5);

/// What a time chart shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// `q̇` against `t`.
    Velocities,
    /// `q` against `t`.
    Displacements,
    /// The energy against `t`.
    Energy,
}

impl Quantity {
    /// The plot's name: its file name and caption.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Velocities => "velocities",
            Quantity::Displacements => "displacements",
            Quantity::Energy => "energy",
        }
    }

    fn axis(self) -> &'static str {
        match self {
            Quantity::Velocities => "velocity",
            Quantity::Displacements => "displacement",
            Quantity::Energy => "energy",
        }
    }

    /// The trajectory's series it shows as solid lines, and their colours' indices.
    fn series(self, n: usize) -> std::ops::Range<usize> {
        match self {
            Quantity::Displacements => 0..n,
            Quantity::Velocities => n..2 * n,
            Quantity::Energy => 2 * n..2 * n + 1,
        }
    }

    /// The trajectory's series it shows dashed over them: the energy balance.
    fn dashed(self, n: usize, scene: &Scene) -> Option<usize> {
        (self == Quantity::Energy && scene.trajectory.balance).then_some(2 * n + 1)
    }
}

/// A time chart as a picture of its own.
pub struct TimeChart<'a> {
    /// The run.
    pub scene: &'a Scene,
    /// What it shows.
    pub quantity: Quantity,
}

impl Picture for TimeChart<'_> {
    fn size(&self) -> (u32, u32) {
        match self.quantity {
            Quantity::Energy => (1000, 420),
            _ => (1000, 480),
        }
    }

    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, layer: &Layer) -> Drawn<DB> {
        area.fill(&WHITE)?;
        let caption = format!("{}: {}", self.scene.record.model, self.quantity.name());
        draw_time(area, layer, self.scene, self.quantity, &caption)
    }
}

/// Draws `quantity` of `scene` against time on `area`, under `caption`.
pub fn draw_time<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    layer: &Layer,
    scene: &Scene,
    quantity: Quantity,
    caption: &str,
) -> Drawn<DB> {
    let n = scene.record.coordinates.len();
    let series = quantity.series(n);
    let dashed = quantity.dashed(n, scene);
    let lines = &scene.trajectory;
    let range = series
        .clone()
        .chain(dashed)
        .filter_map(|s| lines.ranges[s])
        .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
        .unwrap_or((-1.0, 1.0));
    // Room below the lines for the event marks, and above for the switch labels.
    let (low, high) = pad(range, 0.1, 0.12);
    let (t0, t1) = scene.record.time_span();
    let t1 = if t1 > t0 { t1 } else { t0 + 1.0 };
    let names: Vec<&str> = series
        .clone()
        .map(|s| match quantity {
            Quantity::Energy => "energy",
            _ => scene.name(s),
        })
        .collect();
    let styles: Vec<ShapeStyle> = (0..names.len())
        .map(|k| color(k).stroke_width(LINE_WIDTH))
        .collect();
    let record = &scene.record;
    let (impacts, liftoffs) = (record.times("impact"), record.times("liftoff"));
    let mut entries: Vec<Entry> = names
        .iter()
        .zip(&styles)
        .map(|(name, &style)| Entry::new(*name, Sample::Line(style)))
        .collect();
    let dashed_style = color(names.len()).stroke_width(LINE_WIDTH);
    if dashed.is_some() {
        entries.push(Entry::new(BALANCE, Sample::Dashed(dashed_style)));
    }
    // With impacts on several constraints, each constraint's on a row of its own.
    let by_constraint = record.impacts_by_constraint();
    let rows: Vec<(String, Vec<f64>, RGBColor)> = if by_constraint.len() > 1 {
        by_constraint
            .into_iter()
            .enumerate()
            .map(|(k, (name, times))| (name.to_string(), times, impact_color(k)))
            .collect()
    } else {
        vec![(String::new(), impacts.clone(), IMPACT)]
    };
    for (name, times, c) in &rows {
        let label = if name.is_empty() {
            format!("impact ({})", times.len())
        } else {
            format!("impact on {name} ({})", times.len())
        };
        entries.push(Entry::new(label, Sample::Dot(c.filled(), 4)));
    }
    if !liftoffs.is_empty() {
        let label = format!("lift-off ({})", liftoffs.len());
        entries.push(Entry::new(label, Sample::Triangle(LIFTOFF.filled())));
    }

    let mut chart = frame(area, caption, &entries)
        .build_cartesian_2d(drawable((t0, t1)), drawable((low, high)))?;
    axes(&mut chart, layer, "t", quantity.axis())?;
    for ((s, name), style) in series.zip(&names).zip(styles) {
        layer.set("series", name);
        chart.draw_series(LineSeries::new(lines.lines[s].iter().copied(), style))?;
    }
    if let Some(s) = dashed {
        layer.set("series", BALANCE);
        let points = lines.lines[s].iter().copied();
        chart.draw_series(DashedLineSeries::new(points, DASH.0, DASH.1, dashed_style))?;
    }
    switches(&mut chart, layer, scene, (low, high))?;
    // Every impact and lift-off, as a mark along the bottom (a row per constraint reached,
    // where there are several).
    for (row, (name, times, c)) in rows.iter().enumerate() {
        layer.set("impacts", name);
        let (mark, dy) = (c.filled(), -9 - 10 * row as i32);
        chart.draw_series(
            times
                .iter()
                .map(|&t| EmptyElement::at((t, low)) + Circle::new((0, dy), 4, mark)),
        )?;
    }
    if !liftoffs.is_empty() {
        layer.set("liftoffs", "");
        let mark = LIFTOFF.filled();
        chart.draw_series(
            liftoffs
                .iter()
                .map(|&t| EmptyElement::at((t, low)) + TriangleMarker::new((0, -20), 6, mark)),
        )?;
    }
    legend(area, &chart, layer, &entries)
}

/// The colour of the impact marks of the `k`-th constraint reached: the impact red first.
fn impact_color(k: usize) -> RGBColor {
    if k == 0 {
        IMPACT
    } else {
        color(k + 3)
    }
}

/// Draws every switch to the constrained motion (and a stall) as a labelled vertical line.
fn switches<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    layer: &Layer,
    scene: &Scene,
    (low, high): (f64, f64),
) -> Drawn<DB> {
    let record = &scene.record;
    let span = chart.x_range();
    let (t0, t1) = (span.start, span.end);
    for (k, z) in record.zeno.iter().enumerate() {
        let stalled = record.stalled() && k + 1 == record.zeno.len();
        let t = z.t_switch;
        let label = if stalled {
            layer.set("stall", &z.constraint);
            let tau = z.t_zeno.unwrap_or(t);
            format!("stalled at the Zeno point, τ∞ ≈ {}", short(tau))
        } else {
            layer.set("switch", &z.constraint);
            if z.constraints.len() > 1 {
                let set = z.constraints.join("+");
                format!("switch to constrained motion on {set}, t = {}", short(t))
            } else {
                format!("switch to constrained motion, t = {}", short(t))
            }
        };
        chart.draw_series([PathElement::new(
            vec![(t, low), (t, high)],
            SWITCH.stroke_width(2),
        )])?;
        // Labels stay inside the plot: on the line's left when it is on the right; successive
        // labels go one under the other.
        let right = t > t0 + 0.6 * (t1 - t0);
        let (dx, h) = if right {
            (-6, HPos::Right)
        } else {
            (6, HPos::Left)
        };
        let dy = 6 + 20 * (k % 4) as i32;
        chart
            .draw_series([EmptyElement::at((t, high))
                + Text::new(label, (dx, dy), note(SWITCH, h, VPos::Top))])?;
    }
    Ok(())
}
