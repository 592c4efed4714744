//! Work–precision diagrams (`zenosim work-precision POINTS.json`): for each panel (an error
//! measure), the error against the wall time and against the right-hand-side evaluations, on
//! log–log axes, a line per series (a tool and its settings) through its points in order of
//! cost. The points are measured elsewhere (`bench/run` compares zenosim with scipy).

use std::fs::File;
use std::io::Read;
use std::path::Path;

use anyhow::{anyhow, Context};
use plotters::coord::Shift;
use plotters::prelude::{
    Circle, Color, DrawingArea, EmptyElement, IntoFont, IntoLogRange, LineSeries, ShapeStyle, Text,
    WHITE,
};
use plotters::style::text_anchor::{HPos, VPos};
use plotters_backend::DrawingBackend;
use serde::Deserialize;

use super::canvas::{render, Drawn, Format, Picture, FONT};
use super::chart::{frame, legend, mesh, note, Entry, Sample};
use super::style::{color, short, tick, LINE_WIDTH, TEXT_SIZE, TITLE_SIZE};
use super::svg::Layer;
use crate::cli::WorkPrecisionArgs;
use crate::output::write_file;
use crate::{print_report, Classify, Failure, EXIT_OK};

/// The largest input read: a diagram's points take kilobytes.
const MAX_INPUT_BYTES: u64 = 16 << 20;
/// A panel's height in pixels.
const PANEL_HEIGHT: u32 = 460;
/// The fewest decades an axis spans.
const MIN_DECADES: f64 = 1.3;
/// The room for the title and subtitle above the panels.
const HEADER_HEIGHT: u32 = 70;

/// The measured points, as `bench/run` writes them.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Diagram {
    /// Above everything.
    pub title: String,
    /// Below the title: the machine and the date, say.
    #[serde(default)]
    pub subtitle: String,
    /// One row of two plots each.
    pub panels: Vec<Panel>,
}

/// One error measure.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Panel {
    /// The panel's caption.
    pub title: String,
    /// What the error is (the vertical axis).
    pub error: String,
    /// The series.
    pub series: Vec<Series>,
}

/// A tool with its settings.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Series {
    /// In the legend.
    pub label: String,
    /// Its measured points.
    pub points: Vec<Point>,
}

/// One measurement.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Point {
    /// The error (`≥ 0`).
    pub error: f64,
    /// The wall time in seconds (`> 0`).
    pub wall_time_s: f64,
    /// The right-hand-side evaluations (`> 0`).
    pub rhs_evals: f64,
    /// The tolerance it was run at, if any (for the reader of the file).
    #[serde(default)]
    pub tolerance: Option<f64>,
    /// The switching threshold ε, if any.
    #[serde(default)]
    pub epsilon: Option<f64>,
}

impl Point {
    /// `tol 1e-8` and `ε 1e-6`, as far as known.
    fn setting(&self) -> Option<String> {
        let parts: Vec<String> = [("tol", self.tolerance), ("ε", self.epsilon)]
            .iter()
            .filter_map(|(name, value)| value.map(|v| format!("{name} {}", short(v))))
            .collect();
        (!parts.is_empty()).then(|| parts.join(", "))
    }
}

/// The two costs, the horizontal axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Cost {
    WallTime,
    RhsEvals,
}

impl Cost {
    fn of(self, p: &Point) -> f64 {
        match self {
            Cost::WallTime => p.wall_time_s,
            Cost::RhsEvals => p.rhs_evals,
        }
    }

    fn description(self) -> &'static str {
        match self {
            Cost::WallTime => "wall time (s)",
            Cost::RhsEvals => "right-hand-side evaluations",
        }
    }
}

