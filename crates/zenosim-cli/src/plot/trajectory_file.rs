//! Reading `trajectory.csv` back, row by row, into decimated lines: a run of any length is read
//! in constant memory.
//!
//! Rows further apart than a pixel column (a run with long steps, or `--dt`) are joined along
//! the cubic through both rows' `q` and `q̇` (Hermite interpolation), its derivative for the
//! velocities: exact for a free flight under constant gravity (a parabola), third order
//! otherwise, where a straight chord would cut through the constraint's surface. The energy is
//! joined by a straight line, and so are the energy balance `E(0) + work − impact loss` of a
//! trajectory with its columns (a model that is not autonomous) and the tangential forces
//! `f_<constraint>` of a model with friction. The two rows of an event, at the same time, are
//! not joined.

use std::fs::File;
use std::ops::Range;
use std::path::Path;

use anyhow::{anyhow, bail, Context};

use super::decimate::{Bounds, PathDecimator, TimeDecimator};
use super::record::Record;
use crate::trajectory::{self, work_columns};

/// Columns of the time axis kept per series: twice the widest plot's pixels.
const TIME_COLUMNS: usize = 2048;
/// The most columns kept over all series (about 75 MB): a run of many coordinates keeps fewer
/// columns per series, so that memory is bounded whatever `summary.json` lists.
const TIME_CELLS: usize = 1 << 20;
/// The most characters of a file's text quoted in a message.
const QUOTED: usize = 200;
/// Cells across the plane plot's box: about twice its pixels.
const PLANE_CELLS: usize = 1600;
/// The most points drawn between two rows.
const MAX_BETWEEN: usize = 64;

/// The trajectory, decimated for drawing.
pub struct Trajectory {
    /// The series `q`, `q̇` (in the summary's order), then the energy, then (when
    /// [`Trajectory::balance`]) `E(0) + work − impact loss`, then the tangential forces
    /// ([`Trajectory::friction`]): `(t, value)` points.
    pub lines: Vec<Vec<(f64, f64)>>,
    /// Whether the file has the energy balance's columns, and [`Trajectory::lines`] its series.
    pub balance: bool,
    /// The series of the tangential forces `f_<constraint>`, in the order of the summary's
    /// `friction` (empty for a frictionless run).
    pub friction: Range<usize>,
    /// Each series' least and greatest values.
    pub ranges: Vec<Option<(f64, f64)>>,
    /// The path in the plane of two columns of `(q, q̇)`.
    pub path: Vec<(f64, f64)>,
    /// The path's bounding box.
    pub path_bounds: Option<Bounds>,
}

/// A row of the trajectory as [`read_with`] hands it over.
pub struct Row<'a> {
    /// Its time.
    pub t: f64,
    /// Its `mode` column: `free`, or `constrained:` and the constraints held joined by `+`,
    /// then maybe `;stick:` and `;slip:` lists (docs/output.md).
    pub mode: &'a str,
    /// `q…, q̇…`, the energy, `E(0) + work − impact loss` when the file has the energy
    /// balance's columns, then the tangential forces (the layout [`hermite`] joins).
    pub values: &'a [f64],
}

/// Reads the trajectory at `path` of the run `record`, with the plane of columns `plane`.
/// Errors name the file and the line.
pub fn read(path: &Path, record: &Record, plane: (usize, usize)) -> anyhow::Result<Trajectory> {
    read_with(path, record, plane, |_| {})
}

