//! The paper's figure (Ames et al. 2006, Figs. 4 and 5): the velocities, the displacements and
//! the configuration plane, one above the other, under what happened in the run.

use plotters::coord::Shift;
use plotters::prelude::{DrawingArea, WHITE};
use plotters_backend::DrawingBackend;
use zenosim_runs::message::plural;

use super::canvas::{Drawn, Picture, FONT};
use super::plane_chart::{draw_plane, plane_title};
use super::record::Record;
use super::scene::Scene;
use super::style::{short, TITLE_SIZE};
use super::svg::Layer;
use super::time_chart::{draw_time, Quantity};

/// The three panels of the paper's figures.
pub struct Figure<'a> {
    /// The run.
    pub scene: &'a Scene,
}

impl Picture for Figure<'_> {
    fn size(&self) -> (u32, u32) {
        (1000, 1320)
    }

    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, layer: &Layer) -> Drawn<DB> {
        area.fill(&WHITE)?;
        let record = &self.scene.record;
        layer.set("title", "");
        let title = format!("{}: {}", record.model, headline(record));
        let body = area
            .margin(10, 0, 0, 0)
            .titled(&title, (FONT, TITLE_SIZE))?;
        let panels = body.split_evenly((3, 1));
        for (quantity, panel) in [Quantity::Velocities, Quantity::Displacements]
            .into_iter()
            .zip(&panels)
        {
            draw_time(panel, layer, self.scene, quantity, quantity.name())?;
        }
        draw_plane(&panels[2], layer, self.scene, &plane_title(self.scene))
    }
}

/// What happened in the run, in a line that fits the figure's title.
fn headline(record: &Record) -> String {
    let impacts = plural(record.times("impact").len(), "impact");
    let end = record.final_.t.map_or("?".to_string(), short);
    match record.status.as_str() {
        "finished" => format!(
            "finished at t = {end} after {impacts}, {} passed",
            plural(record.zeno.len(), "Zeno point")
        ),
        "zeno_stalled" => {
            let tau = record.zeno.last().and_then(|z| z.t_zeno);
            format!(
                "stuck at the Zeno point τ∞ ≈ {} after {impacts} (--zeno off)",
                tau.map_or("?".to_string(), short)
            )
        }
        _ => format!("failed at t = {end} after {impacts} (see summary.json)"),
    }
}
