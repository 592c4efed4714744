//! What every chart shares: the frame (caption, margins, label areas), the axes, the legend
//! (on the right of the plot, where it hides nothing), and text styles.

use plotters::chart::{ChartBuilder, ChartContext};
use plotters::coord::cartesian::Cartesian2d;
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::{CoordTranslate, Shift};
use plotters::prelude::{
    Circle, Color, DrawingArea, IntoFont, PathElement, RGBColor, Rectangle, ShapeStyle, Text,
    TextStyle, TriangleMarker, BLACK, WHITE,
};
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters_backend::DrawingBackend;

use super::canvas::{Drawn, FONT};
use super::style::{tick, GRID, GRID_MINOR, LABEL_SIZE, TEXT_SIZE, TITLE_SIZE};
use super::svg::Layer;

/// The legend's space for an entry's sample, before its label.
const SAMPLE_WIDTH: i32 = 30;
/// The legend's inner margin.
const LEGEND_MARGIN: i32 = 8;
/// The gap between the plot and the legend.
const LEGEND_GAP: i32 = 14;
/// The least room kept for the legend, so that charts one above the other line up.
const LEGEND_ROOM: i32 = 200;
/// The height of a legend entry.
const ENTRY_HEIGHT: i32 = TEXT_SIZE as i32 + 7;

/// What a legend entry's sample looks like.
#[derive(Clone, Copy, Debug)]
pub enum Sample {
    /// A line.
    Line(ShapeStyle),
    /// A dashed line.
    Dashed(ShapeStyle),
    /// A circle of this radius.
    Dot(ShapeStyle, u32),
    /// A triangle.
    Triangle(ShapeStyle),
    /// A square.
    Square(ShapeStyle),
    /// No sample: a note.
    None,
}

/// A legend entry.
#[derive(Clone, Debug)]
pub struct Entry {
    /// Its label.
    pub label: String,
    /// Its sample.
    pub sample: Sample,
}

impl Entry {
    /// The entry `label` with `sample`.
    pub fn new(label: impl Into<String>, sample: Sample) -> Self {
        Self {
            label: label.into(),
            sample,
        }
    }
}

/// The widest label of `entries` on `area`, in pixels.
fn widest<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, entries: &[Entry]) -> Option<i32> {
    let style = TextStyle::from((FONT, TEXT_SIZE).into_font());
    entries
        .iter()
        .map(|e| {
            area.estimate_text_size(&e.label, &style)
                .map_or(10 * e.label.chars().count() as u32, |size| size.0) as i32
        })
        .max()
}

/// `(low, high)` as an axis range that plotters can place ticks on: finite, at most `f64::MAX`
/// wide, and wide enough for `f64` to resolve its ticks (at least 2⁻³⁶ of its largest end).
/// Outside that, plotters' tick generator never ends: steps of infinity, or below the spacing of
/// the numbers they are added to (a range 1.7e308 wide, or 1e15 to 1e15 + 1e-3). NaN ends become
/// 0, infinite ones ±`f64::MAX`; a range wider than `f64::MAX` keeps its upper end, and a narrow
/// one is widened about its middle.
pub fn drawable((low, high): (f64, f64)) -> std::ops::Range<f64> {
    let clamp = |x: f64| {
        if x.is_nan() {
            0.0
        } else {
            x.clamp(-f64::MAX, f64::MAX)
        }
    };
    let (low, high) = (clamp(low), clamp(high));
    let (mut low, mut high) = (low.min(high), low.max(high));
    if (high - low).is_infinite() {
        low = high - f64::MAX;
    }
    let size = low.abs().max(high.abs());
    let narrowest = if size > 0.0 {
        size * 2f64.powi(-36)
    } else {
        1.0
    };
    if high - low < narrowest {
        let middle = low / 2.0 + high / 2.0;
        low = (middle - narrowest / 2.0).max(-f64::MAX);
        high = (middle + narrowest / 2.0).min(f64::MAX);
    }
    low..high
}