/// [`read`], handing every row of the file, in order, to `visit` as it is read (the report's
/// animation keeps some of them).
pub fn read_with(
    path: &Path,
    record: &Record,
    plane: (usize, usize),
    mut visit: impl FnMut(&Row<'_>),
) -> anyhow::Result<Trajectory> {
    let display = path.display();
    let file = File::open(path).with_context(|| format!("cannot read {display}"))?;
    // No line of a trajectory of these columns is longer than this: a longer one (a file of
    // one line of 1 GB) is refused as it is read, not held in memory.
    let header = trajectory::header(
        record.columns(),
        &record.constraints,
        &record.force_columns(),
        true,
    );
    let header_bytes: usize = header.iter().map(|name| name.len() + 1).sum();
    let longest = 4096 + 2 * header_bytes + 32 * header.len();
    let mut csv = csv::ReaderBuilder::new()
        .buffer_capacity(1 << 16)
        .from_reader(LineLimit::new(file, longest));
    let header = csv
        .byte_headers()
        .map_err(|error| anyhow!("{display}:1: {error}"))?
        .clone();
    let (names, balance) = check_header(&header, record).map_err(|problem| {
        anyhow!(
            "{display}:1: {problem}: this trajectory does not belong to the summary.json beside \
             it; run the model again"
        )
    })?;
    let n = record.coordinates.len();
    // The balance's columns: with friction, its work last.
    let friction_columns = !record.friction.is_empty();
    let works = if balance {
        work_columns(friction_columns).count()
    } else {
        0
    };
    let energy = names.len() - 1 - works;
    // The columns f_<constraint>, just before the energy.
    let forces = energy - record.force_columns().len();
    // The series: q, q̇, the energy, E(0) + work − impact loss, and the tangential forces.
    let first = 2 * n + 1 + usize::from(balance);
    let friction = first..first + record.force_columns().len();
    let series = friction.end;
    let (t_start, t_end) = record.time_span();
    let columns = TIME_COLUMNS.min(TIME_CELLS / series).max(1);
    let mut lines = TimeDecimator::new(series, t_start, t_end, columns);
    let mut plane_path = PathDecimator::new(PLANE_CELLS);
    let mut row = csv::ByteRecord::new();
    let mut values = vec![0.0; series];
    let mut previous: Option<(f64, Vec<f64>)> = None;
    let mut between = vec![0.0; series];
    // E(0): the first row's energy less its balance (0 at the start).
    let mut energy_start = None;
    let column = (t_end - t_start) / columns as f64;
    let mut rows = 0;
    loop {
        match csv.read_byte_record(&mut row) {
            Ok(true) => {}
            Ok(false) => break,
            Err(error) => {
                let line = error.position().map_or(0, |p| p.line());
                bail!("{display}:{line}: {}", csv_problem(&error));
            }
        }
        let line = row.position().map_or(0, |p| p.line());
        let field = |column: usize| {
            let text = &row[column];
            std::str::from_utf8(text)
                .ok()
                .and_then(|s| s.parse::<f64>().ok())
                .ok_or_else(|| {
                    anyhow!(
                        "{display}:{line}: column {}: `{}` is not a number",
                        quote(&names[column]),
                        quote(&String::from_utf8_lossy(text))
                    )
                })
        };
        let t = field(0)?;
        if t.is_finite() && !record.within_span(t) {
            bail!(
                "{display}:{line}: a row at t = {t}, outside the run of summary.json (from t = \
                 {t_start} to {t_end}): the files do not belong together; run the model again"
            );
        }
        for (k, value) in values.iter_mut().take(2 * n + 1).enumerate() {
            *value = field(if k < 2 * n { 2 + k } else { energy })?;
        }
        if balance {
            // work_forces + work_drive + work_constraints (+ work_friction) − impact_loss.
            let mut work = 0.0;
            for (k, name) in work_columns(friction_columns).enumerate() {
                let value = field(energy + 1 + k)?;
                work += if name == "impact_loss" { -value } else { value };
            }
            let start = *energy_start.get_or_insert(values[2 * n] - work);
            values[2 * n + 1] = start + work;
        }
        for (k, value) in values[friction.clone()].iter_mut().enumerate() {
            *value = field(forces + k)?;
        }
        rows += 1;
        let mode = std::str::from_utf8(&row[1])
            .map_err(|_| anyhow!("{display}:{line}: column `mode` is not valid UTF-8"))?;
        visit(&Row {
            t,
            mode,
            values: &values,
        });
        if let Some((t0, before)) = &previous {
            let gap = t - t0;
            if gap > column {
                let steps = ((gap / column).ceil() as usize).min(MAX_BETWEEN);
                for j in 1..steps {
                    let s = j as f64 / steps as f64;
                    hermite(before, &values, gap, s, n, &mut between);
                    lines.push(t0 + s * gap, &between);
                    plane_path.push(between[plane.0], between[plane.1]);
                }
            }
        }
        lines.push(t, &values);
        plane_path.push(values[plane.0], values[plane.1]);
        match &mut previous {
            Some((t0, before)) => {
                *t0 = t;
                before.copy_from_slice(&values);
            }
            None => previous = Some((t, values.clone())),
        }
    }
    if rows != record.trajectory.rows {
        bail!(
            "{display}: {rows} rows, but summary.json counts {}: the files do not belong \
             together; run the model again",
            record.trajectory.rows
        );
    }
    Ok(Trajectory {
        lines: (0..series).map(|s| lines.series(s)).collect(),
        ranges: (0..series).map(|s| lines.range(s)).collect(),
        balance,
        friction,
        path_bounds: plane_path.bounds(),
        path: plane_path.finish(),
    })
}

/// The point a fraction `s` of the way from row `a` to row `b`, `h` apart in time: each of the
/// `n` coordinates on the cubic with `a`'s and `b`'s values and velocities, each velocity its
/// derivative; the values after them (the energy, the balance, the tangential forces) on the
/// straight line. Rows are `q…, q̇…` and then those values.
pub fn hermite(a: &[f64], b: &[f64], h: f64, s: f64, n: usize, out: &mut [f64]) {
    let [h00, h10, h01, h11] = hermite_basis(s);
    // The basis's derivatives in s.
    let s2 = s * s;
    let (d00, d10, d01, d11) = (
        6.0 * s2 - 6.0 * s,
        3.0 * s2 - 4.0 * s + 1.0,
        6.0 * s - 6.0 * s2,
        3.0 * s2 - 2.0 * s,
    );
    for i in 0..n {
        let (q0, q1, v0, v1) = (a[i], b[i], a[n + i], b[n + i]);
        out[i] = h00 * q0 + h10 * h * v0 + h01 * q1 + h11 * h * v1;
        out[n + i] = (d00 * q0 + d01 * q1) / h + d10 * v0 + d11 * v1;
    }
    for k in 2 * n..a.len() {
        out[k] = a[k] + s * (b[k] - a[k]);
    }
}

/// The cubic Hermite basis at `s` in [0, 1]: the weights of the start's value, the start's
/// slope, the end's value and the end's slope (the slopes per unit of `s`).
pub fn hermite_basis(s: f64) -> [f64; 4] {
    let (s2, s3) = (s * s, s * s * s);
    [
        2.0 * s3 - 3.0 * s2 + 1.0,
        s3 - 2.0 * s2 + s,
        3.0 * s2 - 2.0 * s3,
        s3 - s2,
    ]
}

/// The header's names, checked against the summary's: `t, mode, q…, q̇…, h_…, λ_…, f_…,
/// energy` (`f_…` for the constraints the summary lists with friction), and maybe the energy
/// balance's columns (whether it has them).
fn check_header(header: &csv::ByteRecord, record: &Record) -> Result<(Vec<String>, bool), String> {
    let names: Vec<String> = header
        .iter()
        .map(|name| String::from_utf8_lossy(name).into_owned())
        .collect();
    let m = record.constraints.len();
    for balance in [false, true] {
        let expected = trajectory::header(
            record.columns(),
            &record.constraints,
            &record.force_columns(),
            balance,
        );
        if names == expected {
            return Ok((names, balance));
        }
    }
    let expected = trajectory::header(
        record.columns(),
        &record.constraints,
        &record.force_columns(),
        false,
    );
    let friction = match record.friction.len() {
        0 => String::new(),
        k => format!(" ({k} with friction)"),
    };
    Err(format!(
        "the header is `{}`, expected `{}` (and `{}` after it, for a model that is not \
         autonomous) for {} coordinates and {m} constraints{friction}",
        quote(&names.join(",")),
        quote(&expected.join(",")),
        work_columns(!record.friction.is_empty())
            .collect::<Vec<_>>()
            .join(","),
        record.coordinates.len()
    ))
}

/// `text` for a message: at most [`QUOTED`] characters of it, and how long it is when longer.
pub fn quote(text: &str) -> String {
    match text.char_indices().nth(QUOTED) {
        None => text.to_string(),
        Some((end, _)) => format!("{}… ({} bytes in all)", &text[..end], text.len()),
    }
}

/// A reader that fails once a line grows longer than its limit, so that a malformed file (one
/// line of a gigabyte) costs no more memory than the longest line it may hold.
pub(super) struct LineLimit<R> {
    inner: R,
    limit: usize,
    /// Bytes read since the last newline.
    line: usize,
}

impl<R> LineLimit<R> {
    pub(super) fn new(inner: R, limit: usize) -> Self {
        Self {
            inner,
            limit,
            line: 0,
        }
    }
}

impl<R: std::io::Read> std::io::Read for LineLimit<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let read = self.inner.read(buf)?;
        for &byte in &buf[..read] {
            self.line = if byte == b'\n' { 0 } else { self.line + 1 };
            if self.line > self.limit {
                return Err(std::io::Error::new(
                    std::io::ErrorKind::InvalidData,
                    format!(
                        "a line is longer than {} bytes, more than any row of these columns \
                         takes: this is not the run's trajectory",
                        self.limit
                    ),
                ));
            }
        }
        Ok(read)
    }
}

