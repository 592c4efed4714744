//! `trajectory.csv`, streamed row by row as the engine delivers its samples: memory stays flat
//! however long the run.

use std::io;

use zenosim::{Event, Observer, Sample};
use zenosim_runs::number::format_number;
use zenosim_runs::summary::mode_label;

use crate::output::Record;
use crate::progress::Progress;

/// The energy balance's columns, after `energy`, in a run of a model that is not autonomous:
/// the terms of `E(t) − E(0) = work_forces + work_drive + work_constraints − impact_loss`
/// from the start to the row's time ([`zenosim::Work`]), and [`WORK_FRICTION`] after them
/// for a model with friction.
pub const WORK_COLUMNS: [&str; 4] = [
    "work_forces",
    "work_drive",
    "work_constraints",
    "impact_loss",
];

/// The work of friction at slipping contacts, `∫ Σ fₜ s dt ≤ 0` from the start to the row's
/// time: the energy balance's last column in a run of a model with friction that is not
/// autonomous, added to the right-hand side of the balance.
pub const WORK_FRICTION: &str = "work_friction";

/// The energy balance's columns of a model that is not autonomous, with `friction` or not.
pub fn work_columns(friction: bool) -> impl Iterator<Item = &'static str> {
    WORK_COLUMNS
        .into_iter()
        .chain(friction.then_some(WORK_FRICTION))
}

pub use zenosim_runs::summary::force_column;

/// The header of `trajectory.csv`:
/// `t,mode,<columns of (q, q̇)...>,h_<c>...,lambda_<c>...,f_<c>...,energy`, with a column of
/// tangential force ([`force_column`]) for each `(constraint, component)` of `friction` (those
/// with friction, in the model's order, a contact in space's two components one after the
/// other; none for a frictionless model), then when `work` the energy balance's
/// [`work_columns`].
pub fn header<'a>(
    columns: impl IntoIterator<Item = &'a String>,
    constraints: &[String],
    friction: &[(&str, usize)],
    work: bool,
) -> Vec<String> {
    let work_columns = work_columns(!friction.is_empty()).filter(|_| work);
    ["t", "mode"]
        .into_iter()
        .map(str::to_string)
        .chain(columns.into_iter().cloned())
        .chain(constraints.iter().map(|c| format!("h_{c}")))
        .chain(constraints.iter().map(|c| format!("lambda_{c}")))
        .chain(friction.iter().map(|&(c, k)| force_column(c, k)))
        .chain(std::iter::once("energy".to_string()))
        .chain(work_columns.map(str::to_string))
        .collect()
}

/// The observer of a run: writes every sample as a CSV row and moves the progress bar.
///
/// [`Observer::sample`] cannot fail, so the first write error is kept (and nothing more is
/// written); [`TrajectoryWriter::finish`] returns it.
///
/// The file is capped at `max_bytes` (`--max-output`): the first row that would take it past
/// the cap is not written, nor is any after it but the last one the run delivers (its final
/// state), which [`TrajectoryWriter::finish`] writes past the cap so that the file ends, as
/// always, with the state `summary.json` calls final. [`Observer::interrupted`] then stops the
/// run at its next step, as a write error does.
pub struct TrajectoryWriter<W: io::Write> {
    /// Formats one row at a time into `row`, so that its length is known before it is written.
    csv: csv::Writer<Record>,
    row: Record,
    out: io::BufWriter<W>,
    number: String,
    rows: u64,
    /// The bytes written so far, the header included.
    bytes: u64,
    max_bytes: u64,
    /// Whether a row did not fit under `max_bytes`.
    capped: bool,
    /// The last sample delivered since the cap was reached.
    last: Option<zenosim::Point>,
    error: Option<io::Error>,
    progress: Progress,
    /// The constraints' names, for the held set in the `mode` column.
    constraints: Vec<String>,
    /// The columns of tangential force: `(constraint index, component)`.
    friction: Vec<(usize, usize)>,
    mode: String,
    /// Whether the rows end with the energy balance's [`work_columns`].
    work: bool,
}

/// What [`TrajectoryWriter::finish`] wrote.
pub struct Written<W> {
    /// The underlying writer, flushed.
    pub out: W,
    /// The data rows.
    pub rows: u64,
    /// Whether the cap stopped the rows (the file holds those that fit and the final state).
    pub capped: bool,
}

