//! The map of a sweep (`zenosim sweep --plot X,Y,QUANTITY`): a quantity of each run over two
//! of the varied names, one filled cell per run coloured on a scale (with its colour bar), the
//! runs without a value (NaN: no Zeno point, or a point never run) grey and hatched, said in
//! the legend.
//!
//! A cell spans from halfway to its neighbours' values on each axis (the outer cells as wide
//! as their inner neighbours), so that unevenly spaced values are drawn where they are. In the
//! SVG each cell is a group `<g class="cell" data-name="INDEX">` or, without a value,
//! `<g class="no-value" data-name="INDEX">` (INDEX: the run's row).

use std::fmt;
use std::path::Path;
use std::str::FromStr;

use plotters::chart::ChartBuilder;
use plotters::coord::Shift;
use plotters::prelude::{Color, DrawingArea, PathElement, RGBColor, Rectangle, Text, WHITE};
use plotters::style::text_anchor::{HPos, VPos};
use plotters_backend::DrawingBackend;
use zenosim_runs::sweep::{Row, Sweep};

use super::canvas::{render, Drawn, Format, Picture, FONT};
use super::chart::{axes, drawable, legend, note, Entry, Sample};
use super::style::{short, TITLE_SIZE};
use super::svg::Layer;
use crate::output::write_file;
use crate::{Classify, Failure};

/// The cells without a value.
const NO_VALUE: RGBColor = RGBColor(205, 205, 205);
/// Their hatching.
const HATCH: RGBColor = RGBColor(150, 150, 150);
/// The room right of the plot, for the legend and the colour bar.
const RIGHT: u32 = 240;
/// The colour bar's width, and its number of steps.
const BAR_WIDTH: i32 = 24;
const BAR_STEPS: usize = 96;

/// `X,Y,QUANTITY`: a column of the sweep's file over two of its varied names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MapSpec {
    /// The horizontal axis, a varied name.
    pub x: String,
    /// The vertical axis, another.
    pub y: String,
    /// The column drawn as colour.
    pub quantity: String,
}

impl FromStr for MapSpec {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        match text.split(',').map(str::trim).collect::<Vec<_>>()[..] {
            [x, y, q] if !x.is_empty() && !y.is_empty() && !q.is_empty() && x != y => Ok(Self {
                x: x.to_string(),
                y: y.to_string(),
                quantity: q.to_string(),
            }),
            _ => Err(
                "expected two different varied names and a column X,Y,QUANTITY, e.g. \
                 x0,y0,t_zeno"
                    .to_string(),
            ),
        }
    }
}

impl fmt::Display for MapSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{},{},{}", self.x, self.y, self.quantity)
    }
}

/// One cell: its run's index, its corners and its value (NaN for none).
#[derive(Clone, Copy, Debug)]
struct Cell {
    index: usize,
    x: (f64, f64),
    y: (f64, f64),
    value: f64,
}

/// The map, ready to draw.
struct Map {
    title: String,
    spec: MapSpec,
    cells: Vec<Cell>,
    x_range: (f64, f64),
    y_range: (f64, f64),
    /// The lowest and highest values, if any is finite.
    scale: Option<(f64, f64)>,
}

/// Each value's cell edges along an axis: halfway to the neighbours, the outer ones as wide as
/// their inner neighbours (a single value: a tenth of its size either side, or ½ at 0).
fn edges(values: &[f64]) -> Vec<(f64, f64, f64)> {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted.dedup();
    let m = sorted.len();
    (0..m)
        .map(|i| {
            let v = sorted[i];
            let low = if i > 0 {
                0.5 * (sorted[i - 1] + v)
            } else if m > 1 {
                v - 0.5 * (sorted[1] - v)
            } else if v == 0.0 {
                -0.5
            } else {
                v - 0.1 * v.abs()
            };
            let high = if i + 1 < m {
                0.5 * (v + sorted[i + 1])
            } else if m > 1 {
                v + 0.5 * (v - sorted[m - 2])
            } else if v == 0.0 {
                0.5
            } else {
                v + 0.1 * v.abs()
            };
            (v, low, high)
        })
        .collect()
}

/// The cell of `value` among `edges`.
fn span(edges: &[(f64, f64, f64)], value: f64) -> (f64, f64) {
    edges
        .iter()
        .find(|(v, _, _)| *v == value)
        .map_or((value, value), |&(_, low, high)| (low, high))
}