impl Diagram {
    /// Reads and checks `path`; every error names the file and the place.
    pub fn read(path: &Path) -> anyhow::Result<Self> {
        let display = path.display();
        let mut text = String::new();
        File::open(path)
            .and_then(|file| file.take(MAX_INPUT_BYTES + 1).read_to_string(&mut text))
            .with_context(|| format!("cannot read {display}"))?;
        if text.len() as u64 > MAX_INPUT_BYTES {
            return Err(anyhow!(
                "{display}: larger than 16 MiB; a diagram's points take kilobytes: check that \
                 this is the right file"
            ));
        }
        let diagram: Self = serde_json::from_str(&text).map_err(|error| {
            let message = error.to_string();
            let message = message
                .rfind(" at line ")
                .map_or(&*message, |end| &message[..end]);
            anyhow!(
                "{display}:{}:{}: {message}; see `zenosim work-precision --help` for the format",
                error.line(),
                error.column()
            )
        })?;
        diagram
            .check()
            .map_err(|problem| anyhow!("{display}: {problem}"))?;
        Ok(diagram)
    }

    /// What the drawing relies on: something to draw, and costs and errors it can place on
    /// log axes.
    fn check(&self) -> Result<(), String> {
        if self.panels.is_empty() {
            return Err("`panels` is empty: nothing to draw".to_string());
        }
        for (i, panel) in self.panels.iter().enumerate() {
            let points = panel.series.iter().map(|s| s.points.len()).sum::<usize>();
            if points == 0 {
                return Err(format!("panels[{i}] (\"{}\") has no points", panel.title));
            }
            for (j, series) in panel.series.iter().enumerate() {
                for (k, p) in series.points.iter().enumerate() {
                    let at = format!("panels[{i}].series[{j}].points[{k}]");
                    if !(p.error.is_finite() && p.error >= 0.0) {
                        return Err(format!(
                            "{at}.error is {}: an error must be a finite number ≥ 0 (leave out \
                             a point whose run failed)",
                            p.error
                        ));
                    }
                    for (name, value) in
                        [("wall_time_s", p.wall_time_s), ("rhs_evals", p.rhs_evals)]
                    {
                        if !(value.is_finite() && value > 0.0) {
                            return Err(format!(
                                "{at}.{name} is {value}: a cost must be a finite number > 0"
                            ));
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

/// `[low, high]` around the positive `values` with a factor `margin` either side, widened to
/// span a decade at least (so that a log axis has labelled ticks); `default` when there are no
/// positive values.
fn log_range(values: impl Iterator<Item = f64>, margin: f64, default: (f64, f64)) -> (f64, f64) {
    let (low, high) = values
        .filter(|v| *v > 0.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        });
    if low > high {
        return default;
    }
    let (low, high) = (low / margin, high * margin);
    let widen = (10f64.ln() * MIN_DECADES - (high / low).ln()).max(0.0) / 2.0;
    (low / widen.exp(), high * widen.exp())
}

impl Picture for Diagram {
    fn size(&self) -> (u32, u32) {
        (
            1500,
            HEADER_HEIGHT + PANEL_HEIGHT * self.panels.len() as u32,
        )
    }

    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, layer: &Layer) -> Drawn<DB> {
        area.fill(&WHITE)?;
        layer.set("title", "");
        let area = area.titled(&self.title, (FONT, TITLE_SIZE + 4))?;
        let area = if self.subtitle.is_empty() {
            area
        } else {
            area.titled(&self.subtitle, (FONT, TEXT_SIZE))?
        };
        let rows = area.split_evenly((self.panels.len(), 1));
        for (panel, row) in self.panels.iter().zip(&rows) {
            let (left, right) = row.split_horizontally(row.dim_in_pixel().0 * 43 / 100);
            panel.draw(&left, layer, Cost::WallTime, false)?;
            panel.draw(&right, layer, Cost::RhsEvals, true)?;
        }
        Ok(())
    }
}

impl Panel {
    fn draw<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        layer: &Layer,
        cost: Cost,
        with_legend: bool,
    ) -> Drawn<DB> {
        let points = || self.series.iter().flat_map(|s| s.points.iter());
        let (x_low, x_high) = log_range(points().map(|p| cost.of(p)), 1.6, (1e-6, 1.0));
        let (y_low, y_high) = log_range(points().map(|p| p.error), 4.0, (1e-16, 1.0));
        let style = |k: usize| ShapeStyle::from(color(k)).stroke_width(LINE_WIDTH);
        let entries: Vec<Entry> = if with_legend {
            self.series
                .iter()
                .enumerate()
                .map(|(k, s)| Entry::new(s.label.clone(), Sample::Line(style(k))))
                .collect()
        } else {
            Vec::new()
        };
        let caption = match cost {
            Cost::WallTime => format!("{}: error against time", self.title),
            Cost::RhsEvals => format!("{}: error against evaluations", self.title),
        };
        let mut chart = frame(area, &caption, &entries)
            .caption(caption.clone(), (FONT, TEXT_SIZE + 3).into_font())
            .build_cartesian_2d((x_low..x_high).log_scale(), (y_low..y_high).log_scale())?;
        mesh(
            &mut chart,
            layer,
            (cost.description(), &self.error),
            (12, 12),
            &decade,
        )?;
        for (k, series) in self.series.iter().enumerate() {
            layer.set("series", &series.label);
            let mut line: Vec<(f64, f64)> = series
                .points
                .iter()
                .map(|p| (cost.of(p), p.error.max(y_low)))
                .collect();
            line.sort_by(|a, b| a.0.total_cmp(&b.0));
            chart.draw_series(LineSeries::new(line, style(k)))?;
            // A point whose error is exactly 0 sits on the floor, open.
            chart.draw_series(series.points.iter().map(|p| {
                let at = (cost.of(p), p.error.max(y_low));
                let mark = if p.error > 0.0 {
                    color(k).filled()
                } else {
                    color(k).stroke_width(2)
                };
                Circle::new(at, 4, mark)
            }))?;
            // On the time plot, each point says the setting it was measured at.
            if cost == Cost::WallTime {
                layer.set("settings", &series.label);
                let style = note(color(k), HPos::Left, VPos::Bottom);
                chart.draw_series(series.points.iter().filter_map(|p| {
                    let text = p.setting()?;
                    let at = (cost.of(p), p.error.max(y_low));
                    Some(EmptyElement::at(at) + Text::new(text, (5, -3), style.clone()))
                }))?;
            }
        }
        if with_legend {
            legend(area, &chart, layer, &entries)?;
        }
        Ok(())
    }
}

/// A log axis's tick label: the powers of ten only (the ticks between them, 2·10ᵏ, 3·10ᵏ, …,
/// would overlap), which [`log_range`]'s span of more than a decade always includes.
fn decade(x: &f64) -> String {
    let exponent = x.log10().round();
    if (x.log10() - exponent).abs() < 1e-9 {
        tick(&10f64.powi(exponent as i32))
    } else {
        String::new()
    }
}

/// `zenosim work-precision POINTS.json`: draws the diagram.
pub fn work_precision(args: &WorkPrecisionArgs) -> Result<u8, Failure> {
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| args.input.with_extension("svg"));
    let format = format_of(&out).bad_input()?;
    let diagram = Diagram::read(&args.input).bad_input()?;
    let bytes = render(&diagram, format).output()?;
    write_file(&out, &bytes).output()?;
    print_report(&format!("wrote {}\n", out.display()));
    Ok(EXIT_OK)
}

/// The format named by `path`'s extension.
fn format_of(path: &Path) -> anyhow::Result<Format> {
    match path.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("svg") => Ok(Format::Svg),
        Some(e) if e.eq_ignore_ascii_case("png") => Ok(Format::Png),
        _ => Err(anyhow!(
            "--out {}: name the diagram's file with .svg or .png, which says its format",
            path.display()
        )),
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;

    use super::*;

    fn diagram(json: &str) -> anyhow::Result<Diagram> {
        let mut file = tempfile::NamedTempFile::new().unwrap();
        file.write_all(json.as_bytes()).unwrap();
        Diagram::read(file.path())
    }

    const GOOD: &str = r#"{"title": "t", "panels": [{"title": "ball", "error": "|τ∞ − τ|",
        "series": [{"label": "zenosim", "points": [
            {"error": 1e-9, "wall_time_s": 1e-5, "rhs_evals": 300, "tolerance": 1e-8},
            {"error": 0, "wall_time_s": 2e-5, "rhs_evals": 500}]}]}]}"#;