impl<W: io::Write> TrajectoryWriter<W> {
    /// A writer of the columns `t,mode,<q...>,<q_dot...>,h_<c>...,lambda_<c>...,f_<c>...,energy`
    /// ([`header`]; `f_<c>` for the constraints of `friction`, indices into `constraints`), and
    /// when `work` (a model that is not autonomous) the energy balance's [`work_columns`]
    /// (`work_friction` among them where `friction` is not empty).
    /// `mode` is `free`, or `constrained:` and the names of the constraints held, joined by `+`
    /// (`constrained:floor+wall`), then, where held contacts stick or slip, `;stick:` and
    /// `;slip:` and their names joined by `+`, each only where not empty
    /// (`constrained:left+right;stick:left;slip:right`). The rows stop at `max_bytes` (but for
    /// the final state).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        out: W,
        coordinates: &[String],
        velocities: &[String],
        constraints: &[String],
        friction: &[(usize, usize)],
        work: bool,
        max_bytes: u64,
        progress: Progress,
    ) -> Self {
        let row = Record::default();
        let mut writer = Self {
            csv: csv::Writer::from_writer(row.clone()),
            row,
            out: io::BufWriter::with_capacity(1 << 16, out),
            number: String::with_capacity(32),
            rows: 0,
            bytes: 0,
            max_bytes,
            capped: false,
            last: None,
            error: None,
            progress,
            constraints: constraints.to_vec(),
            friction: friction.to_vec(),
            mode: String::new(),
            work,
        };
        let friction_names: Vec<(&str, usize)> = friction
            .iter()
            .map(|&(i, k)| (constraints.get(i).map_or("?", String::as_str), k))
            .collect();
        let header = header(
            coordinates.iter().chain(velocities),
            constraints,
            &friction_names,
            work,
        );
        // The header is written whatever the cap: a file without it is no CSV.
        let written = writer
            .csv
            .write_record(header)
            .map_err(io::Error::from)
            .and_then(|()| writer.put());
        writer.keep(written);
        writer
    }

    /// The data rows written so far.
    #[cfg(test)]
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Writes the final state if the cap held it back, flushes everything and returns the
    /// underlying writer with what was written, or the first error.
    pub fn finish(mut self) -> io::Result<Written<W>> {
        self.progress.finish();
        if let Some(last) = self.last.take() {
            if self.error.is_none() {
                let written = self.format(&last.sample()).and_then(|()| self.put());
                self.keep(written);
                self.rows += 1;
            }
        }
        if let Some(error) = self.error {
            return Err(error);
        }
        let out = self.out.into_inner().map_err(|error| error.into_error())?;
        Ok(Written {
            out,
            rows: self.rows,
            capped: self.capped,
        })
    }

    fn keep(&mut self, result: io::Result<()>) {
        if let Err(error) = result {
            if self.error.is_none() {
                self.error = Some(error);
            }
        }
    }

    fn field(&mut self, x: f64) -> csv::Result<()> {
        write_number(&mut self.csv, &mut self.number, x)
    }

    /// Formats the row of `s`; [`TrajectoryWriter::put`] writes it.
    fn format(&mut self, s: &Sample<'_>) -> io::Result<()> {
        self.format_row(s)?;
        // Into `row` (memory: no I/O).
        self.csv.flush()
    }

    fn format_row(&mut self, s: &Sample<'_>) -> csv::Result<()> {
        self.field(s.t)?;
        mode_label(&mut self.mode, s.mode, s.grips, &self.constraints);
        self.csv.write_field(self.mode.as_bytes())?;
        for &x in s.q.iter().chain(s.q_dot).chain(s.h).chain(s.lambda) {
            self.field(x)?;
        }
        for &(index, component) in &self.friction {
            let forces = if component == 0 {
                s.friction
            } else {
                s.friction_across
            };
            let x = forces.get(index).copied().unwrap_or(f64::NAN);
            write_number(&mut self.csv, &mut self.number, x)?;
        }
        self.field(s.energy)?;
        if self.work {
            let w = &s.work;
            for x in [w.forces, w.drive, w.constraints, w.impact_loss] {
                self.field(x)?;
            }
            if !self.friction.is_empty() {
                self.field(w.friction)?;
            }
        }
        self.csv.write_record(None::<&[u8]>)
    }

    /// The length of the row formatted, in bytes.
    fn formatted(&self) -> u64 {
        self.row.len()
    }

    /// Writes the row formatted.
    fn put(&mut self) -> io::Result<()> {
        self.bytes += self.row.len();
        self.row.take_into(&mut self.out)
    }

    /// Keeps `s` as the last sample delivered past the cap.
    fn hold_back(&mut self, s: &Sample<'_>) {
        match &mut self.last {
            Some(last) => last.set(s),
            None => self.last = Some(zenosim::Point::of(s)),
        }
    }
}

