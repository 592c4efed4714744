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
/// the legend of `entries`.
pub fn frame<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    entries: &[Entry],
) -> ChartBuilder<'a, 'static, DB> {
    let right = widest(area, entries).map_or(28, |w| {
        LEGEND_ROOM.max(w + SAMPLE_WIDTH + 2 * LEGEND_MARGIN + LEGEND_GAP + 12)
    });
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(caption, (FONT, TITLE_SIZE))
        .margin(12)
        .margin_right(right)
        .x_label_area_size(48)
        .y_label_area_size(80);
    builder
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
        }
        area.draw(&Text::new(
            entry.label.clone(),
            (x + LEGEND_MARGIN + SAMPLE_WIDTH, cy),
            note(BLACK, HPos::Left, VPos::Center),
        ))?;
    }
    Ok(())
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
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .axis_desc_style((FONT, LABEL_SIZE))
        .label_style((FONT, TEXT_SIZE))
        .bold_line_style(GRID)
        .light_line_style(GRID_MINOR)
        .x_labels(labels.0)
        .y_labels(labels.1)
        .x_label_formatter(label)
        .y_label_formatter(label)
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
    use super::drawable;

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