/// A chart builder on `area` with `caption`, room for the axes' labels and, on the right, for
/// the legend of `entries`. An empty caption is none (the caller titled the area itself).
pub fn frame<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    entries: &[Entry],
) -> ChartBuilder<'a, 'static, DB> {
    let right = widest(area, entries).map_or(28, |w| {
        LEGEND_ROOM.max(w + SAMPLE_WIDTH + 2 * LEGEND_MARGIN + LEGEND_GAP + 12)
    });
    let mut builder = ChartBuilder::on(area);
    if !caption.is_empty() {
        // Plotters centres the title over the area less its margins, and clips it at both ends.
        let room = area.dim_in_pixel().0 as i32 - right - 2 * 12;
        builder.caption(caption, (FONT, title_size(area, caption, room)));
    }
    builder
        .margin(12)
        .margin_right(right)
        .x_label_area_size(48)
        .y_label_area_size(80);
    builder
}

/// The title's font size: [`TITLE_SIZE`], smaller for a title wider than `room` pixels; at
/// least 9 px.
fn title_size<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, caption: &str, room: i32) -> f64 {
    let size = f64::from(TITLE_SIZE);
    let room = f64::from(room.max(1));
    let style = TextStyle::from((FONT, size).into_font());
    let width = area
        .estimate_text_size(caption, &style)
        .map_or(0.6 * size * caption.chars().count() as f64, |text| {
            f64::from(text.0)
        });
    if width <= room {
        size
    } else {
        (size * room / width).floor().max(9.0)
    }
}

/// Draws the legend of `entries` on `area`, right of `chart`'s plot (in the room [`frame`] left
/// for it), where it hides nothing.
pub fn legend<DB: DrawingBackend, CT: CoordTranslate>(
    area: &DrawingArea<DB, Shift>,
    chart: &ChartContext<'_, DB, CT>,
    layer: &Layer,
    entries: &[Entry],
) -> Drawn<DB> {
    let Some(width) = widest(area, entries) else {
        return Ok(());
    };
    layer.set("legend", "");
    let plot = chart.plotting_area();
    let (base, origin) = (area.get_base_pixel(), plot.get_base_pixel());
    let x = origin.0 - base.0 + plot.dim_in_pixel().0 as i32 + LEGEND_GAP;
    let y = origin.1 - base.1;
    // As many entries as the plot's height holds; the rest folded into "and N more".
    let room = (plot.dim_in_pixel().1 as i32 - 2 * LEGEND_MARGIN) / ENTRY_HEIGHT;
    let folded;
    let entries = match fold(entries, room.max(1) as usize) {
        Some(kept) => {
            folded = kept;
            &folded[..]
        }
        None => entries,
    };
    let (w, h) = (
        width + SAMPLE_WIDTH + 2 * LEGEND_MARGIN,
        ENTRY_HEIGHT * entries.len() as i32 + 2 * LEGEND_MARGIN,
    );
    area.draw(&Rectangle::new([(x, y), (x + w, y + h)], WHITE.filled()))?;
    area.draw(&Rectangle::new(
        [(x, y), (x + w, y + h)],
        RGBColor(190, 190, 190).stroke_width(1),
    ))?;
    for (k, entry) in entries.iter().enumerate() {
        let cy = y + LEGEND_MARGIN + ENTRY_HEIGHT * k as i32 + ENTRY_HEIGHT / 2;
        let cx = x + LEGEND_MARGIN + SAMPLE_WIDTH / 2 - 2;
        match entry.sample {
            Sample::Line(style) => {
                area.draw(&PathElement::new(vec![(cx - 11, cy), (cx + 11, cy)], style))?
            }
            Sample::Dashed(style) => {
                for x in [cx - 11, cx + 3] {
                    area.draw(&PathElement::new(vec![(x, cy), (x + 8, cy)], style))?
                }
            }
            Sample::Dot(style, r) => area.draw(&Circle::new((cx, cy), r, style))?,
            Sample::Triangle(style) => area.draw(&TriangleMarker::new((cx, cy), 6, style))?,
            Sample::Square(style) => {
                area.draw(&Rectangle::new([(cx - 5, cy - 5), (cx + 5, cy + 5)], style))?
            }
            Sample::None => {}
        }
        area.draw(&Text::new(
            entry.label.clone(),
            (x + LEGEND_MARGIN + SAMPLE_WIDTH, cy),
            note(BLACK, HPos::Left, VPos::Center),
        ))?;
    }
    Ok(())
}