/// Writes `x` as a field of `csv`, formatted in `number`.
fn write_number(csv: &mut csv::Writer<Record>, number: &mut String, x: f64) -> csv::Result<()> {
    format_number(number, x);
    csv.write_field(number.as_bytes())
}

impl<W: io::Write> Observer for TrajectoryWriter<W> {
    fn sample(&mut self, sample: &Sample<'_>) {
        self.progress.update(sample.t);
        if self.error.is_some() {
            return;
        }
        if self.capped {
            self.hold_back(sample);
            return;
        }
        if let Err(error) = self.format(sample) {
            self.keep(Err(error));
            return;
        }
        if self.bytes + self.formatted() > self.max_bytes {
            self.capped = true;
            self.row.clear();
            self.hold_back(sample);
            return;
        }
        let written = self.put();
        self.keep(written);
        self.rows += 1;
    }

    fn event(&mut self, _event: &Event) {}

    /// A write failed (a full disk), or the file reached its cap: the run stops at once, its
    /// record kept, instead of simulating to the end for rows that cannot be written. So does
    /// a first Ctrl-C or SIGTERM ([`crate::signals`]).
    fn interrupted(&mut self) -> bool {
        self.error.is_some()
            || self.capped
            || crate::signals::INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use zenosim::Mode;

    #[test]
    fn rows_follow_the_header() {
        use zenosim::ActiveSet;
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let mut writer = TrajectoryWriter::new(
            Vec::new(),
            &names(&["x", "y"]),
            &names(&["x_dot", "y_dot"]),
            &names(&["floor", "left wall"]),
            &[],
            false,
            u64::MAX,
            Progress::hidden(),
        );
        writer.sample(&Sample {
            t: 0.5,
            mode: Mode::Constrained(ActiveSet::single(1)),
            q: &[1.0, 2e-20],
            q_dot: &[-0.25, 0.0],
            h: &[1.0, 0.0],
            lambda: &[0.0, -9.81],
            friction: &[0.0, 0.0],
            friction_across: &[0.0; 3],
            grips: zenosim::Grips::none(),
            energy: f64::NAN,
            work: zenosim::Work::default(),
        });
        assert_eq!(writer.rows(), 1);
        let text = String::from_utf8(writer.finish().unwrap().out).unwrap();
        assert_eq!(
            text,
            "t,mode,x,y,x_dot,y_dot,h_floor,h_left wall,lambda_floor,lambda_left wall,energy\n\
             0.5,constrained:left wall,1,2e-20,-0.25,0,1,0,0,-9.81,NaN\n"
        );
    }

    /// With friction: a column `f_<name>` per constraint with friction, after the multipliers,
    /// and the contacts that stick or slip after the held set in `mode`.
    #[test]
    fn friction_has_its_columns_and_its_states_in_the_mode() {
        use zenosim::{ActiveSet, Grips};
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        // Constraints 0 and 2 have friction, 1 (the wall) has none; 2 is a contact in space
        // (two components).
        assert_eq!(
            header(
                &names(&["x", "x_dot"]),
                &names(&["left", "wall", "right"]),
                &[("left", 0), ("right", 0), ("right", 1)],
                true,
            )
            .join(","),
            "t,mode,x,x_dot,h_left,h_wall,h_right,lambda_left,lambda_wall,lambda_right,\
             f_left,f_right,f2_right,energy,work_forces,work_drive,work_constraints,\
             impact_loss,work_friction"
        );
        let mut writer = TrajectoryWriter::new(
            Vec::new(),
            &names(&["x", "y"]),
            &names(&["x_dot", "y_dot"]),
            &names(&["left", "wall", "right"]),
            &[(0, 0), (2, 0)],
            false,
            u64::MAX,
            Progress::hidden(),
        );
        let held = ActiveSet::single(0).with(1).with(2);
        let rows = [
            // Every held contact: one sticks, one slips backwards (s < 0, fₜ = +μₖ fₙ).
            (
                Mode::Constrained(held),
                Grips {
                    stick: ActiveSet::single(0),
                    forward: ActiveSet::empty(),
                    backward: ActiveSet::single(2),
                },
                [-1.5, 0.0, 2.25],
            ),
            // Both slip, forwards and backwards: one list.
            (
                Mode::Constrained(held),
                Grips {
                    stick: ActiveSet::empty(),
                    forward: ActiveSet::single(2),
                    backward: ActiveSet::single(0),
                },
                [0.5, 0.0, -0.25],
            ),
            // Only the frictionless wall held: no list.
            (
                Mode::Constrained(ActiveSet::single(1)),
                Grips::none(),
                [0.0; 3],
            ),
            (Mode::Free, Grips::none(), [0.0; 3]),
        ];
        for (k, (mode, grips, friction)) in rows.into_iter().enumerate() {
            writer.sample(&Sample {
                t: k as f64,
                mode,
                q: &[1.0, 0.0],
                q_dot: &[0.0, 0.0],
                h: &[0.0, 0.0, 0.0],
                lambda: &[-2.0, -1.0, -3.0],
                friction: &friction,
                friction_across: &[0.0; 3],
                grips,
                energy: 4.0,
                work: zenosim::Work::default(),
            });
        }
        let text = String::from_utf8(writer.finish().unwrap().out).unwrap();
        assert_eq!(
            text,
            "t,mode,x,y,x_dot,y_dot,h_left,h_wall,h_right,lambda_left,lambda_wall,lambda_right,\
             f_left,f_right,energy\n\
             0,constrained:left+wall+right;stick:left;slip:right,1,0,0,0,0,0,0,-2,-1,-3,-1.5,2.25,4\n\
             1,constrained:left+wall+right;slip:left+right,1,0,0,0,0,0,0,-2,-1,-3,0.5,-0.25,4\n\
             2,constrained:wall,1,0,0,0,0,0,0,-2,-1,-3,0,0,4\n\
             3,free,1,0,0,0,0,0,0,-2,-1,-3,0,0,4\n"
        );
    }

    /// The cap keeps the rows that fit, then the last sample delivered (the final state), and
    /// asks the run to stop.
    #[test]
    fn the_cap_keeps_the_rows_that_fit_and_the_final_state() {
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let header = "t,mode,x,x_dot,h_floor,lambda_floor,energy\n";
        let row = |t: f64| format!("{t},free,1,0,1,0,9\n");
        // Room for the header and exactly two rows of one digit's time.
        let cap = (header.len() + 2 * row(1.0).len()) as u64;
        let mut writer = TrajectoryWriter::new(
            Vec::new(),
            &names(&["x"]),
            &names(&["x_dot"]),
            &names(&["floor"]),
            &[],
            false,
            cap,
            Progress::hidden(),
        );
        assert!(!writer.interrupted());
        for k in 1..=5 {
            writer.sample(&Sample {
                t: k as f64,
                mode: Mode::Free,
                q: &[1.0],
                q_dot: &[0.0],
                h: &[1.0],
                lambda: &[0.0],
                friction: &[0.0],
                friction_across: &[0.0; 3],
                grips: zenosim::Grips::none(),
                energy: 9.0,
                work: zenosim::Work::default(),
            });
            // Two rows fit; the third does not, and from then on the run is asked to stop.
            assert_eq!(writer.interrupted(), k >= 3, "k = {k}");
        }
        assert_eq!(writer.rows(), 2);
        let written = writer.finish().unwrap();
        assert!(written.capped);
        assert_eq!(written.rows, 3);
        let text = String::from_utf8(written.out).unwrap();
        assert_eq!(
            text,
            format!("{header}{}{}{}", row(1.0), row(2.0), row(5.0))
        );
        assert_eq!(text.len() as u64, cap + row(5.0).len() as u64);
    }

    #[test]
    fn a_model_that_is_not_autonomous_has_the_balance_after_the_energy() {
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let mut writer = TrajectoryWriter::new(
            Vec::new(),
            &names(&["y"]),
            &names(&["y_dot"]),
            &names(&["floor"]),
            &[],
            true,
            u64::MAX,
            Progress::hidden(),
        );
        let work = zenosim::Work {
            forces: -1.25,
            drive: 0.0,
            constraints: 3e-7,
            impact_loss: 2.5,
            friction: 0.0,
        };
        for (t, mode, work) in [
            (0.0, Mode::Free, zenosim::Work::default()),
            (0.75, Mode::Free, work),
        ] {
            writer.sample(&Sample {
                t,
                mode,
                q: &[1.0],
                q_dot: &[-0.5],
                h: &[1.0],
                lambda: &[0.0],
                friction: &[0.0],
                friction_across: &[0.0; 3],
                grips: zenosim::Grips::none(),
                energy: 9.0,
                work,
            });
        }
        assert_eq!(writer.rows(), 2);
        let text = String::from_utf8(writer.finish().unwrap().out).unwrap();
        assert_eq!(
            text,
            "t,mode,y,y_dot,h_floor,lambda_floor,energy,\
             work_forces,work_drive,work_constraints,impact_loss\n\
             0,free,1,-0.5,1,0,9,0,0,0,0\n\
             0.75,free,1,-0.5,1,0,9,-1.25,0,3e-7,2.5\n"
        );
        // The header without the balance is today's, column for column.
        let plain = header(&names(&["y", "y_dot"]), &names(&["floor"]), &[], false);
        assert_eq!(
            plain.join(","),
            "t,mode,y,y_dot,h_floor,lambda_floor,energy"
        );
    }

    /// With friction, the work of friction after the other terms of the balance.
    #[test]
    fn a_model_with_friction_that_is_not_autonomous_has_the_work_of_friction_last() {
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let mut writer = TrajectoryWriter::new(
            Vec::new(),
            &names(&["x"]),
            &names(&["x_dot"]),
            &names(&["floor"]),
            &[(0, 0)],
            true,
            u64::MAX,
            Progress::hidden(),
        );
        let work = zenosim::Work {
            forces: -1.25,
            friction: -0.5,
            ..Default::default()
        };
        writer.sample(&Sample {
            t: 0.5,
            mode: Mode::Free,
            q: &[1.0],
            q_dot: &[0.0],
            h: &[1.0],
            lambda: &[0.0],
            friction: &[0.0],
            friction_across: &[0.0],
            grips: zenosim::Grips::none(),
            energy: 2.0,
            work,
        });
        let text = String::from_utf8(writer.finish().unwrap().out).unwrap();
        assert_eq!(
            text,
            "t,mode,x,x_dot,h_floor,lambda_floor,f_floor,energy,\
             work_forces,work_drive,work_constraints,impact_loss,work_friction\n\
             0.5,free,1,0,1,0,0,2,-1.25,0,0,0,-0.5\n"
        );
    }

    #[test]
    fn a_run_with_drag_writes_a_balance_that_closes_on_every_row() {
        use zenosim::{models::DraggedBall, Simulation, SimulationOptions};
        let example = DraggedBall::example();
        let options = SimulationOptions {
            t_end: example.t_end,
            ..Default::default()
        };
        let simulation =
            Simulation::new(&example.model, &example.q0, &example.q_dot0, options).unwrap();
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let mut writer = TrajectoryWriter::new(
            Vec::new(),
            &names(&["y"]),
            &names(&["y_dot"]),
            &names(&["floor"]),
            &[],
            true,
            u64::MAX,
            Progress::hidden(),
        );
        let run = simulation.run(&mut writer);
        let text = String::from_utf8(writer.finish().unwrap().out).unwrap();
        let mut lines = text.lines();
        assert_eq!(
            lines.next(),
            Some(
                "t,mode,y,y_dot,h_floor,lambda_floor,energy,\
                 work_forces,work_drive,work_constraints,impact_loss"
            )
        );
        let mut e0 = None;
        let mut last = Vec::new();
        for line in lines {
            let v: Vec<f64> = line
                .split(',')
                .skip(2)
                .map(|x| x.parse().unwrap())
                .collect();
            let [energy, forces, drive, constraints, loss] = v[4..] else {
                panic!("{line}")
            };
            let e0 = *e0.get_or_insert(energy);
            let size = e0.abs() + energy.abs() + forces.abs() + loss.abs();
            let residual = energy - e0 - (forces + drive + constraints - loss);
            assert!(residual.abs() <= 1e-8 * size, "{line}: {residual:e}");
            last = v;
        }
        // The last row holds the run's totals.
        let w = run.work;
        assert_eq!(last[5..], [w.forces, w.drive, w.constraints, w.impact_loss]);
        assert!(w.forces < 0.0 && w.impact_loss > 0.0, "{w:?}");
    }
}