/// What is wrong with a row, in words.
fn csv_problem(error: &csv::Error) -> String {
    match error.kind() {
        csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => format!("{len} fields, where the header has {expected_len}"),
        csv::ErrorKind::Utf8 { .. } => "the row is not valid UTF-8".to_string(),
        csv::ErrorKind::Io(error) => format!("cannot read the file: {error}"),
        _ => error.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_free_flight_is_joined_exactly() {
        // x = x0 + v0 t − g t²/2, v = v0 − g t; y moves at a constant speed.
        let (g, x0, v0) = (9.81, 2.0, 1.5);
        let row = |t: f64| {
            vec![
                x0 + v0 * t - 0.5 * g * t * t,
                3.0 + 0.5 * t,
                v0 - g * t,
                0.5,
                7.0 + t,
            ]
        };
        let (t0, t1) = (0.1, 0.9);
        let mut out = vec![0.0; 5];
        for s in [0.0, 0.25, 0.5, 0.9, 1.0] {
            hermite(&row(t0), &row(t1), t1 - t0, s, 2, &mut out);
            let exact = row(t0 + s * (t1 - t0));
            for (k, (a, b)) in out.iter().zip(&exact).enumerate() {
                assert!((a - b).abs() < 1e-12, "s = {s}, value {k}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn a_smooth_motion_is_joined_to_third_order() {
        // x = sin t over a step of 0.2: the cubic errs by about h⁴/384.
        let row = |t: f64| vec![t.sin(), t.cos(), 0.0];
        let mut out = vec![0.0; 3];
        hermite(&row(1.0), &row(1.2), 0.2, 0.5, 1, &mut out);
        assert!((out[0] - 1.1_f64.sin()).abs() < 1e-5, "{}", out[0]);
        assert!((out[1] - 1.1_f64.cos()).abs() < 1e-3, "{}", out[1]);
    }

    #[test]
    fn the_energy_and_the_balance_are_joined_by_straight_lines() {
        let (a, b) = ([0.0, 1.0, 4.0, 4.5], [1.0, 1.0, 2.0, 2.5]);
        let mut out = [0.0; 4];
        hermite(&a, &b, 1.0, 0.25, 1, &mut out);
        assert_eq!(out[0], 0.25, "x moves at its speed 1");
        assert_eq!(out[1], 1.0);
        assert_eq!((out[2], out[3]), (3.5, 4.0));
    }
}
