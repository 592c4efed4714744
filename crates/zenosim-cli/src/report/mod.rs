//! The report of a run (`zenosim report DIR`, `zenosim run --report`): one self-contained
//! `report.html` in the run's folder, that plays the mechanism, plots the run interactively and
//! lists its events and Zeno points, offline (nothing is fetched: the page's policy forbids
//! it).
//!
//! It reads what `zenosim plot` reads, with the same readers: `summary.json` first, then
//! `trajectory.csv` in one pass, decimated for the plots as the static plots are and thinned
//! into the animation's frames ([`frames`]); and `model.toml`, the model file the run wrote
//! beside them, for the mechanism's drawing ([`mechanism`]). The page ([`page`]) is a template
//! with its script and style written here, no library, and the data as one JSON blob
//! ([`data`]).

mod data;
mod frames;
mod mechanism;
mod page;

use std::path::{Path, PathBuf};

use anyhow::anyhow;

use zenosim_model::Limits;

use crate::cli::ReportArgs;
use crate::output::write_file;
use crate::plot::record::Record;
use crate::plot::scene::default_plane;
use crate::plot::trajectory_file;
use crate::run::{SUMMARY, TRAJECTORY};
use crate::{print_report, Classify, Failure, EXIT_OK};

/// The report's file name.
pub const REPORT: &str = "report.html";

/// `zenosim report DIR`.
pub fn report(args: &ReportArgs) -> Result<u8, Failure> {
    let path = write(&args.dir, args.formulas.limits())?;
    print_report(&format!("wrote {}\n", path.display()));
    Ok(EXIT_OK)
}

/// Writes the report of the run in `dir` (through a temporary file renamed once complete), its
/// model file read again within `limits`; its path. An unreadable run is a bad input; a file
/// that cannot be written, an output failure.
pub fn write(dir: &Path, limits: Limits) -> Result<PathBuf, Failure> {
    let record = Record::read(&dir.join(SUMMARY)).bad_input()?;
    let drawing = mechanism::load(dir, &record, limits).bad_input()?;
    let (t_start, t_end) = record.time_span();
    let mut frames = frames::Frames::new(record.coordinates.len(), t_start, t_end);
    let trajectory = trajectory_file::read_with(
        &dir.join(TRAJECTORY),
        &record,
        default_plane(&record),
        |row| frames.push(row),
    )
    .bad_input()?;
    let frames = frames.finish();
    if frames.len() == 0 {
        return Err(anyhow!(
            "{}: no rows: there is nothing to show; run the model again",
            dir.join(TRAJECTORY).display()
        ))
        .bad_input();
    }
    let drawn = match drawing {
        Ok(drawing) => Ok(mechanism::draw(&drawing, &frames, dir).bad_input()?),
        Err(note) => Err(note),
    };
    let data = data::Data::new(&record, &trajectory, &frames, drawn);
    let html = page::html(&data).output()?;
    let path = dir.join(REPORT);
    write_file(&path, html.as_bytes()).output()?;
    Ok(path)
}