    #[test]
    fn a_diagram_is_drawn_with_a_series_per_tool() {
        let d = diagram(GOOD).unwrap();
        let svg = String::from_utf8(render(&d, Format::Svg).unwrap()).unwrap();
        // Each plot of the row draws the series.
        assert_eq!(
            svg.matches(r#"<g class="series" data-name="zenosim">"#)
                .count(),
            2
        );
        assert!(svg.contains("right-hand-side evaluations"));
        assert!(svg.contains("ball: error against time"));
        assert!(render(&d, Format::Png).is_ok());
    }

    #[test]
    fn bad_points_are_named() {
        let bad = GOOD.replace("\"error\": 1e-9", "\"error\": -1");
        let error = diagram(&bad).unwrap_err().to_string();
        assert!(
            error.contains("panels[0].series[0].points[0].error is -1"),
            "{error}"
        );
        let bad = GOOD.replace("\"rhs_evals\": 500", "\"rhs_evals\": 0");
        let error = diagram(&bad).unwrap_err().to_string();
        assert!(error.contains("points[1].rhs_evals is 0"), "{error}");
        let bad = GOOD.replace("\"wall_time_s\": 1e-5, ", "");
        let error = diagram(&bad).unwrap_err().to_string();
        assert!(
            error.contains(":3:") && error.contains("missing field `wall_time_s`"),
            "{error}"
        );
        let bad = GOOD.replace("\"title\": \"t\"", "\"titel\": \"t\"");
        let error = diagram(&bad).unwrap_err().to_string();
        assert!(error.contains("unknown field `titel`"), "{error}");
        let error = diagram(r#"{"title": "t", "panels": []}"#)
            .unwrap_err()
            .to_string();
        assert!(error.contains("nothing to draw"), "{error}");
    }

    #[test]
    fn the_format_is_the_extension() {
        assert_eq!(format_of(Path::new("a/b.svg")).unwrap(), Format::Svg);
        assert_eq!(format_of(Path::new("b.PNG")).unwrap(), Format::Png);
        assert!(format_of(Path::new("b.pdf")).is_err());
        assert!(format_of(Path::new("b")).is_err());
    }

    #[test]
    fn only_decades_are_labelled() {
        assert_eq!(decade(&1000.0), "1000");
        assert_eq!(decade(&1e-5), "1e-5");
        assert_eq!(decade(&2000.0), "");
        assert_eq!(decade(&0.003), "");
    }

    #[test]
    fn ranges_leave_a_margin_and_skip_zeros() {
        let (low, high) = log_range([0.0, 1.0, 400.0].into_iter(), 2.0, (1.0, 2.0));
        assert!((low - 0.5).abs() < 1e-12 && (high - 800.0).abs() < 1e-9);
        // Narrow ranges are widened to 1.3 decades about their middle.
        let (low, high) = log_range([3000.0, 5000.0].into_iter(), 1.0, (1.0, 2.0));
        assert!(((high / low).log10() - MIN_DECADES).abs() < 1e-12);
        assert!(((low * high).sqrt() - (3000.0f64 * 5000.0).sqrt()).abs() < 1e-6);
        assert_eq!(log_range([0.0].into_iter(), 2.0, (1.0, 2.0)), (1.0, 2.0));
    }
}
