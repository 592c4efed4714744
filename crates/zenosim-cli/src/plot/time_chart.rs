//! Quantities against time (the velocities, the displacements, the energy, the tangential
//! forces of a model with friction), one line per series, with the run's events marked:
//! impacts, lift-offs and (with friction) the contacts' changes to stick and to slip along the
//! time axis, and each switch to the constrained motion (or the stall at a Zeno point) as a
//! labelled vertical line. Beside the energy, when the trajectory has the energy balance,
//! `E(0) + work − impact loss` dashed over it: where the balance holds, the two coincide.

use plotters::chart::ChartContext;
use plotters::coord::cartesian::Cartesian2d;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::{
    Circle, Color, DashedLineSeries, DrawingArea, EmptyElement, IntoFont, LineSeries, PathElement,
    RGBColor, Rectangle, ShapeStyle, Text, TextStyle, TriangleMarker, WHITE,
};
use plotters::style::text_anchor::{HPos, VPos};
use plotters_backend::DrawingBackend;

use super::canvas::{Drawn, Picture, FONT};
use super::chart::{axes, drawable, frame, legend, note, Entry, Sample};
use super::scene::{pad, Scene};
use super::style::{color, short, GRIP, IMPACT, LIFTOFF, LINE_WIDTH, SWITCH, TEXT_SIZE};
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
    /// The tangential forces `f_<constraint>` of the constraints with friction against `t`.
    Friction,
}