/// `entries` cut to `room` lines, the last saying how many were left out ("and 12 more"):
/// `None` when they all fit. The last entries (the event marks, after the series) are kept.
fn fold(entries: &[Entry], room: usize) -> Option<Vec<Entry>> {
    if entries.len() <= room {
        return None;
    }
    // The entries from the first that is not a line on (the impacts, lift-offs and other
    // marks): a third of the room at most, the series the rest.
    let first_mark = entries
        .iter()
        .position(|e| !matches!(e.sample, Sample::Line(_)))
        .unwrap_or(entries.len());
    let marks = (entries.len() - first_mark).min(room.saturating_sub(1) / 3);
    let series = room.saturating_sub(marks + 1).max(1);
    let series = series.min(first_mark.max(1));
    let mut kept: Vec<Entry> = entries[..series].to_vec();
    let from = first_mark.max(series);
    let shown = (entries.len() - from).min(room.saturating_sub(series + 1));
    let left = entries.len() - series - shown;
    kept.push(Entry::new(format!("and {left} more"), Sample::None));
    kept.extend_from_slice(&entries[from..from + shown]);
    Some(kept)
}

/// How an axis labels its ticks: round-off next to 0 (a tick at `-5.6e-17`) is 0, and a range
/// narrow for its distance from 0 (`5e11 + 0.1 … 5e11 + 0.9`) is labelled relative to an offset
/// that the axis' description names (`x (5e11 + …)`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TickAxis {
    /// The offset subtracted from every tick, if any.
    pub offset: Option<f64>,
    /// Its digits, as the description writes it.
    digits: usize,
    /// Ticks closer to 0 than this (relative to the offset) are 0.
    zero: f64,
}

impl TickAxis {
    /// The labelling of an axis over `range`.
    pub fn new(range: std::ops::Range<f64>) -> Self {
        let (low, high) = (range.start.min(range.end), range.start.max(range.end));
        let span = high - low;
        let size = low.abs().max(high.abs());
        let plain = Self {
            offset: None,
            digits: 0,
            zero: span * 1e-9,
        };
        if !(span > 0.0 && span.is_finite() && size.is_finite()) || size / span < 1e5 {
            return plain;
        }
        // A round offset near the middle, so that the ticks relative to it have a few digits.
        let unit = 10f64.powf(span.log10().ceil());
        let offset = ((low / 2.0 + high / 2.0) / unit).round() * unit;
        if !offset.is_finite() || offset == 0.0 {
            return plain;
        }
        let digits = (offset.abs().log10().floor() - unit.log10()).max(0.0) as usize + 1;
        Self {
            offset: Some(offset),
            digits: digits.min(17),
            ..plain
        }
    }

    /// The tick at `x`, as its label shows it: relative to the offset, round-off to 0 dropped.
    pub fn value(&self, x: f64) -> f64 {
        let x = x - self.offset.unwrap_or(0.0);
        if x.abs() < self.zero {
            0.0
        } else {
            x
        }
    }

    /// The axis' description `desc`, naming the offset.
    pub fn describe(&self, desc: &str) -> String {
        match self.offset {
            Some(offset) => format!(
                "{desc} ({} + …)",
                super::style::trim(&super::style::significant(offset, self.digits))
            ),
            None => desc.to_string(),
        }
    }
}

/// Draws the grid, the axes, their tick labels and their descriptions.
pub fn axes<DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    layer: &Layer,
    x_desc: &str,
    y_desc: &str,
) -> Drawn<DB>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    mesh(chart, layer, (x_desc, y_desc), (10, 8), &tick)
}

