//! The plots of a run (`zenosim run --plot`, `zenosim plot DIR`), drawn from its output
//! directory: `summary.json` (read first: it is written last, so its presence means the run is
//! complete) and `trajectory.csv`, read row by row and decimated for drawing.
//!
//! The files, each written under a temporary name and renamed once complete:
//! `figure`, the paper's Figs. 4/5 (velocities, displacements, configuration plane);
//! `velocities`, `displacements`, `energy` against time (with `E(0) + work − impact loss`
//! beside the energy when the trajectory has the energy balance's columns); `plane`; `zeno`,
//! the flight times; and for a run with friction `friction`, the tangential forces against
//! time.

mod animation;
mod animation_frames;
mod animation_render;
mod canvas;
mod chart;
mod contour;
mod decimate;
mod figure;
mod gif_file;
mod plane_chart;
mod raster;
pub(crate) mod record;
pub(crate) mod scene;
mod sequences;
mod style;
mod svg;
mod sweep_map;
mod time_chart;
pub(crate) mod trajectory_file;
mod work_precision;
mod zeno_chart;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use anyhow::{anyhow, Context};

pub use animation::animate;
pub use canvas::Format;
pub use scene::PlaneScale;
pub use style::short;
pub use sweep_map::{draw_map, MapSpec};
pub(crate) use time_chart::BALANCE;
pub use work_precision::work_precision;

use crate::cli::PlotArgs;
use crate::output::OutputDir;
use crate::run::{SUMMARY, TRAJECTORY};
use crate::{print_report, Classify, Failure, EXIT_OK};
use canvas::render;
use figure::Figure;
use plane_chart::PlaneChart;
use record::Record;
use scene::{default_plane, Scene};
use time_chart::{Quantity, TimeChart};
use trajectory_file::quote;
use zeno_chart::ZenoChart;

/// The plots' names, in the order they are written; the files are `<name>.<format>`. The last,
/// [`FRICTION`], only for a run with friction.
pub const PLOTS: [&str; 7] = [
    "figure",
    "velocities",
    "displacements",
    "plane",
    "energy",
    "zeno",
    FRICTION,
];

/// The plot of the tangential forces, drawn for a run of a model with friction only.
pub const FRICTION: &str = "friction";

/// Every file name a plot may have, in every format.
pub fn plot_files() -> Vec<String> {
    let formats = [Format::Svg, Format::Png];
    PLOTS
        .iter()
        .flat_map(|name| formats.map(|f| format!("{name}.{}", f.extension())))
        .collect()
}

/// Two names of coordinates or velocities, the axes of the configuration plot: `X,Y`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Plane {
    /// The horizontal axis.
    pub x: String,
    /// The vertical axis.
    pub y: String,
}

impl FromStr for Plane {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        match text.split(',').map(str::trim).collect::<Vec<_>>()[..] {
            [x, y] if !x.is_empty() && !y.is_empty() && x != y => Ok(Self {
                x: x.to_string(),
                y: y.to_string(),
            }),
            _ => Err("expected two different names X,Y, e.g. x2,x3".to_string()),
        }
    }
}

impl Plane {
    /// The columns of `(q, q̇)` named by the plane, among `names`.
    pub fn columns(&self, names: &[String]) -> anyhow::Result<(usize, usize)> {
        let find = |name: &str| {
            names.iter().position(|n| n == name).ok_or_else(|| {
                anyhow!(
                    "--plane: no coordinate or velocity is named `{}`; this model's are {}",
                    quote(name),
                    quote(&names.join(", "))
                )
            })
        };
        Ok((find(&self.x)?, find(&self.y)?))
    }
}

/// `zenosim plot DIR`: draws the plots of the run in `DIR`.
pub fn plot(args: &PlotArgs) -> Result<u8, Failure> {
    let written = draw_scaled(
        &args.dir,
        args.format,
        args.plane.as_ref(),
        args.plane_scale,
    )?;
    let mut report = String::new();
    for path in written {
        report.push_str(&format!("wrote {}\n", path.display()));
    }
    print_report(&report);
    Ok(EXIT_OK)
}

/// Draws every plot of the run in `dir` in `format`, the configuration plot in `plane` (by
/// default the one [`default_plane`] picks); the files written. An unreadable run is a bad
/// input; a file that cannot be written, an output failure.
pub fn draw(dir: &Path, format: Format, plane: Option<&Plane>) -> Result<Vec<PathBuf>, Failure> {
    draw_scaled(dir, format, plane, PlaneScale::default())
}

/// [`draw`] with the configuration plane's scales `scale`.
pub fn draw_scaled(
    dir: &Path,
    format: Format,
    plane: Option<&Plane>,
    scale: PlaneScale,
) -> Result<Vec<PathBuf>, Failure> {
    let record = Record::read(&dir.join(SUMMARY)).bad_input()?;
    let columns = match plane {
        Some(plane) => plane
            .columns(&record.columns().cloned().collect::<Vec<_>>())
            .with_context(|| format!("cannot plot {}", dir.display()))
            .bad_input()?,
        None => default_plane(&record),
    };
    let mut scene = Scene::load(&dir.join(TRAJECTORY), record, columns).bad_input()?;
    scene.scale = scale;

    let out = OutputDir::existing(dir).output()?;
    let mut written = Vec::new();
    let mut write = |name: &str, bytes: anyhow::Result<Vec<u8>>| {
        let (partial, mut file) = out
            .create(&format!("{name}.{}", format.extension()))
            .output()?;
        let path = partial.target().to_path_buf();
        file.write_all(&bytes.output()?)
            .with_context(|| format!("cannot write {}", path.display()))
            .output()?;
        partial.commit(file).output()?;
        written.push(path);
        Ok::<(), Failure>(())
    };
    let scene = &scene;
    write("figure", render(&Figure { scene }, format))?;
    for quantity in [Quantity::Velocities, Quantity::Displacements] {
        write(
            quantity.name(),
            render(&TimeChart { scene, quantity }, format),
        )?;
    }
    write("plane", render(&PlaneChart { scene }, format))?;
    let quantity = Quantity::Energy;
    write(
        quantity.name(),
        render(&TimeChart { scene, quantity }, format),
    )?;
    write("zeno", render(&ZenoChart::new(&scene.record), format))?;
    if !scene.record.friction.is_empty() {
        let quantity = Quantity::Friction;
        write(FRICTION, render(&TimeChart { scene, quantity }, format))?;
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planes_are_two_different_names() {
        let plane: Plane = "x2, x3".parse().unwrap();
        assert_eq!((plane.x.as_str(), plane.y.as_str()), ("x2", "x3"));
        for bad in ["x2", "x2,", ",x3", "x2,x3,x1", "x2,x2", ""] {
            assert!(bad.parse::<Plane>().is_err(), "{bad}");
        }
        let names = ["x", "y", "x_dot", "y_dot"].map(String::from);
        assert_eq!(plane_of("y_dot,x").columns(&names).unwrap(), (3, 0));
        let error = plane_of("x,z").columns(&names).unwrap_err().to_string();
        assert!(
            error.contains("`z`") && error.contains("x, y, x_dot, y_dot"),
            "{error}"
        );
    }

    fn plane_of(text: &str) -> Plane {
        text.parse().unwrap()
    }

    #[test]
    fn every_plot_has_a_file_in_each_format() {
        let files = plot_files();
        assert_eq!(files.len(), 14);
        assert!(files.contains(&"friction.png".to_string()));
        assert!(files.contains(&"figure.svg".to_string()));
        assert!(files.contains(&"zeno.png".to_string()));
    }
}