impl Map {
    fn new(sweep: &Sweep, spec: &MapSpec, columns: &[String], rows: &[Row]) -> Self {
        let axis = |name: &str| {
            let k = sweep.points().names().iter().position(|n| *n == name);
            let values = k.map_or(&[][..], |k| sweep.points().axes()[k].values());
            (k.unwrap_or(0), edges(values))
        };
        let ((kx, x_edges), (ky, y_edges)) = (axis(&spec.x), axis(&spec.y));
        let q = columns.iter().position(|c| *c == spec.quantity);
        let cells: Vec<Cell> = rows
            .iter()
            .map(|row| Cell {
                index: row.index,
                x: span(&x_edges, row.values[kx]),
                y: span(&y_edges, row.values[ky]),
                value: q.and_then(|q| row.number(q)).unwrap_or(f64::NAN),
            })
            .collect();
        let range = |edges: &[(f64, f64, f64)]| {
            (
                edges.first().map_or(0.0, |e| e.1),
                edges.last().map_or(1.0, |e| e.2),
            )
        };
        let finite = cells.iter().map(|c| c.value).filter(|v| v.is_finite());
        let scale = finite.fold(None, |s: Option<(f64, f64)>, v| {
            Some(s.map_or((v, v), |(lo, hi)| (lo.min(v), hi.max(v))))
        });
        Self {
            title: format!(
                "{}: {} over {} and {}",
                sweep.model(),
                spec.quantity,
                spec.x,
                spec.y
            ),
            spec: spec.clone(),
            cells,
            x_range: range(&x_edges),
            y_range: range(&y_edges),
            scale,
        }
    }

    /// Where `value` lies on the scale, in `[0, 1]`.
    fn fraction(&self, value: f64) -> f64 {
        match self.scale {
            Some((lo, hi)) if hi > lo => ((value - lo) / (hi - lo)).clamp(0.0, 1.0),
            _ => 0.5,
        }
    }

    /// What the legend calls the cells without a value.
    fn no_value_label(&self) -> &'static str {
        match self.spec.quantity.as_str() {
            "t_zeno" | "t_switch" => "no Zeno point",
            _ => "no value (NaN)",
        }
    }
}

/// Viridis, from 0 (dark blue) to 1 (yellow), interpolated between five of its colours.
fn viridis(f: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let at = f.clamp(0.0, 1.0) * 4.0;
    let k = (at.floor() as usize).min(3);
    let t = at - k as f64;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    let mix = |p: f64, q: f64| (p + (q - p) * t).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

impl Picture for Map {
    fn size(&self) -> (u32, u32) {
        (980, 720)
    }

    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, layer: &Layer) -> Drawn<DB> {
        area.fill(&WHITE)?;
        let missing = self.cells.iter().filter(|c| c.value.is_nan()).count();
        let entries: Vec<Entry> = if missing > 0 {
            vec![Entry::new(
                format!("{} ({missing})", self.no_value_label()),
                Sample::Square(NO_VALUE.filled()),
            )]
        } else {
            Vec::new()
        };
        layer.set("title", "");
        let mut chart = ChartBuilder::on(area)
            .caption(&self.title, (FONT, TITLE_SIZE))
            .margin(12)
            .margin_right(RIGHT)
            .x_label_area_size(48)
            .y_label_area_size(80)
            .build_cartesian_2d(drawable(self.x_range), drawable(self.y_range))?;
        axes(&mut chart, layer, &self.spec.x, &self.spec.y)?;
        for cell in &self.cells {
            let corners = [(cell.x.0, cell.y.0), (cell.x.1, cell.y.1)];
            if cell.value.is_nan() {
                layer.set("no-value", &cell.index.to_string());
                chart.draw_series([Rectangle::new(corners, NO_VALUE.filled())])?;
                let (w, h) = (cell.x.1 - cell.x.0, cell.y.1 - cell.y.0);
                let (x0, y0) = (cell.x.0, cell.y.0);
                let hatch = [
                    [(x0, y0), (x0 + w, y0 + h)],
                    [(x0, y0 + h / 2.0), (x0 + w / 2.0, y0 + h)],
                    [(x0 + w / 2.0, y0), (x0 + w, y0 + h / 2.0)],
                ];
                chart.draw_series(
                    hatch.map(|line| PathElement::new(line.to_vec(), HATCH.stroke_width(1))),
                )?;
            } else {
                layer.set("cell", &cell.index.to_string());
                let color = viridis(self.fraction(cell.value));
                chart.draw_series([Rectangle::new(corners, color.filled())])?;
            }
        }
        legend(area, &chart, layer, &entries)?;
        self.colour_bar(
            area,
            &chart.plotting_area().strip_coord_spec(),
            !entries.is_empty(),
        )
    }
}

