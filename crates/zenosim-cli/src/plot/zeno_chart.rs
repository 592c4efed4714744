//! The Zeno diagnostic: the flight times `τ_{i+1} − τ_i` of an impact sequence against the
//! impact index `i`, on a log scale, with the fitted ratio and the estimate of `τ∞`. A genuinely
//! Zeno sequence is a straight line of slope `log e` (Ames et al. 2006, Section III).
//!
//! One panel per Zeno point; a run without one gets a panel per impact sequence of three
//! impacts or more (ended by a lift-off, an impact on another constraint or the run's end).

use plotters::coord::Shift;
use plotters::prelude::{
    Circle, Color, DashedLineSeries, DrawingArea, EmptyElement, IntoLogRange, LineSeries, Text,
    WHITE,
};
use plotters::style::text_anchor::{HPos, VPos};
use plotters_backend::DrawingBackend;

use super::canvas::{Drawn, Picture};
use super::chart::{axes, frame, legend, note, Entry, Sample};
use super::record::Record;
use super::sequences::{sequences, Flights, Sequence};
use super::style::{color, short, significant, LINE_WIDTH, SWITCH, TEXT_SIZE};
use super::svg::Layer;

/// The most panels drawn: a run with more Zeno points shows its first ones.
pub const MAX_PANELS: usize = 12;
/// A panel's height in pixels.
const PANEL_HEIGHT: u32 = 440;

/// The Zeno diagnostic: a column of panels.
pub struct ZenoChart<'a> {
    /// The run.
    pub record: &'a Record,
    /// Its sequences, as [`sequences`] finds them.
    pub sequences: Vec<Sequence<'a>>,
}

impl<'a> ZenoChart<'a> {
    /// The diagnostic of `record`.
    pub fn new(record: &'a Record) -> Self {
        Self {
            record,
            sequences: sequences(record),
        }
    }

    fn panels(&self) -> usize {
        self.sequences.len().clamp(1, MAX_PANELS)
    }
}

impl Picture for ZenoChart<'_> {
    fn size(&self) -> (u32, u32) {
        (1000, PANEL_HEIGHT * self.panels() as u32)
    }

    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, layer: &Layer) -> Drawn<DB> {
        area.fill(&WHITE)?;
        let areas = area.split_evenly((self.panels(), 1));
        if self.sequences.is_empty() {
            let caption = format!("{}: Zeno diagnostic", self.record.model);
            let mut chart =
                frame(&areas[0], &caption, &[]).build_cartesian_2d(0.5..3.5, 0.0..1.0)?;
            axes(&mut chart, layer, "impact i", "flight time τ(i+1) − τ(i)")?;
            layer.set("note", "");
            return chart
                .draw_series([Text::new(
                    "no sequence of three impacts or more: no flight times to compare",
                    (0.6, 0.5),
                    note(SWITCH, HPos::Left, VPos::Center),
                )])
                .map(|_| ());
        }
        let shown = self.sequences.len().min(MAX_PANELS);
        for (k, (sequence, area)) in self.sequences.iter().zip(&areas).enumerate() {
            let mut caption = self.caption(sequence);
            if k == 0 && shown < self.sequences.len() {
                caption = format!("{caption} (first {shown} of {})", self.sequences.len());
            }
            self.panel(area, layer, &Flights::new(sequence), &caption)?;
        }
        Ok(())
    }
}