/// [`axes`] with `labels` ticks on each axis (at most), labelled by `label`.
pub fn mesh<DB, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    layer: &Layer,
    (x_desc, y_desc): (&str, &str),
    labels: (usize, usize),
    label: &dyn Fn(&f64) -> String,
) -> Drawn<DB>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    layer.set("axes", "");
    let (x_axis, y_axis) = (
        TickAxis::new(chart.x_range()),
        TickAxis::new(chart.y_range()),
    );
    let x_label = |x: &f64| label(&x_axis.value(*x));
    let y_label = |y: &f64| label(&y_axis.value(*y));
    chart
        .configure_mesh()
        .x_desc(x_axis.describe(x_desc))
        .y_desc(y_axis.describe(y_desc))
        .axis_desc_style((FONT, LABEL_SIZE))
        .label_style((FONT, TEXT_SIZE))
        .bold_line_style(GRID)
        .light_line_style(GRID_MINOR)
        .x_labels(labels.0)
        .y_labels(labels.1)
        .x_label_formatter(&x_label)
        .y_label_formatter(&y_label)
        .draw()
}

/// Notes and labels: the text size in `color`, anchored at `h`, `v`.
pub fn note(color: RGBColor, h: HPos, v: VPos) -> TextStyle<'static> {
    (FONT, super::style::TEXT_SIZE)
        .into_font()
        .color(&color)
        .pos(Pos::new(h, v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn legends_fold_what_does_not_fit() {
        let line = Sample::Line(BLACK.stroke_width(1));
        let dot = Sample::Dot(BLACK.filled(), 3);
        let mut entries: Vec<Entry> = (0..20).map(|k| Entry::new(format!("y{k}"), line)).collect();
        entries.push(Entry::new("impact (3)", dot));
        entries.push(Entry::new("lift-off (1)", dot));
        assert!(fold(&entries, 22).is_none());
        let kept = fold(&entries, 10).unwrap();
        assert_eq!(kept.len(), 10);
        let labels: Vec<&str> = kept.iter().map(|e| e.label.as_str()).collect();
        assert_eq!(labels[0], "y0");
        assert!(labels.contains(&"impact (3)"), "{labels:?}");
        let more = labels.iter().find(|l| l.starts_with("and ")).unwrap();
        // Every entry is shown or counted.
        let n: usize = more[4..more.len() - 5].parse().unwrap();
        assert_eq!(n + kept.len() - 1, entries.len(), "{labels:?}");
    }

    #[test]
    fn round_off_ticks_are_zero_and_narrow_ranges_offset() {
        let axis = TickAxis::new(-1.0..1.0);
        assert_eq!(axis.value(-5.551115123125783e-17), 0.0);
        assert_eq!(axis.value(0.25), 0.25);
        assert_eq!(axis.describe("x"), "x");
        let axis = TickAxis::new(5e11 - 21.6..5e11 + 2.4);
        assert_eq!(axis.offset, Some(5e11));
        assert_eq!(axis.describe("y"), "y (5e11 + …)");
        assert_eq!(axis.value(5e11 - 15.0), -15.0);
        let axis = TickAxis::new(123456.78..123456.79);
        assert_eq!(axis.describe("t"), "t (123456.79 + …)");
        // Wide ranges and ranges about 0 have no offset.
        assert_eq!(TickAxis::new(0.0..400.0).offset, None);
        assert_eq!(TickAxis::new(399.9..400.0).offset, None);
    }

    #[test]
    fn drawable_ranges_are_finite_and_resolvable() {
        // Ordinary ranges are kept.
        assert_eq!(drawable((-1.0, 10.5)), -1.0..10.5);
        // Infinite or NaN ends, and spans wider than f64 holds.
        let r = drawable((f64::NEG_INFINITY, f64::INFINITY));
        assert!(r.start.is_finite() && r.end == f64::MAX && (r.end - r.start).is_finite());
        assert_eq!(drawable((f64::NAN, 2.0)), 0.0..2.0);
        let r = drawable((-1.7e308, 1.7e308));
        assert_eq!(r.end, 1.7e308);
        assert!((r.end - r.start).is_finite());
        // Too narrow for ticks: widened about the middle to 2^-36 of its size.
        let r = drawable((1e15, 1e15 + 1e-3));
        assert!(r.start < 1e15 && r.end > 1e15 + 1e-3);
        assert!((r.end - r.start) >= 1e15 * 2f64.powi(-36));
        assert_eq!(drawable((0.0, 0.0)), -0.5..0.5);
        let r = drawable((f64::MAX, f64::MAX));
        assert!(r.end == f64::MAX && r.start < f64::MAX);
    }
}