impl Map {
    /// The colour bar, right of `plot` (below the legend when there is one): the scale from the
    /// lowest value (bottom) to the highest (top), with five labels.
    fn colour_bar<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        plot: &DrawingArea<DB, Shift>,
        below_legend: bool,
    ) -> Drawn<DB> {
        let (base, origin) = (area.get_base_pixel(), plot.get_base_pixel());
        let x = origin.0 - base.0 + plot.dim_in_pixel().0 as i32 + 18;
        let top = origin.1 - base.1 + if below_legend { 80 } else { 34 };
        let bottom = origin.1 - base.1 + plot.dim_in_pixel().1 as i32 - 8;
        if bottom - top < 40 {
            return Ok(());
        }
        area.draw(&Text::new(
            self.spec.quantity.clone(),
            (x, top - 10),
            note(RGBColor(0, 0, 0), HPos::Left, VPos::Bottom),
        ))?;
        let Some((lo, hi)) = self.scale else {
            return area.draw(&Text::new(
                "no values",
                (x, top + 10),
                note(RGBColor(0, 0, 0), HPos::Left, VPos::Top),
            ));
        };
        let height = (bottom - top) as f64;
        for k in 0..BAR_STEPS {
            let f0 = k as f64 / BAR_STEPS as f64;
            let f1 = (k + 1) as f64 / BAR_STEPS as f64;
            let y0 = bottom - (f0 * height).round() as i32;
            let y1 = bottom - (f1 * height).round() as i32;
            let color = viridis(0.5 * (f0 + f1));
            area.draw(&Rectangle::new(
                [(x, y1), (x + BAR_WIDTH, y0)],
                color.filled(),
            ))?;
        }
        area.draw(&Rectangle::new(
            [(x, top), (x + BAR_WIDTH, bottom)],
            RGBColor(120, 120, 120).stroke_width(1),
        ))?;
        let labels = if hi > lo { 5 } else { 1 };
        for k in 0..labels {
            let f = if labels == 1 { 0.5 } else { k as f64 / 4.0 };
            let value = lo + (hi - lo) * f;
            let y = bottom - (f * height).round() as i32;
            area.draw(&PathElement::new(
                vec![(x + BAR_WIDTH, y), (x + BAR_WIDTH + 5, y)],
                RGBColor(0, 0, 0).stroke_width(1),
            ))?;
            area.draw(&Text::new(
                short(value),
                (x + BAR_WIDTH + 8, y),
                note(RGBColor(0, 0, 0), HPos::Left, VPos::Center),
            ))?;
        }
        Ok(())
    }
}

/// Draws the map of `spec` of the sweep's `rows` (checked by the caller: X and Y varied in a
/// product, the quantity a column) into `path`, in `format`.
pub fn draw_map(
    sweep: &Sweep,
    spec: &MapSpec,
    columns: &[String],
    rows: &[Row],
    format: Format,
    path: &Path,
) -> Result<(), Failure> {
    let map = Map::new(sweep, spec, columns, rows);
    let bytes = render(&map, format).output()?;
    write_file(path, &bytes).output()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_span_halfway_to_their_neighbours() {
        let e = edges(&[0.0, 1.0, 3.0]);
        assert_eq!(e, [(0.0, -0.5, 0.5), (1.0, 0.5, 2.0), (3.0, 2.0, 4.0)]);
        // Given in any order, repeated values once.
        assert_eq!(edges(&[3.0, 1.0, 0.0, 1.0]), e);
        assert_eq!(edges(&[2.0]), [(2.0, 1.8, 2.2)]);
        assert_eq!(edges(&[0.0]), [(0.0, -0.5, 0.5)]);
        assert_eq!(span(&e, 1.0), (0.5, 2.0));
    }

    #[test]
    fn the_scale_runs_from_dark_to_light() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(0.5), RGBColor(33, 145, 140));
        assert_eq!(viridis(f64::NAN.max(0.0)), viridis(0.0));
    }

    #[test]
    fn specs_are_three_names() {
        let spec: MapSpec = "x0, y0,t_zeno".parse().unwrap();
        assert_eq!(spec.to_string(), "x0,y0,t_zeno");
        for bad in ["x0,y0", "x0,x0,t_zeno", "x0,,t", "a,b,c,d", ""] {
            assert!(bad.parse::<MapSpec>().is_err(), "{bad}");
        }
    }
}