impl ZenoChart<'_> {
    fn caption(&self, s: &Sequence<'_>) -> String {
        let model = &self.record.model;
        match s.zeno {
            Some((k, z)) => {
                // A Zeno point over several constraints names them all.
                let on = if z.constraints.len() > 1 {
                    z.constraints.join("'+'")
                } else {
                    s.constraint.to_string()
                };
                format!(
                    "{model}: Zeno point {} on '{on}', {}, {} impacts",
                    k + 1,
                    z.kind,
                    z.impacts
                )
            }
            None => format!(
                "{model}: {} impacts on '{}' (no Zeno point reached)",
                s.times.len(),
                s.constraint
            ),
        }
    }

    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        layer: &Layer,
        panel: &Flights<'_>,
        caption: &str,
    ) -> Drawn<DB> {
        let last = panel.sequence.times.len().saturating_sub(1).max(1) as f64;
        let (low, high) = panel
            .flights
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), f| {
                (l.min(f.1), h.max(f.1))
            });
        let (low, high) = if low <= high {
            (low / 4.0, high * 4.0)
        } else {
            (1e-3, 1.0)
        };
        let fit_style = SWITCH.stroke_width(1);
        let style = color(0).stroke_width(LINE_WIDTH);
        let mut entries = Vec::new();
        if let Some(fit) = panel.fit {
            let fitted = (fit.span.1 - fit.span.0) as usize + 1;
            let on = if fitted < panel.flights.len() {
                format!(" (last {fitted} flights)")
            } else {
                String::new()
            };
            let label = format!("fit: ratio r = {}{on}", significant(fit.ratio, 4));
            entries.push(Entry::new(label, Sample::Line(fit_style)));
        }
        let label = format!("flight times ({})", panel.flights.len());
        entries.push(Entry::new(label, Sample::Line(style)));
        let mut chart = frame(area, caption, &entries)
            .build_cartesian_2d(0.5..last + 0.5, (low..high).log_scale())?;
        axes(&mut chart, layer, "impact i", "flight time τ(i+1) − τ(i)")?;

        layer.set("flights", panel.sequence.constraint);
        let mark = color(0).filled();
        chart.draw_series(LineSeries::new(panel.flights.iter().copied(), style))?;
        chart.draw_series(panel.flights.iter().map(|&p| Circle::new(p, 3, mark)))?;
        if let Some(fit) = panel.fit {
            layer.set("fit", panel.sequence.constraint);
            // Over the flights it was fitted to only: the tail, for a Zeno point.
            let (from, to) = fit.span;
            let line: Vec<(f64, f64)> = [from, to].iter().map(|&i| (i, fit.at(i))).collect();
            chart.draw_series(DashedLineSeries::new(line, 6, 4, fit_style))?;
        }

        layer.set("notes", panel.sequence.constraint);
        let notes = self.notes(panel);
        let (x0, y0) = (0.5 + 0.02 * last, low);
        chart.draw_series(notes.iter().rev().enumerate().map(|(k, text)| {
            EmptyElement::at((x0, y0))
                + Text::new(
                    text.clone(),
                    (0, -8 - (TEXT_SIZE as i32 + 4) * k as i32),
                    note(SWITCH, HPos::Left, VPos::Bottom),
                )
        }))?;
        legend(area, &chart, layer, &entries)
    }

    /// The lines written on a panel: the ratio against `e`, `τ∞`, the switch.
    fn notes(&self, panel: &Flights<'_>) -> Vec<String> {
        let s = panel.sequence;
        let mut notes = Vec::new();
        let e = self
            .record
            .restitutions
            .get(s.constraint)
            .copied()
            .flatten();
        let e = e.map_or(String::new(), |e| {
            format!(" (restitution e = {})", short(e))
        });
        match (panel.fit, s.zeno) {
            (Some(fit), Some(_)) => notes.push(format!(
                "ratio of successive flights r = {}{e}",
                significant(fit.ratio, 4)
            )),
            (Some(fit), None) => notes.push(format!(
                "least-squares ratio r = {}{e}",
                significant(fit.ratio, 4)
            )),
            (None, _) => notes.push(format!("no ratio measured{e}")),
        }
        match (panel.tau, s.zeno) {
            (Some(tau), Some(_)) => notes.push(format!("estimated τ∞ ≈ {}", significant(tau, 7))),
            (Some(tau), None) => notes.push(format!(
                "τ∞ ≈ {} if the sequence had gone on",
                significant(tau, 7)
            )),
            (None, _) => {}
        }
        if let Some((k, z)) = s.zeno {
            let stalled = self.record.stalled() && k + 1 == self.record.zeno.len();
            let verb = if stalled {
                "stalled"
            } else {
                "switched to constrained motion"
            };
            notes.push(format!("{verb} at t = {}", significant(z.t_switch, 7)));
        }
        if panel.zero > 0 {
            notes.push(format!(
                "{} flights of zero length (chattering) not shown",
                panel.zero
            ));
        }
        notes
    }
}

#[cfg(test)]
mod tests {
    use super::super::sequences::tests::record;
    use super::*;

    #[test]
    fn a_zeno_point_brings_the_engines_ratio_and_tau() {
        let r = record(
            &[
                ("impact", 1.0, "a"),
                ("impact", 1.5, "a"),
                ("impact", 1.7, "a"),
            ],
            &[("a", 1.9)],
            "zeno_stalled",
        );
        let s = sequences(&r);
        let p = Flights::new(&s[0]);
        let fit = p.fit.unwrap();
        assert_eq!(fit.ratio, 0.5);
        assert_eq!(fit.anchor, (2.0, 1.7 - 1.5));
        assert_eq!(fit.span, (1.0, 2.0));
        assert_eq!(p.tau, Some(1.9 + 1e-9));
        let notes = ZenoChart::new(&r).notes(&p);
        assert!(
            notes[0].contains("r = 0.5000 (restitution e = 0.5)"),
            "{notes:?}"
        );
        assert!(notes[1].contains("τ∞ ≈ 1.900000"), "{notes:?}");
        assert!(notes[2].starts_with("stalled at t = 1.9"), "{notes:?}");
    }
}