impl Quantity {
    /// The plot's name: its file name and caption.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Velocities => "velocities",
            Quantity::Displacements => "displacements",
            Quantity::Energy => "energy",
            Quantity::Friction => "friction",
        }
    }

    fn axis(self) -> &'static str {
        match self {
            Quantity::Velocities => "velocity",
            Quantity::Displacements => "displacement",
            Quantity::Energy => "energy",
            Quantity::Friction => "tangential force",
        }
    }

    /// The trajectory's series it shows as solid lines.
    fn series(self, scene: &Scene) -> std::ops::Range<usize> {
        let n = scene.record.coordinates.len();
        match self {
            Quantity::Displacements => 0..n,
            Quantity::Velocities => n..2 * n,
            Quantity::Energy => 2 * n..2 * n + 1,
            Quantity::Friction => scene.trajectory.friction.clone(),
        }
    }

    /// The name of series `s` in the legend.
    fn label(self, scene: &Scene, s: usize) -> String {
        match self {
            Quantity::Energy => "energy".to_string(),
            Quantity::Friction => {
                let k = s - scene.trajectory.friction.start;
                let columns = scene.record.force_columns();
                let (name, component) = columns.get(k).copied().unwrap_or(("?", 0));
                crate::trajectory::force_column(name, component)
            }
            _ => scene.name(s).to_string(),
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
            Quantity::Energy | Quantity::Friction => (1000, 420),
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
    let series = quantity.series(scene);
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
    let names: Vec<String> = series.clone().map(|s| quantity.label(scene, s)).collect();
    let styles: Vec<ShapeStyle> = (0..names.len())
        .map(|k| color(k).stroke_width(LINE_WIDTH))
        .collect();
    let record = &scene.record;
    let (impacts, liftoffs) = (record.times("impact"), record.times("liftoff"));
    let (sticks, slips) = (record.times("stick"), record.times("slip"));
    let mut entries: Vec<Entry> = names
        .iter()
        .zip(&styles)
        .map(|(name, &style)| Entry::new(name.as_str(), Sample::Line(style)))
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
    // A contact's friction state changing: filled squares where it starts to stick, hollow
    // ones where it starts to slip.
    let grips = [
        ("stick", &sticks, GRIP.filled()),
        ("slip", &slips, GRIP.stroke_width(2)),
    ];
    for (kind, times, style) in &grips {
        if !times.is_empty() {
            let label = format!("{kind} ({})", times.len());
            entries.push(Entry::new(label, Sample::Square(*style)));
        }
    }
    let switched = record.zeno.len() - usize::from(record.stalled());
    if switched > 1 {
        let label = format!("switch to constrained motion ({switched})");
        entries.push(Entry::new(label, Sample::Line(SWITCH.stroke_width(1))));
    }

    let mut chart = frame(area, caption, &entries)
        .build_cartesian_2d(drawable((t0, t1)), drawable((low, high)))?;
    axes(&mut chart, layer, "t", quantity.axis())?;
    layer.clip_to(&chart.plotting_area().strip_coord_spec());
    for ((s, name), style) in series.zip(&names).zip(styles) {
        layer.set("series", name);
        chart.draw_series(LineSeries::new(lines.lines[s].iter().copied(), style))?;
    }
    if let Some(s) = dashed {
        layer.set("series", BALANCE);
        let points = lines.lines[s].iter().copied();
        chart.draw_series(DashedLineSeries::new(points, DASH.0, DASH.1, dashed_style))?;
    }
    layer.unclip();
    switches(area, &mut chart, layer, scene, (low, high))?;
    // Every impact and lift-off, as a mark along the bottom (a row per constraint reached,
    // where there are several).
    for (row, (name, times, c)) in rows.iter().enumerate() {
        layer.set("impacts", name);
        let (mark, dy) = (c.filled(), -9 - 10 * row as i32);
        chart.draw_series(
            thin(&chart, times).map(|t| EmptyElement::at((t, low)) + Circle::new((0, dy), 4, mark)),
        )?;
    }
    if !liftoffs.is_empty() {
        layer.set("liftoffs", "");
        let mark = LIFTOFF.filled();
        chart.draw_series(
            thin(&chart, &liftoffs)
                .map(|t| EmptyElement::at((t, low)) + TriangleMarker::new((0, -20), 6, mark)),
        )?;
    }
    // The stick and slip marks, on a row above the impacts' and the lift-offs'.
    let dy = -11 - 10 * rows.len().max(2) as i32;
    for (kind, times, style) in grips {
        if times.is_empty() {
            continue;
        }
        layer.set(kind, "");
        chart.draw_series(thin(&chart, times).map(|t| {
            EmptyElement::at((t, low)) + Rectangle::new([(-4, dy - 4), (4, dy + 4)], style)
        }))?;
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

/// Marks beyond this many are thinned to one per pixel column.
const MAX_MARKS: usize = 500;
/// Switches drawn as lines across the plot, with their labels where they fit, up to this many
/// (and while they are [`SWITCH_GAP`] apart); more are drawn as a rug of short marks along the
/// top of the plot, one per pixel column, counted in the legend.
const MAX_SWITCH_LINES: usize = 40;
/// The least gap between switch lines drawn across the plot, as a fraction of the time axis
/// (a few pixels).
const SWITCH_GAP: f64 = 1.0 / 200.0;
/// The rows of switch labels under the top of the plot.
const LABEL_ROWS: i32 = 4;
/// The switch rug's marks' length, in pixels.
const RUG: i32 = 12;

type TimeContext<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// `times`, or, beyond [`MAX_MARKS`], one of them per pixel column: marks drawn over each
/// other add nothing but size (32 000 impacts of a long run).
fn thin<'a, DB: DrawingBackend>(
    chart: &TimeContext<'_, DB>,
    times: &'a [f64],
) -> impl Iterator<Item = f64> + 'a {
    let columns: Vec<i32> = if times.len() > MAX_MARKS {
        times
            .iter()
            .map(|&t| chart.backend_coord(&(t, 0.0)).0)
            .collect()
    } else {
        Vec::new()
    };
    times
        .iter()
        .enumerate()
        .filter(move |&(k, _)| columns.is_empty() || k == 0 || columns[k] != columns[k - 1])
        .map(|(_, &t)| t)
}

/// Where the labels of vertical lines go: rows under the top of the plot, a label in the first
/// row where it overprints none already placed (or nowhere).
#[derive(Default)]
struct Labels {
    /// The boxes taken, `(row, left, right)` in pixels.
    taken: Vec<(i32, i32, i32)>,
}

impl Labels {
    /// The row for a label from `left` to `right`, taken; `None` if every row is taken there.
    fn place(&mut self, left: i32, right: i32) -> Option<i32> {
        const GAP: i32 = 8;
        let row = (0..LABEL_ROWS).find(|&row| {
            self.taken
                .iter()
                .all(|&(r, l, h)| r != row || right + GAP < l || h + GAP < left)
        })?;
        self.taken.push((row, left, right));
        Some(row)
    }
}

/// Draws every switch to the constrained motion (and a stall, and the failure of a failed run)
/// as a vertical line, labelled where the label overprints no other; many switches, as a rug
/// along the top of the plot.
fn switches<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &mut TimeContext<'_, DB>,
    layer: &Layer,
    scene: &Scene,
    (low, high): (f64, f64),
) -> Drawn<DB> {
    let record = &scene.record;
    let span = chart.x_range();
    let (t0, t1) = (span.start, span.end);
    let mut labels = Labels::default();
    // The lines, the most telling first: where the run ended, then the switches.
    let mut lines: Vec<(&str, &str, f64, String, RGBColor)> = Vec::new();
    if record.status == "failed" {
        if let Some(t) = record.final_.t.filter(|t| t.is_finite()) {
            lines.push((
                "failure",
                "",
                t,
                format!("failed at t = {}", short(t)),
                IMPACT,
            ));
        }
    }
    let n = record.zeno.len();
    let stalled = record.stalled().then(|| n - 1);
    if let Some(z) = stalled.and_then(|k| record.zeno.get(k)) {
        let tau = z.t_zeno.unwrap_or(z.t_switch);
        let label = format!("stalled at the Zeno point, τ∞ ≈ {}", short(tau));
        lines.push(("stall", &z.constraint, z.t_switch, label, SWITCH));
    }
    let switched: Vec<_> = record
        .zeno
        .iter()
        .enumerate()
        .filter(|(k, _)| Some(*k) != stalled)
        .map(|(_, z)| z)
        .collect();
    let crowded = switched.len() > MAX_SWITCH_LINES
        || switched
            .windows(2)
            .any(|w| w[1].t_switch - w[0].t_switch < SWITCH_GAP * (t1 - t0));
    if crowded {
        // A rug: a short mark per pixel column that has a switch.
        let times: Vec<f64> = switched.iter().map(|z| z.t_switch).collect();
        let mut last = None;
        for t in times {
            let x = chart.backend_coord(&(t, high)).0;
            if last == Some(x) {
                continue;
            }
            last = Some(x);
            layer.set("switch", &record.zeno[0].constraint);
            chart.draw_series([EmptyElement::at((t, high))
                + PathElement::new(vec![(0, 0), (0, RUG)], SWITCH.stroke_width(1))])?;
        }
    } else {
        for z in switched {
            let t = z.t_switch;
            let label = if z.constraints.len() > 1 {
                let set = z.constraints.join("+");
                format!("switch to constrained motion on {set}, t = {}", short(t))
            } else {
                format!("switch to constrained motion, t = {}", short(t))
            };
            lines.push(("switch", &z.constraint, t, label, SWITCH));
        }
    }
    let style = TextStyle::from((FONT, TEXT_SIZE).into_font());
    for (class, name, t, label, c) in lines {
        layer.set(class, name);
        chart.draw_series([PathElement::new(
            vec![(t, low), (t, high)],
            c.stroke_width(2),
        )])?;
        // Labels stay inside the plot: on the line's left when it is on the right; a label
        // that would overprint another goes a row lower, or is left out (the legend counts
        // the switches).
        let right = t > t0 + 0.6 * (t1 - t0);
        let x = chart.backend_coord(&(t, high)).0;
        let width = area
            .estimate_text_size(&label, &style)
            .map_or(8 * label.chars().count() as i32, |size| size.0 as i32);
        let (dx, h, (left, end)) = if right {
            (-6, HPos::Right, (x - 6 - width, x - 6))
        } else {
            (6, HPos::Left, (x + 6, x + 6 + width))
        };
        let Some(row) = labels.place(left, end) else {
            continue;
        };
        let dy = 6 + 20 * row;
        chart.draw_series([
            EmptyElement::at((t, high)) + Text::new(label, (dx, dy), note(c, h, VPos::Top))
        ])?;
    }
    Ok(())
}
